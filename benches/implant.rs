//! The whole chapter-6 pipeline on the real defect of ProMED CT 0051
//! (z = 56–84, the `[implant]` and `[defect]` parts of
//! `experiments/ch6_cranial.toml`): read the vendored `.inv3` extract,
//! estimate the tilted midline, reconstruct 29 slices with MHS at the spec's
//! budget (10,000 evaluations per slice), smooth across slices, loft, and
//! write the binary STL in the volume's frame. Target (issue 13): under 2 s
//! on 2 cores. Run with `cargo bench --bench implant`.

use std::path::Path;
use std::time::Duration;

use criterion::Criterion;
use metabezier::ct::stl_bytes;
use metabezier::files::write_atomic;
use metabezier::implant::{load_volume, reconstruct_defect, ImplantSpec};

fn main() {
    let mut c = Criterion::default()
        .configure_from_args()
        .sample_size(10)
        .measurement_time(Duration::from_secs(10));
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/ch6_cranial.toml");
    let spec = ImplantSpec::load(&path).expect("the chapter-6 spec");
    let dir = std::env::temp_dir().join(format!("metabezier-bench-implant-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let stl = dir.join("implant.stl");
    c.bench_function("implant/ct0051_load_to_stl_mhs", |b| {
        b.iter(|| {
            let volume = load_volume(&spec.volume).expect("volume");
            let mut solver = spec.method.solver(spec.seed);
            let implant =
                reconstruct_defect(&volume, &spec.defect_config, &mut *solver).expect("implant");
            assert!(implant.mesh.is_watertight());
            let bytes = stl_bytes(&implant.patient_mesh(), &implant.frame.stl_header());
            write_atomic(&stl, &bytes).expect("stl");
        })
    });
    c.final_summary();
    let _ = std::fs::remove_dir_all(&dir);
}
