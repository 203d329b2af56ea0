//! Coarse trial fits (`SplitOptions::coarse`), `metabezier fit`'s default
//! for a tolerance: every contour still meets the tolerance, the segment
//! counts stay at or below those of full trials (recorded here from
//! `--trials full`), the search spends fewer evaluations, and
//! `--trials full` is the fit without them.

use std::process::Command;

/// What `metabezier fit INPUT --tolerance T --trials TRIALS` reports: the
/// segment count, the largest two-sided distance beyond the staircase it
/// says it held, the evaluations, and the `segmentation` column of its
/// `metrics.csv`.
struct Run {
    segments: usize,
    held: f64,
    evaluations: u64,
    segmentation: String,
}

fn run(input: &str, tolerance: f64, trials: &str) -> Run {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args(["fit", input, "--outputs", "csv", "--trials", trials])
        .arg("--tolerance")
        .arg(tolerance.to_string())
        .arg("--out")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{input} {trials}: {stdout}");
    let word_before = |text: &str, tail: &str| -> String {
        let head = &text[..text.find(tail).unwrap_or_else(|| panic!("{tail}: {text}"))];
        head.rsplit(' ').next().unwrap().to_owned()
    };
    let first = stdout.lines().next().unwrap();
    let held_line = stdout
        .lines()
        .find(|l| l.contains("held: largest"))
        .unwrap();
    // "… held: largest <what> <distance> (curve sampled …)".
    let held = held_line.split(" (").next().unwrap().rsplit(' ').next();
    let metrics = std::fs::read_to_string(dir.path().join("out/metrics.csv")).unwrap();
    let header: Vec<&str> = metrics.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|&h| h == "segmentation").unwrap();
    let row = metrics.lines().nth(1).unwrap();
    Run {
        segments: word_before(first, " segments,").parse().unwrap(),
        held: held.unwrap().parse().unwrap(),
        evaluations: word_before(first, " evaluations,").parse().unwrap(),
        segmentation: row.split(',').nth(column).unwrap().to_owned(),
    }
}

#[test]
fn coarse_trials_hold_the_tolerance_with_no_more_segments_than_full_ones() {
    // (input, tolerance, segments with --trials full): potrace's two-sided
    // distances on the horse and the coin (make peer-potrace), and two
    // glyphs in font units.
    for (input, tolerance, full_segments) in [
        ("data/outlines/horse.png", 1.94, 32),
        ("data/outlines/coin.png", 0.684437, 3),
        ("font:data/outlines/DejaVuSans.ttf:S", 2.0, 9),
        ("font:data/outlines/Cantarell-Regular.otf:a", 5.0, 8),
    ] {
        let coarse = run(input, tolerance, "coarse");
        assert!(coarse.held <= tolerance, "{input}: {}", coarse.held);
        assert!(
            coarse.segments <= full_segments,
            "{input}: {} segments, {full_segments} with full trials",
            coarse.segments
        );
        assert_eq!(coarse.segmentation, "tolerance (coarse trials)", "{input}");
    }
}

#[test]
fn full_trials_are_the_fit_before_and_cost_more() {
    let coarse = run("data/outlines/horse.png", 1.94, "coarse");
    let full = run("data/outlines/horse.png", 1.94, "full");
    assert_eq!(full.segmentation, "tolerance");
    // The fit before coarse trials (issue 52): 32 segments, 30,616
    // evaluations, 1.8754 px.
    assert_eq!((full.segments, full.evaluations), (32, 30_616));
    assert!((full.held - 1.8754).abs() < 1e-4, "{}", full.held);
    // Coarse trials spend at most two thirds of that (about half).
    assert!(
        3 * coarse.evaluations <= 2 * full.evaluations,
        "{} against {}",
        coarse.evaluations,
        full.evaluations
    );
}
