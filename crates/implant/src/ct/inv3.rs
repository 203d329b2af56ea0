//! InVesalius `.inv3` projects: a gzip-compressed tar holding `main.plist`
//! (an XML property list with `matrix.shape = [nz, ny, nx]`,
//! `matrix.dtype = "int16"`, `matrix.filename` and `spacing = [sx, sy, sz]`
//! in mm) and the raw volume `matrix.dat` (little-endian int16 HU, z/y/x
//! order, no header). Format as written by InVesalius 3 (Amorim et al.,
//! "InVesalius: an interactive rendering framework for health care support",
//! ISVC 2015), `invesalius/project.py`.
//!
//! The reader walks the tar itself (POSIX ustar, with pax and GNU long-name
//! records) over the decompressed stream: the gzip trailer's ISIZE gives
//! the tar's length before anything is read, every header's checksum and
//! declared size are checked against the bytes that remain, members the
//! reader does not use are skipped without being held, and the gzip CRC-32
//! and length are verified before the volume is returned. Limits:
//! [`MAX_PLIST_BYTES`], [`MAX_TAR_EXTENSION_BYTES`], [`MAX_INV3_TAR_BYTES`].

use std::io::{BufRead, BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use flate2::bufread::GzDecoder;

use super::error::{CtError, Inv3Problem};
use super::plist::{parse_plist, PlistValue};
use super::volume::{FrameSource, Spacing, Volume, IDENTITY_AXES};
use crate::files::write_atomic;

/// The most bytes deflate can produce per compressed byte: a maximal match
/// of 258 bytes costs at least two bits, so the ratio is bounded by 1,032
/// (RFC 1951; zlib's technical details give the same bound).
const MAX_DEFLATE_RATIO: u64 = 1032;

/// The largest `main.plist` member read: 4 MiB. InVesalius writes a few
/// kilobytes (masks, surfaces and measurements live in their own members).
pub const MAX_PLIST_BYTES: u64 = 4 << 20;

/// The largest pax extended header or GNU long-name record read: 64 KiB
/// (they hold a path and a few numbers; Python's `tarfile` writes one of a
/// hundred bytes or so before each member).
pub const MAX_TAR_EXTENSION_BYTES: u64 = 64 << 10;

/// The largest tar an `.inv3` may hold: 4 GiB − 1 bytes, so that the gzip
/// trailer's ISIZE (the length modulo 2³², RFC 1952) states its length
/// exactly. A 512×512×4000 int16 volume is 2 GiB.
pub const MAX_INV3_TAR_BYTES: u64 = u32::MAX as u64;

/// The name InVesalius gives the volume member (the plist's
/// `matrix.filename`), kept when it comes before `main.plist`.
const DEFAULT_MATRIX: &str = "matrix.dat";

/// A tar block.
const BLOCK: u64 = 512;

/// What `main.plist` says about the volume.
#[derive(Clone, Debug)]
struct PlistInfo {
    nx: usize,
    ny: usize,
    nz: usize,
    spacing: [f64; 3],
    /// The volume member's file name.
    filename: String,
    /// Bytes the shape needs, `2·nx·ny·nz` (`u64::MAX` when that overflows).
    bytes: u64,
    orientation: Option<i64>,
}

/// The volume member as read.
struct Matrix {
    /// Offset of its tar header.
    at: u64,
    /// The size its header declares.
    bytes: u64,
    /// Its samples (empty when `bytes` is odd: no shape can match it).
    data: Vec<i16>,
}

/// The decompressed tar stream, its position, and the length the gzip
/// trailer declares.
struct Tar<R> {
    inner: GzDecoder<R>,
    pos: u64,
    total: u64,
}

impl<R: BufRead> Tar<R> {
    /// A decompression failure at the current position: the trailer's
    /// check when every declared byte was produced, else a corrupt or
    /// truncated stream.
    fn gzip_error(&self, source: std::io::Error) -> Inv3Problem {
        if self.pos >= self.total {
            Inv3Problem::Checksum(source)
        } else {
            Inv3Problem::Gzip {
                at: self.pos,
                total: self.total,
                source,
            }
        }
    }

    /// Reads up to `buf.len()` bytes; fewer only at the end of the stream.
    fn fill(&mut self, buf: &mut [u8]) -> Result<usize, Inv3Problem> {
        let mut n = 0;
        while n < buf.len() {
            match self.inner.read(&mut buf[n..]) {
                Ok(0) => break,
                Ok(k) => {
                    n += k;
                    self.pos += k as u64;
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => return Err(self.gzip_error(e)),
            }
        }
        Ok(n)
    }

    /// Fills `buf` exactly.
    fn exact(&mut self, buf: &mut [u8]) -> Result<(), Inv3Problem> {
        if self.fill(buf)? < buf.len() {
            return Err(Inv3Problem::Truncated {
                at: self.pos,
                total: self.total,
            });
        }
        Ok(())
    }

    /// Skips `n` bytes without holding them.
    fn skip(&mut self, mut n: u64) -> Result<(), Inv3Problem> {
        let mut buf = [0u8; 8192];
        while n > 0 {
            let k = n.min(buf.len() as u64) as usize;
            self.exact(&mut buf[..k])?;
            n -= k as u64;
        }
        Ok(())
    }

    /// Reads the rest of the stream, which verifies the gzip CRC-32 and
    /// length (RFC 1952).
    fn drain(&mut self) -> Result<(), Inv3Problem> {
        let mut buf = [0u8; 8192];
        while self.fill(&mut buf)? == buf.len() {}
        Ok(())
    }

    /// `n` bytes as little-endian int16 samples (`n` even), grown as the
    /// bytes arrive so that memory follows what the stream holds, not what
    /// a header declares.
    fn samples(&mut self, n: u64) -> Result<Vec<i16>, Inv3Problem> {
        let count = (n / 2) as usize;
        let mut buf = vec![0u8; 64 << 10];
        let mut data: Vec<i16> = Vec::with_capacity(count.min(buf.len() / 2));
        let mut left = n;
        while left > 0 {
            let k = left.min(buf.len() as u64) as usize;
            self.exact(&mut buf[..k])?;
            let room = data.capacity() - data.len();
            if room < k / 2 {
                data.reserve_exact((count - data.len()).min(data.len().max(k / 2)));
            }
            data.extend(
                buf[..k]
                    .chunks_exact(2)
                    .map(|c| i16::from_le_bytes([c[0], c[1]])),
            );
            left -= k as u64;
        }
        Ok(data)
    }
}

/// A tar header field as an unsigned number: octal digits (padded with
/// spaces or NULs), or GNU base-256 when the first byte's high bit is set.
fn tar_number(field: &[u8]) -> Option<u64> {
    if field.first().is_some_and(|b| b & 0x80 != 0) {
        let mut v: u64 = (field[0] & 0x7f) as u64;
        for &b in &field[1..] {
            v = v.checked_mul(256)?.checked_add(b as u64)?;
        }
        return Some(v);
    }
    let digits: &[u8] = {
        let t = field
            .iter()
            .position(|&b| b == 0)
            .map_or(field, |i| &field[..i]);
        let s = t.iter().position(|&b| b != b' ').unwrap_or(t.len());
        let e = t.iter().rposition(|&b| b != b' ').map_or(s, |i| i + 1);
        &t[s..e]
    };
    digits.iter().try_fold(0u64, |v, &d| {
        (b'0'..=b'7')
            .contains(&d)
            .then(|| v.checked_mul(8)?.checked_add((d - b'0') as u64))
            .flatten()
    })
}

/// The text of a NUL-terminated header field.
fn tar_text(field: &[u8]) -> String {
    let end = field.iter().position(|&b| b == 0).unwrap_or(field.len());
    String::from_utf8_lossy(&field[..end]).into_owned()
}

/// The `path` and `size` records of a pax extended header (`"LEN key=value\n"`).
fn pax_records(data: &[u8], at: u64) -> Result<(Option<String>, Option<u64>), Inv3Problem> {
    let bad = || Inv3Problem::HeaderField {
        offset: at,
        field: "pax record",
        text: String::from_utf8_lossy(&data[..data.len().min(64)]).into_owned(),
    };
    let (mut path, mut size) = (None, None);
    let mut rest = data;
    while !rest.is_empty() && rest[0] != 0 {
        let space = rest.iter().position(|&b| b == b' ').ok_or_else(bad)?;
        let len: usize = std::str::from_utf8(&rest[..space])
            .ok()
            .and_then(|t| t.parse().ok())
            .filter(|&l| l > space + 1 && l <= rest.len())
            .ok_or_else(bad)?;
        let record = &rest[space + 1..len];
        let record = record.strip_suffix(b"\n").ok_or_else(bad)?;
        let eq = record.iter().position(|&b| b == b'=').ok_or_else(bad)?;
        let value = &record[eq + 1..];
        match &record[..eq] {
            b"path" => path = Some(String::from_utf8_lossy(value).into_owned()),
            b"size" => {
                size = Some(
                    std::str::from_utf8(value)
                        .ok()
                        .and_then(|t| t.parse().ok())
                        .ok_or_else(bad)?,
                )
            }
            _ => {}
        }
        rest = &rest[len..];
    }
    Ok((path, size))
}

/// What one pass over the tar found.
#[derive(Default)]
struct Found {
    /// The plist's header offset and what it says (or why it says nothing).
    plist: Option<(u64, Result<PlistInfo, CtError>)>,
    /// The volume member.
    matrix: Option<Matrix>,
}

/// Checks the header checksum of the tar header `header` at `at`: the sum
/// of its bytes with the checksum field read as spaces.
fn check_checksum(header: &[u8], at: u64) -> Result<(), Inv3Problem> {
    let stored = tar_number(&header[148..156]);
    let computed: u64 = header
        .iter()
        .enumerate()
        .map(|(i, &b)| {
            if (148..156).contains(&i) {
                32
            } else {
                b as u64
            }
        })
        .sum();
    if stored != Some(computed) {
        return Err(Inv3Problem::HeaderChecksum {
            offset: at,
            stored: tar_text(&header[148..156]),
            computed,
        });
    }
    Ok(())
}

/// The extensions pending for the next member: a GNU long name and a pax
/// header's path and size.
#[derive(Default)]
struct Pending {
    long_name: Option<String>,
    pax: (Option<String>, Option<u64>),
}

/// One tar member's header: its type flag, name, size and the padding
/// after its data.
struct Member {
    at: u64,
    kind: u8,
    name: String,
    size: u64,
    padding: u64,
}

impl Member {
    /// Its base name (after the last `/`).
    fn base(&self) -> String {
        self.name.rsplit('/').next().unwrap_or("").to_string()
    }

    /// [`Inv3Problem::DuplicateMember`]: a second member of its base name,
    /// the first at `first`.
    fn duplicate_of(&self, first: u64) -> Inv3Problem {
        Inv3Problem::DuplicateMember {
            name: self.base(),
            first,
            second: self.at,
        }
    }
}

/// The member whose checked `header` is at `at`, with the `pending`
/// extensions applied, its size checked against the bytes that remain.
fn member<R: BufRead>(
    tar: &Tar<R>,
    header: &[u8],
    at: u64,
    pending: &mut Pending,
) -> Result<Member, Inv3Problem> {
    let field = |name: &'static str, range: std::ops::Range<usize>| {
        tar_number(&header[range.clone()]).ok_or_else(|| Inv3Problem::HeaderField {
            offset: at,
            field: name,
            text: tar_text(&header[range]),
        })
    };
    let kind = header[156];
    let size = match pending.pax.1.take() {
        Some(s) => s,
        None => field("size", 124..136)?,
    };
    let mut name = tar_text(&header[..100]);
    if &header[257..262] == b"ustar" && header[345] != 0 {
        name = format!("{}/{name}", tar_text(&header[345..500]));
    }
    let name = pending
        .long_name
        .take()
        .or(pending.pax.0.take())
        .unwrap_or(name);
    let remaining = tar.total.saturating_sub(tar.pos);
    let padded = size.div_ceil(BLOCK).saturating_mul(BLOCK);
    if size > remaining {
        return Err(Inv3Problem::MemberTooLarge {
            name,
            offset: at,
            declared: size,
            remaining,
            total: tar.total,
        });
    }
    Ok(Member {
        at,
        kind,
        name,
        size,
        padding: padded.min(remaining) - size,
    })
}

/// Reads the extension member `m` (a pax extended header or a GNU long
/// name, at most [`MAX_TAR_EXTENSION_BYTES`]) into `pending`.
fn read_extension<R: BufRead>(
    tar: &mut Tar<R>,
    m: &Member,
    pending: &mut Pending,
) -> Result<(), Inv3Problem> {
    if m.size > MAX_TAR_EXTENSION_BYTES {
        return Err(Inv3Problem::Extension {
            kind: if m.kind == b'x' {
                "pax extended header"
            } else {
                "GNU long name"
            },
            offset: m.at,
            declared: m.size,
            limit: MAX_TAR_EXTENSION_BYTES,
        });
    }
    let mut data = vec![0u8; m.size as usize];
    tar.exact(&mut data)?;
    tar.skip(m.padding)?;
    if m.kind == b'x' {
        pending.pax = pax_records(&data, m.at)?;
    } else {
        pending.long_name = Some(tar_text(&data));
    }
    Ok(())
}

/// Reads the member `m`, `main.plist` (at most [`MAX_PLIST_BYTES`], once),
/// into `found`, checking a volume member already held against it.
fn read_plist<R: BufRead>(
    tar: &mut Tar<R>,
    path: &Path,
    m: Member,
    found: &mut Found,
) -> Result<(), CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    if let Some((first, _)) = found.plist {
        return Err(bad(m.duplicate_of(first)));
    }
    if m.size > MAX_PLIST_BYTES {
        return Err(bad(Inv3Problem::PlistTooLarge {
            declared: m.size,
            limit: MAX_PLIST_BYTES,
        }));
    }
    let mut text = vec![0u8; m.size as usize];
    tar.exact(&mut text).map_err(bad)?;
    tar.skip(m.padding).map_err(bad)?;
    let info = plist_info(&text, path);
    if let (Ok(info), Some(held)) = (&info, &found.matrix) {
        if info.filename != DEFAULT_MATRIX {
            found.matrix = None; // held as `matrix.dat`, not the one named
        } else if held.bytes != info.bytes {
            return Err(byte_count(path, info.bytes, held.bytes));
        }
    }
    found.plist = Some((m.at, info));
    Ok(())
}

/// Reads the volume member `m` (once; its size checked against the plist's
/// shape when known) into `found`: its samples, or none for an odd size.
fn read_matrix<R: BufRead>(
    tar: &mut Tar<R>,
    path: &Path,
    m: Member,
    found: &mut Found,
) -> Result<(), CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    if let Some(held) = &found.matrix {
        return Err(bad(m.duplicate_of(held.at)));
    }
    if let Some((_, Ok(info))) = &found.plist {
        if m.size != info.bytes {
            return Err(byte_count(path, info.bytes, m.size));
        }
    }
    let data = if m.size.is_multiple_of(2) {
        tar.samples(m.size).map_err(bad)?
    } else {
        tar.skip(m.size).map_err(bad)?;
        Vec::new()
    };
    tar.skip(m.padding).map_err(bad)?;
    found.matrix = Some(Matrix {
        at: m.at,
        bytes: m.size,
        data,
    });
    Ok(())
}

/// One pass over the tar entries of `tar` up to the end-of-archive block.
/// With `only = None` it keeps `main.plist` and the volume member it names
/// (`matrix.dat` while the plist is not yet read); with `only =
/// Some((name, plist_at))` it keeps only the member `name` and stops at the
/// plist's header. Members are checked before anything is held: the header
/// checksum, the declared size against the bytes that remain by the gzip
/// trailer, [`MAX_PLIST_BYTES`] and [`MAX_TAR_EXTENSION_BYTES`], and the
/// volume member's size against the plist's shape when it is known.
fn scan<R: BufRead>(
    tar: &mut Tar<R>,
    path: &Path,
    only: Option<(&str, u64)>,
) -> Result<Found, CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    let mut found = Found::default();
    let mut header = [0u8; BLOCK as usize];
    let mut pending = Pending::default();
    loop {
        let at = tar.pos;
        if only.is_some_and(|(_, stop)| at >= stop) {
            return Ok(found);
        }
        let n = tar.fill(&mut header).map_err(bad)?;
        if n == 0 {
            return Ok(found); // the stream ends without end-of-archive blocks
        }
        if n < header.len() {
            return Err(bad(Inv3Problem::Truncated {
                at: tar.pos,
                total: tar.total,
            }));
        }
        if header.iter().all(|&b| b == 0) {
            return Ok(found); // end of archive
        }
        check_checksum(&header, at).map_err(bad)?;
        let m = member(tar, &header, at, &mut pending).map_err(bad)?;
        match m.kind {
            b'x' | b'L' => {
                read_extension(tar, &m, &mut pending).map_err(bad)?;
                continue;
            }
            b'0' | b'\0' | b'7' => {}
            _ => {
                // Directories, links, global pax headers, ...: not used.
                tar.skip(m.size + m.padding).map_err(bad)?;
                continue;
            }
        }
        let base = m.base();
        let target = match (only, &found.plist) {
            (Some((want, _)), _) => Some(want),
            (None, None) => Some(DEFAULT_MATRIX),
            (None, Some((_, Ok(info)))) => Some(info.filename.as_str()),
            (None, Some((_, Err(_)))) => None,
        };
        if only.is_none() && base == "main.plist" {
            read_plist(tar, path, m, &mut found)?;
        } else if target == Some(base.as_str()) {
            read_matrix(tar, path, m, &mut found)?;
            if only.is_some() {
                return Ok(found);
            }
        } else {
            tar.skip(m.size + m.padding).map_err(bad)?;
        }
    }
}

fn byte_count(path: &Path, expected: u64, found: u64) -> CtError {
    CtError::ByteCount {
        path: path.to_owned(),
        expected,
        found,
    }
}

/// Opens the gzip stream of `src` as a tar: reads the trailer's ISIZE (the
/// tar's length), at most what a deflate stream of the file's size can
/// produce.
fn open_tar<'a, S: Read + Seek>(
    src: &'a mut S,
    path: &Path,
) -> Result<Tar<BufReader<&'a mut S>>, CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    let io = |e| CtError::io(path, e);
    let file_len = src.seek(SeekFrom::End(0)).map_err(io)?;
    // A gzip member is at least a 10-byte header and an 8-byte trailer.
    if file_len < 18 {
        return Err(bad(Inv3Problem::TooShort { len: file_len }));
    }
    src.seek(SeekFrom::End(-4)).map_err(io)?;
    let mut isize = [0u8; 4];
    src.read_exact(&mut isize).map_err(io)?;
    // At most MAX_INV3_TAR_BYTES by construction. A trailer that claims
    // more than deflate can produce from the file is wrong (the stream's
    // own check will say so); the most it can produce bounds the members.
    let total = (u32::from_le_bytes(isize) as u64).min(file_len.saturating_mul(MAX_DEFLATE_RATIO));
    src.seek(SeekFrom::Start(0)).map_err(io)?;
    Ok(Tar {
        inner: GzDecoder::new(BufReader::new(src)),
        pos: 0,
        total,
    })
}

/// Reads the CT volume of the `.inv3` held by `src` (see [`read_inv3`]).
fn read_inv3_from<S: Read + Seek>(src: &mut S, path: &Path) -> Result<Volume, CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    let mut tar = open_tar(src, path)?;
    let scanned = scan(&mut tar, path, None);
    // The stream's integrity comes first (its CRC-32 and length, and
    // nothing after it, so that ISIZE was the trailer's): a corrupt byte is
    // reported as such, not as whatever it made of the tar.
    tar.drain().map_err(bad)?;
    let mut rest = tar.inner.into_inner();
    if !rest
        .fill_buf()
        .map_err(|e| CtError::io(path, e))?
        .is_empty()
    {
        return Err(bad(Inv3Problem::TrailingData));
    }
    let mut found = scanned?;
    let (plist_at, info) = found
        .plist
        .take()
        .ok_or_else(|| bad(Inv3Problem::MissingMember("main.plist".into())))?;
    let info = info?;
    if found.matrix.is_none() && info.filename != DEFAULT_MATRIX && plist_at > 0 {
        // The member the plist names came before it: a second pass.
        drop(rest);
        let mut again = open_tar(src, path)?;
        found = scan(&mut again, path, Some((&info.filename, plist_at)))?;
    }
    let matrix = found
        .matrix
        .ok_or_else(|| bad(Inv3Problem::MissingMember(info.filename.clone())))?;
    if matrix.bytes != info.bytes {
        return Err(byte_count(path, info.bytes, matrix.bytes));
    }
    let [x, y, z] = info.spacing;
    Volume::new(
        info.nx,
        info.ny,
        info.nz,
        Spacing { x, y, z },
        [0.0; 3],
        matrix.data,
    )?
    .with_frame(
        [0.0; 3],
        IDENTITY_AXES,
        FrameSource::Inv3 {
            orientation: info.orientation,
        },
    )
}

/// What `main.plist` (the bytes `text`) says about the volume: an int16
/// matrix of positive shape, its member's name and a positive spacing.
fn plist_info(text: &[u8], path: &Path) -> Result<PlistInfo, CtError> {
    let bad = |problem: Inv3Problem| CtError::inv3(path, problem);
    let text = std::str::from_utf8(text).map_err(|_| bad(Inv3Problem::PlistNotUtf8))?;
    let plist = parse_plist(text).map_err(|e| bad(Inv3Problem::Plist(e)))?;
    let matrix = plist
        .get("matrix")
        .ok_or_else(|| bad(Inv3Problem::NoMatrix))?;
    let dtype = matrix
        .get("dtype")
        .and_then(PlistValue::as_str)
        .unwrap_or("");
    if dtype != "int16" {
        return Err(bad(Inv3Problem::Dtype(dtype.into())));
    }
    let shape: Vec<i64> = matrix
        .get("shape")
        .and_then(PlistValue::as_array)
        .map(|a| a.iter().filter_map(PlistValue::as_i64).collect())
        .unwrap_or_default();
    if shape.len() != 3 || shape.iter().any(|&s| s <= 0) {
        return Err(bad(Inv3Problem::Shape(shape)));
    }
    let spacing: Vec<f64> = plist
        .get("spacing")
        .and_then(PlistValue::as_array)
        .map(|a| a.iter().filter_map(PlistValue::as_f64).collect())
        .unwrap_or_default();
    if spacing.len() != 3 || spacing.iter().any(|&s| !(s.is_finite() && s > 0.0)) {
        return Err(bad(Inv3Problem::Spacing(spacing)));
    }
    let bytes = shape
        .iter()
        .try_fold(2u64, |acc, &n| acc.checked_mul(n as u64))
        .unwrap_or(u64::MAX);
    Ok(PlistInfo {
        nx: shape[2] as usize,
        ny: shape[1] as usize,
        nz: shape[0] as usize,
        spacing: [spacing[0], spacing[1], spacing[2]],
        filename: matrix
            .get("filename")
            .and_then(PlistValue::as_str)
            .unwrap_or(DEFAULT_MATRIX)
            .to_string(),
        bytes,
        orientation: plist.get("orientation").and_then(PlistValue::as_i64),
    })
}

/// Reads the CT volume of an `.inv3` project. Masks, surfaces and any
/// other member are skipped without being held: memory is the volume, the
/// plist (at most [`MAX_PLIST_BYTES`]) and fixed buffers. The project holds
/// no origin or patient axes (only the spacing and an `orientation` flag,
/// kept in [`FrameSource::Inv3`]), so the volume's frame is the identity
/// at 0. Errors name the file: a corrupt or truncated gzip stream (CRC-32,
/// length, or data after its end), a tar header with a bad checksum or a
/// size beyond the bytes that remain, a missing or duplicated `main.plist`
/// or matrix, a malformed plist, a dtype other than int16, or a matrix
/// whose byte count is not `2·nx·ny·nz`.
pub fn read_inv3(path: &Path) -> Result<Volume, CtError> {
    let mut file = std::fs::File::open(path).map_err(|e| CtError::io(path, e))?;
    read_inv3_from(&mut file, path)
}

/// Reads the CT volume of the `.inv3` whose file holds `bytes` (see
/// [`read_inv3`]; `path` only names it in errors).
pub fn read_inv3_bytes(path: &Path, bytes: &[u8]) -> Result<Volume, CtError> {
    read_inv3_from(&mut std::io::Cursor::new(bytes), path)
}

/// The `main.plist` text for `volume` (InVesalius 3 layout, no masks or
/// surfaces).
pub fn inv3_plist(volume: &Volume, name: &str) -> String {
    let esc = name
        .replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;");
    let (lo, hi) = volume
        .data()
        .iter()
        .fold((i16::MAX, i16::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
<!DOCTYPE plist PUBLIC \"-//Apple Computer//DTD PLIST 1.0//EN\" \"http://www.apple.com/DTDs/PropertyList-1.0.dtd\">\n\
<plist version=\"1.0\">\n<dict>\n\
\t<key>annotations</key>\n\t<dict>\n\t</dict>\n\
\t<key>format_version</key>\n\t<integer>1</integer>\n\
\t<key>masks</key>\n\t<dict>\n\t</dict>\n\
\t<key>matrix</key>\n\t<dict>\n\
\t\t<key>dtype</key>\n\t\t<string>int16</string>\n\
\t\t<key>filename</key>\n\t\t<string>matrix.dat</string>\n\
\t\t<key>shape</key>\n\t\t<array>\n\t\t\t<integer>{}</integer>\n\t\t\t<integer>{}</integer>\n\t\t\t<integer>{}</integer>\n\t\t</array>\n\
\t</dict>\n\
\t<key>modality</key>\n\t<string>CT</string>\n\
\t<key>name</key>\n\t<string>{esc}</string>\n\
\t<key>scalar_range</key>\n\t<array>\n\t\t<integer>{lo}</integer>\n\t\t<integer>{hi}</integer>\n\t</array>\n\
\t<key>spacing</key>\n\t<array>\n\t\t<real>{:?}</real>\n\t\t<real>{:?}</real>\n\t\t<real>{:?}</real>\n\t</array>\n\
\t<key>surfaces</key>\n\t<dict>\n\t</dict>\n\
</dict>\n</plist>\n",
        volume.nz, volume.ny, volume.nx, volume.spacing.x, volume.spacing.y, volume.spacing.z
    )
}

/// The bytes of an `.inv3` file holding `volume` (gzip of a tar with
/// `main.plist` and `matrix.dat`; deterministic: members have mtime 0).
pub fn inv3_bytes(volume: &Volume, name: &str) -> Vec<u8> {
    let plist = inv3_plist(volume, name);
    let mut matrix = Vec::with_capacity(volume.data().len() * 2);
    for v in volume.data() {
        matrix.extend_from_slice(&v.to_le_bytes());
    }
    let mut builder = tar::Builder::new(Vec::new());
    for (member, bytes) in [
        ("main.plist", plist.as_bytes()),
        ("matrix.dat", &matrix[..]),
    ] {
        let mut header = tar::Header::new_ustar();
        header.set_size(bytes.len() as u64);
        header.set_mode(0o644);
        header.set_mtime(0);
        header.set_entry_type(tar::EntryType::Regular);
        // Writing into a Vec cannot fail.
        builder
            .append_data(&mut header, member, bytes)
            .expect("tar into memory");
    }
    let tar_bytes = builder.into_inner().expect("tar into memory");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    std::io::Write::write_all(&mut gz, &tar_bytes).expect("gzip into memory");
    gz.finish().expect("gzip into memory")
}

/// Writes `volume` as an `.inv3` project readable by [`read_inv3`] and by
/// InVesalius (atomically, via [`write_atomic`]).
pub fn write_inv3(path: &Path, volume: &Volume, name: &str) -> Result<(), CtError> {
    write_atomic(path, &inv3_bytes(volume, name))?;
    Ok(())
}
