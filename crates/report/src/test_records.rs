//! Run records for the unit tests: one run of an algorithm on a problem at
//! D = 2, with a budget of 1000 evaluations all spent, no hits and no
//! success; a test changes the fields it needs with struct update syntax.

use crate::experiment::RunRecord;
use crate::functions::Transform;

/// Run `run` of `algorithm` (kind `hs`, no parameters) on `problem` that
/// ended at `error`, seeded by its number.
pub(crate) fn record(algorithm: &str, problem: &str, run: u32, error: f64) -> RunRecord {
    RunRecord {
        algorithm: algorithm.into(),
        kind: "hs".into(),
        params: String::new(),
        problem: problem.into(),
        dim: 2,
        budget: 1000,
        transform: Transform::None,
        instance: 1,
        run,
        seed: u64::from(run),
        best: error,
        error,
        evaluations: 1000,
        evaluations_to_target: None,
        success: false,
        trace: Vec::new(),
        hits: Vec::new(),
        fit: None,
        wall_seconds: 0.0,
    }
}
