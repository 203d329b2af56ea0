"""minimize: reproducibility, batching, the same bits as a spec run, and
errors (exceptions from fun, bad bounds, unknown algorithms or parameters)."""

import math

import numpy as np
import pytest

import metabezier as mb


def sphere(x):
    return sum(v * v for v in x)


def sphere_rows(X):
    return (X * X).sum(axis=1)


@pytest.mark.parametrize("algorithm", sorted(mb.algorithms()))
def test_same_seed_same_result_every_algorithm(algorithm):
    a = mb.minimize(sphere, [(-5, 5)] * 4, algorithm=algorithm, budget=1500, seed=11)
    b = mb.minimize(sphere, [(-5, 5)] * 4, algorithm=algorithm, budget=1500, seed=11)
    c = mb.minimize(sphere, [(-5, 5)] * 4, algorithm=algorithm, budget=1500, seed=12)
    assert list(a.x) == list(b.x) and a.fun == b.fun and a.trace == b.trace
    assert list(a.x) != list(c.x)
    assert a.nfev == 1500 and a.trace[-1] == (1500, a.fun)
    assert all(-5 <= v <= 5 for v in a.x)
    assert math.isclose(sphere(a.x), a.fun, rel_tol=0, abs_tol=0)


@pytest.mark.parametrize("algorithm", ["ga", "cmaes", "lshade", "random", "mhs"])
def test_batch_gives_the_bits_of_scalar_calls(algorithm):
    calls = []

    def f(x):
        return sum(v * v for v in x)

    def rows(X):
        calls.append(X.shape[0])
        return np.array([f(r.tolist()) for r in X])

    def one(x):
        calls.append(1)
        return f(x)

    b = mb.minimize(rows, [(-3, 3)] * 6, algorithm=algorithm, budget=2000, seed=5, batch=True)
    n_batched = len(calls)
    calls.clear()
    s = mb.minimize(one, [(-3, 3)] * 6, algorithm=algorithm, budget=2000, seed=5)
    assert list(b.x) == list(s.x) and b.fun == s.fun and b.trace == s.trace
    if algorithm != "mhs":  # population methods: one call per generation
        assert n_batched < len(calls) / 5, (n_batched, len(calls))


def test_parameters_are_named_as_in_list():
    a = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="hs", budget=1000, seed=3, hms=10)
    b = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="hs", budget=1000, seed=3, hms=30)
    assert list(a.x) != list(b.x)
    names = [p[0] for p in mb.algorithms()["hs"].params]
    assert "hms" in names and "hmcr" in names


def test_matches_a_registered_problem_in_a_campaign(tmp_path):
    """The Python function through minimize and the same function named by
    a spec: the run's seed is recorded, and minimize with it gives the run."""
    mb.register_problem("py_sphere_min", sphere, (-5.0, 5.0))
    spec = """[experiment]
name = "py"
seed = 99
runs = 2
budget = 3000
threshold = 1e-8

[[problem]]
function = "py_sphere_min"
dim = 4

[[algorithm]]
name = "pso"
"""
    mb.run(spec, out=tmp_path / "r", threads=1)
    runs = mb.load(tmp_path / "r", pandas=False)["runs"]
    for seed, best in zip(runs["seed"], runs["best"]):
        r = mb.minimize(sphere, [(-5, 5)] * 4, algorithm="pso", budget=3000, seed=seed)
        assert repr(r.fun) == repr(best) or r.fun == best


def test_an_exception_in_fun_propagates():
    def bad(x):
        if x[0] > 0:
            raise KeyError("boom")
        return 0.0

    with pytest.raises(KeyError, match="boom"):
        mb.minimize(bad, [(-1, 1)] * 2, algorithm="ga", budget=500, seed=1)
    with pytest.raises(ValueError, match="3 values for a batch"):
        mb.minimize(lambda X: [1.0, 2.0, 3.0], [(-1, 1)] * 2, algorithm="ga", budget=500, batch=True)
    with pytest.raises(TypeError, match="real number"):
        mb.minimize(lambda x: "one", [(-1, 1)], budget=10)


@pytest.mark.parametrize(
    "bounds, message",
    [
        ([], "got none"),
        ([(1, 0)], r"bounds\[0\]"),
        ([(0, 1, 2)], "pair"),
        (5, "sequence"),
        ([(0, float("inf"))], "finite"),
        ([("a", 1)], "two numbers"),
    ],
)
def test_bad_bounds_are_value_errors(bounds, message):
    with pytest.raises(ValueError, match=message):
        mb.minimize(sphere, bounds, budget=10)


def test_unknown_algorithm_and_parameter_name_the_choices():
    with pytest.raises(ValueError, match='unknown algorithm "msh"; valid choices: .*"mhs"'):
        mb.minimize(sphere, [(-1, 1)], algorithm="msh")
    with pytest.raises(ValueError, match='unknown parameter "hmrc".*"hmcr"'):
        mb.minimize(sphere, [(-1, 1)], algorithm="hs", hmrc=0.9)
    with pytest.raises(ValueError, match=r"hs.hmcr: expected a real number in \[0, 1\]"):
        mb.minimize(sphere, [(-1, 1)], algorithm="hs", hmcr=2)
    with pytest.raises(ValueError, match="budget"):
        mb.minimize(sphere, [(-1, 1)], budget=0)


def test_optimiser_state_is_sized_before_it_is_allocated():
    # Issue 49: CMA-ES at D = 10**6 would need terabytes for its covariance;
    # the call raises a MemoryError naming the algorithm and D before
    # allocating anything. HS at D = 10**6 is linear in D and runs.
    wide = [(-1.0, 1.0)] * 1_000_000
    with pytest.raises(MemoryError, match=r"cmaes at D = 1000000 needs an estimated .* GiB"):
        mb.minimize(lambda x: 0.0, wide, algorithm="cmaes", budget=10)
    with pytest.raises(MemoryError, match=r"cmaes at D = 30000"):
        mb.benchmark("sphere", 30_000, algorithm="cmaes", budget=10)
    r = mb.minimize(lambda x: 0.0, wide, algorithm="hs", budget=6)
    assert r.nfev == 6
