//! Errors of the CT layer: every failure names the file or the slice it
//! concerns, so that a user with their own scan can act on it.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::files::IoError;

/// An error while reading, checking or processing CT data.
#[derive(Debug)]
pub enum CtError {
    /// A file could not be opened, read or listed.
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// An output file could not be written (see [`crate::files::write_atomic`]).
    Write(IoError),
    /// An `.inv3` project is truncated or corrupt (bad gzip or tar stream,
    /// missing member, malformed `main.plist`).
    Inv3 {
        /// The `.inv3` file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A raw voxel array does not hold `nx·ny·nz` samples of the declared type.
    ByteCount {
        /// The file holding the array.
        path: PathBuf,
        /// Bytes the declared shape needs.
        expected: u64,
        /// Bytes found.
        found: u64,
    },
    /// A DICOM file is corrupt or of an unsupported kind.
    Dicom {
        /// The DICOM file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// A DICOM series has slices of different sizes.
    SizeMismatch {
        /// The first file that disagrees with the first slice.
        path: PathBuf,
        /// (rows, columns) of the first slice.
        expected: (usize, usize),
        /// (rows, columns) of this slice.
        found: (usize, usize),
    },
    /// A DICOM series has inconsistent pixel spacing or uneven slice gaps.
    SpacingMismatch {
        /// The first file that disagrees.
        path: PathBuf,
        /// Which spacing: "row", "column" or "slice gap".
        axis: &'static str,
        /// The value of the first slice (or the first gap), in mm.
        expected: f64,
        /// The value of this file, in mm.
        found: f64,
    },
    /// A slice has no voxel at or above the bone threshold.
    NoBone {
        /// The slice index (z) in its volume.
        slice: usize,
        /// The threshold in HU.
        threshold: i16,
    },
    /// The defect crosses the mid-sagittal line, so mirroring cannot supply
    /// its template.
    DefectCrossesMidline {
        /// x of A in mm.
        a_x: f64,
        /// x of B in mm.
        b_x: f64,
        /// x of the mid-sagittal line in mm.
        midline_x: f64,
    },
    /// A point that must lie on a contour (A, B, or a mirrored end) is too far
    /// from it.
    NotOnContour {
        /// Which point.
        what: &'static str,
        /// Its distance to the contour, in mm.
        distance_mm: f64,
        /// The largest distance accepted, in mm.
        tolerance_mm: f64,
    },
    /// An argument is invalid (empty input, mismatched lengths, ...).
    Invalid(String),
}

impl CtError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, source: io::Error) -> Self {
        CtError::Io {
            path: path.to_owned(),
            source,
        }
    }

    /// A corrupt-`.inv3` error on `path`.
    pub fn inv3(path: &Path, message: impl Into<String>) -> Self {
        CtError::Inv3 {
            path: path.to_owned(),
            message: message.into(),
        }
    }

    /// A corrupt-DICOM error on `path`.
    pub fn dicom(path: &Path, message: impl Into<String>) -> Self {
        CtError::Dicom {
            path: path.to_owned(),
            message: message.into(),
        }
    }
}

impl fmt::Display for CtError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CtError::Io { path, source } => {
                write!(f, "{}: cannot read: {source}", path.display())
            }
            CtError::Write(e) => e.fmt(f),
            CtError::Inv3 { path, message } => {
                write!(f, "{}: truncated or corrupt .inv3: {message}", path.display())
            }
            CtError::ByteCount {
                path,
                expected,
                found,
            } => write!(
                f,
                "{}: wrong byte count: the shape needs {expected} bytes, found {found}",
                path.display()
            ),
            CtError::Dicom { path, message } => {
                write!(f, "{}: corrupt or unsupported DICOM: {message}", path.display())
            }
            CtError::SizeMismatch {
                path,
                expected,
                found,
            } => write!(
                f,
                "{}: slice size {}x{} (rows x columns) differs from the series' {}x{}",
                path.display(),
                found.0,
                found.1,
                expected.0,
                expected.1
            ),
            CtError::SpacingMismatch {
                path,
                axis,
                expected,
                found,
            } => write!(
                f,
                "{}: mismatched slice spacing: {axis} spacing {found} mm differs from the series' {expected} mm",
                path.display()
            ),
            CtError::NoBone { slice, threshold } => write!(
                f,
                "slice {slice}: no bone: no voxel at or above {threshold} HU"
            ),
            CtError::DefectCrossesMidline { a_x, b_x, midline_x } => write!(
                f,
                "the defect crosses the mid-sagittal line (A at x = {a_x:.2} mm, B at x = {b_x:.2} mm, \
                 M_x at x = {midline_x:.2} mm): the mirror technique cannot supply a template; \
                 give an explicit template contour instead"
            ),
            CtError::NotOnContour {
                what,
                distance_mm,
                tolerance_mm,
            } => write!(
                f,
                "{what} is not on the bone contour: {distance_mm:.2} mm away (tolerance {tolerance_mm:.2} mm)"
            ),
            CtError::Invalid(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for CtError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CtError::Io { source, .. } => Some(source),
            CtError::Write(e) => Some(e),
            _ => None,
        }
    }
}

impl From<IoError> for CtError {
    fn from(e: IoError) -> Self {
        CtError::Write(e)
    }
}
