//! Descriptive statistics of one sample (for example the final errors of the
//! independent runs of one optimiser on one problem).

use super::error::{check_no_nan, check_non_empty, StatsError};

/// Summary of a sample: size, best (minimum), worst (maximum), mean, sample
/// standard deviation with the n − 1 divisor, median and quartiles by the
/// linear-interpolation quantile (Hyndman & Fan 1996, type 7).
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Number of values.
    pub n: usize,
    /// Smallest value (the best one when minimising).
    pub best: f64,
    /// Largest value (the worst one when minimising).
    pub worst: f64,
    /// Arithmetic mean Σx / n.
    pub mean: f64,
    /// Sample standard deviation sqrt(Σ(x − mean)² / (n − 1)); `None` when n = 1.
    pub std_dev: Option<f64>,
    /// Median, the type-7 quantile at p = 0.5.
    pub median: f64,
    /// First quartile, the type-7 quantile at p = 0.25.
    pub q1: f64,
    /// Third quartile, the type-7 quantile at p = 0.75.
    pub q3: f64,
}

/// Summarises a sample (see [`Summary`]); quartiles use the type-7 quantile of
/// Hyndman & Fan (1996), "Sample quantiles in statistical packages", The
/// American Statistician 50(4):361–365, the default of NumPy and R.
///
/// Errors on an empty sample or on NaN; infinities follow IEEE arithmetic.
pub fn summarize(sample: &[f64]) -> Result<Summary, StatsError> {
    check_non_empty(sample, "sample")?;
    check_no_nan(sample, "sample")?;
    let mut sorted = sample.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let mean = sample.iter().sum::<f64>() / n as f64;
    let std_dev = if n > 1 {
        let ss: f64 = sample.iter().map(|&x| (x - mean) * (x - mean)).sum();
        Some((ss / (n - 1) as f64).sqrt())
    } else {
        None
    };
    Ok(Summary {
        n,
        best: sorted[0],
        worst: sorted[n - 1],
        mean,
        std_dev,
        median: type7(&sorted, 0.5),
        q1: type7(&sorted, 0.25),
        q3: type7(&sorted, 0.75),
    })
}

/// The median as NumPy's `np.median` computes it: the middle order
/// statistic, or for an even size the mean `(x₍ₙ/₂₎ + x₍ₙ/₂₊₁₎)/2` of the two
/// middle ones (which may differ in the last bit from the type-7
/// [`quantile`] at p = 0.5). NaN for an empty sample; NaNs sort last.
pub fn median(sample: &[f64]) -> f64 {
    let mut sorted = sample.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0,
    }
}

/// Type-7 sample quantile Q(p) = x₍ⱼ₎ + g·(x₍ⱼ₊₁₎ − x₍ⱼ₎) with h = (n − 1)p,
/// j = ⌊h⌋, g = h − j on the order statistics (Hyndman & Fan 1996, The American
/// Statistician 50(4):361–365; NumPy's and R's default). Sorts a copy of `sample`.
pub fn quantile(sample: &[f64], p: f64) -> Result<f64, StatsError> {
    check_non_empty(sample, "sample")?;
    check_no_nan(sample, "sample")?;
    check_probability(p)?;
    let mut sorted = sample.to_vec();
    sorted.sort_by(f64::total_cmp);
    Ok(type7(&sorted, p))
}

/// Type-7 quantile (Hyndman & Fan 1996, The American Statistician
/// 50(4):361–365) of a sample already sorted in ascending order; no copy is made.
///
/// Errors on an empty slice, a NaN or p outside [0, 1]; an unsorted slice gives
/// a meaningless number but never a panic.
pub fn quantile_sorted(sorted: &[f64], p: f64) -> Result<f64, StatsError> {
    check_non_empty(sorted, "sorted sample")?;
    check_no_nan(sorted, "sorted sample")?;
    check_probability(p)?;
    Ok(type7(sorted, p))
}

fn check_probability(p: f64) -> Result<(), StatsError> {
    if (0.0..=1.0).contains(&p) {
        Ok(())
    } else {
        Err(StatsError::InvalidParameter {
            name: "p",
            reason: "a quantile level must lie in [0, 1]",
        })
    }
}

/// Type-7 quantile of a non-empty sorted slice, p in [0, 1].
fn type7(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    let h = (n - 1) as f64 * p;
    let j = (h.floor() as usize).min(n - 1);
    let g = h - j as f64;
    if j + 1 >= n || g == 0.0 {
        return sorted[j];
    }
    let (a, b) = (sorted[j], sorted[j + 1]);
    // NumPy's `_lerp`: interpolate from the nearer end for accuracy.
    if g >= 0.5 {
        b - (b - a) * (1.0 - g)
    } else {
        a + (b - a) * g
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_even_and_empty_samples() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn odd_sample_matches_numpy() {
        // numpy 2.4.6, x = [3.2, 1.5, 7.8, 2.2, 9.1, 4.4, 0.7]:
        // min 0.7, max 9.1, mean 4.128571428571428, std(ddof=1) 3.2019339394155137,
        // median 3.2, percentile(25) 1.85, percentile(75) 6.1,
        // quantile(0.1) 1.1800000000000002, quantile(0.9) 8.32
        let x = [3.2, 1.5, 7.8, 2.2, 9.1, 4.4, 0.7];
        let s = summarize(&x).unwrap();
        assert_eq!(s.n, 7);
        assert_eq!(s.best, 0.7);
        assert_eq!(s.worst, 9.1);
        assert!(close(s.mean, 4.128571428571428, 1e-12));
        assert!(close(s.std_dev.unwrap(), 3.2019339394155137, 1e-12));
        assert!(close(s.median, 3.2, 1e-12));
        assert!(close(s.q1, 1.85, 1e-12));
        assert!(close(s.q3, 6.1, 1e-12));
        assert!(close(quantile(&x, 0.1).unwrap(), 1.1800000000000002, 1e-12));
        assert!(close(quantile(&x, 0.9).unwrap(), 8.32, 1e-12));
        assert_eq!(quantile(&x, 0.0).unwrap(), 0.7);
        assert_eq!(quantile(&x, 1.0).unwrap(), 9.1);
    }

    #[test]
    fn even_sample_matches_numpy() {
        // numpy 2.4.6, x = [0.5, 2.5, 1.0, 4.0, 3.0, 10.0]:
        // mean 3.5, std(ddof=1) 3.4351128074635335, median 2.75,
        // percentile(25) 1.375, percentile(75) 3.75, quantile(0.1) 0.75, quantile(0.9) 7.0
        let x = [0.5, 2.5, 1.0, 4.0, 3.0, 10.0];
        let s = summarize(&x).unwrap();
        assert!(close(s.mean, 3.5, 1e-12));
        assert!(close(s.std_dev.unwrap(), 3.4351128074635335, 1e-12));
        assert!(close(s.median, 2.75, 1e-12));
        assert!(close(s.q1, 1.375, 1e-12));
        assert!(close(s.q3, 3.75, 1e-12));
        let mut sorted = x.to_vec();
        sorted.sort_by(f64::total_cmp);
        assert!(close(quantile_sorted(&sorted, 0.1).unwrap(), 0.75, 1e-12));
        assert!(close(quantile_sorted(&sorted, 0.9).unwrap(), 7.0, 1e-12));
    }

    #[test]
    fn edge_cases_do_not_panic() {
        let s = summarize(&[2.5]).unwrap();
        assert_eq!((s.n, s.best, s.worst, s.mean), (1, 2.5, 2.5, 2.5));
        assert_eq!(s.std_dev, None);
        assert_eq!((s.median, s.q1, s.q3), (2.5, 2.5, 2.5));
        assert!(matches!(summarize(&[]), Err(StatsError::EmptyInput { .. })));
        assert!(matches!(
            summarize(&[1.0, f64::NAN]),
            Err(StatsError::NotANumber { index: 1, .. })
        ));
        assert!(matches!(
            quantile(&[1.0], 1.5),
            Err(StatsError::InvalidParameter { .. })
        ));
        assert!(quantile(&[1.0], f64::NAN).is_err());
        let s = summarize(&[1.0, f64::INFINITY]).unwrap();
        assert_eq!(s.worst, f64::INFINITY);
        assert_eq!(s.mean, f64::INFINITY);
    }
}
