//! Post-hoc tests after Friedman's test, one control against the others,
//! and the step-down corrections of García & Herrera (2008).
//!
//! With k algorithms ranked on N blocks, the average ranks Rᵢ and R_c of an
//! algorithm and of the control give z = (R_c − Rᵢ)/√(k(k+1)/(6N)) and a
//! two-sided normal p-value (Demšar 2006, JMLR 7:1–30, §3.2.2); the k − 1
//! p-values are then adjusted by Holm's (1979) or Finner's (1993) step-down
//! method (García & Herrera 2008, "An extension on 'Statistical comparisons
//! of classifiers over multiple data sets' for all pairwise comparisons",
//! JMLR 9:2677–2694; Derrac et al. 2011, Swarm Evol. Comput. 1(1):3–18).

use statrs::distribution::{ContinuousCDF, Normal};

use super::error::StatsError;
use super::holm::step_down;

/// The comparison of one algorithm with the control after Friedman's test.
#[derive(Clone, Debug, PartialEq)]
pub struct ControlComparison {
    /// The algorithm's index among the treatments.
    pub treatment: usize,
    /// z = (R_control − R_treatment)/SE: positive when the treatment has the
    /// lower (better) average rank.
    pub z: f64,
    /// The unadjusted two-sided p-value 2(1 − Φ(|z|)).
    pub p_value: f64,
}

/// The standard error √(k(k+1)/(6N)) of a difference of two average ranks
/// of k treatments on N blocks (Demšar 2006, JMLR 7:1–30, §3.2.2).
fn rank_se(k: usize, n_blocks: usize) -> f64 {
    let k = k as f64;
    (k * (k + 1.0) / (6.0 * n_blocks as f64)).sqrt()
}

fn two_sided_normal_p(z: f64) -> f64 {
    // N(0, 1) is always constructible.
    let normal = Normal::new(0.0, 1.0).expect("the standard normal");
    (2.0 * normal.sf(z.abs())).min(1.0)
}

/// Every treatment against `control` by the z-test of average ranks after
/// Friedman's test (Demšar 2006, JMLR 7:1–30, §3.2.2), in treatment order
/// without the control; the p-values are unadjusted.
///
/// Errors when there are fewer than two treatments, no blocks, the control
/// is out of range or a rank is NaN.
pub fn friedman_control_posthoc(
    average_ranks: &[f64],
    n_blocks: usize,
    control: usize,
) -> Result<Vec<ControlComparison>, StatsError> {
    let k = average_ranks.len();
    if k < 2 {
        return Err(StatsError::InvalidParameter {
            name: "average_ranks",
            reason: "a post-hoc test needs at least two treatments",
        });
    }
    if n_blocks == 0 {
        return Err(StatsError::EmptyInput { what: "blocks" });
    }
    if control >= k {
        return Err(StatsError::InvalidParameter {
            name: "control",
            reason: "the control must be one of the treatments",
        });
    }
    if let Some(index) = average_ranks.iter().position(|r| r.is_nan()) {
        return Err(StatsError::NotANumber {
            what: "average ranks",
            index,
        });
    }
    let se = rank_se(k, n_blocks);
    Ok((0..k)
        .filter(|&i| i != control)
        .map(|i| {
            let z = (average_ranks[control] - average_ranks[i]) / se;
            ControlComparison {
                treatment: i,
                z,
                p_value: two_sided_normal_p(z),
            }
        })
        .collect())
}

/// The smallest unadjusted p-value of [`friedman_control_posthoc`] with k
/// treatments on N blocks: a treatment ranked first and the control last on
/// every block differ by k − 1 in average rank.
pub fn smallest_friedman_control_p(k: usize, n_blocks: usize) -> f64 {
    if k < 2 || n_blocks == 0 {
        return 1.0;
    }
    two_sided_normal_p((k - 1) as f64 / rank_se(k, n_blocks))
}

/// Finner-adjusted p-values in the original order: with p₍₁₎ ≤ … ≤ p₍ₘ₎,
/// p̃₍ᵢ₎ = min(1, maxⱼ≤ᵢ 1 − (1 − p₍ⱼ₎)^(m/j)) (Finner 1993, "On a
/// monotonicity problem in step-down multiple test procedures", J. Amer.
/// Statist. Assoc. 88(423):920–923; in the form of García & Herrera 2008,
/// JMLR 9:2677–2694). Less conservative than Holm's method; both control the
/// family-wise error rate.
///
/// An empty slice gives an empty vector; NaN or a value outside [0, 1] is an
/// error.
pub fn finner(p_values: &[f64]) -> Result<Vec<f64>, StatsError> {
    step_down(p_values, |p, j, m| {
        1.0 - (1.0 - p).powf(m as f64 / j as f64)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_inputs_are_errors() {
        assert!(friedman_control_posthoc(&[1.0], 3, 0).is_err());
        assert!(friedman_control_posthoc(&[1.0, 2.0], 0, 0).is_err());
        assert!(friedman_control_posthoc(&[1.0, 2.0], 3, 2).is_err());
        assert!(friedman_control_posthoc(&[1.0, f64::NAN], 3, 0).is_err());
        assert!(finner(&[0.1, f64::NAN]).is_err());
        assert!(finner(&[1.5]).is_err());
        assert!(finner(&[]).unwrap().is_empty());
        assert_eq!(smallest_friedman_control_p(1, 5), 1.0);
    }

    #[test]
    fn finner_is_never_above_holm() {
        let p = [0.001, 0.01, 0.02, 0.04, 0.3];
        let f = finner(&p).unwrap();
        let h = crate::stats::holm_bonferroni(&p).unwrap();
        for (a, b) in f.iter().zip(&h) {
            assert!(*a <= b + 1e-12, "{a} > {b}");
        }
    }
}
