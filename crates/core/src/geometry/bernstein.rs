//! Bernstein basis polynomials `B_i^n(t) = C(n,i) tⁱ (1−t)ⁿ⁻ⁱ` (Bernstein 1912;
//! Farin 2002, §5.1).

/// Binomial coefficient `C(n, k) = n! / (k!(n−k)!)`, and 0 when `k > n`.
///
/// Computed exactly in 128-bit integers by the multiplicative formula
/// `C(n,k) = Π_{j<k} (n−j)/(j+1)` for `n ≤ 120` and rounded once to `f64`
/// (so it is exact for `n ≤ 56`, where every `C(n,k) < 2⁵³`); larger `n`
/// fall back to the same product in floating point.
pub fn binomial(n: u32, k: u32) -> f64 {
    if k > n {
        return 0.0;
    }
    let k = k.min(n - k);
    if n <= 120 {
        let mut r: u128 = 1;
        for j in 0..k {
            // r·(n−j) is divisible by (j+1) because r·(n−j)/(j+1) = C(n, j+1).
            r = r * u128::from(n - j) / u128::from(j + 1);
        }
        r as f64
    } else {
        (0..k).fold(1.0, |r, j| r * f64::from(n - j) / f64::from(j + 1))
    }
}

/// One Bernstein polynomial `B_i^n(t) = C(n,i) tⁱ (1−t)ⁿ⁻ⁱ` (Farin 2002,
/// eq. 5.5), and 0 when `i > n`.
#[inline]
pub fn bernstein(n: u32, i: u32, t: f64) -> f64 {
    if i > n {
        return 0.0;
    }
    binomial(n, i) * t.powi(i as i32) * (1.0 - t).powi((n - i) as i32)
}

/// Fills `out` with all `B_0^n(t), …, B_n^n(t)` for `n = out.len() − 1`
/// (an empty slice is left alone), without allocation.
///
/// Uses the stable triangular recurrence `B_i^n = (1−t) B_i^{n−1} + t B_{i−1}^{n−1}`
/// (Piegl & Tiller, *The NURBS Book*, 2nd ed., Algorithm A1.3 "AllBernstein"),
/// which needs no binomials and only convex combinations for `t ∈ [0, 1]`.
#[inline]
pub fn bernstein_all(t: f64, out: &mut [f64]) {
    let Some((first, _)) = out.split_first_mut() else {
        return;
    };
    *first = 1.0;
    let mt = 1.0 - t;
    for j in 1..out.len() {
        let mut saved = 0.0;
        for b in &mut out[..j] {
            let tmp = *b;
            *b = saved + mt * tmp;
            saved = t * tmp;
        }
        out[j] = saved;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomials_are_exact() {
        assert_eq!(binomial(0, 0), 1.0);
        assert_eq!(binomial(5, 2), 10.0);
        assert_eq!(binomial(5, 6), 0.0);
        assert_eq!(binomial(30, 15), 155_117_520.0);
        assert_eq!(binomial(52, 5), 2_598_960.0);
        assert_eq!(binomial(56, 28), 7_648_690_600_760_440.0);
        // Pascal's rule holds exactly up to n = 56.
        for n in 1..=56u32 {
            for k in 1..n {
                assert_eq!(
                    binomial(n, k),
                    binomial(n - 1, k - 1) + binomial(n - 1, k),
                    "n={n} k={k}"
                );
            }
        }
        // Floating-point fallback agrees with the integer path's scale.
        let big = binomial(200, 3);
        assert!((big - 1_313_400.0).abs() < 1e-6);
    }

    #[test]
    fn partition_of_unity_and_symmetry() {
        for n in 0..=30u32 {
            let mut all = vec![0.0; n as usize + 1];
            for k in 0..=20 {
                let t = f64::from(k) / 20.0;
                bernstein_all(t, &mut all);
                let sum: f64 = all.iter().sum();
                assert!((sum - 1.0).abs() < 1e-13, "n={n} t={t} sum={sum}");
                for i in 0..=n {
                    let b = bernstein(n, i, t);
                    assert!(b >= 0.0);
                    assert!((b - all[i as usize]).abs() < 1e-13, "n={n} i={i} t={t}");
                    // Symmetry B_i^n(t) = B_{n−i}^n(1 − t).
                    let s = bernstein(n, n - i, 1.0 - t);
                    assert!((b - s).abs() < 1e-14, "n={n} i={i} t={t}");
                }
            }
        }
        assert_eq!(bernstein(3, 4, 0.5), 0.0);
    }

    #[test]
    fn all_handles_small_slices() {
        let mut empty: [f64; 0] = [];
        bernstein_all(0.3, &mut empty);
        let mut one = [7.0];
        bernstein_all(0.3, &mut one);
        assert_eq!(one, [1.0]);
        let mut two = [0.0; 2];
        bernstein_all(0.25, &mut two);
        assert_eq!(two, [0.75, 0.25]);
        let mut four = [0.0; 4];
        bernstein_all(0.5, &mut four);
        assert_eq!(four, [0.125, 0.375, 0.375, 0.125]);
    }
}
