//! Mann–Whitney U (Wilcoxon rank-sum) test for two independent samples
//! (Mann & Whitney 1947), following `scipy.stats.mannwhitneyu` with its
//! defaults (`use_continuity=True`, `method="auto"`).

use std::ops::{AddAssign, SubAssign};

use statrs::distribution::{ContinuousCDF, Normal};

use super::error::{check_no_nan, check_non_empty, StatsError};
use super::hypothesis::{Alternative, PValueMethod};
use super::ranks::midranks_into;

/// SciPy's `method="auto"` uses the exact distribution when there are no ties
/// and at least one sample has at most this many values.
pub const MANN_WHITNEY_EXACT_MAX_MIN_N: usize = 8;

/// Result of the Mann–Whitney U test: U₁ = R₁ − n₁(n₁+1)/2 where R₁ is the
/// midrank sum of the first sample in the pooled ranking (Mann & Whitney 1947,
/// Ann. Math. Statist. 18(1):50–60), i.e. #{xᵢ > yⱼ} + ½·#{xᵢ = yⱼ}.
#[derive(Clone, Debug, PartialEq)]
pub struct MannWhitneyResult {
    /// U of the first sample (SciPy's statistic); U of the second is n₁n₂ − U₁.
    pub statistic: f64,
    /// The p-value for `alternative`.
    pub p_value: f64,
    /// Size of the first sample.
    pub n1: usize,
    /// Size of the second sample.
    pub n2: usize,
    /// Continuity-corrected standard score (U − n₁n₂/2 − ½)/σ of the U used for the
    /// p-value (max(U₁, U₂) two-sided, U₁ for `Greater`, U₂ for `Less`), when asymptotic.
    pub z: Option<f64>,
    /// How the p-value was computed.
    pub method: PValueMethod,
    /// The alternative hypothesis tested.
    pub alternative: Alternative,
}

impl MannWhitneyResult {
    /// U of the second sample, U₂ = n₁n₂ − U₁ (Mann & Whitney 1947).
    pub fn u2(&self) -> f64 {
        (self.n1 * self.n2) as f64 - self.statistic
    }
}

/// Mann–Whitney U test of two independent samples (Mann & Whitney 1947, "On a
/// test of whether one of two random variables is stochastically larger than
/// the other", Ann. Math. Statist. 18(1):50–60), matching
/// `scipy.stats.mannwhitneyu(x, y, alternative=...)`: exact when there are no
/// ties and min(n₁, n₂) ≤ 8, otherwise normal with σ² = n₁n₂/12·[(n+1) −
/// Σ(t³−t)/(n(n−1))] and continuity correction ½.
///
/// Errors on an empty sample or NaN; if every value is tied the p-value is 1.
pub fn mann_whitney_u(
    x: &[f64],
    y: &[f64],
    alternative: Alternative,
) -> Result<MannWhitneyResult, StatsError> {
    check_non_empty(x, "first sample x")?;
    check_non_empty(y, "second sample y")?;
    check_no_nan(x, "first sample x")?;
    check_no_nan(y, "second sample y")?;
    let (n1, n2) = (x.len(), y.len());
    let n = n1 + n2;
    let mut pooled = Vec::with_capacity(n);
    pooled.extend_from_slice(x);
    pooled.extend_from_slice(y);
    let mut order = Vec::with_capacity(n);
    let mut ranks = Vec::with_capacity(n);
    let mut tie_term = 0.0;
    let mut has_ties = false;
    midranks_into(&pooled, &mut order, &mut ranks, |t| {
        if t > 1 {
            has_ties = true;
            let t = t as f64;
            tie_term += t * t * t - t;
        }
    });
    let r1: f64 = ranks[..n1].iter().sum();
    let (n1f, n2f) = (n1 as f64, n2 as f64);
    let u1 = r1 - n1f * (n1f + 1.0) / 2.0;
    let u2 = n1f * n2f - u1;
    let (u, factor) = match alternative {
        Alternative::Greater => (u1, 1.0),
        Alternative::Less => (u2, 1.0),
        Alternative::TwoSided => (u1.max(u2), 2.0),
    };

    let exact = !has_ties && n1.min(n2) <= MANN_WHITNEY_EXACT_MAX_MIN_N;
    let (p, z, method) = if exact {
        // Without ties U is an integer in 0..=n1*n2.
        let p = exact_sf(n1, n2, u.round() as usize);
        (p, None, PValueMethod::Exact)
    } else {
        let nf = n as f64;
        let mu = n1f * n2f / 2.0;
        let var = n1f * n2f / 12.0 * ((nf + 1.0) - tie_term / (nf * (nf - 1.0)));
        if var > 0.0 && var.is_finite() {
            let z = (u - mu - 0.5) / var.sqrt();
            (Normal::standard().sf(z), Some(z), PValueMethod::Asymptotic)
        } else {
            // Every value tied: U₁ = U₂ = n₁n₂/2 and SciPy's z = −½/0 = −∞.
            (1.0, Some(f64::NEG_INFINITY), PValueMethod::Asymptotic)
        }
    };
    Ok(MannWhitneyResult {
        statistic: u1,
        p_value: (p * factor).clamp(0.0, 1.0),
        n1,
        n2,
        z,
        method,
        alternative,
    })
}

/// Exact P(U ≥ u) for sample sizes n1, n2 without ties.
///
/// Uses the symmetry of U about n1·n2/2 so that only a lower tail
/// P(U ≤ k) with k ≤ n1·n2/2 is ever summed.
fn exact_sf(n1: usize, n2: usize, u: usize) -> f64 {
    let mn = n1 * n2;
    if u == 0 {
        return 1.0;
    }
    if u > mn {
        return 0.0;
    }
    let (upper_tail_by_symmetry, k) = if 2 * u >= mn {
        (true, mn - u) // P(U ≥ u) = P(U ≤ mn − u)
    } else {
        (false, u - 1) // P(U ≥ u) = 1 − P(U ≤ u − 1)
    };
    let (m, n) = (n1.min(n2), n1.max(n2));
    if let Some(total) = binomial_u128(m + n, m).filter(|&t| t < (1u128 << 120)) {
        let cum: i128 = gaussian_binomial_prefix::<i128>(m, n, k).iter().sum();
        let cum = cum as u128;
        let count = if upper_tail_by_symmetry {
            cum
        } else {
            total - cum
        };
        count as f64 / total as f64
    } else {
        // Astronomically many arrangements (n ≳ 2·10⁵ with m ≤ 8): floating point,
        // as SciPy itself does in this regime.
        let coeffs = gaussian_binomial_prefix::<f64>(m, n, k);
        let cum: f64 = coeffs.iter().sum();
        let total = binomial_f64(m + n, m);
        let p = if upper_tail_by_symmetry {
            cum / total
        } else {
            1.0 - cum / total
        };
        p.clamp(0.0, 1.0)
    }
}

/// Coefficients 0..=kmax of the Gaussian binomial [m+n choose m]_q =
/// Π_{i=1..m} (1 − q^{n+i}) / (1 − q^i), whose coefficient of q^u is the number
/// of arrangements with U = u (Mann & Whitney 1947). Coefficients are exact in
/// `i128` when C(m+n, m) < 2^120; both operations are causal, so truncating at
/// `kmax` is exact.
fn gaussian_binomial_prefix<T>(m: usize, n: usize, kmax: usize) -> Vec<T>
where
    T: Copy + From<u8> + AddAssign + SubAssign,
{
    let mut c = vec![T::from(0u8); kmax + 1];
    c[0] = T::from(1u8);
    for i in 1..=m {
        let s = n + i;
        // Multiply by (1 − q^s), descending so that c[k − s] is still the old value.
        if s <= kmax {
            for k in (s..=kmax).rev() {
                let v = c[k - s];
                c[k] -= v;
            }
        }
        // Divide by (1 − q^i): c[k] += c[k − i] ascending.
        for k in i..=kmax {
            let v = c[k - i];
            c[k] += v;
        }
    }
    c
}

/// C(n, k) in u128, `None` on overflow.
fn binomial_u128(n: usize, k: usize) -> Option<u128> {
    let k = k.min(n - k);
    let mut c: u128 = 1;
    for i in 1..=k as u128 {
        // c·(n−k+i)/i is an integer at every step.
        c = c.checked_mul(n as u128 - k as u128 + i)? / i;
    }
    Some(c)
}

/// C(n, k) in floating point.
fn binomial_f64(n: usize, k: usize) -> f64 {
    let k = k.min(n - k);
    (1..=k).fold(1.0, |c, i| c * (n - k + i) as f64 / i as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// P(U ≥ u) by enumerating every way to choose which n1 of the n1 + n2
    /// pooled ranks belong to the first sample.
    fn brute_force_sf(n1: usize, n2: usize, u: usize) -> f64 {
        let n = n1 + n2;
        let (mut hits, mut total) = (0u64, 0u64);
        for mask in 0u32..(1 << n) {
            if mask.count_ones() as usize != n1 {
                continue;
            }
            let r1: usize = (0..n).filter(|b| mask >> b & 1 == 1).map(|b| b + 1).sum();
            let u1 = r1 - n1 * (n1 + 1) / 2;
            total += 1;
            if u1 >= u {
                hits += 1;
            }
        }
        hits as f64 / total as f64
    }

    #[test]
    fn exact_sf_matches_enumeration() {
        for n1 in 1..=6 {
            for n2 in 1..=7 {
                for u in 0..=n1 * n2 + 1 {
                    let (a, b) = (exact_sf(n1, n2, u), brute_force_sf(n1, n2, u));
                    assert!((a - b).abs() < 1e-14, "n1={n1} n2={n2} u={u}: {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn float_and_integer_counts_agree() {
        let a = gaussian_binomial_prefix::<i128>(8, 60, 240);
        let b = gaussian_binomial_prefix::<f64>(8, 60, 240);
        for (x, y) in a.iter().zip(&b) {
            assert!((*x as f64 - y).abs() <= 1e-12 * (*x as f64).max(1.0));
        }
        // The coefficients sum to C(m+n, m) when kmax = m·n.
        let all: i128 = gaussian_binomial_prefix::<i128>(5, 7, 35).iter().sum();
        assert_eq!(all, 792);
        assert_eq!(binomial_u128(12, 5), Some(792));
        assert_eq!(binomial_u128(400, 200), None);
    }

    #[test]
    fn huge_samples_use_the_float_fallback_sensibly() {
        // C(300008, 8) > 2^120, so the floating-point path runs; with these sizes
        // the exact and normal p-values agree closely.
        let (n1, n2) = (8usize, 300_000usize);
        assert!(binomial_u128(n1 + n2, n1).is_none_or(|t| t >= 1u128 << 120));
        let u = 1_400_000;
        let p = exact_sf(n1, n2, u);
        let mu = (n1 * n2) as f64 / 2.0;
        let sigma = ((n1 * n2) as f64 * (n1 + n2 + 1) as f64 / 12.0).sqrt();
        let approx = Normal::standard().sf((u as f64 - mu - 0.5) / sigma);
        assert!(p > 0.0 && p < 1.0);
        assert!((p - approx).abs() < 5e-3, "{p} vs {approx}");
        // Python 3.11 exact integers, same Gaussian-binomial recursion:
        // sum(c[:n1*n2 - u + 1]) / math.comb(300008, 8)
        //   -> u = 1_400_000: 0.21062118689113432, u = 1_900_000: 0.0014691372099821043
        assert!((p - 0.21062118689113432).abs() < 1e-9, "{p}");
        let p = exact_sf(n1, n2, 1_900_000);
        assert!((p - 0.0014691372099821043).abs() < 1e-9, "{p}");
    }
}
