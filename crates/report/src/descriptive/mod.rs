//! Descriptive statistics of the final errors and the success measures of
//! every (cell, problem); [`table`] renders them.

mod table;
#[cfg(test)]
mod tests;

use crate::stats::{success_summary, summarize, RunOutcome, SuccessSummary, Summary};

use super::data::{Dataset, Run};
use super::external::BELOW_OPTIMUM_ROUNDING;

pub(crate) use self::table::{mean_sd, table};

/// The statistics of one (cell, problem).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CellStats {
    /// Number of runs.
    pub runs: usize,
    /// Summary of the final errors; `None` when an error is NaN.
    pub summary: Option<Summary>,
    /// Success rate, mean evaluations to success and aRT.
    pub success: Option<SuccessSummary>,
}

/// The COCO outcome of a run: for a successful run the evaluations until the
/// target was first reached, for an unsuccessful one all its evaluations.
pub(crate) fn outcome(r: &Run) -> RunOutcome {
    if r.success {
        RunOutcome::new(r.evaluations_to_target.unwrap_or(r.evaluations), true)
    } else {
        RunOutcome::new(r.evaluations, false)
    }
}

/// `stats[problem][cell]`, `None` where the cell did not run the problem.
pub(crate) fn compute(ds: &Dataset) -> Vec<Vec<Option<CellStats>>> {
    (0..ds.problems.len())
        .map(|p| {
            (0..ds.cells.len())
                .map(|c| {
                    let runs = ds.runs(p, c);
                    if runs.is_empty() {
                        return None;
                    }
                    let errors: Vec<f64> = runs.iter().map(|r| r.error).collect();
                    let outcomes: Vec<RunOutcome> = runs.iter().map(outcome).collect();
                    Some(CellStats {
                        runs: runs.len(),
                        summary: summarize(&errors).ok(),
                        success: success_summary(&outcomes).ok(),
                    })
                })
                .collect()
        })
        .collect()
}

/// A final error as the report shows it: an error in
/// (−[`BELOW_OPTIMUM_ROUNDING`], 0) is 0 (the CSV keeps the value).
pub(crate) fn shown_error(x: f64) -> f64 {
    if x < 0.0 && x > -BELOW_OPTIMUM_ROUNDING {
        0.0
    } else {
        x
    }
}

/// The mean final error of a cell on a problem, when defined.
pub(crate) fn mean_error(stats: &[Vec<Option<CellStats>>], p: usize, c: usize) -> Option<f64> {
    stats
        .get(p)?
        .get(c)?
        .as_ref()?
        .summary
        .as_ref()
        .map(|s| s.mean)
}
