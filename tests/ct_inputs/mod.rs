//! Inputs for the CT reader tests (`tests/implant/ct/`, `tests/fuzz/fuzz_ct.rs`):
//! DICOM files edited element by element, tar archives built header by
//! header, and gzip streams (compressed or stored).
#![allow(dead_code)]

use std::ops::Range;
use std::path::PathBuf;

use metabezier::ct::{Spacing, Volume};

/// The crate root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// pydicom's CT_small.dcm (explicit VR little endian, 128×128, 16 bits).
pub fn ct_small() -> Vec<u8> {
    std::fs::read(root().join("data/dicom/CT_small.dcm")).unwrap()
}

/// CT_small.dcm re-encoded in implicit VR little endian by `dicom-object`.
pub fn ct_small_implicit() -> Vec<u8> {
    let file = dicom_object::open_file(root().join("data/dicom/CT_small.dcm")).unwrap();
    let obj = file.into_inner();
    let file = obj
        .with_meta(
            dicom_object::FileMetaTableBuilder::new()
                .transfer_syntax(dicom_dictionary_std::uids::IMPLICIT_VR_LITTLE_ENDIAN),
        )
        .unwrap();
    let mut bytes = Vec::new();
    file.write_all(&mut bytes).unwrap();
    bytes
}

/// A top-level element of an explicit-VR little-endian file.
#[derive(Clone, Debug)]
pub struct Elem {
    /// (group, element).
    pub tag: (u16, u16),
    /// The header's offset.
    pub at: usize,
    /// The header's length (8 or 12).
    pub header: usize,
    /// The value's bytes.
    pub value: Range<usize>,
}

fn long_vr(vr: &[u8]) -> bool {
    [
        b"OB", b"OD", b"OF", b"OL", b"OV", b"OW", b"SQ", b"SV", b"UC", b"UN", b"UR", b"UT", b"UV",
    ]
    .iter()
    .any(|v| &v[..] == vr)
}

/// The top-level elements (file meta information included) of an
/// explicit-VR little-endian file with a preamble whose sequences, if any,
/// have defined lengths.
pub fn elements(b: &[u8]) -> Vec<Elem> {
    let mut out = Vec::new();
    let mut p = 132;
    while p + 8 <= b.len() {
        let tag = (
            u16::from_le_bytes([b[p], b[p + 1]]),
            u16::from_le_bytes([b[p + 2], b[p + 3]]),
        );
        let (header, len) = if long_vr(&b[p + 4..p + 6]) {
            (
                12,
                u32::from_le_bytes(b[p + 8..p + 12].try_into().unwrap()) as usize,
            )
        } else {
            (8, u16::from_le_bytes([b[p + 6], b[p + 7]]) as usize)
        };
        out.push(Elem {
            tag,
            at: p,
            header,
            value: p + header..p + header + len,
        });
        p += header + len;
    }
    out
}

/// The element `tag` of `b`.
pub fn element(b: &[u8], tag: (u16, u16)) -> Elem {
    elements(b)
        .into_iter()
        .find(|e| e.tag == tag)
        .unwrap_or_else(|| panic!("no element {tag:04X?}"))
}

/// `b` with the value of `tag` replaced by `value` (its length field and,
/// in the file meta information, the group length updated).
pub fn with_value(b: &[u8], tag: (u16, u16), value: &[u8]) -> Vec<u8> {
    let e = element(b, tag);
    let mut out = b[..e.at + e.header].to_vec();
    if e.header == 12 {
        out[e.at + 8..e.at + 12].copy_from_slice(&(value.len() as u32).to_le_bytes());
    } else {
        out[e.at + 6..e.at + 8].copy_from_slice(&(value.len() as u16).to_le_bytes());
    }
    out.extend_from_slice(value);
    out.extend_from_slice(&b[e.value.end..]);
    if tag.0 == 2 {
        let g = element(&out, (2, 0)).value.start;
        let old = u32::from_le_bytes(out[g..g + 4].try_into().unwrap()) as i64;
        let new = old + value.len() as i64 - e.value.len() as i64;
        out[g..g + 4].copy_from_slice(&(new as u32).to_le_bytes());
    }
    out
}

/// `b` without the top-level elements `tags` (the file meta
/// information's group length updated).
pub fn without(b: &[u8], tags: &[(u16, u16)]) -> Vec<u8> {
    let mut out = b[..132].to_vec();
    let mut meta_removed = 0u32;
    for e in elements(b) {
        if tags.contains(&e.tag) {
            if e.tag.0 == 2 {
                meta_removed += (e.value.end - e.at) as u32;
            }
        } else {
            out.extend_from_slice(&b[e.at..e.value.end]);
        }
    }
    let g = element(&out, (2, 0)).value.start;
    let old = u32::from_le_bytes(out[g..g + 4].try_into().unwrap());
    out[g..g + 4].copy_from_slice(&(old - meta_removed).to_le_bytes());
    out
}

/// `b` with the raw bytes `raw` inserted before the element `tag`.
pub fn insert_before(b: &[u8], tag: (u16, u16), raw: &[u8]) -> Vec<u8> {
    let at = element(b, tag).at;
    [&b[..at], raw, &b[at..]].concat()
}

/// `b` with its declared transfer syntax replaced by `uid`.
pub fn with_syntax(b: &[u8], uid: &str) -> Vec<u8> {
    let mut v = uid.as_bytes().to_vec();
    if v.len() % 2 == 1 {
        v.push(0);
    }
    with_value(b, (0x0002, 0x0010), &v)
}

/// An explicit-VR element header (and value) with a 32-bit length.
pub fn long_element(tag: (u16, u16), vr: &[u8; 2], len: u32, value: &[u8]) -> Vec<u8> {
    let mut v = Vec::new();
    v.extend_from_slice(&tag.0.to_le_bytes());
    v.extend_from_slice(&tag.1.to_le_bytes());
    v.extend_from_slice(vr);
    v.extend_from_slice(&[0, 0]);
    v.extend_from_slice(&len.to_le_bytes());
    v.extend_from_slice(value);
    v
}

/// An explicit-VR element with a 16-bit length.
pub fn short_element(tag: (u16, u16), vr: &[u8; 2], value: &[u8]) -> Vec<u8> {
    let mut v = Vec::new();
    v.extend_from_slice(&tag.0.to_le_bytes());
    v.extend_from_slice(&tag.1.to_le_bytes());
    v.extend_from_slice(vr);
    v.extend_from_slice(&(value.len() as u16).to_le_bytes());
    v.extend_from_slice(value);
    v
}

/// An item or delimiter header: (FFFE, `element`) and a 32-bit length.
pub fn item(element: u16, len: u32) -> Vec<u8> {
    let mut v = vec![0xFE, 0xFF];
    v.extend_from_slice(&element.to_le_bytes());
    v.extend_from_slice(&len.to_le_bytes());
    v
}

/// A 7×5×3 volume with distinct values.
pub fn small_volume() -> Volume {
    let (nx, ny, nz) = (7, 5, 3);
    let data = (0..nx * ny * nz).map(|i| (i as i16) * 37 - 1024).collect();
    Volume::new(
        nx,
        ny,
        nz,
        Spacing {
            x: 0.5,
            y: 0.75,
            z: 2.0,
        },
        [0.0; 3],
        data,
    )
    .unwrap()
}

/// A 48×48×3 block of the vendored CT 0051 extract (columns 104–151, rows
/// 200–247, extract slices 20–22): real, poorly compressible samples.
pub fn ct_block() -> Volume {
    let full = metabezier::ct::read_inv3(&root().join(metabezier::ct::CT0051_PATH)).unwrap();
    let (x0, y0, z0, n) = (104, 200, 20, 48);
    let mut data = Vec::with_capacity(n * n * 3);
    for z in z0..z0 + 3 {
        for y in y0..y0 + n {
            for x in x0..x0 + n {
                data.push(full.get(z, y, x));
            }
        }
    }
    Volume::new(n, n, 3, full.spacing, [0.0; 3], data).unwrap()
}

/// The little-endian bytes of a volume's samples (`matrix.dat`).
pub fn matrix_bytes(v: &Volume) -> Vec<u8> {
    v.data().iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// A ustar header for a member `name` of `size` bytes and type `kind`,
/// with its checksum.
pub fn tar_header(name: &str, size: u64, kind: u8) -> [u8; 512] {
    let mut h = [0u8; 512];
    h[..name.len()].copy_from_slice(name.as_bytes());
    h[100..108].copy_from_slice(b"0000644\0");
    h[108..116].copy_from_slice(b"0000000\0");
    h[116..124].copy_from_slice(b"0000000\0");
    h[124..136].copy_from_slice(format!("{size:011o}\0").as_bytes());
    h[136..148].copy_from_slice(b"00000000000\0");
    h[156] = kind;
    h[257..263].copy_from_slice(b"ustar\0");
    h[263..265].copy_from_slice(b"00");
    set_tar_checksum(&mut h);
    h
}

/// Recomputes the checksum of the tar header `h`.
pub fn set_tar_checksum(h: &mut [u8]) {
    h[148..156].copy_from_slice(b"        ");
    let sum: u32 = h[..512].iter().map(|&b| b as u32).sum();
    h[148..156].copy_from_slice(format!("{sum:06o}\0 ").as_bytes());
}

/// A tar archive of `members` (name, type, bytes), each padded to 512
/// bytes, with the two end-of-archive blocks.
pub fn tar(members: &[(&str, u8, &[u8])]) -> Vec<u8> {
    let mut out = Vec::new();
    for (name, kind, data) in members {
        out.extend_from_slice(&tar_header(name, data.len() as u64, *kind));
        out.extend_from_slice(data);
        out.resize(out.len().div_ceil(512) * 512, 0);
    }
    out.resize(out.len() + 1024, 0);
    out
}

/// A pax extended header's data holding the records `key=value`.
pub fn pax(records: &[(&str, &str)]) -> Vec<u8> {
    let mut out = Vec::new();
    for (k, v) in records {
        let body = format!(" {k}={v}\n");
        let mut len = body.len() + 1;
        while format!("{len}").len() + body.len() != len {
            len += 1;
        }
        out.extend_from_slice(format!("{len}{body}").as_bytes());
    }
    out
}

/// `data` gzip-compressed (fast level).
pub fn gzip(data: &[u8]) -> Vec<u8> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, data).unwrap();
    gz.finish().unwrap()
}

/// `data` as a gzip member of stored (uncompressed) deflate blocks, with
/// its CRC-32 and length: allocates only the output.
pub fn gzip_stored(data: &[u8]) -> Vec<u8> {
    let blocks = data.len().div_ceil(65535).max(1);
    let mut out = Vec::with_capacity(18 + data.len() + 5 * blocks);
    out.extend_from_slice(&[0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0xff]);
    let mut chunks = data.chunks(65535).peekable();
    if data.is_empty() {
        out.extend_from_slice(&[1, 0, 0, 0xff, 0xff]);
    }
    while let Some(c) = chunks.next() {
        out.push(u8::from(chunks.peek().is_none()));
        let n = c.len() as u16;
        out.extend_from_slice(&n.to_le_bytes());
        out.extend_from_slice(&(!n).to_le_bytes());
        out.extend_from_slice(c);
    }
    let mut crc = flate2::Crc::new();
    crc.update(data);
    out.extend_from_slice(&crc.sum().to_le_bytes());
    out.extend_from_slice(&(data.len() as u32).to_le_bytes());
    out
}
