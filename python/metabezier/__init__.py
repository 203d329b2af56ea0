"""metabezier from Python: its optimisers, campaigns and curve fitting.

Every function calls the Rust library (the extension module
``metabezier._core``); nothing here re-implements an algorithm. The same
seed gives the same bits as the library and the ``metabezier`` command line.

- :func:`minimize` runs one optimiser on a Python function, in the shape of
  ``scipy.optimize.minimize``.
- :func:`register_problem` lets a spec name a Python function; :func:`run`
  runs a TOML spec exactly as ``metabezier run`` does, :func:`report` writes
  its report, and :func:`load` reads the results back as columns.
- :func:`fit` fits (rational) Bézier curves to points, :func:`score` measures
  points against the curves of an SVG.
"""

from __future__ import annotations

import csv
import math
import operator
import os
import secrets
import warnings
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np

from . import _core

__version__ = _core.__version__

#: The most evaluations one run may have, as in a spec (``MAX_BUDGET``).
MAX_BUDGET: int = _core.MAX_BUDGET

__all__ = [
    "Algorithm",
    "FitResult",
    "OptimizeResult",
    "Segment",
    "algorithms",
    "benchmark",
    "fit",
    "load",
    "minimize",
    "recommended",
    "register_problem",
    "report",
    "run",
    "score",
]


@dataclass(frozen=True)
class Algorithm:
    """A registered optimiser: its name, its source and its parameters as
    ``(name, default, what it admits)``, as ``metabezier list`` shows them."""

    name: str
    source: str
    params: List[Tuple[str, str, str]]


def algorithms() -> Dict[str, Algorithm]:
    """Every optimiser :func:`minimize` and the specs can name, by name."""
    return {name: Algorithm(name, source, list(params)) for name, source, params in _core.algorithms()}


@dataclass
class OptimizeResult:
    """The outcome of :func:`minimize`, named as ``scipy.optimize.OptimizeResult``.

    ``x`` is the best point found and ``fun`` its value; ``nfev`` the
    evaluations used (never more than the budget); ``nit`` is ``None``: the
    optimisers count evaluations, not iterations. ``trace`` is the
    best-so-far value at log-spaced evaluation counts, as
    ``[(evaluations, best), ...]``, ending at the last evaluation.
    """

    x: Any  # a NumPy array of D floats
    fun: float
    nfev: int
    nit: Optional[int]
    trace: List[Tuple[int, float]]
    algorithm: str
    seed: int
    params: Dict[str, Any] = field(default_factory=dict)
    success: bool = True
    message: str = "budget spent"

    def __getitem__(self, key: str) -> Any:  # scipy's results are also dicts
        return getattr(self, key)


def _integer(value: Any, name: str, low: int, high: int, what: str) -> int:
    """``value`` as an int in ``[low, high]``, or a ``ValueError`` naming
    ``name`` (a bool, a float or anything out of range is refused)."""
    if not isinstance(value, bool):
        try:
            n = operator.index(value)
        except TypeError:
            n = None
        if n is not None and low <= n <= high:
            return n
    raise ValueError(f"{name} = {value!r}: expected {what}, an integer from {low} to {high}")


def _budget(budget: Any, name: str = "budget") -> int:
    return _integer(budget, name, 1, MAX_BUDGET, "a number of evaluations")


def _seed(seed: Any) -> int:
    return _integer(seed, "seed", 0, 2**64 - 1, "a seed")


def _verdict(best: float, nfev: int) -> Tuple[bool, str]:
    """``success`` and ``message`` of a run whose best value is ``best``."""
    if math.isnan(best) or best == math.inf:
        return False, f"no finite value of fun was seen in {nfev} evaluations (each was NaN or inf)"
    if best == -math.inf:
        return False, "fun returned -inf: the problem is unbounded below where it was evaluated"
    return True, "budget spent"


def _bounds_pairs(bounds: Any) -> List[Tuple[float, float]]:
    """``bounds`` as a list of ``(lower, upper)`` floats, or a ``ValueError``."""
    try:
        pairs = [tuple(b) for b in bounds]
    except TypeError:
        raise ValueError(
            "bounds: expected a sequence of (lower, upper) pairs, one per variable"
        ) from None
    out = []
    for i, b in enumerate(pairs):
        if len(b) != 2:
            raise ValueError(
                f"bounds[{i}]: expected a (lower, upper) pair, got {len(b)} values"
            )
        try:
            out.append((float(b[0]), float(b[1])))
        except (TypeError, ValueError):
            raise ValueError(f"bounds[{i}] = {b!r}: expected two numbers") from None
    return out


def _floats(values: Any, name: str) -> List[float]:
    """``values`` as a list of floats, or a ``ValueError`` naming ``name``."""
    try:
        return [float(v) for v in np.asarray(values, dtype=float).reshape(-1)]
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a sequence of numbers") from None


def _real(value: Any, name: str) -> float:
    """``value`` as a float (not NaN), or a ``ValueError`` naming ``name``."""
    if not isinstance(value, bool):
        try:
            x = float(value)
        except (TypeError, ValueError):
            x = math.nan
        if not math.isnan(x):
            return x
    raise ValueError(f"{name} = {value!r}: expected a number")


def _scalar_adapter(fun: Callable, args: tuple) -> Callable:
    """Wraps ``fun(x, *args)`` for the Rust side, which passes ``x`` as a
    list: ``fun`` gets a NumPy array of its own, as in SciPy."""

    def call(x: List[float]) -> Any:
        return fun(np.array(x, dtype=float), *args)

    return call


def _callback_adapter(callback: Callable, algorithm: str, seed: int, params: Dict[str, Any]) -> Callable:
    """Wraps SciPy's ``callback(intermediate_result)`` for the Rust side,
    which passes the best point, its value and the evaluations so far and
    reads ``True`` as "stop" (a ``StopIteration`` too)."""

    def call(x: List[float], best: float, nfev: int) -> bool:
        result = OptimizeResult(
            x=np.array(x, dtype=float), fun=best, nfev=nfev, nit=None, trace=[],
            algorithm=algorithm, seed=seed, params=dict(params), message="in progress",
        )
        try:
            return bool(callback(result))
        except StopIteration:
            return True

    return call


def _batch_adapter(fun: Callable, dim: int, args: tuple = ()) -> Callable:
    """Wraps a vectorised ``fun`` (an ``(n, D)`` array in, ``n`` values out)
    for the Rust side, which passes the rows as bytes."""

    def call(buf: bytes, n: int) -> bytes:
        xs = np.frombuffer(buf, dtype=np.float64).reshape(n, dim)
        y = np.asarray(fun(xs, *args), dtype=np.float64).reshape(-1)
        if y.shape[0] != n:
            raise ValueError(f"fun returned {y.shape[0]} values for a batch of {n} points")
        return y.tobytes()

    return call


def minimize(
    fun: Callable,
    bounds: Sequence[Tuple[float, float]],
    x0: Optional[Sequence[float]] = None,
    args: Any = (),
    algorithm: Optional[str] = None,
    budget: int = 10_000,
    seed: Optional[int] = None,
    callback: Optional[Callable] = None,
    target: Optional[float] = None,
    batch: bool = False,
    **params: Any,
) -> OptimizeResult:
    """Minimises ``fun`` over the box ``bounds`` with a registered optimiser,
    in the shape of ``scipy.optimize.minimize`` and ``differential_evolution``.

    ``fun(x, *args)`` gets ``x`` as a NumPy array of ``D`` floats and
    returns a number. With ``batch=True`` it gets an ``(n, D)`` array and
    returns ``n`` values: one call per generation for the optimisers that
    evaluate a population at once (``ga``, ``cmaes``, ``lshade``,
    ``random``); the others call it with one row at a time.

    - ``x0``: a start point inside the bounds, the run's first evaluation
      (the first member of the initial population, as SciPy's
      ``differential_evolution`` places it; CMA-ES's first mean, as pycma's).
    - ``algorithm``: a name of :func:`algorithms`; ``None`` takes
      :func:`recommended` for ``D`` and ``budget``, the project's rule from
      its own results.
    - ``budget`` counts evaluations (at most ``MAX_BUDGET``).
    - ``seed``: ``None`` draws fresh entropy, as SciPy does; the seed used is
      ``result.seed``, and passing it again gives the same result, bit for
      bit.
    - ``callback(intermediate_result)`` is called at every checkpoint of the
      trace (10 a decade of evaluations) with an :class:`OptimizeResult` of
      the best so far; returning ``True`` or raising ``StopIteration`` stops
      the run (``success=False``, as SciPy).
    - ``target``: stop at the first evaluation with ``fun <= target``
      (``success=True``).
    - ``params`` are the algorithm's parameters, named as in
      :func:`algorithms` (``metabezier list``).

    An exception raised in ``fun`` or ``callback`` stops the run at once and
    propagates with its traceback; Ctrl-C raises ``KeyboardInterrupt``.
    ``success`` is ``False`` (with a ``message``) when no finite value was
    seen.

    >>> r = minimize(lambda x: float((x * x).sum()), [(-5, 5)] * 3, algorithm="mhs", budget=2000, seed=7)
    >>> r.fun < 1e-2, r.nfev
    (True, 2000)
    """
    pairs = _bounds_pairs(bounds)
    budget = _budget(budget)
    seed = secrets.randbits(64) if seed is None else _seed(seed)
    if not callable(fun):
        raise ValueError("fun: expected a callable")
    if callback is not None and not callable(callback):
        raise ValueError("callback: expected a callable or None")
    args = args if isinstance(args, tuple) else (args,)
    start = None if x0 is None else _floats(x0, "x0")
    goal = None if target is None else _real(target, "target")
    if algorithm is None:
        algorithm = _core.recommended(len(pairs), budget)
    algorithm = str(algorithm)
    objective = _batch_adapter(fun, len(pairs), args) if batch else _scalar_adapter(fun, args)
    observe = None if callback is None else _callback_adapter(callback, algorithm, seed, params)
    (x, best, nfev, trace), ended = _core.minimize(
        objective, pairs, algorithm, budget, seed, bool(batch), params or None, start, goal, observe
    )
    if ended == "callback":
        success, message = False, f"stopped by callback after {nfev} evaluations"
    elif ended == "target":
        success, message = True, f"target {goal!r} reached after {nfev} evaluations"
    else:
        success, message = _verdict(best, nfev)
    return OptimizeResult(
        x=np.array(x, dtype=float),
        fun=best,
        nfev=nfev,
        nit=None,
        trace=list(trace),
        algorithm=algorithm,
        seed=seed,
        params=dict(params),
        success=success,
        message=message,
    )


def recommended(dim: int, budget: int) -> str:
    """The optimiser the project's own results recommend for ``budget``
    evaluations at dimension ``dim``, the default of :func:`minimize`:
    ``lshade`` where ``dim <= 10`` and ``budget >= 10**4 * dim``, else
    ``cmaes`` where one run's state fits in 4 GiB, else ``mhs``
    (the evidence: the Rust documentation of ``optim::recommend``)."""
    return _core.recommended(_integer(dim, "dim", 1, 2**32, "a dimension"), _budget(budget))


def benchmark(
    function: str,
    dim: int,
    algorithm: Optional[str] = None,
    budget: int = 10_000,
    seed: Optional[int] = None,
    **params: Any,
) -> OptimizeResult:
    """One run on a built-in benchmark function (``sphere``, ``rastrigin``,
    ... as ``metabezier list`` names them) at dimension ``dim``, entirely in
    Rust: the same run a spec makes with the same seed. ``fun`` is the
    objective value; ``algorithm`` and ``seed`` default as in
    :func:`minimize`. Ctrl-C raises ``KeyboardInterrupt``."""
    dim = _integer(dim, "dim", 1, 2**32, "a dimension")
    budget = _budget(budget)
    seed = secrets.randbits(64) if seed is None else _seed(seed)
    algorithm = _core.recommended(dim, budget) if algorithm is None else str(algorithm)
    x, best, nfev, trace = _core.benchmark(str(function), dim, algorithm, budget, seed, params or None)
    success, message = _verdict(best, nfev)
    return OptimizeResult(
        x=np.array(x, dtype=float), fun=best, nfev=nfev, nit=None, trace=list(trace),
        algorithm=algorithm, seed=seed, params=dict(params),
        success=success, message=message,
    )


def register_problem(
    name: str,
    fun: Callable,
    bounds: Union[Tuple[float, float], Sequence[Tuple[float, float]]],
    optimum: float = 0.0,
    batch: bool = False,
) -> None:
    """Registers ``fun`` so that a spec may name it: ``[[problem]] function
    = "name"`` with ``dim``. ``bounds`` is one ``(lower, upper)`` pair for
    every variable at any dimension, or a list of pairs for that dimension
    only. ``optimum`` is ``f*``, from which the error and the targets are
    measured. ``batch`` as in :func:`minimize`. A name of a built-in
    function is refused."""
    if isinstance(bounds, tuple) and len(bounds) == 2 and not isinstance(bounds[0], (tuple, list)):
        pairs, per_variable = _bounds_pairs([bounds]), False
    else:
        pairs, per_variable = _bounds_pairs(bounds), True
    if not callable(fun):
        raise ValueError("fun: expected a callable")
    if batch:
        if not per_variable:
            raise ValueError("batch=True needs one (lower, upper) pair per variable (a fixed dimension)")
        fun = _batch_adapter(fun, len(pairs))
    _core.register_problem(name, fun, pairs, per_variable, float(optimum), bool(batch))


@dataclass(frozen=True)
class RunSummary:
    """What :func:`run` did: the results directory and the run counts."""

    out: str
    total: int
    reused: int
    executed: int
    complete: bool


def run(
    spec: Union[str, os.PathLike],
    out: Optional[Union[str, os.PathLike]] = None,
    threads: Optional[int] = None,
    resume: bool = False,
    shard: Optional[str] = None,
    allow_large: bool = False,
) -> RunSummary:
    """Runs a campaign exactly as ``metabezier run`` does: ``spec`` is a
    path to a TOML spec, or the TOML text itself (any string with a
    newline); ``out`` the results directory (default: the spec's
    ``results/<name>``), ``threads`` the workers (default all cores; the
    results are the same for any number), ``resume`` reuses finished runs,
    ``shard`` is ``"K/N"``. Problems registered with
    :func:`register_problem` may be named. Ctrl-C raises
    ``KeyboardInterrupt`` within a few evaluations of every run in
    progress; the finished runs are kept, and ``resume=True`` finishes the
    others."""
    text = os.fspath(spec)
    directory = None if out is None else os.fspath(out)
    if threads is not None:
        threads = _integer(threads, "threads", 1, 2**32, "a number of worker threads")
    *result, dropped = _core.run(text, directory, threads, bool(resume), shard, bool(allow_large))
    for message in dropped:
        # A journal row that disagrees with itself: its run was redone.
        warnings.warn(message, RuntimeWarning, stacklevel=2)
    return RunSummary(*result)


def report(results: Union[str, os.PathLike]) -> str:
    """Writes ``report.md`` (with its tables and figures) into a results
    directory, as ``metabezier report`` does, and returns its path."""
    return _core.report(os.fspath(results))


def _column(values: List[str]) -> List[Any]:
    """A CSV column as ints, else floats, else strings (empty cells ``None``)."""
    present = [v for v in values if v != ""]
    for kind in (int, float):
        try:
            converted = {v: kind(v) for v in set(present)}
        except ValueError:
            continue
        return [converted[v] if v != "" else None for v in values]
    return [v if v != "" else None for v in values]


def _read_columns(path: str) -> Dict[str, List[Any]]:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    header, body = rows[0], rows[1:]
    return {name: _column([r[i] for r in body]) for i, name in enumerate(header)}


def load(results: Union[str, os.PathLike], pandas: Optional[bool] = None) -> Dict[str, Any]:
    """Reads a results directory: ``runs``, ``convergence`` and ``hits``
    (and ``fits``, ``segments`` where a fitting campaign wrote them), each
    as a dict of columns, or as a pandas DataFrame when pandas is installed
    (``pandas=False`` keeps the dicts; ``True`` requires pandas)."""
    directory = os.fspath(results)
    if not os.path.isfile(os.path.join(directory, "runs.csv")):
        raise ValueError(f"{directory}: no runs.csv; expected a results directory of metabezier run")
    if pandas is None:
        try:
            import pandas as pd  # noqa: F401

            pandas = True
        except ImportError:
            pandas = False
    out: Dict[str, Any] = {}
    for name in ("runs", "convergence", "hits", "fits", "segments"):
        path = os.path.join(directory, f"{name}.csv")
        if not os.path.isfile(path):
            continue
        if pandas:
            import pandas as pd

            out[name] = pd.DataFrame(_read_columns(path))
        else:
            out[name] = _read_columns(path)
    return out


@dataclass(frozen=True)
class Segment:
    """One fitted segment: its contour, function, control points and
    weights (all 1 for a polynomial segment), and the indices of its first
    and last data points."""

    contour: int
    function: str
    control_points: List[Tuple[float, float]]
    weights: List[float]
    first: int
    last: int


@dataclass(frozen=True)
class FitResult:
    """The outcome of :func:`fit`: the segments and the metrics (``sse`` =
    E, ``rms`` at the data parameters, ``rms_distance`` and
    ``max_distance`` orthogonal, ``points``, ``segments``, ``evaluations``)."""

    segments: List[Segment]
    metrics: Dict[str, float]


def _points(points: Any) -> List[Tuple[float, float]]:
    """``points`` as ``(x, y)`` floats, read once (a generator works too)."""
    out = []
    try:
        for p in points:
            x, y = p
            out.append((float(x), float(y)))
    except (TypeError, ValueError):
        raise ValueError("points: expected a sequence of (x, y) pairs") from None
    return out


def fit(
    points: Sequence[Tuple[float, float]],
    function: str = "rational-cubic",
    continuity: str = "g1",
    segments: Optional[int] = None,
    tolerance: Optional[float] = None,
    algorithm: str = "lm",
    budget: int = 10_000,
    seed: int = 1,
    closed: Optional[bool] = None,
    closing: str = "smooth",
    search_space: str = "technique",
    parameterisation: str = "auto",
    error: str = "orthogonal",
    chain: str = "joint",
    corner_angle: float = 60.0,
    corner_k: int = 5,
) -> FitResult:
    """Fits piecewise (rational) Bézier curves to ``points`` as ``metabezier
    fit`` fits a CSV of points: to ``tolerance`` (default 1, in the points'
    units: every point within it of the curve and the curve within it of the
    points' polyline, with as few segments as found), or ``segments`` of
    them; the metrics include ``max_distance`` (data to curve),
    ``curve_distance`` (curve to data) and ``hausdorff``; ``algorithm`` is an optimiser,
    ``lm`` (the default), or ``<optimiser>+lm``; ``budget`` counts evaluations
    per segment; ``error`` is ``orthogonal`` (the default: each point's
    distance to the curve) or ``fixed`` (the thesis's E at the parameters);
    ``chain`` is ``joint`` (the default: all segments solved together with
    shared joins) or ``sequential`` (one after another, the thesis's).
    The names are those of the command line. As in a CSV of points, the
    outline is closed when its last point repeats the first (that point is
    dropped), unless ``closed`` says otherwise. Ctrl-C raises
    ``KeyboardInterrupt``."""
    pts = _points(points)
    if segments is not None:
        segments = _integer(segments, "segments", 1, 2**32, "a number of segments")
    budget, seed = _budget(budget), _seed(seed)
    corner_k = _integer(corner_k, "corner_k", 1, 2**32, "a number of neighbours")
    rows, metrics = _core.fit(
        pts,
        None if closed is None else bool(closed),
        function,
        continuity,
        segments,
        None if tolerance is None else float(tolerance),
        algorithm,
        budget,
        seed,
        closing,
        search_space,
        parameterisation,
        error,
        chain,
        float(corner_angle),
        corner_k,
    )
    segs = [
        Segment(c, f, [tuple(p) for p in cp], list(w), first, last)
        for c, f, cp, w, first, last in rows
    ]
    return FitResult(segs, {k: (int(v) if k in ("points", "segments", "evaluations") else v) for k, v in metrics})


def score(
    points: Sequence[Tuple[float, float]],
    svg: Union[str, os.PathLike],
    closed: Optional[bool] = None,
    offset: Tuple[float, float] = (0.0, 0.0),
) -> Dict[str, float]:
    """The orthogonal distances of ``points`` to the curves of ``svg`` (a
    path, or the SVG text itself), as ``metabezier score``:
    ``segments``, ``points``, ``max_distance`` and ``rms_distance``."""
    pts = _points(points)
    segments, n, max_distance, rms_distance = _core.score_svg(
        pts, None if closed is None else bool(closed), os.fspath(svg), (float(offset[0]), float(offset[1]))
    )
    return {
        "segments": segments,
        "points": n,
        "max_distance": max_distance,
        "rms_distance": rms_distance,
    }
