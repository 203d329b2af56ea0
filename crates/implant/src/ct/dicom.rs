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

use std::io::Read;
use std::path::{Path, PathBuf};

use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry};
use dicom_core::value::PrimitiveValue;
use dicom_core::{DataElement, Tag, VR};
use dicom_dictionary_std::{tags, uids, StandardDataDictionary};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

use super::error::{CtError, DicomProblem};
use super::volume::{FrameSource, Spacing, Volume};
use crate::files::write_atomic;

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

/// The encoding of a data set (PS3.5 §10): the two the reader supports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Syntax {
    /// Implicit VR little endian: VRs come from the data dictionary.
    Implicit,
    /// Explicit VR little endian.
    Explicit,
}

/// A top-level element with a defined length, borrowed from the file.
#[derive(Clone, Copy, Debug)]
struct Element<'a> {
    /// The VR (explicit, or the dictionary's for implicit VR).
    vr: VR,
    /// Byte offset of the element's header in the file.
    offset: usize,
    /// The value bytes.
    value: &'a [u8],
}

/// A sequence or item being walked, with its end when its length is defined.
#[derive(Clone, Copy, Debug)]
enum Open {
    /// A sequence (SQ) whose header is at `offset`.
    Sequence {
        tag: Tag,
        offset: usize,
        end: Option<usize>,
    },
    /// An item (FFFE,E000) whose header is at `offset`.
    Item { offset: usize, end: Option<usize> },
}

impl Open {
    fn end(&self) -> Option<usize> {
        match *self {
            Open::Sequence { end, .. } | Open::Item { end, .. } => end,
        }
    }
}

/// An item of a sequence (PS3.5 §7.5).
const ITEM: Tag = Tag(0xFFFE, 0xE000);
/// The end of an item of undefined length.
const ITEM_DELIMITER: Tag = Tag(0xFFFE, 0xE00D);
/// The end of a sequence of undefined length.
const SEQUENCE_DELIMITER: Tag = Tag(0xFFFE, 0xE0DD);

fn u16_at(b: &[u8], p: usize) -> u16 {
    u16::from_le_bytes([b[p], b[p + 1]])
}

fn u32_at(b: &[u8], p: usize) -> u32 {
    u32::from_le_bytes([b[p], b[p + 1], b[p + 2], b[p + 3]])
}

/// The VRs whose explicit-VR header has two reserved bytes and a 32-bit
/// length (PS3.5 Table 7.1-1); the others have a 16-bit length.
fn long_header(vr: VR) -> bool {
    matches!(
        vr,
        VR::OB
            | VR::OD
            | VR::OF
            | VR::OL
            | VR::OV
            | VR::OW
            | VR::SQ
            | VR::SV
            | VR::UC
            | VR::UN
            | VR::UR
            | VR::UT
            | VR::UV
    )
}

/// The dictionary VR of `tag` for implicit VR (PixelData is OW, PS3.5 A.1).
fn implicit_vr(tag: Tag) -> VR {
    if tag == tags::PIXEL_DATA {
        return VR::OW;
    }
    StandardDataDictionary
        .by_tag(tag)
        .map(|e| e.vr().relaxed())
        .unwrap_or(VR::UN)
}

/// Walks the elements of `bytes[start..end]` (a data set, or the file meta
/// information) in `syntax`, checking every header and declared length
/// against the bytes that remain in the file and in the enclosing sequence
/// or item, and the nesting against [`MAX_DICOM_NESTING`]. Calls `top` with
/// each top-level element of defined length that is not a sequence.
/// `within` names the range in messages.
fn walk<'a>(
    bytes: &'a [u8],
    (start, end): (usize, usize),
    syntax: Syntax,
    within: &'static str,
    mut top: impl FnMut(Tag, Element<'a>) -> Result<(), DicomProblem>,
) -> Result<(), DicomProblem> {
    let mut stack: Vec<Open> = Vec::new();
    let mut p = start;
    loop {
        // Close the sequences and items whose defined length ends here.
        while let Some(o) = stack.last() {
            if o.end() == Some(p) {
                stack.pop();
            } else {
                break;
            }
        }
        let (limit, container) = stack
            .iter()
            .rev()
            .find_map(|o| match o {
                Open::Sequence { end: Some(e), .. } => Some((*e, "sequence")),
                Open::Item { end: Some(e), .. } => Some((*e, "sequence item")),
                _ => None,
            })
            .unwrap_or((end, within));
        let remaining = limit - p;
        let need = |needed: usize| {
            if remaining < needed {
                Err(DicomProblem::TruncatedHeader {
                    offset: p,
                    needed,
                    remaining,
                })
            } else {
                Ok(())
            }
        };
        let innermost = stack.last().copied();
        if remaining == 0 {
            // The end of the range, or of a defined-length ancestor, inside
            // an undefined-length sequence or item.
            return match innermost {
                None => Ok(()),
                Some(Open::Sequence { tag, offset, .. }) => Err(DicomProblem::Unterminated {
                    what: "sequence",
                    tag,
                    offset,
                }),
                Some(Open::Item { offset, .. }) => Err(DicomProblem::Unterminated {
                    what: "item",
                    tag: ITEM,
                    offset,
                }),
            };
        }
        need(8)?;
        let tag = Tag(u16_at(bytes, p), u16_at(bytes, p + 2));
        if let Some(Open::Sequence {
            tag: seq,
            end: seq_end,
            ..
        }) = innermost
        {
            let len = u32_at(bytes, p + 4);
            if tag == ITEM {
                let end = if len == u32::MAX {
                    None
                } else if len as usize > remaining - 8 {
                    return Err(DicomProblem::ElementLength {
                        tag,
                        offset: p,
                        declared: len as u64,
                        remaining: (remaining - 8) as u64,
                        within: container,
                    });
                } else {
                    Some(p + 8 + len as usize)
                };
                stack.push(Open::Item { offset: p, end });
            } else if tag == SEQUENCE_DELIMITER && seq_end.is_none() {
                stack.pop();
            } else {
                return Err(DicomProblem::ExpectedItem {
                    sequence: seq,
                    found: tag,
                    offset: p,
                });
            }
            p += 8;
            continue;
        }
        if tag.0 == 0xFFFE {
            if tag == ITEM_DELIMITER && matches!(stack.last(), Some(Open::Item { end: None, .. })) {
                stack.pop();
                p += 8;
                continue;
            }
            return Err(DicomProblem::Delimiter { tag, offset: p });
        }
        let (vr, len, header) = match syntax {
            Syntax::Implicit => (implicit_vr(tag), u32_at(bytes, p + 4), 8),
            Syntax::Explicit => {
                let code = [bytes[p + 4], bytes[p + 5]];
                let vr = VR::from_binary(code).ok_or_else(|| DicomProblem::UnknownVr {
                    tag,
                    offset: p,
                    vr: String::from_utf8_lossy(&code).into_owned(),
                })?;
                if long_header(vr) {
                    need(12)?;
                    (vr, u32_at(bytes, p + 8), 12)
                } else {
                    (vr, u16_at(bytes, p + 6) as u32, 8)
                }
            }
        };
        let remaining = remaining - header;
        let sequence = vr == VR::SQ || (syntax == Syntax::Implicit && len == u32::MAX);
        if len == u32::MAX && !sequence {
            return Err(if tag == tags::PIXEL_DATA {
                DicomProblem::EncapsulatedPixelData { offset: p }
            } else {
                DicomProblem::UndefinedLength {
                    tag,
                    offset: p,
                    vr: vr.to_string().into(),
                }
            });
        }
        if len != u32::MAX && len as usize > remaining {
            return Err(DicomProblem::ElementLength {
                tag,
                offset: p,
                declared: len as u64,
                remaining: remaining as u64,
                within: container,
            });
        }
        if sequence {
            let depth = stack
                .iter()
                .filter(|o| matches!(o, Open::Sequence { .. }))
                .count();
            if depth >= MAX_DICOM_NESTING {
                return Err(DicomProblem::Nesting {
                    offset: p,
                    limit: MAX_DICOM_NESTING,
                });
            }
            let end = (len != u32::MAX).then(|| p + header + len as usize);
            stack.push(Open::Sequence {
                tag,
                offset: p,
                end,
            });
            p += header;
            continue;
        }
        let value = &bytes[p + header..p + header + len as usize];
        if stack.is_empty() {
            top(
                tag,
                Element {
                    vr,
                    offset: p,
                    value,
                },
            )?;
        }
        p += header + len as usize;
    }
}

/// Reads the preamble, the "DICM" magic and the file meta information
/// (always explicit VR little endian, PS3.10 §7.1) of `bytes`; returns the
/// data set's syntax and where it starts. An unsupported transfer syntax is
/// refused here, before the data set is looked at.
fn file_meta(bytes: &[u8]) -> Result<(Syntax, usize), DicomProblem> {
    let start = if bytes.len() >= 132 && &bytes[128..132] == b"DICM" {
        132
    } else if bytes.len() >= 4 && &bytes[..4] == b"DICM" {
        4
    } else {
        return Err(DicomProblem::NotDicom { len: bytes.len() });
    };
    // (0002,0000) UL, length 4: the group length.
    let group_ok = bytes.len() >= start + 12
        && Tag(u16_at(bytes, start), u16_at(bytes, start + 2))
            == tags::FILE_META_INFORMATION_GROUP_LENGTH
        && &bytes[start + 4..start + 6] == b"UL"
        && u16_at(bytes, start + 6) == 4;
    if !group_ok {
        return Err(DicomProblem::MetaGroupLength { offset: start });
    }
    let declared = u32_at(bytes, start + 8) as u64;
    let meta_start = start + 12;
    let remaining = (bytes.len() - meta_start) as u64;
    if declared > remaining {
        return Err(DicomProblem::ElementLength {
            tag: tags::FILE_META_INFORMATION_GROUP_LENGTH,
            offset: start,
            declared,
            remaining,
            within: "file",
        });
    }
    let meta_end = meta_start + declared as usize;
    let mut syntax = None;
    walk(
        bytes,
        (meta_start, meta_end),
        Syntax::Explicit,
        "file meta information",
        |tag, e| {
            if tag.0 != 0x0002 {
                return Err(DicomProblem::MetaElement {
                    tag,
                    offset: e.offset,
                });
            }
            if tag == tags::TRANSFER_SYNTAX_UID {
                syntax = Some(text(e.value).to_string());
            }
            Ok(())
        },
    )?;
    let syntax = syntax.ok_or(DicomProblem::NoTransferSyntax)?;
    let kind = match syntax.as_str() {
        uids::IMPLICIT_VR_LITTLE_ENDIAN => Syntax::Implicit,
        uids::EXPLICIT_VR_LITTLE_ENDIAN => Syntax::Explicit,
        _ => return Err(DicomProblem::TransferSyntax { syntax }),
    };
    Ok((kind, meta_end))
}

/// A text value without its padding (trailing spaces and NULs, PS3.5 §6.2);
/// bytes that are not UTF-8 give `"\u{FFFD}"`, which no number or UID is.
fn text(value: &[u8]) -> &str {
    let end = value
        .iter()
        .rposition(|&b| b != b' ' && b != 0)
        .map_or(0, |i| i + 1);
    std::str::from_utf8(&value[..end]).unwrap_or("\u{FFFD}")
}

/// The numbers of a numeric or numeric-string element: US, SS, UL, SL, FL,
/// FD binary values, or the backslash-separated values of a DS or IS (each
/// trimmed of spaces). `None` when the VR is not numeric or a value does
/// not parse; an empty value gives an empty list.
fn numbers(e: &Element) -> Option<Vec<f64>> {
    let v = e.value;
    Some(match e.vr {
        VR::US => v.chunks_exact(2).map(|c| u16_at(c, 0) as f64).collect(),
        VR::SS => v
            .chunks_exact(2)
            .map(|c| u16_at(c, 0) as i16 as f64)
            .collect(),
        VR::UL => v.chunks_exact(4).map(|c| u32_at(c, 0) as f64).collect(),
        VR::SL => v
            .chunks_exact(4)
            .map(|c| u32_at(c, 0) as i32 as f64)
            .collect(),
        VR::FL => v
            .chunks_exact(4)
            .map(|c| f32::from_bits(u32_at(c, 0)) as f64)
            .collect(),
        VR::FD => v
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")))
            .collect(),
        VR::DS | VR::IS => {
            let t = text(v);
            if t.is_empty() {
                return Some(Vec::new());
            }
            t.split('\\')
                .map(|s| s.trim().parse::<f64>().ok())
                .collect::<Option<Vec<f64>>>()?
        }
        _ => return None,
    })
}

/// The top-level elements the reader uses, borrowed from the file.
#[derive(Default)]
struct Attributes<'a> {
    found: Vec<(Tag, Element<'a>)>,
}

/// The tags [`Attributes`] keeps.
const USED_TAGS: [Tag; 16] = [
    tags::SAMPLES_PER_PIXEL,
    tags::NUMBER_OF_FRAMES,
    tags::ROWS,
    tags::COLUMNS,
    tags::PIXEL_SPACING,
    tags::BITS_ALLOCATED,
    tags::BITS_STORED,
    tags::PIXEL_REPRESENTATION,
    tags::RESCALE_INTERCEPT,
    tags::RESCALE_SLOPE,
    tags::SLICE_THICKNESS,
    tags::IMAGE_POSITION_PATIENT,
    tags::IMAGE_ORIENTATION_PATIENT,
    tags::SLICE_LOCATION,
    tags::INSTANCE_NUMBER,
    tags::PIXEL_DATA,
];

impl<'a> Attributes<'a> {
    /// The element `tag` (the last one, if the file repeats it).
    fn get(&self, tag: Tag) -> Option<&Element<'a>> {
        self.found
            .iter()
            .rev()
            .find(|(t, _)| *t == tag)
            .map(|(_, e)| e)
    }

    /// The first value of `tag` as an integer, if present and integral.
    fn int(&self, tag: Tag) -> Option<i64> {
        let v = *numbers(self.get(tag)?)?.first()?;
        (v.fract() == 0.0 && v.abs() < 9e15).then_some(v as i64)
    }

    /// The values of `tag`: `Ok(None)` when absent or empty, an error
    /// naming the tag when present but not `n` finite numbers passing `ok`.
    fn finite(
        &self,
        tag: Tag,
        name: &'static str,
        n: usize,
        expected: &'static str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<Option<Vec<f64>>, DicomProblem> {
        let Some(e) = self.get(tag) else {
            return Ok(None);
        };
        match numbers(e) {
            Some(v) if v.is_empty() => Ok(None),
            Some(v) if v.len() == n && v.iter().all(|&x| x.is_finite() && ok(x)) => Ok(Some(v)),
            _ => Err(DicomProblem::BadValue {
                name,
                tag,
                offset: e.offset,
                found: String::from_utf8_lossy(&e.value[..e.value.len().min(64)]).into_owned(),
                expected,
            }),
        }
    }
}

/// The pixel format of a grey-scale image (Image Pixel module).
#[derive(Clone, Copy, Debug)]
struct PixelFormat {
    rows: usize,
    cols: usize,
    /// BitsAllocated: 8 or 16.
    bits: i64,
    /// BitsStored, `1..=bits`.
    stored: i64,
    /// PixelRepresentation 1: two's complement samples.
    signed: bool,
}

impl PixelFormat {
    /// Reads and checks Rows, Columns, BitsAllocated, BitsStored,
    /// PixelRepresentation, SamplesPerPixel and NumberOfFrames.
    fn read(attrs: &Attributes) -> Result<PixelFormat, DicomProblem> {
        let need = |tag: Tag, name: &'static str| attrs.int(tag).ok_or(DicomProblem::Missing(name));
        let rows = need(tags::ROWS, "Rows")?;
        let cols = need(tags::COLUMNS, "Columns")?;
        if rows <= 0 || cols <= 0 {
            return Err(DicomProblem::EmptyImage { rows, cols });
        }
        let bits = need(tags::BITS_ALLOCATED, "BitsAllocated")?;
        if bits != 8 && bits != 16 {
            return Err(DicomProblem::BitsAllocated(bits));
        }
        let stored = attrs.int(tags::BITS_STORED).unwrap_or(bits);
        if !(1..=bits).contains(&stored) {
            return Err(DicomProblem::BitsStored { stored, bits });
        }
        let signed = attrs.int(tags::PIXEL_REPRESENTATION).unwrap_or(0) == 1;
        if attrs.int(tags::SAMPLES_PER_PIXEL).unwrap_or(1) != 1 {
            return Err(DicomProblem::SamplesPerPixel);
        }
        if attrs.int(tags::NUMBER_OF_FRAMES).unwrap_or(1) != 1 {
            return Err(DicomProblem::MultiFrame);
        }
        Ok(PixelFormat {
            rows: rows as usize,
            cols: cols as usize,
            bits,
            stored,
            signed,
        })
    }

    /// The pixel bytes of PixelData, after checking its VR (OB, OW, or UN)
    /// and that its length is exactly `rows·cols·BitsAllocated/8·samples`
    /// bytes (samples = 1), padded to even length (PS3.5 §7.1.1).
    fn pixels<'a>(&self, attrs: &Attributes<'a>) -> Result<&'a [u8], DicomProblem> {
        let e = attrs
            .get(tags::PIXEL_DATA)
            .ok_or(DicomProblem::NoPixelData)?;
        if !matches!(e.vr, VR::OB | VR::OW | VR::UN) {
            return Err(DicomProblem::PixelDataType {
                offset: e.offset,
                vr: e.vr.to_string().into(),
            });
        }
        let bytes = (self.rows as u64)
            .saturating_mul(self.cols as u64)
            .saturating_mul(self.bits as u64 / 8);
        let needed = bytes.saturating_add(bytes % 2);
        if e.value.len() as u64 != needed {
            return Err(DicomProblem::PixelDataLength {
                offset: e.offset,
                found: e.value.len() as u64,
                rows: self.rows,
                cols: self.cols,
                bits: self.bits,
                samples: 1,
                needed,
            });
        }
        Ok(e.value)
    }

    /// The first `rows·cols` stored samples of `pixels` (little endian, at
    /// least `rows·cols` of them: see [`PixelFormat::pixels`]) as
    /// HU: masked to BitsStored, sign-extended when signed,
    /// `raw·slope + intercept`, rounded and clamped to i16.
    fn hu(&self, pixels: &[u8], slope: f64, intercept: f64) -> Vec<i16> {
        let stored = self.stored;
        let mask: u32 = (1u32 << stored) - 1;
        let convert = |w: u16| {
            let u = (w as u32) & mask;
            let raw = if self.signed && (u >> (stored - 1)) & 1 == 1 {
                u as i64 - (1i64 << stored)
            } else {
                u as i64
            };
            let v = (raw as f64 * slope + intercept).round();
            v.clamp(i16::MIN as f64, i16::MAX as f64) as i16
        };
        let n = self.rows * self.cols;
        if self.bits == 16 {
            pixels
                .chunks_exact(2)
                .take(n)
                .map(|c| convert(u16_at(c, 0)))
                .collect()
        } else {
            pixels.iter().take(n).map(|&b| convert(b as u16)).collect()
        }
    }
}

/// The slice normal `n = r × c` of ImageOrientationPatient `o`.
fn normal(o: &[f64; 6]) -> [f64; 3] {
    [
        o[1] * o[5] - o[2] * o[4],
        o[2] * o[3] - o[0] * o[5],
        o[0] * o[4] - o[1] * o[3],
    ]
}

/// The slice's position along its normal `n = r × c` (from
/// ImagePositionPatient and ImageOrientationPatient), else the position's z,
/// else SliceLocation, else InstanceNumber, else 0.
fn slice_location(
    attrs: &Attributes,
    position: Option<[f64; 3]>,
    orientation: Option<[f64; 6]>,
    slice_location: Option<f64>,
) -> f64 {
    match (position, orientation) {
        (Some(p), Some(o)) => {
            let n = normal(&o);
            p[0] * n[0] + p[1] * n[1] + p[2] * n[2]
        }
        (Some(p), None) => p[2],
        _ => slice_location
            .or_else(|| attrs.int(tags::INSTANCE_NUMBER).map(|i| i as f64))
            .unwrap_or(0.0),
    }
}

/// Reads one DICOM file into HU (see [`dicom_slice_from_bytes`]); a file
/// above [`MAX_DICOM_FILE_BYTES`] is refused before it is read.
pub fn read_dicom_file(path: &Path) -> Result<DicomSlice, CtError> {
    let file = std::fs::File::open(path).map_err(|e| CtError::io(path, e))?;
    let len = file.metadata().map_err(|e| CtError::io(path, e))?.len();
    let too_large = |len: u64| {
        CtError::dicom(
            path,
            DicomProblem::TooLarge {
                len,
                limit: MAX_DICOM_FILE_BYTES,
            },
        )
    };
    if len > MAX_DICOM_FILE_BYTES {
        return Err(too_large(len));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(MAX_DICOM_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| CtError::io(path, e))?;
    if bytes.len() as u64 > MAX_DICOM_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    dicom_slice_from_bytes(path, &bytes)
}

/// Reads one DICOM image from the bytes of its file (`path` only names it
/// in errors). Every element header of the file meta information and the
/// data set is checked before any value is used: declared lengths against
/// the bytes that remain (in the file and in the enclosing sequence or
/// item), the transfer syntax (implicit or explicit VR little endian only),
/// sequence nesting ([`MAX_DICOM_NESTING`]) and the PixelData length
/// against `rows·cols·BitsAllocated/8`. Other errors: more than one frame
/// or sample per pixel, bits allocated other than 8/16, missing Rows,
/// Columns, PixelSpacing or PixelData, a RescaleSlope that is zero or not
/// finite, and a position, orientation, location or intercept that is not
/// finite. Errors name the file, the element's tag and its byte offset.
pub fn dicom_slice_from_bytes(path: &Path, bytes: &[u8]) -> Result<DicomSlice, CtError> {
    slice_from_bytes(path, bytes).map_err(|problem| CtError::dicom(path, problem))
}

fn slice_from_bytes(path: &Path, bytes: &[u8]) -> Result<DicomSlice, DicomProblem> {
    let (syntax, start) = file_meta(bytes)?;
    let mut attrs = Attributes::default();
    walk(bytes, (start, bytes.len()), syntax, "file", |tag, e| {
        if USED_TAGS.contains(&tag) {
            attrs.found.push((tag, e));
        }
        Ok(())
    })?;
    let format = PixelFormat::read(&attrs)?;
    let spacing = attrs
        .get(tags::PIXEL_SPACING)
        .and_then(numbers)
        .filter(|v| v.len() == 2 && v.iter().all(|s| s.is_finite() && *s > 0.0))
        .ok_or(DicomProblem::Missing("PixelSpacing"))?;
    let slope = attrs
        .finite(
            tags::RESCALE_SLOPE,
            "RescaleSlope",
            1,
            "a finite, non-zero number",
            |s| s != 0.0,
        )?
        .map_or(1.0, |v| v[0]);
    let intercept = attrs
        .finite(
            tags::RESCALE_INTERCEPT,
            "RescaleIntercept",
            1,
            "a finite number",
            |_| true,
        )?
        .map_or(0.0, |v| v[0]);
    let position = attrs
        .finite(
            tags::IMAGE_POSITION_PATIENT,
            "ImagePositionPatient",
            3,
            "three finite numbers (x, y, z in mm)",
            |_| true,
        )?
        .map(|v| [v[0], v[1], v[2]]);
    let orientation = attrs
        .finite(
            tags::IMAGE_ORIENTATION_PATIENT,
            "ImageOrientationPatient",
            6,
            "six finite direction cosines",
            |_| true,
        )?
        .map(|v| [v[0], v[1], v[2], v[3], v[4], v[5]]);
    let located = attrs
        .finite(
            tags::SLICE_LOCATION,
            "SliceLocation",
            1,
            "a finite number (mm)",
            |_| true,
        )?
        .map(|v| v[0]);
    let location = slice_location(&attrs, position, orientation, located);
    let thickness = attrs
        .get(tags::SLICE_THICKNESS)
        .and_then(numbers)
        .and_then(|v| v.first().copied());
    let pixels = format.pixels(&attrs)?;
    Ok(DicomSlice {
        path: path.to_owned(),
        rows: format.rows,
        cols: format.cols,
        row_spacing: spacing[0],
        col_spacing: spacing[1],
        position,
        orientation,
        slice_location: located,
        location,
        thickness,
        hu: format.hu(pixels, slope, intercept),
    })
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-3 * a.abs().max(b.abs()).max(1.0)
}

/// Stacks DICOM files into a volume, sorted by position along the slice
/// normal (z increasing). Refuses (naming the first offending file) slices of
/// different sizes, different pixel spacing, a slice without a position
/// when the series has more than one (ImagePositionPatient on every slice,
/// or SliceLocation on every slice when none has a position), two slices at
/// one position, or uneven gaps between slice positions (relative tolerance
/// 10⁻³); a single slice gets its SliceThickness (or 1 mm) as z spacing.
pub fn read_dicom_series(paths: &[PathBuf]) -> Result<Volume, CtError> {
    if paths.is_empty() {
        return Err(CtError::EmptySeries);
    }
    let mut slices = paths
        .iter()
        .map(|p| read_dicom_file(p))
        .collect::<Result<Vec<_>, _>>()?;
    check_positions(&slices)?;
    slices.sort_by(|a, b| a.location.total_cmp(&b.location));
    let first = &slices[0];
    for s in &slices[1..] {
        if (s.rows, s.cols) != (first.rows, first.cols) {
            return Err(CtError::SizeMismatch {
                path: s.path.clone(),
                expected: (first.rows, first.cols),
                found: (s.rows, s.cols),
            });
        }
        if let (Some(e), Some(f)) = (first.orientation, s.orientation) {
            if e.iter().zip(&f).any(|(a, b)| (a - b).abs() > 1e-4) {
                return Err(CtError::OrientationMismatch {
                    path: s.path.clone(),
                    expected: e,
                    found: f,
                });
            }
        }
        for (axis, e, f) in [
            ("row", first.row_spacing, s.row_spacing),
            ("column", first.col_spacing, s.col_spacing),
        ] {
            if !same(e, f) {
                return Err(CtError::SpacingMismatch {
                    path: s.path.clone(),
                    axis,
                    expected: e,
                    found: f,
                });
            }
        }
    }
    let sz = slice_step(&slices)?;
    if let Some(o) = slices[0].orientation {
        check_orthogonal(&slices[0].path, o)?;
    }
    let z_known = slices.len() > 1 || slices[0].thickness.is_some_and(|t| t > 0.0);
    let (origin, axes) = series_frame(&slices);
    let first = &slices[0];
    let (nx, ny, nz) = (first.cols, first.rows, slices.len());
    let spacing = Spacing {
        x: first.col_spacing,
        y: first.row_spacing,
        z: sz,
    };
    let mut data = Vec::with_capacity(nx * ny * nz);
    for s in slices {
        data.extend_from_slice(&s.hu);
    }
    let mut v = Volume::new(nx, ny, nz, spacing, origin, data)?.with_frame(
        origin,
        axes,
        FrameSource::Dicom,
    )?;
    v.z_spacing_known = z_known;
    Ok(v)
}

/// ImageOrientationPatient `o` of the slice at `path` must be two
/// orthogonal unit vectors (within 10⁻³, DICOM PS3.3 C.7.6.2.1.1).
fn check_orthogonal(path: &Path, o: [f64; 6]) -> Result<(), CtError> {
    let (r, c) = ([o[0], o[1], o[2]], [o[3], o[4], o[5]]);
    let dot = r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let (row_len, col_len) = (len(r), len(c));
    if dot.abs() > 1e-3 || (row_len - 1.0).abs() > 1e-3 || (col_len - 1.0).abs() > 1e-3 {
        return Err(CtError::OrientationNotOrthogonal {
            path: path.to_path_buf(),
            orientation: o,
            dot,
            row_len,
            col_len,
        });
    }
    Ok(())
}

/// Checks that every slice of a series of more than one says where it lies:
/// ImagePositionPatient on every slice when any slice has it, else
/// SliceLocation on every slice (InstanceNumber orders slices but does not
/// space them). The error names the first slice without it.
fn check_positions(slices: &[DicomSlice]) -> Result<(), CtError> {
    if slices.len() < 2 {
        return Ok(());
    }
    let positioned = slices.iter().any(|s| s.position.is_some());
    let missing = slices.iter().find(|s| {
        if positioned {
            s.position.is_none()
        } else {
            s.slice_location.is_none()
        }
    });
    match missing {
        Some(s) => Err(CtError::MissingPosition {
            path: s.path.clone(),
            tags: if positioned {
                "ImagePositionPatient (0020,0032)"
            } else {
                "ImagePositionPatient (0020,0032) or SliceLocation (0020,1041)"
            },
            slices: slices.len(),
        }),
        None => Ok(()),
    }
}

/// The slice spacing of a sorted series: the distance between the first
/// and last ImagePositionPatient over `n − 1` (the locations along the
/// normal when a position is missing), after checking that no two slices
/// share a position and that the gaps along the normal are even; a single
/// slice gets its SliceThickness (or 1 mm).
fn slice_step(slices: &[DicomSlice]) -> Result<f64, CtError> {
    let first = &slices[0];
    Ok(if slices.len() > 1 {
        for w in slices.windows(2) {
            if w[1].location == w[0].location {
                return Err(CtError::DuplicatePosition {
                    path: w[1].path.clone(),
                    other: w[0].path.clone(),
                    location: w[1].location,
                });
            }
        }
        let gap0 = slices[1].location - slices[0].location;
        for w in slices.windows(2) {
            let gap = w[1].location - w[0].location;
            if gap.is_nan() || gap <= 0.0 || !same(gap, gap0) {
                return Err(CtError::SpacingMismatch {
                    path: w[1].path.clone(),
                    axis: "slice gap",
                    expected: gap0,
                    found: gap,
                });
            }
        }
        let last = &slices[slices.len() - 1];
        match (first.position, last.position) {
            (Some(p), Some(q)) => {
                let d: f64 = (0..3).map(|i| (q[i] - p[i]).powi(2)).sum::<f64>().sqrt();
                d / (slices.len() - 1) as f64
            }
            _ => (last.location - first.location) / (slices.len() - 1) as f64,
        }
    } else {
        first.thickness.filter(|t| *t > 0.0).unwrap_or(1.0)
    })
}

/// The origin and axes of a sorted series: ImagePositionPatient of the
/// first slice (else `(0, 0, location)`), the row and column directions of
/// ImageOrientationPatient (else the identity), and the slice axis along
/// the positions from the first to the last slice (else the normal).
fn series_frame(slices: &[DicomSlice]) -> ([f64; 3], [[f64; 3]; 3]) {
    let first = &slices[0];
    let last = &slices[slices.len() - 1];
    let origin = first.position.unwrap_or([0.0, 0.0, first.location]);
    let Some(o) = first.orientation else {
        return (origin, crate::ct::volume::IDENTITY_AXES);
    };
    let n = normal(&o);
    let z = match (first.position, last.position) {
        (Some(p), Some(q)) if slices.len() > 1 => {
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            // The positions run along +n (sorted by location).
            if d.iter().map(|c| c * c).sum::<f64>() > 0.0 {
                d
            } else {
                n
            }
        }
        _ => n,
    };
    (origin, [[o[0], o[1], o[2]], [o[3], o[4], o[5]], z])
}

/// Reads every regular file of `dir` as one DICOM series (see
/// [`read_dicom_series`]); any file that is not valid DICOM is an error.
pub fn read_dicom_dir(dir: &Path) -> Result<Volume, CtError> {
    let mut paths = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| CtError::io(dir, e))? {
        let entry = entry.map_err(|e| CtError::io(dir, e))?;
        let p = entry.path();
        if p.is_file() {
            paths.push(p);
        }
    }
    paths.sort();
    read_dicom_series(&paths)
}

/// A DICOM decimal string (≤ 16 characters, PS3.5 6.2) for `v`: the
/// shortest round-trip representation when it fits.
fn ds(v: f64) -> String {
    let s = format!("{v}");
    if s.len() <= 16 {
        return s;
    }
    for prec in (1..=15).rev() {
        let s = format!("{v:.prec$e}");
        if s.len() <= 16 {
            return s;
        }
    }
    format!("{v:.0}")
}

/// A deterministic UID under the `2.25` root (ITU-T X.667 UUID-derived) from
/// a text key (FNV-1a 64-bit, twice).
fn uid(key: &str) -> String {
    let fnv = |seed: u64| {
        key.bytes().fold(seed, |h, b| {
            (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let hi = fnv(0xcbf2_9ce4_8422_2325) as u128;
    let lo = fnv(0x8422_2325_cbf2_9ce4) as u128;
    format!("2.25.{}", (hi << 64 | lo) >> 1)
}

/// The HU samples of slice `z` as the writer's stored words
/// `raw = HU + 1024` (signed 16-bit).
fn stored_words(hu: &[i16], z: usize) -> Result<Vec<u16>, CtError> {
    let mut words = Vec::with_capacity(hu.len());
    for &hu in hu {
        let raw = hu as i32 + 1024;
        let raw = i16::try_from(raw).map_err(|_| CtError::HuOutOfRange { hu, slice: z })?;
        words.push(raw as u16);
    }
    Ok(words)
}

/// The identifying attributes of slice `z` of `series`: SOP class and
/// instance, modality, an anonymous patient, the deterministic study, series
/// and frame-of-reference UIDs, and InstanceNumber `z + 1`.
fn put_identity(obj: &mut InMemDicomObject, series: &str, z: usize) {
    let s = |t: Tag, vr: VR, v: String| DataElement::new(t, vr, PrimitiveValue::from(v));
    let sop = uid(&format!("{series}/{z}"));
    obj.put(s(
        tags::SOP_CLASS_UID,
        VR::UI,
        uids::CT_IMAGE_STORAGE.into(),
    ));
    obj.put(s(tags::SOP_INSTANCE_UID, VR::UI, sop));
    obj.put(s(tags::MODALITY, VR::CS, "CT".into()));
    obj.put(s(tags::PATIENT_NAME, VR::PN, "Anonymous".into()));
    obj.put(s(
        tags::STUDY_INSTANCE_UID,
        VR::UI,
        uid(&format!("{series}/study")),
    ));
    obj.put(s(
        tags::SERIES_INSTANCE_UID,
        VR::UI,
        uid(&format!("{series}/series")),
    ));
    obj.put(s(
        tags::FRAME_OF_REFERENCE_UID,
        VR::UI,
        uid(&format!("{series}/frame")),
    ));
    obj.put(s(tags::INSTANCE_NUMBER, VR::IS, format!("{}", z + 1)));
}

/// The bytes of slice `z` of `volume` as a single-frame CT Image Storage
/// DICOM file (explicit VR little endian; signed 16-bit samples
/// `raw = HU + 1024`, RescaleSlope 1, RescaleIntercept −1024;
/// ImageOrientationPatient = the volume's column and row axes,
/// ImagePositionPatient = the patient position of voxel (0, 0, z)).
/// `series` keys the deterministic study/series/instance UIDs.
pub fn dicom_slice_bytes(volume: &Volume, z: usize, series: &str) -> Result<Vec<u8>, CtError> {
    let sl = volume.slice(z);
    let words = stored_words(sl.data, z)?;
    let sp = volume.spacing;
    let frame = volume.frame();
    let pos = frame.to_patient([0.0, 0.0, z as f64 * sp.z]);
    let [r, c, _] = frame.axes;
    let iop: [f64; 6] = [r[0], r[1], r[2], c[0], c[1], c[2]];
    let n = normal(&iop);
    let location = pos[0] * n[0] + pos[1] * n[1] + pos[2] * n[2];
    let s = |t: Tag, vr: VR, v: String| DataElement::new(t, vr, PrimitiveValue::from(v));
    let u16e = |t: Tag, v: u16| DataElement::new(t, VR::US, PrimitiveValue::from(v));
    let mut obj = InMemDicomObject::new_empty();
    put_identity(&mut obj, series, z);
    obj.put(s(tags::SLICE_THICKNESS, VR::DS, ds(sp.z)));
    obj.put(s(
        tags::IMAGE_POSITION_PATIENT,
        VR::DS,
        format!("{}\\{}\\{}", ds(pos[0]), ds(pos[1]), ds(pos[2])),
    ));
    obj.put(s(
        tags::IMAGE_ORIENTATION_PATIENT,
        VR::DS,
        iop.map(ds).join("\\"),
    ));
    obj.put(s(tags::SLICE_LOCATION, VR::DS, ds(location)));
    obj.put(u16e(tags::SAMPLES_PER_PIXEL, 1));
    obj.put(s(
        tags::PHOTOMETRIC_INTERPRETATION,
        VR::CS,
        "MONOCHROME2".into(),
    ));
    obj.put(u16e(tags::ROWS, sl.ny as u16));
    obj.put(u16e(tags::COLUMNS, sl.nx as u16));
    obj.put(s(
        tags::PIXEL_SPACING,
        VR::DS,
        format!("{}\\{}", ds(sp.y), ds(sp.x)),
    ));
    obj.put(u16e(tags::BITS_ALLOCATED, 16));
    obj.put(u16e(tags::BITS_STORED, 16));
    obj.put(u16e(tags::HIGH_BIT, 15));
    obj.put(u16e(tags::PIXEL_REPRESENTATION, 1));
    obj.put(s(tags::RESCALE_INTERCEPT, VR::DS, "-1024".into()));
    obj.put(s(tags::RESCALE_SLOPE, VR::DS, "1".into()));
    obj.put(s(tags::RESCALE_TYPE, VR::LO, "HU".into()));
    obj.put(DataElement::new(
        tags::PIXEL_DATA,
        VR::OW,
        PrimitiveValue::U16(words.into()),
    ));
    if sl.nx > u16::MAX as usize || sl.ny > u16::MAX as usize {
        return Err(CtError::SliceTooLarge {
            nx: sl.nx,
            ny: sl.ny,
        });
    }
    let file = obj
        .with_meta(FileMetaTableBuilder::new().transfer_syntax(uids::EXPLICIT_VR_LITTLE_ENDIAN))
        .map_err(|e| CtError::DicomMeta {
            source: Box::new(e),
        })?;
    let mut bytes = Vec::new();
    file.write_all(&mut bytes)
        .map_err(|e| CtError::DicomEncode {
            source: Box::new(e),
        })?;
    Ok(bytes)
}

/// Writes slices `z_range` of `volume` into `dir` as `slice_NNNN.dcm`
/// (see [`dicom_slice_bytes`]), each atomically; returns the paths.
pub fn write_dicom_series(
    dir: &Path,
    volume: &Volume,
    z_range: std::ops::Range<usize>,
    series: &str,
) -> Result<Vec<PathBuf>, CtError> {
    let mut out = Vec::new();
    for z in z_range {
        let p = dir.join(format!("slice_{z:04}.dcm"));
        write_atomic(&p, &dicom_slice_bytes(volume, z, series)?)?;
        out.push(p);
    }
    Ok(out)
}
