"""fit and score: a circle fitted by LM, the CLI's fit of the same points,
and bad arguments."""

import csv
import math
import subprocess

import pytest

import metabezier as mb


def circle(n=64, r=50.0):
    return [(100 + r * math.cos(2 * math.pi * k / n), 100 + r * math.sin(2 * math.pi * k / n)) for k in range(n)]


def test_fit_a_circle():
    f = mb.fit(circle(), function="rational-quadratic", segments=4, algorithm="lm", budget=2000, closed=True)
    assert len(f.segments) == 4 and f.metrics["segments"] == 4 and f.metrics["points"] == 64
    assert all(s.function == "rational-quadratic" and len(s.control_points) == 3 for s in f.segments)
    # With the data parameters fixed (chord length) a conic is not recovered
    # exactly (0.70 px on r = 50); the orthogonal fit is a separate issue.
    assert f.metrics["max_distance"] < 1.0, f.metrics
    assert f.metrics["sse"] > 0 and f.metrics["evaluations"] > 0
    # A repeated first point closes the outline, as in a CSV of points.
    again = mb.fit(circle() + [circle()[0]], function="rational-quadratic", segments=4, algorithm="lm", budget=2000)
    assert again == f
    # Points from a generator are read once, as a list would be.
    gen = mb.fit((p for p in circle()), function="rational-quadratic", segments=4, algorithm="lm", budget=2000, closed=True)
    assert gen == f
    # The same call, the same bits.
    assert mb.fit(circle(), function="rational-quadratic", segments=4, algorithm="lm", budget=2000, closed=True) == f


def test_fit_matches_the_cli(cli, tmp_path):
    pts = circle(40)
    data = tmp_path / "c.csv"
    with open(data, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["x", "y"])
        for x, y in pts:
            w.writerow([repr(x), repr(y)])
    subprocess.run(
        [str(cli), "fit", str(data), "--segments", "3", "--algorithm", "pso", "--budget", "3000",
         "--seed", "4", "--out", str(tmp_path / "out")],
        check=True, capture_output=True,
    )
    f = mb.fit(pts, segments=3, algorithm="pso", budget=3000, seed=4)
    with open(tmp_path / "out" / "metrics.csv", newline="") as fh:
        row = next(csv.DictReader(fh))
    assert row["chain"] == "joint"
    assert float(row["sse"]) == f.metrics["sse"], (row, f.metrics)
    subprocess.run(
        [str(cli), "fit", str(data), "--segments", "3", "--algorithm", "pso", "--budget", "3000",
         "--seed", "4", "--chain", "sequential", "--out", str(tmp_path / "seq")],
        check=True, capture_output=True,
    )
    s = mb.fit(pts, segments=3, algorithm="pso", budget=3000, seed=4, chain="sequential")
    with open(tmp_path / "seq" / "metrics.csv", newline="") as fh:
        row = next(csv.DictReader(fh))
    assert float(row["sse"]) == s.metrics["sse"], (row, s.metrics)
    # The joint chain starts from the sequential one: never worse.
    assert f.metrics["sse"] <= s.metrics["sse"]


def test_tolerance_and_score(tmp_path):
    f = mb.fit(circle(), function="cubic", tolerance=0.5, algorithm="lm", closed=True)
    assert f.metrics["max_distance"] <= 0.5 + 1e-9
    k = 0.5522847498 * 50
    c = [(150, 100), (150, 100 + k, 100 + k, 150, 100, 150), (100 - k, 150, 50, 100 + k, 50, 100),
         (50, 100 - k, 100 - k, 50, 100, 50), (100 + k, 50, 150, 100 - k, 150, 100)]
    d = "M %g %g " % c[0] + " ".join("C %g %g %g %g %g %g" % seg for seg in c[1:]) + " Z"
    svg = f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200"><path d="{d}"/></svg>'
    s = mb.score(circle(), svg, closed=True)
    assert s["segments"] == 4 and s["points"] == 64
    assert s["max_distance"] < 0.02, s  # four cubics miss a circle by 0.027 % of r
    (tmp_path / "c.svg").write_text(svg)
    assert mb.score(circle(), tmp_path / "c.svg", closed=True) == s
    shifted = mb.score(circle(), svg, closed=True, offset=(3.0, 4.0))
    assert abs(shifted["max_distance"] - 5.0) < 0.05, shifted


def test_the_default_fits_to_a_tolerance_of_one_on_both_sides():
    # No segments and no tolerance: a tolerance of 1 (the command line's
    # default), held by the Hausdorff distance; a circle takes 2 rational
    # cubics, exact.
    f = mb.fit(circle(), closed=True)
    assert f.metrics["segments"] == 2, f.metrics
    assert f.metrics["hausdorff"] <= 1.0, f.metrics
    assert f.metrics["hausdorff"] >= max(f.metrics["max_distance"], f.metrics["curve_distance"])
    assert f.metrics["max_distance"] < 1e-9, f.metrics


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(function="cubicc"), 'function: unknown "cubicc"; valid choices'),
        (dict(continuity="g2"), "continuity"),
        (dict(algorithm="hz"), "algorithm"),
        (dict(segments=3, tolerance=1.0), "not both"),
        (dict(tolerance=-1.0), "tolerance"),
        (dict(segments=0), "segments"),
        (dict(chain="jiont"), 'chain: unknown "jiont"; valid choices: "sequential" or "joint"'),
        (dict(function="quadratic", continuity="c1"), 'chain "sequential"'),
    ],
)
def test_bad_fit_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        mb.fit(circle(), **kwargs)
    with pytest.raises(ValueError, match="points"):
        mb.fit([(0, 1, 2)])
