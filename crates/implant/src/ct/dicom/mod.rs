//! DICOM CT series: a reader for uncompressed single-frame grey-scale images
//! (implicit or explicit VR little endian) and a minimal explicit-VR
//! little-endian CT writer (the writer is built on the pure-Rust
//! `dicom-object` crate).
//!
//! The reader walks the file's element headers itself (PS3.5 §7: the file
//! meta information, then the data set, with sequences and items of
//! defined or undefined length) and checks every declared length against
//! the bytes that remain in the file and in the enclosing sequence or item
//! before it looks at a value; values are borrowed from the file's bytes,
//! so reading a slice holds the file and its HU samples and nothing
//! proportional to what the file merely declares. Limits:
//! [`MAX_DICOM_FILE_BYTES`] and [`MAX_DICOM_NESTING`].
//!
//! Attributes used (DICOM PS3.3, C.7.6.2 Image Plane and C.7.6.3 Image Pixel
//! modules, C.11.1 Modality LUT): Rows, Columns, BitsAllocated (8 or 16),
//! BitsStored, PixelRepresentation, SamplesPerPixel (1), RescaleSlope and
//! RescaleIntercept (`HU = raw·slope + intercept`), PixelSpacing (row
//! spacing, column spacing), ImagePositionPatient and ImageOrientationPatient
//! (slice position along the normal `n = r × c`), else SliceLocation, else
//! InstanceNumber.

use std::path::PathBuf;

mod series;
mod slice;
mod walk;
mod writer;

pub use series::{read_dicom_dir, read_dicom_series};
pub use slice::{dicom_slice_from_bytes, read_dicom_file};
pub use writer::{dicom_slice_bytes, write_dicom_series};

/// The largest file read as one DICOM slice: 256 MiB. A CT slice is
/// 512×512 to 2048×2048 16-bit pixels (0.5 to 8 MiB); 256 MiB holds an
/// 8192×8192 16-bit image twice over. A larger file is refused before it is
/// read.
pub const MAX_DICOM_FILE_BYTES: u64 = 256 << 20;

/// The deepest nesting of sequences in a DICOM file: 32. Real CT headers
/// nest three or four deep (e.g. a code sequence in a procedure sequence);
/// a deeper file is refused.
pub const MAX_DICOM_NESTING: usize = 32;

/// One decoded DICOM image: HU samples and its geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct DicomSlice {
    /// The file it came from.
    pub path: PathBuf,
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Spacing between rows (y) in mm, PixelSpacing\[0\].
    pub row_spacing: f64,
    /// Spacing between columns (x) in mm, PixelSpacing\[1\].
    pub col_spacing: f64,
    /// ImagePositionPatient (x, y, z) of the first pixel in mm, if present.
    pub position: Option<[f64; 3]>,
    /// ImageOrientationPatient (row then column direction cosines), if present.
    pub orientation: Option<[f64; 6]>,
    /// SliceLocation in mm, if present.
    pub slice_location: Option<f64>,
    /// Position along the slice normal in mm, used to sort a series.
    pub location: f64,
    /// SliceThickness in mm, if present.
    pub thickness: Option<f64>,
    /// Row-major HU samples (`raw·slope + intercept`, rounded, clamped to i16).
    pub hu: Vec<i16>,
}

/// The slice normal `n = r × c` of ImageOrientationPatient `o`.
fn normal(o: &[f64; 6]) -> [f64; 3] {
    [
        o[1] * o[5] - o[2] * o[4],
        o[2] * o[3] - o[0] * o[5],
        o[0] * o[4] - o[1] * o[3],
    ]
}
