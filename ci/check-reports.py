#!/usr/bin/env python3
"""Checks that the reports under the given results directories read on a
screen: report.md opens (after its title) with "## Summary" and has fewer
than 300 lines, report.html sits beside it, and no picture (beside the
report or under plots/) is wider or taller than 3,000 px. Prints one line
per report and exits 1 if any fails. Standard library only.

Usage: ci/check-reports.py DIR... (each a results directory, or a folder of
them such as results/)."""

import pathlib
import struct
import sys

MAX_LINES = 300
MAX_SIDE = 3000


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[1:4] != b"PNG":
        raise ValueError(f"{path}: not a PNG")
    return struct.unpack(">II", head[16:24])


def check(report_dir):
    md = (report_dir / "report.md").read_text(encoding="utf-8")
    lines = md.count("\n") + (0 if md.endswith("\n") else 1)
    first = next((l for l in md.splitlines() if l.startswith("## ")), None)
    faults = []
    if first != "## Summary":
        faults.append(f"first section {first!r}")
    if lines >= MAX_LINES:
        faults.append(f"{lines} lines")
    if not (report_dir / "report.html").is_file():
        faults.append("no report.html")
    pngs = sorted(report_dir.glob("*.png")) + sorted(report_dir.glob("plots/*.png"))
    largest = (0, 0, None)
    for p in pngs:
        w, h = png_size(p)
        if max(w, h) > max(largest[0], largest[1]):
            largest = (w, h, p.name)
        if w > MAX_SIDE or h > MAX_SIDE:
            faults.append(f"{p.relative_to(report_dir)} {w}x{h} px")
    size = f"{largest[0]}x{largest[1]} ({largest[2]})" if largest[2] else "-"
    state = "ok" if not faults else "FAIL: " + "; ".join(faults)
    print(f"{str(report_dir):40} {lines:4} lines  {len(pngs):3} pictures, largest {size:38} {state}")
    return not faults


def main(args):
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    dirs = []
    for a in args:
        p = pathlib.Path(a)
        if (p / "report.md").is_file():
            dirs.append(p)
        elif p.is_dir():
            dirs.extend(sorted(d for d in p.iterdir() if (d / "report.md").is_file()))
        else:
            print(f"{a}: no report.md and not a folder of results", file=sys.stderr)
            return 2
    if not dirs:
        print(f"no report.md under {' '.join(args)}", file=sys.stderr)
        return 2
    ok = [check(d) for d in dirs]
    print(f"{sum(ok)} of {len(ok)} reports read on a screen")
    return 0 if all(ok) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
