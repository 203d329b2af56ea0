//! What a fit promises beyond its data points: no curve where there is no
//! data (whiskers), and the same bytes on every run.

use std::path::Path;

use metabezier::fit::{Chain, ErrorMeasure, FitOptions, FunctionType};
use metabezier::geometry::Continuity;
use metabezier::outline::CornerOptions;
use metabezier::reconstruction::{LoadOptions, Method, Reconstruction, Segmentation, Source};

/// An input of the repository (`data/outlines/horse.png`,
/// `font:data/outlines/DejaVuSans.ttf:Q`), loaded as `fit` loads it.
fn source(input: &str) -> Source {
    let base = Path::new(env!("CARGO_MANIFEST_DIR"));
    Source::load(input, base, &LoadOptions::default()).unwrap()
}

/// `metabezier fit`'s options: rational cubics joined G1, the orthogonal
/// error, the joint chain.
fn cli_options() -> FitOptions {
    FitOptions {
        error: ErrorMeasure::Orthogonal,
        chain: Chain::Joint,
        ..FitOptions::new(FunctionType::RationalCubic, Continuity::G1)
    }
}

#[test]
fn a_joint_solve_that_parks_curve_past_a_corner_is_not_kept() {
    // DejaVu Sans `Q` to 0.5 font units: the joint solve of the split's
    // chain parks curve some 200 units past the tail's corner, every data
    // point still within the tolerance; DejaVu `G` in 20 segments does the
    // same at its spur (about 110 units).
    let q = source("font:data/outlines/DejaVuSans.ttf:Q");
    let r = Reconstruction {
        source: &q,
        segmentation: Segmentation::Tolerance(0.5),
        corners: Some(CornerOptions::default()),
        options: cli_options(),
    };
    let fit = r.fit(&Method::Exact, 1).unwrap();
    let c = &fit.contours[0].fit;
    let strayed = c.joint_rejected.expect("the joint solve strays here");
    assert!(strayed > 100.0, "{strayed}");
    assert_eq!(c.chain, Chain::Sequential);
    // What is kept holds the tolerance on both sides.
    for c in &fit.contours {
        let m = &c.fit.metrics;
        assert!(m.curve_distance <= 0.5, "{m:?}");
        assert!(m.hausdorff <= 0.5, "{m:?}");
    }

    let g = source("font:data/outlines/DejaVuSans.ttf:G");
    let r = Reconstruction {
        source: &g,
        segmentation: Segmentation::Count(20),
        corners: Some(CornerOptions::default()),
        options: cli_options(),
    };
    let fit = r.fit(&Method::Exact, 1).unwrap();
    let c = &fit.contours[0].fit;
    assert!(c.joint_rejected.expect("strays") > 50.0);
    // No whisker left: no segment's curve runs more than half as far again
    // from the outline as its data do.
    for s in &c.segments {
        let m = &s.metrics;
        assert!(
            m.curve_distance <= 1.5 * m.max_distance.max(1e-9) + 0.25,
            "{m:?}"
        );
    }
}

/// A debug dump of a fit: every float printed in its shortest round-trip
/// form, so two dumps are equal exactly when the fits are bit for bit.
fn dump(r: &Reconstruction<'_>) -> String {
    format!("{:?}", r.fit_each(&Method::Exact, 1))
}

#[test]
fn a_multi_contour_fit_repeats_bit_for_bit_on_one_and_two_threads() {
    // The scikit-image logo: 11 contours, the default tolerance. The
    // reference fit, then 6 repeats in this thread and 2 × 6 in two
    // threads at once (anything shared between fits, or depending on
    // timing or allocation, would show).
    let source = source("data/outlines/logo.png");
    assert!(source.contours.len() > 5);
    let r = Reconstruction {
        source: &source,
        segmentation: Segmentation::Tolerance(1.0),
        corners: Some(CornerOptions::default()),
        options: cli_options(),
    };
    let reference = dump(&r);
    assert!(reference.contains("failed: []"), "a contour failed");
    for k in 0..6 {
        assert_eq!(dump(&r), reference, "repeat {k}");
    }
    std::thread::scope(|s| {
        let runs: Vec<_> = (0..2)
            .map(|_| s.spawn(|| (0..6).map(|_| dump(&r)).collect::<Vec<_>>()))
            .collect();
        for run in runs {
            for (k, d) in run.join().unwrap().iter().enumerate() {
                assert_eq!(*d, reference, "threaded repeat {k}");
            }
        }
    });
}

/// Runs `metabezier fit` with `args` into a fresh directory: the exit
/// status, stdout, stderr and the directory.
fn cli_fit(args: &[&str]) -> (bool, String, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("fit")
        .args(args)
        .arg("--out")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
        dir,
    )
}

#[test]
fn contours_that_fail_are_named_and_the_others_written_with_exit_1() {
    // 300 segments per contour: the logo's two large contours take them,
    // its nine small ones have fewer point gaps than that.
    let (ok, stdout, stderr, dir) = cli_fit(&["data/outlines/logo.png", "--segments", "300"]);
    assert!(!ok);
    assert!(stdout.starts_with("logo: 2 contour(s)"), "{stdout}");
    assert!(
        stderr.contains("9 of 11 contour(s) could not be fitted (the other 2 are in"),
        "{stderr}"
    );
    for k in 2..11 {
        assert!(
            stderr.contains(&format!("\n  contour {k}: 300 segment(s) requested")),
            "{stderr}"
        );
    }
    let metrics = std::fs::read_to_string(dir.path().join("out/metrics.csv")).unwrap();
    let header: Vec<&str> = metrics.lines().next().unwrap().split(',').collect();
    let at = header.iter().position(|h| *h == "contour").unwrap();
    let contours: Vec<&str> = metrics
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(at).unwrap())
        .collect();
    assert_eq!(contours, ["0", "1", "all"], "{metrics}");
}

#[test]
fn a_tolerance_below_the_noise_is_said() {
    // The logo at 0.1 px is below its pixel staircase: each contour is
    // named, with a tolerance below the points' estimated noise or a
    // segment every few points; most cannot be held to it and fail (exit
    // 1, the others written). The default says nothing.
    let (ok, _, stderr, _dir) = cli_fit(&["data/outlines/logo.png", "--tolerance", "0.1"]);
    assert!(!ok && stderr.contains("could not be fitted"), "{stderr}");
    for k in 0..11 {
        let line = stderr
            .lines()
            .find(|l| {
                l.starts_with(&format!(
                    "metabezier: note: contour {k}: the tolerance 0.1 "
                ))
            })
            .unwrap_or_else(|| panic!("contour {k}: {stderr}"));
        assert!(
            line.contains("follows the noise") || line.contains("follows the points' noise"),
            "{line}"
        );
    }
    let (ok, _, stderr, _dir) = cli_fit(&["data/outlines/logo.png"]);
    assert!(ok && stderr.is_empty(), "{stderr}");
}

#[test]
fn odd_outlines_get_a_documented_result() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        path.display().to_string()
    };
    // A one-pixel image has one grey level: refused, naming the file.
    let png = metabezier_plot::png::encode_png(&[0, 0, 0], 1, 1).unwrap();
    let one = write("one.png", &png);
    let (ok, _, stderr, out) = cli_fit(&[&one]);
    assert!(
        !ok && stderr.contains("one.png: every pixel has grey level 0"),
        "{stderr}"
    );
    assert!(!out.path().join("out").exists());
    // A bow tie is fitted as given, crossing where its points cross.
    let bow = write("bow.csv", b"x,y\n0,0\n10,10\n10,0\n0,10\n0,0\n");
    let (ok, stdout, stderr, _out) = cli_fit(&[&bow]);
    assert!(ok, "{stderr}");
    assert!(
        stdout.starts_with("bow: 1 contour(s), 4 points, 4 segments"),
        "{stdout}"
    );
    // A tolerance of 1e308 is a tolerance: one segment per corner span.
    let square = write(
        "square.csv",
        b"x,y\n0,0\n5,0\n10,0\n10,5\n10,10\n5,10\n0,10\n0,5\n0,0\n",
    );
    let (ok, stdout, stderr, _out) = cli_fit(&[&square, "--tolerance", "1e308"]);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("tolerance 1e308 held"), "{stdout}");
    // As few segments as the corners allow: these 8 points have one
    // corner, so one span round the loop, which one segment cannot close
    // smoothly on itself: two.
    assert!(stdout.contains("8 points, 2 segments,"), "{stdout}");
}

#[test]
fn the_horse_at_101_segments_keeps_its_accuracy_on_both_sides() {
    // potrace's segment count: the command line's defaults stay within
    // 0.91 px both ways (potrace's own trace: 1.94 px data -> curve) and
    // 0.23 px RMS.
    let source = source("data/outlines/horse.png");
    let r = Reconstruction {
        source: &source,
        segmentation: Segmentation::Count(101),
        corners: Some(CornerOptions::default()),
        options: cli_options(),
    };
    let m = r.fit(&Method::Exact, 1).unwrap().metrics;
    assert_eq!(m.segments, 101);
    assert!(m.max_distance <= 0.91 && m.hausdorff <= 0.91, "{m:?}");
    assert!(m.curve_distance <= 0.91 && m.rms_distance <= 0.23, "{m:?}");
}
