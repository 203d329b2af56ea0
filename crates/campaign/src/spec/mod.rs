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
//! A `[[problem]]` with `suite = "…"` is read by that suite's
//! [`ProblemFamily`] (COCO's `bbob`, or one a library user registers), with
//! its own keys; the spec reads `[experiment]` and `[[algorithm]]`, and
//! expands every family's problems over their budgets in one place.
//!
//! A spec may also hold `[[fit]]` sections, outline-fitting problems
//! (see [`FitCase`]), beside or instead of `[[problem]]`;
//! its algorithms may then also be `lm` or `<alg>+lm`.
//!
//! Every error names the file, line, column and field, says what was
//! expected and lists the valid choices.

use std::ops::Range;
use std::path::{Path, PathBuf};

use crate::optim::ParamSet;
use crate::reconstruction::Method;
use crate::registry::Registry;

mod bbob;
mod budget;
mod cells;
mod families;
mod family;
mod fit;
mod fit_tolerance;
mod functions;
mod parser;
mod problem;
mod problem_sections;
mod reader;
mod report;
mod stop;

pub use metabezier_spec::SpecError;
pub(crate) use metabezier_spec::{choices_hint, raw, Table, Value};

pub use bbob::{Bbob, BbobSuite, NO_COCO};
pub use families::FamilyRegistryError;
pub use family::{FamilyProblem, ProblemFamily, ProblemSection, ProblemSink};
pub use fit::FitCase;
pub use functions::{Benchmark, Functions, RegisteredProblem};
pub use problem::{
    benchmark_evaluator, execute_benchmark, factor_suffix, minimise_problem, Factor, ProblemEntry,
    ProblemKind,
};
pub use report::{rope_measure, REPORT_KEYS};
pub use stop::Stop;

use reader::Parser;

/// A value with the span of the text it was read from.
type WithSpan<T> = (T, Range<usize>);

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
