//! The reader's walk over a DICOM file's element headers (PS3.5 §7): the
//! file meta information, then the data set, with sequences and items of
//! defined or undefined length, every declared length checked against the
//! bytes that remain in the file and in the enclosing sequence or item
//! before a value is looked at; values are borrowed from the file's bytes.

use dicom_core::dictionary::{DataDictionary, DataDictionaryEntry};
use dicom_core::{Tag, VR};
use dicom_dictionary_std::{tags, uids, StandardDataDictionary};

use super::MAX_DICOM_NESTING;
use crate::ct::error::DicomProblem;

/// The encoding of a data set (PS3.5 §10): the two the reader supports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Syntax {
    /// Implicit VR little endian: VRs come from the data dictionary.
    Implicit,
    /// Explicit VR little endian.
    Explicit,
}

/// A top-level element with a defined length, borrowed from the file.
#[derive(Clone, Copy, Debug)]
pub(super) struct Element<'a> {
    /// The VR (explicit, or the dictionary's for implicit VR).
    pub(super) vr: VR,
    /// Byte offset of the element's header in the file.
    pub(super) offset: usize,
    /// The value bytes.
    pub(super) value: &'a [u8],
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

/// The little-endian `u16` at `b[p..p + 2]`.
pub(super) fn u16_at(b: &[u8], p: usize) -> u16 {
    u16::from_le_bytes([b[p], b[p + 1]])
}

/// The little-endian `u32` at `b[p..p + 4]`.
pub(super) fn u32_at(b: &[u8], p: usize) -> u32 {
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

/// Where the walk is: the byte offset `p`, the bytes that remain before
/// the innermost defined end (`remaining`), and what that end belongs to.
#[derive(Clone, Copy, Debug)]
struct Here {
    p: usize,
    remaining: usize,
    container: &'static str,
}

impl Here {
    /// Error [`DicomProblem::TruncatedHeader`] unless `needed` bytes remain.
    fn need(&self, needed: usize) -> Result<(), DicomProblem> {
        if self.remaining < needed {
            Err(DicomProblem::TruncatedHeader {
                offset: self.p,
                needed,
                remaining: self.remaining,
            })
        } else {
            Ok(())
        }
    }

    /// Error [`DicomProblem::ElementLength`] for an element `tag` that
    /// declares `len` bytes when `remaining` are left after its header.
    fn too_long(&self, tag: Tag, len: u32, remaining: usize) -> DicomProblem {
        DicomProblem::ElementLength {
            tag,
            offset: self.p,
            declared: len as u64,
            remaining: remaining as u64,
            within: self.container,
        }
    }
}

/// The open sequences and items of a walk, innermost last.
struct Stack(Vec<Open>);

impl Stack {
    /// Closes the sequences and items whose defined length ends at `p`.
    fn close_ended(&mut self, p: usize) {
        while let Some(o) = self.0.last() {
            if o.end() == Some(p) {
                self.0.pop();
            } else {
                break;
            }
        }
    }

    /// Where the walk at `p` is: the innermost defined end, else `end` of
    /// the range `within`.
    fn here(&self, p: usize, end: usize, within: &'static str) -> Here {
        let (limit, container) = self
            .0
            .iter()
            .rev()
            .find_map(|o| match o {
                Open::Sequence { end: Some(e), .. } => Some((*e, "sequence")),
                Open::Item { end: Some(e), .. } => Some((*e, "sequence item")),
                _ => None,
            })
            .unwrap_or((end, within));
        Here {
            p,
            remaining: limit - p,
            container,
        }
    }

    /// The end of the range, or of a defined-length ancestor: fine at the
    /// top level, an unterminated sequence or item inside one of
    /// undefined length.
    fn at_end(&self) -> Result<(), DicomProblem> {
        match self.0.last() {
            None => Ok(()),
            Some(&Open::Sequence { tag, offset, .. }) => Err(DicomProblem::Unterminated {
                what: "sequence",
                tag,
                offset,
            }),
            Some(&Open::Item { offset, .. }) => Err(DicomProblem::Unterminated {
                what: "item",
                tag: ITEM,
                offset,
            }),
        }
    }

    /// Reads the 8-byte header `tag` (length `len`) met directly inside
    /// the sequence `seq` (ending at `seq_end`): an item opens, the
    /// delimiter of an undefined-length sequence closes it, anything else
    /// is an error.
    fn in_sequence(
        &mut self,
        here: Here,
        (tag, len): (Tag, u32),
        (seq, seq_end): (Tag, Option<usize>),
    ) -> Result<(), DicomProblem> {
        let p = here.p;
        if tag == ITEM {
            let end = if len == u32::MAX {
                None
            } else if len as usize > here.remaining - 8 {
                return Err(here.too_long(tag, len, here.remaining - 8));
            } else {
                Some(p + 8 + len as usize)
            };
            self.0.push(Open::Item { offset: p, end });
        } else if tag == SEQUENCE_DELIMITER && seq_end.is_none() {
            self.0.pop();
        } else {
            return Err(DicomProblem::ExpectedItem {
                sequence: seq,
                found: tag,
                offset: p,
            });
        }
        Ok(())
    }

    /// Opens the sequence `tag` whose header (`header` bytes, value length
    /// `len`, `u32::MAX` undefined) is at `p`, refusing a nesting deeper
    /// than [`MAX_DICOM_NESTING`].
    fn open_sequence(
        &mut self,
        tag: Tag,
        p: usize,
        header: usize,
        len: u32,
    ) -> Result<(), DicomProblem> {
        let depth = self
            .0
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
        self.0.push(Open::Sequence {
            tag,
            offset: p,
            end,
        });
        Ok(())
    }
}

/// The VR, value length and header size of the element `tag` whose header
/// is at `here.p`, in `syntax`.
fn element_header(
    bytes: &[u8],
    here: Here,
    tag: Tag,
    syntax: Syntax,
) -> Result<(VR, u32, usize), DicomProblem> {
    let p = here.p;
    Ok(match syntax {
        Syntax::Implicit => (implicit_vr(tag), u32_at(bytes, p + 4), 8),
        Syntax::Explicit => {
            let code = [bytes[p + 4], bytes[p + 5]];
            let vr = VR::from_binary(code).ok_or_else(|| DicomProblem::UnknownVr {
                tag,
                offset: p,
                vr: String::from_utf8_lossy(&code).into_owned(),
            })?;
            if long_header(vr) {
                here.need(12)?;
                (vr, u32_at(bytes, p + 8), 12)
            } else {
                (vr, u16_at(bytes, p + 6) as u32, 8)
            }
        }
    })
}

/// Checks the declared length `len` of a non-item element: undefined only
/// for a sequence (encapsulated pixel data is refused), defined no longer
/// than the `remaining` bytes after its header.
fn check_length(
    here: Here,
    (tag, vr, len): (Tag, VR, u32),
    sequence: bool,
    remaining: usize,
) -> Result<(), DicomProblem> {
    if len == u32::MAX && !sequence {
        return Err(if tag == tags::PIXEL_DATA {
            DicomProblem::EncapsulatedPixelData { offset: here.p }
        } else {
            DicomProblem::UndefinedLength {
                tag,
                offset: here.p,
                vr: vr.to_string().into(),
            }
        });
    }
    if len != u32::MAX && len as usize > remaining {
        return Err(here.too_long(tag, len, remaining));
    }
    Ok(())
}

/// Walks the elements of `bytes[start..end]` (a data set, or the file meta
/// information) in `syntax`, checking every header and declared length
/// against the bytes that remain in the file and in the enclosing sequence
/// or item, and the nesting against [`MAX_DICOM_NESTING`]. Calls `top` with
/// each top-level element of defined length that is not a sequence.
/// `within` names the range in messages.
pub(super) fn walk<'a>(
    bytes: &'a [u8],
    (start, end): (usize, usize),
    syntax: Syntax,
    within: &'static str,
    mut top: impl FnMut(Tag, Element<'a>) -> Result<(), DicomProblem>,
) -> Result<(), DicomProblem> {
    let mut stack = Stack(Vec::new());
    let mut p = start;
    loop {
        stack.close_ended(p);
        let here = stack.here(p, end, within);
        if here.remaining == 0 {
            return stack.at_end();
        }
        here.need(8)?;
        let tag = Tag(u16_at(bytes, p), u16_at(bytes, p + 2));
        if let Some(&Open::Sequence {
            tag: seq,
            end: seq_end,
            ..
        }) = stack.0.last()
        {
            let len = u32_at(bytes, p + 4);
            stack.in_sequence(here, (tag, len), (seq, seq_end))?;
            p += 8;
            continue;
        }
        if tag.0 == 0xFFFE {
            if tag == ITEM_DELIMITER && matches!(stack.0.last(), Some(Open::Item { end: None, .. }))
            {
                stack.0.pop();
                p += 8;
                continue;
            }
            return Err(DicomProblem::Delimiter { tag, offset: p });
        }
        let (vr, len, header) = element_header(bytes, here, tag, syntax)?;
        let remaining = here.remaining - header;
        let sequence = vr == VR::SQ || (syntax == Syntax::Implicit && len == u32::MAX);
        check_length(here, (tag, vr, len), sequence, remaining)?;
        if sequence {
            stack.open_sequence(tag, p, header, len)?;
            p += header;
            continue;
        }
        let value = &bytes[p + header..p + header + len as usize];
        if stack.0.is_empty() {
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
pub(super) fn file_meta(bytes: &[u8]) -> Result<(Syntax, usize), DicomProblem> {
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
pub(super) fn text(value: &[u8]) -> &str {
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
pub(super) fn numbers(e: &Element) -> Option<Vec<f64>> {
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
