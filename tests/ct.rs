//! Tests of the CT data layer (`metabezier::ct`) on synthetic data, on the
//! vendored ProMED CT 0051 extract and on pydicom's CT_small.dcm.

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

fn small_volume() -> Volume {
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

#[test]
fn inv3_round_trip_and_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("a.inv3");
    let v = small_volume();
    write_inv3(&p, &v, "test & <name>").unwrap();
    assert_eq!(read_inv3(&p).unwrap(), v);

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
    let v = small_volume();
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

// ---------------------------------------------------------------- bone, defect

/// Measured bone-gap end points (row, col) in the full volume's slice index.
type Px = (usize, usize);
const MEASURED_ENDS: [(usize, Px, Px); 3] = [
    (64, (196, 111), (188, 86)),
    (72, (194, 107), (184, 86)),
    (80, (185, 104), (179, 93)),
];

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
    for (z, p, q) in MEASURED_ENDS {
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
    let o = t.outer.vertex_mean();
    let _ = o;
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
