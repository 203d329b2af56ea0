//! Friedman's rank test for a blocks × treatments layout (Friedman 1937),
//! following `scipy.stats.friedmanchisquare`, plus the average rank of every
//! treatment as used for critical-difference diagrams (Demšar 2006).

use statrs::distribution::{ChiSquared, ContinuousCDF};

use super::error::StatsError;
use super::ranks::midranks_into;

/// Result of the Friedman test on N blocks and k treatments: χ²_F =
/// [12/(Nk(k+1)) Σⱼ Rⱼ² − 3N(k+1)] / C with C = 1 − Σ(t³−t)/(Nk(k²−1)) and p from
/// χ²(k−1) (Friedman 1937, J. Amer. Statist. Assoc. 32(200):675–701).
#[derive(Clone, Debug, PartialEq)]
pub struct FriedmanResult {
    /// The tie-corrected Friedman chi-square statistic.
    pub statistic: f64,
    /// Upper-tail p-value of the statistic under χ²(k − 1).
    pub p_value: f64,
    /// Degrees of freedom k − 1.
    pub df: usize,
    /// Number of blocks N (rows, e.g. problems).
    pub n_blocks: usize,
    /// Number of treatments k (columns, e.g. algorithms).
    pub n_treatments: usize,
    /// Average rank of every treatment over the blocks, Rⱼ/N; rank 1 is the
    /// smallest value (the best when minimising) and ties share midranks.
    pub average_ranks: Vec<f64>,
}

/// Friedman test of a blocks × treatments matrix given as rows (one row per
/// block, one column per treatment), ranking within rows (Friedman 1937, "The
/// use of ranks to avoid the assumption of normality implicit in the analysis of
/// variance", J. Amer. Statist. Assoc. 32(200):675–701); equals
/// `scipy.stats.friedmanchisquare(*columns)`.
///
/// Needs k ≥ 2 (SciPy requires k ≥ 3) and N ≥ 1, equal row lengths and no NaN;
/// if every row is entirely tied the statistic is 0 and p = 1 (SciPy gives NaN).
pub fn friedman<R: AsRef<[f64]>>(blocks: &[R]) -> Result<FriedmanResult, StatsError> {
    let n_blocks = blocks.len();
    if n_blocks == 0 {
        return Err(StatsError::EmptyInput { what: "blocks" });
    }
    let k = blocks[0].as_ref().len();
    if k < 2 {
        return Err(StatsError::InvalidParameter {
            name: "blocks",
            reason: "the Friedman test needs at least two treatments (columns)",
        });
    }
    for (i, row) in blocks.iter().enumerate() {
        let row = row.as_ref();
        if row.len() != k {
            return Err(StatsError::LengthMismatch {
                what: "rows of the blocks x treatments matrix",
                expected: k,
                found: row.len(),
            });
        }
        if let Some(j) = row.iter().position(|v| v.is_nan()) {
            return Err(StatsError::NotANumber {
                what: "blocks x treatments matrix (row-major index)",
                index: i * k + j,
            });
        }
    }

    let mut rank_sums = vec![0.0; k];
    let mut order = Vec::with_capacity(k);
    let mut ranks = Vec::with_capacity(k);
    let mut ties = 0.0;
    for row in blocks {
        midranks_into(row.as_ref(), &mut order, &mut ranks, |t| {
            let t = t as f64;
            ties += t * (t * t - 1.0);
        });
        for (s, r) in rank_sums.iter_mut().zip(&ranks) {
            *s += r;
        }
    }

    let (nf, kf) = (n_blocks as f64, k as f64);
    let c = 1.0 - ties / (kf * (kf * kf - 1.0) * nf);
    let ssbn: f64 = rank_sums.iter().map(|s| s * s).sum();
    let numerator = 12.0 / (kf * nf * (kf + 1.0)) * ssbn - 3.0 * nf * (kf + 1.0);
    let df = k - 1;
    let (statistic, p_value) = if c > 1e-12 {
        let stat = numerator / c;
        // df ≥ 1, so the distribution is always valid.
        let p = match ChiSquared::new(df as f64) {
            Ok(chi2) => chi2.sf(stat.max(0.0)),
            Err(_) => f64::NAN,
        };
        (stat, p.clamp(0.0, 1.0))
    } else {
        // All rows fully tied: no evidence of any difference.
        (0.0, 1.0)
    };
    let average_ranks = rank_sums.iter().map(|s| s / nf).collect();
    Ok(FriedmanResult {
        statistic,
        p_value,
        df,
        n_blocks,
        n_treatments: k,
        average_ranks,
    })
}
