//! Chapter-6 pipeline on the vendored ProMED CT 0051 extract.

use std::path::Path;

use metabezier::ct::{
    read_inv3, slice_overlay_png, write_png, Overlay, Window, CT0051_FIRST_Z, CT0051_PATH,
};
use metabezier::fit::LmSolver;
use metabezier::implant::*;

fn real_config() -> DefectConfig {
    let measured = [
        (64, (196.0, 111.0), (188.0, 86.0)),
        (72, (194.0, 107.0), (184.0, 86.0)),
        (80, (185.0, 104.0), (179.0, 93.0)),
    ];
    DefectConfig {
        first_z: CT0051_FIRST_Z,
        slices: (56..=84)
            .map(|z| SliceSpec {
                z,
                ends: measured
                    .iter()
                    .find(|m| m.0 == z)
                    .map_or(Ends::Auto, |m| Ends::Pixels { a: m.1, b: m.2 }),
            })
            .collect(),
        midline: MidlineSpec::Auto(vec![]),
        threshold: 300,
        wall: WallOptions::default(),
        ring_points: 160,
    }
}

#[test]
fn explore() {
    let v = read_inv3(Path::new(CT0051_PATH)).unwrap();
    let cfg = real_config();
    let imp = reconstruct_defect(&v, &cfg, &mut LmSolver::default()).unwrap();
    println!("midline {} dice {:?}", imp.midline_x, imp.midline_dice);
    std::fs::create_dir_all("/tmp/ch6_explore").unwrap();
    for s in &imp.slices {
        let w = &s.wall;
        println!(
            "z {} A {:?} B {:?} C {:?} D {:?} t {:?} E {} joins {:?}",
            s.z,
            w.a,
            w.b,
            w.c,
            w.d,
            w.thickness,
            w.fit_error,
            w.join_angles_deg()
        );
        if s.z % 8 == 0 {
            let sl = v.slice(s.z - CT0051_FIRST_Z);
            let ov = Overlay {
                polylines: vec![
                    (s.outer.clone(), [0, 200, 0]),
                    (s.inner.clone(), [0, 120, 255]),
                    (w.template.clone(), [255, 0, 255]),
                    (w.outer.clone(), [255, 0, 0]),
                    (w.inner.clone(), [255, 160, 0]),
                ],
                points: vec![
                    ("A".into(), w.a, [255, 255, 0]),
                    ("B".into(), w.b, [255, 255, 0]),
                    ("C".into(), w.c, [0, 255, 255]),
                    ("D".into(), w.d, [0, 255, 255]),
                ],
                vertical_lines: vec![(imp.midline_x, [255, 255, 255])],
            };
            let png = slice_overlay_png(&sl, Window::BONE, 3, &ov).unwrap();
            write_png(Path::new(&format!("/tmp/ch6_explore/z{}.png", s.z)), &png).unwrap();
        }
    }
    println!(
        "watertight {} oriented {} vol {}",
        imp.mesh.is_watertight(),
        imp.mesh.is_consistently_oriented(),
        imp.mesh.signed_volume()
    );
}
