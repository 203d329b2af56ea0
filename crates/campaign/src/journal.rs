//! The journal of a running campaign: each finished run is appended to
//! `journal.csv` as one self-checking line, so that an interrupted campaign
//! resumes without losing finished runs.
//!
//! A line holds the `runs.csv` fields (in the layout without instances),
//! the convergence trace as `evaluations:best|...`, the fit detail of a
//! fitting run, the wall time, the transform, the instance, the target hits
//! as `precision:evaluations|...`, and the sentinel `ok`; a line without its
//! sentinel is the trace of an interruption and is dropped when it is the
//! last one. Lines written before the transform, instance and hits existed
//! (the sentinel right after the wall time) are read as untransformed runs
//! without hits, so older campaigns still resume.

use std::path::Path;

use super::records::{
    data, parse, parse_real, parse_transform, record_from_fields, run_fields, DataProblem,
    FitDetail, ReadError, Real, RunRecord, FIT_FIELDS, FIT_FIELDS_CURRENT, FIT_FIELDS_RMS,
    RUNS_HEADER,
};
use super::segments::{FIT_SEGMENT_HEADER, SEGMENT_HEADER};
use crate::files::{fmt_real, IoError};
use crate::optim::{TargetHit, TracePoint};

/// Fields of a line before its sentinel, after the `runs.csv` ones: the
/// current layout and the one before transforms and hits.
const EXTRA: usize = 6;
const EXTRA_BEFORE_INSTANCES: usize = 3;

/// One journal line (no header): the `runs.csv` fields, the trace as
/// `evaluations:best|...`, the fit detail, the wall time, the transform,
/// the instance, the hits, and the sentinel `ok` that marks the line as
/// complete.
pub fn journal_line(r: &RunRecord) -> Vec<u8> {
    let mut fields = run_fields(r);
    let trace: Vec<String> = r
        .trace
        .iter()
        .map(|p| format!("{}:{}", p.evaluations, fmt_real(p.best)))
        .collect();
    fields.push(trace.join("|"));
    fields.push(r.fit.as_ref().map_or(String::new(), fit_field));
    fields.push(fmt_real(r.wall_seconds));
    fields.push(r.transform.name().to_owned());
    fields.push(r.instance.to_string());
    let hits: Vec<String> = r
        .hits
        .iter()
        .map(|h| format!("{}:{}", fmt_real(h.precision), h.evaluations))
        .collect();
    fields.push(hits.join("|"));
    fields.push("ok".into());
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(&fields).expect("writing to memory");
    w.into_inner().expect("writing to memory")
}

/// Reads the records of a journal, ignoring an incomplete last line (the
/// trace of an interruption); a malformed line elsewhere is an error. The
/// file is read a line at a time (one line ahead, to know the last), so a
/// resume holds the records, not the journal's text.
pub fn read_journal(path: &Path) -> Result<Vec<RunRecord>, ReadError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::new("read", path, e))?;
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(std::io::BufReader::new(file));
    let mut rows = reader.records().peekable();
    let mut out = Vec::new();
    let mut line = 0u64;
    while let Some(row) = rows.next() {
        line += 1;
        let last = rows.peek().is_none();
        let complete = match &row {
            Ok(r) => [EXTRA, EXTRA_BEFORE_INSTANCES].iter().any(|extra| {
                r.len() == RUNS_HEADER.len() + extra + 1
                    && r.get(RUNS_HEADER.len() + extra) == Some("ok")
            }),
            Err(_) => false,
        };
        if !complete {
            if last {
                break;
            }
            let at = row
                .as_ref()
                .ok()
                .and_then(|r| r.position())
                .map_or(line, |p| p.line());
            return Err(data(path, at, DataProblem::Malformed("journal line")));
        }
        let r = row.expect("checked above");
        let line = r.position().map_or(line, |p| p.line());
        let mut rec = record_from_fields(path, line, &r)?;
        for (column, at) in [("best", 8), ("error", 9)] {
            parse_real(path, line, column, &r[at], Real::NotNan)?;
        }
        let trace_text = r.get(RUNS_HEADER.len()).unwrap_or("");
        if !trace_text.is_empty() {
            for part in trace_text.split('|') {
                let (e, b) = part
                    .split_once(':')
                    .ok_or_else(|| data(path, line, DataProblem::Malformed("trace")))?;
                rec.trace.push(TracePoint {
                    evaluations: parse(path, line, "trace", e)?,
                    best: parse_real(path, line, "trace", b, Real::NotNan)?,
                });
            }
        }
        let fit_text = r.get(RUNS_HEADER.len() + 1).unwrap_or("");
        if !fit_text.is_empty() {
            rec.fit = Some(fit_from_field(path, line, fit_text)?);
        }
        rec.wall_seconds = parse_real(
            path,
            line,
            "wall_seconds",
            r.get(RUNS_HEADER.len() + 2).unwrap_or(""),
            Real::NonNegative,
        )?;
        if r.len() == RUNS_HEADER.len() + EXTRA + 1 {
            let at = |k: usize| r.get(RUNS_HEADER.len() + k).unwrap_or("");
            rec.transform = parse_transform(path, line, at(3))?;
            rec.instance = parse(path, line, "instance", at(4))?;
            rec.hits = hits_from_field(path, line, at(5))?;
        }
        out.push(rec);
    }
    Ok(out)
}

/// Reads the hits field `precision:evaluations|...` back.
fn hits_from_field(path: &Path, line: u64, text: &str) -> Result<Vec<TargetHit>, ReadError> {
    if text.is_empty() {
        return Ok(Vec::new());
    }
    text.split('|')
        .map(|part| {
            let (p, e) = part
                .split_once(':')
                .ok_or_else(|| data(path, line, DataProblem::Malformed("hits")))?;
            Ok(TargetHit {
                precision: parse_real(path, line, "hits", p, Real::Positive)?,
                evaluations: parse(path, line, "hits", e)?,
            })
        })
        .collect()
}

/// One journal field: the run-level fields joined by `;`, then each
/// segment row joined by `;`, all separated by `|`.
fn fit_field(detail: &FitDetail) -> String {
    std::iter::once(detail.fields().join(";"))
        .chain(detail.segments.iter().map(|r| r.join(";")))
        .collect::<Vec<_>>()
        .join("|")
}

/// Reads [`fit_field`] back.
fn fit_from_field(path: &Path, line: u64, text: &str) -> Result<FitDetail, ReadError> {
    let mut parts = text.split('|');
    let head: Vec<&str> = parts.next().unwrap_or("").split(';').collect();
    let current = head.len() == FIT_FIELDS_CURRENT.len() || head.len() == FIT_FIELDS_RMS.len();
    if head.len() != FIT_FIELDS.len() && !current {
        return Err(data(path, line, DataProblem::Malformed("fit detail")));
    }
    let mut detail = FitDetail::from_fields(path, line, &head)?;
    for part in parts {
        let row: Vec<String> = part.split(';').map(str::to_owned).collect();
        let width = if current {
            FIT_SEGMENT_HEADER.len()
        } else {
            SEGMENT_HEADER.len()
        };
        if row.len() != width {
            return Err(data(
                path,
                line,
                DataProblem::Malformed("segment in the fit detail"),
            ));
        }
        detail.segments.push(row);
    }
    Ok(detail)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::sample_record;

    #[test]
    fn lines_written_before_instances_and_hits_still_resume() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        let mut legacy = sample_record(4);
        legacy.transform = crate::functions::Transform::None;
        legacy.instance = 1;
        legacy.hits.clear();
        legacy.algorithm = "HS".into();
        // The layout before: runs fields, trace, fit, wall time, ok.
        let line = String::from_utf8(journal_line(&legacy)).unwrap();
        let fields: Vec<&str> = line.trim_end().rsplitn(5, ',').collect();
        let old = format!("{},ok\n", fields[4]);
        assert_eq!(
            old.matches(',').count(),
            RUNS_HEADER.len() + EXTRA_BEFORE_INSTANCES
        );
        std::fs::write(&path, old).unwrap();
        assert_eq!(read_journal(&path).unwrap(), vec![legacy]);
    }

    #[test]
    fn journal_round_trips_and_drops_a_torn_last_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        let mut bytes = journal_line(&sample_record(0));
        bytes.extend(journal_line(&sample_record(1)));
        let torn = journal_line(&sample_record(2));
        bytes.extend(&torn[..torn.len() - 5]);
        std::fs::write(&path, &bytes).unwrap();
        let back = read_journal(&path).unwrap();
        assert_eq!(back, vec![sample_record(0), sample_record(1)]);
    }

    #[test]
    fn a_malformed_line_in_the_middle_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        let mut bytes = b"garbage,line\n".to_vec();
        bytes.extend(journal_line(&sample_record(1)));
        std::fs::write(&path, &bytes).unwrap();
        let err = read_journal(&path).unwrap_err().to_string();
        assert!(
            err.ends_with("journal.csv:1: malformed journal line"),
            "{err}"
        );
    }
}
