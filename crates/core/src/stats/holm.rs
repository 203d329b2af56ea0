//! Holm–Bonferroni step-down adjustment of p-values (Holm 1979).

use super::error::StatsError;

/// Holm-adjusted p-values in the original order: with p₍₁₎ ≤ … ≤ p₍ₘ₎,
/// p̃₍ᵢ₎ = min(1, maxⱼ≤ᵢ (m − j + 1)·p₍ⱼ₎) (Holm 1979, "A simple sequentially
/// rejective multiple test procedure", Scand. J. Statist. 6(2):65–70); equals
/// `statsmodels.stats.multitest.multipletests(p, method="holm")[1]`.
///
/// Rejecting the hypotheses whose adjusted p-value is ≤ α controls the
/// family-wise error rate at α. An empty slice gives an empty vector; NaN or a
/// value outside [0, 1] is an error.
pub fn holm_bonferroni(p_values: &[f64]) -> Result<Vec<f64>, StatsError> {
    step_down(p_values, |p, j, m| (m - j + 1) as f64 * p)
}

/// A step-down adjustment: with p₍₁₎ ≤ … ≤ p₍ₘ₎, p̃₍ᵢ₎ = min(1, maxⱼ≤ᵢ
/// c(p₍ⱼ₎, j, m)) in the original order, where `candidate(p, j, m)` is the
/// method's adjusted value of the j-th smallest of m p-values (j from 1).
/// Errors on a NaN p-value or one outside [0, 1].
pub(super) fn step_down(
    p_values: &[f64],
    candidate: impl Fn(f64, usize, usize) -> f64,
) -> Result<Vec<f64>, StatsError> {
    check_p_values(p_values)?;
    let m = p_values.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p_values[a].total_cmp(&p_values[b]));
    let mut adjusted = vec![0.0; m];
    let mut running_max: f64 = 0.0;
    for (rank, &idx) in order.iter().enumerate() {
        running_max = running_max.max(candidate(p_values[idx], rank + 1, m));
        adjusted[idx] = running_max.min(1.0);
    }
    Ok(adjusted)
}

/// Errors on a NaN p-value or one outside [0, 1].
fn check_p_values(p_values: &[f64]) -> Result<(), StatsError> {
    for (index, &p) in p_values.iter().enumerate() {
        if p.is_nan() {
            return Err(StatsError::NotANumber {
                what: "p-values",
                index,
            });
        }
        if !(0.0..=1.0).contains(&p) {
            return Err(StatsError::InvalidParameter {
                name: "p_values",
                reason: "every p-value must lie in [0, 1]",
            });
        }
    }
    Ok(())
}
