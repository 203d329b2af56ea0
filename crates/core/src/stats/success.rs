//! Success-based performance measures over independent runs: success rate,
//! mean evaluations to success and COCO's average runtime (aRT).

use super::error::{check_no_nan, check_non_empty, StatsError};

/// Outcome of one run with respect to a target: whether the target was reached
/// and how many function evaluations were spent (until the target was first
/// reached for a successful run, in total for an unsuccessful one), as in
/// Hansen et al. (2016), "COCO: Performance Assessment", arXiv:1605.03560.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct RunOutcome {
    /// Evaluations spent: until the first success, or the whole run when it failed.
    pub evaluations: u64,
    /// Whether the run reached the target (error ≤ threshold).
    pub success: bool,
}

impl RunOutcome {
    /// A run outcome from its evaluation count and success flag (see [`RunOutcome`]).
    pub fn new(evaluations: u64, success: bool) -> Self {
        Self {
            evaluations,
            success,
        }
    }
}

/// Success measures of a set of runs: success rate #successes / #runs, mean
/// evaluations over the successful runs, and aRT = Σ evaluations / #successes
/// (Hansen et al. 2016, "COCO: Performance Assessment", arXiv:1605.03560).
#[derive(Clone, Debug, PartialEq)]
pub struct SuccessSummary {
    /// Number of runs.
    pub runs: usize,
    /// Number of successful runs.
    pub successes: usize,
    /// Fraction of successful runs, in [0, 1].
    pub success_rate: f64,
    /// Mean evaluations to success over the successful runs; `None` without success.
    pub mean_evaluations_to_success: Option<f64>,
    /// Average runtime aRT; `None` (infinite) without success.
    pub average_runtime: Option<f64>,
}

/// Success rate #{i : errorᵢ ≤ threshold} / n of final errors (the empirical
/// success probability of Hansen et al. 2016, "COCO: Performance Assessment",
/// arXiv:1605.03560).
///
/// Errors on an empty slice, on NaN errors or on a NaN threshold.
pub fn success_rate(errors: &[f64], threshold: f64) -> Result<f64, StatsError> {
    check_non_empty(errors, "errors")?;
    check_no_nan(errors, "errors")?;
    if threshold.is_nan() {
        return Err(StatsError::InvalidParameter {
            name: "threshold",
            reason: "the success threshold must not be NaN",
        });
    }
    let hits = errors.iter().filter(|&&e| e <= threshold).count();
    Ok(hits as f64 / errors.len() as f64)
}

/// Mean evaluations to success Σ_{successful} evaluationsᵢ / #successes, the
/// mean runtime of successful runs (Hansen et al. 2016, arXiv:1605.03560);
/// `Ok(None)` when no run succeeded, an error when there is no run.
pub fn mean_evaluations_to_success(runs: &[RunOutcome]) -> Result<Option<f64>, StatsError> {
    Ok(success_summary(runs)?.mean_evaluations_to_success)
}

/// COCO average runtime aRT = (Σ over all runs of the evaluations spent) /
/// #successes (Hansen et al. 2016, "COCO: Performance Assessment",
/// arXiv:1605.03560; Price 1997's expected running time); `Ok(None)` stands for
/// an infinite aRT when no run succeeded, an error when there is no run.
pub fn average_runtime(runs: &[RunOutcome]) -> Result<Option<f64>, StatsError> {
    Ok(success_summary(runs)?.average_runtime)
}

/// All success measures of [`SuccessSummary`] in one pass (Hansen et al. 2016,
/// "COCO: Performance Assessment", arXiv:1605.03560); errors when there is no run.
pub fn success_summary(runs: &[RunOutcome]) -> Result<SuccessSummary, StatsError> {
    if runs.is_empty() {
        return Err(StatsError::EmptyInput { what: "runs" });
    }
    let mut successes = 0usize;
    let mut total: u128 = 0;
    let mut successful: u128 = 0;
    for r in runs {
        total += u128::from(r.evaluations);
        if r.success {
            successes += 1;
            successful += u128::from(r.evaluations);
        }
    }
    let (mean_evaluations_to_success, average_runtime) = if successes == 0 {
        (None, None)
    } else {
        let s = successes as f64;
        (Some(successful as f64 / s), Some(total as f64 / s))
    };
    Ok(SuccessSummary {
        runs: runs.len(),
        successes,
        success_rate: successes as f64 / runs.len() as f64,
        mean_evaluations_to_success,
        average_runtime,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn success_rate_counts_threshold_inclusively() {
        let e = [1e-9, 1e-8, 1e-7, 0.5, 1e-8];
        assert_eq!(success_rate(&e, 1e-8).unwrap(), 0.6);
        assert_eq!(success_rate(&e, 0.0).unwrap(), 0.0);
        assert_eq!(success_rate(&e, f64::INFINITY).unwrap(), 1.0);
        assert!(success_rate(&[], 1.0).is_err());
        assert!(success_rate(&[f64::NAN], 1.0).is_err());
        assert!(success_rate(&[1.0], f64::NAN).is_err());
    }

    #[test]
    fn art_is_total_evaluations_over_successes() {
        // Hand computation: successes use 100 and 300 evaluations, failures
        // use the budget 1000 twice: aRT = (100 + 300 + 1000 + 1000) / 2 = 1200,
        // mean evaluations to success = (100 + 300) / 2 = 200, rate = 2/4.
        let runs = [
            RunOutcome::new(100, true),
            RunOutcome::new(1000, false),
            RunOutcome::new(300, true),
            RunOutcome::new(1000, false),
        ];
        let s = success_summary(&runs).unwrap();
        assert_eq!(s.runs, 4);
        assert_eq!(s.successes, 2);
        assert_eq!(s.success_rate, 0.5);
        assert_eq!(s.mean_evaluations_to_success, Some(200.0));
        assert_eq!(s.average_runtime, Some(1200.0));
        assert_eq!(average_runtime(&runs).unwrap(), Some(1200.0));
        assert_eq!(mean_evaluations_to_success(&runs).unwrap(), Some(200.0));
    }

    #[test]
    fn no_success_and_no_runs() {
        let runs = [RunOutcome::new(10, false); 3];
        assert_eq!(average_runtime(&runs).unwrap(), None);
        assert_eq!(mean_evaluations_to_success(&runs).unwrap(), None);
        assert_eq!(success_summary(&runs).unwrap().success_rate, 0.0);
        assert!(average_runtime(&[]).is_err());
        // No overflow with huge counts.
        let big = [
            RunOutcome::new(u64::MAX, true),
            RunOutcome::new(u64::MAX, true),
        ];
        assert_eq!(average_runtime(&big).unwrap(), Some(u64::MAX as f64));
    }
}
