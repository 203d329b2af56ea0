//! Modified Harmony Search, MHS: the thesis's HS variant that "borrows its
//! mechanism from GA and PSO into classical HS in generating new solution
//! vectors".
//!
//! **This is a reconstruction.** The thesis chapter that defines MHS is lost;
//! its list of symbols keeps "D_l: temporary harmony vectors in MHS" and
//! "α: random number in \[0,1\]". What follows is this project's documented,
//! configurable reading of that description, not the thesis's own text.
//!
//! Three readings are available, all parameters of one optimiser:
//! * `scheme = "candidates"`, `update = "best-of-l"` (the default): each
//!   improvisation builds `L` whole candidate vectors `D_l` (HS, GA, PSO
//!   operators in turn), evaluates each, and only the best may replace the
//!   worst harmony;
//! * `scheme = "candidates"`, `update = "each"`: the same candidates, each
//!   offered to the memory in turn as soon as it is evaluated;
//! * `scheme = "per-variable"`: one candidate per improvisation (one
//!   evaluation); per variable, after memory consideration, the value is
//!   pitch-adjusted (probability PAR), crossed with the same variable of
//!   another harmony (GA, probability `p_ga`), pulled toward the best
//!   harmony (PSO, probability `p_pso`) or kept. This follows the published
//!   hybrids that act inside one improvisation: the particle-swarm harmony
//!   search of Geem (2009, "Particle-swarm harmony search for water network
//!   design", Engineering Optimization 41(4):297–311) and the global-best
//!   HS of Omran & Mahdavi (2008) for the pull to the best, and the
//!   crossover-in-HS hybrids such as Abu Doush et al. (2013, "Hybridizing
//!   harmony search algorithm with multi-parent crossover", IJAMC 4(3):1–14)
//!   for the GA step, applied here per variable (our adaptation).

use crate::optim::params::Param;
use crate::rng::Words;

use super::harmony::{
    Bandwidth, BoundColumns, HarmonyMemory, Improvisation, BW_DECAY_PARAM, BW_MIN_PARAM, BW_PARAM,
    CHUNK,
};
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{clamp, policy_param, select, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::{unit_of, Draw, Field21};
use crate::simd::{dispatch, Simd};

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

/// How the temporary harmonies enter the memory (`update`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Update {
    /// Only the best `D_l` of an improvisation is offered to the memory.
    BestOfL,
    /// Every `D_l` is offered to the memory as soon as it is evaluated.
    Each,
}

/// Where the GA and PSO mechanisms act (`scheme`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// On whole candidate vectors `D_1..D_L`, one evaluation each.
    Candidates,
    /// Per variable inside one improvisation, one evaluation.
    PerVariable,
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
    /// How the candidates enter the memory.
    pub update: Update,
    /// Whole candidates or per-variable mechanisms.
    pub scheme: Scheme,
    /// Per-variable probability of the GA crossover (per-variable scheme).
    pub p_ga: f64,
    /// Per-variable probability of the PSO pull (per-variable scheme).
    pub p_pso: f64,
}

/// The key of the `scheme` parameter.
pub const SCHEME_KEY: Param<&'static str> = Param::new("scheme");
/// The key of the `par` parameter.
pub const PAR_KEY: Param<f64> = Param::new("par");
/// The key of the `p_ga` parameter.
pub const P_GA_KEY: Param<f64> = Param::new("p_ga");
/// The key of the `p_pso` parameter.
pub const P_PSO_KEY: Param<f64> = Param::new("p_pso");
/// The key of the `hms` parameter.
pub const HMS_KEY: Param<u64> = Param::new("hms");
/// The key of the `hmcr` parameter.
pub const HMCR_KEY: Param<f64> = Param::new("hmcr");
/// The key of the `l` parameter.
pub const L_KEY: Param<u64> = Param::new("l");
/// The key of the `operators` parameter.
pub const OPERATORS_KEY: Param<Vec<&'static str>> = Param::new("operators");
/// The key of the `pm` parameter.
pub const PM_KEY: Param<f64> = Param::new("pm");
/// The key of the `mutation` parameter.
pub const MUTATION_KEY: Param<&'static str> = Param::new("mutation");
/// The key of the `sigma` parameter.
pub const SIGMA_KEY: Param<f64> = Param::new("sigma");
/// The key of the `c` parameter.
pub const C_KEY: Param<f64> = Param::new("c");
/// The key of the `update` parameter.
pub const UPDATE_KEY: Param<&'static str> = Param::new("update");

/// The parameters of [`ModifiedHarmonySearch`]; all defaults are this
/// project's choices (the thesis's values are lost). The last four were
/// added with the alternative readings and are left out of the canonical
/// text at their defaults, so earlier results keep their keys and seeds.
pub static PARAMS: [ParamDef; 17] = [
    ParamDef {
        name: HMS_KEY.name,
        doc: "harmony memory size HMS",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(10),
        omit_at_default: false,
    },
    ParamDef {
        name: HMCR_KEY.name,
        doc: "HMCR of the HS operator",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.9),
        omit_at_default: false,
    },
    ParamDef {
        name: PAR_KEY.name,
        doc: "PAR of the HS operator",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.3),
        omit_at_default: false,
    },
    BW_PARAM,
    BW_DECAY_PARAM,
    BW_MIN_PARAM,
    ParamDef {
        name: L_KEY.name,
        doc: "number L of temporary harmony vectors D_l per improvisation",
        kind: Kind::Count { min: 1, max: 1000 },
        default: Setting::Count(3),
        omit_at_default: false,
    },
    ParamDef {
        name: OPERATORS_KEY.name,
        doc: "operators cycled over D_1..D_L",
        kind: Kind::Sequence(&Operator::NAMES),
        default: Setting::Sequence(std::borrow::Cow::Borrowed(&["hs", "ga", "pso"])),
        omit_at_default: false,
    },
    ParamDef {
        name: PM_KEY.name,
        doc: "mutation rate of the GA operator, per variable",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.05),
        omit_at_default: false,
    },
    ParamDef {
        name: MUTATION_KEY.name,
        doc: "\"uniform\" (reset in the bounds) or \"gaussian\" mutation",
        kind: Kind::Choice(&["uniform", "gaussian"]),
        default: Setting::Choice("uniform"),
        omit_at_default: false,
    },
    ParamDef {
        name: SIGMA_KEY.name,
        doc: "standard deviation of Gaussian mutation, as a fraction of the range",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.1),
        omit_at_default: false,
    },
    ParamDef {
        name: C_KEY.name,
        doc: "step coefficient c of the PSO operator",
        kind: Kind::Real {
            min: 0.0,
            max: 4.0,
            open_min: true,
        },
        default: Setting::Real(2.0),
        omit_at_default: false,
    },
    BOUNDS_PARAM,
    ParamDef {
        name: UPDATE_KEY.name,
        doc: "\"best-of-l\" (only the best D_l is offered to the memory) or \"each\" (every D_l in turn)",
        kind: Kind::Choice(&["best-of-l", "each"]),
        default: Setting::Choice("best-of-l"),
        omit_at_default: true,
    },
    ParamDef {
        name: SCHEME_KEY.name,
        doc: "\"candidates\" (L whole vectors D_l) or \"per-variable\" (PA, GA or PSO per variable, one evaluation)",
        kind: Kind::Choice(&["candidates", "per-variable"]),
        default: Setting::Choice("candidates"),
        omit_at_default: true,
    },
    ParamDef {
        name: P_GA_KEY.name,
        doc: "per-variable scheme: probability of the GA crossover α·x_j + (1 − α)·x^b_j",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.2),
        omit_at_default: true,
    },
    ParamDef {
        name: P_PSO_KEY.name,
        doc: "per-variable scheme: probability of the PSO pull x_j + c·φ·(best_j − x_j)",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.2),
        omit_at_default: true,
    },
];

impl Default for ModifiedHarmonySearch {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl ModifiedHarmonySearch {
    /// Builds MHS from validated parameters.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let scheme = match p.get(SCHEME_KEY) {
            "per-variable" => Scheme::PerVariable,
            _ => Scheme::Candidates,
        };
        let (par, p_ga, p_pso) = (p.get(PAR_KEY), p.get(P_GA_KEY), p.get(P_PSO_KEY));
        if scheme == Scheme::PerVariable && par + p_ga + p_pso > 1.0 {
            return Err(ParamError::new(
                "p_pso",
                format!(
                    "the per-variable scheme needs par + p_ga + p_pso ≤ 1, found {par} + {p_ga} + {p_pso}"
                ),
            ));
        }
        Ok(Self {
            hms: p.get(HMS_KEY) as usize,
            hmcr: p.get(HMCR_KEY),
            par: p.get(PAR_KEY),
            bandwidth: Bandwidth::from_params(p)?,
            l: p.get(L_KEY) as usize,
            operators: p
                .get(OPERATORS_KEY)
                .iter()
                .map(|n| Operator::from_name(n))
                .collect(),
            pm: p.get(PM_KEY),
            gaussian_mutation: p.get(MUTATION_KEY) == "gaussian",
            sigma: p.get(SIGMA_KEY),
            c: p.get(C_KEY),
            policy: policy_param(p),
            update: match p.get(UPDATE_KEY) {
                "each" => Update::Each,
                _ => Update::BestOfL,
            },
            scheme,
            p_ga,
            p_pso,
        })
    }
}

impl Optimiser for ModifiedHarmonySearch {
    /// The harmony memory (HMS × D), the L temporary harmonies and a few
    /// D-vectors.
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        super::vectors_bytes(self.hms + self.l + 4, dim)
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let mut hm = HarmonyMemory::random(self.hms, eval, rng);
        if hm.is_empty() {
            return;
        }
        let widths: Vec<f64> = eval.bounds().iter().map(|b| b.width()).collect();
        let mut bw = vec![0.0; widths.len()];
        self.bandwidth.scale(0.0, &widths, &mut bw);
        dispatch(
            #[inline(always)]
            |simd| match self.scheme {
                Scheme::Candidates => self.candidates(&mut hm, eval, rng, &widths, &mut bw, simd),
                Scheme::PerVariable => self.per_variable(&mut hm, eval, rng, &widths, &mut bw),
            },
        )
    }
}

impl ModifiedHarmonySearch {
    /// The candidate scheme: `L` whole vectors `D_l` per improvisation.
    #[inline(always)]
    fn candidates<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        hm: &mut HarmonyMemory,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        widths: &[f64],
        bw: &mut [f64],
        simd: Simd,
    ) {
        let bounds = eval.bounds();
        let dim = bounds.len();
        let cols = BoundColumns::new(bounds);
        let imp = Improvisation {
            hmcr: self.hmcr,
            par: self.par,
            policy: self.policy,
        };
        let mut candidate = vec![0.0; dim];
        let mut words = [0; 2 * CHUNK];
        // Scratch for the GA and PSO steps' uniforms, one block at a time.
        let mut units = vec![0.0; dim.min(CHUNK)];
        let mut best_candidate = vec![0.0; dim];
        let ops = if self.operators.is_empty() {
            &[Operator::Hs][..]
        } else {
            &self.operators[..]
        };
        while eval.remaining() > 0 {
            if self.bandwidth.decay {
                self.bandwidth.scale(eval.progress(), widths, bw);
            }
            let mut best_value = f64::INFINITY;
            let mut have = false;
            for l in 0..self.l {
                if eval.remaining() == 0 {
                    break;
                }
                match ops[l % ops.len()] {
                    Operator::Hs => {
                        imp.improvise(hm, &cols, bw, rng, &mut words, &mut candidate, simd)
                    }
                    Operator::Ga => {
                        self.crossover(hm, bounds, widths, rng, &mut units, &mut candidate)
                    }
                    Operator::Pso => self.pull_to_best(hm, bounds, rng, &mut units, &mut candidate),
                }
                let v = eval.evaluate(&candidate);
                match self.update {
                    Update::Each => {
                        hm.consider(&candidate, v);
                    }
                    Update::BestOfL => {
                        if !have || v < best_value {
                            best_value = v;
                            best_candidate.copy_from_slice(&candidate);
                            have = true;
                        }
                    }
                }
            }
            if have {
                hm.consider(&best_candidate, best_value);
            }
        }
    }

    /// The GA operator: arithmetic crossover `α·x^a + (1 − α)·x^b` of two
    /// distinct random harmonies, then per-variable mutation with rate `pm`.
    fn crossover<R: Words + ?Sized>(
        &self,
        hm: &HarmonyMemory,
        bounds: &[Bounds],
        widths: &[f64],
        rng: &mut R,
        trials: &mut [f64],
        candidate: &mut [f64],
    ) {
        let hms = hm.len();
        let a = rng.index(hms);
        let b = if hms > 1 {
            (a + 1 + rng.index(hms - 1)) % hms
        } else {
            a
        };
        let alpha = rng.unit();
        let (xa, xb) = (hm.harmony(a), hm.harmony(b));
        // The mutation trials of a block of variables are drawn together;
        // a mutation (rare) draws its own values after them.
        for start in (0..bounds.len()).step_by(CHUNK) {
            let end = (start + CHUNK).min(bounds.len());
            let trials = &mut trials[..end - start];
            rng.units(trials);
            for (j, &trial) in (start..end).zip(trials.iter()) {
                let bj = bounds[j];
                let mut v = alpha * xa[j] + (1.0 - alpha) * xb[j];
                if trial < self.pm {
                    v = if self.gaussian_mutation {
                        bj.repair(v + self.sigma * widths[j] * rng.gaussian(), self.policy)
                    } else {
                        bj.lerp(rng.unit())
                    };
                }
                candidate[j] = bj.clip(v);
            }
        }
    }

    /// The PSO operator: a random harmony moved toward the best,
    /// `x + c·φ∘(x^best − x)`.
    fn pull_to_best<R: Words + ?Sized>(
        &self,
        hm: &HarmonyMemory,
        bounds: &[Bounds],
        rng: &mut R,
        phi: &mut [f64],
        candidate: &mut [f64],
    ) {
        let x = hm.harmony(rng.index(hm.len()));
        let best = hm.harmony(hm.best());
        for start in (0..bounds.len()).step_by(CHUNK) {
            let end = (start + CHUNK).min(bounds.len());
            let phi = &mut phi[..end - start];
            rng.units(phi);
            for (j, &phi) in (start..end).zip(phi.iter()) {
                let v = x[j] + self.c * phi * (best[j] - x[j]);
                candidate[j] = bounds[j].repair(v, self.policy);
            }
        }
    }

    /// The per-variable scheme: one candidate, one evaluation, per
    /// improvisation. Per variable, with probability HMCR the value of a
    /// random harmony `a` is taken and then one mechanism is chosen by one
    /// uniform field `u`: pitch adjustment `± u·bw_j` if `u < PAR`, the GA
    /// crossover `α·x^a_j + (1 − α)·x^b_j` with another random harmony `b`
    /// if `u < PAR + p_ga`, the PSO pull `x^a_j + c·φ·(best_j − x^a_j)` if
    /// `u < PAR + p_ga + p_pso`, else the value is kept; otherwise the
    /// variable is uniform in its bounds. The candidate replaces the worst
    /// harmony if it is better.
    #[inline(always)]
    fn per_variable<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        hm: &mut HarmonyMemory,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        widths: &[f64],
        bw: &mut [f64],
    ) {
        let bounds = eval.bounds();
        let dim = bounds.len();
        let mut candidate = vec![0.0; dim];
        let hmcr = Field21::threshold(self.hmcr);
        let t_pa = Field21::threshold(self.par);
        let t_ga = Field21::threshold(self.par + self.p_ga);
        let t_pso = Field21::threshold(self.par + self.p_ga + self.p_pso);
        let mut words = [0u64; 3 * CHUNK];
        while eval.remaining() > 0 {
            if self.bandwidth.decay {
                self.bandwidth.scale(eval.progress(), widths, bw);
            }
            let best = hm.harmony(hm.best());
            for start in (0..dim).step_by(CHUNK) {
                let end = (start + CHUNK).min(dim);
                let words = &mut words[..3 * (end - start)];
                rng.words(words);
                match self.policy {
                    BoundPolicy::Clip => self.per_variable_block(
                        hm,
                        best,
                        start,
                        words,
                        bounds,
                        bw,
                        &mut candidate,
                        [hmcr, t_pa, t_ga, t_pso],
                        clamp,
                    ),
                    BoundPolicy::Reflect => self.per_variable_block(
                        hm,
                        best,
                        start,
                        words,
                        bounds,
                        bw,
                        &mut candidate,
                        [hmcr, t_pa, t_ga, t_pso],
                        Bounds::reflect,
                    ),
                }
            }
            let v = eval.evaluate(&candidate);
            hm.consider(&candidate, v);
        }
    }

    /// The per-variable scheme on variables `start..start + words.len()/3`.
    /// Each variable reads three words: the HMCR trial, memory index and
    /// mechanism field `u`; the variate of the uniform draw, the pitch
    /// adjustment, the crossover's α or the pull's φ (one of them is used);
    /// and the index of the crossover's second harmony. Every mechanism is
    /// computed and one is kept by masks.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn per_variable_block(
        &self,
        hm: &HarmonyMemory,
        best: &[f64],
        start: usize,
        words: &[u64],
        bounds: &[Bounds],
        bw: &[f64],
        candidate: &mut [f64],
        [hmcr, t_pa, t_ga, t_pso]: [u64; 4],
        repair: impl Fn(Bounds, f64) -> f64,
    ) {
        let hms = hm.len();
        for (w, j) in words.chunks_exact(3).zip(start..) {
            let [consider, pick, choose] = Field21::split(w[0]);
            let u = unit_of(w[1]);
            let b = bounds[j];
            let v = hm.get(Field21::index(pick, hms), j);
            let other = hm.get(Field21::index(w[2] & Field21::MASK, hms), j);
            let adjusted = repair(b, v + bw[j] * (2.0 * u - 1.0));
            let crossed = clamp(b, u * v + (1.0 - u) * other);
            let pulled = repair(b, v + self.c * u * (best[j] - v));
            let kept = select(
                choose < t_pa,
                adjusted,
                select(choose < t_ga, crossed, select(choose < t_pso, pulled, v)),
            );
            let fresh = clamp(b, b.lower + u * b.width());
            candidate[j] = select(consider < hmcr, kept, fresh);
        }
    }
}
