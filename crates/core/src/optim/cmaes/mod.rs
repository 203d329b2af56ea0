//! CMA-ES with restarts: the covariance matrix adaptation evolution strategy
//! (Hansen & Ostermeier 2001, "Completely derandomized self-adaptation in
//! evolution strategies", Evol. Comput. 9(2):159–195) with the rank-μ
//! update and the default parameters of Hansen (2016, "The CMA evolution
//! strategy: a tutorial", arXiv:1604.00772), restarted with an increasing
//! population, IPOP (Auger & Hansen 2005, "A restart CMA evolution strategy
//! with increasing population size", Proc. IEEE CEC 2005, 1769–1776), or
//! with two interlaced population regimes, BIPOP (Hansen 2009,
//! "Benchmarking a BI-population CMA-ES on the BBOB-2009 function testbed",
//! GECCO 2009 workshop, 2389–2396).
//!
//! # One generation
//!
//! The search runs in the unit box: variable `j` is `x_j = L_j + u_j·(U_j −
//! L_j)` with `u ∈ [0, 1]ⁿ`, so one step size `σ` (a fraction of each
//! range) suits variables of any scale; this is CMA-ES started with the
//! covariance `diag((U_j − L_j)²)` in the problem's coordinates. With mean
//! `m`, step size `σ`, covariance `C = B D² Bᵀ` (`B` orthonormal
//! eigenvectors, `D` the square roots of the eigenvalues) and paths `p_σ`,
//! `p_c` (tutorial, Section 4 and Appendix A):
//!
//! * sampling: `z_k ~ N(0, I)`, `y_k = B D z_k`, `u_k = m + σ y_k`,
//!   `k = 1…λ`, each `u_k` repaired into the box (below);
//! * recombination: the `μ = ⌊λ/2⌋` best, `⟨y⟩_w = Σ_{i≤μ} w_i y_{i:λ}`,
//!   `m ← m + σ⟨y⟩_w` (learning rate `c_m = 1`);
//! * step-size control (CSA): `p_σ ← (1 − c_σ) p_σ + √(c_σ(2 − c_σ)μ_eff)
//!   C^{−1/2}⟨y⟩_w` with `C^{−1/2} = B D⁻¹ Bᵀ`, then
//!   `σ ← σ·exp((c_σ/d_σ)(‖p_σ‖/E‖N(0,I)‖ − 1))`;
//! * `h_σ = 1` if `‖p_σ‖/√(1 − (1 − c_σ)^{2(g+1)}) < (1.4 + 2/(n+1))
//!   E‖N(0,I)‖`, else 0 (`g` counts the generations of the run from 0);
//! * `p_c ← (1 − c_c) p_c + h_σ √(c_c(2 − c_c)μ_eff) ⟨y⟩_w`;
//! * rank-one and rank-μ update: `C ← (1 + c_1 δ(h_σ) − c_1 − c_μ Σw_j) C +
//!   c_1 p_c p_cᵀ + c_μ Σ_{i≤λ} w°_i y_{i:λ} y_{i:λ}ᵀ` with
//!   `δ(h_σ) = (1 − h_σ) c_c (2 − c_c)`, `w°_i = w_i` for `w_i ≥ 0` and
//!   `w°_i = w_i n/‖C^{−1/2} y_{i:λ}‖²` for the negative weights of the
//!   active update (Jastrebski & Arnold 2006, "Improving evolution
//!   strategies through active covariance matrix adaptation", Proc. IEEE
//!   CEC 2006, 2814–2821; the tutorial's eq. (46)–(47));
//! * flat fitness: if `f(u_{1:λ}) = f(u_{⌈0.7λ⌉:λ})`, `σ ← σ·exp(0.2 +
//!   c_σ/d_σ)` (Appendix B.4, with the factor of the tutorial's
//!   `purecmaes.m`).
//!
//! `B` and `D` are recomputed as in the tutorial's code, once more than
//! `λ/(c_1 + c_μ)/n/10` evaluations have passed since the last
//! eigendecomposition, i.e. every `⌊1/(10 n (c_1 + c_μ))⌋ + 1` generations,
//! which keeps the cost per sampled point `O(n²)` (Householder
//! tridiagonalisation and implicit QL, [`crate::linalg::symmetric_eigen`]).
//! Only the upper triangle of `C` is updated and decomposed. At the
//! default λ this is every generation for `n ≤ 30`, and the decomposition
//! is then most of the cost of a generation (about 55 µs of a 30 × 30
//! matrix against λ = 14 samples). The parameter `eigen_gap` multiplies the
//! gap (pycma's `updatecovwait` sets it in generations instead): between
//! decompositions the samples are drawn from the `B` and `D` of the last
//! one while `C` keeps learning, and the next decomposition catches up.
//! `eigen_gap = 1` is the tutorial's schedule, bit for bit; the default,
//! [`EIGEN_GAP_DEFAULT`] = 5, is the `cmaes` crate's `0.5·λ/((c_1 + c_μ)
//! n)` evaluations, chosen by measurement among 5, 10 and 20: on bbob each
//! needs the same evaluations to `10⁻⁸` as the tutorial's (median ratio
//! over the functions 1.00, 1.00 and 1.03 at D = 10, 1.02, 0.99 and 0.97
//! at D = 20; `tests/optimisers/cmaes_parity.rs`), but between decompositions `C`
//! changes by about `(c_1 + c_μ)` per generation, `eigen_gap/(10n)` of
//! itself over a gap, so that at small `n` the active update's negative
//! weights, normalised with the last decomposition, can make `C`
//! indefinite: at 10 a run on Sphere-2 ends on `Numerics`, at 5 none of
//! the tests does; 20 also loses the parity with pycma on f9 (1.15 times
//! its median). On Sphere-30 in runs of 2·10⁴ evaluations gap 5 costs 0.62
//! of the tutorial's CPU time per evaluation, gap 10 0.81 of gap 5's.
//!
//! # Defaults (the tutorial's Table 1)
//!
//! `λ = 4 + ⌊3 ln n⌋`; `w_i ∝ ln((λ+1)/2) − ln i` for `i ≤ μ`, summing
//! to 1, `μ_eff = 1/Σw_i²`; with `covariance = "active"` (the default, as
//! pycma's) the ranks `i > μ` enter the update of `C` with the negative
//! weights of the tutorial's Table 1 ([`Strategy::cov_weights`]), with
//! `"positive"` they do not (the IPOP-CMA-ES of Auger & Hansen 2005; no
//! mirrored sampling either way);
//! `c_σ = (μ_eff + 2)/(n + μ_eff + 5)`;
//! `d_σ = 1 + 2 max(0, √((μ_eff − 1)/(n + 1)) − 1) + c_σ`;
//! `c_c = (4 + μ_eff/n)/(n + 4 + 2μ_eff/n)`;
//! `c_1 = 2/((n + 1.3)² + μ_eff)`;
//! `c_μ = min(1 − c_1, 2(μ_eff − 2 + 1/μ_eff)/((n + 2)² + μ_eff))`;
//! `E‖N(0,I)‖ ≈ √n (1 − 1/(4n) + 1/(21n²))` ([`Strategy`]). The initial
//! mean is uniform in the box and `σ₀ = 0.3` of each range: the tutorial's
//! advice for an optimum expected in `[a, b]ⁿ` is `m` uniform in the box and
//! `σ₀ = 0.3(b − a)`. BBOB's usual start (pycma's BBOB scripts; Hansen
//! 2009) is `σ₀ = 2` and `m` uniform in `[−4, 4]ⁿ` on `[−5, 5]ⁿ`: `sigma0 =
//! 0.2` with `x0 = "central"` ([`InitialMean`]).
//!
//! # Bounds
//!
//! A sample that leaves the unit box is repaired coordinate by coordinate
//! with the run's [`BoundPolicy`]: `clip` projects onto the box, `reflect`
//! mirrors at the violated face. The repaired point is evaluated and also
//! used in the update (a "Lamarckian" repair, one of the options of the
//! tutorial's Appendix B.5 on boundaries and constraints): its step becomes `y_k = (u_k −
//! m)/σ`, shortened, if its Mahalanobis length `‖D⁻¹Bᵀy_k‖` exceeds
//! `√n + 2n/(n + 2)`, to that length, as Hansen (2011, "Injecting external
//! solutions into CMA-ES", arXiv:1110.4181) prescribes for solutions that
//! were not drawn from the distribution (pycma's `repair_genotype`). The
//! mean, a convex combination of repaired points, stays in the box, and no
//! evaluation is ever outside it.
//!
//! # Termination and restarts
//!
//! A run ends, and the next starts with what is left of the budget, when any
//! of the tutorial's criteria (Appendix B.3) fires after a generation:
//!
//! * `tolfun`: the range of the best values of the last `10 + ⌈30n/λ⌉`
//!   generations and of all values of the current one is below `10⁻¹²`;
//! * `equalfunvals`: the range of those best values is zero;
//! * `tolx`: `σ·max(|p_c,j|, √C_jj) < 10⁻¹²·σ₀` for every `j`;
//! * `noeffectaxis`: adding `0.1σ D_ii b_i` (axis `i = g mod n`) leaves
//!   `m` unchanged;
//! * `noeffectcoord`: adding `0.2σ√C_jj` to some `m_j` leaves it unchanged;
//! * `conditioncov`: the condition number of `C` exceeds `10¹⁴`;
//! * `stagnation`: over the last 20 % of the generations (at least `120 +
//!   ⌈30n/λ⌉`, at most 20 000), the median of the most recent 30 % of the
//!   generations' best values and that of their medians are no better than
//!   those of the first 30 % (checked every `⌈window/40⌉` generations, to
//!   keep the check's cost per generation constant);
//!
//! and on numerical failure: every value of a generation infinite or NaN
//! (nothing to rank), a non-finite or non-positive-definite `C`, or `σ·max D`
//! above `10²⁰·σ₀` (pycma's `tolupsigma`). The restart schemes
//! ([`Restarts`]) are:
//!
//! * `ipop` (Auger & Hansen 2005): restart `r` uses `λ_r = ⌊λ_def ·
//!   inc_popsize^r⌋` with `σ₀` and a new uniform mean;
//! * `bipop` (Hansen 2009, with the accounting of pycma's `fmin`): the
//!   first run uses `λ_def` and its evaluations count as the small regime's;
//!   each restart then runs the regime that has used fewer evaluations so
//!   far. A large-regime run is the next IPOP run, `λ = ⌊λ_def ·
//!   inc_popsize^k⌋` for the `k`-th large run, with `σ₀`. A small-regime run
//!   draws `U_σ, U_λ ~ U(0, 1)` and uses `σ = σ₀·10^{−2U_σ}`,
//!   `λ_s = ⌊λ_def·(λ_l/λ_def)^{U_λ²}⌋` (`λ_l` the population of the latest
//!   large run, `λ_def` before any), and stops after half the evaluations
//!   the large regime has used so far. Hansen (2009) states the step size
//!   for his BBOB default `σ₀ = 2` on `[−5, 5]ⁿ`, as `2·10^{−2U}`; `λ_l`
//!   is computed as in pycma's `fmin`, where the paper writes `½λ_l` with
//!   `λ_l` the doubled population of the next large run;
//! * `none`: independent restarts with `λ_def` and `σ₀`.
//!
//! `λ_def` is the `lambda` parameter, or `4 + ⌊3 ln n⌋` when it is 0, and
//! `λ` never exceeds [`LAMBDA_MAX`]. pycma ends after nine IPOP restarts;
//! here the runs go on until the budget is spent, as every optimiser of the
//! crate does. A generation the budget cannot complete samples and
//! evaluates only the points that are left.
//!
//! # Random numbers
//!
//! Everything is drawn from the caller's generator, in this order: at the
//! start of each run, for a BIPOP small-regime run `U_σ` then `U_λ`, then
//! the `n` coordinates of the mean ([`Draw::unit`] each); in each
//! generation the `n` normal variates of sample 1, then of sample 2, and so
//! on. The normals form one stream per call of [`Optimiser::minimise`]:
//! Marsaglia's polar method (Marsaglia & Bray 1964, "A convenient method
//! for generating normal variables", SIAM Rev. 6(3):260–264) draws pairs
//! `v = 2u − 1` until `0 < s = v₁² + v₂² < 1` and yields `v₁f` then `v₂f`,
//! `f = √(−2 ln s / s)`; a pair's second value is the next normal used, in
//! the next sample, generation or run if need be. The method needs one
//! logarithm per two normals, where Box–Muller ([`Draw::gaussian`]) needs a
//! logarithm and a cosine per normal.
//!
//! # Why not a crate
//!
//! This is implemented from the papers rather than with the `cmaes` crate:
//! that crate draws from its own random generator (so runs could not follow
//! a campaign's derived seeds, nor be reproduced bit for bit from them),
//! does its linear algebra with `nalgebra` (whose decompositions are not
//! documented to give the same bits on every vector instruction set), and
//! is not built to stop at an exact evaluation count in mid-generation or
//! to repair samples with this crate's bound policies. The loops here are
//! plain `f64` code in a fixed order of operations, compiled for the CPU
//! by [`dispatch`] like the other optimisers, and give the same bits on
//! every [`crate::simd::Simd`] level; the state lives in the call, so runs
//! on any number of threads are identical.

use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{policy_param, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::optim::params::Param;
use crate::problem::{BoundPolicy, Problem};
use crate::rng::{Draw, Words};
use crate::simd::dispatch;

mod run;
mod strategy;
#[cfg(test)]
mod tests;

use run::{Setup, Work};
pub use strategy::{Covariance, RunRecord, Stop, Strategy};

/// The largest population size a run uses: IPOP's growth stops there
/// (and `lambda` admits no more), the largest population any optimiser of
/// the crate admits.
pub const LAMBDA_MAX: usize = 100_000;

/// `tolfun`: the range of recent best values below which a run ends.
pub const TOL_FUN: f64 = 1e-12;

/// `tolx`, relative to the run's `σ₀`.
pub const TOL_X: f64 = 1e-12;

/// `conditioncov`: the condition number of `C` at which a run ends.
pub const TOL_CONDITION: f64 = 1e14;

/// `tolupsigma`: `σ·max D` relative to `σ₀` at which a run ends as diverged.
pub const TOL_UP_SIGMA: f64 = 1e20;

/// The longest history the `stagnation` criterion looks at, in generations.
pub const STAGNATION_MAX: usize = 20_000;

/// How a run that has ended is followed up.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Restarts {
    /// IPOP: each restart multiplies λ by `inc_popsize`.
    Ipop,
    /// BIPOP: IPOP runs interlaced with small-population runs of random λ
    /// and σ₀.
    Bipop,
    /// Independent restarts, all with the first run's λ and σ₀.
    None,
}

impl Restarts {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["ipop", "bipop", "none"];

    /// Parses a spec name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "ipop" => Some(Self::Ipop),
            "bipop" => Some(Self::Bipop),
            "none" => Some(Self::None),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// Where the mean of a run is drawn, in each variable's range `[L, U]`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InitialMean {
    /// Uniform in `[L, U]` (the tutorial's advice for an optimum expected
    /// in the box).
    Uniform,
    /// Uniform in the central 80 %, `[L + 0.1(U − L), U − 0.1(U − L)]`:
    /// `[−4, 4]ⁿ` on bbob's `[−5, 5]ⁿ`, the start of pycma's and Hansen's
    /// (2009) BBOB experiments.
    Central,
}

impl InitialMean {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["uniform", "central"];

    /// Parses a spec name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "uniform" => Some(Self::Uniform),
            "central" => Some(Self::Central),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// CMA-ES with IPOP, BIPOP or independent restarts (see the module docs
/// for the algorithm, its defaults and its sources).
#[derive(Clone, Debug, PartialEq)]
pub struct CmaEs {
    /// The restart scheme.
    pub restarts: Restarts,
    /// The first run's population size `λ_def`; 0 means `4 + ⌊3 ln n⌋`.
    pub lambda: usize,
    /// The initial step size `σ₀`, as a fraction of each variable's range.
    pub sigma0: f64,
    /// The factor by which a restart multiplies λ (IPOP, BIPOP's large
    /// regime).
    pub inc_popsize: f64,
    /// The multiple of the tutorial's gap between eigendecompositions of
    /// `C` (1 = the tutorial's `λ/(c_1 + c_μ)/n/10` evaluations).
    pub eigen_gap: f64,
    /// Active (the default) or positive-only covariance update.
    pub covariance: Covariance,
    /// Where each run's mean is drawn.
    pub x0: InitialMean,
    /// Bound handling of samples outside the box.
    pub policy: BoundPolicy,
}

/// The key of the `lambda` parameter.
pub const LAMBDA_KEY: Param<u64> = Param::new("lambda");
/// The key of the `restarts` parameter.
pub const RESTARTS_KEY: Param<&'static str> = Param::new("restarts");
/// The key of the `sigma0` parameter.
pub const SIGMA0_KEY: Param<f64> = Param::new("sigma0");
/// The key of the `inc_popsize` parameter.
pub const INC_POPSIZE_KEY: Param<f64> = Param::new("inc_popsize");
/// The key of the `eigen_gap` parameter.
pub const EIGEN_GAP_KEY: Param<f64> = Param::new("eigen_gap");
/// The key of the `covariance` parameter.
pub const COVARIANCE_KEY: Param<&'static str> = Param::new("covariance");
/// The key of the `x0` parameter.
pub const X0_KEY: Param<&'static str> = Param::new("x0");

/// The default of `eigen_gap`: 5 times the tutorial's gap, the `cmaes`
/// crate's `0.5·λ/((c_1 + c_μ) n)` evaluations between
/// eigendecompositions, chosen by measurement (module docs).
pub const EIGEN_GAP_DEFAULT: f64 = 5.0;

/// The parameters of [`CmaEs`]. The defaults are the tutorial's (Hansen
/// 2016: λ from Table 1, `σ₀ = 0.3` of the range) and IPOP's factor 2
/// (Auger & Hansen 2005).
pub static PARAMS: [ParamDef; 8] = [
    ParamDef {
        name: RESTARTS_KEY.name,
        doc: "restart scheme: \"ipop\" (λ × inc_popsize at each restart), \"bipop\" (IPOP interlaced with small-population runs) or \"none\" (independent restarts)",
        kind: Kind::Choice(&Restarts::NAMES),
        default: Setting::Choice("ipop"),
        omit_at_default: false,
    },
    ParamDef {
        name: LAMBDA_KEY.name,
        doc: "population size λ of the first run, at least 2; 0 = 4 + ⌊3 ln D⌋ (Hansen 2016)",
        kind: Kind::Count {
            min: 0,
            max: LAMBDA_MAX as u64,
        },
        default: Setting::Count(0),
        omit_at_default: false,
    },
    ParamDef {
        name: SIGMA0_KEY.name,
        doc: "initial step size σ₀, as a fraction of each variable's range",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.3),
        omit_at_default: false,
    },
    ParamDef {
        name: INC_POPSIZE_KEY.name,
        doc: "factor by which each IPOP restart multiplies λ",
        kind: Kind::Real {
            min: 1.0,
            max: 10.0,
            open_min: true,
        },
        default: Setting::Real(2.0),
        omit_at_default: false,
    },
    ParamDef {
        name: EIGEN_GAP_KEY.name,
        doc: "multiple of the tutorial's gap between eigendecompositions of C, λ/(c1 + cμ)/D/10 evaluations (Hansen 2016); 1 = the tutorial, larger is cheaper per evaluation and staler",
        kind: Kind::Real {
            min: 1.0,
            max: 1000.0,
            open_min: false,
        },
        default: Setting::Real(EIGEN_GAP_DEFAULT),
        omit_at_default: true,
    },
    ParamDef {
        name: COVARIANCE_KEY.name,
        doc: "covariance update: \"active\" (negative weights for the λ − μ worst steps; Jastrebski & Arnold 2006, Hansen 2016, pycma's default) or \"positive\" (the μ best only, the IPOP-CMA-ES of Auger & Hansen 2005)",
        kind: Kind::Choice(&Covariance::NAMES),
        default: Setting::Choice("active"),
        omit_at_default: true,
    },
    ParamDef {
        name: X0_KEY.name,
        doc: "where each run's mean is drawn: \"uniform\" in the box, or \"central\", uniform in the central 80 % of each range ([−4, 4]^D on bbob, with sigma0 = 0.2 BBOB's usual start)",
        kind: Kind::Choice(&InitialMean::NAMES),
        default: Setting::Choice("uniform"),
        omit_at_default: true,
    },
    BOUNDS_PARAM,
];

impl Default for CmaEs {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl CmaEs {
    /// Builds CMA-ES from validated parameters; `lambda = 1` is refused.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let lambda = p.get(LAMBDA_KEY) as usize;
        if lambda == 1 {
            return Err(ParamError::new(
                "lambda",
                "λ must be at least 2 (or 0 for 4 + ⌊3 ln D⌋), found 1".into(),
            ));
        }
        Ok(Self {
            restarts: Restarts::from_name(p.get(RESTARTS_KEY)).unwrap_or(Restarts::Ipop),
            lambda,
            sigma0: p.get(SIGMA0_KEY),
            inc_popsize: p.get(INC_POPSIZE_KEY),
            eigen_gap: p.get(EIGEN_GAP_KEY),
            covariance: Covariance::from_name(p.get(COVARIANCE_KEY)).unwrap_or(Covariance::Active),
            x0: InitialMean::from_name(p.get(X0_KEY)).unwrap_or(InitialMean::Uniform),
            policy: policy_param(p),
        })
    }

    /// The tutorial's default population size `4 + ⌊3 ln n⌋` (4 for
    /// `n ≤ 1`).
    pub fn default_lambda(n: usize) -> usize {
        if n <= 1 {
            4
        } else {
            4 + (3.0 * (n as f64).ln()).floor() as usize
        }
    }

    /// The first run's population size `λ_def` at dimension `n`.
    pub fn base_lambda(&self, n: usize) -> usize {
        if self.lambda == 0 {
            Self::default_lambda(n)
        } else {
            self.lambda
        }
        .min(LAMBDA_MAX)
    }

    /// `⌊λ_def · inc_popsize^k⌋`, at most [`LAMBDA_MAX`]: the `k`-th IPOP
    /// restart's population.
    pub fn grown_lambda(&self, base: usize, k: u32) -> usize {
        let grown = (base as f64 * self.inc_popsize.powi(k.min(i32::MAX as u32) as i32)).floor();
        grown.min(LAMBDA_MAX as f64) as usize
    }

    /// Minimises like [`Optimiser::minimise`] and returns a record of each
    /// run (population, step size, evaluations, why it ended).
    pub fn minimise_recorded<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) -> Vec<RunRecord> {
        let mut log = Vec::new();
        dispatch(
            #[inline(always)]
            |_| self.restart_loop(eval, rng, Some(&mut log)),
        );
        log
    }
}

impl CmaEs {
    /// The restarts until the budget is spent: the body of
    /// [`Optimiser::minimise`], compiled for the CPU by [`dispatch`].
    #[inline(always)]
    fn restart_loop<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        mut log: Option<&mut Vec<RunRecord>>,
    ) {
        let n = eval.dim();
        if n == 0 {
            // Nothing to adapt: spend the budget on the only point there is.
            while eval.remaining() > 0 {
                eval.evaluate(&[]);
            }
            return;
        }
        let base = self.base_lambda(n);
        let mut work = Work::new(n);
        let mut large_runs = 0u32;
        let (mut small_evals, mut large_evals) = (0u64, 0u64);
        let mut first = true;
        while eval.remaining() > 0 {
            let mut setup = Setup {
                lambda: base,
                sigma0: self.sigma0,
                limit: u64::MAX,
                eigen_gap: self.eigen_gap,
                covariance: self.covariance,
                x0: self.x0,
            };
            let mut small = false;
            match self.restarts {
                Restarts::None => {}
                Restarts::Ipop => {
                    if !first {
                        large_runs = large_runs.saturating_add(1);
                        setup.lambda = self.grown_lambda(base, large_runs);
                    }
                }
                Restarts::Bipop => {
                    if first {
                        small = true;
                    } else if small_evals < large_evals {
                        small = true;
                        let u_sigma = rng.unit();
                        let u_lambda = rng.unit();
                        setup.sigma0 = self.sigma0 * 10f64.powf(-2.0 * u_sigma);
                        let ratio = self.grown_lambda(base, large_runs) as f64 / base as f64;
                        let lambda = (base as f64 * ratio.powf(u_lambda * u_lambda)).floor();
                        setup.lambda = (lambda as usize).clamp(2, LAMBDA_MAX);
                        setup.limit = large_evals.div_ceil(2);
                    } else {
                        large_runs = large_runs.saturating_add(1);
                        setup.lambda = self.grown_lambda(base, large_runs);
                    }
                }
            }
            first = false;
            let before = eval.used();
            let (generations, stop) = work.run(eval, rng, setup, self.policy);
            let spent = eval.used() - before;
            if small {
                small_evals += spent;
            } else {
                large_evals += spent;
            }
            if let Some(log) = log.as_deref_mut() {
                log.push(RunRecord {
                    lambda: setup.lambda,
                    sigma0: setup.sigma0,
                    small,
                    evaluations: spent,
                    generations,
                    stop,
                });
            }
        }
    }
}

impl Optimiser for CmaEs {
    /// The covariance matrix and its eigenvectors (2 D²), the sampled and
    /// mapped populations (2 λ D) and four words per sample at the largest λ a restart can reach
    /// within the budget (IPOP and BIPOP multiply λ by `inc_popsize` up to
    /// [`LAMBDA_MAX`]; the run before a restart spent at least one
    /// generation, λ / inc_popsize evaluations, so λ ≤ inc_popsize · budget),
    /// and a few D-vectors. An upper bound: runs that converge slowly never
    /// reach it.
    fn state_bytes(&self, dim: usize, budget: u64) -> u128 {
        let base = self.base_lambda(dim);
        let lambda = match self.restarts {
            Restarts::None => base,
            _ => {
                let reach = (budget as f64 * self.inc_popsize).max(base as f64);
                let cap = (LAMBDA_MAX as f64).min(reach);
                let mut l = base as f64;
                while l * self.inc_popsize <= cap && self.inc_popsize > 1.0 {
                    l *= self.inc_popsize;
                }
                l as usize
            }
        };
        let d = dim as u128;
        // Per sample also an order index, a Mahalanobis length and a
        // coefficient of the rank-μ update (8 + 8 + 16 bytes).
        2 * d * d * 8 + super::vectors_bytes(2 * lambda + 16, dim) + 32 * lambda as u128
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        dispatch(
            #[inline(always)]
            |_| self.restart_loop(eval, rng, None),
        )
    }
}
