//! The whole chapter-6 pipeline on the real defect of ProMED CT 0051
//! (z = 56–84, `experiments/ch6_cranial.toml`'s `[defect]` part): read the
//! vendored `.inv3` extract, estimate M_x, reconstruct 29 slices with MHS at
//! its default budget (10,000 evaluations per slice), loft, and write the
//! binary STL. Target: under 5 s on 2 cores. Run with
//! `cargo bench --bench implant`.

use std::path::Path;
use std::time::Duration;

use criterion::Criterion;
use metabezier::ct::{stl_bytes, CT0051_FIRST_Z, CT0051_PATH};
use metabezier::error::write_atomic;
use metabezier::implant::{
    load_volume, reconstruct_defect, solver_for, DefectConfig, Ends, MidlineSpec, SliceSpec,
    WallOptions,
};
use metabezier::optim::Algorithm;
use metabezier::reconstruction::Method;

fn config() -> DefectConfig {
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
        midline: MidlineSpec::Auto((86..=92).collect()),
        threshold: 300,
        wall: WallOptions::default(),
        ring_points: 160,
    }
}

fn main() {
    let mut c = Criterion::default()
        .configure_from_args()
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    let cfg = config();
    let method = Method::Metaheuristic(Algorithm::default_for("mhs").expect("mhs"));
    let dir = std::env::temp_dir().join(format!("metabezier-bench-implant-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let stl = dir.join("implant.stl");
    c.bench_function("implant/ct0051_load_to_stl_mhs", |b| {
        b.iter(|| {
            let volume = load_volume(Path::new(CT0051_PATH)).expect("volume");
            let mut solver = solver_for(&method, 2026);
            let implant = reconstruct_defect(&volume, &cfg, &mut *solver).expect("implant");
            assert!(implant.mesh.is_watertight());
            write_atomic(&stl, &stl_bytes(&implant.mesh, "bench")).expect("stl");
        })
    });
    c.final_summary();
    let _ = std::fs::remove_dir_all(&dir);
}
