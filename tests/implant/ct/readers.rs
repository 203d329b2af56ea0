//! The readers: `.inv3` projects and DICOM files and series, their round trips
//! and errors.

use super::*;

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
