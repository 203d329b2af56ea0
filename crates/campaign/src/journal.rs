//! The journal of a running campaign: each finished run is appended to
//! `journal.csv` as one self-checking line, so that an interrupted campaign
//! resumes without losing finished runs.
//!
//! A line holds the `runs.csv` fields (in the layout without instances),
//! the convergence trace as `evaluations:best|...`, the fit detail of a
//! fitting run, the wall time, the transform, the instance, the target hits
//! as `precision:evaluations|...`, a checksum of these fields, and the
//! sentinel `ok`; a line without its sentinel is the trace of an
//! interruption and is dropped when it is the last one. Lines written
//! before the checksum existed are read as they are (checked by their trace
//! instead, see [`crate::journal_check`]); lines written before the
//! transform, instance and hits existed (the sentinel right after the wall
//! time) are read as untransformed runs without hits, so older campaigns
//! still resume.

use std::path::Path;

use super::journal_check::{check_row, checksum};
pub use super::journal_check::{JournalRow, RowProblem};
#[cfg(test)]
use super::reading::MAX_RESULT_LINE_BYTES;
use super::reading::{open_csv, JOURNAL_LIMITS};
use super::records::{
    data, parse, parse_real, parse_transform, record_from_fields, run_fields, DataProblem,
    FitDetail, ReadError, Real, RunRecord, FIT_FIELDS, FIT_FIELDS_CURRENT, FIT_FIELDS_RMS,
    RUNS_HEADER,
};
use super::segments::{FIT_SEGMENT_HEADER, SEGMENT_HEADER};
use crate::files::fmt_real;
use crate::optim::{TargetHit, TracePoint};

/// Fields of a line before its sentinel, after the `runs.csv` ones: the
/// current layout (ending with the checksum), the one before checksums and
/// the one before transforms and hits.
const EXTRA: usize = 7;
const EXTRA_BEFORE_CHECKSUM: usize = 6;
const EXTRA_BEFORE_INSTANCES: usize = 3;

/// One journal line (no header): the `runs.csv` fields, the trace as
/// `evaluations:best|...`, the fit detail, the wall time, the transform,
/// the instance, the hits, the checksum of these fields (`checksum`),
/// and the sentinel `ok` that marks the line as complete.
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
    fields.push(checksum(&fields));
    fields.push("ok".into());
    let mut w = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    w.write_record(&fields).expect("writing to memory");
    w.into_inner().expect("writing to memory")
}

/// Reads the records of a journal, ignoring an incomplete last line (the
/// trace of an interruption) and the rows that disagree with themselves
/// ([`read_journal_rows`]); a malformed line elsewhere is an error.
pub fn read_journal(path: &Path) -> Result<Vec<RunRecord>, ReadError> {
    Ok(read_journal_rows(path)?
        .into_iter()
        .filter(|r| r.problem.is_none())
        .map(|r| r.record)
        .collect())
}

/// Reads every complete line of a journal, each checked against itself
/// (`check_row`), ignoring an incomplete last line (the trace of an
/// interruption); a malformed line elsewhere is an error. The file is read
/// a line at a time (one line ahead, to know the last) under
/// [`JOURNAL_LIMITS`], so a resume holds the records, not the journal's
/// text, and an endless stream is refused at its cap.
pub fn read_journal_rows(path: &Path) -> Result<Vec<JournalRow>, ReadError> {
    let reader = open_csv(path, JOURNAL_LIMITS, false)?;
    let mut rows = reader.into_records().peekable();
    let mut out = Vec::new();
    let mut line = 0u64;
    while let Some(row) = rows.next() {
        line += 1;
        let row = match row {
            // A refusal of the reader (a cap) or of the system, not a torn line.
            Err(e) if matches!(e.kind(), csv::ErrorKind::Io(_)) => {
                return Err(data(path, line, DataProblem::Csv(e)))
            }
            row => row,
        };
        let last = rows.peek().is_none();
        let extra = row.as_ref().ok().and_then(|r| {
            [EXTRA, EXTRA_BEFORE_CHECKSUM, EXTRA_BEFORE_INSTANCES]
                .into_iter()
                .find(|extra| {
                    r.len() == RUNS_HEADER.len() + extra + 1
                        && r.get(RUNS_HEADER.len() + extra) == Some("ok")
                })
        });
        let (Some(extra), Ok(r)) = (extra, &row) else {
            if last {
                break;
            }
            let at = row
                .as_ref()
                .ok()
                .and_then(|r| r.position())
                .map_or(line, |p| p.line());
            return Err(data(path, at, DataProblem::Malformed("journal line")));
        };
        let line = r.position().map_or(line, |p| p.line());
        let record = record_of_row(path, line, r, extra)?;
        let problem = check_row(r, extra == EXTRA, &record);
        out.push(JournalRow {
            line,
            record,
            problem,
        });
    }
    Ok(out)
}

/// The record of a complete journal line with `extra` fields after the
/// `runs.csv` ones.
fn record_of_row(
    path: &Path,
    line: u64,
    r: &csv::StringRecord,
    extra: usize,
) -> Result<RunRecord, ReadError> {
    let mut rec = record_from_fields(path, line, r)?;
    for (column, at) in [("best", 8), ("error", 9)] {
        parse_real(path, line, column, &r[at], Real::NotNan)?;
    }
    let at = |k: usize| r.get(RUNS_HEADER.len() + k).unwrap_or("");
    if !at(0).is_empty() {
        for part in at(0).split('|') {
            let (e, b) = part
                .split_once(':')
                .ok_or_else(|| data(path, line, DataProblem::Malformed("trace")))?;
            rec.trace.push(TracePoint {
                evaluations: parse(path, line, "trace", e)?,
                best: parse_real(path, line, "trace", b, Real::NotNan)?,
            });
        }
    }
    if !at(1).is_empty() {
        rec.fit = Some(fit_from_field(path, line, at(1))?);
    }
    rec.wall_seconds = parse_real(path, line, "wall_seconds", at(2), Real::NonNegative)?;
    if extra >= EXTRA_BEFORE_CHECKSUM {
        rec.transform = parse_transform(path, line, at(3))?;
        rec.instance = parse(path, line, "instance", at(4))?;
        rec.hits = hits_from_field(path, line, at(5))?;
    }
    Ok(rec)
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

    /// `r` as a journal line of an older layout: the current line without
    /// its last `cut` fields before the sentinel.
    fn older_line(r: &RunRecord, cut: usize) -> String {
        let line = String::from_utf8(journal_line(r)).unwrap();
        let fields: Vec<&str> = line.trim_end().rsplitn(cut + 2, ',').collect();
        format!("{},ok\n", fields[cut + 1])
    }

    /// A record whose best and evaluations are its trace's last point, as
    /// every benchmark run's are.
    fn consistent_record(run: u32) -> RunRecord {
        let mut r = sample_record(run);
        r.trace.push(TracePoint {
            evaluations: r.evaluations,
            best: r.best,
        });
        r
    }

    #[test]
    fn lines_written_before_instances_and_hits_still_resume() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        let mut legacy = consistent_record(4);
        legacy.transform = crate::functions::Transform::None;
        legacy.instance = 1;
        legacy.hits.clear();
        legacy.algorithm = "HS".into();
        // The layout before: runs fields, trace, fit, wall time, ok.
        let old = older_line(&legacy, 4);
        assert_eq!(
            old.matches(',').count(),
            RUNS_HEADER.len() + EXTRA_BEFORE_INSTANCES
        );
        std::fs::write(&path, old).unwrap();
        assert_eq!(read_journal(&path).unwrap(), vec![legacy]);
    }

    #[test]
    fn lines_written_before_checksums_are_checked_by_their_trace() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        let mut good = consistent_record(1);
        good.algorithm = "HS".into();
        let old = older_line(&good, 1);
        assert_eq!(
            old.matches(',').count(),
            RUNS_HEADER.len() + EXTRA_BEFORE_CHECKSUM
        );
        // The same line with its best edited, then with its evaluations.
        let best = old.replacen(",1.2345678901234566e-13,", ",1e-13,", 1);
        let evaluations = old.replacen(",1000,17,", ",999,17,", 1);
        assert_ne!(best, old);
        assert_ne!(evaluations, old);
        std::fs::write(&path, format!("{old}{best}{evaluations}")).unwrap();
        let rows = read_journal_rows(&path).unwrap();
        assert_eq!(rows[0].record, good);
        assert_eq!(rows[0].problem, None);
        let fields: Vec<_> = rows[1..]
            .iter()
            .map(|r| (r.line, r.problem.as_ref().map(|p| p.field)))
            .collect();
        assert_eq!(fields, [(2, Some("best")), (3, Some("evaluations"))]);
        assert_eq!(read_journal(&path).unwrap(), vec![good]);
    }

    #[test]
    fn a_row_whose_fields_do_not_give_its_checksum_is_flagged() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("journal.csv");
        // Its trace ends at its best: only the checksum tells that its wall
        // time was edited.
        let line = String::from_utf8(journal_line(&consistent_record(2))).unwrap();
        let edited = line.replacen(",0.0125,", ",0.5,", 1);
        assert_ne!(edited, line);
        std::fs::write(&path, format!("{line}{edited}")).unwrap();
        let rows = read_journal_rows(&path).unwrap();
        assert_eq!(rows[0].problem, None);
        let p = rows[1].problem.as_ref().expect("flagged");
        assert_eq!(p.field, "checksum");
        assert_eq!(read_journal(&path).unwrap(), vec![consistent_record(2)]);
    }

    #[test]
    fn an_endless_or_newline_free_journal_is_refused_at_its_cap() {
        let dir = tempfile::tempdir().unwrap();
        // A sparse file over the line cap: NUL bytes and no newline.
        let path = dir.path().join("journal.csv");
        let f = std::fs::File::create(&path).unwrap();
        f.set_len(MAX_RESULT_LINE_BYTES + 10).unwrap();
        for p in [path.as_path(), Path::new("/dev/zero")] {
            let e = read_journal(p).unwrap_err().to_string();
            assert!(
                e.starts_with(&format!(
                    "{}:1: line 1 is longer than the 64 MiB",
                    p.display()
                )),
                "{e}"
            );
        }
        // Under a test cap, a journal of many short lines is refused too.
        let small = crate::files::ReadLimits {
            file_bytes: 100,
            ..JOURNAL_LIMITS
        };
        std::fs::write(&path, "x\n".repeat(80)).unwrap();
        let mut reader = open_csv(&path, small, false).unwrap();
        let e = reader.records().find_map(Result::err).unwrap().to_string();
        assert_eq!(
            e,
            "it is larger than the 100 bytes a journal may be; give the journal.csv a \
             campaign of this tool wrote"
        );
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
