//! The Hodges–Lehmann one-sample location estimate (the median of the
//! Walsh averages) with the confidence interval obtained by inverting the
//! Wilcoxon signed-rank test (Tukey's interval).
//!
//! For paired samples, apply it to the differences dᵢ = xᵢ − yᵢ: the
//! estimate is then a shift, the pseudo-median of the differences.

use statrs::distribution::{ContinuousCDF, Normal};

use super::error::{check_no_nan, check_non_empty, StatsError};
use super::wilcoxon::WILCOXON_EXACT_MAX_N;

/// Largest sample [`hodges_lehmann_interval`] accepts: it materialises all
/// M = n(n+1)/2 Walsh averages (4,501,500 values, 36 MB, at n = 3000) and
/// finds the order statistics it needs by selection in O(M) time.
pub const HODGES_LEHMANN_MAX_N: usize = 3000;

/// A location estimate with a two-sided confidence interval (Hodges &
/// Lehmann 1963, "Estimates of location based on rank tests", Ann. Math.
/// Statist. 34(2):598–611; interval: Hollander, Wolfe & Chicken 2014,
/// "Nonparametric Statistical Methods", 3rd ed., Wiley, §3.3).
///
/// An interval that the sample is too small to bound is (−∞, +∞) with
/// `level` 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShiftInterval {
    /// The Hodges–Lehmann estimate θ̂ = median{(dᵢ + dⱼ)/2 : i ≤ j}.
    pub estimate: f64,
    /// The lower end W₍ₖ₎ (−∞ when unbounded).
    pub low: f64,
    /// The upper end W₍M+1−k₎ (+∞ when unbounded).
    pub high: f64,
    /// The achieved coverage 1 − 2·P(T⁺ ≤ k − 1), at least the requested
    /// confidence for exact intervals; 1 when unbounded.
    pub level: f64,
}

/// The Hodges–Lehmann estimate of the centre of symmetry of `d` and its
/// two-sided signed-rank confidence interval at `confidence`.
///
/// **Estimate** (Hodges & Lehmann 1963, "Estimates of location based on
/// rank tests", Ann. Math. Statist. 34(2):598–611): the median of the
/// M = n(n+1)/2 Walsh averages (dᵢ + dⱼ)/2, i ≤ j (the mean of the two
/// middle ones when M is even).
///
/// **Interval** (Tukey's; Hollander, Wolfe & Chicken 2014, "Nonparametric
/// Statistical Methods", 3rd ed., Wiley, §3.3; Bauer 1972, "Constructing
/// confidence sets using rank statistics", JASA 67(339):687–690): with the
/// sorted Walsh averages W₍₁₎ ≤ … ≤ W₍M₎ and the null distribution of the
/// signed-rank statistic T⁺ on n untied observations, k is the largest
/// integer with P(T⁺ ≤ k − 1) ≤ (1 − confidence)/2, and the interval is
/// [W₍ₖ₎, W₍M+1−ₖ₎] with achieved level 1 − 2·P(T⁺ ≤ k − 1). This is the set
/// of shifts θ that the two-sided test of d − θ does not reject, so zeros
/// and ties of d are ordinary observations (no tie correction, no zeros
/// dropped). If no k ≥ 1 qualifies (n ≤ 5 at 95 %) the interval is
/// (−∞, +∞) with level 1.
///
/// For n ≤ [`WILCOXON_EXACT_MAX_N`] (50) the distribution of T⁺ is exact
/// (integer counts). Above, k = ⌊n(n+1)/4 − z·σ⌋ with
/// σ = √(n(n+1)(2n+1)/24) and z = Φ⁻¹((1 + confidence)/2): the largest k
/// whose uncorrected normal approximation Φ((k − μ)/σ) is at most
/// (1 − confidence)/2, half a unit of T⁺ more conservative than the
/// continuity-corrected approximation of P(T⁺ ≤ k − 1), and the achieved
/// level is reported as 1 − 2·Φ((k − ½ − μ)/σ) (μ = n(n+1)/4).
///
/// Differences from R's `wilcox.test(d, conf.int = TRUE)`: where R's exact
/// branch applies (n < 50, no ties, no zeros) the interval is the same,
/// except that R returns [W₍₁₎, W₍M₎] instead of an unbounded interval
/// when no k ≥ 1 qualifies. With ties, zeros or larger samples R inverts
/// the tie-corrected normal statistic numerically (`uniroot`), so its ends
/// are not order statistics.
///
/// Errors: empty `d`, a NaN ([`StatsError::NotANumber`]), an infinite value
/// (refused: Walsh averages ∞ − ∞ would be NaN), more than
/// [`HODGES_LEHMANN_MAX_N`] values, or `confidence` outside (0, 1).
///
/// ```
/// use metabezier_core::stats::hodges_lehmann_interval;
///
/// let d = [1.2, -0.4, 2.3, 0.7, 3.1, 1.9];
/// let s = hodges_lehmann_interval(&d, 0.95).unwrap();
/// assert_eq!((s.estimate, s.low, s.high), (1.5, -0.4, 3.1));
/// assert_eq!(s.level, 1.0 - 2.0 / 64.0);
/// ```
pub fn hodges_lehmann_interval(d: &[f64], confidence: f64) -> Result<ShiftInterval, StatsError> {
    check_inputs(d, confidence)?;
    let n = d.len();
    let m = n * (n + 1) / 2;
    let (k, tail) = if n <= WILCOXON_EXACT_MAX_N {
        exact_depth(n, (1.0 - confidence) / 2.0)
    } else {
        normal_depth(n, confidence)
    };
    let mut ranks = vec![(m - 1) / 2, m / 2];
    if k > 0 {
        ranks.extend([k - 1, m - k]);
    }
    ranks.sort_unstable();
    ranks.dedup();
    let mut walsh = walsh_averages(d);
    let values = order_statistics(&mut walsh, &ranks);
    let at = |rank: usize| values[ranks.partition_point(|&r| r < rank)];
    let estimate = at((m - 1) / 2).midpoint(at(m / 2));
    if k == 0 {
        return Ok(ShiftInterval {
            estimate,
            low: f64::NEG_INFINITY,
            high: f64::INFINITY,
            level: 1.0,
        });
    }
    Ok(ShiftInterval {
        estimate,
        low: at(k - 1),
        high: at(m - k),
        level: (1.0 - 2.0 * tail).clamp(0.0, 1.0),
    })
}

/// Refuses empty, NaN or infinite `d`, too many values, and a confidence
/// outside (0, 1).
fn check_inputs(d: &[f64], confidence: f64) -> Result<(), StatsError> {
    check_non_empty(d, "differences")?;
    check_no_nan(d, "differences")?;
    if d.iter().any(|v| v.is_infinite()) {
        return Err(StatsError::InvalidParameter {
            name: "differences",
            reason: "the Hodges-Lehmann interval needs finite differences",
        });
    }
    if d.len() > HODGES_LEHMANN_MAX_N {
        return Err(StatsError::InvalidParameter {
            name: "differences",
            reason: "more than HODGES_LEHMANN_MAX_N (3000) values",
        });
    }
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(StatsError::InvalidParameter {
            name: "confidence",
            reason: "a confidence level must lie in (0, 1)",
        });
    }
    Ok(())
}

/// The M = n(n+1)/2 Walsh averages (dᵢ + dⱼ)/2, i ≤ j, in no particular
/// order, each the correctly rounded midpoint (no overflow for large
/// finite values) with −0 written as +0.
fn walsh_averages(d: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(d.len() * (d.len() + 1) / 2);
    for (i, &a) in d.iter().enumerate() {
        for &b in &d[i..] {
            let w = a.midpoint(b);
            out.push(if w == 0.0 { 0.0 } else { w });
        }
    }
    out
}

/// The values of `v` at the 0-based sorted positions `ranks` (ascending,
/// distinct, each below `v.len()`), by recursive `select_nth_unstable`:
/// O(len · log(ranks.len())) time; `v` is reordered.
fn order_statistics(v: &mut [f64], ranks: &[usize]) -> Vec<f64> {
    let mut out = vec![0.0; ranks.len()];
    select_into(v, 0, ranks, &mut out);
    out
}

/// [`order_statistics`] of the sub-slice `v` that starts at sorted
/// position `base` of the whole.
fn select_into(v: &mut [f64], base: usize, ranks: &[usize], out: &mut [f64]) {
    if ranks.is_empty() || v.is_empty() {
        return;
    }
    let mid = ranks.len() / 2;
    let r = ranks[mid] - base;
    let (left, value, right) = v.select_nth_unstable_by(r, f64::total_cmp);
    out[mid] = *value;
    let (low_out, high_out) = out.split_at_mut(mid);
    select_into(left, base, &ranks[..mid], low_out);
    select_into(right, base + r + 1, &ranks[mid + 1..], &mut high_out[1..]);
}

/// The number of sign vectors of 1..n with each value t of T⁺ = Σ of the
/// ranks given a + sign: c(t) for t = 0..n(n+1)/2, by the recursion
/// c_r(t) = c_{r−1}(t) + c_{r−1}(t − r). Exact in u64 for n ≤ 63.
fn signed_rank_counts(n: usize) -> Vec<u64> {
    let m = n * (n + 1) / 2;
    let mut counts = vec![0u64; m + 1];
    counts[0] = 1;
    let mut reach = 0;
    for r in 1..=n {
        reach += r;
        for t in (r..=reach).rev() {
            counts[t] += counts[t - r];
        }
    }
    counts
}

/// The exact depth: the largest k ≥ 1 with P(T⁺ ≤ k − 1) ≤ `tail` and that
/// probability, or (0, 0) when P(T⁺ = 0) = 2⁻ⁿ already exceeds `tail`.
fn exact_depth(n: usize, tail: f64) -> (usize, f64) {
    let total = (n as f64).exp2();
    let mut cumulative = 0u64;
    let mut best = (0, 0.0);
    for (t, &c) in signed_rank_counts(n).iter().enumerate() {
        cumulative += c;
        // Exact: cumulative < 2^53 and the division is by a power of two.
        let p = cumulative as f64 / total;
        if p > tail {
            break;
        }
        best = (t + 1, p);
    }
    best
}

/// The normal-approximation depth k = ⌊μ − z·σ⌋ (μ = n(n+1)/4,
/// σ² = n(n+1)(2n+1)/24, z = Φ⁻¹((1 + confidence)/2)) with the
/// continuity-corrected Φ((k − ½ − μ)/σ) ≈ P(T⁺ ≤ k − 1), or (0, 0) when
/// k < 1.
fn normal_depth(n: usize, confidence: f64) -> (usize, f64) {
    let norm = Normal::standard();
    let nf = n as f64;
    let mu = nf * (nf + 1.0) / 4.0;
    let sigma = (nf * (nf + 1.0) * (2.0 * nf + 1.0) / 24.0).sqrt();
    let z = norm.inverse_cdf((1.0 + confidence) / 2.0);
    let k = (mu - z * sigma).floor();
    if k.is_nan() || k < 1.0 {
        return (0, 0.0);
    }
    // z > 0, so k ≤ μ = M/2 and W₍ₖ₎ ≤ W₍M+1−k₎.
    (k as usize, norm.cdf((k - 0.5 - mu) / sigma))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{run_rng, Draw};

    /// The Walsh averages sorted, by brute force.
    fn sorted_walsh(d: &[f64]) -> Vec<f64> {
        let mut w = walsh_averages(d);
        w.sort_by(f64::total_cmp);
        w
    }

    #[test]
    fn reference_intervals_with_ties_zeros_and_small_samples() {
        // ci/stats-reference/bayes_and_hl.py (Python 3.11.7, NumPy 2.4.6,
        // SciPy 1.17.1): Walsh averages and the null distribution of T⁺ by
        // enumerating all 2^n sign vectors, checked by inverting the test.
        let ties = [
            0.0, 0.0, 1.5, -0.5, 2.0, 2.0, 3.5, -1.0, 0.75, 2.0, 4.25, -0.25,
        ];
        let s = hodges_lehmann_interval(&ties, 0.95).unwrap();
        // -> 1.0, 0.0, 2.125, level 0.95751953125 (k = 14)
        assert_eq!((s.estimate, s.low, s.high), (1.0, 0.0, 2.125));
        assert_eq!(s.level, 0.95751953125);
        // n = 6, the smallest n with a 95 % interval: k = 1, [min, max].
        let n6 = [1.2, -0.4, 2.3, 0.7, 3.1, 1.9];
        let s = hodges_lehmann_interval(&n6, 0.95).unwrap();
        // -> 1.5, -0.4, 3.1, level 0.96875 (k = 1)
        assert_eq!(
            (s.estimate, s.low, s.high, s.level),
            (1.5, -0.4, 3.1, 0.96875)
        );
        // n = 5: 2⁻⁵ > 0.025, no interval.
        let s = hodges_lehmann_interval(&n6[..5], 0.95).unwrap();
        // -> 1.35, -inf, inf, level 1.0 (k = 0)
        assert_eq!(s.estimate, 1.35);
        assert_eq!(
            (s.low, s.high, s.level),
            (f64::NEG_INFINITY, f64::INFINITY, 1.0)
        );
        let n15 = [
            0.31, -0.12, 0.77, 0.05, 1.42, -0.58, 0.93, 0.26, 0.64, -0.07, 1.1, 0.18, 0.49, -0.33,
            0.85,
        ];
        let s = hodges_lehmann_interval(&n15, 0.90).unwrap();
        // -> 0.395, 0.11499999999999999, 0.6699999999999999, level 0.9053955078125 (k = 31)
        assert_eq!(s.estimate, 0.395);
        assert_eq!((s.low, s.high), (0.11499999999999999, 0.6699999999999999));
        assert_eq!(s.level, 0.9053955078125);
    }

    #[test]
    fn normal_approximation_above_fifty() {
        // numpy.random.default_rng(1) normals N(0.3, 0.5²), 3 decimals;
        // ci/stats-reference/bayes_and_hl.py (SciPy 1.17.1 norm.ppf/cdf):
        // -> 0.22425, 0.0925, 0.34550000000000003, level 0.9510731772468273 (k = 648)
        #[allow(clippy::approx_constant)] // 0.318 is a data value, not 1/π
        let d = [
            -1.056, -0.645, 0.213, 0.089, 0.407, 0.409, 1.359, -0.256, 0.111, 1.321, 0.623, 0.632,
            0.043, -0.524, 0.384, 0.355, -0.314, -0.042, 0.264, -0.172, 0.251, 0.348, 0.318, 0.047,
            0.597, 0.746, 0.46, -0.109, 0.666, 0.049, 0.74, -0.236, 0.757, 0.29, -0.324, 0.143,
            0.327, 0.436, -0.191, -0.254, 0.4, 0.067, 0.418, 0.68, -0.524, 0.427, 0.912, 0.151,
            -0.105, 0.676, 0.427, 0.748, 0.127, -0.441, 0.245, 0.077, 0.688, 0.397, -0.515, -0.298,
        ];
        assert_eq!(normal_depth(60, 0.95).0, 648);
        let s = hodges_lehmann_interval(&d, 0.95).unwrap();
        assert_eq!(
            (s.estimate, s.low, s.high),
            (0.22425, 0.0925, 0.34550000000000003)
        );
        // statrs 0.18's Φ and SciPy's differ by about 2e-12 here.
        assert!((s.level - 0.9510731772468273).abs() < 1e-9, "{}", s.level);
    }

    #[test]
    fn exact_depth_matches_enumeration_and_the_approximation_is_close() {
        // Brute force over the 2^n sign vectors for n ≤ 12.
        for n in 1..=12usize {
            let m = n * (n + 1) / 2;
            let mut counts = vec![0u64; m + 1];
            for mask in 0u32..(1 << n) {
                let t: usize = (0..n).filter(|b| mask >> b & 1 == 1).map(|b| b + 1).sum();
                counts[t] += 1;
            }
            assert_eq!(signed_rank_counts(n), counts, "n = {n}");
        }
        // At n = 50 and 95 % the exact depth is 435, the approximation 434.
        assert_eq!(exact_depth(50, 0.025).0, 435);
        assert_eq!(normal_depth(50, 0.95).0, 434);
        assert_eq!(exact_depth(5, 0.025), (0, 0.0));
        assert_eq!(exact_depth(6, 0.025), (1, 1.0 / 64.0));
    }

    #[test]
    fn shifting_the_data_shifts_estimate_and_interval() {
        let mut rng = run_rng(11);
        for n in [1, 2, 6, 9, 24, 50, 51, 80] {
            // Multiples of 1/8 below 2^10: every sum and shift is exact.
            let d: Vec<f64> = (0..n).map(|_| rng.index(161) as f64 / 8.0 - 10.0).collect();
            let base = hodges_lehmann_interval(&d, 0.95).unwrap();
            for c in [-3.625, 0.0, 17.25] {
                let moved: Vec<f64> = d.iter().map(|v| v + c).collect();
                let s = hodges_lehmann_interval(&moved, 0.95).unwrap();
                assert_eq!(s.estimate, base.estimate + c, "n = {n}, c = {c}");
                assert_eq!((s.low, s.high), (base.low + c, base.high + c));
                assert_eq!(s.level, base.level);
            }
            // Negating the data mirrors the interval.
            let neg: Vec<f64> = d.iter().map(|v| -v).collect();
            let s = hodges_lehmann_interval(&neg, 0.95).unwrap();
            assert_eq!((s.low, s.high), (-base.high, -base.low));
        }
    }

    #[test]
    fn selection_agrees_with_sorting() {
        let mut rng = run_rng(5);
        for n in [1, 2, 3, 7, 30, 64] {
            let d: Vec<f64> = (0..n).map(|_| rng.gaussian()).collect();
            let sorted = sorted_walsh(&d);
            let m = sorted.len();
            let ranks: Vec<usize> = [0, (m - 1) / 2, m / 2, m - 1]
                .into_iter()
                .collect::<std::collections::BTreeSet<_>>()
                .into_iter()
                .collect();
            let got = order_statistics(&mut walsh_averages(&d), &ranks);
            let want: Vec<f64> = ranks.iter().map(|&r| sorted[r]).collect();
            assert_eq!(got, want, "n = {n}");
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        assert!(matches!(
            hodges_lehmann_interval(&[], 0.95),
            Err(StatsError::EmptyInput { .. })
        ));
        assert!(matches!(
            hodges_lehmann_interval(&[1.0, f64::NAN], 0.95),
            Err(StatsError::NotANumber { index: 1, .. })
        ));
        assert!(hodges_lehmann_interval(&[1.0, f64::INFINITY], 0.95).is_err());
        for c in [0.0, 1.0, -0.5, f64::NAN] {
            assert!(hodges_lehmann_interval(&[1.0, 2.0], c).is_err(), "{c}");
        }
        let big = vec![1.0; HODGES_LEHMANN_MAX_N + 1];
        assert!(matches!(
            hodges_lehmann_interval(&big, 0.95),
            Err(StatsError::InvalidParameter { .. })
        ));
        // A single value: its own estimate, no interval.
        let s = hodges_lehmann_interval(&[2.5], 0.5).unwrap();
        assert_eq!((s.estimate, s.level), (2.5, 1.0));
        // Huge finite values do not overflow.
        let s = hodges_lehmann_interval(&[f64::MAX; 7], 0.95).unwrap();
        assert_eq!((s.estimate, s.low, s.high), (f64::MAX, f64::MAX, f64::MAX));
    }
}
