"""pycma's default CMA-ES on COCO's bbob suite: the figures that
tests/optimisers/cmaes_parity.rs pins (issue 51).

Not run by the build, the tests or CI. Run it once, in a virtual
environment with the pinned packages (`make pycma-parity` does this):

    python3 -m venv target/pycma-venv
    target/pycma-venv/bin/pip install -r tools/pycma-requirements.txt
    target/pycma-venv/bin/python tools/pycma_bbob.py > target/pycma_bbob.csv

For bbob f1..f14 at D = 10, instances 1..5 and 3 runs each (15 runs per
function), it runs pycma's `CMAEvolutionStrategy` at its defaults (active
covariance update, λ = 4 + ⌊3 ln D⌋, no bounds) with BBOB's usual start:
σ₀ = 2 and x0 uniform in [−4, 4]^D, restarted with a doubled population
(IPOP, Auger & Hansen 2005) until f − f* ≤ 1e-8 or 10^4·D evaluations are
spent. The problem is COCO's own (coco-experiment, module cocoex), whose
values equal metabezier's (tests/optimisers/bbob.rs, tests/data/bbob_reference.csv).

It writes one line per run (function, instance, run, evaluations to 1e-8,
empty when not reached, best f − f*) and then, after a line `# median`,
one line per function: the median evaluations to 1e-8 over the 15 runs
(an unsolved run counts as infinite; empty when the median is infinite)
and the number of runs that reached it.
"""
import csv
import math
import os
import sys
import tempfile

import numpy as np
import cma
import cocoex

D = 10
FUNCTIONS = range(1, 15)
INSTANCES = range(1, 6)
RUNS = 3
BUDGET = 10_000 * D
PRECISION = 1e-8


def fopt_of(problem):
    """f* as COCO's f(x*): cocoex prints x* into a file of the cwd."""
    problem._best_parameter("print")
    with open("._bbob_problem_best_parameter.txt") as fh:
        xopt = np.array([float(v) for v in fh.read().split()])
    return problem(xopt)


def one_run(problem, fopt, seed):
    """IPOP-aCMA-ES (pycma's defaults) until the target or the budget."""
    rng = np.random.default_rng(seed)
    target = fopt + PRECISION
    state = {"evals": 0, "hit": None, "best": math.inf}

    def f(x):
        y = problem(x)
        state["evals"] += 1
        state["best"] = min(state["best"], y - fopt)
        if state["hit"] is None and y <= target:
            state["hit"] = state["evals"]
        return y

    popsize = 4 + int(3 * math.log(D))
    restart = 0
    while state["evals"] < BUDGET and state["hit"] is None:
        x0 = rng.uniform(-4.0, 4.0, D)
        opts = {
            "popsize": popsize,
            "maxfevals": BUDGET - state["evals"],
            "ftarget": target,
            "seed": seed * 100 + restart + 1,
            "verbose": -9,
        }
        es = cma.CMAEvolutionStrategy(x0, 2.0, opts)
        while not es.stop():
            xs = es.ask()
            if len(xs) > BUDGET - state["evals"]:
                for x in xs[: BUDGET - state["evals"]]:
                    f(x)
                break
            es.tell(xs, [f(x) for x in xs])
            if state["hit"] is not None:
                break
        popsize *= 2
        restart += 1
    return state["hit"], state["best"]


def main():
    cocoex.log_level("error")
    os.chdir(tempfile.mkdtemp())
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["function", "instance", "run", "evaluations", "best_delta"])
    medians = []
    for fn in FUNCTIONS:
        hits = []
        for inst in INSTANCES:
            suite = cocoex.Suite("bbob", f"instances: {inst}", f"dimensions: {D} function_indices: {fn}")
            problem = next(iter(suite))
            fopt = fopt_of(problem)
            for run in range(RUNS):
                seed = 10_000 * fn + 10 * inst + run + 1
                hit, best = one_run(problem, fopt, seed)
                hits.append(math.inf if hit is None else hit)
                out.writerow([fn, inst, run, "" if hit is None else hit, f"{best:.3e}"])
                sys.stdout.flush()
        hits.sort()
        med = hits[len(hits) // 2]
        medians.append((fn, med, sum(h < math.inf for h in hits)))
    print("# median")
    out.writerow(["function", "median_evaluations", "solved"])
    for fn, med, solved in medians:
        out.writerow([fn, "" if med == math.inf else med, solved])


if __name__ == "__main__":
    main()
