//! Effect sizes beside the p-values: the Vargha–Delaney A measure of
//! stochastic superiority, and percentile bootstrap intervals of a
//! two-sample statistic such as the ratio of medians.

use super::descriptive::quantile_sorted;
use super::error::{check_no_nan, check_non_empty, StatsError};
use super::ranks::average_ranks;

/// The Vargha–Delaney A₁₂ = P(X > Y) + ½·P(X = Y) of two independent
/// samples, estimated as U₁/(n₁n₂) with U₁ the Mann–Whitney statistic of x
/// (Vargha & Delaney 2000, "A critique and improvement of the CL common
/// language effect size statistics of McGraw and Wong", J. Educ. Behav.
/// Statist. 25(2):101–132). 0.5 is no effect; for errors (lower is better)
/// A₁₂ < 0.5 means x tends to be the lower. Vargha and Delaney call
/// |A₁₂ − 0.5| ≥ 0.06, 0.14 and 0.21 small, medium and large.
///
/// Errors on an empty sample or a NaN.
pub fn vargha_delaney_a12(x: &[f64], y: &[f64]) -> Result<f64, StatsError> {
    check_non_empty(x, "first sample x")?;
    check_non_empty(y, "second sample y")?;
    let pooled: Vec<f64> = x.iter().chain(y).copied().collect();
    let ranks = average_ranks(&pooled)?;
    let (n1, n2) = (x.len() as f64, y.len() as f64);
    let r1: f64 = ranks.ranks[..x.len()].iter().sum();
    Ok((r1 - n1 * (n1 + 1.0) / 2.0) / (n1 * n2))
}

/// How a bootstrap draws its resamples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resampling {
    /// Each sample is resampled on its own (independent samples).
    Independent,
    /// Pairs (xᵢ, yᵢ) are resampled together (paired samples, equal lengths).
    Paired,
}

/// A two-sided confidence interval.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    /// The lower end.
    pub low: f64,
    /// The upper end.
    pub high: f64,
}

/// The median of `v`, reordering it (the mean of the two middle values
/// when the length is even); NaN when empty.
pub fn median_in_place(v: &mut [f64]) -> f64 {
    let n = v.len();
    if n == 0 {
        return f64::NAN;
    }
    let (_, &mut upper, _) = v.select_nth_unstable_by(n / 2, f64::total_cmp);
    if n % 2 == 1 {
        return upper;
    }
    let lower = v[..n / 2]
        .iter()
        .copied()
        .max_by(f64::total_cmp)
        .unwrap_or(upper);
    (lower + upper) / 2.0
}

/// The ratio of the medians of `x` and `y`, each value first raised to
/// `floor` (for errors: the success threshold, below which values are not
/// told apart): median(max(x, floor)) / median(max(y, floor)). Reorders
/// both slices.
pub fn ratio_of_medians(x: &mut [f64], y: &mut [f64], floor: f64) -> f64 {
    for v in x.iter_mut().chain(y.iter_mut()) {
        *v = v.max(floor);
    }
    median_in_place(x) / median_in_place(y)
}

/// The percentile bootstrap interval at confidence `level` of a statistic of
/// two samples (Efron & Tibshirani 1993, "An Introduction to the
/// Bootstrap", ch. 13): `resamples` resamples drawn with `index(n)` (a
/// uniform index in 0..n, so that the caller's seeded generator makes the
/// interval reproducible), the statistic of each, and their type-7
/// quantiles at (1 − level)/2 and (1 + level)/2, as
/// `scipy.stats.bootstrap(..., method="percentile")` computes them.
/// `statistic` receives the resampled x and y in scratch buffers it may
/// reorder.
///
/// Errors on an empty sample, a NaN, unequal lengths for paired
/// resampling, no resamples, a level outside (0, 1) or a NaN statistic.
pub fn bootstrap_interval(
    x: &[f64],
    y: &[f64],
    resampling: Resampling,
    resamples: usize,
    level: f64,
    mut statistic: impl FnMut(&mut [f64], &mut [f64]) -> f64,
    mut index: impl FnMut(usize) -> usize,
) -> Result<Interval, StatsError> {
    check_non_empty(x, "first sample x")?;
    check_non_empty(y, "second sample y")?;
    check_no_nan(x, "first sample x")?;
    check_no_nan(y, "second sample y")?;
    if resampling == Resampling::Paired && x.len() != y.len() {
        return Err(StatsError::LengthMismatch {
            what: "paired samples x and y",
            expected: x.len(),
            found: y.len(),
        });
    }
    if resamples == 0 {
        return Err(StatsError::InvalidParameter {
            name: "resamples",
            reason: "a bootstrap needs at least one resample",
        });
    }
    if !(level > 0.0 && level < 1.0) {
        return Err(StatsError::InvalidParameter {
            name: "level",
            reason: "a confidence level must lie in (0, 1)",
        });
    }
    let mut bx = vec![0.0; x.len()];
    let mut by = vec![0.0; y.len()];
    let mut stats = Vec::with_capacity(resamples);
    for _ in 0..resamples {
        match resampling {
            Resampling::Independent => {
                for v in bx.iter_mut() {
                    *v = x[index(x.len())];
                }
                for v in by.iter_mut() {
                    *v = y[index(y.len())];
                }
            }
            Resampling::Paired => {
                for (a, b) in bx.iter_mut().zip(by.iter_mut()) {
                    let i = index(x.len());
                    *a = x[i];
                    *b = y[i];
                }
            }
        }
        stats.push(statistic(&mut bx, &mut by));
    }
    check_no_nan(&stats, "bootstrap statistics")?;
    stats.sort_by(f64::total_cmp);
    let tail = (1.0 - level) / 2.0;
    let at = |p: f64| -> Result<f64, StatsError> {
        // Two equal neighbours (infinite ones included) need no interpolation.
        let h = (stats.len() - 1) as f64 * p;
        let j = h.floor() as usize;
        if j + 1 < stats.len() && stats[j] == stats[j + 1] {
            return Ok(stats[j]);
        }
        quantile_sorted(&stats, p)
    };
    Ok(Interval {
        low: at(tail)?,
        high: at(1.0 - tail)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_inputs_are_errors() {
        let ix = |_n: usize| 0usize;
        let stat = |a: &mut [f64], b: &mut [f64]| a[0] - b[0];
        assert!(vargha_delaney_a12(&[], &[1.0]).is_err());
        assert!(vargha_delaney_a12(&[f64::NAN], &[1.0]).is_err());
        assert!(
            bootstrap_interval(&[], &[1.0], Resampling::Independent, 10, 0.95, stat, ix).is_err()
        );
        assert!(
            bootstrap_interval(&[1.0], &[1.0, 2.0], Resampling::Paired, 10, 0.95, stat, ix)
                .is_err()
        );
        assert!(
            bootstrap_interval(&[1.0], &[1.0], Resampling::Independent, 0, 0.95, stat, ix).is_err()
        );
        assert!(
            bootstrap_interval(&[1.0], &[1.0], Resampling::Independent, 5, 1.0, stat, ix).is_err()
        );
        let nan = |_: &mut [f64], _: &mut [f64]| f64::NAN;
        assert!(
            bootstrap_interval(&[1.0], &[1.0], Resampling::Independent, 5, 0.9, nan, ix).is_err()
        );
    }

    #[test]
    fn medians_in_place_and_floored_ratios() {
        assert_eq!(median_in_place(&mut [3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median_in_place(&mut [4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median_in_place(&mut []).is_nan());
        // Both below the floor: the ratio is 1 ("both solved").
        assert_eq!(ratio_of_medians(&mut [0.0, 1e-12], &mut [1e-10], 1e-8), 1.0);
        assert_eq!(ratio_of_medians(&mut [2.0, 4.0], &mut [1.0], 0.0), 3.0);
    }
}
