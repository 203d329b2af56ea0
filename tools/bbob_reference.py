"""Reference values of COCO's bbob suite for metabezier's tests.

Run with COCO's own Python package (coco-experiment 2.8.2, module cocoex):

    python -m venv venv && venv/bin/pip install numpy coco-experiment==2.8.2
    venv/bin/python tools/bbob_reference.py > tests/data/bbob_reference.csv

For every function 1..24, dimension 2, 5, 10 and instances 1, 2, 15 it
writes COCO's problem id, the box, f* (the value at the optimum x* that COCO
prints with _best_parameter), and f at three fixed points (written in full,
so the test does not recompute them). The tests never call Python.
"""
import csv
import math
import os
import sys
import tempfile

import numpy as np
import cocoex

cocoex.log_level("error")
w = csv.writer(sys.stdout, lineterminator="\n")
w.writerow(["function", "dim", "instance", "id", "lower", "upper", "fopt", "point", "x", "f"])
work = tempfile.mkdtemp()
os.chdir(work)
for f in range(1, 25):
    for d in (2, 5, 10):
        for i in (1, 2, 15):
            suite = cocoex.Suite("bbob", f"instances: {i}", f"dimensions: {d} function_indices: {f}")
            p = next(iter(suite))
            p._best_parameter("print")
            with open("._bbob_problem_best_parameter.txt") as fh:
                xopt = np.array([float(v) for v in fh.read().split()])
            fopt = p(xopt)
            points = [np.zeros(d)] + [
                np.array([4.0 * math.sin(1.7 * (j + 1) + 0.9 * k) for j in range(d)]) for k in (1, 2)
            ]
            for k, x in enumerate(points):
                w.writerow([
                    f, d, i, p.id, repr(float(p.lower_bounds[0])), repr(float(p.upper_bounds[0])),
                    repr(float(fopt)), k, " ".join(repr(float(v)) for v in x), repr(float(p(x))),
                ])
            suite.free()
