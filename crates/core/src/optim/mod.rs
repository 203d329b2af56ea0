//! The optimisers of the thesis's chapter 4, two reference algorithms from
//! beyond the thesis (L-SHADE and random search), and the interface they share.
//!
//! Every optimiser minimises a [`Problem`] through an [`Evaluator`], which
//! counts the objective evaluations against a budget, so that algorithms
//! are compared at equal cost. Optimisers take their random number
//! generator from the caller and keep no global state. The contract they
//! share (exact budgets, per-variable bounds, NaN regions ranked last, runs
//! fixed by their seed) is checked once for every registered optimiser by
//! [`conformance`].
//!
//! | spec name | algorithm | source |
//! |---|---|---|
//! | `hs` | [`HarmonySearch`] | Geem, Kim & Loganathan 2001 |
//! | `ghs` | [`GlobalBestHarmonySearch`] | Omran & Mahdavi 2008 |
//! | `ga` | [`GeneticAlgorithm`] | real-coded GA (Goldberg 1989; Eshelman & Schaffer 1993) |
//! | `pso` | [`ParticleSwarm`] | Kennedy & Eberhart 1995; Shi & Eberhart 1998 |
//! | `mhs` | [`ModifiedHarmonySearch`] | the thesis (reconstructed) |
//! | `cmaes` | [`CmaEs`] | CMA-ES (Hansen & Ostermeier 2001; Hansen 2016) with IPOP or BIPOP restarts (Auger & Hansen 2005; Hansen 2009) |
//! | `lshade` | [`Lshade`] | Tanabe & Fukunaga 2014 (L-SHADE, after SHADE, Tanabe & Fukunaga 2013) |
//! | `random` | [`RandomSearch`] | uniform random search (Brooks 1958; Rastrigin 1963): the floor every optimiser must beat |

#[cfg(test)]
mod bowl;
pub mod cmaes;
pub mod conformance;
pub mod evaluator;
pub mod ga;
pub mod ghs;
pub mod harmony;
pub mod hs;
pub mod interrupt;
pub mod lm;
pub mod lshade;
pub mod mhs;
pub mod params;
pub mod pso;
pub mod random;
pub mod recommend;
pub mod registry;

use std::fmt;

use crate::rng::Words;

pub use cmaes::CmaEs;
pub use evaluator::{EarlyEnd, Evaluator, Observer, Outcome, TargetHit, TracePoint};
pub use ga::GeneticAlgorithm;
pub use ghs::GlobalBestHarmonySearch;
pub use hs::HarmonySearch;
pub use lm::{LeastSquares, LevenbergMarquardt};
pub use lshade::Lshade;
pub use mhs::ModifiedHarmonySearch;
pub use params::{
    quoted_list, Kind, Param, ParamDef, ParamSet, ParamValue, Raw, Setting, SettingError,
};
pub use pso::ParticleSwarm;
pub use random::RandomSearch;
pub use recommend::recommended;
pub use registry::{
    Algorithm, ComparisonFamily, DynOptimiser, Factory, OptimiserDef, Optimisers, RegistryError,
    Runs,
};

use crate::problem::{BoundPolicy, Bounds, Problem};

/// `if take_a { a } else { b }` through a bit mask instead of a branch, so
/// that a loop of random choices neither mispredicts nor stops the compiler
/// from vectorising it.
#[inline(always)]
pub fn select(take_a: bool, a: f64, b: f64) -> f64 {
    let m = u64::from(take_a).wrapping_neg();
    f64::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
}

/// `if a > b { a } else { b }`: the rule of x86 `maxpd` (the second operand
/// when either is NaN), so that scalar and vector code agree bit for bit.
#[inline(always)]
pub fn max_x86(a: f64, b: f64) -> f64 {
    if a > b {
        a
    } else {
        b
    }
}

/// `if a < b { a } else { b }`: the rule of x86 `minpd`.
#[inline(always)]
pub fn min_x86(a: f64, b: f64) -> f64 {
    if a < b {
        a
    } else {
        b
    }
}

/// `x` clipped into `[b.lower, b.upper]` by [`max_x86`] and [`min_x86`],
/// which compile to branch-free instructions: the value of
/// [`Bounds::clip`] (a NaN goes to the lower bound) up to the sign of a
/// zero (`clip` keeps an `x` equal to a bound, `clamp` returns the bound).
#[inline(always)]
pub fn clamp(b: Bounds, x: f64) -> f64 {
    min_x86(max_x86(x, b.lower), b.upper)
}

/// A minimiser of box-bounded problems under an evaluation budget.
pub trait Optimiser {
    /// Minimises `eval`'s problem until its budget is spent, drawing all
    /// randomness from `rng`.
    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    );

    /// The most bytes of state this optimiser allocates for one run on a
    /// problem of dimension `dim` with `budget` evaluations (populations,
    /// matrices, archives, restart growth up to the budget), so that a
    /// caller can refuse a run before it allocates ([`Algorithm::state_bytes`]). The
    /// default, for an optimiser that does not say, is 16 vectors of `dim`
    /// reals.
    fn state_bytes(&self, dim: usize, budget: u64) -> u128 {
        let _ = budget;
        vectors_bytes(16, dim)
    }

    /// Minimises `problem` with `budget` evaluations and returns the outcome.
    fn run<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        problem: &P,
        budget: u64,
        rng: &mut R,
    ) -> Outcome {
        let mut eval = Evaluator::new(problem, budget);
        self.minimise(&mut eval, rng);
        eval.finish()
    }
}

/// The bytes of `count` vectors of `dim` reals (f64).
pub fn vectors_bytes(count: usize, dim: usize) -> u128 {
    count as u128 * dim as u128 * 8
}

/// The most bytes a run's optimiser state may take without `--allow-large`
/// (per worker): 4 GiB, the campaign's memory limit.
pub const MAX_STATE_BYTES: u128 = 4 << 30;

/// A parameter combination that is invalid as a whole (each value may be
/// in range on its own), naming the parameter to change.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamError {
    /// The parameter to change.
    pub param: &'static str,
    /// What is wrong.
    pub message: String,
}

impl ParamError {
    /// An error about `param`.
    pub fn new(param: &'static str, message: String) -> Self {
        Self { param, message }
    }
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for ParamError {}

/// The key of the `bounds` parameter.
pub const BOUNDS_KEY: Param<&'static str> = Param::new("bounds");

/// The shared `bounds` parameter: how values outside the box are repaired.
pub const BOUNDS_PARAM: ParamDef = ParamDef {
    name: BOUNDS_KEY.name,
    doc: "bound handling: \"clip\" or \"reflect\"",
    kind: Kind::Choice(&BoundPolicy::NAMES),
    default: Setting::Choice("clip"),
    omit_at_default: false,
};

/// Reads the [`BOUNDS_PARAM`] of a parameter set.
pub fn policy_param(p: &ParamSet) -> BoundPolicy {
    BoundPolicy::from_name(p.get(BOUNDS_KEY)).unwrap_or_default()
}

/// The built-in optimisers, one registration each, in the order
/// `metabezier list` shows them. A new built-in optimiser is one module and
/// one line here.
fn builtin_optimisers() -> Vec<OptimiserDef> {
    vec![
        OptimiserDef::new("hs", &hs::PARAMS, "Geem, Kim & Loganathan 2001", HarmonySearch::from_params).in_family(ComparisonFamily::Thesis),
        OptimiserDef::new("ghs", &ghs::PARAMS, "Omran & Mahdavi 2008", GlobalBestHarmonySearch::from_params).in_family(ComparisonFamily::Thesis),
        OptimiserDef::new("ga", &ga::PARAMS, "real-coded GA (Goldberg 1989; Eshelman & Schaffer 1993)", GeneticAlgorithm::from_params).in_family(ComparisonFamily::Thesis),
        OptimiserDef::new("pso", &pso::PARAMS, "Kennedy & Eberhart 1995; Shi & Eberhart 1998", ParticleSwarm::from_params).in_family(ComparisonFamily::Thesis),
        OptimiserDef::new("mhs", &mhs::PARAMS, "the thesis's Modified HS (reconstructed)", ModifiedHarmonySearch::from_params).in_family(ComparisonFamily::Thesis),
        OptimiserDef::new("cmaes", &cmaes::PARAMS, "Hansen & Ostermeier 2001; Hansen 2016; IPOP/BIPOP restarts (Auger & Hansen 2005; Hansen 2009)", CmaEs::from_params),
        OptimiserDef::new("lshade", &lshade::PARAMS, "Tanabe & Fukunaga 2014", Lshade::from_params),
        OptimiserDef::new("random", &random::PARAMS, "uniform random search (Brooks 1958)", RandomSearch::from_params),
    ]
}
