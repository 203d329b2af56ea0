//! A problem of a spec ([`ProblemEntry`]): what it solves (a
//! [`ProblemKind`] of some family), its dimension, budget, transform and
//! instance, and the keys its seeds and records derive from.

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use super::{Spec, Stop};
use crate::functions::Transform;
use crate::optim::evaluator::log_checkpoints;
use crate::optim::{Algorithm, Evaluator, Outcome};
use crate::outcome::{default_targets, FitDetail};
use crate::problem::Problem;
use crate::reconstruction::Method;
use crate::rng::run_rng;

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

    /// Every factor, in the order of [`Factor::NAMES`].
    pub const ALL: [Factor; 5] = [
        Factor::Budget,
        Factor::Transform,
        Factor::Instance,
        Factor::SearchSpace,
        Factor::AlphaSize,
    ];

    /// Parses a factor name.
    pub fn from_name(name: &str) -> Option<Factor> {
        Self::ALL.into_iter().find(|f| f.name() == name)
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

/// One run of a benchmark problem of any family (a registered problem, a
/// registered suite's): the cell's metaheuristic minimises `problem`,
/// whose optimum is `f_star`, under the run's budget, target, target
/// precisions and checkpoints ([`minimise_problem`]); a benchmark run has
/// no fit record.
pub fn execute_benchmark(
    spec: &Spec,
    entry: &ProblemEntry,
    method: &Method,
    problem: &dyn Problem,
    f_star: f64,
    seed: u64,
) -> (Outcome, Option<FitDetail>) {
    let algorithm = metaheuristic(method);
    let out = minimise_problem(spec, entry, algorithm, problem, f_star, seed);
    (out, None)
}

/// The metaheuristic of a benchmark run: the spec refuses least-squares
/// methods on benchmark functions.
pub(crate) fn metaheuristic(method: &Method) -> &Algorithm {
    match method {
        Method::Metaheuristic(a) => a,
        _ => unreachable!("the spec refuses least-squares methods on benchmark functions"),
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
