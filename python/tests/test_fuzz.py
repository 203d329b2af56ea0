"""A seeded fuzz loop over the Python entry points (issue 49): arguments
of every kind and objectives that misbehave. Each call either returns a
result that holds together or raises a Python exception a user can act on
(ValueError, TypeError, MemoryError, or the objective's own exception,
raised at once): never a Rust panic, an OverflowError or a SystemError.
The seed is fixed, so a failure is replayed by its case number."""

import math
import random

import numpy as np
import pytest

import metabezier as mb

SEED = 20261205
CASES = 2000

ODD = [
    0, -1, 2**64, 10**30, -(10**30), 1.5, math.nan, math.inf, -0.0, True, None,
    "", "x", "sphere", [], [1], {}, object(), b"1", (1, 2), "10", 3 + 4j,
    np.int64(7), np.float64(2.0), np.array([1.0, 2.0]),
]
ALGORITHMS = sorted(mb.algorithms())


class Planted(Exception):
    """The objective's own exception."""


def objective(rng):
    """A misbehaving ``fun`` (and whether it is a batch one), with a call
    counter, raising ``Planted`` at a random call in some cases."""
    kind = rng.choice(["ok", "nan", "inf", "-inf", "str", "none", "list", "raise", "numpy", "mixed"])
    at = rng.randint(1, 40)
    calls = [0]

    def value(x):
        calls[0] += 1
        if kind == "raise" and calls[0] == at:
            raise Planted(f"call {at}")
        return {
            "ok": lambda: float(sum(v * v for v in x)),
            "nan": lambda: math.nan,
            "inf": lambda: math.inf,
            "-inf": lambda: -math.inf,
            "str": lambda: "one",
            "none": lambda: None,
            "list": lambda: [1.0],
            "raise": lambda: 0.0,
            "numpy": lambda: np.float64(sum(x)),
            "mixed": lambda: math.nan if calls[0] % 3 else float(calls[0]),
        }[kind]()

    batch = rng.random() < 0.3 and kind not in ("str", "none", "list")

    def rows(X):
        return np.array([value(list(r)) for r in X], dtype=float)

    return (rows if batch else value), batch, kind, calls, at


def arguments(rng):
    """minimize's arguments, valid or with one or two replaced by odd values."""
    dim = rng.randint(1, 6)
    args = {
        "bounds": [(-1.0, 1.0)] * dim,
        "algorithm": rng.choice(ALGORITHMS) if rng.random() < 0.95 else "msh",
        "budget": rng.randint(1, 600),
        "seed": rng.randint(0, 2**64 - 1),
    }
    for _ in range(rng.choice([0, 0, 0, 1, 2])):
        args[rng.choice(list(args))] = rng.choice(ODD)
    if rng.random() < 0.2:
        args[rng.choice(["hms", "hmcr", "popsize", "lambda", "nonsense"])] = rng.choice(ODD + [5, 0.5])
    return args


ALLOWED = (ValueError, TypeError, MemoryError, Planted)


def check_result(r, args):
    budget = args["budget"]
    assert 1 <= r.nfev <= budget
    assert len(r.x) == len(args["bounds"])
    assert r.success == (math.isfinite(r.fun)), (r.fun, r.success, r.message)
    bests = [b for _, b in r.trace]
    assert all(a >= b or math.isnan(a) for a, b in zip(bests, bests[1:]))
    assert r.trace[-1][0] == r.nfev


@pytest.mark.parametrize("block", range(4))
def test_minimize_never_panics_and_stops_at_the_first_exception(block):
    rng = random.Random(SEED + block)
    for case in range(CASES // 4):
        fun, batch, kind, calls, at = objective(rng)
        args = arguments(rng)
        where = f"block {block} case {case}: kind={kind} batch={batch} args={args!r}"
        try:
            r = mb.minimize(fun, batch=batch, **args)
        except ALLOWED as e:
            if isinstance(e, Planted):
                assert calls[0] == at, f"{where}: {calls[0]} calls after the exception at {at}"
            else:
                assert str(e), where
            continue
        except BaseException as e:  # a panic, an OverflowError, a SystemError
            pytest.fail(f"{where}: {type(e).__name__}: {e}")
        check_result(r, args)


def test_benchmark_and_fit_never_panic():
    rng = random.Random(SEED)
    names = ["sphere", "rastrigin", "rosenbrock", "nosuch"]
    for case in range(400):
        args = {
            "function": rng.choice(names),
            "dim": rng.randint(1, 40),
            "algorithm": rng.choice(ALGORITHMS),
            "budget": rng.randint(1, 3000),
            "seed": rng.randint(0, 99),
        }
        for _ in range(rng.choice([0, 1, 2])):
            args[rng.choice(list(args))] = rng.choice(ODD)
        try:
            r = mb.benchmark(**args)
        except (ValueError, TypeError, MemoryError):
            continue
        except BaseException as e:
            pytest.fail(f"benchmark case {case} {args!r}: {type(e).__name__}: {e}")
        assert r.nfev == args["budget"] and r.success
    for case in range(200):
        n = rng.randint(0, 60)
        points = [(math.cos(t / max(n, 1) * 6.2) * 50, math.sin(t / max(n, 1) * 6.2) * 30) for t in range(n)]
        if rng.random() < 0.3 and points:
            points[rng.randrange(len(points))] = rng.choice([(math.nan, 0.0), (1e300, 0.0), ("a", 1), (1,)])
        args = {
            "segments": rng.choice([None, 1, 3, 0, -2, 10**30, 1.5]),
            "tolerance": rng.choice([None, 0.5, 0.0, -1.0, math.inf, math.nan]),
            "budget": rng.choice([1, 200, 0, 10**30]),
            "function": rng.choice(["cubic", "rational-cubic", "quadratic", "nosuch"]),
            "algorithm": rng.choice(["lm", "mhs", "hs+lm", "nosuch"]),
            "corner_k": rng.choice([5, 0, 10**30]),
        }
        try:
            r = mb.fit(points, **args)
        except (ValueError, TypeError, MemoryError):
            continue
        except BaseException as e:
            pytest.fail(f"fit case {case} n={n} {args!r}: {type(e).__name__}: {e}")
        assert r.metrics["segments"] == len(r.segments) >= 1
        assert math.isfinite(r.metrics["max_distance"])
