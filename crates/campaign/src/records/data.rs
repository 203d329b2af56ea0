//! What is wrong with a results file, and the reading of its reals.

use std::path::Path;

use crate::files::{excerpt, IoError};

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
pub(crate) enum Real {
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
pub(crate) fn parse_real(
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

pub(crate) fn data(path: &Path, line: u64, problem: DataProblem) -> ReadError {
    ReadError::Data(DataError::new(path, line, problem))
}

/// The cell `text` of `column` at `line` of `path` read as a `T`, or the
/// located error of a cell its column cannot hold.
pub(crate) fn parse<T: std::str::FromStr>(
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
