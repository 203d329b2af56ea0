//! Run records and the tidy CSV files they are written to.
//!
//! * `runs.csv`: one row per run (the columns of [`RUNS_HEADER`]);
//! * `convergence.csv`: long format, the best-so-far of each run at
//!   log-spaced evaluation counts;
//! * `timing.csv`: wall time per run, kept apart so that `runs.csv` and
//!   `convergence.csv` are byte-identical whatever the thread count;
//! * `journal.csv`: while a campaign runs, each finished run is appended
//!   here as one self-checking line, so an interrupted campaign resumes
//!   without losing finished runs.
//!
//! Reals are written in Rust's shortest round-trip form, so reading a file
//! back gives bit-identical values.

use std::collections::HashMap;
use std::path::Path;

use super::segments::{segment_rows, SEGMENT_HEADER};
use crate::files::{csv_bytes, fmt_real, IoError};
use crate::fit::PiecewiseFit;
use crate::optim::TracePoint;

/// What is wrong with a results file at one line.
#[derive(Debug, thiserror::Error)]
pub enum DataProblem {
    /// A cell cannot be read as its column's type.
    #[error("column {column}: cannot read \"{text}\"")]
    Cell {
        /// The column.
        column: String,
        /// The text found.
        text: String,
    },
    /// The `success` column holds neither `true` nor `false`.
    #[error("column success: expected true or false, found \"{0}\"")]
    Success(String),
    /// A row has too few columns.
    #[error("expected {expected} columns, found {found}")]
    TooFewColumns {
        /// Columns needed.
        expected: usize,
        /// Columns found.
        found: usize,
    },
    /// A row's column count differs from the header's.
    #[error("wrong number of columns")]
    WrongColumnCount,
    /// The header is not the file's schema.
    #[error("expected the columns {}, found {}", expected.join(","), found.join(","))]
    Header {
        /// The schema's columns.
        expected: Vec<String>,
        /// The columns found.
        found: Vec<String>,
    },
    /// The CSV syntax is broken.
    #[error("{0}")]
    Csv(#[source] csv::Error),
    /// A journal line, trace or fit detail is malformed.
    #[error("malformed {0}")]
    Malformed(&'static str),
    /// A keyed row names a run that `runs.csv` does not hold.
    #[error("this run is not in runs.csv")]
    UnknownRun,
    /// A `segments.csv` row names a run that `fits.csv` does not hold.
    #[error("this run has no row in fits.csv")]
    NoFitRow,
    /// A cell of a numeric column (numbered from 1) is not a number.
    #[error("column {0}: not a number")]
    NotANumber(usize),
    /// The file holds no run.
    #[error("no runs to report")]
    NoRuns,
}

/// A results file is malformed: the file, the line and what is wrong.
#[derive(Debug, thiserror::Error)]
pub struct DataError {
    /// The file.
    pub path: std::path::PathBuf,
    /// 1-based line, or 0 if the problem concerns the whole file.
    pub line: u64,
    /// What is wrong.
    #[source]
    pub problem: DataProblem,
}

impl DataError {
    /// A problem in `path` at `line`.
    pub fn new(path: &Path, line: u64, problem: DataProblem) -> Self {
        DataError {
            path: path.to_owned(),
            line,
            problem,
        }
    }
}

impl std::fmt::Display for DataError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            0 => write!(f, "{}: {}", self.path.display(), self.problem),
            n => write!(f, "{}:{n}: {}", self.path.display(), self.problem),
        }
    }
}

/// A results file could not be read, or is malformed.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be read.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The file is malformed.
    #[error(transparent)]
    Data(#[from] DataError),
}

pub(super) fn data(path: &Path, line: u64, problem: DataProblem) -> ReadError {
    ReadError::Data(DataError::new(path, line, problem))
}

/// The result of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRecord {
    /// The cell's label.
    pub algorithm: String,
    /// The optimiser's spec name (`hs`, `ghs`, `ga`, `pso`, `mhs`).
    pub kind: String,
    /// The canonical parameter text `name=value;...`.
    pub params: String,
    /// The problem's name.
    pub problem: String,
    /// The problem's dimension.
    pub dim: usize,
    /// The run's evaluation budget.
    pub budget: u64,
    /// The run number, from 0.
    pub run: u32,
    /// The run's derived seed.
    pub seed: u64,
    /// The best objective value found.
    pub best: f64,
    /// `best − f*`.
    pub error: f64,
    /// Evaluations used.
    pub evaluations: u64,
    /// First evaluation count at which `f ≤ f* + threshold`, if reached.
    pub evaluations_to_target: Option<u64>,
    /// Whether the threshold was reached.
    pub success: bool,
    /// The best-so-far at the convergence checkpoints.
    pub trace: Vec<TracePoint>,
    /// For a fitting problem, the fitted outline (`fits.csv`, `segments.csv`).
    pub fit: Option<FitDetail>,
    /// Wall time of the run in seconds (not part of the reproducible output).
    pub wall_seconds: f64,
}

/// What a fitting run adds to its record: the fit's accuracy beyond `E`
/// and every segment's control points.
#[derive(Clone, Debug, PartialEq)]
pub struct FitDetail {
    /// `√(E/N)`.
    pub rms: f64,
    /// The largest orthogonal distance of a data point to the curve.
    pub max_distance: f64,
    /// On a closed outline, the tangent angle at the closing joint
    /// (degrees), where only C⁰ is imposed.
    pub closing_angle_degrees: Option<f64>,
    /// On a closed outline, the relative derivative gap there.
    pub closing_relative_derivative_gap: Option<f64>,
    /// One row per segment, in the columns of [`SEGMENT_HEADER`].
    pub segments: Vec<Vec<String>>,
}

impl FitDetail {
    /// The detail of a finished fit.
    pub fn of(fit: &PiecewiseFit) -> FitDetail {
        FitDetail {
            rms: fit.metrics.rms,
            max_distance: fit.metrics.max_distance,
            closing_angle_degrees: fit.closing.map(|c| c.angle_degrees),
            closing_relative_derivative_gap: fit.closing.map(|c| c.relative_derivative_gap),
            segments: segment_rows(fit),
        }
    }

    /// The run-level columns of `fits.csv` after the run key.
    pub(super) fn fields(&self) -> Vec<String> {
        let opt = |x: Option<f64>| x.map_or(String::new(), fmt_real);
        vec![
            fmt_real(self.rms),
            fmt_real(self.max_distance),
            opt(self.closing_angle_degrees),
            opt(self.closing_relative_derivative_gap),
        ]
    }

    /// Reads [`FitDetail::fields`] back (segments empty).
    pub(super) fn from_fields(path: &Path, line: u64, f: &[&str]) -> Result<FitDetail, ReadError> {
        let opt = |name: &str, t: &str| -> Result<Option<f64>, ReadError> {
            if t.is_empty() {
                Ok(None)
            } else {
                parse(path, line, name, t).map(Some)
            }
        };
        Ok(FitDetail {
            rms: parse(path, line, "rms", f[0])?,
            max_distance: parse(path, line, "max_distance", f[1])?,
            closing_angle_degrees: opt("closing_angle_degrees", f[2])?,
            closing_relative_derivative_gap: opt("closing_relative_derivative_gap", f[3])?,
            segments: Vec::new(),
        })
    }
}

/// The run-level columns of `fits.csv` after the run key.
pub(super) const FIT_FIELDS: [&str; 4] = [
    "rms",
    "max_distance",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The columns that identify a run in `convergence.csv`, `timing.csv`,
/// `fits.csv` and `segments.csv`.
const RUN_KEY_HEADER: [&str; 6] = ["algorithm", "kind", "params", "problem", "dim", "run"];

fn run_key_fields(r: &RunRecord) -> Vec<String> {
    vec![
        r.algorithm.clone(),
        r.kind.clone(),
        r.params.clone(),
        r.problem.clone(),
        r.dim.to_string(),
        r.run.to_string(),
    ]
}

/// The run key columns followed by `rest`.
fn keyed_header(rest: &[&'static str]) -> Vec<&'static str> {
    RUN_KEY_HEADER.iter().chain(rest).copied().collect()
}

/// The bytes of `fits.csv`: one row per fitting run with its RMS, maximum
/// orthogonal distance and closing-joint mismatch (`E` and evaluations are
/// in `runs.csv`).
pub fn fits_csv(records: &[RunRecord]) -> Vec<u8> {
    let rows = records.iter().filter_map(|r| {
        r.fit.as_ref().map(|f| {
            let mut row = run_key_fields(r);
            row.extend(f.fields());
            row
        })
    });
    csv_bytes(&keyed_header(&FIT_FIELDS), rows)
}

/// The bytes of `segments.csv`: one row per segment of every fitting run,
/// with its control points, weights and metrics.
pub fn segments_csv(records: &[RunRecord]) -> Vec<u8> {
    let rows = records.iter().flat_map(|r| {
        let key = run_key_fields(r);
        r.fit.iter().flat_map(move |f| {
            let key = key.clone();
            f.segments.iter().map(move |seg| {
                let mut row = key.clone();
                row.extend(seg.iter().cloned());
                row
            })
        })
    });
    csv_bytes(&keyed_header(&SEGMENT_HEADER), rows)
}

/// Identifies a run within a campaign: (cell key, problem key, run).
pub type RunKey = (String, String, u32);

impl RunRecord {
    /// The cell key `label:kind[params]`, as [`crate::experiment::spec::Cell::key`].
    pub fn cell_key(&self) -> String {
        format!("{}:{}[{}]", self.algorithm, self.kind, self.params)
    }

    /// The problem key `problem-dim`.
    pub fn problem_key(&self) -> String {
        format!("{}-{}", self.problem, self.dim)
    }

    /// The run's key.
    pub fn key(&self) -> RunKey {
        (self.cell_key(), self.problem_key(), self.run)
    }
}

/// The columns of `runs.csv`.
pub const RUNS_HEADER: [&str; 13] = [
    "algorithm",
    "kind",
    "params",
    "problem",
    "dim",
    "budget",
    "run",
    "seed",
    "best",
    "error",
    "evaluations",
    "evaluations_to_target",
    "success",
];

/// The columns of `convergence.csv`.
pub const CONVERGENCE_HEADER: [&str; 9] = [
    "algorithm",
    "kind",
    "params",
    "problem",
    "dim",
    "run",
    "evaluations",
    "best",
    "error",
];

/// The columns of `timing.csv`.
pub const TIMING_HEADER: [&str; 7] = [
    "algorithm",
    "kind",
    "params",
    "problem",
    "dim",
    "run",
    "wall_seconds",
];

pub(super) fn run_fields(r: &RunRecord) -> Vec<String> {
    vec![
        r.algorithm.clone(),
        r.kind.clone(),
        r.params.clone(),
        r.problem.clone(),
        r.dim.to_string(),
        r.budget.to_string(),
        r.run.to_string(),
        r.seed.to_string(),
        fmt_real(r.best),
        fmt_real(r.error),
        r.evaluations.to_string(),
        r.evaluations_to_target
            .map_or(String::new(), |e| e.to_string()),
        r.success.to_string(),
    ]
}

/// The bytes of `runs.csv` for records in their final order.
pub fn runs_csv(records: &[RunRecord]) -> Vec<u8> {
    csv_bytes(&RUNS_HEADER, records.iter().map(run_fields))
}

/// The bytes of `convergence.csv` for records in their final order;
/// `optimum` gives `f*` of a record so the error column can be filled.
pub fn convergence_csv(records: &[RunRecord], optimum: impl Fn(&RunRecord) -> f64) -> Vec<u8> {
    let rows = records.iter().flat_map(|r| {
        let f_star = optimum(r);
        let key = run_key_fields(r);
        r.trace.iter().map(move |p| {
            let mut row = key.clone();
            row.extend([
                p.evaluations.to_string(),
                fmt_real(p.best),
                fmt_real(p.best - f_star),
            ]);
            row
        })
    });
    csv_bytes(&CONVERGENCE_HEADER, rows)
}

/// The bytes of `timing.csv`.
pub fn timing_csv(records: &[RunRecord]) -> Vec<u8> {
    let rows = records.iter().map(|r| {
        let mut row = run_key_fields(r);
        row.push(fmt_real(r.wall_seconds));
        row
    });
    csv_bytes(&TIMING_HEADER, rows)
}

pub(super) fn parse<T: std::str::FromStr>(
    path: &Path,
    line: u64,
    column: &str,
    text: &str,
) -> Result<T, ReadError> {
    text.parse().map_err(|_| {
        data(
            path,
            line,
            DataProblem::Cell {
                column: column.to_owned(),
                text: text.to_owned(),
            },
        )
    })
}

pub(super) fn record_from_fields(
    path: &Path,
    line: u64,
    f: &csv::StringRecord,
) -> Result<RunRecord, ReadError> {
    if f.len() < RUNS_HEADER.len() {
        return Err(data(
            path,
            line,
            DataProblem::TooFewColumns {
                expected: RUNS_HEADER.len(),
                found: f.len(),
            },
        ));
    }
    let get = |i: usize| f.get(i).unwrap_or("");
    let success = match get(12) {
        "true" => true,
        "false" => false,
        other => return Err(data(path, line, DataProblem::Success(other.to_owned()))),
    };
    Ok(RunRecord {
        algorithm: get(0).to_owned(),
        kind: get(1).to_owned(),
        params: get(2).to_owned(),
        problem: get(3).to_owned(),
        dim: parse(path, line, "dim", get(4))?,
        budget: parse(path, line, "budget", get(5))?,
        run: parse(path, line, "run", get(6))?,
        seed: parse(path, line, "seed", get(7))?,
        best: parse(path, line, "best", get(8))?,
        error: parse(path, line, "error", get(9))?,
        evaluations: parse(path, line, "evaluations", get(10))?,
        evaluations_to_target: match get(11) {
            "" => None,
            t => Some(parse(path, line, "evaluations_to_target", t)?),
        },
        success,
        trace: Vec::new(),
        fit: None,
        wall_seconds: 0.0,
    })
}

fn open_csv(path: &Path, headers: bool) -> Result<csv::Reader<std::fs::File>, ReadError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::new("read", path, e))?;
    Ok(csv::ReaderBuilder::new()
        .has_headers(headers)
        .flexible(true)
        .from_reader(file))
}

fn check_header(
    path: &Path,
    reader: &mut csv::Reader<std::fs::File>,
    expected: &[&str],
) -> Result<(), ReadError> {
    let header = reader
        .headers()
        .map_err(|e| data(path, 1, DataProblem::Csv(e)))?;
    let found: Vec<&str> = header.iter().collect();
    if found != expected {
        return Err(data(
            path,
            1,
            DataProblem::Header {
                expected: expected.iter().map(|c| c.to_string()).collect(),
                found: found.iter().map(|c| c.to_string()).collect(),
            },
        ));
    }
    Ok(())
}

/// Reads `runs.csv` alone (traces empty, wall time 0): the input of reports,
/// which may also come from outside this tool.
pub fn read_runs(path: &Path) -> Result<Vec<RunRecord>, ReadError> {
    let mut reader = open_csv(path, true)?;
    check_header(path, &mut reader, &RUNS_HEADER)?;
    let mut out = Vec::new();
    for (i, row) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let row = row.map_err(|e| data(path, line, DataProblem::Csv(e)))?;
        out.push(record_from_fields(path, line, &row)?);
    }
    Ok(out)
}

/// Reads the rows of a CSV file with `header`, checking the header and
/// every row's column count, and hands each to `row` with its line number.
fn read_keyed(
    path: &Path,
    header: &[&str],
    mut row: impl FnMut(&Path, u64, &csv::StringRecord) -> Result<(), ReadError>,
) -> Result<(), ReadError> {
    let mut reader = open_csv(path, true)?;
    check_header(path, &mut reader, header)?;
    for (i, r) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let r = r.map_err(|e| data(path, line, DataProblem::Csv(e)))?;
        if r.len() != header.len() {
            return Err(data(path, line, DataProblem::WrongColumnCount));
        }
        row(path, line, &r)?;
    }
    Ok(())
}

/// Reads a finished campaign directory's `runs.csv`, `convergence.csv` and
/// `timing.csv` back into complete records.
pub fn read_results(dir: &Path) -> Result<Vec<RunRecord>, ReadError> {
    let runs_path = dir.join("runs.csv");
    let mut records = read_runs(&runs_path)?;
    let index: HashMap<RunKey, usize> = records
        .iter()
        .enumerate()
        .map(|(i, r)| (r.key(), i))
        .collect();
    let lookup = |path: &Path, line: u64, row: &csv::StringRecord| -> Result<usize, ReadError> {
        let run: u32 = parse(path, line, "run", row.get(5).unwrap_or(""))?;
        let key = (
            format!("{}:{}[{}]", &row[0], &row[1], &row[2]),
            format!("{}-{}", &row[3], &row[4]),
            run,
        );
        index
            .get(&key)
            .copied()
            .ok_or_else(|| data(path, line, DataProblem::UnknownRun))
    };
    read_keyed(
        &dir.join("convergence.csv"),
        &CONVERGENCE_HEADER,
        |path, line, row| {
            let k = lookup(path, line, row)?;
            records[k].trace.push(TracePoint {
                evaluations: parse(path, line, "evaluations", &row[6])?,
                best: parse(path, line, "best", &row[7])?,
            });
            Ok(())
        },
    )?;
    read_keyed(
        &dir.join("timing.csv"),
        &TIMING_HEADER,
        |path, line, row| {
            let k = lookup(path, line, row)?;
            records[k].wall_seconds = parse(path, line, "wall_seconds", &row[6])?;
            Ok(())
        },
    )?;
    if dir.join("fits.csv").exists() {
        read_keyed(
            &dir.join("fits.csv"),
            &keyed_header(&FIT_FIELDS),
            |path, line, row| {
                let k = lookup(path, line, row)?;
                let fields: Vec<&str> = row.iter().skip(RUN_KEY_HEADER.len()).collect();
                records[k].fit = Some(FitDetail::from_fields(path, line, &fields)?);
                Ok(())
            },
        )?;
        read_keyed(
            &dir.join("segments.csv"),
            &keyed_header(&SEGMENT_HEADER),
            |path, line, row| {
                let k = lookup(path, line, row)?;
                let fit = records[k]
                    .fit
                    .as_mut()
                    .ok_or_else(|| data(path, line, DataProblem::NoFitRow))?;
                fit.segments.push(
                    row.iter()
                        .skip(RUN_KEY_HEADER.len())
                        .map(str::to_owned)
                        .collect(),
                );
                Ok(())
            },
        )?;
    }
    Ok(records)
}

/// A run record with awkward values (quotes, extreme reals, an infinite
/// trace point) for round-trip tests.
#[cfg(test)]
pub(crate) fn sample_record(run: u32) -> RunRecord {
    RunRecord {
        algorithm: "HS, tuned".into(),
        kind: "hs".into(),
        params: "hms=5;hmcr=0.9".into(),
        problem: "sphere".into(),
        dim: 10,
        budget: 1000,
        run,
        seed: u64::MAX - 3,
        best: 1.234_567_890_123_456_7e-13,
        error: 1.234_567_890_123_456_7e-13,
        evaluations: 1000,
        evaluations_to_target: if run == 0 { None } else { Some(17) },
        success: run != 0,
        trace: vec![
            TracePoint {
                evaluations: 1,
                best: f64::INFINITY,
            },
            TracePoint {
                evaluations: 10,
                best: 0.1 + 0.2,
            },
        ],
        fit: None,
        wall_seconds: 0.0125,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn result_files_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let recs = vec![sample_record(0), sample_record(1)];
        std::fs::write(dir.path().join("runs.csv"), runs_csv(&recs)).unwrap();
        std::fs::write(
            dir.path().join("convergence.csv"),
            convergence_csv(&recs, |_| 0.0),
        )
        .unwrap();
        std::fs::write(dir.path().join("timing.csv"), timing_csv(&recs)).unwrap();
        assert_eq!(read_results(dir.path()).unwrap(), recs);
    }
}
