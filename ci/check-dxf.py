"""Reads metabezier's fit.dxf back with ezdxf, a real DXF library, and checks
that it is exact: ezdxf's auditor finds no error, and every SPLINE has the
degree, the clamped Bezier knots, the control points and the weights of its
row in fit.csv, bit for bit; ezdxf's own NURBS evaluation of each SPLINE
agrees with the rational Bezier form of the row to 1e-9 of the drawing's size.

Usage: python check-dxf.py DIR [DIR ...]   (each DIR written by `metabezier fit`)
"""

import csv
import math
import sys

import ezdxf
from ezdxf.math import BSpline


def rational_bezier(points, weights, t):
    """The rational Bezier curve sum w_k B_k P_k / sum w_k B_k at t."""
    m = len(points) - 1
    num_x = num_y = den = 0.0
    for k, ((x, y), w) in enumerate(zip(points, weights)):
        b = math.comb(m, k) * t**k * (1 - t) ** (m - k) * w
        num_x += b * x
        num_y += b * y
        den += b
    return num_x / den, num_y / den


def rows_of(path):
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            degree = {"quadratic": 2, "rational-quadratic": 2}.get(row["function"], 3)
            pts = [(float(row[f"c{k}x"]), float(row[f"c{k}y"])) for k in range(degree + 1)]
            ws = [float(row[f"w{k}"]) for k in range(degree + 1)]
            yield row["function"], pts, ws


def check(directory):
    doc = ezdxf.readfile(f"{directory}/fit.dxf")
    auditor = doc.audit()
    if auditor.has_errors:
        raise SystemExit(f"{directory}/fit.dxf: ezdxf's auditor found {len(auditor.errors)} error(s): "
                         + "; ".join(str(e.message) for e in auditor.errors[:5]))
    splines = list(doc.modelspace().query("SPLINE"))
    rows = list(rows_of(f"{directory}/fit.csv"))
    if len(splines) != len(rows):
        raise SystemExit(f"{directory}: {len(splines)} SPLINE entities, {len(rows)} segments in fit.csv")
    size = max(max(abs(c) for p in pts for c in p) for _, pts, _ in rows) or 1.0
    worst = 0.0
    for i, (spline, (function, pts, ws)) in enumerate(zip(splines, rows)):
        m = len(pts) - 1
        where = f"{directory}/fit.dxf: SPLINE {i} ({function})"
        if spline.dxf.degree != m:
            raise SystemExit(f"{where}: degree {spline.dxf.degree}, expected {m}")
        if list(spline.knots) != [0.0] * (m + 1) + [1.0] * (m + 1):
            raise SystemExit(f"{where}: knots {list(spline.knots)}")
        got = [(v[0], v[1]) for v in spline.control_points]
        if got != pts:
            raise SystemExit(f"{where}: control points {got}, fit.csv has {pts}")
        rational = function.startswith("rational")
        if rational != bool(spline.dxf.flags & 4):
            raise SystemExit(f"{where}: rational flag {spline.dxf.flags}")
        weights = list(spline.weights) if rational else [1.0] * (m + 1)
        if weights != ws:
            raise SystemExit(f"{where}: weights {weights}, fit.csv has {ws}")
        curve = BSpline(spline.control_points, order=m + 1, knots=spline.knots,
                        weights=spline.weights if rational else None)
        for j in range(11):
            t = j / 10
            x, y = rational_bezier(pts, ws, t)
            p = curve.point(t)
            worst = max(worst, math.hypot(p[0] - x, p[1] - y))
    if worst > 1e-9 * size:
        raise SystemExit(f"{directory}: ezdxf's evaluation differs by {worst:e} (size {size:e})")
    print(f"{directory}/fit.dxf: {len(splines)} SPLINE(s) read by ezdxf {ezdxf.__version__}, "
          f"audit clean, control points and weights exact, evaluation within {worst:.1e}")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    for d in sys.argv[1:]:
        check(d)
