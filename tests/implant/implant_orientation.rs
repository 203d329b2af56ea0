//! Issue 27: the pictures' orientation from the data (ImageOrientationPatient
//! for DICOM, the declared convention for `.inv3`) and one-slice designs of
//! a one-slice DICOM study in the standard LPS frame.

use crate::common;
use crate::ct_inputs;

use std::path::{Path, PathBuf};

use metabezier::ct::{
    parse_stl, read_inv3, write_dicom_series, FrameSource, PatientDirection, Volume,
    CT0051_FIRST_Z, CT0051_PATH, IDENTITY_AXES,
};
use metabezier::geometry::Point;
use metabezier::implant::render::Orientation;
use metabezier::implant::{load_volume, resolve_midline, DefectConfig, MidlineSpec};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("metabezier-orient-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn ct0051() -> Volume {
    read_inv3(&Path::new(env!("CARGO_MANIFEST_DIR")).join(CT0051_PATH)).unwrap()
}

/// Slice 72 of CT 0051 as a one-slice study in the standard LPS frame:
/// the rows turned over, so that row 0 is the face (patient −Y, anterior)
/// as a scanner writes an axial head CT, with identity
/// ImageOrientationPatient (rows along +X = left, columns along +Y =
/// posterior).
fn lps_slice() -> Volume {
    let v = ct0051();
    let k = 72 - CT0051_FIRST_Z;
    let one = v.sub_z(k, k + 1);
    let (nx, ny) = (one.nx, one.ny);
    let src = one.data();
    let data: Vec<i16> = (0..ny)
        .flat_map(|r| src[(ny - 1 - r) * nx..(ny - r) * nx].iter().copied())
        .collect();
    one.with_data(data)
        .with_frame([-122.0, -110.0, 80.0], IDENTITY_AXES, FrameSource::Given)
        .unwrap()
}

/// The midline of CT 0051 (intact slices 86–92) with its rows turned over
/// as in [`lps_slice`]: `[x, y, tilt_deg]` for a spec.
fn lps_midline(ny: usize) -> [f64; 3] {
    let v = ct0051();
    let cfg = DefectConfig {
        first_z: CT0051_FIRST_Z,
        slices: Vec::new(),
        midline: MidlineSpec::Auto((86..=92).collect()),
        max_tilt_deg: 20.0,
        threshold: 300,
        wall: Default::default(),
        smoothing: Default::default(),
        templates: None,
        plane: None,
        ring_points: 120,
        thickness_mm: None,
    };
    let m = resolve_midline(&v, &cfg).unwrap().0;
    let h = (ny - 1) as f64 * v.spacing.y;
    [m.point.x, h - m.point.y, -m.tilt_deg()]
}

/// Writes the one-slice study into `dir/study` (optionally without
/// SliceThickness) and returns the directory.
fn write_study(dir: &Path, v: &Volume, thickness: bool) -> PathBuf {
    let study = dir.join("study");
    std::fs::create_dir_all(&study).unwrap();
    let paths = write_dicom_series(&study, v, 0..1, "1.2.826.0.1.27").unwrap();
    if !thickness {
        let bytes = std::fs::read(&paths[0]).unwrap();
        std::fs::write(&paths[0], ct_inputs::without(&bytes, &[(0x0018, 0x0050)])).unwrap();
    }
    study
}

/// A spec of the one-slice LPS study: the defect ends of z = 72 measured on
/// CT 0051 (row, col) with the rows turned over.
fn one_slice_spec(study: &Path, ny: usize, extra_defect: &str) -> String {
    let m = lps_midline(ny);
    let row = |r: usize| ny - 1 - r;
    format!(
        "[implant]\nvolume = \"{}\"\nfirst_z = 72\nmidline = [{}, {}, {}]\nmethod = \"lm\"\nbudget = 2000\n\
         [defect]\nslices = [72, 72]\noverlays = [72]\n{extra_defect}\n\
         [[defect.end]]\nz = 72\na = [{}, 107]\nb = [{}, 86]\n",
        study.display(),
        m[0],
        m[1],
        m[2],
        row(194),
        row(184)
    )
}

#[test]
fn labels_and_flip_come_from_the_orientation_on_lps_dicom_and_on_the_vendored_inv3() {
    let dir = tmp("labels");
    let lps = lps_slice();
    let study = write_study(&dir, &lps, true);
    let d = load_volume(&study).unwrap();
    assert_eq!(d.frame_source, FrameSource::Dicom);
    let o = Orientation::of(&d.frame()).unwrap();
    // Rows run posterior (+Y): drawn y-down, the face (row 0) at the top,
    // the patient's right on the picture's left (radiological convention).
    assert!(!o.y_up);
    assert_eq!(
        o.edges(),
        [
            PatientDirection::Anterior,
            PatientDirection::Posterior,
            PatientDirection::Right,
            PatientDirection::Left
        ]
    );
    // The vendored .inv3 by its declared convention: +y is the face, drawn
    // y-up, anterior again at the top.
    let inv3 = ct0051();
    let oi = Orientation::of(&inv3.frame()).unwrap();
    assert!(oi.y_up);
    assert_eq!(oi.edges()[0], PatientDirection::Anterior);
    // On both, the frontal bone (the bone pixel nearest the face) is drawn
    // in the top half, under the label "anterior (face)".
    for (v, o, face_row) in [(&d, o, 0usize), (&inv3, oi, inv3.ny - 1)] {
        let k = if v.nz == 1 { 0 } else { 72 - CT0051_FIRST_Z };
        let s = v.slice(k);
        let rows = (0..s.ny).filter(|&r| (0..s.nx).any(|c| s.get(r, c) >= 300));
        let r = if face_row == 0 {
            rows.min().unwrap()
        } else {
            rows.max().unwrap()
        };
        let hi = Point::new(s.nx as f64 * s.sx, s.ny as f64 * s.sy);
        let view = o.slice_view(Point::ZERO, hi, 512);
        let (_, y) = view.to_px(Point::new(0.5 * hi.x, r as f64 * s.sy));
        assert!(y < 128.0, "face drawn at y = {y}");
        assert_eq!(view.top_label, "anterior (face)");
        assert_eq!(view.bottom_label, "posterior");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_one_slice_lps_dicom_study_gives_an_implant_overlay_and_metrics() {
    let dir = tmp("oneslice");
    let lps = lps_slice();
    let study = write_study(&dir, &lps, true);
    let (ok, err) = common::implant(&dir, &one_slice_spec(&study, lps.ny, ""));
    assert!(ok, "{err}");
    let out = dir.join("out");
    for f in [
        "implant.stl",
        "metrics.csv",
        "overlay_z072.png",
        "preview_3d.png",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let stl = parse_stl(
        &std::fs::read(out.join("implant.stl")).unwrap(),
        Path::new("x"),
    )
    .unwrap();
    assert!(stl.is_watertight() && stl.is_consistently_oriented());
    // Extruded by the slice thickness (1.5 mm), centred on the slice.
    let zs: Vec<f64> = stl.vertices.iter().map(|v| v[2]).collect();
    let (lo, hi) = zs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    assert!(
        (hi - lo - 1.5).abs() < 1e-3 && ((lo + hi) / 2.0 - 80.0).abs() < 1e-3,
        "{lo} {hi}"
    );
    let metrics = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    assert_eq!(metrics.lines().count(), 2, "{metrics}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_one_slice_study_without_slice_thickness_needs_thickness_mm() {
    let dir = tmp("nothick");
    let lps = lps_slice();
    let study = write_study(&dir, &lps, false);
    let (ok, err) = common::implant(&dir, &one_slice_spec(&study, lps.ny, ""));
    assert!(!ok);
    assert!(
        err.contains("slice z = 72")
            && err.contains("SliceThickness (0018,0050)")
            && err.contains("`thickness_mm` in [defect]"),
        "{err}"
    );
    assert!(!dir.join("out").exists());
    let (ok, err) = common::implant(&dir, &one_slice_spec(&study, lps.ny, "thickness_mm = 2.0"));
    assert!(ok, "{err}");
    let stl = parse_stl(
        &std::fs::read(dir.join("out/implant.stl")).unwrap(),
        Path::new("x"),
    )
    .unwrap();
    let zs: Vec<f64> = stl.vertices.iter().map(|v| v[2]).collect();
    let (lo, hi) = zs
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &z| (a.min(z), b.max(z)));
    assert!((hi - lo - 2.0).abs() < 1e-3, "{lo} {hi}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_orientation_that_is_not_orthogonal_is_refused_naming_the_file() {
    let dir = tmp("skew");
    let study = write_study(&dir, &lps_slice(), true);
    let path = study.join("slice_0000.dcm");
    let bytes = std::fs::read(&path).unwrap();
    std::fs::write(
        &path,
        ct_inputs::with_value(&bytes, (0x0020, 0x0037), b"1\\0\\0\\0.5\\1\\0 "),
    )
    .unwrap();
    let err = load_volume(&study).unwrap_err().to_string();
    assert!(
        err.contains("slice_0000.dcm")
            && err.contains("ImageOrientationPatient")
            && err.contains("not two orthogonal unit vectors"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
