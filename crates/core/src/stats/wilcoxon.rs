//! Wilcoxon signed-rank test for paired samples (Wilcoxon 1945), following
//! `scipy.stats.wilcoxon` with its defaults (`zero_method="wilcox"`,
//! `correction=False`, `method="auto"`); the continuity-corrected variant
//! (`correction=True`) is [`wilcoxon_signed_rank_with`].

use statrs::distribution::{ContinuousCDF, Normal};

use super::error::{check_no_nan, check_non_empty, StatsError};
use super::hypothesis::{Alternative, PValueMethod};
use super::ranks::midranks_into;

/// Largest sample (zeros included) for which SciPy's `method="auto"` may use an
/// exact distribution; larger samples always use the normal approximation.
pub const WILCOXON_EXACT_MAX_N: usize = 50;

/// Largest sample (zeros included) for which SciPy's `method="auto"` uses the
/// exact permutation distribution when there are ties or zero differences.
pub const WILCOXON_PERMUTATION_MAX_N: usize = 13;

/// Result of the Wilcoxon signed-rank test on differences d = x − y: rank sums
/// R⁺ = Σ_{dᵢ>0} rank|dᵢ| and R⁻ = Σ_{dᵢ<0} rank|dᵢ| over the non-zero
/// differences (Wilcoxon 1945, Biometrics Bulletin 1(6):80–83).
#[derive(Clone, Debug, PartialEq)]
pub struct WilcoxonResult {
    /// SciPy's statistic: min(R⁺, R⁻) for a two-sided test, R⁺ for a one-sided one.
    pub statistic: f64,
    /// Sum of the midranks of |d| over the positive differences.
    pub r_plus: f64,
    /// Sum of the midranks of |d| over the negative differences.
    pub r_minus: f64,
    /// The p-value for `alternative`.
    pub p_value: f64,
    /// Number of non-zero differences used (zero differences are dropped).
    pub n: usize,
    /// Number of zero differences dropped.
    pub n_zero: usize,
    /// Standard score (R⁺ − n(n+1)/4)/σ (continuity-corrected if requested),
    /// signed, when the normal approximation was used (SciPy reports −|z| for two-sided tests).
    pub z: Option<f64>,
    /// How the p-value was computed.
    pub method: PValueMethod,
    /// The alternative hypothesis tested.
    pub alternative: Alternative,
}

/// Wilcoxon signed-rank test of paired samples on d = x − y (Wilcoxon 1945,
/// "Individual comparisons by ranking methods", Biometrics Bulletin 1(6):80–83);
/// see [`wilcoxon_signed_rank`] for the method selection, which is SciPy 1.17's.
///
/// Errors on empty input, different lengths or a NaN difference (x or y NaN, or ∞ − ∞).
///
/// ```
/// use metabezier_core::stats::{wilcoxon, Alternative};
///
/// let before = [1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30];
/// let after = [0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29];
/// let r = wilcoxon(&before, &after, Alternative::Greater).unwrap();
/// // Hollander & Wolfe's depression data: exact one-sided p = 0.01953.
/// assert!((r.p_value - 0.019_531_25).abs() < 1e-9);
/// ```
pub fn wilcoxon(
    x: &[f64],
    y: &[f64],
    alternative: Alternative,
) -> Result<WilcoxonResult, StatsError> {
    if x.len() != y.len() {
        return Err(StatsError::LengthMismatch {
            what: "paired samples x and y",
            expected: x.len(),
            found: y.len(),
        });
    }
    let d: Vec<f64> = x.iter().zip(y).map(|(a, b)| a - b).collect();
    check_no_nan(&d, "differences x - y")?;
    wilcoxon_signed_rank(&d, alternative)
}

/// Wilcoxon signed-rank test of differences dᵢ (Wilcoxon 1945, Biometrics
/// Bulletin 1(6):80–83), matching `scipy.stats.wilcoxon(d, alternative=...)`:
/// zeros are dropped, and with N = `d.len()` (zeros included) the p-value is
/// exact if N ≤ 50 without ties or zeros, a sign-flip permutation p-value if
/// N ≤ 13 otherwise, else from the normal approximation with variance
/// [n(n+1)(2n+1) − Σ(t³−t)/2]/24 and no continuity correction (SciPy's default).
///
/// If every difference is zero the result is R⁺ = R⁻ = 0 with p = 1 (SciPy
/// gives p = 1 for N ≤ 13 and NaN above). Errors on an empty slice or a NaN.
pub fn wilcoxon_signed_rank(
    differences: &[f64],
    alternative: Alternative,
) -> Result<WilcoxonResult, StatsError> {
    wilcoxon_signed_rank_with(differences, alternative, false)
}

/// Wilcoxon signed-rank test of differences (Wilcoxon 1945, Biometrics Bulletin
/// 1(6):80–83) as [`wilcoxon_signed_rank`], except that with `continuity_correction`
/// the normal approximation moves R⁺ by ½ towards its mean, like
/// `scipy.stats.wilcoxon(d, correction=True)`; exact p-values are unaffected.
pub fn wilcoxon_signed_rank_with(
    differences: &[f64],
    alternative: Alternative,
    continuity_correction: bool,
) -> Result<WilcoxonResult, StatsError> {
    check_non_empty(differences, "differences")?;
    check_no_nan(differences, "differences")?;
    let n_total = differences.len();
    let nonzero: Vec<f64> = differences.iter().copied().filter(|&v| v != 0.0).collect();
    let n = nonzero.len();
    let n_zero = n_total - n;

    if n == 0 {
        return Ok(WilcoxonResult {
            statistic: 0.0,
            r_plus: 0.0,
            r_minus: 0.0,
            p_value: 1.0,
            n,
            n_zero,
            z: None,
            method: PValueMethod::Permutation,
            alternative,
        });
    }

    let abs: Vec<f64> = nonzero.iter().map(|v| v.abs()).collect();
    let mut order = Vec::with_capacity(n);
    let mut ranks = Vec::with_capacity(n);
    let mut tie_term = 0.0;
    let mut has_ties = false;
    midranks_into(&abs, &mut order, &mut ranks, |t| {
        if t > 1 {
            has_ties = true;
            let t = t as f64;
            tie_term += t * t * t - t;
        }
    });
    let mut r_plus = 0.0;
    let mut r_minus = 0.0;
    for (&v, &r) in nonzero.iter().zip(&ranks) {
        if v > 0.0 {
            r_plus += r;
        } else {
            r_minus += r;
        }
    }

    let method = if n_total > WILCOXON_EXACT_MAX_N {
        PValueMethod::Asymptotic
    } else if !has_ties && n_zero == 0 {
        PValueMethod::Exact
    } else if n_total <= WILCOXON_PERMUTATION_MAX_N {
        PValueMethod::Permutation
    } else {
        PValueMethod::Asymptotic
    };

    let (p_value, z) = match method {
        PValueMethod::Exact | PValueMethod::Permutation => {
            // Work on doubled midranks so that every score is an integer; for the
            // untied exact case the scores are 2, 4, ..., 2n, which gives the
            // same probabilities as 1, ..., n.
            let scores: Vec<usize> = ranks.iter().map(|&r| (2.0 * r).round() as usize).collect();
            let observed: usize = nonzero
                .iter()
                .zip(&scores)
                .filter(|(&v, _)| v > 0.0)
                .map(|(_, &s)| s)
                .sum();
            (sign_flip_p_value(&scores, observed, alternative), None)
        }
        PValueMethod::Asymptotic => {
            let nf = n as f64;
            let mean = nf * (nf + 1.0) / 4.0;
            let se = ((nf * (nf + 1.0) * (2.0 * nf + 1.0) - tie_term / 2.0) / 24.0).sqrt();
            let mut z = (r_plus - mean) / se;
            let sign = match alternative {
                Alternative::Greater => 1.0,
                Alternative::Less => -1.0,
                Alternative::TwoSided => {
                    if z > 0.0 {
                        1.0
                    } else if z < 0.0 {
                        -1.0
                    } else {
                        0.0
                    }
                }
            };
            if continuity_correction {
                z -= sign * 0.5 / se;
            }
            (normal_p_value(z, alternative), Some(z))
        }
    };

    let statistic = match alternative {
        Alternative::TwoSided => r_plus.min(r_minus),
        Alternative::Less | Alternative::Greater => r_plus,
    };
    Ok(WilcoxonResult {
        statistic,
        r_plus,
        r_minus,
        p_value,
        n,
        n_zero,
        z,
        method,
        alternative,
    })
}

/// p-value of a standard normal score for an alternative: Φ(z), 1 − Φ(z) or 2(1 − Φ(|z|)).
pub(crate) fn normal_p_value(z: f64, alternative: Alternative) -> f64 {
    let norm = Normal::standard();
    let p = match alternative {
        Alternative::Less => norm.cdf(z),
        Alternative::Greater => norm.sf(z),
        Alternative::TwoSided => 2.0 * norm.sf(z.abs()),
    };
    p.clamp(0.0, 1.0)
}

/// Exact p-value of S = Σ_{i: sᵢ = +} scoreᵢ under independent fair sign flips,
/// by the counting recursion c_k(s) = c_{k−1}(s) + c_{k−1}(s − score_k).
///
/// Exact in integers; the number of scores is at most [`WILCOXON_EXACT_MAX_N`].
fn sign_flip_p_value(scores: &[usize], observed: usize, alternative: Alternative) -> f64 {
    let max_sum: usize = scores.iter().sum();
    let mut counts = vec![0u64; max_sum + 1];
    counts[0] = 1;
    let mut reach = 0;
    for &s in scores {
        reach += s;
        for k in (s..=reach).rev() {
            counts[k] += counts[k - s];
        }
    }
    let total = (scores.len() as f64).exp2();
    let observed = observed.min(max_sum);
    let le: u64 = counts[..=observed].iter().sum();
    let ge: u64 = counts[observed..].iter().sum();
    let p_less = le as f64 / total;
    let p_greater = ge as f64 / total;
    let p = match alternative {
        Alternative::Less => p_less,
        Alternative::Greater => p_greater,
        Alternative::TwoSided => 2.0 * p_less.min(p_greater),
    };
    p.clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two-sided sign-flip p-value by enumerating all 2^n sign vectors.
    fn brute_force(scores: &[usize], observed: usize) -> (f64, f64) {
        let n = scores.len();
        let (mut le, mut ge) = (0u64, 0u64);
        for mask in 0u32..(1 << n) {
            let s: usize = (0..n)
                .filter(|b| mask >> b & 1 == 1)
                .map(|b| scores[b])
                .sum();
            le += u64::from(s <= observed);
            ge += u64::from(s >= observed);
        }
        let total = (1u64 << n) as f64;
        (le as f64 / total, ge as f64 / total)
    }

    #[test]
    fn sign_flip_counts_match_enumeration() {
        // Doubled midranks of |d| = [1, 2, 2, 3, 3, 3, 4, 5]: 2, 5, 5, 10, 10, 10, 14, 16.
        let scores = [2, 5, 5, 10, 10, 10, 14, 16];
        for observed in 0..=72 {
            let (le, ge) = brute_force(&scores, observed);
            assert_eq!(sign_flip_p_value(&scores, observed, Alternative::Less), le);
            assert_eq!(
                sign_flip_p_value(&scores, observed, Alternative::Greater),
                ge
            );
            let two = (2.0 * le.min(ge)).min(1.0);
            assert_eq!(
                sign_flip_p_value(&scores, observed, Alternative::TwoSided),
                two
            );
        }
    }

    #[test]
    fn rank_sums_add_up() {
        let d = [3.0, -1.0, 4.0, -1.0, 5.0, 0.0, -9.0, 2.0, 6.0];
        let r = wilcoxon_signed_rank(&d, Alternative::TwoSided).unwrap();
        let n = r.n as f64;
        assert_eq!(r.r_plus + r.r_minus, n * (n + 1.0) / 2.0);
        assert_eq!(r.statistic, r.r_plus.min(r.r_minus));
    }
}
