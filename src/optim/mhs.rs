//! Modified Harmony Search, MHS: the thesis's HS variant that "borrows its
//! mechanism from GA and PSO into classical HS in generating new solution
//! vectors".
//!
//! **This is a reconstruction.** The thesis chapter that defines MHS is lost;
//! its list of symbols keeps "D_l: temporary harmony vectors in MHS" and
//! "α: random number in \[0,1\]". What follows is this project's documented,
//! configurable reading of that description, not the thesis's own text.

use rand::RngCore;

use super::harmony::{
    Bandwidth, HarmonyMemory, Improvisation, BW_DECAY_PARAM, BW_MIN_PARAM, BW_PARAM,
};
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{policy_param, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::problem::{BoundPolicy, Problem};
use crate::rng::Draw;

/// One way of building a temporary harmony `D_l`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Operator {
    /// The classical HS improvisation (memory consideration, pitch
    /// adjustment, random selection).
    Hs,
    /// A GA step: arithmetic crossover `α·x^a + (1 − α)·x^b` of two distinct
    /// random harmonies with `α ~ U(0,1)`, then per-variable mutation with
    /// rate `pm`.
    Ga,
    /// A PSO step: a random harmony moved toward the best,
    /// `x + c·φ∘(x^best − x)` with `φ_j ~ U(0,1)` per variable (the social
    /// term of Kennedy & Eberhart 1995).
    Pso,
}

impl Operator {
    /// Spec names of the operators.
    pub const NAMES: [&'static str; 3] = ["hs", "ga", "pso"];

    fn from_name(name: &str) -> Self {
        match name {
            "hs" => Self::Hs,
            "ga" => Self::Ga,
            _ => Self::Pso,
        }
    }
}

/// Modified Harmony Search (reconstruction; see the module docs).
///
/// Each improvisation builds `L` temporary harmony vectors `D_1..D_L`,
/// `D_l` made by operator `operators[(l − 1) mod len]` (default `hs+ga+pso`,
/// `L = 3`). Each `D_l` is repaired into the bounds and evaluated (so every
/// `D_l` costs one evaluation of the budget), and the best of them replaces
/// the worst harmony in memory if it is better.
#[derive(Clone, Debug, PartialEq)]
pub struct ModifiedHarmonySearch {
    /// Harmony memory size HMS.
    pub hms: usize,
    /// HMCR of the HS operator.
    pub hmcr: f64,
    /// PAR of the HS operator.
    pub par: f64,
    /// Bandwidth of the HS operator and its schedule.
    pub bandwidth: Bandwidth,
    /// The number `L` of temporary harmonies per improvisation.
    pub l: usize,
    /// The operator sequence, cycled over `D_1..D_L`.
    pub operators: Vec<Operator>,
    /// Mutation rate of the GA operator, per variable.
    pub pm: f64,
    /// Gaussian mutation (`σ` as a fraction of the range) instead of uniform.
    pub gaussian_mutation: bool,
    /// Standard deviation of Gaussian mutation, as a fraction of the range.
    pub sigma: f64,
    /// Step coefficient `c` of the PSO operator.
    pub c: f64,
    /// Bound handling.
    pub policy: BoundPolicy,
}

/// The parameters of [`ModifiedHarmonySearch`]; all defaults are this
/// project's choices (the thesis's values are lost).
pub static PARAMS: [ParamDef; 13] = [
    ParamDef {
        name: "hms",
        doc: "harmony memory size HMS",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(10),
    },
    ParamDef {
        name: "hmcr",
        doc: "HMCR of the HS operator",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.9),
    },
    ParamDef {
        name: "par",
        doc: "PAR of the HS operator",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.3),
    },
    BW_PARAM,
    BW_DECAY_PARAM,
    BW_MIN_PARAM,
    ParamDef {
        name: "l",
        doc: "number L of temporary harmony vectors D_l per improvisation",
        kind: Kind::Count { min: 1, max: 1000 },
        default: Setting::Count(3),
    },
    ParamDef {
        name: "operators",
        doc: "operators cycled over D_1..D_L",
        kind: Kind::Sequence(&Operator::NAMES),
        default: Setting::Sequence(std::borrow::Cow::Borrowed(&["hs", "ga", "pso"])),
    },
    ParamDef {
        name: "pm",
        doc: "mutation rate of the GA operator, per variable",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.05),
    },
    ParamDef {
        name: "mutation",
        doc: "\"uniform\" (reset in the bounds) or \"gaussian\" mutation",
        kind: Kind::Choice(&["uniform", "gaussian"]),
        default: Setting::Choice("uniform"),
    },
    ParamDef {
        name: "sigma",
        doc: "standard deviation of Gaussian mutation, as a fraction of the range",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.1),
    },
    ParamDef {
        name: "c",
        doc: "step coefficient c of the PSO operator",
        kind: Kind::Real {
            min: 0.0,
            max: 4.0,
            open_min: true,
        },
        default: Setting::Real(2.0),
    },
    BOUNDS_PARAM,
];

impl Default for ModifiedHarmonySearch {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl ModifiedHarmonySearch {
    /// Builds MHS from validated parameters.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        Ok(Self {
            hms: p.count("hms") as usize,
            hmcr: p.real("hmcr"),
            par: p.real("par"),
            bandwidth: Bandwidth::from_params(p)?,
            l: p.count("l") as usize,
            operators: p
                .sequence("operators")
                .iter()
                .map(|n| Operator::from_name(n))
                .collect(),
            pm: p.real("pm"),
            gaussian_mutation: p.choice("mutation") == "gaussian",
            sigma: p.real("sigma"),
            c: p.real("c"),
            policy: policy_param(p),
        })
    }
}

impl Optimiser for ModifiedHarmonySearch {
    fn minimise<P: Problem + ?Sized, R: RngCore + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let mut hm = HarmonyMemory::random(self.hms, eval, rng);
        if hm.is_empty() {
            return;
        }
        let bounds = eval.bounds();
        let dim = bounds.len();
        let hms = hm.len();
        let widths: Vec<f64> = bounds.iter().map(|b| b.width()).collect();
        let mut bw = vec![0.0; dim];
        self.bandwidth.scale(0.0, &widths, &mut bw);
        let imp = Improvisation {
            hmcr: self.hmcr,
            par: self.par,
            policy: self.policy,
        };
        let mut candidate = vec![0.0; dim];
        let mut best_candidate = vec![0.0; dim];
        let ops = if self.operators.is_empty() {
            &[Operator::Hs][..]
        } else {
            &self.operators[..]
        };
        while eval.remaining() > 0 {
            if self.bandwidth.decay {
                self.bandwidth.scale(eval.progress(), &widths, &mut bw);
            }
            let mut best_value = f64::INFINITY;
            let mut have = false;
            for l in 0..self.l {
                if eval.remaining() == 0 {
                    break;
                }
                match ops[l % ops.len()] {
                    Operator::Hs => imp.improvise(&hm, bounds, &bw, rng, &mut candidate),
                    Operator::Ga => {
                        let a = rng.index(hms);
                        let b = if hms > 1 {
                            (a + 1 + rng.index(hms - 1)) % hms
                        } else {
                            a
                        };
                        let alpha = rng.unit();
                        let (xa, xb) = (hm.harmony(a), hm.harmony(b));
                        for j in 0..dim {
                            let bj = bounds[j];
                            let mut v = alpha * xa[j] + (1.0 - alpha) * xb[j];
                            if rng.unit() < self.pm {
                                v = if self.gaussian_mutation {
                                    bj.repair(
                                        v + self.sigma * widths[j] * rng.gaussian(),
                                        self.policy,
                                    )
                                } else {
                                    bj.lerp(rng.unit())
                                };
                            }
                            candidate[j] = bj.clip(v);
                        }
                    }
                    Operator::Pso => {
                        let x = hm.harmony(rng.index(hms));
                        let best = hm.harmony(hm.best());
                        for j in 0..dim {
                            let v = x[j] + self.c * rng.unit() * (best[j] - x[j]);
                            candidate[j] = bounds[j].repair(v, self.policy);
                        }
                    }
                }
                let v = eval.evaluate(&candidate);
                if !have || v < best_value {
                    best_value = v;
                    best_candidate.copy_from_slice(&candidate);
                    have = true;
                }
            }
            if have {
                hm.consider(&best_candidate, best_value);
            }
        }
    }
}
