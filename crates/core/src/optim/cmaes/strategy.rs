//! The strategy parameters of one run (Hansen 2016, "The CMA evolution
//! strategy: a tutorial", arXiv:1604.00772, Table 1), with the negative
//! recombination weights of the active covariance update (Jastrebski &
//! Arnold 2006, "Improving evolution strategies through active covariance
//! matrix adaptation", Proc. IEEE CEC 2006, 2814–2821; the tutorial's
//! Table 1 and eq. (46)–(47)), and the records a run leaves.

/// How `C` learns from a generation's ranked steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Covariance {
    /// Active CMA-ES (Jastrebski & Arnold 2006; Hansen 2016, Table 1): the
    /// `λ − μ` worst steps enter the rank-μ update with negative weights,
    /// pycma's default.
    Active,
    /// The positive weights of the `μ` best steps only (Hansen &
    /// Ostermeier 2001; Auger & Hansen 2005's IPOP-CMA-ES).
    Positive,
}

impl Covariance {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["active", "positive"];

    /// Parses a spec name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "active" => Some(Self::Active),
            "positive" => Some(Self::Positive),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

/// The strategy parameters of one run: the tutorial's Table 1 for
/// dimension `n` and population `λ`.
#[derive(Clone, Debug, PartialEq)]
pub struct Strategy {
    /// Population size λ.
    pub lambda: usize,
    /// Number of parents `μ = ⌊λ/2⌋`.
    pub mu: usize,
    /// Recombination weights `w_1 ≥ … ≥ w_μ > 0`, summing to 1: the mean
    /// moves by `Σ_{i≤μ} w_i y_{i:λ}`.
    pub weights: Vec<f64>,
    /// The weights of the rank-μ update of `C`, one per rank `i ≤ λ`: the
    /// positive `w_i` of [`Strategy::weights`], then, for active CMA-ES,
    /// `w_i = α⁻ w'_i / Σ_{j>μ} |w'_j| ≤ 0` for `i > μ`, with `w'_i =
    /// ln((λ+1)/2) − ln i` and `α⁻ = min(1 + c_1/c_μ, 1 + 2μ_eff⁻/(μ_eff +
    /// 2), (1 − c_1 − c_μ)/(n c_μ))`, `μ_eff⁻ = (Σ_{j>μ} w'_j)²/Σ_{j>μ} w'_j²`
    /// (Hansen 2016, Table 1). Only the positive ones for
    /// [`Covariance::Positive`].
    pub cov_weights: Vec<f64>,
    /// `Σ_{i≤λ} w_i` of [`Strategy::cov_weights`]: 1, or `1 − α⁻` with the
    /// active update (the decay of `C` is `1 − c_1 − c_μ Σ w_i`).
    pub cov_weight_sum: f64,
    /// Variance-effective selection mass `μ_eff = 1/Σw_i²`.
    pub mueff: f64,
    /// Learning rate of the step-size path `c_σ`.
    pub cs: f64,
    /// Step-size damping `d_σ`.
    pub ds: f64,
    /// Learning rate of the covariance path `c_c`.
    pub cc: f64,
    /// Rank-one learning rate `c_1`.
    pub c1: f64,
    /// Rank-μ learning rate `c_μ`.
    pub cmu: f64,
    /// `E‖N(0, I)‖ ≈ √n (1 − 1/(4n) + 1/(21n²))`.
    pub chi_n: f64,
    /// Evaluations after which `B` and `D` are recomputed,
    /// `λ/(c_1 + c_μ)/n/10`.
    pub eigen_gap: f64,
}

impl Strategy {
    /// Table 1 for dimension `n ≥ 1` and population `λ ≥ 2`.
    pub fn new(n: usize, lambda: usize, covariance: Covariance) -> Self {
        let nf = n as f64;
        let mu = (lambda / 2).max(1);
        let top = ((lambda as f64 + 1.0) / 2.0).ln();
        let mut weights: Vec<f64> = (1..=mu).map(|i| top - (i as f64).ln()).collect();
        let sum: f64 = weights.iter().sum();
        for w in &mut weights {
            *w /= sum;
        }
        let mueff = 1.0 / weights.iter().map(|w| w * w).sum::<f64>();
        let cs = (mueff + 2.0) / (nf + mueff + 5.0);
        let ds = 1.0 + 2.0 * (((mueff - 1.0) / (nf + 1.0)).sqrt() - 1.0).max(0.0) + cs;
        let cc = (4.0 + mueff / nf) / (nf + 4.0 + 2.0 * mueff / nf);
        let c1 = 2.0 / ((nf + 1.3) * (nf + 1.3) + mueff);
        let cmu =
            (1.0 - c1).min(2.0 * (mueff - 2.0 + 1.0 / mueff) / ((nf + 2.0) * (nf + 2.0) + mueff));
        let chi_n = nf.sqrt() * (1.0 - 1.0 / (4.0 * nf) + 1.0 / (21.0 * nf * nf));
        let mut cov_weights = weights.clone();
        let mut cov_weight_sum = 1.0;
        if covariance == Covariance::Active {
            let raw: Vec<f64> = (mu + 1..=lambda).map(|i| top - (i as f64).ln()).collect();
            let neg_sum: f64 = raw.iter().map(|w| w.abs()).sum();
            let neg_sq: f64 = raw.iter().map(|w| w * w).sum();
            if neg_sum > 0.0 && cmu > 0.0 {
                let mueff_neg = neg_sum * neg_sum / neg_sq;
                let alpha = (1.0 + c1 / cmu)
                    .min(1.0 + 2.0 * mueff_neg / (mueff + 2.0))
                    .min((1.0 - c1 - cmu) / (nf * cmu));
                cov_weights.extend(raw.iter().map(|w| alpha * w / neg_sum));
                cov_weight_sum = 1.0 + cov_weights[mu..].iter().sum::<f64>();
            }
        }
        Self {
            lambda,
            mu,
            weights,
            cov_weights,
            cov_weight_sum,
            mueff,
            cs,
            ds,
            cc,
            c1,
            cmu,
            chi_n,
            eigen_gap: lambda as f64 / (c1 + cmu) / nf / 10.0,
        }
    }
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// The evaluation budget is spent.
    Budget,
    /// `tolfun`.
    TolFun,
    /// `equalfunvals`.
    EqualFunValues,
    /// `tolx`.
    TolX,
    /// `noeffectaxis`.
    NoEffectAxis,
    /// `noeffectcoord`.
    NoEffectCoord,
    /// `conditioncov`.
    ConditionCov,
    /// `stagnation`.
    Stagnation,
    /// `tolupsigma`.
    TolUpSigma,
    /// Every value of a generation was infinite or NaN.
    NoFiniteValue,
    /// `C` was not finite and positive definite, or `σ` not finite.
    Numerics,
    /// A BIPOP small-regime run used its share of the budget.
    RunBudget,
}

/// What one run of a [`super::CmaEs::minimise_recorded`] call did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunRecord {
    /// Its population size λ.
    pub lambda: usize,
    /// Its initial step size, as a fraction of the ranges.
    pub sigma0: f64,
    /// Whether it belongs to BIPOP's small regime.
    pub small: bool,
    /// The evaluations it used.
    pub evaluations: u64,
    /// Its generations, the last partial one included.
    pub generations: u64,
    /// Why it ended.
    pub stop: Stop,
}
