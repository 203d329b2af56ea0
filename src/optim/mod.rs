//! The optimisers of the thesis's chapter 4, two reference algorithms from
//! beyond the thesis (L-SHADE and random search), and the interface they share.
//!
//! Every optimiser minimises a [`Problem`] through an [`Evaluator`], which
//! counts the objective evaluations against a budget, so that algorithms
//! are compared at equal cost. Optimisers take their random number
//! generator from the caller and keep no global state.
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
pub mod evaluator;
pub mod ga;
pub mod ghs;
pub mod harmony;
pub mod hs;
pub mod lm;
pub mod lshade;
pub mod mhs;
pub mod params;
pub mod pso;
pub mod random;

use std::fmt;

use crate::rng::Words;

pub use cmaes::CmaEs;
pub use evaluator::{Evaluator, Outcome, TargetHit, TracePoint};
pub use ga::GeneticAlgorithm;
pub use ghs::GlobalBestHarmonySearch;
pub use hs::HarmonySearch;
pub use lm::{LeastSquares, LevenbergMarquardt};
pub use lshade::Lshade;
pub use mhs::ModifiedHarmonySearch;
pub use params::{quoted_list, Kind, ParamDef, ParamSet, Raw, Setting, SettingError};
pub use pso::ParticleSwarm;
pub use random::RandomSearch;

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

/// The shared `bounds` parameter: how values outside the box are repaired.
pub const BOUNDS_PARAM: ParamDef = ParamDef {
    name: "bounds",
    doc: "bound handling: \"clip\" or \"reflect\"",
    kind: Kind::Choice(&BoundPolicy::NAMES),
    default: Setting::Choice("clip"),
    omit_at_default: false,
};

/// Reads the [`BOUNDS_PARAM`] of a parameter set.
pub fn policy_param(p: &ParamSet) -> BoundPolicy {
    BoundPolicy::from_name(p.choice("bounds")).unwrap_or_default()
}

/// One of the optimisers, configured; the unit an experiment spec names.
#[derive(Clone, Debug, PartialEq)]
pub enum Algorithm {
    /// Harmony Search.
    Hs(HarmonySearch),
    /// Global-best Harmony Search.
    Ghs(GlobalBestHarmonySearch),
    /// Real-coded Genetic Algorithm.
    Ga(GeneticAlgorithm),
    /// Particle Swarm Optimisation.
    Pso(ParticleSwarm),
    /// Modified Harmony Search (reconstruction).
    Mhs(ModifiedHarmonySearch),
    /// CMA-ES with restarts.
    CmaEs(CmaEs),
    /// L-SHADE: success-history adaptive DE with linear population size
    /// reduction.
    Lshade(Lshade),
    /// Uniform random search.
    Random(RandomSearch),
}

impl Algorithm {
    /// The spec names of the algorithms.
    pub const NAMES: [&'static str; 8] =
        ["hs", "ghs", "ga", "pso", "mhs", "cmaes", "lshade", "random"];

    /// The parameter declarations of the algorithm called `name`.
    pub fn params(name: &str) -> Option<&'static [ParamDef]> {
        Some(match name {
            "hs" => &hs::PARAMS,
            "ghs" => &ghs::PARAMS,
            "ga" => &ga::PARAMS,
            "pso" => &pso::PARAMS,
            "mhs" => &mhs::PARAMS,
            "cmaes" => &cmaes::PARAMS,
            "lshade" => &lshade::PARAMS,
            "random" => &random::PARAMS,
            _ => return None,
        })
    }

    /// Builds the algorithm called `name` from a parameter set made from
    /// [`Algorithm::params`]`(name)`.
    pub fn from_params(name: &str, p: &ParamSet) -> Result<Self, ParamError> {
        Ok(match name {
            "hs" => Self::Hs(HarmonySearch::from_params(p)?),
            "ghs" => Self::Ghs(GlobalBestHarmonySearch::from_params(p)?),
            "ga" => Self::Ga(GeneticAlgorithm::from_params(p)?),
            "pso" => Self::Pso(ParticleSwarm::from_params(p)?),
            "mhs" => Self::Mhs(ModifiedHarmonySearch::from_params(p)?),
            "cmaes" => Self::CmaEs(CmaEs::from_params(p)?),
            "lshade" => Self::Lshade(Lshade::from_params(p)?),
            "random" => Self::Random(RandomSearch::from_params(p)?),
            other => {
                return Err(ParamError::new(
                    "algorithm",
                    format!("unknown algorithm \"{other}\""),
                ))
            }
        })
    }

    /// The algorithm with its default parameters.
    pub fn default_for(name: &str) -> Option<Self> {
        let defs = Self::params(name)?;
        Self::from_params(name, &ParamSet::defaults(defs)).ok()
    }

    /// The spec name of this algorithm.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Hs(_) => "hs",
            Self::Ghs(_) => "ghs",
            Self::Ga(_) => "ga",
            Self::Pso(_) => "pso",
            Self::Mhs(_) => "mhs",
            Self::CmaEs(_) => "cmaes",
            Self::Lshade(_) => "lshade",
            Self::Random(_) => "random",
        }
    }
}

impl Optimiser for Algorithm {
    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        match self {
            Self::Hs(a) => a.minimise(eval, rng),
            Self::Ghs(a) => a.minimise(eval, rng),
            Self::Ga(a) => a.minimise(eval, rng),
            Self::Pso(a) => a.minimise(eval, rng),
            Self::Mhs(a) => a.minimise(eval, rng),
            Self::CmaEs(a) => a.minimise(eval, rng),
            Self::Lshade(a) => a.minimise(eval, rng),
            Self::Random(a) => a.minimise(eval, rng),
        }
    }
}
