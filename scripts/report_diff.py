#!/usr/bin/python3
"""Old against new values of a regenerated validation report (issue 29: "every validation report
regenerated ..., and its old-versus-new differences listed").

Usage: report_diff.py OLD.md NEW.md [--top K]
       report_diff.py docs/validation/usf.md            # the committed version (git HEAD) against the file

Every table cell written "value ± error" is keyed by its section heading and the line of text
before its table, the table's column header and the row's cells that are not values (so the same quantity is found in both reports even when
rows or tables were added); the difference is given in units of the combined error
sqrt(e_old^2 + e_new^2). Prints a summary (cells compared, how many differ by more than 2 and 3
combined errors, the expected count for independent Gaussian values) and the K largest differences
as a Markdown table. Cells whose runs did not change give a difference of 0; cells with no error are
skipped."""
import argparse
import math
import re
import subprocess

SIGNED = re.compile(r"^[-+−]\d[\d.]*$")
VALUE = re.compile(r"^\s*\*{0,2}([-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)\s*±\s*(\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)\*{0,2}")


def cells(text):
    """{(section, column, row label): (value, error)} of every "value ± error" table cell."""
    out, section, header, caption = {}, "", None, ""
    for line in text.splitlines():
        if line.startswith("#"):
            section, header, caption = line.lstrip("#").strip(), None, ""
            continue
        if not line.startswith("|"):
            header = None
            if line.strip():
                caption = line.strip()[:60]  # the text before a table tells same-shaped tables apart
            continue
        row = [c.strip() for c in line.strip().strip("|").split("|")]
        if header is None:
            header = row
            continue
        if all(set(c) <= set("-: ") for c in row):
            continue
        parsed = [VALUE.match(c) for c in row]
        # The row's name: its cells that are neither values nor signed numbers (a signed number is a
        # derived column, such as a difference in standard errors, which changes with the values).
        label = " / ".join(c for c, m in zip(row, parsed) if not m and c and not SIGNED.match(c))
        for k, m in enumerate(parsed):
            if m and k < len(header):
                key = (section + (" — " + caption if caption else ""), header[k], label)
                if key not in out:  # the first of duplicate cells (a table repeated in a figure note)
                    out[key] = (float(m.group(1)), float(m.group(2)))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("reports", nargs="+", metavar="REPORT", help="OLD.md NEW.md, or one file against git HEAD")
    parser.add_argument("--top", type=int, default=15, help="how many of the largest differences to list (15)")
    opts = parser.parse_args()
    args, top = opts.reports, opts.top
    if len(args) == 1:
        old = subprocess.run(["git", "show", "HEAD:" + args[0]], capture_output=True, text=True, check=True).stdout
        new = open(args[0]).read()
    elif len(args) == 2:
        old, new = open(args[0]).read(), open(args[1]).read()
    else:
        parser.error("give OLD.md NEW.md, or one report to compare with its committed version")
    a, b = cells(old), cells(new)
    rows = []
    for key in a.keys() & b.keys():
        (v0, e0), (v1, e1) = a[key], b[key]
        s = math.hypot(e0, e1)
        if s > 0:
            rows.append(((v1 - v0) / s, key, a[key], b[key]))
    rows.sort(key=lambda r: -abs(r[0]))
    n = len(rows)
    over2 = sum(abs(r[0]) > 2 for r in rows)
    over3 = sum(abs(r[0]) > 3 for r in rows)
    print(f"{n} cells with errors in both reports ({len(a.keys() - b.keys())} only in the old, "
          f"{len(b.keys() - a.keys())} only in the new); |new − old| > 2 combined errors: {over2} "
          f"(independent Gaussian values: {0.0455 * n:.1f} expected), > 3: {over3} ({0.0027 * n:.1f} expected).")
    print()
    print("| section | column | row | old | new | (new − old) / √(e_old² + e_new²) |")
    print("|---|---|---|---|---|---|")
    for z, (sec, col, lab), (v0, e0), (v1, e1) in rows[:top]:
        print(f"| {sec} | {col} | {lab} | {v0:g} ± {e0:g} | {v1:g} ± {e1:g} | {z:+.1f} |")


if __name__ == "__main__":
    main()
