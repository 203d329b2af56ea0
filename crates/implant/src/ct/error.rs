//! Errors of the CT layer: every failure names the file or the slice it
//! concerns, so that a user with their own scan can act on it.

use std::io;
use std::path::{Path, PathBuf};

use dicom_core::Tag;

use super::plist::PlistError;
use crate::files::IoError;

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
    /// A slice of a multi-slice DICOM series does not say where it lies.
    #[error(
        "{}: no {tags}: the position of every slice is needed to order and space the {slices} slices of the series",
        path.display()
    )]
    MissingPosition {
        /// The first slice without it.
        path: PathBuf,
        /// The attributes that would have given its position.
        tags: &'static str,
        /// The number of slices in the series.
        slices: usize,
    },
    /// Two slices of a DICOM series lie at the same position.
    #[error(
        "{}: same slice position as {} ({location} mm along the slice normal): a series needs one slice per position",
        path.display(),
        other.display()
    )]
    DuplicatePosition {
        /// One of the slices.
        path: PathBuf,
        /// The other.
        other: PathBuf,
        /// Their position along the normal, in mm.
        location: f64,
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
    /// A DICOM slice's ImageOrientationPatient row and column directions
    /// are not orthogonal unit vectors.
    #[error("{}: ImageOrientationPatient {orientation:?} is not two orthogonal unit vectors (row·column = {dot:.4}, lengths {row_len:.4} and {col_len:.4}); expected direction cosines such as 1\\0\\0\\0\\1\\0", path.display())]
    OrientationNotOrthogonal {
        /// The slice.
        path: PathBuf,
        /// Its ImageOrientationPatient.
        orientation: [f64; 6],
        /// The dot product of the row and column directions.
        dot: f64,
        /// The row direction's length.
        row_len: f64,
        /// The column direction's length.
        col_len: f64,
    },
    /// Two voxel axes point mostly along the same patient axis, so the
    /// pictures cannot be labelled anterior/posterior, left/right,
    /// superior/inferior.
    #[error("the volume's axes {axes:?} (column, row, slice; patient LPS) do not point along three different patient axes: no anatomical labels")]
    AmbiguousOrientation {
        /// The unit axes.
        axes: [[f64; 3]; 3],
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
    /// The mirror technique was given an empty outer contour.
    #[error("the outer contour is empty")]
    EmptyContour,

    // The mirror technique and the implant wall.
    /// The defect crosses the mid-sagittal line, so mirroring cannot supply
    /// its template.
    #[error(
        "the defect crosses the mid-sagittal line (A at x = {a_x:.2} mm, B at x = {b_x:.2} mm, \
         the midline at x = {midline_x:.2} mm): the mirror technique cannot supply a template; \
         give an explicit template contour instead (`template = \"file.csv\"` in [defect]), \
         or continue the bone from both sides (`template_source = \"auto\"` or \"continuation\" in [implant])"
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
    #[error("{what} is not on the bone contour: {}", off_contour(*distance_mm, *tolerance_mm))]
    NotOnContour {
        /// Which point.
        what: &'static str,
        /// Its distance to the contour, in mm.
        distance_mm: f64,
        /// The largest distance accepted, in mm.
        tolerance_mm: f64,
    },
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

/// What is wrong with an `.inv3` project ([`CtError::Inv3`]). Offsets
/// are bytes of the decompressed tar stream.
#[derive(Debug, thiserror::Error)]
pub enum Inv3Problem {
    /// The file is too short to be a gzip stream.
    #[error("{len} bytes is too short for a gzip stream (at least 18)")]
    TooShort {
        /// The file's length.
        len: u64,
    },
    /// The gzip stream cannot be decompressed before its declared end.
    #[error(
        "the gzip stream is corrupt or truncated at uncompressed byte {at} of the {total} its trailer declares: {source}"
    )]
    Gzip {
        /// Bytes decompressed so far.
        at: u64,
        /// The length the trailer declares.
        total: u64,
        /// The decompressor's error.
        source: io::Error,
    },
    /// The tar stream ends in the middle of a header or member.
    #[error("the tar stream ends at byte {at}, inside a header or member (the gzip trailer declares {total} bytes)")]
    Truncated {
        /// Where it ends.
        at: u64,
        /// The length the gzip trailer declares.
        total: u64,
    },
    /// The gzip stream's end does not check out: its CRC-32 or its length
    /// (RFC 1952 trailer) disagrees with the data.
    #[error("gzip stream fails its integrity check (CRC-32 or length, RFC 1952): {0}")]
    Checksum(#[source] io::Error),
    /// Bytes follow the gzip stream (whose trailer must end the file).
    #[error("data follows the end of the gzip stream (the file must hold one gzip member)")]
    TrailingData,
    /// A tar header's checksum disagrees with its bytes.
    #[error(
        "tar header at byte {offset} fails its checksum (stored {stored:?}, computed {computed})"
    )]
    HeaderChecksum {
        /// The header's offset.
        offset: u64,
        /// The checksum field's text.
        stored: String,
        /// The sum of the header's bytes.
        computed: u64,
    },
    /// A numeric tar header field (or pax record) that does not parse.
    #[error("tar header at byte {offset}: bad {field} {text:?}")]
    HeaderField {
        /// The header's offset.
        offset: u64,
        /// The field.
        field: &'static str,
        /// Its text.
        text: String,
    },
    /// A tar member declares more bytes than the stream holds after its header.
    #[error(
        "member {name} declares {declared} bytes (tar header at byte {offset}), but only {remaining} of the tar's {total} bytes (the gzip trailer's ISIZE) remain"
    )]
    MemberTooLarge {
        /// The member's name.
        name: String,
        /// Its header's offset.
        offset: u64,
        /// The size in its tar header.
        declared: u64,
        /// Bytes after its header.
        remaining: u64,
        /// The tar's length by the gzip trailer.
        total: u64,
    },
    /// A pax header or GNU long name above [`crate::ct::inv3::MAX_TAR_EXTENSION_BYTES`].
    #[error(
        "{kind} at byte {offset} declares {declared} bytes, more than the {limit}-byte limit (MAX_TAR_EXTENSION_BYTES)"
    )]
    Extension {
        /// "pax extended header" or "GNU long name".
        kind: &'static str,
        /// Its header's offset.
        offset: u64,
        /// The size it declares.
        declared: u64,
        /// The limit.
        limit: u64,
    },
    /// `main.plist` above [`crate::ct::inv3::MAX_PLIST_BYTES`].
    #[error(
        "main.plist declares {declared} bytes, more than the {limit}-byte limit (MAX_PLIST_BYTES)"
    )]
    PlistTooLarge {
        /// The size in its tar header.
        declared: u64,
        /// The limit.
        limit: u64,
    },
    /// Two members the reader uses have the same name.
    #[error("two {name} members (tar headers at bytes {first} and {second})")]
    DuplicateMember {
        /// The name.
        name: String,
        /// The first one's header offset.
        first: u64,
        /// The second one's.
        second: u64,
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
}

/// What is wrong with a DICOM file ([`CtError::Dicom`]). Offsets are
/// bytes from the start of the file; tags are written `(gggg,eeee)` with
/// the attribute's keyword when the dictionary knows it.
#[derive(Debug, thiserror::Error)]
pub enum DicomProblem {
    /// The file is larger than [`crate::ct::dicom::MAX_DICOM_FILE_BYTES`].
    #[error(
        "the file is {len} bytes, more than the {limit}-byte limit for one slice (MAX_DICOM_FILE_BYTES)"
    )]
    TooLarge {
        /// The file's length.
        len: u64,
        /// The limit.
        limit: u64,
    },
    /// No "DICM" magic after the 128-byte preamble (nor at the start).
    #[error("not a DICOM file: no \"DICM\" at byte 128 (nor at byte 0) of its {len} bytes")]
    NotDicom {
        /// The file's length.
        len: usize,
    },
    /// The file meta information does not start with its group length.
    #[error(
        "the file meta information at byte {offset} does not start with its group length (0002,0000), UL, 4 bytes"
    )]
    MetaGroupLength {
        /// Where the group length was expected.
        offset: usize,
    },
    /// An element of another group inside the file meta information's
    /// declared length.
    #[error(
        "element {} at byte {offset} lies within the file meta information's group length but is not of group 0002",
        tag_label(*.tag)
    )]
    MetaElement {
        /// The element's tag.
        tag: Tag,
        /// Its header's offset.
        offset: usize,
    },
    /// The file meta information has no transfer syntax.
    #[error("the file meta information has no TransferSyntaxUID (0002,0010)")]
    NoTransferSyntax,
    /// The transfer syntax is compressed, big endian or unknown.
    #[error(
        "transfer syntax {} is not supported (only uncompressed little endian: {} Implicit VR Little Endian or {} Explicit VR Little Endian)",
        syntax_label(.syntax),
        dicom_dictionary_std::uids::IMPLICIT_VR_LITTLE_ENDIAN,
        dicom_dictionary_std::uids::EXPLICIT_VR_LITTLE_ENDIAN
    )]
    TransferSyntax {
        /// The file's transfer syntax UID.
        syntax: String,
    },
    /// An element or item header runs past the end of the file (or of its
    /// sequence or item).
    #[error(
        "truncated element header at byte {offset}: it needs {needed} bytes, {remaining} remain"
    )]
    TruncatedHeader {
        /// The header's offset.
        offset: usize,
        /// Bytes the header needs.
        needed: usize,
        /// Bytes left in the file or the enclosing sequence or item.
        remaining: usize,
    },
    /// An element or item declares more bytes than remain.
    #[error(
        "element {} at byte {offset} declares {declared} bytes, but only {remaining} remain in the {within}",
        tag_label(*.tag)
    )]
    ElementLength {
        /// The element's (or item's) tag.
        tag: Tag,
        /// Its header's offset.
        offset: usize,
        /// The length its header declares.
        declared: u64,
        /// The bytes left after its header in the enclosing range.
        remaining: u64,
        /// The enclosing range: "file", "file meta information",
        /// "sequence" or "sequence item".
        within: &'static str,
    },
    /// An explicit VR that DICOM does not define.
    #[error("element {} at byte {offset} has an unknown VR {vr:?}", tag_label(*.tag))]
    UnknownVr {
        /// The element's tag.
        tag: Tag,
        /// Its header's offset.
        offset: usize,
        /// The two VR characters found.
        vr: String,
    },
    /// An undefined length on an element that is not a sequence.
    #[error(
        "element {} ({vr}) at byte {offset} has an undefined length, which only a sequence (SQ) may have",
        tag_label(*.tag)
    )]
    UndefinedLength {
        /// The element's tag.
        tag: Tag,
        /// Its header's offset.
        offset: usize,
        /// Its VR.
        vr: String,
    },
    /// An item or delimiter tag outside a sequence.
    #[error("unexpected {} at byte {offset}, outside a sequence", tag_label(*.tag))]
    Delimiter {
        /// The tag found.
        tag: Tag,
        /// Its offset.
        offset: usize,
    },
    /// Something other than an item or the sequence delimiter in a sequence.
    #[error(
        "sequence {}: expected an item (FFFE,E000) or the sequence delimiter at byte {offset}, found {}",
        tag_label(*.sequence),
        tag_label(*.found)
    )]
    ExpectedItem {
        /// The sequence's tag.
        sequence: Tag,
        /// The tag found.
        found: Tag,
        /// Its offset.
        offset: usize,
    },
    /// An undefined-length sequence or item without its delimiter.
    #[error(
        "{what} {} at byte {offset} has an undefined length and no delimiter before its end",
        tag_label(*.tag)
    )]
    Unterminated {
        /// "sequence" or "item".
        what: &'static str,
        /// The sequence's tag ((FFFE,E000) for an item).
        tag: Tag,
        /// Its header's offset.
        offset: usize,
    },
    /// Sequences nested deeper than [`crate::ct::dicom::MAX_DICOM_NESTING`].
    #[error("sequence at byte {offset} is nested more than {limit} deep (MAX_DICOM_NESTING)")]
    Nesting {
        /// The sequence's header offset.
        offset: usize,
        /// The limit.
        limit: usize,
    },
    /// A required attribute is missing or unreadable.
    #[error("missing or bad {0}")]
    Missing(&'static str),
    /// An attribute is present with a value the reader cannot use.
    #[error("{name} {tag} at byte {offset} is {found:?}: expected {expected}")]
    BadValue {
        /// The attribute's keyword.
        name: &'static str,
        /// Its tag.
        tag: Tag,
        /// Its header's offset.
        offset: usize,
        /// The value's text (at most 64 bytes).
        found: String,
        /// What it must be.
        expected: &'static str,
    },
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
    /// No PixelData element.
    #[error("no PixelData")]
    NoPixelData,
    /// PixelData is encapsulated (compressed fragments of undefined length),
    /// which a native transfer syntax does not allow.
    #[error(
        "PixelData (7FE0,0010) at byte {offset} is encapsulated (undefined length), which an uncompressed transfer syntax does not allow"
    )]
    EncapsulatedPixelData {
        /// Its header's offset.
        offset: usize,
    },
    /// PixelData has a VR other than OB, OW or UN.
    #[error("PixelData (7FE0,0010) at byte {offset} has VR {vr}: expected OB or OW")]
    PixelDataType {
        /// Its header's offset.
        offset: usize,
        /// Its VR.
        vr: String,
    },
    /// PixelData's length is not `rows·cols·BitsAllocated/8·samples` bytes
    /// (padded to even length, PS3.5 §7.1.1).
    #[error(
        "PixelData holds {found} bytes, {rows}x{cols} at {bits} bits allocated needs {needed} ({samples} sample per pixel; element (7FE0,0010) at byte {offset})"
    )]
    PixelDataLength {
        /// Its header's offset.
        offset: usize,
        /// The length it declares.
        found: u64,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// BitsAllocated.
        bits: i64,
        /// SamplesPerPixel.
        samples: u64,
        /// `rows·cols·bits/8·samples`, rounded up to even.
        needed: u64,
    },
}

/// `(gggg,eeee)` and, when the standard dictionary knows the tag, its keyword.
pub fn tag_label(tag: Tag) -> String {
    use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry};
    match dicom_dictionary_std::StandardDataDictionary.by_tag(tag) {
        Some(e) => format!("{tag} {}", e.alias()),
        None => format!("{tag}"),
    }
}

/// A transfer syntax UID with its name when it is a common one.
fn syntax_label(uid: &str) -> String {
    const NAMES: [(&str, &str); 12] = [
        ("1.2.840.10008.1.2", "Implicit VR Little Endian"),
        ("1.2.840.10008.1.2.1", "Explicit VR Little Endian"),
        (
            "1.2.840.10008.1.2.1.99",
            "Deflated Explicit VR Little Endian",
        ),
        ("1.2.840.10008.1.2.2", "Explicit VR Big Endian"),
        ("1.2.840.10008.1.2.4.50", "JPEG Baseline"),
        ("1.2.840.10008.1.2.4.51", "JPEG Extended"),
        ("1.2.840.10008.1.2.4.57", "JPEG Lossless"),
        (
            "1.2.840.10008.1.2.4.70",
            "JPEG Lossless, first-order prediction",
        ),
        ("1.2.840.10008.1.2.4.80", "JPEG-LS Lossless"),
        ("1.2.840.10008.1.2.4.90", "JPEG 2000 Lossless"),
        ("1.2.840.10008.1.2.4.91", "JPEG 2000"),
        ("1.2.840.10008.1.2.5", "RLE Lossless"),
    ];
    match NAMES.iter().find(|(u, _)| *u == uid) {
        Some((_, name)) => format!("{uid} ({name})"),
        None => format!("{uid:?}"),
    }
}

/// How far a point is from the contour it must lie on: a distance, or, where
/// no ray from the polar centre meets the contour there (an infinite
/// distance), that.
fn off_contour(distance_mm: f64, tolerance_mm: f64) -> String {
    if distance_mm.is_finite() {
        format!("{distance_mm:.2} mm away (tolerance {tolerance_mm:.2} mm)")
    } else {
        format!("the ray from the polar centre through it meets no outer contour (tolerance {tolerance_mm:.2} mm)")
    }
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
            "a.dcm: corrupt or unsupported DICOM: transfer syntax 1.2.840.10008.1.2.2 (Explicit VR Big Endian) \
             is not supported (only uncompressed little endian: 1.2.840.10008.1.2 Implicit VR Little Endian \
             or 1.2.840.10008.1.2.1 Explicit VR Little Endian)"
        );
    }
}
