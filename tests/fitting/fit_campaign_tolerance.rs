//! `tolerance = T` in a `[[fit]]` section: every method fits the segments
//! of the exact fit to `T`, and `fits.csv` records the two-sided distance.

use std::path::Path;

use metabezier::experiment::{run_campaign, RunOptions, Spec};
use metabezier::fit::{ErrorMeasure, FitOptions, FunctionType};
use metabezier::geometry::Continuity;
use metabezier::outline::CornerOptions;
use metabezier::reconstruction::{LoadOptions, Method, Reconstruction, Segmentation, Source};

fn write_spec(dir: &Path, body: &str) -> std::path::PathBuf {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/coin.png");
    std::fs::copy(data, dir.join("coin.png")).unwrap();
    let path = dir.join("spec.toml");
    std::fs::write(
        &path,
        format!(
            "[experiment]\nname = \"tol\"\nseed = 3\nruns = 2\nbudget = 400\n\n[[fit]]\n\
             input = \"coin.png\"\nfunction = \"rational-cubic\"\ncontinuity = \"g1\"\n\
             closing = \"smooth\"\nerror = \"orthogonal\"\n{body}\n\n\
             [[algorithm]]\nname = \"lm\"\n\n[[algorithm]]\nname = \"mhs\"\n"
        ),
    )
    .unwrap();
    path
}

#[test]
fn a_tolerance_section_fits_every_method_to_the_exact_fits_segments() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = Spec::load(&write_spec(tmp.path(), "tolerance = 0.5")).unwrap();
    // The exact fit to 0.5 px, as the command line makes it.
    let source = Source::load(
        &tmp.path().join("coin.png").display().to_string(),
        Path::new(""),
        &LoadOptions::default(),
    )
    .unwrap();
    let exact = Reconstruction {
        source: &source,
        segmentation: Segmentation::Tolerance(0.5),
        corners: Some(CornerOptions::default()),
        options: FitOptions {
            error: ErrorMeasure::Orthogonal,
            closing: metabezier::fit::Closing::Smooth,
            ..FitOptions::new(FunctionType::RationalCubic, Continuity::G1)
        },
    }
    .fit(&Method::Exact, 0)
    .unwrap();
    let segments = exact.metrics.segments;
    assert!(segments >= 3, "{segments}");
    assert_eq!(spec.problems.len(), 1);
    assert_eq!(spec.problems[0].dim, segments);

    let out = tmp.path().join("out");
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        resume: false,
        shard: None,
        max_runs: None,
        progress: false,
        allow_large: false,
    };
    run_campaign(&spec, &opts).unwrap();
    let fits = std::fs::read_to_string(out.join("fits.csv")).unwrap();
    let mut lines = fits.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (max, curve, hausdorff) = (col("max_distance"), col("curve_distance"), col("hausdorff"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            [max, curve, hausdorff]
                .map(|k| f[k].parse().unwrap())
                .to_vec()
        })
        .collect();
    assert_eq!(rows.len(), 4, "{fits}");
    // The Hausdorff distance is at least either side (its data side also
    // samples the polyline between the data points).
    for r in &rows {
        assert!(r[2] >= r[0].max(r[1]), "{fits}");
    }
    // LM on the exact fit's own segments holds the tolerance; each row
    // records where a method stands against it.
    assert!(rows.iter().any(|r| r[2] <= 0.5 + 1e-9), "{fits}");
}

#[test]
fn a_tolerance_beside_segments_or_out_of_range_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    for (body, message) in [
        (
            "tolerance = 1\nsegments = 4",
            "expected either tolerance or segments, not both",
        ),
        ("tolerance = 0", "expected a distance > 0"),
        ("tolerance = \"fine\"", "expected a real number"),
    ] {
        let e = Spec::load(&write_spec(tmp.path(), body)).unwrap_err();
        assert!(e.field.ends_with("tolerance"), "{body}: {}", e.field);
        assert!(e.message.contains(message), "{body}: {}", e.message);
    }
}

/// `stop = "target"` is for benchmark runs: a spec with `[[fit]]` problems,
/// which have no target, is refused at the `stop` line.
#[test]
fn stop_at_target_is_refused_for_fits() {
    let tmp = tempfile::tempdir().unwrap();
    let path = write_spec(tmp.path(), "tolerance = 0.5");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(
        &path,
        text.replace("budget = 400\n", "budget = 400\nstop = \"target\"\n"),
    )
    .unwrap();
    let e = Spec::load(&path).unwrap_err();
    assert_eq!((e.field.as_str(), e.line), ("experiment.stop", 6), "{e}");
    assert!(
        e.to_string()
            .contains("[[fit]] problems, which have no target"),
        "{e}"
    );
}
