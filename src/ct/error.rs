//! Errors of the CT layer: every failure names the file or the slice it
//! concerns, so that a user with their own scan can act on it.

use std::io;
use std::path::{Path, PathBuf};

use super::plist::PlistError;
use crate::files::IoError;
use crate::fit::FitError;

/// An error while reading, checking or processing CT data.
#[derive(Debug, thiserror::Error)]
pub enum CtError {
    // Reading and writing files.
    /// A file could not be opened, read or listed.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// An output file could not be written (see [`crate::files::write_atomic`]).
    #[error("{0}")]
    Write(#[from] IoError),
    /// An `.inv3` project is truncated or corrupt (bad gzip or tar stream,
    /// missing member, malformed `main.plist`).
    #[error("{}: truncated or corrupt .inv3: {problem}", path.display())]
    Inv3 {
        /// The `.inv3` file.
        path: PathBuf,
        /// What is wrong.
        #[source]
        problem: Inv3Problem,
    },
    /// A raw voxel array does not hold `nx·ny·nz` samples of the declared type.
    #[error(
        "{}: wrong byte count: the shape needs {expected} bytes, found {found}",
        path.display()
    )]
    ByteCount {
        /// The file holding the array.
        path: PathBuf,
        /// Bytes the declared shape needs.
        expected: u64,
        /// Bytes found.
        found: u64,
    },
    /// A DICOM file is corrupt or of an unsupported kind.
    #[error("{}: corrupt or unsupported DICOM: {problem}", path.display())]
    Dicom {
        /// The DICOM file.
        path: PathBuf,
        /// What is wrong.
        #[source]
        problem: DicomProblem,
    },
    /// A DICOM series was given no files.
    #[error("empty DICOM series: no files")]
    EmptySeries,
    /// A DICOM series has slices of different sizes.
    #[error(
        "{}: slice size {}x{} (rows x columns) differs from the series' {}x{}",
        path.display(),
        found.0,
        found.1,
        expected.0,
        expected.1
    )]
    SizeMismatch {
        /// The first file that disagrees with the first slice.
        path: PathBuf,
        /// (rows, columns) of the first slice.
        expected: (usize, usize),
        /// (rows, columns) of this slice.
        found: (usize, usize),
    },
    /// A DICOM series has inconsistent pixel spacing or uneven slice gaps.
    #[error(
        "{}: mismatched slice spacing: {axis} spacing {found} mm differs from the series' {expected} mm",
        path.display()
    )]
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
    /// A HU value does not fit the DICOM writer's encoding
    /// (`raw = HU + 1024` as a signed 16-bit sample).
    #[error("HU {hu} in slice {slice} does not fit the DICOM encoding")]
    HuOutOfRange {
        /// The value.
        hu: i16,
        /// The slice (volume index).
        slice: usize,
    },
    /// A slice has more rows or columns than DICOM can describe (65535).
    #[error("slice too large for DICOM")]
    SliceTooLarge {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
    },
    /// The DICOM file meta information could not be built.
    #[error("DICOM meta: {source}")]
    DicomMeta {
        /// The DICOM library's error.
        source: Box<dicom_object::WithMetaError>,
    },
    /// A DICOM object could not be encoded.
    #[error("DICOM encoding: {source}")]
    DicomEncode {
        /// The DICOM library's error.
        source: Box<dicom_object::WriteError>,
    },

    // Volumes, masks and contours.
    /// A volume with a zero dimension.
    #[error("volume size {nx}x{ny}x{nz} has a zero dimension")]
    ZeroDimension {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
        /// Slices.
        nz: usize,
    },
    /// A volume whose voxel count does not fit in `usize`.
    #[error("volume size overflows")]
    VolumeOverflow {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
        /// Slices.
        nz: usize,
    },
    /// The samples given for a volume do not match its shape.
    #[error("volume {nx}x{ny}x{nz} needs {expected} voxels, got {found}")]
    VoxelCount {
        /// Columns.
        nx: usize,
        /// Rows.
        ny: usize,
        /// Slices.
        nz: usize,
        /// `nx·ny·nz`.
        expected: usize,
        /// Samples given.
        found: usize,
    },
    /// A voxel spacing that is not a positive finite number.
    #[error("voxel spacing must be positive and finite, got {value}")]
    BadSpacing {
        /// The spacing given, in mm.
        value: f64,
    },
    /// The axes given for a volume's frame are zero, not finite or coplanar.
    #[error(
        "bad volume axes {axes:?}: expected three finite, non-zero, non-coplanar direction vectors"
    )]
    BadAxes {
        /// The axes given.
        axes: [[f64; 3]; 3],
    },
    /// The slices of a DICOM series have different orientations.
    #[error("{}: ImageOrientationPatient {found:?} differs from the series' {expected:?}", path.display())]
    OrientationMismatch {
        /// The first slice with another orientation.
        path: PathBuf,
        /// The series' orientation (first slice).
        expected: [f64; 6],
        /// This slice's.
        found: [f64; 6],
    },
    /// A slice has no voxel at or above the bone threshold.
    #[error("slice {slice}: no bone: no voxel at or above {threshold} HU")]
    NoBone {
        /// The slice index (z) in its volume.
        slice: usize,
        /// The threshold in HU.
        threshold: i16,
    },
    /// Two masks compared by a metric lie on different grids.
    #[error(
        "masks on different grids: {}x{}x{} vs {}x{}x{}",
        a[0], a[1], a[2], b[0], b[1], b[2]
    )]
    GridMismatch {
        /// `[nx, ny, nz]` of the first mask.
        a: [usize; 3],
        /// `[nx, ny, nz]` of the second mask.
        b: [usize; 3],
    },
    /// HD95 asked of an empty mask.
    #[error("HD95 of an empty mask is undefined")]
    EmptyMask,
    /// A contour deviation asked of an empty polyline or with a step that
    /// is not positive.
    #[error("contour deviation needs two non-empty polylines and a positive step")]
    BadDeviationInput,
    /// No bone loop of the slice encloses a positive area.
    #[error("no closed bone contour in the slice")]
    NoClosedContour,
    /// The slice's bone ring has no inner cavity and no defect ends were
    /// given to cut it.
    #[error("the bone ring is open (no inner cavity): give the defect ends A and B")]
    OpenRing,
    /// Defect detection found no gap in the bone ring.
    #[error("no defect found (the bone ring is closed): give A and B for this slice")]
    NoDefectFound,
    /// The mirror technique was given an empty outer contour.
    #[error("the outer contour is empty")]
    EmptyContour,

    // The mirror technique and the implant wall.
    /// The defect crosses the mid-sagittal line, so mirroring cannot supply
    /// its template.
    #[error(
        "the defect crosses the mid-sagittal line (A at x = {a_x:.2} mm, B at x = {b_x:.2} mm, \
         the midline at x = {midline_x:.2} mm): the mirror technique cannot supply a template; \
         give an explicit template contour instead (`template = \"file.csv\"` in [defect])"
    )]
    DefectCrossesMidline {
        /// x of A in mm.
        a_x: f64,
        /// x of B in mm.
        b_x: f64,
        /// x of the mid-sagittal line at the defect's height, in mm.
        midline_x: f64,
    },
    /// A point that must lie on a contour (A, B, or a mirrored end) is too far
    /// from it.
    #[error(
        "{what} is not on the bone contour: {distance_mm:.2} mm away (tolerance {tolerance_mm:.2} mm)"
    )]
    NotOnContour {
        /// Which point.
        what: &'static str,
        /// Its distance to the contour, in mm.
        distance_mm: f64,
        /// The largest distance accepted, in mm.
        tolerance_mm: f64,
    },
    /// Too few rays across the defect meet the mirrored contour to make a
    /// template.
    #[error("the mirrored contour does not cover the defect")]
    TemplateNotCovered {
        /// Template points found.
        points: usize,
        /// Points the wall's function needs.
        needed: usize,
    },
    /// Too few rays next to a defect end meet the intact contour to fit its
    /// tangent.
    #[error("too little intact outer contour next to the defect ends")]
    TooLittleIntactContour {
        /// Envelope points found before A.
        before: usize,
        /// Envelope points found after B.
        after: usize,
    },
    /// No bone along the inward ray next to a defect end, so the wall has
    /// no thickness.
    #[error("no bone next to the defect ends: cannot measure the bone thickness")]
    NoBoneAtEnds {
        /// Thickness measured next to A, in mm.
        thickness_a: f64,
        /// Thickness measured next to B, in mm.
        thickness_b: f64,
    },
    /// The curve fit of the outer wall (or of a neighbouring tangent) was
    /// refused.
    #[error("the outer-wall fit failed: {source}")]
    OuterWallFit {
        /// The fitting error.
        source: FitError,
    },

    // Artificial defects of the validation.
    /// The outer envelope has no point at the defect's centre angle.
    #[error("no outer contour at {position_deg}° from the centre")]
    NoContourAt {
        /// The defect's centre angle in degrees.
        position_deg: f64,
    },
    /// A ray of the artificial defect misses the outer contour.
    #[error("the defect leaves the outer contour")]
    DefectLeavesContour,
    /// The artificial defect's wedge holds no bone pixel.
    #[error("the cut removed no bone")]
    CutRemovedNoBone,

    /// Clipping the implant section to the tissue left nothing: the section
    /// lies entirely in bone.
    #[error("the implant section lies entirely in bone (nothing left after clipping to the tissue below the threshold)")]
    ClippedAway,

    // Meshes and pictures.
    /// Lofting was given fewer than two sections or a height count that
    /// differs from the section count.
    #[error(
        "lofting needs at least two sections with one height each (got {sections} sections, {heights} heights)"
    )]
    LoftSections {
        /// Sections given.
        sections: usize,
        /// Heights given.
        heights: usize,
    },
    /// Lofting was asked for rings of fewer than three points.
    #[error("lofting needs n ≥ 3 points per ring")]
    LoftRingPoints {
        /// Points per ring asked for.
        n: usize,
    },
    /// The section heights of a loft do not increase strictly.
    #[error("section heights must increase strictly")]
    LoftHeights,
    /// A loft section is not a polygon with positive area.
    #[error("section {index} is not a polygon with positive area")]
    DegenerateSection {
        /// The section's index.
        index: usize,
    },
    /// A binary STL file is shorter than its 84-byte header.
    #[error(
        "{}: bad binary STL: {len} bytes, shorter than the 84-byte header",
        path.display()
    )]
    StlTooShort {
        /// The file (only used in messages).
        path: PathBuf,
        /// Its length in bytes.
        len: usize,
    },
    /// A binary STL file's length disagrees with its triangle count.
    #[error(
        "{}: bad binary STL: {triangles} triangles need {expected} bytes, found {found}",
        path.display()
    )]
    StlLength {
        /// The file (only used in messages).
        path: PathBuf,
        /// The triangle count of the header.
        triangles: usize,
        /// Bytes those triangles need.
        expected: usize,
        /// Bytes found.
        found: usize,
    },
    /// An RGB buffer could not be PNG-encoded.
    #[error("PNG encoding: {source}")]
    PngEncode {
        /// The image library's error.
        source: Box<image::ImageError>,
    },
    /// The plotting library failed to draw a slice overlay.
    #[error("drawing the overlay: {message}")]
    Draw {
        /// The plotting library's error text.
        message: String,
    },
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
    pub fn inv3(path: &Path, problem: Inv3Problem) -> Self {
        CtError::Inv3 {
            path: path.to_owned(),
            problem,
        }
    }

    /// A corrupt-DICOM error on `path`.
    pub fn dicom(path: &Path, problem: DicomProblem) -> Self {
        CtError::Dicom {
            path: path.to_owned(),
            problem,
        }
    }
}

/// What is wrong with an `.inv3` project ([`CtError::Inv3`]).
#[derive(Debug, thiserror::Error)]
pub enum Inv3Problem {
    /// The gzip or tar stream cannot be read.
    #[error("bad tar stream: {0}")]
    TarStream(#[source] io::Error),
    /// A tar entry cannot be read.
    #[error("bad tar entry: {0}")]
    TarEntry(#[source] io::Error),
    /// A tar entry's name cannot be read.
    #[error("bad member name: {0}")]
    MemberName(#[source] io::Error),
    /// A member's bytes cannot be read.
    #[error("member {name}: {source}")]
    Member {
        /// The member's file name.
        name: String,
        /// The read error.
        source: io::Error,
    },
    /// A member the project needs is missing.
    #[error("no {0} member")]
    MissingMember(String),
    /// `main.plist` is not UTF-8 text.
    #[error("main.plist is not UTF-8")]
    PlistNotUtf8,
    /// `main.plist` is not a well-formed property list.
    #[error("main.plist: {0}")]
    Plist(#[source] PlistError),
    /// `main.plist` has no `matrix` entry.
    #[error("main.plist has no `matrix` entry")]
    NoMatrix,
    /// The matrix's sample type is not int16.
    #[error("matrix dtype {0:?} is not supported (only int16)")]
    Dtype(String),
    /// The matrix's shape is not three positive integers.
    #[error("matrix shape {0:?} is not three positive integers")]
    Shape(Vec<i64>),
    /// The voxel spacing is not three positive numbers.
    #[error("spacing {0:?} is not three positive numbers")]
    Spacing(Vec<f64>),
    /// The gzip stream's end does not check out: its CRC-32 or its length
    /// (RFC 1952 trailer) disagrees with the data, or it is truncated.
    #[error("gzip stream fails its integrity check (CRC-32 or length, RFC 1952): {0}")]
    Checksum(#[source] io::Error),
    /// A tar member declares more bytes than a deflate stream of the file's
    /// size can hold (at most 1,032 bytes out per byte in).
    #[error(
        "member {name} declares {declared} bytes, more than the {limit} a {file_len}-byte gzip file can hold"
    )]
    MemberTooLarge {
        /// The member's file name.
        name: String,
        /// The size in its tar header.
        declared: u64,
        /// The most a deflate stream of the file's size can decompress to.
        limit: u64,
        /// The compressed file's size in bytes.
        file_len: u64,
    },
}

/// What is wrong with a DICOM file ([`CtError::Dicom`]).
#[derive(Debug, thiserror::Error)]
pub enum DicomProblem {
    /// The file cannot be opened or parsed as DICOM.
    #[error("{0}")]
    Open(#[source] Box<dicom_object::ReadError>),
    /// The transfer syntax is compressed or big endian.
    #[error(
        "transfer syntax {syntax} is not supported (only uncompressed little endian: {} or {})",
        dicom_dictionary_std::uids::IMPLICIT_VR_LITTLE_ENDIAN,
        dicom_dictionary_std::uids::EXPLICIT_VR_LITTLE_ENDIAN
    )]
    TransferSyntax {
        /// The file's transfer syntax UID.
        syntax: String,
    },
    /// A required attribute is missing or unreadable.
    #[error("missing or bad {0}")]
    Missing(&'static str),
    /// Rows or Columns is not positive.
    #[error("image size {rows}x{cols} is empty")]
    EmptyImage {
        /// Rows.
        rows: i64,
        /// Columns.
        cols: i64,
    },
    /// BitsAllocated is not 8 or 16.
    #[error("BitsAllocated {0} is not supported (8 or 16)")]
    BitsAllocated(i64),
    /// BitsStored is not in `1..=BitsAllocated`.
    #[error("BitsStored {stored} exceeds BitsAllocated {bits}")]
    BitsStored {
        /// BitsStored.
        stored: i64,
        /// BitsAllocated.
        bits: i64,
    },
    /// More than one sample per pixel (colour).
    #[error("only one sample per pixel (grey scale) is supported")]
    SamplesPerPixel,
    /// More than one frame.
    #[error("multi-frame images are not supported")]
    MultiFrame,
    /// PixelData cannot be accessed.
    #[error("{0}")]
    PixelDataAccess(#[source] Box<dicom_object::AccessError>),
    /// No PixelData element.
    #[error("no PixelData")]
    NoPixelData,
    /// PixelData is compressed (encapsulated) or of an unexpected value type.
    #[error("PixelData is encapsulated or of an unexpected type")]
    PixelDataType,
    /// PixelData's length is not `rows·cols·BitsAllocated/8` bytes (padded
    /// to even length, PS3.5 §7.1.1).
    #[error(
        "PixelData holds {found} bytes, {rows}x{cols} at {bits} bits allocated needs {needed}"
    )]
    PixelDataLength {
        /// Bytes found.
        found: usize,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// BitsAllocated.
        bits: i64,
        /// `rows·cols·bits/8`, rounded up to even.
        needed: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_numbers() {
        let e = CtError::GridMismatch {
            a: [1, 2, 3],
            b: [4, 5, 6],
        };
        assert_eq!(e.to_string(), "masks on different grids: 1x2x3 vs 4x5x6");
        let e = CtError::StlLength {
            path: PathBuf::from("m.stl"),
            triangles: 2,
            expected: 184,
            found: 90,
        };
        assert_eq!(
            e.to_string(),
            "m.stl: bad binary STL: 2 triangles need 184 bytes, found 90"
        );
        let e = CtError::VoxelCount {
            nx: 2,
            ny: 3,
            nz: 4,
            expected: 24,
            found: 23,
        };
        assert_eq!(e.to_string(), "volume 2x3x4 needs 24 voxels, got 23");
    }

    #[test]
    fn file_problems_keep_their_text() {
        let e = CtError::inv3(Path::new("x.inv3"), Inv3Problem::Shape(vec![1, 2]));
        assert_eq!(
            e.to_string(),
            "x.inv3: truncated or corrupt .inv3: matrix shape [1, 2] is not three positive integers"
        );
        let e = CtError::inv3(
            Path::new("x.inv3"),
            Inv3Problem::MissingMember("main.plist".into()),
        );
        assert_eq!(
            e.to_string(),
            "x.inv3: truncated or corrupt .inv3: no main.plist member"
        );
        let e = CtError::dicom(Path::new("a.dcm"), DicomProblem::Missing("PixelSpacing"));
        assert_eq!(
            e.to_string(),
            "a.dcm: corrupt or unsupported DICOM: missing or bad PixelSpacing"
        );
        let e = CtError::dicom(
            Path::new("a.dcm"),
            DicomProblem::TransferSyntax {
                syntax: "1.2.840.10008.1.2.2".into(),
            },
        );
        assert_eq!(
            e.to_string(),
            "a.dcm: corrupt or unsupported DICOM: transfer syntax 1.2.840.10008.1.2.2 is not supported \
             (only uncompressed little endian: 1.2.840.10008.1.2 or 1.2.840.10008.1.2.1)"
        );
    }

    #[test]
    fn the_fit_error_is_the_source() {
        use std::error::Error as _;
        let fit = FitError::TooFewOutlinePoints {
            found: 2,
            needed: 4,
        };
        let e = CtError::OuterWallFit {
            source: fit.clone(),
        };
        assert_eq!(e.to_string(), format!("the outer-wall fit failed: {fit}"));
        assert!(e.source().is_some());
    }
}
