//! A journal row checked against itself and against the spec before a
//! resume trusts it, so that an edited or damaged `best`, `seed` or other
//! field never reaches `runs.csv`.
//!
//! The choice made: each row carries a **checksum**, FNV-1a 64 (the hash of
//! the seed derivation, [`crate::rng::fnv1a64`]) of its fields before it
//! joined by the unit separator U+001F, as 16 hexadecimal digits, so an edit
//! of any field (best, error, evaluations, the trace, the fit detail, the
//! hits) is seen. A row written before checksums existed (the layouts the
//! journal still reads) is checked by its **trace** instead: for a run that
//! is not a fit, its `best` and `evaluations` must be the trace's last
//! point, which the evaluator always ends a run with (a fit's trace ends
//! before its chain's last evaluations, so an old fit row has only the
//! spec's checks). Against the spec, every row's `seed` must be the one
//! derived for its run ([`crate::runner::run_seed`]), and its `error` must
//! be `best − f*` of its problem.
//!
//! A row that disagrees is not an error: it is dropped, its run is redone,
//! and the resume names the journal, the line and the field
//! ([`crate::Summary::dropped`]).

use std::collections::HashMap;
use std::path::Path;

use crate::files::fmt_real;
use crate::records::RunRecord;

/// One complete line of a journal, read.
#[derive(Clone, Debug, PartialEq)]
pub struct JournalRow {
    /// Its line in the journal, from 1.
    pub line: u64,
    /// The run it records.
    pub record: RunRecord,
    /// Where the line disagrees with itself (its checksum, or for a line
    /// written before checksums its trace), if it does: such a row is not
    /// to be trusted and its run is to be redone.
    pub problem: Option<RowProblem>,
}

/// Where a journal row disagrees with itself or with the spec.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("field {field}: {reason}")]
pub struct RowProblem {
    /// The field that disagrees (`checksum` when the checksum alone says
    /// that some field was changed).
    pub field: &'static str,
    /// How it disagrees.
    pub reason: String,
}

impl RowProblem {
    fn new(field: &'static str, reason: String) -> Self {
        RowProblem { field, reason }
    }
}

/// The checksum of a journal line's fields before it: FNV-1a 64 of the
/// fields joined by U+001F, as 16 lowercase hexadecimal digits.
pub(crate) fn checksum<S: AsRef<str>>(fields: &[S]) -> String {
    let joined: Vec<&str> = fields.iter().map(AsRef::as_ref).collect();
    format!("{:016x}", crate::rng::fnv1a64(&joined.join("\u{1f}")))
}

/// Whether the complete journal line `r` (its last field the sentinel)
/// disagrees with itself: with `has_checksum`, the checksum before the
/// sentinel against its other fields (the trace naming the field where it
/// can), else the trace alone ([`trace_problem`]).
pub(crate) fn check_row(
    r: &csv::StringRecord,
    has_checksum: bool,
    record: &RunRecord,
) -> Option<RowProblem> {
    if !has_checksum {
        return trace_problem(record);
    }
    let fields: Vec<&str> = r.iter().collect();
    let (before, checksum_field) = (&fields[..fields.len() - 2], fields[fields.len() - 2]);
    if checksum(before) == checksum_field {
        return None;
    }
    trace_problem(record).or_else(|| {
        Some(RowProblem::new(
            "checksum",
            "the row's fields do not give its checksum: a field was edited or damaged".into(),
        ))
    })
}

/// Whether the `best` or `evaluations` of a run that is not a fit differ
/// from its trace's last point (a run without a trace, or a fit, has
/// nothing to compare).
fn trace_problem(r: &RunRecord) -> Option<RowProblem> {
    let last = r.trace.last().filter(|_| r.fit.is_none())?;
    if last.best != r.best {
        return Some(RowProblem::new(
            "best",
            format!(
                "{} is not the trace's last best, {} at evaluation {}",
                fmt_real(r.best),
                fmt_real(last.best),
                last.evaluations
            ),
        ));
    }
    (last.evaluations != r.evaluations).then(|| {
        RowProblem::new(
            "evaluations",
            format!(
                "{} is not the trace's last evaluation count, {}",
                r.evaluations, last.evaluations
            ),
        )
    })
}

/// Whether run `r` disagrees with what the spec gives its run: its seed
/// with `seed`, the one derived for it ([`crate::runner::run_seed`]), or
/// its error with `best − optimum`.
fn check_against_spec(r: &RunRecord, seed: u64, optimum: f64) -> Option<RowProblem> {
    if r.seed != seed {
        return Some(RowProblem::new(
            "seed",
            format!(
                "{} is not the seed the spec derives for this run, {seed}",
                r.seed
            ),
        ));
    }
    let error = r.best - optimum;
    (r.error != error).then(|| {
        RowProblem::new(
            "error",
            format!(
                "{} is not best − f* of this run, {}",
                fmt_real(r.error),
                fmt_real(error)
            ),
        )
    })
}

/// The runs a resume keeps, by position in the spec's fixed order, and a
/// located message for each journal row it dropped.
pub(crate) type Recovered = (HashMap<usize, RunRecord>, Vec<String>);

/// The runs of `rows` (read from the journal at `journal`) that a resume
/// keeps, by their position in the spec's fixed order (`position`), and a
/// located message for each row dropped because it disagrees with itself
/// or with what the spec gives its run (`expected`: the derived seed and
/// `f*` of a position). A row of a run the spec does not define is the
/// error, returned as its record, unless the row also disagrees with
/// itself (then its key may be what was damaged).
pub(crate) fn trusted_rows(
    rows: Vec<JournalRow>,
    journal: &Path,
    position: impl Fn(&RunRecord) -> Option<usize>,
    expected: impl Fn(usize) -> (u64, f64),
) -> Result<Recovered, Box<RunRecord>> {
    let mut done = HashMap::new();
    let mut dropped = Vec::new();
    for row in rows {
        let position = position(&row.record);
        let against_spec = position.and_then(|i| {
            let (seed, optimum) = expected(i);
            check_against_spec(&row.record, seed, optimum)
        });
        // The most telling field: the checksum says only that some field
        // changed, the spec's checks say which.
        let problem = match (row.problem, against_spec) {
            (Some(own), Some(theirs)) if own.field == "checksum" => Some(theirs),
            (own, theirs) => own.or(theirs),
        };
        match (position, problem) {
            (_, Some(p)) => dropped.push(format!(
                "{}:{}: {p}; the row is dropped and its run redone",
                journal.display(),
                row.line
            )),
            (Some(i), None) => {
                done.insert(i, row.record);
            }
            (None, None) => return Err(Box::new(row.record)),
        }
    }
    Ok((done, dropped))
}
