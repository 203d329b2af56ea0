//! The hardened readers: lengths, limits, transfer syntaxes, sequences and
//! series checks of DICOM, and the tar and gzip checks of `.inv3`.

use super::*;

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
