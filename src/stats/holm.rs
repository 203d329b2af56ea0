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
    let m = p_values.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p_values[a].total_cmp(&p_values[b]));
    let mut adjusted = vec![0.0; m];
    let mut running_max: f64 = 0.0;
    for (rank, &idx) in order.iter().enumerate() {
        let candidate = (m - rank) as f64 * p_values[idx];
        running_max = running_max.max(candidate);
        adjusted[idx] = running_max.min(1.0);
    }
    Ok(adjusted)
}
