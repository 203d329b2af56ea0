//! The Rust side of the `metabezier` Python package: thin bindings that call
//! the library and add no algorithm of their own. The Python layer
//! (`python/metabezier/__init__.py`) shapes the results; this module
//! converts arguments, runs the library and turns every error into a
//! Python exception (`ValueError` for bad arguments, `RuntimeError` for a
//! campaign or fit that fails, and the user's own exception when `fun`
//! raises).
//!
//! Python behaves like Python here: a call that runs Rust code for long
//! (`benchmark`, `run`, `fit`) runs it on a worker thread while the calling
//! thread looks for signals every [`SIGNAL_POLL`] and, on Ctrl-C, asks
//! every run to end ([`interrupt::request`]) and raises `KeyboardInterrupt`;
//! `minimize` calls Python for every evaluation and looks for signals after
//! each call. The first exception of a Python objective stops its run at
//! once: the problem unwinds out of the optimiser with
//! [`std::panic::resume_unwind`], which runs no panic hook, so nothing but
//! the exception reaches the user.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};
use std::time::Duration;

use metabezier::experiment::spec::MAX_BUDGET;
use metabezier::experiment::{
    run_campaign, ProblemDef, Registry, RunOptions, Spec, SpecLimits, Summary,
};
use metabezier::fit::{Chain, Closing, ErrorMeasure, FitOptions, FunctionType, SearchSpace};
use metabezier::geometry::{Continuity, Parameterisation, Point};
use metabezier::optim::{
    interrupt, recommended, EarlyEnd, Evaluator, Observer, Optimisers, ParamSet, Raw,
};
use metabezier::outline::{
    outline_from_points, svg_from_str, CornerOptions, CsvOptions, Outline, MAX_COORDINATE,
};
use metabezier::problem::{Bounds, Problem};
use metabezier::reconstruction::{
    score, Method, Reconstruction, Segmentation, Source, DEFAULT_TOLERANCE,
};
use metabezier::report::{write_report, ReportOptions};
use metabezier::rng::run_rng;
use pyo3::exceptions::{PyMemoryError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBytes, PyDict, PyList};

/// A problem whose objective is a Python callable.
///
/// Scalar mode calls `fun(x)` with a list of `D` floats per point; batch
/// mode calls the package's adapter with the row-major bytes of `n` points
/// and `n`, once per [`Problem::objective_batch`] (a generation of GA,
/// CMA-ES or L-SHADE), and reads `n` little-endian `f64` back. The first
/// exception `fun` raises (a `KeyboardInterrupt` from a signal seen after a
/// call too) is kept and the run unwinds at once ([`PyProblem::fail`]):
/// `minimize` re-raises it, a campaign's runner reports the run as stopped
/// with the finished runs kept.
struct PyProblem {
    name: String,
    fun: Py<PyAny>,
    bounds: Vec<Bounds>,
    batch: bool,
    /// A campaign's problem: its exception goes to [`CAMPAIGN_ERROR`], and
    /// an interrupt of the campaign ends its run at the next call.
    in_campaign: bool,
    /// The first exception of `fun` or of a `callback` observing its run.
    error: Arc<Mutex<Option<PyErr>>>,
}

/// The exception of the last failed campaign run, for `run` to re-raise.
static CAMPAIGN_ERROR: Mutex<Option<PyErr>> = Mutex::new(None);

impl PyProblem {
    /// Keeps `err` and ends the run at once: unwinds out of the optimiser
    /// without running the panic hook (no Rust text on stderr), to the
    /// `catch_unwind` of `minimize` or of the campaign runner.
    fn fail(&self, err: PyErr) -> ! {
        let message = format!("the Python function of problem {}: {err}", self.name);
        let slot = if self.in_campaign {
            &CAMPAIGN_ERROR
        } else {
            &*self.error
        };
        if let Ok(mut slot) = slot.lock() {
            slot.get_or_insert(err);
        }
        std::panic::resume_unwind(Box::new(message))
    }

    /// Ends a campaign's run at once when the campaign was interrupted.
    fn stop_if_interrupted(&self) {
        if self.in_campaign && interrupt::requested() {
            std::panic::resume_unwind(Box::new(String::from("interrupted")))
        }
    }

    fn take_error(&self) -> Option<PyErr> {
        self.error.lock().ok().and_then(|mut e| e.take())
    }

    fn call_scalar(&self, py: Python<'_>, x: &[f64]) -> PyResult<f64> {
        let list = PyList::new(py, x)?;
        let y = self.fun.bind(py).call1((list,))?;
        // A builtin `fun` runs no bytecode, where Python would handle a
        // signal: look for one after every call (a flag test when none).
        py.check_signals()?;
        y.extract::<f64>().map_err(|_| {
            PyTypeError::new_err(format!(
                "fun must return a real number, returned {}",
                y.get_type()
                    .name()
                    .map_or_else(|_| "?".into(), |n| n.to_string())
            ))
        })
    }

    fn call_batch(&self, py: Python<'_>, xs: &[f64], out: &mut [f64]) -> PyResult<()> {
        let bytes: Vec<u8> = xs.iter().flat_map(|v| v.to_le_bytes()).collect();
        let y = self
            .fun
            .bind(py)
            .call1((PyBytes::new(py, &bytes), out.len()))?;
        py.check_signals()?;
        let y = y.cast::<PyBytes>().map_err(|_| {
            PyTypeError::new_err("the batch adapter must return bytes (internal error)")
        })?;
        let data = y.as_bytes();
        if data.len() != out.len() * 8 {
            return Err(PyValueError::new_err(format!(
                "fun returned {} values for a batch of {}",
                data.len() / 8,
                out.len()
            )));
        }
        for (o, c) in out.iter_mut().zip(data.chunks_exact(8)) {
            let mut b = [0u8; 8];
            b.copy_from_slice(c);
            *o = f64::from_le_bytes(b);
        }
        Ok(())
    }
}

impl Problem for PyProblem {
    fn dim(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        if self.batch {
            let mut out = [0.0];
            self.objective_batch(x, &mut out);
            return out[0];
        }
        self.stop_if_interrupted();
        match Python::attach(|py| self.call_scalar(py, x)) {
            Ok(y) => y,
            Err(e) => self.fail(e),
        }
    }

    fn objective_batch(&self, xs: &[f64], out: &mut [f64]) {
        if !self.batch {
            metabezier::problem::objective_rows(self, xs, out);
            return;
        }
        self.stop_if_interrupted();
        if let Err(e) = Python::attach(|py| self.call_batch(py, xs, out)) {
            self.fail(e)
        }
    }
}

/// How often a call running Rust code on a worker thread looks for signals.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// Runs `work` on a worker thread while this thread looks for signals every
/// [`SIGNAL_POLL`], without the GIL; on a signal's exception (Ctrl-C's
/// `KeyboardInterrupt`) every run is asked to end ([`interrupt::request`]),
/// the worker is joined (its runs end within [`interrupt::POLL_EVALUATIONS`]
/// evaluations) and the exception is raised: whatever `work` returned is not
/// a result.
fn interruptible<T: Send>(py: Python<'_>, work: impl FnOnce() -> T + Send) -> PyResult<T> {
    let _watch = interrupt::Watch::begin();
    let caller = std::thread::current();
    let mut signal: Option<PyErr> = None;
    let joined = py.detach(|| {
        std::thread::scope(|s| {
            let worker = s.spawn(|| {
                let out = work();
                caller.unpark();
                out
            });
            while !worker.is_finished() {
                std::thread::park_timeout(SIGNAL_POLL);
                if signal.is_none() && !worker.is_finished() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        interrupt::request();
                        signal = Some(e);
                    }
                }
            }
            worker.join()
        })
    });
    if let Some(e) = signal {
        return Err(e);
    }
    match joined {
        Ok(out) => Ok(out),
        Err(panic) => std::panic::resume_unwind(panic),
    }
}

/// `[(lower, upper), ...]` as bounds, each finite with `lower < upper`.
fn bounds_of(pairs: &[(f64, f64)]) -> PyResult<Vec<Bounds>> {
    if pairs.is_empty() {
        return Err(PyValueError::new_err(
            "bounds: expected one (lower, upper) pair per variable, got none",
        ));
    }
    pairs
        .iter()
        .enumerate()
        .map(|(i, &(lo, hi))| {
            if lo.is_finite() && hi.is_finite() && lo < hi {
                Ok(Bounds::new(lo, hi))
            } else {
                Err(PyValueError::new_err(format!(
                    "bounds[{i}] = ({lo}, {hi}): expected finite numbers with lower < upper"
                )))
            }
        })
        .collect()
}

/// A Python value as a raw parameter value of a spec.
fn raw_of(value: &Bound<'_, PyAny>) -> Raw {
    if value.is_instance_of::<pyo3::types::PyBool>() {
        Raw::Other("boolean")
    } else if let Ok(n) = value.extract::<i64>() {
        Raw::Int(n)
    } else if let Ok(x) = value.extract::<f64>() {
        Raw::Float(x)
    } else if let Ok(s) = value.extract::<String>() {
        Raw::Text(s)
    } else {
        Raw::Other("object")
    }
}

/// The names of every registered optimiser, quoted.
fn algorithm_choices() -> String {
    metabezier::optim::quoted_list(&Optimisers::builtin().names())
}

/// The parameter set of `algorithm` with `params` applied, each checked
/// against its declaration.
fn param_set(algorithm: &str, params: Option<&Bound<'_, PyDict>>) -> PyResult<ParamSet> {
    let def = Optimisers::builtin().get(algorithm).ok_or_else(|| {
        PyValueError::new_err(format!(
            "unknown algorithm \"{algorithm}\"; valid choices: {}",
            algorithm_choices()
        ))
    })?;
    let mut set = ParamSet::defaults(def.params);
    if let Some(params) = params {
        for (key, value) in params.iter() {
            let key: String = key.extract()?;
            set.set(&key, &raw_of(&value)).map_err(|e| {
                let names: Vec<&str> = def.params.iter().map(|d| d.name).collect();
                PyValueError::new_err(format!(
                    "{algorithm}.{key}: {e}; the parameters of {algorithm} are {}",
                    metabezier::optim::quoted_list(&names)
                ))
            })?;
        }
    }
    Ok(set)
}

/// The registered optimiser `algorithm` with `params`, for a run of
/// `budget` (at least 1) evaluations at dimension `dim`; a `MemoryError`
/// naming the algorithm, D and the bytes where one run's state would be
/// over [`metabezier::optim::MAX_STATE_BYTES`] (as `metabezier check`).
fn configured(
    algorithm: &str,
    params: Option<&Bound<'_, PyDict>>,
    budget: u64,
    dim: usize,
) -> PyResult<metabezier::optim::Algorithm> {
    check_budget("budget", budget)?;
    let set = param_set(algorithm, params)?;
    let alg = Optimisers::builtin()
        .build(algorithm, &set)
        .map_err(|e| PyValueError::new_err(format!("{algorithm}: {e}")))?;
    let bytes = alg.state_bytes(dim, budget);
    if bytes > metabezier::optim::MAX_STATE_BYTES {
        return Err(PyMemoryError::new_err(format!(
            "{algorithm} at D = {dim} needs an estimated {:.1} GiB of state for one run, over \
             the limit of {} GiB (its matrices and populations grow with D); lower D or its \
             population",
            bytes as f64 / f64::from(1u32 << 30),
            metabezier::optim::MAX_STATE_BYTES >> 30
        )));
    }
    Ok(alg)
}

/// `budget` (named `name`) checked as a spec's: from 1 to
/// [`MAX_BUDGET`] evaluations.
fn check_budget(name: &str, budget: u64) -> PyResult<()> {
    if (1..=MAX_BUDGET).contains(&budget) {
        return Ok(());
    }
    Err(PyValueError::new_err(format!(
        "{name} = {budget}: expected from 1 to {MAX_BUDGET} evaluations (the limit of a spec's \
         budget, MAX_BUDGET)"
    )))
}

/// One run's result for Python: (best x, its value, evaluations used,
/// the trace as `(evaluations, best)`).
type RunResult = (Vec<f64>, f64, u64, Vec<(u64, f64)>);

/// [`RunResult`] of an outcome.
fn run_result(outcome: metabezier::optim::Outcome) -> RunResult {
    let trace = outcome
        .trace
        .iter()
        .map(|t| (t.evaluations, t.best))
        .collect();
    (
        outcome.best_x,
        outcome.best_value,
        outcome.evaluations,
        trace,
    )
}

/// An optimiser for Python: (name, source, [(parameter, default, admits)]).
type AlgorithmRow = (String, String, Vec<(String, String, String)>);

/// `x0` checked against `bounds`: one finite value per variable, inside.
fn start_of(x0: Vec<f64>, bounds: &[Bounds]) -> PyResult<Vec<f64>> {
    if x0.len() != bounds.len() {
        return Err(PyValueError::new_err(format!(
            "x0: expected {} values (one per variable of bounds), got {}",
            bounds.len(),
            x0.len()
        )));
    }
    for (i, (&x, b)) in x0.iter().zip(bounds).enumerate() {
        if !b.contains(x) {
            return Err(PyValueError::new_err(format!(
                "x0[{i}] = {x}: expected a number inside bounds[{i}] = ({}, {})",
                b.lower, b.upper
            )));
        }
    }
    Ok(x0)
}

/// The observer of a run for a Python `callback`: the package's adapter
/// gets `(x, fun, nfev)` at every checkpoint and returns `True` to stop;
/// its exception is kept in `slot` and ends the run at once.
fn observer_of(callback: Py<PyAny>, slot: Arc<Mutex<Option<PyErr>>>) -> Observer {
    Box::new(move |nfev, best, x| {
        match Python::attach(|py| {
            callback
                .bind(py)
                .call1((x.to_vec(), best, nfev))?
                .is_truthy()
        }) {
            Ok(stop) => !stop,
            Err(e) => {
                if let Ok(mut s) = slot.lock() {
                    s.get_or_insert(e);
                }
                std::panic::resume_unwind(Box::new(String::from("callback raised")))
            }
        }
    })
}

/// `minimize`: one run of a registered optimiser on a Python function,
/// from `x0` if given, stopped at `target` or by `callback` if given.
/// Returns `(x, fun, nfev, trace, ended)` with the trace as `(evaluations,
/// best)` and `ended` `"target"`, `"callback"` or `None` (the budget).
#[pyfunction]
#[pyo3(signature = (fun, bounds, algorithm, budget, seed, batch, params=None, x0=None, target=None, callback=None))]
#[allow(clippy::too_many_arguments)]
fn minimize(
    fun: Py<PyAny>,
    bounds: Vec<(f64, f64)>,
    algorithm: &str,
    budget: u64,
    seed: u64,
    batch: bool,
    params: Option<&Bound<'_, PyDict>>,
    x0: Option<Vec<f64>>,
    target: Option<f64>,
    callback: Option<Py<PyAny>>,
) -> PyResult<(RunResult, Option<&'static str>)> {
    let bounds = bounds_of(&bounds)?;
    let alg = configured(algorithm, params, budget, bounds.len())?;
    let x0 = x0.map(|x| start_of(x, &bounds)).transpose()?;
    if let Some(t) = target.filter(|t| t.is_nan()) {
        return Err(PyValueError::new_err(format!(
            "target = {t}: expected a number (a value of fun at which to stop)"
        )));
    }
    let problem = PyProblem {
        name: "fun".into(),
        fun,
        bounds,
        batch,
        in_campaign: false,
        error: Arc::default(),
    };
    let mut eval = Evaluator::new(&problem as &dyn Problem, budget);
    if let Some(x0) = x0 {
        eval = eval.with_start(x0);
    }
    if let Some(t) = target {
        eval = eval.with_target(t).stop_at_target();
    }
    if let Some(cb) = callback {
        eval = eval.with_observer(observer_of(cb, Arc::clone(&problem.error)));
    }
    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        alg.minimise(&mut eval, &mut run_rng(seed));
    }));
    match (run, problem.take_error()) {
        (Ok(()), _) => {
            let ended = match eval.ended_early() {
                Some(EarlyEnd::Target) => Some("target"),
                Some(EarlyEnd::Observer) => Some("callback"),
                _ => None,
            };
            Ok((run_result(eval.finish()), ended))
        }
        (Err(_), Some(e)) => Err(e),
        (Err(panic), None) => std::panic::resume_unwind(panic),
    }
}

/// `recommended`: the optimiser the project's results recommend for a run
/// of `budget` evaluations at dimension `dim` ([`recommended`]).
#[pyfunction]
#[pyo3(name = "recommended")]
fn recommended_algorithm(dim: usize, budget: u64) -> &'static str {
    recommended(dim, budget)
}

/// `benchmark`: one run of a registered optimiser on a built-in benchmark
/// function at dimension `dim`, all in Rust (the monomorphic path a spec
/// run takes). Returns `(x, f, nfev, trace)` like [`minimize`], with `f`
/// the objective value (not the error `f − f*`).
#[pyfunction]
#[pyo3(signature = (function, dim, algorithm, budget, seed, params=None))]
fn benchmark(
    py: Python<'_>,
    function: &str,
    dim: usize,
    algorithm: &str,
    budget: u64,
    seed: u64,
    params: Option<&Bound<'_, PyDict>>,
) -> PyResult<RunResult> {
    let f = metabezier::functions::Function::from_name(function).ok_or_else(|| {
        let names: Vec<&str> = metabezier::functions::Function::ALL
            .iter()
            .map(|f| f.name())
            .collect();
        PyValueError::new_err(format!(
            "unknown function \"{function}\"; valid choices: {}",
            metabezier::optim::quoted_list(&names)
        ))
    })?;
    let problem = metabezier::functions::TestProblem::new(f, dim)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let alg = configured(algorithm, params, budget, dim)?;
    let outcome = interruptible(py, || alg.run(&problem, budget, &mut run_rng(seed)))?;
    Ok(run_result(outcome))
}

/// Every registered optimiser: name → [(parameter, default, what it admits)].
#[pyfunction]
fn algorithms() -> Vec<AlgorithmRow> {
    Optimisers::builtin()
        .iter()
        .map(|def| {
            let params = def
                .params
                .iter()
                .map(|p| (p.name.to_owned(), p.default.to_string(), p.expected()))
                .collect();
            (def.name.to_string(), def.source.to_string(), params)
        })
        .collect()
}

/// The registry campaigns run with: the built-ins and the problems
/// registered from Python.
fn registry() -> &'static Mutex<Registry> {
    static REGISTRY: OnceLock<Mutex<Registry>> = OnceLock::new();
    REGISTRY.get_or_init(|| Mutex::new(Registry::with_builtins()))
}

/// `register_problem`: a Python function that specs may name as
/// `function = "name"`. `bounds` is one `(lower, upper)` pair for every
/// dimension a spec asks for, or one pair per variable for that dimension
/// only.
#[pyfunction]
#[pyo3(signature = (name, fun, bounds, per_variable, optimum, batch))]
fn register_problem(
    name: &str,
    fun: Py<PyAny>,
    bounds: Vec<(f64, f64)>,
    per_variable: bool,
    optimum: f64,
    batch: bool,
) -> PyResult<()> {
    let bounds = bounds_of(&bounds)?;
    if !optimum.is_finite() {
        return Err(PyValueError::new_err(format!(
            "optimum = {optimum}: expected a finite f* (the value the targets are measured from)"
        )));
    }
    let problem_name = name.to_owned();
    let def = ProblemDef::new(
        name,
        "Python",
        move |dim| {
            let b = if per_variable {
                if dim != bounds.len() {
                    return Err(format!(
                        "registered with {} bounds, so only for D = {}",
                        bounds.len(),
                        bounds.len()
                    )
                    .into());
                }
                bounds.clone()
            } else {
                vec![bounds[0]; dim]
            };
            Ok(PyProblem {
                name: problem_name.clone(),
                fun: Python::attach(|py| fun.clone_ref(py)),
                bounds: b,
                batch,
                in_campaign: true,
                error: Arc::default(),
            })
        },
        move |_| optimum,
    );
    let mut reg = registry()
        .lock()
        .map_err(|_| PyRuntimeError::new_err("the problem registry is poisoned"))?;
    reg.register_problem(def)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The spec `spec`: TOML text when it contains a newline, else a path.
fn load_spec(spec: &str, allow_large: bool, reg: &Registry) -> PyResult<Spec> {
    let limits = SpecLimits::new(allow_large);
    let loaded = if spec.contains('\n') {
        Spec::parse_in(Path::new("<string>"), spec, limits, reg)
    } else {
        Spec::load_in(Path::new(spec), limits, reg)
    };
    loaded.map_err(|e| PyValueError::new_err(e.to_string()))
}

/// `run`: a campaign exactly as `metabezier run` runs it. Returns
/// `(output directory, total, reused, executed, complete, dropped)`, with
/// `dropped` the journal rows a resume refused (their runs were redone).
#[pyfunction]
#[pyo3(signature = (spec, out, threads, resume, shard, allow_large))]
fn run(
    py: Python<'_>,
    spec: &str,
    out: Option<PathBuf>,
    threads: Option<usize>,
    resume: bool,
    shard: Option<String>,
    allow_large: bool,
) -> PyResult<(String, usize, usize, usize, bool, Vec<String>)> {
    let spec = {
        let reg = registry()
            .lock()
            .map_err(|_| PyRuntimeError::new_err("the problem registry is poisoned"))?;
        load_spec(spec, allow_large, &reg)?
    };
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads: expected at least 1"));
    }
    let mut opts = RunOptions {
        out,
        threads,
        resume,
        allow_large,
        ..RunOptions::default()
    };
    if let Some(text) = shard {
        opts.shard = Some(
            metabezier::experiment::Shard::parse(&text)
                .map_err(|e| PyValueError::new_err(format!("shard: {e}")))?,
        );
    }
    if let Ok(mut slot) = CAMPAIGN_ERROR.lock() {
        *slot = None;
    }
    // On a worker thread without the GIL, so that the workers can call
    // Python functions and Ctrl-C ends the campaign, resumable.
    let result: Result<Summary, String> =
        interruptible(py, || run_campaign(&spec, &opts).map_err(|e| e.to_string()))?;
    match result {
        Ok(s) => Ok((
            s.out.display().to_string(),
            s.total,
            s.reused,
            s.executed,
            s.complete,
            s.dropped,
        )),
        Err(message) => {
            let cause = CAMPAIGN_ERROR.lock().ok().and_then(|mut e| e.take());
            let err = PyRuntimeError::new_err(message);
            if let Some(cause) = cause {
                err.set_cause(py, Some(cause));
            }
            Err(err)
        }
    }
}

/// `report`: writes `report.md` (and its tables, its figures and
/// `report.html`, the same as one page) into a
/// results directory, as `metabezier report` does.
#[pyfunction]
fn report(py: Python<'_>, dir: PathBuf) -> PyResult<String> {
    py.detach(|| write_report(&dir, &ReportOptions::default()))
        .map(|s| s.report.display().to_string())
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The outline of points given directly, by the rule of a CSV of points
/// (a repeated first point closes it unless `closed` says otherwise), each
/// coordinate finite and at most [`MAX_COORDINATE`] in size.
fn outline_of(points: &[(f64, f64)], closed: Option<bool>) -> PyResult<Outline> {
    if let Some((i, _)) = points
        .iter()
        .enumerate()
        .find(|(_, (x, y))| !(x.abs() <= MAX_COORDINATE && y.abs() <= MAX_COORDINATE))
    {
        return Err(PyValueError::new_err(format!(
            "points[{i}]: expected finite coordinates of at most {MAX_COORDINATE:e} in size"
        )));
    }
    let pts = points.iter().map(|&(x, y)| Point::new(x, y)).collect();
    outline_from_points(
        pts,
        closed,
        CsvOptions::default().min_points,
        Path::new("points"),
    )
    .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// One fitted segment: (contour, function, control points, weights,
/// first point, last point).
type SegmentRow = (usize, String, Vec<(f64, f64)>, Vec<f64>, usize, usize);

/// A fit for Python: its segments and its metrics by name.
type FitRows = (Vec<SegmentRow>, Vec<(String, f64)>);

/// `fit`: the piecewise fit of an outline given as points, as `metabezier
/// fit` fits a CSV of points. Returns the segments and the metrics.
#[pyfunction]
#[pyo3(signature = (points, closed, function, continuity, segments, tolerance, algorithm, budget, seed, closing, search_space, parameterisation, error, chain, corner_angle, corner_k))]
#[allow(clippy::too_many_arguments)]
fn fit(
    py: Python<'_>,
    points: Vec<(f64, f64)>,
    closed: Option<bool>,
    function: &str,
    continuity: &str,
    segments: Option<usize>,
    tolerance: Option<f64>,
    algorithm: &str,
    budget: u64,
    seed: u64,
    closing: &str,
    search_space: &str,
    parameterisation: &str,
    error: &str,
    chain: &str,
    corner_angle: f64,
    corner_k: usize,
) -> PyResult<FitRows> {
    let choice = |what: &str, name: &str, names: &[&str]| {
        PyValueError::new_err(format!(
            "{what}: unknown \"{name}\"; valid choices: {}",
            metabezier::optim::quoted_list(names)
        ))
    };
    let function_type = FunctionType::from_name(function)
        .ok_or_else(|| choice("function", function, &FunctionType::NAMES))?;
    let continuity = Continuity::from_name(continuity)
        .ok_or_else(|| choice("continuity", continuity, &Continuity::NAMES))?;
    let closing =
        Closing::from_name(closing).ok_or_else(|| choice("closing", closing, &Closing::NAMES))?;
    let space = SearchSpace::from_name(search_space)
        .ok_or_else(|| choice("search_space", search_space, &SearchSpace::NAMES))?;
    let error = ErrorMeasure::from_name(error)
        .ok_or_else(|| choice("error", error, &ErrorMeasure::NAMES))?;
    let chain = Chain::from_name(chain).ok_or_else(|| choice("chain", chain, &Chain::NAMES))?;
    let method = Method::from_name(algorithm).ok_or_else(|| {
        let names = Method::names();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        choice("algorithm", algorithm, &names)
    })?;
    let segmentation = match (segments, tolerance) {
        (Some(_), Some(_)) => {
            return Err(PyValueError::new_err(
                "give segments or tolerance, not both",
            ))
        }
        (Some(0), None) => return Err(PyValueError::new_err("segments: expected at least 1")),
        (Some(n), None) => Segmentation::Count(n),
        (None, Some(t)) if t.is_finite() && t > 0.0 => Segmentation::Tolerance(t),
        (None, Some(t)) => {
            return Err(PyValueError::new_err(format!(
                "tolerance = {t}: expected a finite distance > 0"
            )))
        }
        (None, None) => Segmentation::Tolerance(DEFAULT_TOLERANCE),
    };
    check_budget("budget", budget)?;
    if !(0.0..180.0).contains(&corner_angle) || corner_k == 0 {
        return Err(PyValueError::new_err(
            "corner_angle: expected degrees in [0, 180) (0 finds no corners); corner_k: at least 1",
        ));
    }
    let source = Source::from_outline("points", outline_of(&points, closed)?);
    let mut options = FitOptions::new(function_type, continuity);
    options.budget_per_segment = budget;
    options.closing = closing;
    options.search.kind = space;
    options.error = error;
    options.chain = chain;
    options.parameterisation = match parameterisation {
        "auto" => source.auto_parameterisation(false),
        name => Parameterisation::from_name(name).ok_or_else(|| {
            let mut names = vec!["auto"];
            names.extend(Parameterisation::NAMES);
            choice("parameterisation", name, &names)
        })?,
    };
    let r = Reconstruction {
        source: &source,
        segmentation,
        corners: (corner_angle > 0.0).then_some(CornerOptions {
            k: corner_k,
            angle_deg: corner_angle,
        }),
        options,
    };
    let shape = interruptible(py, || r.fit(&method, seed))?
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    let rows = shape
        .segments()
        .map(|(contour, s)| {
            (
                contour,
                s.segment.function().name().to_owned(),
                s.segment
                    .control_points()
                    .iter()
                    .map(|p| (p.x, p.y))
                    .collect(),
                s.segment.weights(),
                s.first,
                s.last,
            )
        })
        .collect();
    let m = &shape.metrics;
    let metrics = vec![
        ("points".to_owned(), m.points as f64),
        ("segments".to_owned(), m.segments as f64),
        ("sse".to_owned(), m.sse),
        ("rms".to_owned(), m.rms),
        ("rms_distance".to_owned(), m.rms_distance),
        ("max_distance".to_owned(), m.max_distance),
        ("curve_distance".to_owned(), m.curve_distance),
        ("hausdorff".to_owned(), m.hausdorff),
        ("evaluations".to_owned(), m.evaluations as f64),
    ];
    Ok((rows, metrics))
}

/// `score`: the orthogonal distances of `points` to the curves of an SVG
/// (path or text): (segments, points, max distance, RMS distance).
#[pyfunction]
#[pyo3(signature = (points, closed, svg, offset))]
fn score_svg(
    points: Vec<(f64, f64)>,
    closed: Option<bool>,
    svg: &str,
    offset: (f64, f64),
) -> PyResult<(usize, usize, f64, f64)> {
    let (text, path) = if svg.trim_start().starts_with('<') {
        (svg.to_owned(), PathBuf::from("<string>"))
    } else {
        let path = PathBuf::from(svg);
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
        (text, path)
    };
    let paths = svg_from_str(&text, &path).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let source = Source::from_outline("points", outline_of(&points, closed)?);
    let s = score(&source, &paths.to_frame(Point::new(offset.0, offset.1)))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok((
        s.segments,
        s.total.points,
        s.total.max_distance,
        s.total.rms_distance,
    ))
}

/// The extension module `metabezier._core`.
#[pymodule]
fn _core(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(minimize, m)?)?;
    m.add_function(wrap_pyfunction!(benchmark, m)?)?;
    m.add_function(wrap_pyfunction!(recommended_algorithm, m)?)?;
    m.add_function(wrap_pyfunction!(algorithms, m)?)?;
    m.add_function(wrap_pyfunction!(register_problem, m)?)?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(score_svg, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("MAX_BUDGET", MAX_BUDGET)?;
    Ok(())
}
