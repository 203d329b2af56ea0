"""minimize in the shape a SciPy user knows (issue 53): x a NumPy array in
and out, x0, args, callback and target stops, seed=None reported, and the
default algorithm from the project's rule."""

import math

import numpy as np
import pytest

import metabezier as mb


def sphere(x, shift=0.0):
    assert isinstance(x, np.ndarray) and x.dtype == np.float64
    return float(((x - shift) ** 2).sum())


@pytest.mark.parametrize("algorithm", sorted(mb.algorithms()))
def test_x0_is_the_first_evaluation_and_the_best_is_never_worse(algorithm):
    seen = []

    def f(x):
        seen.append(x.copy())
        return sphere(x, 0.7)

    x0 = [0.69, 0.71, 0.7]
    r = mb.minimize(f, [(-5, 5)] * 3, x0=x0, algorithm=algorithm, budget=300, seed=2)
    assert list(seen[0]) == x0
    assert r.fun <= sphere(np.array(x0), 0.7)
    assert isinstance(r.x, np.ndarray) and r.x.shape == (3,)
    with pytest.raises(ValueError, match=r"x0\[1\] = 9: expected a number inside bounds\[1\]"):
        mb.minimize(f, [(-5, 5)] * 3, x0=[0, 9, 0], algorithm=algorithm, budget=10)
    with pytest.raises(ValueError, match="x0: expected 3 values"):
        mb.minimize(f, [(-5, 5)] * 3, x0=[0, 0], algorithm=algorithm, budget=10)


def test_args_are_passed_after_x():
    r = mb.minimize(sphere, [(-5, 5)] * 2, args=(1.5,), algorithm="cmaes", budget=3000, seed=4)
    assert np.allclose(r.x, 1.5, atol=1e-4)
    s = mb.minimize(sphere, [(-5, 5)] * 2, args=1.5, algorithm="cmaes", budget=3000, seed=4)
    assert list(r.x) == list(s.x)
    b = mb.minimize(lambda X, c: ((X - c) ** 2).sum(axis=1), [(-5, 5)] * 2, args=(1.5,),
                    algorithm="cmaes", budget=3000, seed=4, batch=True)
    assert list(b.x) == list(r.x)


@pytest.mark.parametrize("how", ["true", "stopiteration"])
def test_callback_sees_the_best_so_far_and_may_stop_the_run(how):
    seen = []

    def callback(intermediate_result):
        seen.append((intermediate_result.nfev, intermediate_result.fun, intermediate_result.x.copy()))
        if intermediate_result.nfev >= 100:
            if how == "true":
                return True
            raise StopIteration

    r = mb.minimize(sphere, [(-5, 5)] * 4, algorithm="hs", budget=10**6, seed=3, callback=callback)
    assert r.nfev == 100 and not r.success and "callback" in r.message
    assert [n for n, _, _ in seen][:5] == [1, 2, 3, 4, 5] and seen[-1][0] == 100
    assert all(a[1] >= b[1] for a, b in zip(seen, seen[1:])), "the best so far"
    assert seen[-1][1] == r.fun and list(seen[-1][2]) == list(r.x)


def test_an_exception_in_callback_propagates_at_once():
    calls = []

    def callback(res):
        calls.append(res.nfev)
        raise ZeroDivisionError("in the callback")

    with pytest.raises(ZeroDivisionError, match="in the callback"):
        mb.minimize(sphere, [(-5, 5)] * 2, algorithm="hs", budget=10**9, seed=1, callback=callback)
    assert calls == [1]


def test_target_stops_the_run_where_it_is_reached():
    r = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="cmaes", budget=10**6, seed=8, target=1e-6)
    assert r.success and r.fun <= 1e-6 and r.nfev < 10**4 and "target" in r.message
    full = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="cmaes", budget=r.nfev, seed=8)
    assert full.fun == r.fun, "the same run, ended at the target"
    with pytest.raises(ValueError, match="target = nan"):
        mb.minimize(sphere, [(-5, 5)], target=math.nan)


def test_seed_none_draws_fresh_entropy_and_reports_it():
    a = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="pso", budget=500)
    b = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="pso", budget=500)
    assert a.seed != b.seed and 0 <= a.seed < 2**64
    again = mb.minimize(sphere, [(-5, 5)] * 3, algorithm="pso", budget=500, seed=a.seed)
    assert list(again.x) == list(a.x) and again.fun == a.fun


@pytest.mark.parametrize(
    "dim, budget, expected",
    [(2, 10**5, "lshade"), (10, 10**5, "lshade"), (10, 10**4, "cmaes"), (30, 10**5, "cmaes"), (40_000, 100, "mhs")],
)
def test_the_default_algorithm_is_the_recommended_one(dim, budget, expected):
    assert mb.recommended(dim, budget) == expected
    if dim <= 30:
        r = mb.minimize(lambda x: float(x.sum()), [(0, 1)] * dim, budget=budget // 100, seed=1)
        assert r.algorithm == mb.recommended(dim, budget // 100)
