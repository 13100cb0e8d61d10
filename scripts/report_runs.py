"""Find a report's runs by what they are, not by where they were saved: every gdsmc output records
its provenance (the pipeline file, the --set overrides, the sweep axes and each case's values, and
each plugin's name, version and parameters), and the validation reports select their runs from it.

    runs = report_runs.index(OUTDIR)                     # every *.h5 under OUTDIR (or given files)
    sweep = runs.one(config="poiseuille_sweep")          # the one output of that pipeline file
    seeds = runs.one(config="poiseuille", set={"run.stop.time": "176"})
    for case in sweep.cases: case.sweep["Kn"], case.param("collision", "alpha")

An output is matched by the stem of its pipeline file (config), by overrides it must carry (set:
key -> value, as given to --set; has: keys, any value), by overrides it must not carry (unset: keys),
and by its sweep axes (axes: the axis names, in any order). Needs Debian's python3-h5py and python3-yaml."""
import glob
import os
import re

import h5py


OVERRIDE = re.compile(r"^[A-Za-z_][A-Za-z0-9_.]*=")


def text(v):
    """An HDF5 string attribute as str (h5py returns bytes or str depending on how it was written)."""
    return v.decode() if isinstance(v, bytes) else str(v)


class Case:
    """One case of an output: a sweep's /cases/<i> group, or the whole file for a single run."""

    def __init__(self, output, group, g):
        self.output, self.group = output, group
        self.label = text(g.attrs.get("case", ""))
        self.sweep = {k[len("sweep."):]: text(v) for k, v in g.attrs.items() if k.startswith("sweep.")}
        self.plugins = {}
        for slot, p in (g["plugins"].items() if "plugins" in g else []):
            self.plugins[slot] = {"plugin": text(p.attrs.get("plugin", "")), "version": text(p.attrs.get("version", "")),
                                  "params": {k[len("param."):]: text(v) for k, v in p.attrs.items() if k.startswith("param.")}}

    def param(self, slot, name, default=None):
        """A plugin parameter as the output recorded it (a string), or default when absent."""
        return self.plugins.get(slot, {}).get("params", {}).get(name, default)

    def open(self):
        """The case's HDF5 group, in a file opened read-only (close it with .file.close())."""
        f = h5py.File(self.output.path, "r")
        return f[self.group]

    def __repr__(self):
        return f"Case({self.output.path}:{self.group} {self.label})"


class Output:
    """One output file and its provenance."""

    def __init__(self, path):
        self.path = path
        with h5py.File(path, "r") as f:
            a = f.attrs
            self.pipeline_file = text(a.get("pipeline_file", ""))
            self.config = os.path.splitext(os.path.basename(self.pipeline_file))[0]
            self.overrides, key = {}, None
            for line in text(a.get("overrides", "")).splitlines():  # one --set per line; a value may span lines
                if OVERRIDE.match(line):
                    key, _, value = line.partition("=")
                    self.overrides[key] = value
                elif key:
                    self.overrides[key] += "\n" + line
            self.version = text(a.get("gdsmc_version", "?"))
            if "cases" in f:
                self.cases = [Case(self, f"cases/{k}", f["cases"][k]) for k in sorted(f["cases"], key=int)]
            else:
                self.cases = [Case(self, "/", f)]
        self.axes = tuple(sorted({axis for c in self.cases for axis in c.sweep}))

    def matches(self, config=None, set=None, unset=(), axes=None, has=()):
        if config is not None and self.config != config:
            return False
        if any(self.overrides.get(k) != str(v) for k, v in (set or {}).items()):
            return False
        if any(k not in self.overrides for k in has):
            return False
        if any(k in self.overrides for k in unset):
            return False
        return axes is None or self.axes == tuple(sorted(axes))

    def __repr__(self):
        return f"Output({self.path}: {self.config}, axes {self.axes}, {len(self.overrides)} overrides)"


class Runs(list):
    """The outputs found, with selection by provenance; unreadable: (path, why) of the files that could not be
    read (a run still writing its output, or one stopped before its end)."""

    unreadable = ()

    def find(self, **match):
        return Runs(o for o in self if o.matches(**match))

    def one(self, **match):
        """The one output that matches, None if none does; two that match are an error naming both."""
        found = self.find(**match)
        if len(found) > 1:
            raise SystemExit(f"report_runs: {len(found)} outputs match {match}: "
                             + ", ".join(o.path for o in found) + " (keep one, or select by more overrides)")
        return found[0] if found else None


def index(*places):
    """Every gdsmc output among places: files, or folders searched recursively for *.h5. Files that are
    not gdsmc outputs (no pipeline_file attribute) are skipped; files that cannot be read are listed in
    .unreadable (a report says so instead of failing on a run still in progress)."""
    paths = []
    for p in places:
        paths += sorted(glob.glob(os.path.join(p, "**", "*.h5"), recursive=True)) if os.path.isdir(p) else [p]
    runs = Runs()
    runs.unreadable = []
    for path in paths:
        try:
            with h5py.File(path, "r") as f:
                if "pipeline_file" not in f.attrs:
                    continue
            runs.append(Output(path))
        except (OSError, KeyError) as ex:  # h5py's error for a file being written or cut short
            runs.unreadable.append((path, f"{type(ex).__name__}: {ex}"))
    return runs


if __name__ == "__main__":
    import sys

    runs = index(*(sys.argv[1:] or ["."]))
    for path, why in runs.unreadable:
        print(f"{path}: unreadable ({why})")
    for o in runs:
        print(f"{o.path}: config {o.config}, axes {', '.join(o.axes) or '(none)'}, {len(o.cases)} case(s)")
        for k, v in o.overrides.items():
            print(f"    --set {k}={v[:100]}" + (" ..." if len(v) > 100 else ""))
