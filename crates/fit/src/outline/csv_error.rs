//! Why a CSV outline file cannot be read: the file, its line and column,
//! and what was expected there.

use std::fmt;
use std::path::PathBuf;

/// What is wrong with a CSV file of `x,y` points ([`super::csv_from_bytes`]).
#[derive(Debug)]
pub enum CsvError {
    /// A cell is not a finite number.
    Number {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// 1-based column (1 = x, 2 = y).
        column: usize,
        /// The text found in the cell.
        text: String,
    },
    /// A coordinate is finite but beyond ±[`crate::outline::MAX_COORDINATE`].
    Range {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// 1-based column (1 = x, 2 = y).
        column: usize,
        /// The value found.
        value: f64,
    },
    /// The points of the outline span too little for E to be resolved
    /// ([`crate::outline::MIN_EXTENT`], [`crate::outline::MIN_RELATIVE_EXTENT`]).
    Extent {
        /// The CSV file.
        path: PathBuf,
        /// The diagonal of the points' bounding box.
        extent: f64,
        /// The largest coordinate magnitude.
        largest: f64,
        /// The smallest diagonal accepted.
        need: f64,
    },
    /// The file goes beyond a limit of the reader
    /// ([`crate::outline::MAX_CSV_POINTS`], [`crate::outline::MAX_CSV_LINE_BYTES`]).
    Limit {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line where the limit was passed.
        line: u64,
        /// What is counted (`points`, `bytes on one line`).
        what: &'static str,
        /// How many were found (at least).
        found: usize,
        /// The limit.
        limit: usize,
    },
    /// A line does not have exactly two cells `x,y`.
    Fields {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: u64,
        /// Number of cells found.
        found: usize,
    },
    /// The file is malformed in another way (such as invalid UTF-8).
    Malformed {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line, or 0 if unknown.
        line: u64,
        /// The reader's explanation.
        message: String,
    },
}

impl fmt::Display for CsvError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Range {
                path,
                line,
                column,
                value,
            } => write!(
                f,
                "{}:{line}: column {column} ({}): {value:e} is beyond ±1e15, the range of coordinates this tool fits (squared distances must not overflow)",
                path.display(),
                if *column == 1 { "x" } else { "y" }
            ),
            Self::Extent {
                path,
                extent,
                largest,
                need,
            } => write!(
                f,
                "{}: the points span {extent:e} units (bounding-box diagonal) at coordinates up to {largest:e}; an outline must span at least {need:e} (1e-9 of its largest coordinate, and 1e-100) for its squared distances to be resolved: rescale the data",
                path.display()
            ),
            Self::Number {
                path,
                line,
                column,
                text,
            } => {
                let axis = if *column == 1 { "x" } else { "y" };
                write!(
                    f,
                    "{}:{line}: column {column} ({axis}): expected a finite number, found \"{}\"",
                    path.display(),
                    crate::files::excerpt(text)
                )
            }
            Self::Limit {
                path,
                line,
                what,
                found,
                limit,
            } => write!(
                f,
                "{}:{line}: at least {found} {what}, beyond this reader's limit of {limit} \
                 (expected one \"x,y\" pair per line)",
                path.display()
            ),
            Self::Fields { path, line, found } => write!(
                f,
                "{}:{line}: expected 2 cells \"x,y\", found {found}",
                path.display()
            ),
            Self::Malformed {
                path,
                line: 0,
                message,
            } => write!(f, "{}: {message}", path.display()),
            Self::Malformed {
                path,
                line,
                message,
            } => write!(f, "{}:{line}: {message}", path.display()),
        }
    }
}

impl std::error::Error for CsvError {}
