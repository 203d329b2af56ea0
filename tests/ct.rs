//! Tests of the CT data layer (`metabezier::ct`) on synthetic data, on the
//! vendored ProMED CT 0051 extract and on pydicom's CT_small.dcm.

mod common;
mod ct_inputs;
use common::oblique_axes;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use metabezier::ct::*;
use metabezier::geometry::Point;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The vendored extract, read once per test binary.
fn ct0051() -> &'static Volume {
    static V: OnceLock<Volume> = OnceLock::new();
    V.get_or_init(|| read_inv3(&root().join(CT0051_PATH)).expect("vendored CT"))
}

/// Vendored slice index of original slice `z`.
fn vz(z: usize) -> usize {
    z - CT0051_FIRST_Z
}

// ---------------------------------------------------------------- readers

#[test]
fn vendored_inv3_has_the_documented_shape_spacing_and_values() {
    let v = ct0051();
    assert_eq!((v.nz, v.ny, v.nx), (61, 256, 256));
    assert_eq!(v.spacing.x, 0.9570312);
    assert_eq!(v.spacing.y, 0.9570312);
    assert_eq!(v.spacing.z, 1.5);
    // Fingerprint computed independently (Python, from matrix.dat slices 40..=100).
    let sum: i64 = v.data().iter().map(|&x| x as i64).sum();
    assert_eq!(sum, -2_345_383_034);
    let (lo, hi) = v
        .data()
        .iter()
        .fold((i16::MAX, i16::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert_eq!((lo, hi), (-1024, 1746));
    assert_eq!(v.get(vz(64), 196, 111), 653);
    assert_eq!(v.get(vz(72), 100, 30), -997);
    assert_eq!(v.slice(vz(89)).get(128, 128), 40);
}

#[test]
fn inv3_round_trip_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.inv3");
    let v = ct_inputs::small_volume();
    write_inv3(&p, &v, "test & <name>").unwrap();
    // An .inv3 holds no origin or axes: it reads back at the identity frame
    // and says where the frame came from.
    let inv3_frame = FrameSource::Inv3 { orientation: None };
    let expected = v
        .clone()
        .with_frame([0.0; 3], IDENTITY_AXES, inv3_frame)
        .unwrap();
    assert_eq!(read_inv3(&p).unwrap(), expected);

    // Truncated file: the error names the file and says truncated/corrupt.
    let bytes = std::fs::read(&p).unwrap();
    let t = dir.path().join("trunc.inv3");
    std::fs::write(&t, &bytes[..bytes.len() / 2]).unwrap();
    let e = read_inv3(&t).unwrap_err();
    assert!(matches!(e, CtError::Inv3 { .. }), "{e}");
    assert!(e.to_string().contains("trunc.inv3"), "{e}");
    assert!(e.to_string().contains("truncated or corrupt"), "{e}");

    // Not gzip at all.
    let g = dir.path().join("garbage.inv3");
    std::fs::write(&g, b"this is not a gzip stream").unwrap();
    assert!(matches!(read_inv3(&g).unwrap_err(), CtError::Inv3 { .. }));

    // Wrong byte count: a plist that declares one more slice.
    let mut bigger = v.clone();
    bigger = Volume::new(
        bigger.nx,
        bigger.ny,
        bigger.nz + 1,
        bigger.spacing,
        bigger.origin,
        [bigger.data(), &vec![0i16; bigger.nx * bigger.ny][..]].concat(),
    )
    .unwrap();
    let plist = metabezier::ct::inv3::inv3_plist(&bigger, "x");
    let mut matrix = Vec::new();
    for x in v.data() {
        matrix.extend_from_slice(&x.to_le_bytes());
    }
    let w = dir.path().join("wrong.inv3");
    write_tar_gz(
        &w,
        &[("main.plist", plist.as_bytes()), ("matrix.dat", &matrix)],
    );
    match read_inv3(&w).unwrap_err() {
        CtError::ByteCount {
            path,
            expected,
            found,
        } => {
            assert_eq!(path, w);
            assert_eq!(expected, 7 * 5 * 4 * 2);
            assert_eq!(found, 7 * 5 * 3 * 2);
        }
        e => panic!("expected ByteCount, got {e}"),
    }
    // Missing matrix member.
    let m = dir.path().join("nomatrix.inv3");
    write_tar_gz(&m, &[("main.plist", plist.as_bytes())]);
    let e = read_inv3(&m).unwrap_err();
    assert!(e.to_string().contains("no matrix.dat"), "{e}");
}

fn write_tar_gz(path: &Path, members: &[(&str, &[u8])]) {
    let mut b = tar::Builder::new(Vec::new());
    for (name, bytes) in members {
        let mut h = tar::Header::new_ustar();
        h.set_size(bytes.len() as u64);
        h.set_mode(0o644);
        b.append_data(&mut h, name, *bytes).unwrap();
    }
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, &b.into_inner().unwrap()).unwrap();
    std::fs::write(path, gz.finish().unwrap()).unwrap();
}

#[test]
fn dicom_reads_pydicom_ct_small() {
    let p = root().join("data/dicom/CT_small.dcm");
    let s = read_dicom_file(&p).unwrap();
    assert_eq!((s.rows, s.cols), (128, 128));
    assert_eq!((s.row_spacing, s.col_spacing), (0.661468, 0.661468));
    assert_eq!(s.position, Some([-158.135803, -179.035797, -75.699997]));
    // Reference values read with pydicom 3.0.2 (raw − 1024, RescaleIntercept −1024).
    assert_eq!(s.hu[0], 175 - 1024);
    assert_eq!(s.hu[64 * 128 + 64], 1928 - 1024);
    assert_eq!(s.hu[127 * 128 + 127], 909 - 1024);
    assert_eq!(s.hu[10 * 128 + 100], 1227 - 1024);
    let sum: i64 = s.hu.iter().map(|&x| x as i64).sum();
    assert_eq!(sum, 14_826_310 - 1024 * 128 * 128);
    let v = read_dicom_series(&[p]).unwrap();
    assert_eq!((v.nx, v.ny, v.nz), (128, 128, 1));
    assert_eq!(v.spacing.z, 5.0); // SliceThickness
}

#[test]
fn dicom_round_trip_of_ct_slices_is_bit_exact() {
    let v = ct0051();
    let z0 = vz(62);
    let sub = v.sub_z(z0, z0 + 4);
    let dir = tempfile::tempdir().unwrap();
    let mut paths = write_dicom_series(dir.path(), &sub, 0..4, "ct0051-test").unwrap();
    paths.reverse(); // order must come from the positions, not the file list
    let back = read_dicom_series(&paths).unwrap();
    assert_eq!((back.nx, back.ny, back.nz), (256, 256, 4));
    assert_eq!(back.data(), sub.data());
    assert_eq!(back.spacing.x, sub.spacing.x);
    assert_eq!(back.spacing.y, sub.spacing.y);
    assert!((back.spacing.z - 1.5).abs() < 1e-9);
    assert_eq!(back.origin, sub.origin);
    let again = read_dicom_dir(dir.path()).unwrap();
    assert_eq!(again.data(), sub.data());
}

#[test]
fn dicom_errors_name_the_file() {
    let v = ct_inputs::small_volume();
    let dir = tempfile::tempdir().unwrap();
    let paths = write_dicom_series(dir.path(), &v, 0..3, "s").unwrap();

    // Corrupt: truncated in the pixel data.
    let bytes = std::fs::read(&paths[0]).unwrap();
    let c = dir.path().join("corrupt.dcm");
    std::fs::write(&c, &bytes[..bytes.len() - 20]).unwrap();
    let e = read_dicom_file(&c).unwrap_err();
    assert!(matches!(e, CtError::Dicom { .. }), "{e}");
    assert!(e.to_string().contains("corrupt.dcm"), "{e}");
    let n = dir.path().join("notdicom.dcm");
    std::fs::write(&n, b"hello").unwrap();
    assert!(matches!(
        read_dicom_file(&n).unwrap_err(),
        CtError::Dicom { .. }
    ));

    // Uneven slice gap: drop the middle slice of a 4-slice series.
    let v4 = Volume::new(7, 5, 4, v.spacing, v.origin, vec![0; 7 * 5 * 4]).unwrap();
    let d2 = tempfile::tempdir().unwrap();
    let p4 = write_dicom_series(d2.path(), &v4, 0..4, "g").unwrap();
    let e = read_dicom_series(&[p4[0].clone(), p4[1].clone(), p4[3].clone()]).unwrap_err();
    match &e {
        CtError::SpacingMismatch { path, axis, .. } => {
            assert_eq!(path, &p4[3]);
            assert_eq!(*axis, "slice gap");
        }
        e => panic!("expected SpacingMismatch, got {e}"),
    }
    assert!(e.to_string().contains("mismatched slice spacing"), "{e}");

    // Different pixel spacing.
    let mut other = v.clone();
    other.spacing.x = 0.6;
    other.origin[2] = 100.0;
    let d3 = tempfile::tempdir().unwrap();
    let q = write_dicom_series(d3.path(), &other, 0..1, "o").unwrap();
    let e = read_dicom_series(&[paths[0].clone(), q[0].clone()]).unwrap_err();
    assert!(
        matches!(&e, CtError::SpacingMismatch { axis: "column", .. }),
        "{e}"
    );

    // Different size.
    let small = Volume::new(6, 5, 1, v.spacing, [0.0, 0.0, 50.0], vec![0; 30]).unwrap();
    let d4 = tempfile::tempdir().unwrap();
    let r = write_dicom_series(d4.path(), &small, 0..1, "z").unwrap();
    let e = read_dicom_series(&[paths[0].clone(), r[0].clone()]).unwrap_err();
    match e {
        CtError::SizeMismatch {
            path,
            expected,
            found,
        } => {
            assert_eq!(path, r[0]);
            assert_eq!(expected, (5, 7));
            assert_eq!(found, (5, 6));
        }
        e => panic!("expected SizeMismatch, got {e}"),
    }
}

// ---------------------------------------------------------------- hardened readers

use ct_inputs::{element, item, long_element, short_element, with_syntax, with_value, without};

/// The error text of reading `bytes` as the DICOM file `slice.dcm`.
fn dicom_error(bytes: &[u8]) -> String {
    let (_dir, path) = temp_file("slice.dcm", bytes);
    read_dicom_file(&path).unwrap_err().to_string()
}

/// `bytes` written to `name` in a fresh directory.
fn temp_file(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

#[test]
fn dicom_lengths_past_the_end_name_the_tag_offset_and_bytes() {
    // Issue 31: a PixelData length of 0xFFFFFFF0 in a 39 KB slice took
    // 4.1 GB before failing. Now the header is refused as read.
    let b = ct_inputs::ct_small();
    let px = element(&b, (0x7FE0, 0x0010));
    let mut m = b.clone();
    m[px.at + 8..px.at + 12].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    let e = dicom_error(&m);
    let remaining = b.len() - px.at - 12;
    assert!(
        e.contains("slice.dcm")
            && e.contains(&format!(
                "element (7FE0,0010) PixelData at byte {} declares 4294967280 bytes, but only {remaining} remain in the file",
                px.at
            )),
        "{e}"
    );
    // A short-VR element (PixelSpacing, DS) whose 16-bit length runs past the end.
    let sp = element(&b, (0x0028, 0x0030));
    let cut = &b[..sp.at + 8 + 4];
    let e = dicom_error(cut);
    assert!(
        e.contains(&format!(
            "element (0028,0030) PixelSpacing at byte {} declares 18 bytes, but only 4 remain in the file",
            sp.at
        )),
        "{e}"
    );
    // The file meta information's group length, and a header cut short.
    let mut g = b.clone();
    g[140..144].copy_from_slice(&0x7FFF_FFFFu32.to_le_bytes());
    let e = dicom_error(&g);
    assert!(
        e.contains("element (0002,0000) FileMetaInformationGroupLength at byte 132 declares 2147483647 bytes"),
        "{e}"
    );
    let e = dicom_error(&b[..px.at + 10]);
    assert!(
        e.contains(&format!(
            "truncated element header at byte {}: it needs 12 bytes, 10 remain",
            px.at
        )),
        "{e}"
    );
    // PixelData that fits the file but not the image: 128x128 at 16 bits is 32768 bytes.
    let short = with_value(&b, (0x7FE0, 0x0010), &b[px.value.start..px.value.end - 2]);
    let e = dicom_error(&short);
    assert!(
        e.contains(&format!(
            "PixelData holds 32766 bytes, 128x128 at 16 bits allocated needs 32768 (1 sample per pixel; element (7FE0,0010) at byte {})",
            px.at
        )),
        "{e}"
    );
}

#[test]
fn dicom_files_above_the_size_limit_are_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("huge.dcm");
    let f = std::fs::File::create(&p).unwrap();
    let len = metabezier::ct::dicom::MAX_DICOM_FILE_BYTES + 1;
    f.set_len(len).unwrap(); // sparse: nothing is written
    let e = read_dicom_file(&p).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}: corrupt or unsupported DICOM: the file is {len} bytes, more than the 268435456-byte limit for one slice (MAX_DICOM_FILE_BYTES)",
            p.display()
        )
    );
}

#[test]
fn dicom_unsupported_transfer_syntaxes_are_named_with_the_supported_ones() {
    // Issue 31: a big-endian slice took 1.3 GB; the syntax is now refused
    // before the data set is read, by name.
    let b = ct_inputs::ct_small();
    for (uid, name) in [
        ("1.2.840.10008.1.2.2", "Explicit VR Big Endian"),
        (
            "1.2.840.10008.1.2.1.99",
            "Deflated Explicit VR Little Endian",
        ),
        ("1.2.840.10008.1.2.4.50", "JPEG Baseline"),
    ] {
        let e = dicom_error(&with_syntax(&b, uid));
        assert!(
            e.contains(&format!("transfer syntax {uid} ({name}) is not supported"))
                && e.contains("1.2.840.10008.1.2 Implicit VR Little Endian")
                && e.contains("1.2.840.10008.1.2.1 Explicit VR Little Endian"),
            "{e}"
        );
    }
    let e = dicom_error(&without(&b, &[(0x0002, 0x0010)]));
    assert!(e.contains("no TransferSyntaxUID (0002,0010)"), "{e}");
    let e = dicom_error(&b"not dicom at all".repeat(20));
    assert!(e.contains("not a DICOM file: no \"DICM\""), "{e}");
}

#[test]
fn dicom_implicit_vr_reads_like_explicit_and_is_checked_the_same() {
    let explicit = read_dicom_file(&root().join("data/dicom/CT_small.dcm")).unwrap();
    let imp = ct_inputs::ct_small_implicit();
    let (_dir, path) = temp_file("implicit.dcm", &imp);
    let s = read_dicom_file(&path).unwrap();
    assert_eq!(s.hu, explicit.hu);
    assert_eq!(s.position, explicit.position);
    assert_eq!((s.row_spacing, s.col_spacing), (0.661468, 0.661468));
    // The PixelData header of the implicit file: tag, then a 32-bit length.
    let at = imp
        .windows(8)
        .rposition(|w| w == [0xE0, 0x7F, 0x10, 0x00, 0x00, 0x80, 0x00, 0x00])
        .unwrap();
    let mut m = imp.clone();
    m[at + 4..at + 8].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    let e = dicom_error(&m);
    assert!(
        e.contains(&format!(
            "element (7FE0,0010) PixelData at byte {at} declares 4294967280 bytes"
        )),
        "{e}"
    );
}

#[test]
fn dicom_sequences_are_walked_and_their_lengths_checked() {
    let b = ct_inputs::ct_small();
    let original = read_dicom_file(&root().join("data/dicom/CT_small.dcm")).unwrap();
    let at = element(&b, (0x7FE0, 0x0010)).at;
    let inner = short_element((0x0008, 0x1150), b"UI", b"1.2.3\0");
    // A sequence of undefined length holding an item of undefined length and
    // one of defined length: read through, the image unchanged.
    let seq = [
        long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[]),
        item(0xE000, u32::MAX),
        inner.clone(),
        item(0xE00D, 0),
        item(0xE000, inner.len() as u32),
        inner.clone(),
        item(0xE0DD, 0),
    ]
    .concat();
    let with_seq = ct_inputs::insert_before(&b, (0x7FE0, 0x0010), &seq);
    let (_dir, path) = temp_file("seq.dcm", &with_seq);
    assert_eq!(read_dicom_file(&path).unwrap().hu, original.hu);
    // An element that overruns its item of defined length.
    let mut long_inner = inner.clone();
    long_inner[6..8].copy_from_slice(&40u16.to_le_bytes());
    let seq = [
        long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[]),
        item(0xE000, inner.len() as u32),
        long_inner,
        item(0xE0DD, 0),
    ]
    .concat();
    let e = dicom_error(&ct_inputs::insert_before(&b, (0x7FE0, 0x0010), &seq));
    assert!(
        e.contains(&format!(
            "element (0008,1150) ReferencedSOPClassUID at byte {} declares 40 bytes, but only 6 remain in the sequence item",
            at + 12 + 8
        )),
        "{e}"
    );
    // Something other than an item in a sequence; a sequence never closed.
    let seq = [
        long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[]),
        inner.clone(),
    ]
    .concat();
    let e = dicom_error(&ct_inputs::insert_before(&b, (0x7FE0, 0x0010), &seq));
    assert!(
        e.contains(&format!(
            "sequence (0008,1140) ReferencedImageSequence: expected an item (FFFE,E000) or the sequence delimiter at byte {}, found (0008,1150)",
            at + 12
        )),
        "{e}"
    );
    let open = [
        &b[..at],
        &long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[])[..],
        &item(0xE000, u32::MAX),
    ]
    .concat();
    let e = dicom_error(&open);
    assert!(
        e.contains(&format!(
            "item (FFFE,E000) at byte {} has an undefined length and no delimiter before its end",
            at + 12
        )),
        "{e}"
    );
    // Sequences nested one deeper than the limit.
    let depth = metabezier::ct::dicom::MAX_DICOM_NESTING + 1;
    let mut nest = Vec::new();
    for _ in 0..depth {
        nest.extend(long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[]));
        nest.extend(item(0xE000, u32::MAX));
    }
    for _ in 0..depth {
        nest.extend(item(0xE00D, 0));
        nest.extend(item(0xE0DD, 0));
    }
    let e = dicom_error(&ct_inputs::insert_before(&b, (0x7FE0, 0x0010), &nest));
    let deepest = at + (depth - 1) * 20;
    assert!(
        e.contains(&format!(
            "sequence at byte {deepest} is nested more than 32 deep (MAX_DICOM_NESTING)"
        )),
        "{e}"
    );
    // An undefined length on an element that is not a sequence.
    let e = dicom_error(&ct_inputs::insert_before(
        &b,
        (0x7FE0, 0x0010),
        &long_element((0x0009, 0x0010), b"OB", u32::MAX, &[]),
    ));
    assert!(
        e.contains("has an undefined length, which only a sequence (SQ) may have"),
        "{e}"
    );
}

/// Slice `z` of the 7×5×3 test volume as DICOM bytes.
fn slice_bytes(z: usize) -> Vec<u8> {
    metabezier::ct::dicom::dicom_slice_bytes(&ct_inputs::small_volume(), z, "hard").unwrap()
}

#[test]
fn dicom_rescale_slope_must_be_finite_and_non_zero() {
    // Issue 31: RescaleSlope = 0 passed the reader (every HU = intercept).
    let b = slice_bytes(0);
    let at = element(&b, (0x0028, 0x1053)).at;
    for (value, shown) in [(&b"0 "[..], "0 "), (b"-0", "-0"), (b"inf ", "inf ")] {
        let e = dicom_error(&with_value(&b, (0x0028, 0x1053), value));
        assert!(
            e.contains("slice.dcm")
                && e.contains(&format!(
                    "RescaleSlope (0028,1053) at byte {at} is {shown:?}: expected a finite, non-zero number"
                )),
            "{e}"
        );
    }
    let at = element(&b, (0x0028, 0x1052)).at;
    let e = dicom_error(&with_value(&b, (0x0028, 0x1052), b"NaN "));
    assert!(
        e.contains(&format!(
            "RescaleIntercept (0028,1052) at byte {at} is \"NaN \": expected a finite number"
        )),
        "{e}"
    );
    let at = element(&b, (0x0020, 0x0032)).at;
    let e = dicom_error(&with_value(&b, (0x0020, 0x0032), b"1\\2\\nan "));
    assert!(
        e.contains(&format!(
            "ImagePositionPatient (0020,0032) at byte {at} is \"1\\\\2\\\\nan \": expected three finite numbers"
        )),
        "{e}"
    );
    // A slope of 2 is used.
    let (_dir, p) = temp_file("two.dcm", &with_value(&b, (0x0028, 0x1053), b"2 "));
    let s = read_dicom_file(&p).unwrap();
    let one = {
        let (_d, q) = temp_file("one.dcm", &b);
        read_dicom_file(&q).unwrap()
    };
    for (a, o) in s.hu.iter().zip(&one.hu) {
        assert_eq!(
            *a as i32,
            ((*o as i32 + 1024) * 2 - 1024).clamp(-32768, 32767)
        );
    }
}

#[test]
fn dicom_series_without_positions_names_the_slice_and_why() {
    // Issue 31: slices without ImagePositionPatient said "slice gap spacing
    // 0 mm differs from the series' 0 mm".
    let dir = tempfile::tempdir().unwrap();
    let bare: Vec<PathBuf> = (0..3)
        .map(|z| {
            let b = without(
                &slice_bytes(z),
                &[(0x0020, 0x0032), (0x0020, 0x1041), (0x0020, 0x0013)],
            );
            let p = dir.path().join(format!("bare{z}.dcm"));
            std::fs::write(&p, b).unwrap();
            p
        })
        .collect();
    let e = read_dicom_series(&bare).unwrap_err();
    assert!(
        matches!(&e, CtError::MissingPosition { path, .. } if *path == bare[0]),
        "{e}"
    );
    assert_eq!(
        e.to_string(),
        format!(
            "{}: no ImagePositionPatient (0020,0032) or SliceLocation (0020,1041): the position of every slice is needed to order and space the 3 slices of the series",
            bare[0].display()
        )
    );
    // InstanceNumber orders but does not space: without a position the
    // series is refused rather than spaced 1 mm apart.
    let numbered: Vec<PathBuf> = (0..3)
        .map(|z| {
            let b = without(&slice_bytes(z), &[(0x0020, 0x0032), (0x0020, 0x1041)]);
            let p = dir.path().join(format!("numbered{z}.dcm"));
            std::fs::write(&p, b).unwrap();
            p
        })
        .collect();
    assert!(matches!(
        read_dicom_series(&numbered).unwrap_err(),
        CtError::MissingPosition { .. }
    ));
    // One slice without a position among slices with one.
    let mixed: Vec<PathBuf> = (0..3)
        .map(|z| {
            let b = if z == 1 {
                without(&slice_bytes(z), &[(0x0020, 0x0032)])
            } else {
                slice_bytes(z)
            };
            let p = dir.path().join(format!("mixed{z}.dcm"));
            std::fs::write(&p, b).unwrap();
            p
        })
        .collect();
    let e = read_dicom_series(&mixed).unwrap_err().to_string();
    assert!(
        e.starts_with(&format!(
            "{}: no ImagePositionPatient (0020,0032): the position",
            mixed[1].display()
        )),
        "{e}"
    );
    // SliceLocation alone still orders and spaces a series; one slice alone
    // needs no position.
    let located: Vec<PathBuf> = (0..3)
        .map(|z| {
            let b = without(&slice_bytes(z), &[(0x0020, 0x0032), (0x0020, 0x0037)]);
            let p = dir.path().join(format!("located{z}.dcm"));
            std::fs::write(&p, b).unwrap();
            p
        })
        .collect();
    let v = read_dicom_series(&located).unwrap();
    assert_eq!(v.nz, 3);
    assert!((v.spacing.z - 2.0).abs() < 1e-9);
    assert_eq!(read_dicom_series(&bare[..1]).unwrap().nz, 1);
}

#[test]
fn dicom_series_with_two_slices_at_one_position_names_both() {
    let dir = tempfile::tempdir().unwrap();
    let paths = write_dicom_series(dir.path(), &ct_inputs::small_volume(), 0..3, "dup").unwrap();
    let copy = dir.path().join("copy.dcm");
    std::fs::copy(&paths[1], &copy).unwrap();
    let e = read_dicom_series(&[
        paths[0].clone(),
        paths[1].clone(),
        copy.clone(),
        paths[2].clone(),
    ])
    .unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, CtError::DuplicatePosition { .. }), "{text}");
    assert!(
        text.contains("same slice position as") && text.contains("2 mm along the slice normal"),
        "{text}"
    );
    assert!(
        text.contains(&*copy.display().to_string())
            && text.contains(&*paths[1].display().to_string()),
        "{text}"
    );
}

/// The error text of reading `bytes` as the `.inv3` `p.inv3`.
fn inv3_error(bytes: &[u8]) -> String {
    let (_dir, path) = temp_file("p.inv3", bytes);
    read_inv3(&path).unwrap_err().to_string()
}

#[test]
fn inv3_tar_headers_and_the_gzip_trailer_are_checked() {
    let v = ct_inputs::small_volume();
    let plist = metabezier::ct::inv3::inv3_plist(&v, "t");
    let matrix = ct_inputs::matrix_bytes(&v);
    let good = ct_inputs::tar(&[
        ("main.plist", b'0', plist.as_bytes()),
        ("matrix.dat", b'0', &matrix),
    ]);
    let (_d, p) = temp_file("ok.inv3", &ct_inputs::gzip(&good));
    assert_eq!(read_inv3(&p).unwrap().data(), v.data());
    let second = 512 * (1 + plist.len().div_ceil(512));
    // A header whose checksum disagrees (one byte of the name changed).
    let mut t = good.clone();
    t[second] = b'n';
    let e = inv3_error(&ct_inputs::gzip(&t));
    assert!(
        e.contains("p.inv3")
            && e.contains(&format!("tar header at byte {second} fails its checksum")),
        "{e}"
    );
    // A size beyond what the archive holds (checksum fixed).
    let mut t = good.clone();
    t[second + 124..second + 136].copy_from_slice(format!("{:011o}\0", 1u64 << 30).as_bytes());
    ct_inputs::set_tar_checksum(&mut t[second..second + 512]);
    let e = inv3_error(&ct_inputs::gzip(&t));
    let remaining = good.len() - second - 512;
    assert!(
        e.contains(&format!(
            "member matrix.dat declares 1073741824 bytes (tar header at byte {second}), but only {remaining} of the tar's {} bytes (the gzip trailer's ISIZE) remain",
            good.len()
        )),
        "{e}"
    );
    // Data after the gzip stream.
    let mut z = ct_inputs::gzip(&good);
    z.extend_from_slice(b"junk");
    let e = inv3_error(&z);
    assert!(e.contains("data follows the end of the gzip stream"), "{e}");
    // A trailer that declares more than deflate can make of the file, or
    // a wrong but plausible length: the stream's own check says so.
    for isize in [0xFFFF_FFF0u32, good.len() as u32 + 512, 512] {
        let mut z = ct_inputs::gzip(&good);
        let n = z.len();
        z[n - 4..].copy_from_slice(&isize.to_le_bytes());
        let e = inv3_error(&z);
        assert!(
            e.contains("gzip stream fails its integrity check")
                || e.contains(&format!(
                    "the gzip stream is corrupt or truncated at uncompressed byte {}",
                    good.len()
                )),
            "{e}"
        );
    }
}

#[test]
fn inv3_members_are_found_in_any_order_and_ambiguity_is_refused() {
    let v = ct_inputs::small_volume();
    let plist = metabezier::ct::inv3::inv3_plist(&v, "t");
    let matrix = ct_inputs::matrix_bytes(&v);
    let read = |t: &[u8]| {
        let (_d, p) = temp_file("o.inv3", &ct_inputs::gzip(t));
        read_inv3(&p)
    };
    // InVesalius's own order (matrix.dat first), under a directory, with
    // Python-style pax headers and a mask member.
    let pax = ct_inputs::pax(&[("mtime", "1700000000.25"), ("path", "tmpab/matrix.dat")]);
    let t = ct_inputs::tar(&[
        ("././@PaxHeader", b'x', &pax),
        ("tmpab/m", b'0', &matrix),
        ("tmpab/mask_0.dat", b'0', &[7u8; 3000]),
        ("tmpab/main.plist", b'0', plist.as_bytes()),
    ]);
    assert_eq!(read(&t).unwrap().data(), v.data());
    // A matrix named otherwise, before the plist: found by a second pass.
    let renamed = plist.replace("matrix.dat", "volume.raw");
    let t = ct_inputs::tar(&[
        ("volume.raw", b'0', &matrix),
        ("main.plist", b'0', renamed.as_bytes()),
    ]);
    assert_eq!(read(&t).unwrap().data(), v.data());
    // ... and its absence named.
    let t = ct_inputs::tar(&[("main.plist", b'0', renamed.as_bytes())]);
    assert!(read(&t)
        .unwrap_err()
        .to_string()
        .contains("no volume.raw member"));
    // Two plists: which one describes the volume?
    let t = ct_inputs::tar(&[
        ("main.plist", b'0', plist.as_bytes()),
        ("matrix.dat", b'0', &matrix),
        ("x/main.plist", b'0', plist.as_bytes()),
    ]);
    let second = 512 * (2 + plist.len().div_ceil(512) + matrix.len().div_ceil(512));
    let e = read(&t).unwrap_err().to_string();
    assert!(
        e.contains(&format!(
            "two main.plist members (tar headers at bytes 0 and {second})"
        )),
        "{e}"
    );
    // A matrix whose size disagrees with the shape is refused at its header.
    let t = ct_inputs::tar(&[
        ("main.plist", b'0', plist.as_bytes()),
        ("matrix.dat", b'0', &matrix[..matrix.len() - 2]),
    ]);
    let e = read(&t).unwrap_err();
    assert!(
        matches!(
            e,
            CtError::ByteCount {
                expected: 210,
                found: 208,
                ..
            }
        ),
        "{e}"
    );
    // A plist above MAX_PLIST_BYTES, a long name above MAX_TAR_EXTENSION_BYTES.
    let limit = metabezier::ct::inv3::MAX_PLIST_BYTES;
    let big = plist.replacen(
        "<plist",
        &format!("<!--{}--><plist", "x".repeat(limit as usize)),
        1,
    );
    let t = ct_inputs::tar(&[("main.plist", b'0', big.as_bytes())]);
    let e = read(&t).unwrap_err().to_string();
    assert!(
        e.contains(&format!(
            "main.plist declares {} bytes, more than the {limit}-byte limit (MAX_PLIST_BYTES)",
            big.len()
        )),
        "{e}"
    );
    let name = "d/".repeat(40_000);
    let t = ct_inputs::tar(&[
        ("././@LongLink", b'L', name.as_bytes()),
        ("x", b'0', b"x"),
        ("main.plist", b'0', plist.as_bytes()),
    ]);
    let e = read(&t).unwrap_err().to_string();
    assert!(
        e.contains("GNU long name at byte 0 declares 80000 bytes, more than the 65536-byte limit (MAX_TAR_EXTENSION_BYTES)"),
        "{e}"
    );
}

// ---------------------------------------------------------------- bone, defect

/// Tolerance of the automatic end points: 3 pixels (Chebyshev).
const END_TOL_PX: usize = 3;

fn px_dist(a: (usize, usize), b: (usize, usize)) -> usize {
    a.0.abs_diff(b.0).max(a.1.abs_diff(b.1))
}

#[test]
fn bone_mask_drops_the_head_holder() {
    let v = ct0051();
    for z in [64, 72, 80, 89] {
        let s = v.slice(vz(z));
        let t = threshold_slice(&s, BONE_THRESHOLD_HU);
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        // The holder arc runs along the top rows of the image, far from the head.
        let top = |mask: &Mask2| {
            (0..15)
                .flat_map(|r| (0..256).map(move |c| (r, c)))
                .filter(|&(r, c)| mask.get(r, c))
                .count()
        };
        assert!(top(&t) >= 20, "z={z}: the threshold should see the holder");
        assert_eq!(top(&m), 0, "z={z}: the holder must drop out");
        assert!(m.count() > 2500 && m.count() < t.count(), "z={z}");
    }
    // Same in 3D (26-connected) on a few slices around the defect.
    let sub = v.sub_z(vz(60), vz(92));
    let m3 = bone_mask_volume(&sub, BONE_THRESHOLD_HU).unwrap();
    for z in 0..sub.nz {
        let m2 = m3.slice(z);
        assert!(
            (0..15).all(|r| (0..256).all(|c| !m2.get(r, c))),
            "3D, slice {z}"
        );
        assert!(m2.count() > 2500, "3D, slice {z}: skull kept");
    }
    // No bone above an impossible threshold.
    let e = bone_mask_slice(&v.slice(0), 4000).unwrap_err();
    assert!(
        matches!(
            e,
            CtError::NoBone {
                slice: 0,
                threshold: 4000
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("no bone"), "{e}");
}

#[test]
fn defect_ends_match_the_measured_points() {
    let v = ct0051();
    for (z, p, q) in CT0051_MEASURED_ENDS {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default())
            .unwrap_or_else(|| panic!("z={z}: defect not found"));
        // Unordered pair.
        let err = (px_dist(d.a, p).max(px_dist(d.b, q))).min(px_dist(d.a, q).max(px_dist(d.b, p)));
        eprintln!(
            "z={z}: A={:?} B={:?} reference {p:?} {q:?}, error {err} px, width {:.1} mm",
            d.a,
            d.b,
            d.width_mm()
        );
        assert!(
            err <= END_TOL_PX,
            "z={z}: {:?} {:?} vs {p:?} {q:?}",
            d.a,
            d.b
        );
        // A and B lie on the bone, and the mm positions agree with the pixels.
        assert!(m.get(d.a.0, d.a.1) && m.get(d.b.0, d.b.1));
        assert_eq!(d.a_mm, s.to_mm(d.a.0 as f64, d.a.1 as f64));
    }
}

#[test]
fn defect_spans_the_documented_slices_and_intact_slices_have_none() {
    let v = ct0051();
    let params = DefectParams::default();
    let found = |z: usize| {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        detect_defect(&m, s.sx, s.sy, &params)
    };
    for z in 88..=90 {
        assert_eq!(found(z), None, "z={z} is intact");
    }
    // The gap narrows from ~25 mm (z=64) to ~12 mm (z=80), on one side.
    let w64 = found(64).unwrap().width_mm();
    let w72 = found(72).unwrap().width_mm();
    let w80 = found(80).unwrap().width_mm();
    assert!((22.0..28.0).contains(&w64), "{w64}");
    assert!((19.0..25.0).contains(&w72), "{w72}");
    assert!((10.0..16.0).contains(&w80), "{w80}");
    for z in (56..=84).step_by(4) {
        let d = found(z).unwrap_or_else(|| panic!("z={z}: no defect"));
        // Left-posterior side of the image: columns < 128, rows > 150.
        assert!(
            d.a.1 < 128 && d.b.1 < 128 && d.a.0 > 150 && d.b.0 > 150,
            "z={z}: {d:?}"
        );
    }
}

#[test]
fn defect_detection_on_a_synthetic_ring() {
    // Ring of radii 40..50 px around (100, 100) with a 30° gap centred at 90°
    // (straight down in the image); ends are known in closed form.
    let ring = |gap: bool| {
        Mask2::from_fn(200, 200, |r, c| {
            let (dy, dx) = (r as f64 - 100.0, c as f64 - 100.0);
            let rad = dx.hypot(dy);
            let ang = dy.atan2(dx).to_degrees();
            (40.0..=50.0).contains(&rad) && !(gap && (75.0..=105.0).contains(&ang))
        })
    };
    assert_eq!(
        detect_defect(&ring(false), 1.0, 1.0, &DefectParams::default()),
        None
    );
    let d = detect_defect(&ring(true), 1.0, 1.0, &DefectParams::default()).unwrap();
    // The narrowest chord joins the inner corners at radius 40, angles 75° and 105°.
    let expect_w = 2.0 * 40.0 * (15f64).to_radians().sin();
    assert!(
        (d.width_mm() - expect_w).abs() < 2.5,
        "{} vs {expect_w}",
        d.width_mm()
    );
    assert!((d.gap_width_deg - 30.0).abs() < 8.0, "{}", d.gap_width_deg);
    assert!(d.a.0 > 100 && d.b.0 > 100);
}

// ---------------------------------------------------------------- contours

#[test]
fn marching_squares_on_a_disc_is_subpixel_and_oriented() {
    // f = R − distance from the centre (a cone): the 0-level set is the circle
    // of radius R; linear interpolation along edges is exact to O(h²/R).
    let (n, r0, sx, sy) = (100usize, 20.3, 0.5, 0.75);
    let (cy, cx) = (48.7, 50.2);
    let f: Vec<f64> = (0..n * n)
        .map(|i| {
            let (r, c) = ((i / n) as f64, (i % n) as f64);
            // Distance in mm, so the contour is a true circle in mm.
            r0 - ((c - cx) * sx).hypot((r - cy) * sy)
        })
        .collect();
    let loops = marching_squares(&f, n, n, 0.0, sx, sy);
    assert_eq!(loops.len(), 1);
    let l = &loops[0];
    assert!(l.closed);
    let c = Point::new(cx * sx, cy * sy);
    for p in &l.points {
        assert!(
            (p.distance(c) - r0).abs() < 0.02,
            "{} at {:?} px {:?}",
            p.distance(c),
            p,
            (p.y / sy, p.x / sx)
        );
    }
    let area = l.signed_area();
    assert!(area > 0.0, "outer boundary has positive area");
    assert!(
        (area - std::f64::consts::PI * r0 * r0).abs() / area < 2e-3,
        "{area}"
    );
    // The complement: a hole, negative area (inside on the left).
    let g: Vec<f64> = f.iter().map(|v| -v).collect();
    let holes = marching_squares(&g, n, n, 0.0, sx, sy);
    let hole = holes.iter().find(|l| l.signed_area() < 0.0).unwrap();
    assert!((hole.signed_area() + area).abs() < 1e-6);
}

#[test]
fn saddles_join_diagonal_bone_pixels() {
    // Two pixels touching at a corner are one 8-connected component: one loop.
    let m = Mask2::from_fn(4, 4, |r, c| (r, c) == (1, 1) || (r, c) == (2, 2));
    let f: Vec<f64> = m.data.iter().map(|&b| if b { 1.0 } else { 0.0 }).collect();
    let loops = marching_squares(&f, 4, 4, 0.5, 1.0, 1.0);
    assert_eq!(loops.len(), 1);
    assert_eq!(largest_component_2d(&m).count(), 2);
}

#[test]
fn table_contours_of_intact_and_defect_slices() {
    let v = ct0051();
    // Intact slice: two loops, the outer around the inner.
    let s = v.slice(vz(89));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let t = table_contours(&loops, None).unwrap();
    assert!(t.intact && t.outer.closed && t.inner.closed);
    assert!(t.outer.signed_area() > 0.0 && t.inner.signed_area() < 0.0);
    assert!(t.inner.points.iter().all(|&p| t.outer.contains(p)));
    // Bone ring area (outer − cavity) ≈ bone pixel count × pixel area.
    let ring = t.outer.signed_area() + t.inner.signed_area();
    let px = m.count() as f64 * s.sx * s.sy;
    assert!((ring - px).abs() / px < 0.1, "{ring} vs {px}");
    // Every contour vertex is within one pixel of a bone pixel boundary.
    for p in t.outer.points.iter().chain(&t.inner.points) {
        let (r, c) = s.to_pixel(*p);
        let near = (-1..=1).any(|dr| {
            (-1..=1).any(|dc| m.get_or_false(r.round() as i64 + dr, c.round() as i64 + dc))
        });
        assert!(near);
    }

    // Defect slice: one loop; split at the detected ends.
    let s = v.slice(vz(72));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let e = table_contours(&loops, None).unwrap_err();
    assert!(e.to_string().contains("open"), "{e}");
    let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default()).unwrap();
    let t = table_contours(&loops, Some((d.a_mm, d.b_mm))).unwrap();
    assert!(!t.intact && !t.outer.closed && !t.inner.closed);
    let centre = d.centre;
    let mean_r = |p: &Polyline| {
        p.points.iter().map(|q| q.distance(centre)).sum::<f64>() / p.points.len() as f64
    };
    assert!(mean_r(&t.outer) > mean_r(&t.inner) + 3.0);
    // The two arcs start and end at the cut points near A and B.
    for arc in [&t.outer, &t.inner] {
        let ends = [arc.points[0], *arc.points.last().unwrap()];
        assert!(ends.iter().any(|p| p.distance(d.a_mm) < 1.0));
        assert!(ends.iter().any(|p| p.distance(d.b_mm) < 1.0));
    }
    // A point far from the contour is refused.
    let far = Point::new(128.0 * s.sx, 110.0 * s.sy);
    let e = table_contours(&loops, Some((far, d.b_mm))).unwrap_err();
    assert!(matches!(e, CtError::NotOnContour { what: "A", .. }), "{e}");
}
// ---------------------------------------------------------------- mirror

fn circle(c: Point, r: f64, n: usize) -> Polyline {
    Polyline::closed(
        (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / n as f64;
                c + Point::new(r * t.cos(), r * t.sin())
            })
            .collect(),
    )
}

#[test]
fn midline_of_a_symmetric_synthetic_ring() {
    // Ellipse ring symmetric about column 60.25 (between pixel centres).
    for centre in [60.25, 61.0, 59.5] {
        let m = Mask2::from_fn(130, 120, |r, c| {
            let (dx, dy) = ((c as f64 - centre) / 45.0, (r as f64 - 55.0) / 40.0);
            let q = dx.hypot(dy);
            (0.8..=1.0).contains(&q)
        });
        let ml = estimate_midline(std::slice::from_ref(&m), 0.5).unwrap();
        assert!((ml.col - centre).abs() <= 0.25, "{} vs {centre}", ml.col);
        assert!((ml.x - ml.col * 0.5).abs() < 1e-12);
        // Exactly symmetric on the pixel grid when 2·centre is an integer.
        if (2.0 * centre).fract() == 0.0 {
            assert_eq!(ml.dice, 1.0);
        } else {
            assert!(ml.dice > 0.9);
        }
    }
    assert_eq!(reflect(Point::new(1.0, 2.0), 3.0), Point::new(5.0, 2.0));
}

#[test]
fn mirror_template_on_the_real_defect() {
    let v = ct0051();
    // M_x from intact slices (pooled): the head is centred near column 128.
    let masks: Vec<Mask2> = (88..=90)
        .map(|z| bone_mask_slice(&v.slice(vz(z)), BONE_THRESHOLD_HU).unwrap())
        .collect();
    let ml = estimate_midline(&masks, v.spacing.x).unwrap();
    eprintln!(
        "M_x: col {:.2}, x {:.2} mm, Dice {:.3}",
        ml.col, ml.x, ml.dice
    );
    assert!((110.0..146.0).contains(&ml.col), "{ml:?}");
    assert!(ml.dice > 0.8, "{ml:?}");
    // The estimate is stable between slice groups.
    let other: Vec<Mask2> = (92..=94)
        .map(|z| bone_mask_slice(&v.slice(vz(z)), BONE_THRESHOLD_HU).unwrap())
        .collect();
    let ml2 = estimate_midline(&other, v.spacing.x).unwrap();
    assert!((ml.col - ml2.col).abs() < 3.0, "{ml:?} {ml2:?}");

    let s = v.slice(vz(72));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default()).unwrap();
    let loops = bone_loops(&s, &m, BONE_THRESHOLD_HU);
    let t = table_contours(&loops, Some((d.a_mm, d.b_mm))).unwrap();
    let tpl = mirror_template(&t.outer, d.a_mm, d.b_mm, ml.x, 6.0).unwrap();
    // C and D are the reflections; the template runs from near A to near B
    // and bridges the gap with a curve of similar length on the other side.
    assert_eq!(tpl.c, reflect(d.a_mm, ml.x));
    assert!(
        tpl.c.x > ml.x && tpl.d.x > ml.x,
        "intact side is right of M_x"
    );
    let first = tpl.template.points[0];
    let last = *tpl.template.points.last().unwrap();
    assert!(
        first.distance(d.a_mm) < 6.0 && last.distance(d.b_mm) < 6.0,
        "{first:?} {last:?}"
    );
    let len = tpl.template.length();
    assert!(len > d.width_mm() && len < 2.0 * d.width_mm(), "{len}");
    for (p, q) in tpl.template.points.iter().zip(&tpl.intact_arc.points) {
        assert_eq!(*p, reflect(*q, ml.x));
    }
    // A defect across the midline is refused with a clear message.
    let e = mirror_template(&t.outer, d.a_mm, reflect(d.b_mm, ml.x), ml.x, 6.0).unwrap_err();
    assert!(matches!(e, CtError::DefectCrossesMidline { .. }));
    assert!(e.to_string().contains("explicit template"), "{e}");
    // A midline far off puts C, D away from the contour.
    let e = mirror_template(&t.outer, d.a_mm, d.b_mm, ml.x + 60.0, 6.0).unwrap_err();
    assert!(matches!(e, CtError::NotOnContour { .. }), "{e}");
}

// ---------------------------------------------------------------- mesh, STL, voxels

#[test]
fn loft_of_circles_is_a_closed_oriented_cylinder() {
    let r = 10.0;
    let sections: Vec<Polyline> = (0..5)
        .map(|k| {
            // Alternate orientation and start point: loft must normalise both.
            let c = circle(Point::new(50.0, 40.0), r, 90 + 7 * k);
            if k % 2 == 1 {
                c.reversed()
            } else {
                c
            }
        })
        .collect();
    let zs: Vec<f64> = (0..5).map(|k| k as f64 * 1.5).collect();
    let mesh = loft(&sections, &zs, 64).unwrap();
    assert!(mesh.is_watertight());
    assert!(mesh.is_consistently_oriented());
    assert_eq!(mesh.triangles.len(), 4 * 64 * 2 + 2 * (64 - 2));
    // Volume of the inscribed 64-gon prism: ½ n r² sin(2π/n) · h.
    let n = 64.0;
    let poly_area = 0.5 * n * r * r * (std::f64::consts::TAU / n).sin();
    let expect = poly_area * 6.0;
    assert!(
        (mesh.signed_volume() - expect).abs() / expect < 0.01,
        "{}",
        mesh.signed_volume()
    );
    // Flipping one triangle breaks the orientation but not watertightness.
    let mut bad = mesh.clone();
    bad.triangles[3].swap(0, 1);
    assert!(bad.is_watertight() && !bad.is_consistently_oriented());
    // Removing one breaks watertightness.
    let mut open = mesh.clone();
    open.triangles.pop();
    assert!(!open.is_watertight());
    assert!(loft(&sections[..1], &zs[..1], 64).is_err());
}

#[test]
fn ear_clipping_a_nonconvex_polygon() {
    // An L-shape (area 3) plus a collinear vertex.
    let p = [
        Point::new(0.0, 0.0),
        Point::new(1.0, 0.0),
        Point::new(2.0, 0.0),
        Point::new(2.0, 1.0),
        Point::new(1.0, 1.0),
        Point::new(1.0, 2.0),
        Point::new(0.0, 2.0),
    ];
    let tris = ear_clip(&p);
    assert_eq!(tris.len(), p.len() - 2);
    let area: f64 = tris
        .iter()
        .map(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]) / 2.0)
        .sum();
    assert!((area - 3.0).abs() < 1e-12, "{area}");
    assert!(tris
        .iter()
        .all(|t| (p[t[1]] - p[t[0]]).cross(p[t[2]] - p[t[0]]) >= 0.0));
}

#[test]
fn stl_round_trip_keeps_a_watertight_mesh() {
    let sections = vec![
        circle(Point::new(0.0, 0.0), 5.0, 40),
        circle(Point::new(1.0, 0.5), 6.0, 40),
    ];
    let mesh = loft(&sections, &[0.0, 2.0], 32).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("implant.stl");
    write_stl(&p, &mesh, "metabezier test").unwrap();
    let bytes = std::fs::read(&p).unwrap();
    assert_eq!(bytes.len(), 84 + 50 * mesh.triangles.len());
    assert!(!bytes.starts_with(b"solid"));
    let back = parse_stl(&bytes, &p).unwrap();
    assert_eq!(back.triangles.len(), mesh.triangles.len());
    assert_eq!(back.vertices.len(), mesh.vertices.len());
    assert!(back.is_watertight() && back.is_consistently_oriented());
    assert!((back.signed_volume() - mesh.signed_volume()).abs() < 1e-3);
    assert!(parse_stl(&bytes[..bytes.len() - 1], &p).is_err());
    // No temporary file is left behind.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

#[test]
fn voxelised_disc_has_the_disc_area() {
    let sp = Spacing {
        x: 0.5,
        y: 0.75,
        z: 1.5,
    };
    let r = 12.0;
    let c = Point::new(25.0, 30.0);
    let m = voxelise(&[(1, circle(c, r, 400))], 100, 80, 3, sp);
    assert_eq!(m.slice(0).count(), 0);
    // Voxel centres inside the exact circle (the 400-gon differs by < 0.01%).
    let lattice = (0..80)
        .flat_map(|row| (0..100).map(move |col| (row, col)))
        .filter(|&(row, col)| Point::new(col as f64 * sp.x, row as f64 * sp.y).distance(c) < r)
        .count();
    assert!(
        m.slice(1).count().abs_diff(lattice) <= 2,
        "{} vs {lattice}",
        m.slice(1).count()
    );
    let area = m.slice(1).count() as f64 * sp.x * sp.y;
    let expect = std::f64::consts::PI * r * r;
    assert!((area - expect).abs() / expect < 0.02, "{area} vs {expect}");
    // Each voxel agrees with the point-in-polygon test of its centre.
    let poly = circle(c, r, 400);
    for row in 0..80 {
        for col in 0..100 {
            let p = Point::new(col as f64 * sp.x, row as f64 * sp.y);
            assert_eq!(m.get(1, row, col), poly.contains(p), "({row}, {col})");
        }
    }
}

// ---------------------------------------------------------------- metrics

fn cube(n: usize, lo: [usize; 3], size: usize, sp: Spacing) -> Mask3 {
    Mask3::from_fn(n, n, n, sp, |z, y, x| {
        (lo[0]..lo[0] + size).contains(&z)
            && (lo[1]..lo[1] + size).contains(&y)
            && (lo[2]..lo[2] + size).contains(&x)
    })
}

#[test]
fn dice_of_offset_cubes_is_analytic() {
    let sp = Spacing {
        x: 1.0,
        y: 1.0,
        z: 1.0,
    };
    let a = cube(30, [5, 5, 5], 10, sp);
    for d in 0..=10 {
        let b = cube(30, [5, 5, 5 + d], 10, sp);
        let expect = 1.0 - d as f64 / 10.0;
        assert!((dice(&a, &b).unwrap() - expect).abs() < 1e-12, "shift {d}");
    }
    let empty = Mask3::new(30, 30, 30, sp);
    assert_eq!(dice(&empty, &empty).unwrap(), 1.0);
    assert!(dice(&a, &Mask3::new(29, 30, 30, sp)).is_err());
}

#[test]
fn hd95_of_a_shifted_cube_is_the_shift_in_mm() {
    // Anisotropic spacing: shifts along x, y and z give shift × spacing.
    let sp = Spacing {
        x: 0.5,
        y: 0.75,
        z: 1.5,
    };
    let a = cube(32, [8, 8, 8], 12, sp);
    for (axis, s) in [(2usize, sp.x), (1, sp.y), (0, sp.z)] {
        for d in [1usize, 2, 3] {
            let mut lo = [8, 8, 8];
            lo[axis] += d;
            let b = cube(32, lo, 12, sp);
            let h = hd95(&a, &b).unwrap();
            assert!(
                (h - d as f64 * s).abs() < 1e-9,
                "axis {axis} shift {d}: {h}"
            );
        }
    }
    assert_eq!(hd95(&a, &a).unwrap(), 0.0);
    assert!(hd95(&a, &Mask3::new(32, 32, 32, sp)).is_err());
}

#[test]
fn hd95_of_a_shifted_square_slice_is_the_shift() {
    // One-slice masks (the 2D case): a 20×20 square shifted by 4 columns.
    let sp = Spacing {
        x: 0.8,
        y: 0.8,
        z: 1.5,
    };
    let sq = |c0: usize| {
        Mask3::from_fn(40, 40, 1, sp, |_, y, x| {
            (10..30).contains(&y) && (c0..c0 + 20).contains(&x)
        })
    };
    let h = hd95(&sq(8), &sq(12)).unwrap();
    assert!((h - 4.0 * 0.8).abs() < 1e-9, "{h}");
}

#[test]
fn edt_matches_brute_force() {
    let sp = Spacing {
        x: 0.7,
        y: 1.1,
        z: 2.0,
    };
    // A scattered set of sites.
    let sites = Mask3::from_fn(13, 11, 7, sp, |z, y, x| (x * 7 + y * 13 + z * 29) % 37 == 0);
    let d2 = edt_squared(&sites);
    let pts: Vec<(usize, usize, usize)> = (0..7)
        .flat_map(|z| (0..11).flat_map(move |y| (0..13).map(move |x| (z, y, x))))
        .filter(|&(z, y, x)| sites.get(z, y, x))
        .collect();
    assert!(!pts.is_empty());
    for z in 0..7 {
        for y in 0..11 {
            for x in 0..13 {
                let bf = pts
                    .iter()
                    .map(|&(zz, yy, xx)| {
                        let (dx, dy, dz) = (
                            (x as f64 - xx as f64) * sp.x,
                            (y as f64 - yy as f64) * sp.y,
                            (z as f64 - zz as f64) * sp.z,
                        );
                        dx * dx + dy * dy + dz * dz
                    })
                    .fold(f64::INFINITY, f64::min);
                assert!((d2[sites.index(z, y, x)] - bf).abs() < 1e-9);
            }
        }
    }
    assert!(edt_squared(&Mask3::new(3, 3, 3, sp))
        .iter()
        .all(|d| d.is_infinite()));
}

#[test]
fn boundary_dice_only_counts_voxels_near_the_skull() {
    let sp = Spacing {
        x: 1.0,
        y: 1.0,
        z: 1.0,
    };
    // Skull: the slab x < 5. Implant truth: 5 ≤ x < 25; prediction: 5 ≤ x < 15.
    let n = 30;
    let slab =
        |lo: usize, hi: usize| Mask3::from_fn(n, n, n, sp, move |_, _, x| (lo..hi).contains(&x));
    let skull = slab(0, 5);
    let truth = slab(5, 25);
    let pred = slab(5, 15);
    // Within 10 mm of the skull (x ≤ 14) both agree exactly.
    assert_eq!(boundary_dice(&pred, &truth, &skull, 10.0).unwrap(), 1.0);
    // Within 15 mm (x ≤ 19): |A∩B| = 10·n², |A| = 10·n², |B| = 15·n².
    let bd = boundary_dice(&pred, &truth, &skull, 15.0).unwrap();
    assert!((bd - 2.0 * 10.0 / 25.0).abs() < 1e-12, "{bd}");
    // The plain Dice sees the whole difference.
    assert!((dice(&pred, &truth).unwrap() - 2.0 * 10.0 / 30.0).abs() < 1e-12);
}

#[test]
fn contour_deviation_of_known_curves() {
    let a = circle(Point::new(0.0, 0.0), 10.0, 720);
    let b = circle(Point::new(0.0, 0.0), 12.0, 720);
    let d = contour_deviation(&a, &b, 0.1).unwrap();
    assert!(
        (d.mean - 2.0).abs() < 0.01 && (d.max - 2.0).abs() < 0.01,
        "{d:?}"
    );
    // Parallel segments 3 mm apart: exactly 3 everywhere.
    let s1 = Polyline::open(vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0)]);
    let s2 = Polyline::open(vec![Point::new(0.0, 3.0), Point::new(10.0, 3.0)]);
    let d = contour_deviation(&s1, &s2, 0.5).unwrap();
    assert!(
        (d.mean - 3.0).abs() < 1e-12 && (d.max - 3.0).abs() < 1e-12,
        "{d:?}"
    );
    // A bump of height 1 over a 2 mm base on a 10 mm line: max 1.
    let bump = Polyline::open(vec![
        Point::new(0.0, 0.0),
        Point::new(4.0, 0.0),
        Point::new(5.0, 1.0),
        Point::new(6.0, 0.0),
        Point::new(10.0, 0.0),
    ]);
    let d = contour_deviation(&s1, &bump, 0.05).unwrap();
    assert!((d.max - 1.0).abs() < 1e-9 && d.mean < 0.2, "{d:?}");
}

#[test]
fn loft_of_real_outer_tables_is_watertight_and_voxelises_back() {
    let v = ct0051();
    let zs: Vec<usize> = (88..=92).collect();
    let mut sections = Vec::new();
    for &z in &zs {
        let s = v.slice(vz(z));
        let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
        let t = table_contours(&bone_loops(&s, &m, BONE_THRESHOLD_HU), None).unwrap();
        sections.push(t.outer);
    }
    let heights: Vec<f64> = zs.iter().map(|&z| vz(z) as f64 * v.spacing.z).collect();
    let mesh = loft(&sections, &heights, 200).unwrap();
    assert!(mesh.is_watertight() && mesh.is_consistently_oriented());
    // Volume ≈ trapezoidal integral of the section areas.
    let areas: Vec<f64> = sections.iter().map(|p| p.signed_area()).collect();
    let trap: f64 = areas
        .windows(2)
        .map(|w| (w[0] + w[1]) / 2.0 * v.spacing.z)
        .sum();
    assert!(
        (mesh.signed_volume() - trap).abs() / trap < 0.03,
        "{} vs {trap}",
        mesh.signed_volume()
    );
    // Voxelising the sections gives the head (bone and cavity) of each slice.
    let secs: Vec<(usize, Polyline)> = zs
        .iter()
        .zip(&sections)
        .map(|(&z, p)| (vz(z), p.clone()))
        .collect();
    let vox = voxelise(&secs, v.nx, v.ny, v.nz, v.spacing);
    for (k, &z) in zs.iter().enumerate() {
        let n = vox.slice(vz(z)).count() as f64 * v.spacing.x * v.spacing.y;
        assert!(
            (n - areas[k]).abs() / areas[k] < 0.02,
            "z={z}: {n} vs {}",
            areas[k]
        );
    }
}

// ---------------------------------------------------------------- rendering

#[test]
fn overlay_and_mesh_previews_render() {
    let v = ct0051();
    let s = v.slice(vz(72));
    let m = bone_mask_slice(&s, BONE_THRESHOLD_HU).unwrap();
    let d = detect_defect(&m, s.sx, s.sy, &DefectParams::default()).unwrap();
    let t = table_contours(
        &bone_loops(&s, &m, BONE_THRESHOLD_HU),
        Some((d.a_mm, d.b_mm)),
    )
    .unwrap();
    let red = [255, 0, 0];
    let overlay = Overlay {
        polylines: vec![
            (t.outer.clone(), [0, 200, 0]),
            (t.inner.clone(), [0, 120, 255]),
        ],
        points: vec![("A".into(), d.a_mm, red), ("B".into(), d.b_mm, red)],
        vertical_lines: vec![(128.0 * s.sx, [255, 255, 0])],
        ..Default::default()
    };
    let png = slice_overlay_png(&s, Window::BONE, 2, &overlay).unwrap();
    let img = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (512, 512));
    // The marker of A is drawn at its pixel (scaled ×2, centre of the block).
    let (ar, ac) = d.a;
    assert_eq!(img.get_pixel(ac as u32 * 2 + 1, ar as u32 * 2 + 1).0, red);
    // Bone window: air is black, the M_x line yellow.
    assert_eq!(img.get_pixel(2, 300).0, [0, 0, 0]);
    assert_eq!(img.get_pixel(257, 5).0, [255, 255, 0]);
    let dir = tempfile::tempdir().unwrap();
    write_png(&dir.path().join("z072.png"), &png).unwrap();

    // A lofted cylinder seen along −z is a shaded disc; from the side a rectangle.
    let secs = vec![
        circle(Point::new(0.0, 0.0), 10.0, 60),
        circle(Point::new(0.0, 0.0), 10.0, 60),
    ];
    let mesh = loft(&secs, &[0.0, 30.0], 48).unwrap();
    let top = mesh_view_rgb(
        &[(&mesh, [200, 180, 160])],
        View {
            direction: [0.0, 0.0, -1.0],
            up: [0.0, 1.0, 0.0],
            mirror: false,
        },
        100,
    );
    let at = |buf: &[u8], x: usize, y: usize| {
        [
            buf[(y * 100 + x) * 3],
            buf[(y * 100 + x) * 3 + 1],
            buf[(y * 100 + x) * 3 + 2],
        ]
    };
    assert_eq!(at(&top, 50, 50), [200, 180, 160]); // cap faces the viewer: full light
    assert_eq!(at(&top, 1, 1), [255, 255, 255]);
    let side = mesh_view_rgb(
        &[(&mesh, [200, 180, 160])],
        View {
            direction: [0.0, 1.0, 0.0],
            up: [0.0, 0.0, 1.0],
            mirror: false,
        },
        100,
    );
    let centre = at(&side, 50, 50);
    let edge = at(&side, 50 - 15, 50);
    assert!(
        centre[0] > edge[0],
        "Lambert: darker towards the silhouette"
    );
    let png = encode_png(&side, 100, 100).unwrap();
    assert!(image::load_from_memory(&png).is_ok());
}

// ---------------------------------------------------------------- frames, midline, clipping

#[test]
fn frame_maps_voxel_millimetres_to_patient_and_back() {
    let v = ct_inputs::small_volume()
        .with_frame([-120.5, 33.25, -47.0], oblique_axes(), FrameSource::Given)
        .unwrap();
    let f = v.frame();
    let p = [1.5, -2.25, 7.0];
    let q = f.to_patient(p);
    let back = f.to_voxel_mm(q);
    for i in 0..3 {
        assert!((back[i] - p[i]).abs() < 1e-12, "{back:?}");
    }
    // The origin is voxel (0, 0, 0); a step of one slice is sz along the
    // third axis.
    assert_eq!(f.to_patient([0.0; 3]), [-120.5, 33.25, -47.0]);
    let step = f.to_patient([0.0, 0.0, 2.0]);
    let d: f64 = (0..3)
        .map(|i| (step[i] - f.origin[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((d - 2.0).abs() < 1e-12);
    // Coplanar axes are refused; sub_z moves the origin along the slice axis.
    let flat = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 1.0, 0.0]];
    assert!(matches!(
        ct_inputs::small_volume().with_frame([0.0; 3], flat, FrameSource::Given),
        Err(CtError::BadAxes { .. })
    ));
    let sub = v.sub_z(1, 3);
    let o = f.to_patient([0.0, 0.0, 2.0]);
    for (a, b) in sub.origin.iter().zip(&o) {
        assert!((a - b).abs() < 1e-12);
    }
    // An .inv3 says in the STL header that it has no origin.
    assert!(ct0051()
        .frame()
        .stl_header()
        .contains(".inv3 has no origin"));
    assert!(ct0051().frame().stl_header().len() <= 80);
}

#[test]
fn dicom_series_keeps_a_non_zero_origin_and_an_oblique_orientation() {
    let v = ct0051()
        .sub_z(vz(70), vz(73))
        .with_frame([-118.25, -96.5, 412.0], oblique_axes(), FrameSource::Given)
        .unwrap();
    let dir = tempfile::tempdir().unwrap();
    let mut paths = write_dicom_series(dir.path(), &v, 0..3, "oblique").unwrap();
    paths.reverse();
    let back = read_dicom_series(&paths).unwrap();
    assert_eq!(back.data(), v.data());
    assert_eq!(back.frame_source, FrameSource::Dicom);
    assert!((back.spacing.z - 1.5).abs() < 1e-9);
    for i in 0..3 {
        assert!(
            (back.origin[i] - v.origin[i]).abs() < 1e-9,
            "{:?}",
            back.origin
        );
        for j in 0..3 {
            assert!(
                (back.axes[i][j] - v.axes[i][j]).abs() < 1e-9,
                "{:?}",
                back.axes
            );
        }
    }
    assert!(back.frame().stl_header().contains("DICOM patient frame"));
    // Slices of different orientations do not make one series.
    let other = v
        .clone()
        .with_frame(v.origin, IDENTITY_AXES, FrameSource::Given)
        .unwrap();
    let d2 = tempfile::tempdir().unwrap();
    let q = write_dicom_series(d2.path(), &other.sub_z(2, 3), 0..1, "x").unwrap();
    let e = read_dicom_series(&[paths[0].clone(), q[0].clone()]).unwrap_err();
    assert!(matches!(e, CtError::OrientationMismatch { .. }), "{e}");
}

#[test]
fn a_lofted_mesh_sliced_at_its_rings_voxelises_to_the_rings() {
    let sp = Spacing {
        x: 0.5,
        y: 0.5,
        z: 1.5,
    };
    let secs: Vec<Polyline> = (0..4)
        .map(|k| {
            circle(
                Point::new(12.13 + k as f64, 11.07),
                6.0 + 0.5 * k as f64,
                50,
            )
        })
        .collect();
    // Centres off the voxel grid, so no voxel centre lies on a ring.
    let zs: Vec<f64> = (1..5).map(|k| k as f64 * sp.z).collect();
    let rings = loft_rings(&secs, &zs, 90).unwrap();
    let mesh = mesh_of_rings(&rings, &zs);
    assert!(mesh.is_watertight() && mesh.is_consistently_oriented());
    // The cross-section between two rings is a closed counter-clockwise loop.
    let mid = slice_mesh(&mesh, 2.25);
    assert_eq!(mid.len(), 1);
    assert!(mid[0].signed_area() > 0.0);
    let vox: Vec<(usize, Polyline)> = (1..5).zip(rings).collect();
    let expect = voxelise(&vox, 50, 40, 6, sp);
    let got = voxelise_mesh(&mesh, 50, 40, 6, sp);
    assert_eq!(got.slice(0).count(), 0);
    assert_eq!(got.slice(5).count(), 0);
    let diff = got
        .data
        .iter()
        .zip(&expect.data)
        .filter(|(a, b)| a != b)
        .count();
    assert!(diff <= 2, "{diff} voxels differ of {}", expect.count());
}

#[test]
fn tilted_midline_of_ct0051_turned_by_known_angles_within_1_degree() {
    let v = ct0051().sub_z(vz(86), vz(93));
    let masks = |w: &Volume| -> Vec<Mask2> {
        (0..w.nz)
            .map(|k| bone_mask_slice(&w.slice(k), BONE_THRESHOLD_HU).unwrap())
            .collect()
    };
    let (sx, sy) = (v.spacing.x, v.spacing.y);
    let straight = estimate_tilted_midline(&masks(&v), sx, sy, 20.0).unwrap();
    // The head in CT 0051 is itself turned by about 3°, and the tilted line
    // mirrors it better than the best vertical one.
    assert!(
        (straight.line.tilt_deg() + 3.15).abs() < 0.5,
        "{straight:?}"
    );
    let vertical = estimate_midline(&masks(&v), sx).unwrap();
    assert!(straight.dice > vertical.dice + 0.02);
    let centre = Point::new(128.0 * sx, 128.0 * sy);
    for angle in [-10.0, -4.0, 6.0, 12.0] {
        let turned = v.rotated_in_plane(angle, centre);
        let m = estimate_tilted_midline(&masks(&turned), sx, sy, 20.0).unwrap();
        // Turning the image by +β turns the line's tilt by −β.
        let expect = straight.line.tilt_deg() - angle;
        assert!(
            (m.line.tilt_deg() - expect).abs() < 1.0,
            "turned {angle}°: tilt {} vs {expect}",
            m.line.tilt_deg()
        );
        assert!(m.dice > 0.9, "{m:?}");
        // The turned line passes through the turned image of a point of the
        // original line.
        let p = straight.line.point - centre;
        let (s, c) = angle.to_radians().sin_cos();
        let q = centre + Point::new(c * p.x - s * p.y, s * p.x + c * p.y);
        assert!(m.line.side(q).abs() < 1.5, "{}", m.line.side(q));
    }
    // The line's geometry.
    let l = MidLine {
        point: Point::new(10.0, 0.0),
        tilt: 30f64.to_radians(),
    };
    let p = Point::new(3.0, 4.0);
    assert!(l.reflect(l.reflect(p)).distance(p) < 1e-12);
    assert!((l.side(p) + l.side(l.reflect(p))).abs() < 1e-12);
    assert!(l.side(l.at_y(7.0)).abs() < 1e-12);
}

#[test]
fn clipping_a_section_leaves_no_bone_pixel_inside() {
    // A slice of soft tissue (40 HU) with a bone block (1000 HU) in
    // columns 20..30, and a section overlapping the block.
    let (nx, ny) = (50usize, 40usize);
    let data: Vec<i16> = (0..nx * ny)
        .map(|i| {
            if (20..30).contains(&(i % nx)) {
                1000
            } else {
                40
            }
        })
        .collect();
    let slice = Slice {
        z: 0,
        nx,
        ny,
        sx: 0.8,
        sy: 0.8,
        data: &data,
    };
    let rect = |x0: f64, y0: f64, x1: f64, y1: f64| {
        Polyline::closed(vec![
            Point::new(x0, y0),
            Point::new(x1, y0),
            Point::new(x1, y1),
            Point::new(x0, y1),
        ])
    };
    let section = rect(8.0, 8.0, 20.0, 20.0);
    let c = clip_to_tissue(&section, &slice, 300, 4).unwrap();
    assert!((c.area_before - 144.0).abs() < 1e-9);
    // The block starts at x = 20·0.8 = 16 mm; the 300 HU level lies 0.27
    // pixel before it (bilinear), so about 8 × 12 − a sliver remains.
    assert!(
        c.area_after > 88.0 && c.area_after < 96.0,
        "{}",
        c.area_after
    );
    let sp = Spacing {
        x: 0.8,
        y: 0.8,
        z: 1.0,
    };
    let vox = voxelise(&[(0, c.section.clone())], nx, ny, 1, sp);
    assert!(vox.count() > 100);
    for (r, col) in vox.slice(0).pixels() {
        assert!(slice.get(r, col) < 300, "({r}, {col}) is bone");
    }
    // A section entirely in bone leaves nothing.
    assert!(clip_to_tissue(&rect(17.0, 8.0, 22.0, 20.0), &slice, 300, 4).is_none());
}

/// A ring broken twice (an artificial cut on a slice that also has a real
/// defect) is two bone pieces; the largest component alone loses the piece
/// that holds B, the mask holding the ends keeps it, and the tables are
/// the two pieces' loops (A's first), read as one envelope by the design.
#[test]
fn a_ring_broken_twice_keeps_both_pieces_and_gives_their_loops() {
    let (n, c) = (128usize, Point::new(64.0, 64.0));
    let in_gap = |deg: f64| (-10.0..=10.0).contains(&deg) || (140.0..=160.0).contains(&deg);
    let data: Vec<i16> = (0..n * n)
        .map(|i| {
            let p = Point::new((i % n) as f64, (i / n) as f64) - c;
            let r = (p.x * p.x + p.y * p.y).sqrt();
            let deg = p.y.atan2(p.x).to_degrees();
            if (30.0..=36.0).contains(&r) && !in_gap(deg) {
                1000
            } else {
                0
            }
        })
        .collect();
    let slice = Slice {
        z: 0,
        nx: n,
        ny: n,
        sx: 1.0,
        sy: 1.0,
        data: &data,
    };
    let at = |deg: f64| c + Point::new(deg.to_radians().cos(), deg.to_radians().sin()) * 36.2;
    // A ends the larger piece (160°..350°), B the smaller (10°..140°).
    let (a, b) = (at(-10.5), at(10.5));
    let near = |m: &Mask2, p: Point| {
        m.pixels()
            .iter()
            .any(|&(r, cc)| Point::new(cc as f64, r as f64).distance(p) <= 2.0)
    };
    let largest = bone_mask_slice(&slice, 300).unwrap();
    assert!(near(&largest, a) && !near(&largest, b));
    let e = table_contours(&bone_loops(&slice, &largest, 300), Some((a, b))).unwrap_err();
    assert!(matches!(e, CtError::NotOnContour { what: "B", .. }), "{e}");
    let both = bone_mask_slice_holding(&slice, 300, &[a, b], 2.0).unwrap();
    assert!(near(&both, a) && near(&both, b));
    assert_eq!(
        both.count(),
        threshold_slice(&slice, 300).count(),
        "both pieces, nothing else"
    );
    // An end next to no bone adds nothing.
    let alone = bone_mask_slice_holding(&slice, 300, &[a, c], 2.0).unwrap();
    assert_eq!(alone, largest);
    let t = table_contours(&bone_loops(&slice, &both, 300), Some((a, b))).unwrap();
    assert!(!t.intact && t.outer.closed && t.inner.closed);
    assert!(t.outer.nearest(a).unwrap().distance <= 2.0);
    assert!(t.inner.nearest(b).unwrap().distance <= 2.0);
    assert!(t.outer.nearest(b).unwrap().distance > 2.0);
    // The centre's height is read from both pieces.
    let m = t.vertex_mean();
    assert!((m.y - 0.5 * (t.outer.vertex_mean().y + t.inner.vertex_mean().y)).abs() < 1e-9);
}
