//! Nemenyi post-hoc test: the critical difference of average ranks
//! (Nemenyi 1963; tabulated by Demšar 2006).

use super::error::StatsError;

/// q_α for α = 0.05 and k = 2..=10 (Demšar 2006, JMLR 7:1–30, Table 5a):
/// studentized-range quantiles divided by √2.
const Q_05: [f64; 9] = [
    1.960, 2.343, 2.569, 2.728, 2.850, 2.949, 3.031, 3.102, 3.164,
];
/// q_α for α = 0.10 and k = 2..=10 (Demšar 2006, JMLR 7:1–30, Table 5a).
const Q_10: [f64; 9] = [
    1.645, 2.052, 2.291, 2.459, 2.589, 2.693, 2.780, 2.855, 2.920,
];

/// The Nemenyi critical value q_α (studentized range statistic / √2) for k
/// treatments, from Demšar (2006), "Statistical comparisons of classifiers over
/// multiple data sets", JMLR 7:1–30, Table 5(a); only k = 2..=10 and α ∈ {0.05, 0.10}.
pub fn nemenyi_q(k: usize, alpha: f64) -> Result<f64, StatsError> {
    let table = if (alpha - 0.05).abs() < 1e-12 {
        &Q_05
    } else if (alpha - 0.10).abs() < 1e-12 {
        &Q_10
    } else {
        return Err(StatsError::OutOfTable { k, alpha });
    };
    if (2..=10).contains(&k) {
        Ok(table[k - 2])
    } else {
        Err(StatsError::OutOfTable { k, alpha })
    }
}

/// Nemenyi critical difference CD = q_α·sqrt(k(k+1)/(6N)) for k treatments
/// ranked on N blocks: two average ranks differing by at least CD differ
/// significantly (Nemenyi 1963, PhD thesis, Princeton; Demšar 2006, JMLR 7:1–30).
///
/// Errors outside the q_α table (see [`nemenyi_q`]) or when N = 0.
pub fn nemenyi_critical_difference(
    k: usize,
    n_blocks: usize,
    alpha: f64,
) -> Result<f64, StatsError> {
    let q = nemenyi_q(k, alpha)?;
    if n_blocks == 0 {
        return Err(StatsError::InvalidParameter {
            name: "n_blocks",
            reason: "the critical difference needs at least one block",
        });
    }
    let (k, n) = (k as f64, n_blocks as f64);
    Ok(q * (k * (k + 1.0) / (6.0 * n)).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_values_and_cd() {
        // Demšar (2006), Table 5(a).
        assert_eq!(nemenyi_q(2, 0.05).unwrap(), 1.960);
        assert_eq!(nemenyi_q(4, 0.05).unwrap(), 2.569);
        assert_eq!(nemenyi_q(10, 0.05).unwrap(), 3.164);
        assert_eq!(nemenyi_q(5, 0.10).unwrap(), 2.459);
        assert_eq!(nemenyi_q(10, 0.1).unwrap(), 2.920);
        // Demšar (2006), Section 3.2.4 example: k = 4, N = 14, α = 0.05 → CD = 1.25;
        // α = 0.10 → CD = 1.12.
        let cd = nemenyi_critical_difference(4, 14, 0.05).unwrap();
        assert!((cd - 2.569 * (20.0f64 / 84.0).sqrt()).abs() < 1e-12);
        assert!((cd - 1.25).abs() < 0.005);
        let cd10 = nemenyi_critical_difference(4, 14, 0.10).unwrap();
        assert!((cd10 - 1.12).abs() < 0.005);
    }

    #[test]
    fn scipy_studentized_range_agrees_to_table_precision() {
        // scipy 1.17.1: scipy.stats.studentized_range.ppf(1 - a, k, inf) / sqrt(2)
        // (rounded to 5 decimals)
        // a = 0.05: [1.95996, 2.3437, 2.56903, 2.72777, 2.84971, 2.94832, 3.03088, 3.10173, 3.16368]
        // a = 0.10: [1.64485, 2.05229, 2.29134, 2.45952, 2.58852, 2.69273, 2.77988, 2.85461, 2.91989]
        let scipy_05 = [
            1.95996, 2.3437, 2.56903, 2.72777, 2.84971, 2.94832, 3.03088, 3.10173, 3.16368,
        ];
        let scipy_10 = [
            1.64485, 2.05229, 2.29134, 2.45952, 2.58852, 2.69273, 2.77988, 2.85461, 2.91989,
        ];
        for (k, (s05, s10)) in (2..=10).zip(scipy_05.into_iter().zip(scipy_10)) {
            assert!((nemenyi_q(k, 0.05).unwrap() - s05).abs() < 1e-3, "k = {k}");
            assert!((nemenyi_q(k, 0.10).unwrap() - s10).abs() < 1e-3, "k = {k}");
        }
    }

    #[test]
    fn outside_the_table() {
        assert!(matches!(
            nemenyi_q(1, 0.05),
            Err(StatsError::OutOfTable { k: 1, .. })
        ));
        assert!(nemenyi_q(11, 0.05).is_err());
        assert!(nemenyi_q(3, 0.01).is_err());
        assert!(nemenyi_q(3, f64::NAN).is_err());
        assert!(nemenyi_critical_difference(3, 0, 0.05).is_err());
        assert!(nemenyi_critical_difference(12, 5, 0.05).is_err());
    }
}
