"""Runs one long call named on the command line, for ``test_interrupt.py``
to interrupt from outside (a real SIGINT, as Ctrl-C sends): prints
``ready`` just before the call and ``KeyboardInterrupt`` when it raises.
Not collected by pytest (no ``test_`` prefix)."""

import math
import signal
import sys

import metabezier as mb

SPEC = """[experiment]
name = "interrupted"
seed = 5
runs = 6
budget = {budget}
threshold = 1e-300

[[problem]]
function = "sphere"
dim = 10

[[algorithm]]
name = "hs"
"""

OUTLINE = [
    (100 * math.cos(t / 500 * 2 * math.pi) + 3 * math.sin(t), 60 * math.sin(t / 500 * 2 * math.pi))
    for t in range(500)
]


def call(case, out):
    if case == "benchmark":
        return mb.benchmark("sphere", 30, algorithm="hs", budget=10**9)
    if case == "minimize":
        return mb.minimize(lambda x: sum(v * v for v in x), [(-1, 1)] * 5, algorithm="hs", budget=10**9)
    if case == "minimize-builtin":
        return mb.minimize(sum, [(-1, 1)] * 5, algorithm="cmaes", budget=10**9)
    if case == "minimize-batch":
        return mb.minimize(lambda X: X.sum(axis=1), [(-1, 1)] * 5, algorithm="cmaes", budget=10**9, batch=True)
    if case == "run":
        return mb.run(SPEC.format(budget=10**9), out=out, threads=2)
    if case == "run-resumable":
        # Runs of about a tenth of a second, one at a time: some finish
        # before the signal, the others are redone by the resume.
        return mb.run(SPEC.format(budget=3 * 10**6), out=out, threads=1)
    if case == "fit":
        return mb.fit(OUTLINE, algorithm="mhs", budget=10**7, segments=12, corner_angle=0)
    raise SystemExit(f"unknown case {case}")


if __name__ == "__main__":
    # Python raises KeyboardInterrupt on SIGINT only if SIGINT was not
    # ignored when it started, and a shell ignores it for a job started in
    # the background (`.ci/run &`): install Python's handler, as an
    # interactive session has it.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    print("ready", flush=True)
    try:
        call(sys.argv[1], sys.argv[2])
        print("returned", flush=True)
    except KeyboardInterrupt:
        print("KeyboardInterrupt", flush=True)
