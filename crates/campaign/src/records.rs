//! Run records and the tidy CSV files they are written to.
//!
//! * `runs.csv`: one row per run (the columns of [`RUNS_HEADER`], with
//!   `transform` and `instance` when the campaign has benchmark instances,
//!   see [`Schema`]);
//! * `convergence.csv`: long format, the best-so-far of each run at
//!   log-spaced evaluation counts;
//! * `timing.csv`: wall time per run, kept apart so that `runs.csv` and
//!   `convergence.csv` are byte-identical whatever the thread count;
//! * `hits.csv`: long format, the first evaluation at which each run
//!   reached each target precision ([`default_targets`]);
//! * `journal.csv`: while a campaign runs, each finished run is appended
//!   here as one self-checking line, so an interrupted campaign resumes
//!   without losing finished runs.
//!
//! Reals are written in Rust's shortest round-trip form, so reading a file
//! back gives bit-identical values.

use std::collections::HashMap;
use std::io::{self, Write};
use std::path::Path;

pub use super::outcome::{default_targets, FitDetail};
use super::reading::{open_csv, CsvFile, RESULT_LIMITS, RUNS_LIMITS};
use super::segments::{FIT_SEGMENT_HEADER, SEGMENT_HEADER};
use super::spec::{factor_suffix, Spec};
use crate::files::{excerpt, fmt_real, write_atomic_with, IoError};
use crate::functions::Transform;
use crate::optim::{TargetHit, TracePoint};

/// What is wrong with a results file at one line.
#[derive(Debug, thiserror::Error)]
pub enum DataProblem {
    /// A cell cannot be read as its column's type.
    #[error("column {column}: cannot read \"{}\"", excerpt(text))]
    Cell {
        /// The column.
        column: String,
        /// The text found.
        text: String,
    },
    /// The `success` column holds neither `true` nor `false`.
    #[error("column success: expected true or false, found \"{}\"", excerpt(.0))]
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
    /// The header is not the file's schema: the file is not of this
    /// format (its first line is not quoted: it may be any file).
    #[error("expected the header {} ({} columns), but the first line is not that header (it has {found} column{}): this file is not in that format", expected.join(","), expected.len(), if *found == 1 { "" } else { "s" })]
    Header {
        /// The schema's columns.
        expected: Vec<String>,
        /// How many columns the first line has.
        found: usize,
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
    /// A real is not of the kind its column needs (a NaN, say, where the
    /// tool never writes one).
    #[error("column {column}: expected {expected}, found \"{}\"", excerpt(text))]
    NotFinite {
        /// The column.
        column: String,
        /// What the column holds.
        expected: &'static str,
        /// The text found.
        text: String,
    },
    /// A run's rows are out of order: the column must rise (or fall)
    /// strictly from one row of the run to the next.
    #[error("column {0}: must {1} strictly from one row of a run to the next, but does not here (a row repeated or out of order)")]
    Order(&'static str, &'static str),
    /// A keyed file has a second row for a run that has one.
    #[error("a second row for the run of an earlier row")]
    RepeatedRun,
    /// A keyed file has no row for a run of `runs.csv`.
    #[error("no row for {0} of runs.csv")]
    NoRowFor(String),
    /// A file that a campaign directory must hold is absent.
    #[error("not found, but {0}")]
    Missing(&'static str),
}

/// What a column of reals admits, beyond being a number.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Real {
    /// Any number but NaN (an objective value may be infinite).
    NotNan,
    /// A finite number of at least 0.
    NonNegative,
    /// A finite number above 0.
    Positive,
}

impl Real {
    fn admits(self, x: f64) -> bool {
        match self {
            Real::NotNan => !x.is_nan(),
            Real::NonNegative => x.is_finite() && x >= 0.0,
            Real::Positive => x.is_finite() && x > 0.0,
        }
    }

    fn expected(self) -> &'static str {
        match self {
            Real::NotNan => "a number (not NaN)",
            Real::NonNegative => "a finite number of at least 0",
            Real::Positive => "a finite number above 0",
        }
    }
}

/// Parses a real of `column` that must be of kind `kind`.
pub(super) fn parse_real(
    path: &Path,
    line: u64,
    column: &str,
    text: &str,
    kind: Real,
) -> Result<f64, ReadError> {
    let x: f64 = parse(path, line, column, text)?;
    if kind.admits(x) {
        Ok(x)
    } else {
        Err(data(
            path,
            line,
            DataProblem::NotFinite {
                column: column.to_owned(),
                expected: kind.expected(),
                text: text.to_owned(),
            },
        ))
    }
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
    /// The benchmark transform (`none` for untransformed and fitting runs).
    pub transform: Transform,
    /// The benchmark instance (1 unless transformed).
    pub instance: u32,
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
    /// The first evaluation at which each target precision was reached
    /// (`hits.csv`; unreached targets are absent).
    pub hits: Vec<TargetHit>,
    /// For a fitting problem, the fitted outline (`fits.csv`, `segments.csv`).
    pub fit: Option<FitDetail>,
    /// Wall time of the run in seconds (not part of the reproducible output).
    pub wall_seconds: f64,
}

impl FitDetail {
    /// The run-level columns of `fits.csv` after the run key: those of
    /// [`FIT_FIELDS_CURRENT`] with `rms_distance` (the two-sided columns
    /// empty for a run journalled before they existed), else of
    /// [`FIT_FIELDS`].
    pub(super) fn fields(&self) -> Vec<String> {
        let opt = |x: Option<f64>| x.map_or(String::new(), fmt_real);
        let mut out = vec![fmt_real(self.rms), fmt_real(self.max_distance)];
        if let Some(d) = self.rms_distance {
            out.push(fmt_real(d));
            out.push(opt(self.two_sided.map(|t| t.0)));
            out.push(opt(self.two_sided.map(|t| t.1)));
        }
        out.push(opt(self.closing_angle_degrees));
        out.push(opt(self.closing_relative_derivative_gap));
        out
    }

    /// Reads [`FitDetail::fields`] back (segments empty), in either layout.
    pub(super) fn from_fields(path: &Path, line: u64, f: &[&str]) -> Result<FitDetail, ReadError> {
        let opt = |name: &str, t: &str| -> Result<Option<f64>, ReadError> {
            if t.is_empty() {
                Ok(None)
            } else {
                parse(path, line, name, t).map(Some)
            }
        };
        // 4 fields (legacy), 5 (with rms_distance) or 7 (and the two sides).
        let with_rms = f.len() >= FIT_FIELDS_RMS.len();
        let two_sided = f.len() == FIT_FIELDS_CURRENT.len();
        let at = usize::from(with_rms) + 2 * usize::from(two_sided);
        let two = if two_sided {
            match (opt("curve_distance", f[3])?, opt("hausdorff", f[4])?) {
                (Some(c), Some(h)) => Some((c, h)),
                _ => None,
            }
        } else {
            None
        };
        Ok(FitDetail {
            rms: parse(path, line, "rms", f[0])?,
            max_distance: parse(path, line, "max_distance", f[1])?,
            rms_distance: if with_rms {
                Some(parse(path, line, "rms_distance", f[2])?)
            } else {
                None
            },
            two_sided: two,
            closing_angle_degrees: opt("closing_angle_degrees", f[2 + at])?,
            closing_relative_derivative_gap: opt("closing_relative_derivative_gap", f[3 + at])?,
            segments: Vec::new(),
        })
    }
}

/// The bytes the system allocator takes for a block of `n` requested
/// bytes: glibc's chunk, `n` plus its 8-byte header rounded up to 16, at
/// least 32; nothing for an empty block (an empty `String` or `Vec`
/// allocates nothing).
pub const fn heap_block(n: u64) -> u64 {
    if n == 0 {
        return 0;
    }
    let chunk = (n + 8 + 15) & !15;
    if chunk < 32 {
        32
    } else {
        chunk
    }
}

/// The heap one segment row of a fitting run's record takes (its vector of
/// [`FIT_SEGMENT_HEADER`] strings and each string's block), measured by
/// `tests/memory.rs` over the four fitting functions: the one figure of
/// [`record_heap`] that depends on the values (the length of each real's
/// shortest round-trip form), so the test fails when it drifts.
pub const SEGMENT_ROW_HEAP: u64 = 1336;

/// What a run's record holds beyond its fixed fields, for [`record_heap`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordShape {
    /// The lengths of the label, the optimiser's name, the canonical
    /// parameters and the problem's name.
    pub strings: [usize; 4],
    /// Convergence checkpoints in the trace.
    pub trace_points: usize,
    /// Target hits.
    pub hits: usize,
    /// Segments of a fitting run (0 for a benchmark run).
    pub segments: usize,
}

/// The heap one record of `shape` takes beyond `size_of::<RunRecord>()`:
/// its four strings, its trace and hits (16 bytes a point, vectors at
/// their exact length, as the runner keeps them) and a fitting run's
/// segment rows ([`SEGMENT_ROW_HEAP`] each, in a vector of 24-byte rows).
pub fn record_heap(shape: &RecordShape) -> u64 {
    let strings: u64 = shape.strings.iter().map(|&n| heap_block(n as u64)).sum();
    let point = std::mem::size_of::<TracePoint>() as u64;
    let hit = std::mem::size_of::<TargetHit>() as u64;
    let rows = std::mem::size_of::<Vec<String>>() as u64;
    let segments = shape.segments as u64;
    strings
        + heap_block(point * shape.trace_points as u64)
        + heap_block(hit * shape.hits as u64)
        + heap_block(rows * segments)
        + segments * SEGMENT_ROW_HEAP
}

/// The run-level columns of a legacy `fits.csv` after the run key.
pub(super) const FIT_FIELDS: [&str; 4] = [
    "rms",
    "max_distance",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The run-level columns of `fits.csv` written before the two-sided
/// distances: the orthogonal `rms_distance` next to `max_distance` (read,
/// no longer written).
pub(super) const FIT_FIELDS_RMS: [&str; 5] = [
    "rms",
    "max_distance",
    "rms_distance",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The run-level columns of `fits.csv` with the current fitting records:
/// the orthogonal `rms_distance` next to `max_distance` (data → curve),
/// then `curve_distance` (curve → data) and `hausdorff` (the larger).
pub(super) const FIT_FIELDS_CURRENT: [&str; 7] = [
    "rms",
    "max_distance",
    "rms_distance",
    "curve_distance",
    "hausdorff",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// Whether any record carries the current fitting records.
fn current_fit_records(records: &[RunRecord]) -> bool {
    records
        .iter()
        .any(|r| r.fit.as_ref().is_some_and(|f| f.rms_distance.is_some()))
}

/// Which design-factor columns the result files of a campaign carry, beyond
/// the columns every campaign has. Files of campaigns without transformed
/// instances or budget grids keep exactly the columns they had before these
/// factors existed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Schema {
    /// `transform` and `instance` columns: some run is on a transformed
    /// benchmark instance.
    pub instances: bool,
    /// A `budget` column in the files keyed by run (convergence, timing,
    /// fits, segments, hits): runs of one problem differ in budget.
    pub keyed_budget: bool,
}

impl Schema {
    /// The schema the records need.
    pub fn of<'a>(records: impl IntoIterator<Item = &'a RunRecord>) -> Schema {
        let mut instances = false;
        let mut budgets: HashMap<(String, String, u32), u64> = HashMap::new();
        let mut keyed_budget = false;
        for r in records {
            instances |= r.transform != Transform::None || r.instance != 1;
            let b = budgets
                .entry((r.cell_key(), r.match_key(), r.run))
                .or_insert(r.budget);
            keyed_budget |= *b != r.budget;
        }
        Schema {
            instances,
            keyed_budget,
        }
    }

    /// The schema of the complete records of `spec`, from the spec alone
    /// (equal to [`Schema::of`] of them, without a map over every run):
    /// instances when a problem is a transformed instance, a keyed budget
    /// when two problems differ in budget only.
    pub fn of_spec(spec: &Spec) -> Schema {
        let instances = spec
            .problems
            .iter()
            .any(|p| p.transform != Transform::None || p.instance != 1);
        let mut budgets: HashMap<String, u64> = HashMap::new();
        let mut keyed_budget = false;
        for p in &spec.problems {
            keyed_budget |= *budgets.entry(p.match_key()).or_insert(p.budget) != p.budget;
        }
        Schema {
            instances,
            keyed_budget,
        }
    }

    /// The columns of `runs.csv`: [`RUNS_HEADER`], with `transform` and
    /// `instance` after `budget` when the campaign has instances.
    pub fn runs_header(self) -> Vec<&'static str> {
        let mut h: Vec<&'static str> = RUNS_HEADER.to_vec();
        if self.instances {
            h.splice(6..6, ["transform", "instance"]);
        }
        h
    }

    /// The columns identifying a run in the keyed files, followed by `rest`.
    pub fn keyed_header(self, rest: &[&'static str]) -> Vec<&'static str> {
        let mut h = vec!["algorithm", "kind", "params", "problem", "dim"];
        if self.keyed_budget {
            h.push("budget");
        }
        if self.instances {
            h.extend(["transform", "instance"]);
        }
        h.push("run");
        h.extend_from_slice(rest);
        h
    }

    /// The number of key columns of a keyed file.
    fn key_len(self) -> usize {
        6 + usize::from(self.keyed_budget) + 2 * usize::from(self.instances)
    }

    /// The schema whose [`Schema::runs_header`] is `found`.
    fn from_runs_header(found: &[&str]) -> Option<Schema> {
        [false, true]
            .into_iter()
            .map(|instances| Schema {
                instances,
                keyed_budget: false,
            })
            .find(|s| s.runs_header() == found)
    }

    /// The schema whose [`Schema::keyed_header`] with `rest` is `found`.
    fn from_keyed_header(found: &[&str], rest: &[&'static str]) -> Option<Schema> {
        [(false, false), (false, true), (true, false), (true, true)]
            .into_iter()
            .map(|(instances, keyed_budget)| Schema {
                instances,
                keyed_budget,
            })
            .find(|s| s.keyed_header(rest) == found)
    }

    /// The key fields of `r` in a keyed file.
    fn key_fields(self, r: &RunRecord) -> Vec<String> {
        let mut row = vec![
            r.algorithm.clone(),
            r.kind.clone(),
            r.params.clone(),
            r.problem.clone(),
            r.dim.to_string(),
        ];
        if self.keyed_budget {
            row.push(r.budget.to_string());
        }
        if self.instances {
            row.extend([r.transform.name().to_owned(), r.instance.to_string()]);
        }
        row.push(r.run.to_string());
        row
    }
}

/// The bytes of `hits.csv`: one row per run and target reached, with the
/// first evaluation at which it was reached.
pub fn hits_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_hits(w, Schema::of(records), records))
}

/// Streams `hits.csv` of `records` under `schema` into `w`.
pub fn write_hits(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rows = records.iter().flat_map(|r| {
        let key = schema.key_fields(r);
        r.hits.iter().map(move |h| {
            let mut row = key.clone();
            row.extend([fmt_real(h.precision), h.evaluations.to_string()]);
            row
        })
    });
    write_csv(w, &schema.keyed_header(&HITS_FIELDS), rows)
}

/// The columns of `hits.csv` after the run key.
const HITS_FIELDS: [&str; 2] = ["target", "evaluations"];

/// The bytes of `fits.csv`: one row per fitting run with its RMS, maximum
/// orthogonal distance and closing-joint mismatch (`E` and evaluations are
/// in `runs.csv`).
pub fn fits_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_fits(w, Schema::of(records), records))
}

/// Streams `fits.csv` of `records` under `schema` into `w`.
pub fn write_fits(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rest: &[&'static str] = if current_fit_records(records) {
        &FIT_FIELDS_CURRENT
    } else {
        &FIT_FIELDS
    };
    let rows = records.iter().filter_map(|r| {
        r.fit.as_ref().map(|f| {
            let mut row = schema.key_fields(r);
            row.extend(f.fields());
            row
        })
    });
    write_csv(w, &schema.keyed_header(rest), rows)
}

/// The bytes of `segments.csv`: one row per segment of every fitting run,
/// with its control points, weights and metrics (and its contour and
/// orthogonal RMS with the current fitting records).
pub fn segments_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_segments(w, Schema::of(records), records))
}

/// Streams `segments.csv` of `records` under `schema` into `w`.
pub fn write_segments(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rest: &[&'static str] = if current_fit_records(records) {
        &FIT_SEGMENT_HEADER
    } else {
        &SEGMENT_HEADER
    };
    let rows = records.iter().flat_map(|r| {
        let key = schema.key_fields(r);
        r.fit.iter().flat_map(move |f| {
            let key = key.clone();
            f.segments.iter().map(move |seg| {
                let mut row = key.clone();
                row.extend(seg.iter().cloned());
                row
            })
        })
    });
    write_csv(w, &schema.keyed_header(rest), rows)
}

/// Identifies a run within a campaign: (cell key, problem match key,
/// budget, run); see [`crate::spec::ProblemEntry::match_key`].
pub type RunKey = (String, String, u64, u32);

impl RunRecord {
    /// The cell key `label:kind[params]`, as [`crate::spec::Cell::key`].
    pub fn cell_key(&self) -> String {
        format!("{}:{}[{}]", self.algorithm, self.kind, self.params)
    }

    /// The problem key without the budget: `problem-dim` and the transform
    /// and instance of a transformed benchmark, as
    /// [`crate::spec::ProblemEntry::match_key`].
    pub fn match_key(&self) -> String {
        format!(
            "{}-{}{}",
            self.problem,
            self.dim,
            factor_suffix(self.transform, self.instance, true, true)
        )
    }

    /// `run R of CELL on PROBLEM`, for messages.
    pub fn describe(&self) -> String {
        format!(
            "run {} of {} on {}",
            self.run,
            self.cell_key(),
            self.match_key()
        )
    }

    /// The run's key.
    pub fn key(&self) -> RunKey {
        (self.cell_key(), self.match_key(), self.budget, self.run)
    }
}

/// The columns of `runs.csv` of a campaign without instances (see
/// [`Schema::runs_header`]).
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

/// The columns of `convergence.csv` after the run key.
const CONVERGENCE_FIELDS: [&str; 3] = ["evaluations", "best", "error"];

/// The columns of `timing.csv` after the run key.
const TIMING_FIELDS: [&str; 1] = ["wall_seconds"];

/// The fields of `runs.csv` of a campaign without instances: the layout the
/// journal keeps for every run.
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

/// The fields of `r` in `runs.csv` under `schema`.
fn runs_row(schema: Schema, r: &RunRecord) -> Vec<String> {
    let mut row = run_fields(r);
    if schema.instances {
        row.splice(
            6..6,
            [r.transform.name().to_owned(), r.instance.to_string()],
        );
    }
    row
}

/// The bytes of `runs.csv` for records in their final order.
pub fn runs_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_runs(w, Schema::of(records), records))
}

/// Streams `runs.csv` of `records` (in their final order) under `schema`
/// into `w`.
pub fn write_runs(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    write_csv(
        w,
        &schema.runs_header(),
        records.iter().map(|r| runs_row(schema, r)),
    )
}

/// The bytes of `convergence.csv` for records in their final order;
/// `optimum` gives `f*` of a record so the error column can be filled.
pub fn convergence_csv(records: &[RunRecord], optimum: impl Fn(&RunRecord) -> f64) -> Vec<u8> {
    in_memory(|w| write_convergence(w, Schema::of(records), records, &optimum))
}

/// Streams `convergence.csv` of `records` under `schema` into `w`;
/// `optimum` gives `f*` of a record.
pub fn write_convergence(
    w: impl Write,
    schema: Schema,
    records: &[RunRecord],
    optimum: impl Fn(&RunRecord) -> f64,
) -> io::Result<()> {
    let rows = records.iter().flat_map(|r| {
        let f_star = optimum(r);
        let key = schema.key_fields(r);
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
    write_csv(w, &schema.keyed_header(&CONVERGENCE_FIELDS), rows)
}

/// The bytes of `timing.csv`.
pub fn timing_csv(records: &[RunRecord]) -> Vec<u8> {
    in_memory(|w| write_timing(w, Schema::of(records), records))
}

/// Streams `timing.csv` of `records` under `schema` into `w`.
pub fn write_timing(w: impl Write, schema: Schema, records: &[RunRecord]) -> io::Result<()> {
    let rows = records.iter().map(|r| {
        let mut row = schema.key_fields(r);
        row.push(fmt_real(r.wall_seconds));
        row
    });
    write_csv(w, &schema.keyed_header(&TIMING_FIELDS), rows)
}

/// Streams a CSV file, a header then rows, into `w` exactly as
/// [`crate::files::csv_bytes`] writes it to memory.
fn write_csv<W, H, R, I>(w: W, header: &[H], rows: I) -> io::Result<()>
where
    W: Write,
    H: AsRef<[u8]>,
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
    I: IntoIterator<Item = R>,
{
    let mut w = csv::WriterBuilder::new().flexible(true).from_writer(w);
    w.write_record(header)?;
    for row in rows {
        w.write_record(row)?;
    }
    w.flush()
}

/// The bytes that `write` streams, in memory.
fn in_memory(write: impl FnOnce(&mut Vec<u8>) -> io::Result<()>) -> Vec<u8> {
    let mut bytes = Vec::new();
    write(&mut bytes).expect("writing to memory cannot fail");
    bytes
}

/// Writes the result files of `records`, complete and in their final order,
/// into `out`: `runs.csv`, `convergence.csv`, `timing.csv`, `hits.csv` when
/// `hits` (the campaign has benchmark problems) and, when some run is a fit,
/// `fits.csv` and `segments.csv`. Each file is streamed to its temporary
/// file and renamed into place, so no file's text is ever held in memory
/// whole; `optimum` gives `f*` of a record.
pub(super) fn write_files(
    spec: &Spec,
    out: &Path,
    records: &[RunRecord],
    optimum: impl Fn(&RunRecord) -> f64,
    hits: bool,
) -> Result<(), IoError> {
    let schema = Schema::of_spec(spec);
    debug_assert_eq!(schema, Schema::of(records));
    let stream = |name: &str, write: &dyn Fn(&mut std::fs::File) -> io::Result<()>| {
        write_atomic_with(&out.join(name), |f| write(f))
    };
    stream("runs.csv", &|f| write_runs(f, schema, records))?;
    stream("convergence.csv", &|f| {
        write_convergence(f, schema, records, &optimum)
    })?;
    stream("timing.csv", &|f| write_timing(f, schema, records))?;
    if hits {
        stream("hits.csv", &|f| write_hits(f, schema, records))?;
    }
    if records.iter().any(|r| r.fit.is_some()) {
        stream("fits.csv", &|f| write_fits(f, schema, records))?;
        stream("segments.csv", &|f| write_segments(f, schema, records))?;
    }
    Ok(())
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

/// Parses a transform name.
pub(super) fn parse_transform(path: &Path, line: u64, text: &str) -> Result<Transform, ReadError> {
    Transform::from_name(text).ok_or_else(|| {
        data(
            path,
            line,
            DataProblem::Cell {
                column: "transform".to_owned(),
                text: text.to_owned(),
            },
        )
    })
}

/// A record from the fields of a `runs.csv` row in the layout of
/// [`run_fields`] (no transform and instance columns).
pub(super) fn record_from_fields(
    path: &Path,
    line: u64,
    f: &csv::StringRecord,
) -> Result<RunRecord, ReadError> {
    let fields: Vec<&str> = f.iter().collect();
    record_from(path, line, &fields)
}

fn record_from(path: &Path, line: u64, f: &[&str]) -> Result<RunRecord, ReadError> {
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
    let get = |i: usize| f.get(i).copied().unwrap_or("");
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
        transform: Transform::None,
        instance: 1,
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
        hits: Vec::new(),
        fit: None,
        wall_seconds: 0.0,
    })
}

/// The header of `reader`, checked by `schema_of` (which gives the schema
/// the header belongs to); `expected` names the legacy layout in the error,
/// which says how many columns the first line has but never quotes it.
fn read_header(
    path: &Path,
    reader: &mut CsvFile,
    expected: &[&str],
    schema_of: impl Fn(&[&str]) -> Option<Schema>,
) -> Result<Schema, ReadError> {
    let header = reader
        .headers()
        .map_err(|e| data(path, 1, DataProblem::Csv(e)))?;
    let found: Vec<&str> = header.iter().collect();
    schema_of(&found).ok_or_else(|| {
        data(
            path,
            1,
            DataProblem::Header {
                expected: expected.iter().map(|c| c.to_string()).collect(),
                found: found.len(),
            },
        )
    })
}

/// Whether the header line of the CSV file at `path` has the column `name`.
fn header_has(path: &Path, name: &str) -> Result<bool, ReadError> {
    let mut reader = open_csv(path, RESULT_LIMITS, true)?;
    let header = reader
        .headers()
        .map_err(|e| data(path, 1, DataProblem::Csv(e)))?;
    Ok(header.iter().any(|h| h == name))
}

/// Reads `runs.csv` alone (traces empty, wall time 0): the input of reports,
/// which may also come from outside this tool.
pub fn read_runs(path: &Path) -> Result<Vec<RunRecord>, ReadError> {
    read_runs_with(path, false)
}

/// Reads `runs.csv`; `strict` (the file of a campaign of this tool, which
/// never writes a NaN objective) refuses a NaN `best` or `error`.
fn read_runs_with(path: &Path, strict: bool) -> Result<Vec<RunRecord>, ReadError> {
    let mut reader = open_csv(path, RUNS_LIMITS, true)?;
    let schema = read_header(path, &mut reader, &RUNS_HEADER, Schema::from_runs_header)?;
    let mut out = Vec::new();
    let mut row = csv::StringRecord::new();
    loop {
        let line = reader.position().line();
        match reader.read_record(&mut row) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(data(path, line, DataProblem::Csv(e))),
        }
        let line = row.position().map_or(line, |p| p.line());
        let mut fields: Vec<&str> = row.iter().collect();
        let factors = if schema.instances && fields.len() >= RUNS_HEADER.len() + 2 {
            let f: Vec<&str> = fields.drain(6..8).collect();
            Some((f[0], f[1]))
        } else {
            None
        };
        let mut rec = record_from(path, line, &fields)?;
        if strict {
            parse_real(path, line, "best", fields[8], Real::NotNan)?;
            parse_real(path, line, "error", fields[9], Real::NotNan)?;
        }
        if let Some((t, k)) = factors {
            rec.transform = parse_transform(path, line, t)?;
            rec.instance = parse(path, line, "instance", k)?;
        }
        out.push(rec);
    }
    Ok(out)
}

/// The run keys of a keyed file under `schema`, mapped to their records.
struct KeyIndex {
    schema: Schema,
    index: HashMap<(String, String, Option<u64>, u32), usize>,
}

impl KeyIndex {
    fn new(schema: Schema, records: &[RunRecord]) -> KeyIndex {
        let index = records
            .iter()
            .enumerate()
            .map(|(i, r)| {
                let budget = schema.keyed_budget.then_some(r.budget);
                ((r.cell_key(), r.match_key(), budget, r.run), i)
            })
            .collect();
        KeyIndex { schema, index }
    }

    /// The record a keyed row belongs to.
    fn lookup(&self, path: &Path, line: u64, row: &csv::StringRecord) -> Result<usize, ReadError> {
        let mut col = 5;
        let budget = if self.schema.keyed_budget {
            col += 1;
            Some(parse(path, line, "budget", &row[5])?)
        } else {
            None
        };
        let (transform, instance) = if self.schema.instances {
            col += 2;
            (
                parse_transform(path, line, &row[col - 2])?,
                parse(path, line, "instance", &row[col - 1])?,
            )
        } else {
            (Transform::None, 1)
        };
        let run: u32 = parse(path, line, "run", &row[col])?;
        let key = (
            format!("{}:{}[{}]", &row[0], &row[1], &row[2]),
            format!(
                "{}-{}{}",
                &row[3],
                &row[4],
                factor_suffix(transform, instance, true, true)
            ),
            budget,
            run,
        );
        self.index
            .get(&key)
            .copied()
            .ok_or_else(|| data(path, line, DataProblem::UnknownRun))
    }
}

/// Reads the rows of a keyed CSV file whose columns after the run key are
/// `rest`, checking the header and every row's column count, and hands each
/// record index, its fields after the key and its line number to `row`.
fn read_keyed(
    path: &Path,
    rest: &[&'static str],
    records: &[RunRecord],
    mut row: impl FnMut(usize, &[&str], u64) -> Result<(), ReadError>,
) -> Result<(), ReadError> {
    let mut reader = open_csv(path, RESULT_LIMITS, true)?;
    let legacy = Schema::default().keyed_header(rest);
    let schema = read_header(path, &mut reader, &legacy, |h| {
        Schema::from_keyed_header(h, rest)
    })?;
    let index = KeyIndex::new(schema, records);
    let width = schema.key_len() + rest.len();
    let mut r = csv::StringRecord::new();
    loop {
        let line = reader.position().line();
        match reader.read_record(&mut r) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(data(path, line, DataProblem::Csv(e))),
        }
        let line = r.position().map_or(line, |p| p.line());
        if r.len() != width {
            return Err(data(path, line, DataProblem::WrongColumnCount));
        }
        let k = index.lookup(path, line, &r)?;
        let fields: Vec<&str> = r.iter().skip(schema.key_len()).collect();
        row(k, &fields, line)?;
    }
    Ok(())
}

/// Reads a finished campaign directory's `runs.csv`, `convergence.csv`,
/// `timing.csv` and, when present, `hits.csv`, `fits.csv` and
/// `segments.csv` back into complete records.
pub fn read_results(dir: &Path) -> Result<Vec<RunRecord>, ReadError> {
    let mut records = read_runs_with(&dir.join("runs.csv"), true)?;
    let mut traces: Vec<Vec<TracePoint>> = vec![Vec::new(); records.len()];
    let path = dir.join("convergence.csv");
    read_keyed(&path, &CONVERGENCE_FIELDS, &records, |k, f, line| {
        let point = TracePoint {
            evaluations: parse(&path, line, "evaluations", f[0])?,
            best: parse_real(&path, line, "best", f[1], Real::NotNan)?,
        };
        parse_real(&path, line, "error", f[2], Real::NotNan)?;
        // Each run's checkpoints rise strictly: a row repeated or out of
        // order is not a trace this tool wrote.
        if traces[k]
            .last()
            .is_some_and(|p| p.evaluations >= point.evaluations)
        {
            return Err(data(&path, line, DataProblem::Order("evaluations", "rise")));
        }
        traces[k].push(point);
        Ok(())
    })?;
    let mut walls: Vec<Option<f64>> = vec![None; records.len()];
    let path = dir.join("timing.csv");
    read_keyed(&path, &TIMING_FIELDS, &records, |k, f, line| {
        let wall = parse_real(&path, line, "wall_seconds", f[0], Real::NonNegative)?;
        if walls[k].replace(wall).is_some() {
            return Err(data(&path, line, DataProblem::RepeatedRun));
        }
        Ok(())
    })?;
    if let Some(k) = walls.iter().position(Option::is_none) {
        return Err(data(&path, 0, DataProblem::NoRowFor(records[k].describe())));
    }
    let walls = walls.into_iter().map(|w| w.unwrap_or(0.0));
    let mut hits: Vec<Vec<TargetHit>> = vec![Vec::new(); records.len()];
    let path = dir.join("hits.csv");
    if path.exists() {
        read_keyed(&path, &HITS_FIELDS, &records, |k, f, line| {
            let hit = TargetHit {
                precision: parse_real(&path, line, "target", f[0], Real::Positive)?,
                evaluations: parse(&path, line, "evaluations", f[1])?,
            };
            // Each run reaches its targets from the largest down.
            if hits[k].last().is_some_and(|h| h.precision <= hit.precision) {
                return Err(data(&path, line, DataProblem::Order("target", "fall")));
            }
            hits[k].push(hit);
            Ok(())
        })?;
    }
    let mut fits: Vec<Option<FitDetail>> = vec![None; records.len()];
    if dir.join("fits.csv").exists() {
        let path = dir.join("fits.csv");
        let current = header_has(&path, "rms_distance")?;
        let two_sided = header_has(&path, "hausdorff")?;
        let (fit_rest, segment_rest): (&[&'static str], &[&'static str]) =
            match (current, two_sided) {
                (true, true) => (&FIT_FIELDS_CURRENT, &FIT_SEGMENT_HEADER),
                (true, false) => (&FIT_FIELDS_RMS, &FIT_SEGMENT_HEADER),
                _ => (&FIT_FIELDS, &SEGMENT_HEADER),
            };
        read_keyed(&path, fit_rest, &records, |k, f, line| {
            if fits[k]
                .replace(FitDetail::from_fields(&path, line, f)?)
                .is_some()
            {
                return Err(data(&path, line, DataProblem::RepeatedRun));
            }
            Ok(())
        })?;
        // Every fitting run (its problem is source/function/continuity)
        // has its row.
        if let Some(k) =
            (0..records.len()).find(|&k| fits[k].is_none() && records[k].problem.contains('/'))
        {
            return Err(data(&path, 0, DataProblem::NoRowFor(records[k].describe())));
        }
        let path = dir.join("segments.csv");
        read_keyed(&path, segment_rest, &records, |k, f, line| {
            let fit = fits[k]
                .as_mut()
                .ok_or_else(|| data(&path, line, DataProblem::NoFitRow))?;
            fit.segments.push(f.iter().map(|c| c.to_string()).collect());
            Ok(())
        })?;
    }
    for ((((r, t), w), h), f) in records
        .iter_mut()
        .zip(traces)
        .zip(walls)
        .zip(hits)
        .zip(fits)
    {
        r.trace = t;
        r.wall_seconds = w;
        r.hits = h;
        r.fit = f;
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
        transform: Transform::ShiftRotate,
        instance: 3,
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
        hits: vec![
            TargetHit {
                precision: 100.0,
                evaluations: 1,
            },
            TargetHit {
                precision: 1e-8,
                evaluations: 10,
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
        std::fs::write(dir.path().join("hits.csv"), hits_csv(&recs)).unwrap();
        assert_eq!(read_results(dir.path()).unwrap(), recs);
        let runs = std::fs::read_to_string(dir.path().join("runs.csv")).unwrap();
        assert!(
            runs.starts_with("algorithm,kind,params,problem,dim,budget,transform,instance,run,")
        );
        // A budget grid adds the budget to the keyed files.
        let mut grid = recs.clone();
        grid.extend(recs.iter().cloned().map(|mut r| {
            r.budget *= 10;
            r
        }));
        std::fs::write(dir.path().join("runs.csv"), runs_csv(&grid)).unwrap();
        std::fs::write(
            dir.path().join("convergence.csv"),
            convergence_csv(&grid, |_| 0.0),
        )
        .unwrap();
        std::fs::write(dir.path().join("timing.csv"), timing_csv(&grid)).unwrap();
        std::fs::write(dir.path().join("hits.csv"), hits_csv(&grid)).unwrap();
        let timing = std::fs::read_to_string(dir.path().join("timing.csv")).unwrap();
        assert!(timing.starts_with(
            "algorithm,kind,params,problem,dim,budget,transform,instance,run,wall_seconds"
        ));
        assert_eq!(read_results(dir.path()).unwrap(), grid);
    }
}
