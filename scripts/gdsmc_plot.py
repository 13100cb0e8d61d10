#!/usr/bin/python3
"""gdsmc plot: one PNG per figure for every diagnostic of a gdsmc output file (HDF5).

    gdsmc plot OUTPUT.h5 [--out DIR]        (or: /usr/bin/python3 gdsmc_plot.py OUTPUT.h5 [--out DIR])

Reads the layout of output-format.md (installed in share/doc/gdsmc; docs/ in the source tree) and draws, for each diagnostic group
(/diagnostics/<name>, or /cases/<k>/diagnostics/<name> in a sweep):
  - time series against t/tau0 and against s (collisions per particle), with the band of one
    standard error over realizations where <series>_stderr exists, each realization's own series
    as thin lines (output.realizations), and the steady mean with its error over its window for
    the series the diagnostic declares stationary (its group's attribute `stationary`: names
    separated by commas, or "all"); a logarithmic y axis where the positive values of a figure
    span two decades or more (Haff's law);
  - profiles [records, bins] against y (bin_centre): a few records and, where declared
    stationary, the steady profile;
  - histograms {edges, values} as steps, with their _stderr companion as error bars;
  - other arrays: 1-D against the grid they declare (their attribute `axis` names a 1-D array of
    the group of the same length, OutputSink::axis: a profile's bin centres, a curve's alpha grid),
    else against their index; 2-D as an image; the scalars of a group as a table;
  - a sweep's /summary: every quantity against the swept parameter(s), with its error.
Theory written by a diagnostic (a dataset with the attributes role = "theory", theory_of = the
measured datasets it is theory for, separated by commas, and equation; OutputSink::theory) is drawn
as lines on the figures of those measured quantities, and on a figure of its own when theory_of is
empty; the names of the datasets play no part.
Axis labels carry each dataset's `unit` attribute. Prints the path of each file written; each
PNG's Description text says what it shows: "y axis: log|linear; steady means: NAMES|none; theory:
NAMES|none" for a series, "theory: NAMES|none" for a histogram or a sweep quantity, "x axis: GRID|index"
for a 1-D array.
Needs the Debian packages python3-h5py, python3-numpy and python3-matplotlib (Agg backend).
"""
import argparse
import os
import re
import signal
import sys

MISSING = []
try:
    import numpy as np
except ImportError:
    MISSING.append("python3-numpy")
try:
    import h5py
except ImportError:
    MISSING.append("python3-h5py")
try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    MISSING.append("python3-matplotlib")

MAX_PROFILE_RECORDS = 6


class Failure(Exception):
    """A problem with the input: printed as one line, exit status 1."""


# ---------------------------------------------------------------------------------------------
# Names and labels

def theory_of(obj):
    """The measured names a dataset is theory for (its attributes role = "theory" and theory_of,
    written by OutputSink::theory; [] when it has no measured twin), or None if it is not theory."""
    if attr(obj, "role") != "theory":
        return None
    return [n.strip() for n in str(attr(obj, "theory_of")).split(",") if n.strip()]


def names_or_none(names):
    """The names for a figure's Description text: 'a, b', or 'none'."""
    return ", ".join(names) if names else "none"


def pair_figures(names, theory, key):
    """{figure: ([measured names], [theory names])} in the order first seen: a measured name goes on
    the figure key(name), a theory name (theory: {name: [measured]}) on the figures of the measured
    names it is theory for, or on a figure of its own, key(name), when none of them is in `names`."""
    figures = {}
    for n in names:
        if n not in theory:
            figures.setdefault(key(n), ([], []))[0].append(n)
    for n in names:
        if n in theory:
            keys = [key(m) for m in theory[n] if m in names and m not in theory] or [key(n)]
            for k in dict.fromkeys(keys):
                figures.setdefault(k, ([], []))[1].append(n)
    return figures


def measured_base(name):
    """The quantity a measured name stands for: 'measured_a2_mean' -> 'a2', 'a2_mean' -> 'a2'."""
    if name.startswith("measured_"):
        name = name[len("measured_"):]
    if name.endswith("_mean"):
        name = name[:-len("_mean")]
    return name


def pretty_unit(unit):
    if isinstance(unit, bytes):
        unit = unit.decode()
    unit = str(unit)
    for plain, nice in (("lambda0", "λ⁰"), ("tau0", "τ⁰"), ("T0", "T⁰")):
        unit = unit.replace(plain, nice)
    return unit


def attr(obj, name, default=""):
    v = obj.attrs.get(name, default)
    if isinstance(v, bytes):
        v = v.decode()
    return v


def label(name, obj):
    unit = attr(obj, "unit")
    return name if unit in ("", "1") else "%s [%s]" % (name, pretty_unit(unit))


def file_part(text):
    return re.sub(r"[^A-Za-z0-9_.+=-]+", "_", text).strip("_") or "x"


def window_start(description):
    """('s' or 't', value) from a steady-mean description ('... records with s >= 5.000000 ...')."""
    m = re.search(r"\b(s|t)(?:/tau0)?\s*>=\s*([-+0-9.eE]+)", description or "")
    return (m.group(1), float(m.group(2))) if m else None


class Writer:
    def __init__(self, out_dir):
        self.out_dir = out_dir
        self.count = 0

    def save(self, fig, name, description=""):
        """Writes the figure; `description` (its axes' scales, the steady means drawn) goes into the
        PNG's Description text, so that what a figure shows can be read without looking at it."""
        os.makedirs(self.out_dir, exist_ok=True)
        path = os.path.join(self.out_dir, file_part(name) + ".png")
        fig.savefig(path, dpi=100, metadata={"Description": description} if description else None)
        plt.close(fig)
        print(path, flush=True)
        self.count += 1


# ---------------------------------------------------------------------------------------------
# One diagnostic group

class Group:
    """The datasets of one diagnostic group, sorted by kind."""

    def __init__(self, g):
        self.g = g
        self.time = g["time"][()] if "time" in g else None
        self.s = g["collisions_per_particle"][()] if "collisions_per_particle" in g else None
        records = None if self.time is None else len(self.time)
        # The series and profiles the diagnostic declares stationary (its group's attribute
        # `stationary`: names separated by commas, or "all"): only theirs get a steady-mean line.
        declared = attr(g, "stationary")
        declared = declared.decode() if isinstance(declared, bytes) else str(declared)
        self.all_stationary = declared.strip() == "all"
        self.stationary = {n.strip() for n in declared.split(",") if n.strip()}
        self.series, self.profiles, self.arrays, self.scalars, self.histograms = [], [], [], [], []
        self.theory = {}  # {name: [measured names]} of the datasets marked as theory
        for name, obj in g.items():
            measured = theory_of(obj)
            if measured is not None:
                self.theory[name] = measured
            if name in ("time", "collisions_per_particle", "bin_centre", "realizations"):
                continue
            if isinstance(obj, h5py.Group):
                if "edges" in obj and "values" in obj and not name.endswith("_stderr"):
                    self.histograms.append(name)
                continue
            if name.endswith("_stderr") or ".steady_" in name or obj.dtype.kind not in "fiu":
                continue
            if obj.ndim == 0:
                self.scalars.append(name)
            elif obj.ndim == 1 and records is not None and obj.shape[0] == records:
                self.series.append(name)
            elif obj.ndim == 2 and "bin_centre" in g and records is not None and obj.shape == (records, g["bin_centre"].shape[0]):
                self.profiles.append(name)
            else:
                self.arrays.append(name)

    def stderr(self, name):
        e = self.g.get(name + "_stderr")
        return e[()] if isinstance(e, h5py.Dataset) else None

    def steady(self, name):
        """(mean, stderr, description) of a series the diagnostic declares stationary, else None."""
        if not (self.all_stationary or name in self.stationary):
            return None
        m, e = self.g.get(name + ".steady_mean"), self.g.get(name + ".steady_stderr")
        if m is None:
            return None
        return m[()], (e[()] if e is not None else np.nan), attr(m, "description")

    def realization_values(self, name):
        r = self.g.get("realizations")
        out = []
        if isinstance(r, h5py.Group):
            for k in sorted(r.keys(), key=lambda x: int(x) if x.isdigit() else 0):
                rk = r[k]
                if name in rk and "time" in rk and "collisions_per_particle" in rk:
                    out.append((rk["time"][()], rk["collisions_per_particle"][()], rk[name][()]))
        return out


def series_figures(grp):
    """{figure: ([measured series], [theory series], [theory scalars])}: the measured series by
    measured_base, the theory series and scalars on the figures of the series they are theory for."""
    figures = {k: (m, t, []) for k, (m, t) in pair_figures(grp.series, grp.theory, measured_base).items()}
    for n in grp.scalars:
        for k in dict.fromkeys(measured_base(m) for m in grp.theory.get(n, ()) if m in grp.series and m not in grp.theory):
            figures[k][2].append(n)
    return figures


LOG_DECADES = 2.0  # a series spanning at least this many decades gets a logarithmic axis


def spans_decades(arrays):
    """Whether the finite values of `arrays` are all positive and span LOG_DECADES decades or more."""
    values = [np.asarray(a, dtype=float).ravel() for a in arrays]
    values = np.concatenate(values) if values else np.array([])
    values = values[np.isfinite(values)]
    if values.size < 2 or np.any(values <= 0):
        return False
    return np.log10(values.max() / values.min()) >= LOG_DECADES


def plot_series(grp, title, prefix, w):
    groups = series_figures(grp)
    panels = [("t", grp.time, attr(grp.g["time"], "unit"))]
    if grp.s is not None:
        panels.append(("s", grp.s, "1"))
    used_scalars = set()
    for base, (measured, theory, theory_scalars) in groups.items():
        fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.2), sharey=True, squeeze=False)
        axes = axes[0]
        unit_of = grp.g[(measured or theory)[0]]
        log_y = spans_decades([grp.g[n][()] for n in measured + theory])
        drawn = []
        for ax, (xname, x, xunit) in zip(axes, panels):
            for n in measured:
                y = grp.g[n][()]
                line, = ax.plot(x, y, "-", lw=1.4, label=n)
                err = grp.stderr(n)
                if err is not None:
                    ax.fill_between(x, y - err, y + err, color=line.get_color(), alpha=0.25, lw=0,
                                    label="%s ± 1 s.e. (realizations)" % n)
                for k, (rt, rs, ry) in enumerate(grp.realization_values(n)):
                    ax.plot(rt if xname == "t" else rs, ry, "-", lw=0.6, color="0.45", alpha=0.6,
                            label="each realization" if k == 0 else None)
                st = grp.steady(n)
                if st is not None and np.isfinite(st[0]):
                    mean, err, desc = st
                    w0 = window_start(desc)
                    lo = x[0]
                    if w0 is not None and w0[0] == xname:
                        lo = w0[1]
                    elif w0 is not None:  # the window is given on the other axis: map it through the records
                        other = grp.s if w0[0] == "s" else grp.time
                        inside = np.nonzero(other >= w0[1])[0]
                        lo = x[inside[0]] if len(inside) else x[-1]
                    ax.hlines(mean, lo, x[-1], colors="k", lw=1.0, label="%s steady mean" % n)
                    if n not in drawn:
                        drawn.append(n)
                    if np.isfinite(err):
                        ax.fill_between([lo, x[-1]], mean - err, mean + err, color="k", alpha=0.15, lw=0)
            for n in theory:
                ax.plot(x, grp.g[n][()], "--", lw=1.4, label=n)
            for n in theory_scalars:
                ax.axhline(float(grp.g[n][()]), ls=":", lw=1.4, color="C3", label=n)
                used_scalars.add(n)
            ax.set_xlabel("t [%s]" % pretty_unit(xunit) if xname == "t" else "s (collisions per particle)")
            if log_y:
                ax.set_yscale("log")
            ax.grid(alpha=0.3, which="both" if log_y else "major")
        axes[0].set_ylabel(label(base, unit_of))
        axes[0].legend(fontsize=7, loc="best")
        fig.suptitle("%s: %s" % (title, base), fontsize=10)
        fig.tight_layout()
        w.save(fig, "%s%s" % (prefix, base), "y axis: %s; steady means: %s; theory: %s" %
               ("log" if log_y else "linear", ", ".join(drawn) if drawn else "none", names_or_none(theory + theory_scalars)))
    return used_scalars


def plot_profiles(grp, title, prefix, w):
    if not grp.profiles:
        return
    y = grp.g["bin_centre"][()]
    ylab = label("y", grp.g["bin_centre"])
    for name in grp.profiles:
        data = grp.g[name][()]
        err = grp.stderr(name)
        rows = np.unique(np.linspace(0, data.shape[0] - 1, min(MAX_PROFILE_RECORDS, data.shape[0])).round().astype(int))
        fig, ax = plt.subplots(figsize=(6.5, 4.2))
        colours = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
        for c, r in zip(colours, rows):
            ax.plot(y, data[r], "-", color=c, lw=1.2, label="t = %.3g %s" % (grp.time[r], pretty_unit(attr(grp.g["time"], "unit"))))
            if err is not None:
                ax.fill_between(y, data[r] - err[r], data[r] + err[r], color=c, alpha=0.2, lw=0)
        st = grp.steady(name)
        if st is not None and np.all(np.isfinite(np.atleast_1d(st[0]))):
            mean, e, _ = st
            ax.errorbar(y, mean, yerr=e if np.all(np.isfinite(e)) else None, fmt="k.-", lw=1.6, ms=3, capsize=1.5,
                        label="steady mean")
        ax.set_xlabel(ylab)
        ax.set_ylabel(label(name, grp.g[name]))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title("%s: %s (%s)" % (title, name, "band: 1 s.e. over realizations" if err is not None else "profile"), fontsize=10)
        fig.tight_layout()
        w.save(fig, "%s%s" % (prefix, name), "y axis: linear; steady means: %s" % (name if st is not None else "none"))


def plot_histograms(grp, title, prefix, w):
    measured = [h for h in grp.histograms if h not in grp.theory]
    theory = [h for h in grp.histograms if h in grp.theory]
    overlaid = set()
    for name in measured:
        h = grp.g[name]
        edges, values = h["edges"][()], h["values"][()]
        fig, ax = plt.subplots(figsize=(6.5, 4.2))
        ax.stairs(values, edges, lw=1.4, label=name)
        se = grp.g.get(name + "_stderr")
        if isinstance(se, h5py.Group) and "values" in se:
            centres = 0.5 * (edges[1:] + edges[:-1])
            ax.errorbar(centres, values, yerr=se["values"][()], fmt="none", ecolor="C0", alpha=0.5, lw=0.8,
                        label="± 1 s.e. (realizations)")
        drawn = [t for t in theory if name in grp.theory[t]]
        for t in drawn:
            ax.stairs(grp.g[t]["values"][()], grp.g[t]["edges"][()], ls="--", lw=1.4, label=t)
            overlaid.add(t)
        xdesc = attr(grp.g, "edges")
        xlab = label(xdesc if xdesc else "edges", h["edges"])
        ax.set_xlabel(xlab)
        ax.set_ylabel(label(name, h["values"]))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        ax.set_title("%s: %s\n%s" % (title, name, attr(h, "description")[:100]), fontsize=9)
        fig.tight_layout()
        w.save(fig, "%s%s" % (prefix, name), "theory: %s" % names_or_none(drawn))
    for t in theory:
        if t not in overlaid:
            h = grp.g[t]
            fig, ax = plt.subplots(figsize=(6.5, 4.2))
            ax.stairs(h["values"][()], h["edges"][()], ls="--", lw=1.4, label=t)
            ax.set_xlabel(label("edges", h["edges"]))
            ax.set_ylabel(label(t, h["values"]))
            ax.set_title("%s: %s" % (title, t), fontsize=10)
            fig.tight_layout()
            w.save(fig, "%s%s" % (prefix, t))


def array_axis(grp, d):
    """The grid a 1-D array declares (its attribute axis, OutputSink::axis) if the group holds it with
    the array's shape, else None (the array is drawn against its index)."""
    grid = attr(d, "axis")
    g = grp.g.get(grid) if grid else None
    return grid if isinstance(g, h5py.Dataset) and g.shape == d.shape else None


def plot_arrays(grp, title, prefix, w):
    for name in grp.arrays:
        d = grp.g[name]
        data = d[()]
        fig, ax = plt.subplots(figsize=(6.5, 4.2))
        description = ""
        if data.ndim == 1:
            grid = array_axis(grp, d)
            x = grp.g[grid][()] if grid else np.arange(len(data))
            ax.plot(x, data, ".-")
            ax.set_xlabel(label(grid, grp.g[grid]) if grid else "index")
            ax.set_ylabel(label(name, d))
            ax.grid(alpha=0.3)
            description = "x axis: %s" % (grid or "index")
        else:
            im = ax.imshow(data.reshape(data.shape[0], -1), aspect="auto", origin="lower", interpolation="nearest")
            fig.colorbar(im, ax=ax, label=label(name, d))
            ax.set_xlabel("column")
            ax.set_ylabel("row")
        ax.set_title("%s: %s %s\n%s" % (title, name, list(data.shape), attr(d, "description")[:100]), fontsize=9)
        fig.tight_layout()
        w.save(fig, "%s%s" % (prefix, name), description)


def plot_scalars(grp, names, title, prefix, w):
    if not names:
        return
    rows = []
    for n in names:
        d = grp.g[n]
        v = float(d[()])
        e = grp.stderr(n)
        text = "%.6g" % v if e is None else "%.6g ± %.2g" % (v, float(e))
        rows.append([n, text, pretty_unit(attr(d, "unit"))])
    fig, ax = plt.subplots(figsize=(8, 0.7 + 0.22 * len(rows)))
    ax.axis("off")
    table = ax.table(cellText=rows, colLabels=["scalar", "value (± s.e. over realizations)", "unit"],
                     loc="upper center", cellLoc="left", colWidths=[0.45, 0.35, 0.2])
    table.auto_set_font_size(False)
    table.set_fontsize(8)
    ax.set_title("%s: scalars" % title, fontsize=10)
    fig.tight_layout()
    w.save(fig, "%sscalars" % prefix)


def plot_group(g, title, prefix, w):
    grp = Group(g)
    used = set()
    if grp.series:
        used = plot_series(grp, title, prefix, w)
    plot_profiles(grp, title, prefix, w)
    plot_histograms(grp, title, prefix, w)
    plot_arrays(grp, title, prefix, w)
    plot_scalars(grp, [n for n in grp.scalars if n not in used], title, prefix, w)


def plot_diagnostics(root, where, prefix, w):
    diags = root.get("diagnostics")
    if not isinstance(diags, h5py.Group):
        return
    for name, g in diags.items():
        if isinstance(g, h5py.Group):
            plot_group(g, where + name, prefix + name + "-", w)


# ---------------------------------------------------------------------------------------------
# A sweep's summary

def plot_summary(f, w):
    s = f["summary"]
    axes = [n for n in s if attr(s[n], "description").startswith("sweep axis")]
    if not axes:
        return
    values = {a: s[a][()] for a in axes}
    for a in axes:
        if values[a].dtype.kind in "OSU":
            values[a] = np.array([v.decode() if isinstance(v, bytes) else str(v) for v in values[a]])
    numeric = [a for a in axes if values[a].dtype.kind in "fiu"]
    # x: the numeric axis with the most distinct values (or the first axis, as categories)
    if numeric:
        x_axis = max(numeric, key=lambda a: len(np.unique(values[a])))
    else:
        x_axis = axes[0]
    others = [a for a in axes if a != x_axis]
    n_cases = len(values[x_axis])
    line_key = ["" if not others else ", ".join("%s=%s" % (a, values[a][k]) for a in others) for k in range(n_cases)]
    lines = list(dict.fromkeys(line_key))
    if values[x_axis].dtype.kind in "fiu":
        x = values[x_axis].astype(float)
        ticks = None
    else:
        cats = list(dict.fromkeys(values[x_axis]))
        x = np.array([cats.index(v) for v in values[x_axis]], dtype=float)
        ticks = cats

    # Quantities: {diagnostic: {name: (dataset, error dataset or None)}}; theory: {diagnostic: {name:
    # [measured names]}} of the columns marked as theory (their theory_of names columns "<diagnostic>.<name>")
    quantities, theory = {}, {}
    for n in s:
        if n in axes or "." not in n:
            continue
        diag, rest = n.split(".", 1)
        if rest.endswith(".steady_stderr") or rest.endswith("_stderr") and (diag + "." + rest[:-7]) in s:
            continue
        if rest.endswith("_standard_error") and (diag + "." + rest[:-len("_standard_error")] + "_mean") in s:
            continue
        err = None
        if rest.endswith(".steady_mean"):
            err = s.get(n[:-len(".steady_mean")] + ".steady_stderr")
        else:
            err = s.get(n + "_stderr")
            if err is None and rest.endswith("_mean"):
                err = s.get(n[:-len("_mean")] + "_standard_error")
        quantities.setdefault(diag, {})[rest] = (s[n], err)
        measured = theory_of(s[n])
        if measured is not None:
            theory.setdefault(diag, {})[rest] = [m.split(".", 1)[1] for m in measured if m.startswith(diag + ".")]

    for diag, q in quantities.items():
        short = {name: name[:-len(".steady_mean")] if name.endswith(".steady_mean") else name for name in q}
        groups = pair_figures(list(q), theory.get(diag, {}), lambda name: measured_base(short[name]))
        for base, (measured, theory_names) in groups.items():
            fig, ax = plt.subplots(figsize=(6.5, 4.2))
            for li, line in enumerate(lines):
                idx = np.array([k for k in range(n_cases) if line_key[k] == line])
                order = idx[np.argsort(x[idx], kind="stable")]
                for mi, name in enumerate(measured):
                    d, e = q[name]
                    y = d[()].astype(float)
                    yerr = e[()].astype(float)[order] if e is not None else None
                    kind = " (steady)" if name.endswith(".steady_mean") else ""
                    ax.errorbar(x[order] + 0.0, y[order], yerr=yerr, fmt="o-" if mi == 0 else "s:", ms=4, capsize=2,
                                color="C%d" % li, label=" ".join(p for p in (line, short[name] + kind) if p))
                for ti, name in enumerate(theory_names):
                    d, _ = q[name]
                    ax.plot(x[order], d[()].astype(float)[order], ("--", "-.", ":")[ti % 3], color="C%d" % li, lw=1.2,
                            label=" ".join(p for p in (line, short[name]) if p))
            unit_of = q[(measured or theory_names)[0]][0]
            ax.set_ylabel(label(base, unit_of))
            ax.set_xlabel(label(x_axis, s[x_axis]))
            if ticks is not None:
                ax.set_xticks(range(len(ticks)))
                ax.set_xticklabels(ticks)
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7)
            ax.set_title("sweep summary: %s: %s (error bars: 1 s.e.)" % (diag, base), fontsize=10)
            fig.tight_layout()
            w.save(fig, "summary-%s-%s" % (diag, base), "theory: %s" % names_or_none(theory_names))


# ---------------------------------------------------------------------------------------------

def open_output(path):
    if not os.path.exists(path):
        raise Failure("%s: no such file (expected a gdsmc output file, OUTPUT.h5 written by `gdsmc run`)" % path)
    if os.path.isdir(path):
        raise Failure("%s: is a directory (expected a gdsmc output file, OUTPUT.h5 written by `gdsmc run`)" % path)
    if not h5py.is_hdf5(path):
        raise Failure("%s: not an HDF5 file (expected a gdsmc output file, OUTPUT.h5 written by `gdsmc run`)" % path)
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise Failure("%s: cannot open it as HDF5: %s" % (path, e))
    if "gdsmc_version" not in f.attrs or "seed" not in f.attrs:
        f.close()
        raise Failure("%s: an HDF5 file but not a gdsmc output: its root has no gdsmc_version and seed "
                      "attributes (the provenance every output of `gdsmc run` carries)" % path)
    return f


def main(argv):
    parser = argparse.ArgumentParser(prog="gdsmc plot", description="One PNG per figure for every diagnostic of a gdsmc output file.")
    parser.add_argument("output", metavar="OUTPUT.h5")
    parser.add_argument("--out", metavar="DIR", help="directory for the PNG files (default: OUTPUT_plots/ beside OUTPUT.h5)")
    args = parser.parse_args(argv)
    if MISSING:
        print("gdsmc plot: %s needs the Debian package%s %s: install %s with `apt-get install %s` (or run scripts/install-deps)"
              % (sys.executable, "s" if len(MISSING) > 1 else "", ", ".join(MISSING), "them" if len(MISSING) > 1 else "it",
                 " ".join(MISSING)), file=sys.stderr)
        return 1
    out_dir = args.out
    if not out_dir:
        stem = args.output[:-3] if args.output.endswith(".h5") else args.output
        out_dir = stem + "_plots"
    if os.path.exists(out_dir) and not os.path.isdir(out_dir):
        raise Failure("--out %s: exists and is not a directory (give a directory for the PNG files)" % out_dir)
    w = Writer(out_dir)
    with open_output(args.output) as f:
        if "cases" in f:
            cases = f["cases"]
            for k in sorted(cases.keys(), key=lambda c: int(c) if c.isdigit() else 0):
                c = cases[k]
                plot_diagnostics(c, "case %s (%s): " % (k, attr(c, "case")), "case%s-" % k, w)
            if "summary" in f:
                plot_summary(f, w)
        else:
            plot_diagnostics(f, "", "", w)
    if w.count == 0:
        print("gdsmc plot: %s: no diagnostics to draw" % args.output, file=sys.stderr)
    return 0


if __name__ == "__main__":
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `gdsmc plot F | head`: no traceback
    try:
        sys.exit(main(sys.argv[1:]))
    except Failure as e:
        print("gdsmc plot: %s" % e, file=sys.stderr)
        sys.exit(1)
    except OSError as e:
        print("gdsmc plot: %s" % e, file=sys.stderr)
        sys.exit(1)
