//! The whole chapter-6 pipeline on the real defect of ProMED CT 0051
//! (z = 56–84, `experiments/ch6_cranial.toml`'s `[defect]` part): read the
//! vendored `.inv3` extract, estimate M_x, reconstruct 29 slices with MHS at
//! its default budget (10,000 evaluations per slice), loft, and write the
//! binary STL. Target: under 5 s on 2 cores. Run with
//! `cargo bench --bench implant`.

use std::path::Path;
use std::time::Duration;

use criterion::Criterion;
use metabezier::ct::{stl_bytes, CT0051_FIRST_Z, CT0051_MEASURED_ENDS, CT0051_PATH};
use metabezier::files::write_atomic;
use metabezier::implant::{
    load_volume, reconstruct_defect, DefectConfig, Ends, MidlineSpec, SliceSpec, Smoothing,
    WallOptions,
};
use metabezier::optim::Algorithm;
use metabezier::reconstruction::Method;

fn config() -> DefectConfig {
    DefectConfig {
        first_z: CT0051_FIRST_Z,
        slices: (56..=84)
            .map(|z| SliceSpec {
                z,
                ends: CT0051_MEASURED_ENDS.iter().find(|m| m.0 == z).map_or(
                    Ends::Auto,
                    |&(_, a, b)| Ends::Pixels {
                        a: (a.0 as f64, a.1 as f64),
                        b: (b.0 as f64, b.1 as f64),
                    },
                ),
            })
            .collect(),
        midline: MidlineSpec::Auto((86..=92).collect()),
        max_tilt_deg: 20.0,
        threshold: 300,
        wall: WallOptions::default(),
        smoothing: Smoothing::default(),
        templates: None,
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
            let mut solver = method.solver(2026);
            let implant = reconstruct_defect(&volume, &cfg, &mut *solver).expect("implant");
            assert!(implant.mesh.is_watertight());
            write_atomic(&stl, &stl_bytes(&implant.mesh, "bench")).expect("stl");
        })
    });
    c.final_summary();
    let _ = std::fs::remove_dir_all(&dir);
}
