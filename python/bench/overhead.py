"""The cost per evaluation of calling a Python function from metabezier,
scalar and batched, against a pure-Rust run of the same algorithm and
against numpy's own cost of evaluating the same batches; and, where they
are installed, the same GA in mealpy and NiaPy.

    python python/bench/overhead.py [--budget 50000] [--repeat 3]

Times are CPU seconds per evaluation (time.process_time, best of
--repeat); the problems are Sphere-30 and Rastrigin-30 on [-100, 100]^30
and [-5.12, 5.12]^30, the algorithm a GA with a population of 50.
"""

import argparse
import math
import time

import numpy as np

import metabezier as mb

D = 30
POP = 50


def sphere(x):
    return sum(v * v for v in x)


def rastrigin(x):
    return 10.0 * len(x) + sum(v * v - 10.0 * math.cos(2.0 * math.pi * v) for v in x)


def sphere_rows(X):
    return np.einsum("ij,ij->i", X, X)


def rastrigin_rows(X):
    return 10.0 * X.shape[1] + (X * X - 10.0 * np.cos(2.0 * np.pi * X)).sum(axis=1)


PROBLEMS = {
    "sphere": (sphere, sphere_rows, 100.0),
    "rastrigin": (rastrigin, rastrigin_rows, 5.12),
}


def best_of(repeat, f):
    times = []
    for _ in range(repeat):
        t = time.process_time()
        f()
        times.append(time.process_time() - t)
    return min(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--budget", type=int, default=50_000)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    n = a.budget
    rows = []
    for name, (scalar, batched, half) in PROBLEMS.items():
        bounds = [(-half, half)] * D
        rust = best_of(a.repeat, lambda: mb.benchmark(name, D, "ga", n, 1, pop=POP))
        py = best_of(a.repeat, lambda: mb.minimize(scalar, bounds, "ga", n, 1, pop=POP))
        bat = best_of(a.repeat, lambda: mb.minimize(batched, bounds, "ga", n, 1, batch=True, pop=POP))
        rng = np.random.default_rng(1)
        X = rng.uniform(-half, half, size=(POP, D))
        calls = n // POP
        own = best_of(a.repeat, lambda: [batched(X) for _ in range(calls)])
        row = {"problem": f"{name}-{D}", "rust": rust / n, "python scalar": py / n,
               "python batched": bat / n, "numpy alone": own / n}
        try:
            from mealpy import FloatVar, GA

            prob = {"obj_func": scalar, "bounds": FloatVar(lb=(-half,) * D, ub=(half,) * D),
                    "minmax": "min", "log_to": None}
            epochs = n // POP
            model = GA.BaseGA(epoch=epochs, pop_size=POP)
            row["mealpy GA"] = best_of(1, lambda: model.solve(prob, seed=1)) / n
        except Exception as e:  # not installed, or another API
            row["mealpy GA"] = f"n/a ({type(e).__name__})"
        try:
            from niapy.algorithms.basic import GeneticAlgorithm
            from niapy.problems import Problem
            from niapy.task import Task

            class P(Problem):
                def __init__(self):
                    super().__init__(D, -half, half)

                def _evaluate(self, x):
                    return scalar(x)

            def niapy_run():
                task = Task(problem=P(), max_evals=n)
                GeneticAlgorithm(population_size=POP, seed=1).run(task)

            row["NiaPy GA"] = best_of(1, niapy_run) / n
        except Exception as e:
            row["NiaPy GA"] = f"n/a ({type(e).__name__})"
        rows.append(row)
    keys = list(rows[0])
    print("| " + " | ".join(keys) + " |")
    print("|" + "---|" * len(keys))
    for r in rows:
        cells = [r["problem"]] + [
            f"{v * 1e6:.3g} µs" if isinstance(v, float) else v for k, v in r.items() if k != "problem"
        ]
        print("| " + " | ".join(cells) + " |")
    for r in rows:
        print(f"{r['problem']}: batched / numpy alone = {r['python batched'] / r['numpy alone']:.2f}; "
              f"batched overhead per evaluation = {(r['python batched'] - r['rust']) * 1e9:.0f} ns")


if __name__ == "__main__":
    main()
