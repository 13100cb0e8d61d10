"""Figures of the validation reports (docs/validation/*.md): matplotlib on the Agg backend, the one
savefig that writes DOCDIR/SUBDIR/NAME.png and returns the markdown line embedding it (a path
relative to DOCDIR, where the reports live), and the shared looks of error bands and of the numbers
a paper states. Used by poiseuille_report.py, usf_inhomogeneous_report.py, enskog_report.py and
heat_flux_report.py.
Needs Debian's python3-matplotlib and python3-numpy."""
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402,F401  (re-exported: `from report_figures import plt`)
import numpy as np  # noqa: E402

PAPER_COLOUR = "0.35"


def h5_text(v):
    """An HDF5 string attribute or value as str (h5py returns bytes or str depending on how it was written)."""
    return v.decode() if isinstance(v, bytes) else str(v)


def runs_line(*paths):
    """'gdsmc VERSION, runs of DATE': the version each output records (gdsmc_version) and the UTC
    time its file was written (the end of its run), the earliest to the latest; for a report's
    header (issue 29: every report says the gdsmc version and the date of the runs behind it)."""
    import datetime

    import h5py

    versions, times = [], []
    for path in paths:
        with h5py.File(path, "r") as f:
            v = f.attrs.get("gdsmc_version", "?")
        v = h5_text(v)
        if v not in versions:
            versions.append(v)
        times.append(os.path.getmtime(path))
    fmt = "%Y-%m-%d %H:%M UTC"
    first, last = (datetime.datetime.fromtimestamp(t, datetime.timezone.utc).strftime(fmt)
                   for t in (min(times), max(times)))
    when = first if first == last else f"{first} to {last}"
    return f"gdsmc {', '.join(versions)}, runs of {when}"  # the paper's stated numbers: grey dotted lines, black open markers


def band_upper(band):
    """The upper end of a seed check's band as gdsmc writes it ("[0.607, 1.49] for 39 dof"); NaN if none."""
    return float(band.split("]")[0].strip("[").split(",")[1]) if band.startswith("[") else float("nan")


def seed_check(group, quantities, fmt=lambda v, e: f"{v:.6g} ± {e:.2g}"):
    """The seed check gdsmc wrote into a diagnostic group of a study with realizations (issue 29
    item 2; user guide, "The seed check of every error"), as report rows. `quantities`: (label,
    value dataset, error dataset), e.g. ("Q", "Q", "Q_error") or ("T", "temperature.steady_mean",
    "temperature.steady_stderr"). Returns (rows, band text, labels with chi2/dof above the band):
    rows of [label, mean ± error over realizations, mean own error (— for the host's steady errors, whose
    realizations' own values are not in the output), chi2/dof, weighted, sd/error],
    sd/error = sqrt(chi2/dof), the factor by which one run's error understates (> 1) the scatter.
    `fmt(value, error)` writes the mean and its error (the report's own rounding)."""
    def val(name):
        return float(group[name][()]) if name in group else float("nan")

    band = h5_text(group.attrs.get("seed_chi2_band_95", ""))
    high = band_upper(band)
    rows, above = [], []
    for label, value, error in quantities:
        if error + "_seed_chi2_dof" not in group:
            continue
        chi = val(error + "_seed_chi2_dof")
        # The host's steady error of a realization average is that over the realizations (the realizations'
        # own steady errors are not averaged into the output); a plugin's error is averaged, beside X_stderr.
        host = error.endswith(".steady_stderr")
        v, se = val(value), val(error if host else value + "_stderr")
        chi_text = f"{chi:.2f}"
        if not np.isfinite(chi):  # say how many realizations' own errors were NaN (the host's reason is in them)
            m = re.search(r"(\d+) left out", h5_text(group[error + "_seed_chi2_dof"].attrs.get("description", "")))
            chi_text = f"— ({m.group(1)} own errors NaN)" if m else "—"
        weighted = val(error + "_seed_chi2_dof_weighted")
        rows.append([label, fmt(v, se), "—" if host else f"{val(error):.2g}", chi_text,
                     f"{weighted:.2f}" if np.isfinite(weighted) else "—", f"{np.sqrt(chi):.2f}" if chi >= 0 else "—"])
        if chi > high:
            above.append(f"{label} {chi:.2f}")
    return rows, band, above


SEED_CHECK_HEADER = ["quantity", "mean ± error over realizations", "mean own error", "χ²/dof", "weighted", "sd/error"]


def savefig(fig, docdir, subdir, name, dpi=110):
    """Write fig to DOCDIR/SUBDIR/NAME.png, close it, return '![NAME](SUBDIR/NAME.png)'."""
    d = os.path.join(docdir, subdir)
    os.makedirs(d, exist_ok=True)
    fig.savefig(os.path.join(d, name + ".png"), dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return f"![{name}]({subdir}/{name}.png)"


def band(ax, x, y, e=None, alpha=0.25, **kw):
    """A line y(x) with a shaded band of +- e (a standard error; none where e is None or not finite)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    (line,) = ax.plot(x, y, **kw)
    if e is not None:
        e = np.asarray(e, dtype=float)
        ok = np.isfinite(e) & np.isfinite(y)
        if ok.any():
            ax.fill_between(x, np.where(ok, y - e, np.nan), np.where(ok, y + e, np.nan),
                            color=line.get_color(), alpha=alpha, linewidth=0)
    return line


def paper_hline(ax, y, label=None, **kw):
    """A value the paper states, as a grey dotted horizontal line."""
    kw = {"color": PAPER_COLOUR, "linestyle": ":", "linewidth": 1.2, **kw}
    return ax.axhline(y, label=label, **kw)


def paper_vline(ax, x, label=None, **kw):
    """A position the paper states (a time, a density), as a grey dash-dot vertical line."""
    kw = {"color": PAPER_COLOUR, "linestyle": "-.", "linewidth": 1.0, **kw}
    return ax.axvline(x, label=label, **kw)


def paper_points(ax, x, y, label=None, **kw):
    """Points the paper states, as black open markers drawn above the curves."""
    kw = {"marker": "o", "markersize": 7, "markerfacecolor": "none", "markeredgecolor": "k",
          "markeredgewidth": 1.4, "linestyle": "none", "zorder": 5, **kw}
    return ax.plot(x, y, label=label, **kw)[0]
