//! The checks an external `runs.csv` (`report --external`) passes before
//! its runs join a comparison, so that another tool's runs are held to what
//! a campaign's own runs are: not the results directory's own file, finite
//! errors of at least 0 (a rounding below the optimum allowed), evaluations
//! within the budget, one row per run, labels that are not spreadsheet
//! formulas (OWASP, "CSV Injection"), and the results directory's problems
//! at its budgets. A refusal names the file, the line and what is wrong.

use std::collections::BTreeSet;
use std::path::Path;

use crate::experiment::records::RunRecord;

use super::integrity::runs_once;
use crate::ReportError;

/// How far below 0 a final error f − f* may be and still be read as the
/// rounding of f at the optimum (or of the tabulated f*), not as a wrong
/// f*: the six-hump camel's f(x*) rounds 2.2·10⁻¹⁶ below f* in f64. The
/// report shows such an error as 0 and accepts it in an external file.
pub(crate) const BELOW_OPTIMUM_ROUNDING: f64 = 1e-12;

/// The first characters a spreadsheet reads as a formula.
const FORMULA_STARTS: [char; 6] = ['=', '+', '-', '@', '\t', '\r'];

/// Refuses the external runs `theirs` (read from `ext`, one record per
/// line from line 2, in file order) against the results directory `dir`'s
/// own runs `ours`.
pub(crate) fn check_external<'r>(
    dir: &Path,
    ext: &Path,
    ours: impl Iterator<Item = &'r RunRecord>,
    theirs: &[RunRecord],
) -> Result<(), ReportError> {
    let refuse = |line: usize, message: String| ReportError::External {
        path: ext.to_owned(),
        line,
        message,
    };
    let own = dir.join("runs.csv");
    if let (Ok(a), Ok(b)) = (std::fs::canonicalize(ext), std::fs::canonicalize(&own)) {
        if a == b {
            return Err(refuse(
                0,
                "is the results directory's own runs.csv: its runs would be compared with \
                 themselves"
                    .into(),
            ));
        }
    }
    let problems: BTreeSet<(String, u64)> = ours.map(|r| (r.match_key(), r.budget)).collect();
    let repeat = runs_once(theirs).err();
    for (i, r) in theirs.iter().enumerate() {
        let line = i + 2;
        if let Some(why) = row_problem(r) {
            return Err(refuse(line, why));
        }
        if repeat == Some(i) {
            return Err(refuse(
                line,
                format!(
                    "run {} of {} on {} at budget {} appears twice; one row per run",
                    r.run,
                    r.algorithm,
                    r.match_key(),
                    r.budget
                ),
            ));
        }
        if !problems.contains(&(r.match_key(), r.budget)) {
            let known: Vec<String> = problems
                .iter()
                .take(6)
                .map(|(p, b)| format!("{p} at {b}"))
                .collect();
            return Err(refuse(
                line,
                format!(
                    "problem {} at budget {} is not one of the results directory's ({}{}): \
                     runs are compared on the same problems at the same budgets",
                    r.match_key(),
                    r.budget,
                    known.join(", "),
                    if problems.len() > 6 { ", …" } else { "" }
                ),
            ));
        }
    }
    Ok(())
}

/// What is wrong with one external run on its own, if anything.
fn row_problem(r: &RunRecord) -> Option<String> {
    if r.algorithm.starts_with(FORMULA_STARTS) {
        return Some(format!(
            "label \"{}\" starts like a spreadsheet formula ({}); a label starts with a \
             letter or a digit",
            crate::files::excerpt(&r.algorithm),
            "=, +, -, @, a tab or a carriage return"
        ));
    }
    if !(r.error.is_finite() && r.error >= -BELOW_OPTIMUM_ROUNDING) {
        return Some(format!(
            "error {} of run {} of {}: expected a finite number of at least 0 (f − f*)",
            r.error, r.run, r.algorithm
        ));
    }
    if r.evaluations > r.budget {
        return Some(format!(
            "run {} of {} used {} evaluations, over its budget of {}",
            r.run, r.algorithm, r.evaluations, r.budget
        ));
    }
    None
}
