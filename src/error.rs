//! The crate's error type: every failure a user can cause, with the file
//! and the place it concerns. Each room has its own error enum with real
//! variants; [`Error`] wraps them (keeping their messages and causes, see
//! [`std::error::Error::source`]) and adds the command line's own argument
//! errors ([`UsageError`]).

use crate::experiment::archive::ArchiveError;
use crate::experiment::{ExperimentError, ReadError, SpecError};
use crate::files::IoError;
use crate::fit::FitError;
use crate::implant::ImplantError;
use crate::reconstruction::{ScoreError, SourceError};
use crate::report::ReportError;

/// An error reported to the user; none of these is a panic.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A campaign failed: its spec, its files or its resume or merge.
    #[error(transparent)]
    Experiment(#[from] ExperimentError),
    /// An archive could not be written, or does not check.
    #[error(transparent)]
    Archive(#[from] ArchiveError),
    /// A report could not be written.
    #[error(transparent)]
    Report(#[from] ReportError),
    /// A report was written, but figures its results should allow could
    /// not be drawn.
    #[error(
        "{}: written, but {} figure(s) the results should allow could not be drawn: {}; \
         the report's summary names them (pass --keep-going to accept such a report)",
        report.display(),
        faults.len(),
        faults.join("; ")
    )]
    Figures {
        /// The report written.
        report: std::path::PathBuf,
        /// What could not be drawn, and why.
        faults: Vec<String>,
    },
    /// The chapter-6 implant experiment failed.
    #[error(transparent)]
    Implant(#[from] ImplantError),
    /// An outline source could not be read.
    #[error(transparent)]
    Source(#[from] SourceError),
    /// A fit of an outline failed.
    #[error("{}: {source}", input)]
    Fit {
        /// The input as the user wrote it.
        input: String,
        /// Why the fit failed.
        #[source]
        source: FitError,
    },
    /// Some contours of an input could not be fitted; the others were
    /// written.
    #[error(
        "{input}: {} of {} contour(s) could not be fitted (the other {} are in {}):{}",
        failed.len(),
        failed.len() + fitted,
        fitted,
        out.display(),
        failed.iter().map(|e| format!("\n  {e}")).collect::<String>()
    )]
    ContoursFailed {
        /// The input as the user wrote it.
        input: String,
        /// How many contours were fitted and written.
        fitted: usize,
        /// Where they were written.
        out: std::path::PathBuf,
        /// Why each of the others failed (each names its contour).
        failed: Vec<FitError>,
    },
    /// Curves could not be scored against an outline.
    #[error("{}: {source}", curves.display())]
    Score {
        /// The curves' file.
        curves: std::path::PathBuf,
        /// Why they could not be scored.
        #[source]
        source: ScoreError,
    },
    /// A command-line argument is invalid.
    #[error(transparent)]
    Usage(#[from] UsageError),
}

/// A command-line argument that the argument parser accepts but the
/// command cannot use.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum UsageError {
    /// `--algorithm` names no method.
    #[error("--algorithm: unknown algorithm \"{name}\"; valid choices: {}", choices.join(", "))]
    UnknownAlgorithm {
        /// The name given.
        name: String,
        /// Every valid method name.
        choices: Vec<String>,
    },
    /// `--tolerance` is not a positive distance.
    #[error("--tolerance: expected a finite distance > 0 (data units), found {0}")]
    Tolerance(f64),
    /// `--foreground` on an input that is not an image.
    #[error(
        "--foreground: {0} is not an image (a CSV, SVG or glyph outline has no background to tell apart); drop the option"
    )]
    ForegroundNotImage(String),
    /// `--true-breaks` on an input that is not a glyph.
    #[error(
        "--true-breaks: {0} is not a glyph, so it has no true break points; use --segments or --tolerance"
    )]
    NotAGlyph(String),
    /// `--budget` above the limit without `--allow-large`.
    #[error(
        "--budget {0}: more than the limit of {max} evaluations per segment; pass --allow-large to run it",
        max = crate::experiment::spec::MAX_BUDGET
    )]
    Budget(u64),
    /// `archive` given neither `DIR --out FILE` nor `--verify FILE` alone.
    #[error("archive: give DIR --out FILE.tar.gz to write an archive, or --verify FILE alone to check one")]
    ArchiveMode,
}

impl From<SpecError> for Error {
    fn from(e: SpecError) -> Self {
        Error::Experiment(e.into())
    }
}

impl From<IoError> for Error {
    fn from(e: IoError) -> Self {
        Error::Experiment(e.into())
    }
}

impl From<ReadError> for Error {
    fn from(e: ReadError) -> Self {
        Error::Experiment(e.into())
    }
}
