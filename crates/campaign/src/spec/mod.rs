//! TOML experiment specs: what to run, checked completely before anything runs.
//!
//! ```toml
//! [experiment]
//! name = "quick"            # results go to results/<name>/
//! seed = 2026               # master seed
//! runs = 5                  # independent runs per (algorithm cell, problem)
//! budget = 20000            # objective evaluations per run (or budget_per_dim)
//! threshold = 1e-8          # success when f − f* ≤ threshold
//! # stop = "target"         # end a run at its target (default "budget")
//!
//! [[problem]]
//! function = ["sphere", "rastrigin"]   # a name or a list of names
//! dim = [10, 30]                       # a dimension or a list
//! # transform = "shift-rotate"         # optional: "none", "shift", "shift-rotate"
//! # instances = [6, 7, 8]              # of a transform: a count N (1..N) or a list
//!
//! [[algorithm]]
//! name = "mhs"
//! label = "MHS"             # optional; defaults to the name
//! hmcr = [0.7, 0.8, 0.9]    # a list expands into a grid of cells
//! ```
//!
//! A spec may also hold `[[fit]]` sections, outline-fitting problems
//! (see [`FitCase`]), beside or instead of `[[problem]]`;
//! its algorithms may then also be `lm` or `<alg>+lm`.
//!
//! Every error names the file, line, column and field, says what was
//! expected and lists the valid choices.

use std::any::Any;
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

use toml::de::DeValue;

use super::outcome::{default_targets, FitDetail};
use super::registry::{ProblemDef, Registry, SharedProblem};
use crate::functions::{Function, TestProblem, Transform};
use crate::optim::evaluator::log_checkpoints;
use crate::optim::{quoted_list, ParamDef, ParamSet, Raw, Setting};
use crate::optim::{Algorithm, Evaluator, Outcome};
use crate::problem::Problem;
use crate::reconstruction::Method;
use crate::rng::run_rng;

mod bbob;
mod fit;
mod fit_tolerance;
mod report;
mod stop;

pub use metabezier_spec::SpecError;
pub(crate) use metabezier_spec::{choices_hint, raw, Table, Value};

pub use bbob::{Bbob, NO_COCO};
pub use fit::FitCase;
pub use report::{rope_measure, REPORT_KEYS};
pub use stop::Stop;

/// One problem of a spec, with its budget: a benchmark function at a
/// dimension (possibly a shifted or rotated instance), or an
/// outline-fitting case.
#[derive(Clone, Debug)]
pub struct ProblemEntry {
    /// What is solved.
    pub kind: Arc<dyn ProblemKind>,
    /// The dimension of a benchmark function; the number of segments of a
    /// fitting case.
    pub dim: usize,
    /// Objective evaluations per run (for a fitting case, over all its
    /// segments).
    pub budget: u64,
    /// Whether the budget was one value of a list in the spec (a budget
    /// grid): then it is part of the problem's key.
    pub budget_factor: bool,
    /// How a benchmark function is transformed (`none` for fitting).
    pub transform: Transform,
    /// The instance number `k ≥ 1` of a transformed function (1 otherwise).
    pub instance: u32,
}

/// A design factor of the problems, beside the function (or fitting case)
/// and the dimension: what `[experiment] paired` may name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Factor {
    /// The evaluation budget, when given as a list.
    Budget,
    /// The benchmark transform.
    Transform,
    /// The benchmark instance.
    Instance,
    /// The search space of a fitting case.
    SearchSpace,
    /// The technique's `α_size` of a fitting case, when listed.
    AlphaSize,
}

impl Factor {
    /// The names accepted in `paired`.
    pub const NAMES: [&'static str; 5] = [
        "budget",
        "transform",
        "instance",
        "search_space",
        "alpha_size",
    ];

    /// Parses a factor name.
    pub fn from_name(name: &str) -> Option<Factor> {
        Self::NAMES.iter().position(|n| *n == name).map(|i| {
            [
                Factor::Budget,
                Factor::Transform,
                Factor::Instance,
                Factor::SearchSpace,
                Factor::AlphaSize,
            ][i]
        })
    }

    /// The factor's name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// What a [`ProblemEntry`] solves: one problem of a family (the thesis's
/// functions, COCO's bbob suite, an outline-fitting case, a registered
/// problem), with everything the seeds, the runner and the records ask of
/// it. The runner matches on no list of families: a new family implements
/// this beside its own spec section, in its own file.
pub trait ProblemKind: Any + Send + Sync + fmt::Debug {
    /// The problem's name in results (`sphere`, `bbob_f001_i01_d10`,
    /// `horse/cubic/g1`).
    fn name(&self, entry: &ProblemEntry) -> String;

    /// The name the seeds derive from when the `paired` factors are left
    /// out of them; by default [`ProblemKind::name`].
    fn seed_name(&self, entry: &ProblemEntry, paired: &[Factor]) -> String {
        let _ = paired;
        self.name(entry)
    }

    /// The value of a factor the family owns (a fitting case's search
    /// space and `α_size`); `None` where it does not apply.
    fn factor_value(&self, factor: Factor) -> Option<String> {
        let _ = factor;
        None
    }

    /// The optimum value `f*` errors are measured from.
    fn optimum(&self) -> f64;

    /// Executes one run of `method` seeded with `seed`: its outcome, and
    /// for a fitting problem the fit's own record.
    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>);

    /// The size of one run's record: its trace points, target hits (an
    /// upper bound) and segment rows; by default a benchmark run's (the
    /// spec's checkpoints and every target).
    fn record_shape(&self, spec: &Spec, entry: &ProblemEntry) -> (usize, usize, usize) {
        (
            log_checkpoints(entry.budget, spec.checkpoints_per_decade).len(),
            default_targets().len(),
            0,
        )
    }

    /// Whether least-squares methods (`lm`, `<alg>+lm`) solve it: only
    /// fitting problems, whose objective is a sum of squares.
    fn least_squares(&self) -> bool {
        false
    }

    /// Whether its runs record target hits (`hits.csv`); fitting runs,
    /// whose error is `E`, do not.
    fn has_targets(&self) -> bool {
        true
    }
}

/// The evaluator of a benchmark run with optimum `f_star`: the run's
/// budget, target, target precisions and checkpoints.
pub fn benchmark_evaluator<'p, P: Problem + ?Sized>(
    spec: &Spec,
    entry: &ProblemEntry,
    problem: &'p P,
    f_star: f64,
) -> Evaluator<'p, P> {
    let eval = Evaluator::new(problem, entry.budget)
        .with_target(f_star + spec.threshold)
        .with_targets(f_star, default_targets())
        .with_checkpoints(log_checkpoints(entry.budget, spec.checkpoints_per_decade));
    match spec.stop {
        Stop::Budget => eval,
        Stop::Target => eval.stop_at_target(),
    }
}

/// Minimises `problem`, reached through `dyn Problem` (COCO's bbob, a
/// registered problem), with optimum `f_star` under the run's budget,
/// target, target precisions and checkpoints.
pub fn minimise_problem(
    spec: &Spec,
    entry: &ProblemEntry,
    algorithm: &Algorithm,
    problem: &dyn Problem,
    f_star: f64,
    seed: u64,
) -> Outcome {
    let mut eval = benchmark_evaluator(spec, entry, problem, f_star);
    algorithm.minimise(&mut eval, &mut run_rng(seed));
    eval.finish()
}

/// The metaheuristic of a benchmark run: the spec refuses least-squares
/// methods on benchmark functions.
pub(crate) fn metaheuristic(method: &Method) -> &Algorithm {
    match method {
        Method::Metaheuristic(a) => a,
        _ => unreachable!("the spec refuses least-squares methods on benchmark functions"),
    }
}

/// One of the thesis's functions at a dimension, transform and instance;
/// the problem is drawn on its first run (a rotation costs `O(D³)`) and
/// shared by all its runs.
#[derive(Debug)]
pub struct Benchmark {
    /// The function.
    pub function: Function,
    problem: OnceLock<TestProblem>,
}

impl Benchmark {
    /// The function `function`, drawn when first run.
    pub fn new(function: Function) -> Benchmark {
        Benchmark {
            function,
            problem: OnceLock::new(),
        }
    }

    /// The problem of `entry` (its dimension, transform and instance).
    pub fn problem(&self, entry: &ProblemEntry) -> &TestProblem {
        self.problem.get_or_init(|| {
            TestProblem::instance(self.function, entry.dim, entry.transform, entry.instance)
                .expect("instance checked when the spec loaded")
        })
    }
}

impl ProblemKind for Benchmark {
    fn name(&self, _: &ProblemEntry) -> String {
        self.function.name().to_owned()
    }

    fn optimum(&self) -> f64 {
        self.function.optimum_value()
    }

    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        let problem = self.problem(entry);
        let mut eval = benchmark_evaluator(spec, entry, problem, self.optimum());
        metaheuristic(method).minimise_benchmark(&mut eval, &mut run_rng(seed));
        (eval.finish(), None)
    }
}

/// A registered problem at one dimension, built once and shared by its runs.
#[derive(Clone)]
pub struct RegisteredProblem {
    /// Its registered name.
    pub name: String,
    /// Its optimum value `f*` at this dimension.
    pub optimum: f64,
    /// The problem.
    pub problem: SharedProblem,
}

impl fmt::Debug for RegisteredProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RegisteredProblem")
            .field("name", &self.name)
            .field("optimum", &self.optimum)
            .finish()
    }
}

impl ProblemKind for RegisteredProblem {
    fn name(&self, _: &ProblemEntry) -> String {
        self.name.clone()
    }

    fn optimum(&self) -> f64 {
        self.optimum
    }

    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        let algorithm = metaheuristic(method);
        let out = minimise_problem(spec, entry, algorithm, &*self.problem, self.optimum, seed);
        (out, None)
    }
}

impl ProblemEntry {
    /// The problem's name in results: the function's name, or the fitting
    /// case's `source/function/continuity[/search-space]`.
    pub fn name(&self) -> String {
        self.kind.name(self)
    }

    /// The stable key of the problem, used in seeds and for resuming:
    /// `name-dim`, followed by `|factor=value` for each design factor that
    /// is not at its default (a listed budget, a transform, an instance
    /// other than 1). A spec that uses none of them keeps the keys, and so
    /// the seeds, of campaigns recorded before the factors existed.
    pub fn key(&self) -> String {
        self.key_with(&[], true)
    }

    /// The key the run seeds derive from: [`ProblemEntry::key`] without the
    /// `paired` factors, so that problems differing only in them share
    /// their seeds (common random numbers).
    pub fn seed_key(&self, paired: &[Factor]) -> String {
        self.key_with(paired, true)
    }

    /// The key without the budget, which runs are matched by together with
    /// their budget column (see [`crate::records::RunKey`]).
    pub fn match_key(&self) -> String {
        self.key_with(&[], false)
    }

    fn key_with(&self, paired: &[Factor], with_budget: bool) -> String {
        let mut key = format!("{}-{}", self.kind.seed_name(self, paired), self.dim);
        if with_budget && self.budget_factor && !paired.contains(&Factor::Budget) {
            key.push_str(&format!("|budget={}", self.budget));
        }
        key.push_str(&factor_suffix(
            self.transform,
            self.instance,
            !paired.contains(&Factor::Transform),
            !paired.contains(&Factor::Instance),
        ));
        key
    }

    /// The value of `factor` for this problem, as text (`None` when the
    /// factor does not apply, such as a search space of a benchmark).
    pub fn factor_value(&self, factor: Factor) -> Option<String> {
        match factor {
            Factor::Budget => Some(self.budget.to_string()),
            Factor::Transform => Some(self.transform.name().to_owned()),
            Factor::Instance => Some(self.instance.to_string()),
            Factor::SearchSpace | Factor::AlphaSize => self.kind.factor_value(factor),
        }
    }

    /// The optimum value `f*` errors are measured from (0 for fitting:
    /// the error of a fit is its `E`).
    pub fn optimum_value(&self) -> f64 {
        self.kind.optimum()
    }

    /// The problem as its own type, if it is a `K` (a family's own tools
    /// read their problems so: COCO's logger its bbob problems, the
    /// outlines file its fitting cases).
    pub fn kind_as<K: ProblemKind>(&self) -> Option<&K> {
        (&*self.kind as &dyn Any).downcast_ref::<K>()
    }
}

/// The key suffix of a transformed benchmark: `|transform=<t>` and
/// `|instance=<k>` (the instance only when not 1), each only when asked for
/// and when the transform is not `none`. Shared by specs and records so that
/// both build the same keys.
pub fn factor_suffix(
    transform: Transform,
    instance: u32,
    with_transform: bool,
    with_instance: bool,
) -> String {
    let mut out = String::new();
    if transform != Transform::None {
        if with_transform {
            out.push_str(&format!("|transform={}", transform.name()));
        }
        if with_instance && instance != 1 {
            out.push_str(&format!("|instance={instance}"));
        }
    }
    out
}

/// One algorithm cell: a configured method with its label.
#[derive(Clone, Debug)]
pub struct Cell {
    /// The label shown in results (`algorithm` column).
    pub label: String,
    /// The configured method: a metaheuristic, or for fitting problems
    /// also `lm` or a metaheuristic polished by LM.
    pub method: Method,
    /// Its complete parameter set, defaults filled in (those of the
    /// metaheuristic; empty for `lm`).
    pub params: ParamSet,
}

impl Cell {
    /// The stable key `label:name[params]`, used in seeds and for resuming.
    pub fn key(&self) -> String {
        format!(
            "{}:{}[{}]",
            self.label,
            self.method.name(),
            self.params.canonical()
        )
    }
}

/// A loaded, validated experiment spec.
#[derive(Clone, Debug)]
pub struct Spec {
    /// Where it was read from.
    pub path: PathBuf,
    /// Its exact text (copied next to the results).
    pub text: String,
    /// The experiment name; results go to `results/<name>/`.
    pub name: String,
    /// The master seed from which each run's seed is derived.
    pub seed: u64,
    /// Runs per (cell, problem).
    pub runs: u32,
    /// Success when `f − f* ≤ threshold`.
    pub threshold: f64,
    /// Convergence checkpoints per decade of evaluations.
    pub checkpoints_per_decade: u32,
    /// Where a benchmark run ends: at its budget (the default) or its target.
    pub stop: Stop,
    /// The problems, in spec order.
    pub problems: Vec<ProblemEntry>,
    /// The algorithm cells, in spec order (grids expanded).
    pub cells: Vec<Cell>,
    /// The problem factors left out of the seed derivation (`paired`), so
    /// that runs differing only in them share their random numbers.
    pub paired: Vec<Factor>,
    /// The ropes of the optional `[report]` section, (measure, half-width),
    /// which the campaign's report reads from its copy of the spec.
    pub ropes: Vec<(String, f64)>,
}

/// One run of a campaign: indices into the spec and the run number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunId {
    /// Position in the campaign's fixed order (problem, cell, run).
    pub index: usize,
    /// Index into [`Spec::problems`].
    pub problem: usize,
    /// Index into [`Spec::cells`].
    pub cell: usize,
    /// The run number, from 0.
    pub run: u32,
}

/// The most evaluations one run may have unless `--allow-large` lifts
/// it: 10¹⁰ (about a day of the cheapest benchmark function on one core).
pub const MAX_BUDGET: u64 = 10_000_000_000;

/// The most algorithm cells a spec may expand into (every grid of every
/// `[[algorithm]]` together): 10⁶. Not lifted by `--allow-large`: a cell
/// takes about half a KiB before any run, so this bounds a spec's own
/// memory at about 0.5 GiB.
pub const MAX_CELLS: usize = 1_000_000;

/// The most problems a spec may expand into (every function × dimension ×
/// transform × instance × budget × fitting case together): 10⁶, not lifted
/// by `--allow-large`.
pub const MAX_PROBLEMS: usize = 1_000_000;

/// The longest experiment name: 100 characters (it names the results
/// directory and, with a suffix, its shards).
pub const MAX_NAME_CHARS: usize = 100;

/// The limits a spec is read under: the runs of the campaign and the
/// evaluations of one run, both counted before anything is expanded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SpecLimits {
    /// The most runs (problems × cells × runs).
    pub max_runs: u128,
    /// The most evaluations of one run.
    pub max_budget: u64,
}

impl SpecLimits {
    /// The limits of `run`, `check` and `slurm`: [`super::MAX_RUNS`] runs
    /// and [`MAX_BUDGET`] evaluations per run.
    pub const DEFAULT: SpecLimits = SpecLimits {
        max_runs: super::MAX_RUNS,
        max_budget: MAX_BUDGET,
    };

    /// No limit on runs or budgets (`--allow-large`; the cell and problem
    /// limits stay).
    pub const LARGE: SpecLimits = SpecLimits {
        max_runs: u128::MAX,
        max_budget: u64::MAX,
    };

    /// [`SpecLimits::LARGE`] with `allow_large`, else the default.
    pub fn new(allow_large: bool) -> SpecLimits {
        if allow_large {
            SpecLimits::LARGE
        } else {
            SpecLimits::DEFAULT
        }
    }
}

impl Default for SpecLimits {
    fn default() -> Self {
        SpecLimits::DEFAULT
    }
}

impl Spec {
    /// Reads and validates a spec file under the default limits.
    pub fn load(path: &Path) -> Result<Spec, SpecError> {
        Spec::load_with(path, SpecLimits::DEFAULT)
    }

    /// Reads and validates a spec file under `limits`.
    pub fn load_with(path: &Path, limits: SpecLimits) -> Result<Spec, SpecError> {
        Spec::parse_with(path, &SpecError::read(path)?, limits)
    }

    /// Validates spec text under the default limits; `path` is used in
    /// error messages.
    pub fn parse(path: &Path, text: &str) -> Result<Spec, SpecError> {
        Spec::parse_with(path, text, SpecLimits::DEFAULT)
    }

    /// Validates spec text under `limits`.
    pub fn parse_with(path: &Path, text: &str, limits: SpecLimits) -> Result<Spec, SpecError> {
        Spec::parse_in(path, text, limits, Registry::builtin())
    }

    /// Reads and validates a spec file under `limits`, its algorithm and
    /// function names resolved in `registry`.
    pub fn load_in(
        path: &Path,
        limits: SpecLimits,
        registry: &Registry,
    ) -> Result<Spec, SpecError> {
        Spec::parse_in(path, &SpecError::read(path)?, limits, registry)
    }

    /// Validates spec text under `limits`, its algorithm and function
    /// names resolved in `registry`.
    ///
    /// ```
    /// use std::path::Path;
    /// use metabezier_campaign::{Registry, Spec, SpecLimits};
    ///
    /// let text = "[experiment]\nname = \"tiny\"\nseed = 1\nruns = 2\nbudget = 500\n\n\
    ///             [[problem]]\nfunction = \"sphere\"\ndim = 3\n\n\
    ///             [[algorithm]]\nname = \"hs\"\n";
    /// let spec = Spec::parse_in(Path::new("tiny.toml"), text, SpecLimits::DEFAULT, Registry::builtin())
    ///     .unwrap();
    /// assert_eq!(spec.run_count(), 2);
    /// // An unknown name is refused with the valid choices.
    /// let bad = Spec::parse(Path::new("tiny.toml"), &text.replace("\"hs\"", "\"hz\"")).unwrap_err();
    /// assert!(bad.to_string().contains("unknown algorithm \"hz\""));
    /// ```
    pub fn parse_in(
        path: &Path,
        text: &str,
        limits: SpecLimits,
        registry: &Registry,
    ) -> Result<Spec, SpecError> {
        Parser {
            grammar: metabezier_spec::Parser { path, text },
            limits,
            registry,
        }
        .spec()
    }

    /// All runs in the campaign's fixed order: problem, then cell, then run.
    pub fn run_ids(&self) -> Vec<RunId> {
        let n = self.problems.len() * self.cells.len() * self.runs as usize;
        (0..n).map(|i| self.run_id(i)).collect()
    }

    /// The run at position `index` of the fixed order, as [`Spec::run_ids`]
    /// lists it, without listing the others.
    pub fn run_id(&self, index: usize) -> RunId {
        let runs = self.runs as usize;
        let (pc, run) = (index / runs, index % runs);
        RunId {
            index,
            problem: pc / self.cells.len(),
            cell: pc % self.cells.len(),
            run: run as u32,
        }
    }

    /// The number of runs: problems × cells × runs (without listing them).
    pub fn run_count(&self) -> u128 {
        self.problems.len() as u128 * self.cells.len() as u128 * u128::from(self.runs)
    }

    /// The total objective evaluations the campaign will spend.
    pub fn total_evaluations(&self) -> u128 {
        let per_cell: u128 = self.problems.iter().map(|p| u128::from(p.budget)).sum();
        per_cell * self.cells.len() as u128 * u128::from(self.runs)
    }
}

/// The spec reader: the grammar's [`metabezier_spec::Parser`] (the file's
/// path and text, for errors located by line and column, and the
/// primitives: fields, tables, strings, numbers, known keys), reached
/// through `Deref`, with the limits and the registry a campaign spec is
/// read under.
pub(crate) struct Parser<'a> {
    /// The file and its text, and the grammar's primitives.
    pub(crate) grammar: metabezier_spec::Parser<'a>,
    /// The limits of runs and budgets.
    pub(crate) limits: SpecLimits,
    /// The optimisers and problems names resolve in.
    pub(crate) registry: &'a Registry,
}

impl<'a> std::ops::Deref for Parser<'a> {
    type Target = metabezier_spec::Parser<'a>;

    fn deref(&self) -> &Self::Target {
        &self.grammar
    }
}

const EXPERIMENT_KEYS: [&str; 10] = [
    "name",
    "description",
    "seed",
    "runs",
    "budget",
    "budget_per_dim",
    "threshold",
    "checkpoints_per_decade",
    "paired",
    "stop",
];
const SECTIONS: [&str; 5] = ["experiment", "problem", "fit", "algorithm", "report"];
/// The largest instance count, and instance number, of a `[[problem]]` of
/// the thesis's functions.
const MAX_INSTANCES: u64 = 10_000;
const PROBLEM_KEYS: [&str; 7] = [
    "suite",
    "function",
    "dim",
    "budget",
    "budget_per_dim",
    "transform",
    "instances",
];

impl<'a> Parser<'a> {
    fn spec(&self) -> Result<Spec, SpecError> {
        let doc = self.toml()?;
        let root = doc.get_ref();
        self.check_sections(root)?;
        let header = self.experiment(root, doc.span())?;
        let problems = self.all_problems(root, header.budget.as_ref(), doc.span())?;
        let benchmarks = problems.iter().any(|p| !p.kind.least_squares());
        if header.stop.0 == Stop::Target && problems.iter().any(|p| !p.kind.has_targets()) {
            return Err(self.error(
                header.stop.1.clone(),
                "experiment.stop",
                "stop = \"target\" ends a benchmark run at f − f* ≤ threshold, but this spec \
                 has [[fit]] problems, which have no target: remove `stop` (a fit ends at its \
                 budget or its `tolerance`) or put the fits in a spec of their own"
                    .into(),
            ));
        }
        let cells = self.cells(root, doc.span(), benchmarks, (problems.len(), header.runs))?;
        let paired = self.paired(root, &problems)?;
        let ropes = self.report_section(root)?;
        Ok(Spec {
            path: self.path.to_owned(),
            text: self.text.to_owned(),
            name: header.name,
            seed: header.seed,
            runs: header.runs,
            threshold: header.threshold,
            checkpoints_per_decade: header.checkpoints_per_decade,
            stop: header.stop.0,
            problems,
            cells,
            paired,
            ropes,
        })
    }

    /// The optional `experiment.paired`: factors that vary among the
    /// problems and are left out of the seeds.
    fn paired(
        &self,
        root: &Table<'_>,
        problems: &[ProblemEntry],
    ) -> Result<Vec<Factor>, SpecError> {
        let Some(experiment) = self
            .get(root, "experiment")
            .and_then(|e| match e.get_ref() {
                DeValue::Table(t) => Some(t),
                _ => None,
            })
        else {
            return Ok(Vec::new());
        };
        let Some(v) = self.get(experiment, "paired") else {
            return Ok(Vec::new());
        };
        let field = "experiment.paired";
        let mut out = Vec::new();
        for item in self.one_or_many(v, field)? {
            let name = self.string(item, field)?;
            let factor = Factor::from_name(&name).ok_or_else(|| {
                self.error(
                    item.span(),
                    field,
                    format!(
                        "unknown factor \"{name}\"; {}",
                        choices_hint(&name, &Factor::NAMES)
                    ),
                )
            })?;
            let values: std::collections::BTreeSet<String> = problems
                .iter()
                .filter_map(|p| p.factor_value(factor))
                .collect();
            if values.len() < 2 {
                let varying: Vec<&str> = Factor::NAMES
                    .iter()
                    .copied()
                    .filter(|n| {
                        let f = Factor::from_name(n).expect("a factor name");
                        problems
                            .iter()
                            .filter_map(|p| p.factor_value(f))
                            .collect::<std::collections::BTreeSet<_>>()
                            .len()
                            > 1
                    })
                    .collect();
                return Err(self.error(
                    item.span(),
                    field,
                    format!(
                        "\"{name}\" does not vary among this spec's problems, so there is nothing to pair; {}",
                        if varying.is_empty() {
                            "no factor varies here".to_owned()
                        } else {
                            format!("the varying factors are {}", quoted_list(&varying))
                        }
                    ),
                ));
            }
            if !out.contains(&factor) {
                out.push(factor);
            }
        }
        out.sort();
        Ok(out)
    }

    /// Checks that every top-level key is a known section.
    fn check_sections(&self, root: &Table<'_>) -> Result<(), SpecError> {
        for (k, _) in root.iter() {
            let key: &str = k.get_ref();
            if !SECTIONS.contains(&key) {
                return Err(self.error(
                    k.span(),
                    key,
                    format!("unknown section; {}", choices_hint(key, &SECTIONS)),
                ));
            }
        }
        Ok(())
    }

    /// The required `[experiment]` section; `span` is the document's.
    fn experiment(&self, root: &Table<'_>, span: Range<usize>) -> Result<Header, SpecError> {
        let experiment = self
            .get(root, "experiment")
            .ok_or_else(|| self.error(0..0, "experiment", "missing [experiment] section".into()))?;
        let experiment = self.table(experiment, "experiment")?;
        self.check_keys(experiment, "experiment", &EXPERIMENT_KEYS)?;
        let name = self.experiment_name(experiment, span.clone())?;
        let seed_v = self.required(experiment, "experiment", "seed", span.clone())?;
        let seed = self.integer(seed_v, "experiment.seed", 0, i64::MAX as u64)?;
        let runs_v = self.required(experiment, "experiment", "runs", span)?;
        let runs = self.integer(runs_v, "experiment.runs", 1, u64::from(u32::MAX))? as u32;
        let budget = self.budget(experiment, "experiment")?;
        let threshold = match self.get(experiment, "threshold") {
            Some(v) => {
                let t = self.real(v, "experiment.threshold")?;
                if !t.is_finite() || t < 0.0 {
                    return Err(self.error(
                        v.span(),
                        "experiment.threshold",
                        format!("expected a finite real number ≥ 0, found {t}"),
                    ));
                }
                t
            }
            None => 1e-8,
        };
        let checkpoints_per_decade = match self.get(experiment, "checkpoints_per_decade") {
            Some(v) => self.integer(v, "experiment.checkpoints_per_decade", 1, 1000)? as u32,
            None => 10,
        };
        if let Some(v) = self.get(experiment, "description") {
            self.string(v, "experiment.description")?;
        }
        let stop = self.stop(experiment)?;
        Ok(Header {
            name,
            seed,
            runs,
            budget,
            threshold,
            checkpoints_per_decade,
            stop,
        })
    }

    /// The optional `experiment.stop` ([`Stop`]), with its span (the empty
    /// span when absent).
    fn stop(&self, experiment: &Table<'_>) -> Result<WithSpan<Stop>, SpecError> {
        let Some(v) = self.get(experiment, "stop") else {
            return Ok((Stop::default(), 0..0));
        };
        let name = self.string(v, "experiment.stop")?;
        let stop = Stop::from_name(&name).ok_or_else(|| {
            self.error(
                v.span(),
                "experiment.stop",
                format!(
                    "expected where a run ends, found \"{name}\"; {}",
                    choices_hint(&name, &Stop::NAMES)
                ),
            )
        })?;
        Ok((stop, v.span()))
    }

    /// The required `experiment.name`, which names the results directory.
    fn experiment_name(
        &self,
        experiment: &Table<'_>,
        span: Range<usize>,
    ) -> Result<String, SpecError> {
        let name_v = self.required(experiment, "experiment", "name", span)?;
        let name = self.string(name_v, "experiment.name")?;
        if name.chars().count() > MAX_NAME_CHARS {
            return Err(self.error(
                name_v.span(),
                "experiment.name",
                format!(
                    "expected a name of at most {MAX_NAME_CHARS} characters (it names the results directory), found {} characters",
                    name.chars().count()
                ),
            ));
        }
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
            || name.starts_with('.')
        {
            return Err(self.error(
                name_v.span(),
                "experiment.name",
                format!("expected a name of letters, digits, '-', '_' or '.' (it names the results directory), found \"{name}\""),
            ));
        }
        Ok(name)
    }

    /// The `[[problem]]` problems (required without `[[fit]]`), then the
    /// `[[fit]]` ones; no problem twice.
    fn all_problems(
        &self,
        root: &Table<'_>,
        budget: Option<&Budget>,
        span: Range<usize>,
    ) -> Result<Vec<ProblemEntry>, SpecError> {
        let mut problems = Vec::new();
        if self.get(root, "problem").is_some() || self.get(root, "fit").is_none() {
            problems = self.problems(root, budget, span.clone())?;
        }
        if self.get(root, "fit").is_some() {
            let mut seen: std::collections::HashSet<String> =
                problems.iter().map(ProblemEntry::key).collect();
            for p in self.fits(root, budget, span.clone())? {
                if !seen.insert(p.key()) {
                    return Err(self.error(
                        span,
                        "fit",
                        format!("problem {} is listed twice", p.key()),
                    ));
                }
                problems.push(p);
            }
        }
        Ok(problems)
    }
    /// One budget value: an integer in 1..=`limits.max_budget`, the limit
    /// named when it is passed.
    pub(crate) fn budget_value(&self, v: &Value<'_>, field: &str) -> Result<u64, SpecError> {
        let max = self.limits.max_budget;
        match raw(v.get_ref()) {
            Raw::Int(n) if n >= 1 && (n as u64) > max => Err(self.error(
                v.span(),
                field,
                format!(
                    "{n} evaluations per run pass the limit of {max}; pass --allow-large to run budgets above it"
                ),
            )),
            _ => self.integer(v, field, 1, u64::MAX),
        }
    }

    /// The budgets of a problem of dimension `dim` (a per-dimension budget
    /// times `dim`), each within `limits.max_budget`; errors at `span`.
    fn dim_budgets(
        &self,
        budget: &Budget,
        dim: usize,
        span: &Range<usize>,
        section: &str,
    ) -> Result<Vec<u64>, SpecError> {
        let max = self.limits.max_budget;
        let budgets = budget.for_dim(dim);
        if let Some(b) = budgets.iter().find(|&&b| b > max) {
            return Err(self.error(
                span.clone(),
                &format!("{section}.budget_per_dim"),
                format!(
                    "budget_per_dim × dim = {b} evaluations per run at D = {dim} pass the limit of {max}; pass --allow-large to run budgets above it"
                ),
            ));
        }
        Ok(budgets)
    }

    /// Refuses a spec whose problems would pass [`MAX_PROBLEMS`] once
    /// `more` are added to the `have` already expanded.
    pub(crate) fn check_problem_count(
        &self,
        have: usize,
        more: u128,
        span: &Range<usize>,
        section: &str,
    ) -> Result<(), SpecError> {
        if have as u128 + more > MAX_PROBLEMS as u128 {
            return Err(self.error(
                span.clone(),
                section,
                format!(
                    "this section makes {more} problems{}, over the limit of {MAX_PROBLEMS} problems of a spec; split the spec",
                    if have > 0 {
                        format!(" (after {have} before it)")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        Ok(())
    }

    /// `budget` or `budget_per_dim` of a table, if present (not both): a
    /// value or a list of values (a budget grid).
    fn budget(&self, table: &Table<'_>, section: &str) -> Result<Option<Budget>, SpecError> {
        let fixed = self.get(table, "budget");
        let per_dim = self.get(table, "budget_per_dim");
        let values = |v: &Value<'_>, key: &str| -> Result<Vec<u64>, SpecError> {
            let field = format!("{section}.{key}");
            self.one_or_many(v, &field)?
                .into_iter()
                .map(|item| self.budget_value(item, &field))
                .collect()
        };
        match (fixed, per_dim) {
            (Some(_), Some(p)) => Err(self.error(
                p.span(),
                &format!("{section}.budget_per_dim"),
                "give either \"budget\" or \"budget_per_dim\", not both".into(),
            )),
            (Some(b), None) => Ok(Some(Budget::Fixed(values(b, "budget")?))),
            (None, Some(p)) => Ok(Some(Budget::PerDim(values(p, "budget_per_dim")?))),
            (None, None) => Ok(None),
        }
    }
    /// The `[[problem]]` problems of the spec: every function × dimension
    /// × transform × instance × budget of each section.
    fn problems(
        &self,
        root: &Table<'_>,
        default_budget: Option<&Budget>,
        span: Range<usize>,
    ) -> Result<Vec<ProblemEntry>, SpecError> {
        let mut out: Vec<ProblemEntry> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for (i, entry) in self
            .array_of_tables(root, "problem", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("problem[{}]", i + 1);
            let table = self.table(entry, &section)?;
            self.check_keys(table, &section, &PROBLEM_KEYS)?;
            let own = self.budget(table, &section)?;
            let budget = own.as_ref().or(default_budget).ok_or_else(|| {
                self.error(
                    entry.span(),
                    &format!("{section}.budget"),
                    "no budget: give \"budget\" or \"budget_per_dim\" in [experiment] or in this [[problem]]".into(),
                )
            })?;
            if self.problem_suite(table, &section)? {
                self.bbob_problems(table, &section, entry, budget, &mut out, &mut seen)?;
                continue;
            }
            let functions = self.problem_functions(table, &section, entry)?;
            let dims = self.problem_dims(table, &section, entry)?;
            let transforms = self.problem_transforms(table, &section, entry)?;
            let instances = self.instances(table, &section, MAX_INSTANCES, MAX_INSTANCES)?;
            let budgets = match budget {
                Budget::Fixed(b) | Budget::PerDim(b) => b.len(),
            };
            let count = [
                functions.len(),
                dims.len(),
                transforms.len(),
                instances.len(),
                budgets,
            ]
            .iter()
            .fold(1u128, |n, &k| n.saturating_mul(k as u128));
            self.check_problem_count(out.len(), count, &entry.span(), &section)?;
            for (f, fspan) in &functions {
                let f = match f {
                    FunctionRef::Builtin(f) => f,
                    FunctionRef::Registered(def) => {
                        let at = (fspan, section.as_str(), budget);
                        self.registered_problems(def, at, &dims, &transforms, &mut out, &mut seen)?;
                        continue;
                    }
                };
                for (dim, dspan) in &dims {
                    let dim = self.problem_dim(*f, *dim, fspan, dspan, &section)?;
                    for (t, tspan) in &transforms {
                        TestProblem::check_instance(*f, dim, *t).map_err(|e| {
                            self.error(
                                tspan.clone(),
                                &format!("{section}.transform"),
                                e.to_string(),
                            )
                        })?;
                        // The published function has one instance, whatever
                        // the list.
                        let listed: &[u32] = if *t == Transform::None {
                            &[1]
                        } else {
                            &instances
                        };
                        for &instance in listed {
                            for b in self.dim_budgets(budget, dim, dspan, &section)? {
                                let p = ProblemEntry {
                                    kind: Arc::new(Benchmark::new(*f)),
                                    dim,
                                    budget: b,
                                    budget_factor: budget.is_grid(),
                                    transform: *t,
                                    instance,
                                };
                                if !seen.insert(p.key()) {
                                    return Err(self.error(
                                        fspan.clone(),
                                        &section,
                                        format!("problem {} is listed twice", p.key()),
                                    ));
                                }
                                out.push(p);
                            }
                        }
                    }
                }
            }
        }
        Ok(out)
    }

    /// The optional `instances` of a `[[problem]]`: a count N (instances
    /// 1..=N, N ≤ `max_count`) or a list of distinct instance numbers, each
    /// in 1..=`max_instance`; absent, instance 1 alone. Shared by the
    /// thesis's functions and the bbob suite.
    fn instances(
        &self,
        table: &Table<'_>,
        section: &str,
        max_count: u64,
        max_instance: u64,
    ) -> Result<Vec<u32>, SpecError> {
        let field = format!("{section}.instances");
        let Some(v) = self.get(table, "instances") else {
            return Ok(vec![1]);
        };
        let DeValue::Array(_) = v.get_ref() else {
            return Ok((1..=self.integer(v, &field, 1, max_count)? as u32).collect());
        };
        let mut out: Vec<u32> = Vec::new();
        for item in self.one_or_many(v, &field)? {
            let k = self.integer(item, &field, 1, max_instance)? as u32;
            if out.contains(&k) {
                return Err(self.error(
                    item.span(),
                    &field,
                    format!(
                        "instance {k} is listed twice; give a count N (instances 1..N) or a list of distinct instance numbers"
                    ),
                ));
            }
            out.push(k);
        }
        Ok(out)
    }

    /// Whether a `[[problem]]` names the `bbob` suite (`suite = "bbob"`);
    /// absent, the problem is one of the thesis's ten functions.
    fn problem_suite(&self, table: &Table<'_>, section: &str) -> Result<bool, SpecError> {
        let Some(v) = self.get(table, "suite") else {
            return Ok(false);
        };
        let field = format!("{section}.suite");
        let name = self.string(v, &field)?;
        match name.as_str() {
            "bbob" if cfg!(feature = "coco") => Ok(true),
            "bbob" => Err(self.error(v.span(), &field, bbob::NO_COCO.to_owned())),
            _ => Err(self.error(
                v.span(),
                &field,
                format!(
                    "unknown suite \"{name}\"; {}",
                    choices_hint(&name, &["bbob"])
                ),
            )),
        }
    }

    /// The optional `transform` of a `[[problem]]`: a name or a list.
    fn problem_transforms(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<Vec<WithSpan<Transform>>, SpecError> {
        let Some(tv) = self.get(table, "transform") else {
            return Ok(vec![(Transform::None, entry.span())]);
        };
        let field = format!("{section}.transform");
        self.one_or_many(tv, &field)?
            .into_iter()
            .map(|v| {
                let name = self.string(v, &field)?;
                let t = Transform::from_name(&name).ok_or_else(|| {
                    self.error(
                        v.span(),
                        &field,
                        format!(
                            "unknown transform \"{name}\"; {}",
                            choices_hint(&name, &Transform::NAMES)
                        ),
                    )
                })?;
                Ok((t, v.span()))
            })
            .collect()
    }

    /// The problems of a registered function `def` at each of `dims` (one
    /// budget each, as for the built-ins); a registered problem has no
    /// transform and no instances, and is built here, so that a builder's
    /// refusal is an error of the spec, located at the dimension.
    fn registered_problems(
        &self,
        def: &ProblemDef,
        (fspan, section, budget): (&Range<usize>, &str, &Budget),
        dims: &[WithSpan<Option<usize>>],
        transforms: &[WithSpan<Transform>],
        out: &mut Vec<ProblemEntry>,
        seen: &mut std::collections::HashSet<String>,
    ) -> Result<(), SpecError> {
        if let Some((_, tspan)) = transforms.iter().find(|(t, _)| *t != Transform::None) {
            return Err(self.error(
                tspan.clone(),
                &format!("{section}.transform"),
                format!(
                    "{} is a registered problem, which has no transforms; give it in a [[problem]] of its own without \"transform\"",
                    def.name
                ),
            ));
        }
        for (dim, dspan) in dims {
            let Some(dim) = *dim else {
                return Err(self.error(
                    fspan.clone(),
                    &format!("{section}.dim"),
                    format!(
                        "missing \"dim\": {} is a registered problem and needs a dimension",
                        def.name
                    ),
                ));
            };
            let problem = def
                .instance(dim)
                .map_err(|e| self.error(dspan.clone(), &format!("{section}.dim"), e))?;
            for b in self.dim_budgets(budget, dim, dspan, section)? {
                let p = ProblemEntry {
                    kind: Arc::new(RegisteredProblem {
                        name: def.name.clone(),
                        optimum: def.optimum(dim),
                        problem: problem.clone(),
                    }),
                    dim,
                    budget: b,
                    budget_factor: budget.is_grid(),
                    transform: Transform::None,
                    instance: 1,
                };
                if !seen.insert(p.key()) {
                    return Err(self.error(
                        fspan.clone(),
                        section,
                        format!("problem {} is listed twice", p.key()),
                    ));
                }
                out.push(p);
            }
        }
        Ok(())
    }

    /// The required `function` of a `[[problem]]`: the benchmark functions
    /// (built-in or registered) with their spans.
    fn problem_functions(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<Vec<WithSpan<FunctionRef>>, SpecError> {
        let fv = self.required(table, section, "function", entry.span())?;
        let field = format!("{section}.function");
        let mut functions = Vec::new();
        for v in self.one_or_many(fv, &field)? {
            let name = self.string(v, &field)?;
            let builtin = Function::from_name(&name).map(FunctionRef::Builtin);
            let registered = || {
                self.registry
                    .problem(&name)
                    .map(|d| FunctionRef::Registered(d.clone()))
            };
            let f = builtin.or_else(registered).ok_or_else(|| {
                let names = self.registry.function_names();
                self.error(
                    v.span(),
                    &field,
                    format!(
                        "unknown function \"{name}\"; {}",
                        choices_hint(&name, &names)
                    ),
                )
            })?;
            functions.push((f, v.span()));
        }
        Ok(functions)
    }

    /// The optional `dim` of a `[[problem]]`: the dimensions with their
    /// spans, or one unset dimension (each function's fixed one).
    fn problem_dims(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<Vec<WithSpan<Option<usize>>>, SpecError> {
        let Some(dv) = self.get(table, "dim") else {
            return Ok(vec![(None, entry.span())]);
        };
        let field = format!("{section}.dim");
        self.one_or_many(dv, &field)?
            .into_iter()
            .map(|v| {
                Ok((
                    Some(self.integer(v, &field, 1, 1_000_000)? as usize),
                    v.span(),
                ))
            })
            .collect()
    }

    /// The dimension of function `f` (the one given, else its fixed one),
    /// checked against the function.
    fn problem_dim(
        &self,
        f: Function,
        dim: Option<usize>,
        fspan: &Range<usize>,
        dspan: &Range<usize>,
        section: &str,
    ) -> Result<usize, SpecError> {
        let dim = match (dim, f.fixed_dim()) {
            (Some(d), _) => d,
            (None, Some(d)) => d,
            (None, None) => {
                return Err(self.error(
                    fspan.clone(),
                    &format!("{section}.dim"),
                    format!(
                        "missing \"dim\": {} is scalable and needs a dimension",
                        f.name()
                    ),
                ))
            }
        };
        if let Err(e) = TestProblem::new(f, dim) {
            return Err(self.error(dspan.clone(), &format!("{section}.dim"), e.to_string()));
        }
        Ok(dim)
    }

    /// The algorithm cells of the spec: each `[[algorithm]]` expanded into
    /// the grid of its listed parameter values. With `benchmarks`, only
    /// metaheuristics are allowed.
    fn cells(
        &self,
        root: &Table<'_>,
        span: Range<usize>,
        benchmarks: bool,
        (problems, runs): (usize, u32),
    ) -> Result<Vec<Cell>, SpecError> {
        let mut out: Vec<Cell> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for (i, entry) in self
            .array_of_tables(root, "algorithm", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("algorithm[{}]", i + 1);
            let table = self.table(entry, &section)?;
            let algorithm = self.algorithm_entry(table, section, entry.span(), benchmarks)?;
            self.check_grid_size(&algorithm, out.len(), problems, runs)?;
            for combo in grid(&algorithm.axes) {
                let cell = self.grid_cell(&algorithm, &combo)?;
                if !seen.insert(cell.key()) {
                    return Err(self.error(
                        algorithm.span.clone(),
                        &algorithm.section,
                        format!(
                            "algorithm cell {} [{}] appears twice; give the entries different labels or parameters",
                            cell.label,
                            cell.params.canonical()
                        ),
                    ));
                }
                out.push(cell);
            }
        }
        Ok(out)
    }

    /// Refuses, before it is expanded, a grid that takes the spec past
    /// [`MAX_CELLS`] cells, or the campaign past `limits.max_runs` runs
    /// (problems × cells × runs, counted with the `have` cells before it).
    fn check_grid_size(
        &self,
        entry: &AlgorithmEntry,
        have: usize,
        problems: usize,
        runs: u32,
    ) -> Result<(), SpecError> {
        let sizes: Vec<usize> = entry.axes.iter().map(|a| a.len().max(1)).collect();
        let grid = sizes
            .iter()
            .fold(1u128, |n, &k| n.saturating_mul(k as u128));
        let shape = if sizes.iter().any(|&k| k > 1) {
            let listed: Vec<String> = sizes
                .iter()
                .filter(|&&k| k > 1)
                .map(usize::to_string)
                .collect();
            format!("its grid of {} = {grid} cells", listed.join(" × "))
        } else {
            "its cell".to_owned()
        };
        let cells = have as u128 + grid;
        if cells > MAX_CELLS as u128 {
            return Err(self.error(
                entry.span.clone(),
                &entry.section,
                format!(
                    "{shape}{} pass the limit of {MAX_CELLS} algorithm cells of a spec; list fewer values, or split the spec",
                    if have > 0 {
                        format!(" after {have} cells before it")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        let total = (problems as u128)
            .saturating_mul(cells)
            .saturating_mul(u128::from(runs));
        if total > self.limits.max_runs {
            return Err(self.error(
                entry.span.clone(),
                &entry.section,
                format!(
                    "with {shape} the campaign has {problems} problems × {cells} cells × {runs} runs = {total} runs, over the limit of {} runs; split the spec, or pass --allow-large",
                    self.limits.max_runs
                ),
            ));
        }
        Ok(())
    }

    /// Reads one `[[algorithm]]` table: its method, label and parameter
    /// axes, in that order.
    fn algorithm_entry(
        &self,
        table: &Table<'_>,
        section: String,
        span: Range<usize>,
        benchmarks: bool,
    ) -> Result<AlgorithmEntry, SpecError> {
        let (name, base, polish) = self.method_name(table, &section, span.clone(), benchmarks)?;
        let defs: &'static [ParamDef] = match &base {
            Some(b) => {
                self.registry
                    .optimisers
                    .get(b)
                    .expect("a known algorithm")
                    .params
            }
            None => &[],
        };
        let label = self.cell_label(table, &section, &name)?;
        self.check_params(table, &section, &name, defs)?;
        let axes = self.param_axes(table, &section, defs)?;
        Ok(AlgorithmEntry {
            section,
            span,
            base,
            polish,
            label,
            defs,
            axes,
        })
    }

    /// The required `name` of an `[[algorithm]]`, resolved to a method;
    /// Levenberg–Marquardt is refused when the spec has `benchmarks`.
    fn method_name(
        &self,
        table: &Table<'_>,
        section: &str,
        span: Range<usize>,
        benchmarks: bool,
    ) -> Result<(String, Option<String>, bool), SpecError> {
        let nv = self.required(table, section, "name", span)?;
        let field = format!("{section}.name");
        let name = self.string(nv, &field)?;
        let optimisers = &self.registry.optimisers;
        let (base, polish) = Method::parse_name_in(&name, optimisers).ok_or_else(|| {
            // Only the methods that can solve this spec's problems.
            let names = if benchmarks {
                optimisers.names().iter().map(|s| s.to_string()).collect()
            } else {
                Method::names_in(optimisers)
            };
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            self.error(
                nv.span(),
                &field,
                format!(
                    "unknown algorithm \"{name}\"; {}",
                    choices_hint(&name, &names)
                ),
            )
        })?;
        if benchmarks && (base.is_none() || polish) {
            return Err(self.error(
                nv.span(),
                &field,
                format!(
                    "\"{name}\" uses Levenberg–Marquardt, which solves least-squares fitting problems only, but this spec has [[problem]] benchmark functions; use it with [[fit]] problems, or choose one of {}",
                    quoted_list(&optimisers.names())
                ),
            ));
        }
        let base = base.map(str::to_owned);
        Ok((name, base, polish))
    }

    /// The cell label: `label` if given, else the method name.
    fn cell_label(
        &self,
        table: &Table<'_>,
        section: &str,
        name: &str,
    ) -> Result<String, SpecError> {
        let Some(v) = self.get(table, "label") else {
            return Ok(name.to_owned());
        };
        let l = self.string(v, &format!("{section}.label"))?;
        if l.is_empty() || l.contains(['\n', '\r', '"']) {
            return Err(self.error(
                v.span(),
                &format!("{section}.label"),
                "expected a non-empty label without quotes or line breaks".into(),
            ));
        }
        Ok(l)
    }

    /// Checks that every key of an `[[algorithm]]` besides `name` and
    /// `label` is a parameter of method `name` (whose parameters are `defs`).
    fn check_params(
        &self,
        table: &Table<'_>,
        section: &str,
        name: &str,
        defs: &[ParamDef],
    ) -> Result<(), SpecError> {
        let param_names: Vec<&str> = defs.iter().map(|d| d.name).collect();
        for (k, _) in table.iter() {
            let key: &str = k.get_ref();
            if key == "name" || key == "label" || param_names.contains(&key) {
                continue;
            }
            let mut valid = vec!["name", "label"];
            valid.extend(&param_names);
            return Err(self.error(
                k.span(),
                &format!("{section}.{key}"),
                format!(
                    "unknown parameter for {name}{}; {}",
                    if defs.is_empty() {
                        " (it has none)"
                    } else {
                        ""
                    },
                    choices_hint(key, &valid)
                ),
            ));
        }
        Ok(())
    }

    /// Each parameter's listed values with their spans, in declaration
    /// order; empty for a parameter left at its default.
    fn param_axes(
        &self,
        table: &Table<'_>,
        section: &str,
        defs: &[ParamDef],
    ) -> Result<Vec<Axis>, SpecError> {
        let mut axes: Vec<Axis> = Vec::new();
        for def in defs {
            let Some(v) = self.get(table, def.name) else {
                axes.push(Vec::new());
                continue;
            };
            let field = format!("{section}.{}", def.name);
            let mut values = Vec::new();
            for item in self.one_or_many(v, &field)? {
                let setting = def
                    .check(&raw(item.get_ref()))
                    .map_err(|e| self.error(item.span(), &field, e.to_string()))?;
                values.push((setting, item.span()));
            }
            axes.push(values);
        }
        Ok(axes)
    }

    /// The cell of one grid point `combo` (an index into each axis): the
    /// defaults with the chosen values, and the method configured with them.
    fn grid_cell(&self, entry: &AlgorithmEntry, combo: &[usize]) -> Result<Cell, SpecError> {
        let mut params = ParamSet::defaults(entry.defs);
        let mut spans = Vec::new();
        for ((def, axis), k) in entry.defs.iter().zip(&entry.axes).zip(combo) {
            if let Some((setting, sp)) = axis.get(*k) {
                params.put(def.name, setting.clone());
                spans.push((def.name, sp.clone()));
            }
        }
        let algorithm = match &entry.base {
            None => None,
            Some(b) => Some(self.registry.optimisers.build(b, &params).map_err(|e| {
                let sp = spans
                    .iter()
                    .find(|(n, _)| *n == e.param)
                    .map_or(entry.span.clone(), |(_, s)| s.clone());
                self.error(
                    sp,
                    &format!("{}.{}", entry.section, e.param),
                    e.message.clone(),
                )
            })?),
        };
        Ok(Cell {
            label: entry.label.clone(),
            method: Method::build(algorithm, entry.polish),
            params,
        })
    }
}

/// One `[[algorithm]]` entry, read: its method, label and parameter axes.
struct AlgorithmEntry {
    /// `algorithm[i]`, for errors.
    section: String,
    /// The entry's span, for errors about the whole entry.
    span: Range<usize>,
    /// The metaheuristic whose parameters it takes (`None` for `lm`).
    base: Option<String>,
    /// Whether the metaheuristic is polished by LM.
    polish: bool,
    /// The label of its cells.
    label: String,
    /// The parameters of the metaheuristic.
    defs: &'static [ParamDef],
    /// The listed values of each parameter, in `defs` order.
    axes: Vec<Axis>,
}

/// A `[[problem]] function` name, resolved.
enum FunctionRef {
    /// One of the thesis's functions.
    Builtin(Function),
    /// A registered problem.
    Registered(Arc<ProblemDef>),
}

/// The values listed for one parameter, each with its span; empty when the
/// parameter keeps its default.
type Axis = Vec<WithSpan<Setting>>;

/// The cartesian product of the axes as index vectors, first axis slowest;
/// an empty axis counts as one value (the default).
fn grid(axes: &[Axis]) -> Vec<Vec<usize>> {
    let mut combos: Vec<Vec<usize>> = vec![Vec::new()];
    for axis in axes {
        let n = axis.len().max(1);
        combos = combos
            .into_iter()
            .flat_map(|c| {
                (0..n).map(move |k| {
                    let mut c = c.clone();
                    c.push(k);
                    c
                })
            })
            .collect();
    }
    combos
}

/// A value with the span of the text it was read from.
type WithSpan<T> = (T, Range<usize>);

/// The `[experiment]` section of a spec.
struct Header {
    name: String,
    seed: u64,
    runs: u32,
    /// The default budget of the problems.
    budget: Option<Budget>,
    threshold: f64,
    checkpoints_per_decade: u32,
    /// `experiment.stop` and its span.
    stop: WithSpan<Stop>,
}

/// A budget as written in a spec: one value or a grid of values.
#[derive(Clone, Debug)]
pub(crate) enum Budget {
    /// Evaluations per run.
    Fixed(Vec<u64>),
    /// Evaluations per run and dimension.
    PerDim(Vec<u64>),
}

impl Budget {
    /// The budgets of a problem of dimension `dim`.
    fn for_dim(&self, dim: usize) -> Vec<u64> {
        match self {
            Budget::Fixed(b) => b.clone(),
            Budget::PerDim(b) => b.iter().map(|b| b.saturating_mul(dim as u64)).collect(),
        }
    }

    /// Whether several budgets were listed, making the budget a factor.
    pub(crate) fn is_grid(&self) -> bool {
        match self {
            Budget::Fixed(b) | Budget::PerDim(b) => b.len() > 1,
        }
    }
}
