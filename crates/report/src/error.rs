//! The report's error type.

use std::path::PathBuf;

use crate::experiment::{DataError, ReadError};
use crate::files::IoError;
use metabezier_plot::font::FontError;

/// Why a report could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A results file could not be read or is malformed.
    #[error(transparent)]
    Read(#[from] ReadError),
    /// A report file could not be written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The significance level is not in (0, 1).
    #[error("--alpha: the significance level must lie strictly between 0 and 1, found {0}")]
    Alpha(f64),
    /// A rope (region of practical equivalence) is not one the report can use.
    #[error("{origin}: {error}")]
    Rope {
        /// Where it was set: the spec's `[report]` key or `--rope`.
        origin: String,
        /// What is wrong with it.
        error: crate::verdicts::RopeError,
    },
    /// The claims file does not load, or a claim's primary row is missing.
    #[error(transparent)]
    Claims(#[from] crate::claims::ClaimError),
    /// An external runs.csv that a campaign's own reader would refuse: its
    /// file, line and what is wrong.
    #[error("{}: {message}", located(path, *line))]
    External {
        /// The external file.
        path: PathBuf,
        /// The line of the offending row (0: the file as a whole).
        line: usize,
        /// What is wrong and what was expected.
        message: String,
    },
    /// The requested reference algorithm is not in the results.
    #[error(
        "the reference algorithm \"{requested}\" is not in the results; the algorithms are: {}",
        names.join(", ")
    )]
    UnknownReference {
        /// The name asked for.
        requested: String,
        /// The configurations in the results.
        names: Vec<String>,
    },
    /// A place the report writes is a symbolic link out of the results
    /// directory.
    #[error(
        "{} is a symbolic link to {}, outside the results directory; the report writes only inside it: remove the link",
        path.display(),
        target.display()
    )]
    LinkOut {
        /// The link.
        path: PathBuf,
        /// Where it points.
        target: PathBuf,
    },
    /// The campaign in the directory is not finished.
    #[error(
        "{}: campaign unfinished (a journal.csv and no runs.csv): run `metabezier run SPEC --resume` to finish it",
        dir.display()
    )]
    Unfinished {
        /// The results directory.
        dir: PathBuf,
    },
    /// The rows of runs.csv do not state the campaign.
    #[error("{}: {problem}", path.display())]
    Rows {
        /// The runs.csv file.
        path: PathBuf,
        /// What is wrong.
        #[source]
        problem: super::integrity::RowProblem,
    },
    /// A directory given to `compare` is not a finished campaign's: no
    /// `runs.csv`, or a `journal.csv` (an unfinished or interrupted run).
    #[error("{}: {why}", dir.display())]
    CompareInput {
        /// The directory.
        dir: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// Two campaigns given to `compare` share no (cell, problem): there is
    /// nothing to compare.
    #[error(
        "{} and {} share no algorithm configuration (algorithm label and parameters) on a \
         problem at the same budget, so there is nothing to compare; the first has {}, the \
         second {}",
        a.display(),
        b.display(),
        a_cells.join(", "),
        b_cells.join(", ")
    )]
    NothingShared {
        /// The first campaign's directory.
        a: PathBuf,
        /// The other campaign's directory.
        b: PathBuf,
        /// A few of the first campaign's (cell, problem) pairs.
        a_cells: Vec<String>,
        /// A few of the other campaign's (cell, problem) pairs.
        b_cells: Vec<String>,
    },
    /// `compare` was given fewer than two directories, or one twice.
    #[error("compare: {0}")]
    CompareUsage(String),
    /// The embedded font could not be registered.
    #[error(transparent)]
    Font(#[from] FontError),
    /// A plot could not be drawn.
    #[error("cannot draw {file}: {message}")]
    Draw {
        /// The file being drawn, such as `convergence.svg`.
        file: String,
        /// The plotting library's message.
        message: String,
    },
}

/// `path:line`, or `path` alone for line 0.
fn located(path: &std::path::Path, line: usize) -> String {
    if line == 0 {
        format!("--external {}", path.display())
    } else {
        format!("--external {}:{line}", path.display())
    }
}

impl From<DataError> for ReportError {
    fn from(e: DataError) -> Self {
        ReportError::Read(ReadError::Data(e))
    }
}
