//! Glyphs with every contour, `metabezier score` on other curves and its
//! refusals, too many segments refused, and the command line's default on the
//! horse.

use super::campaigns::spec_error;
use super::*;

/// Runs `metabezier` with `args` in the data directory; (status, stdout,
/// stderr).
fn cli(args: &[&str]) -> (bool, String, String) {
    let out = metabezier()
        .current_dir(data())
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// The `all` row of a `metrics.csv`, as column name → value.
fn all_row(dir: &Path) -> std::collections::HashMap<String, String> {
    let text = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let all: Vec<&str> = lines.last().unwrap().split(',').collect();
    header
        .iter()
        .zip(all)
        .map(|(h, v)| (h.to_string(), v.to_string()))
        .collect()
}

#[test]
fn glyphs_keep_every_contour_and_are_recovered_at_their_own_breaks() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    // B: the outer contour and two counters, holes clockwise.
    let (ok, stdout, err) = cli(&[
        "fit",
        "font:DejaVuSans.ttf:B",
        "--true-breaks",
        "--algorithm",
        "lm",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("3 contour(s)"), "{stdout}");
    let metrics = std::fs::read_to_string(tmp.path().join("metrics.csv")).unwrap();
    assert_eq!(metrics.lines().count(), 1 + 3 + 1, "{metrics}");
    assert_eq!(
        metrics.matches(",counter-clockwise,").count(),
        1,
        "{metrics}"
    );
    assert_eq!(metrics.matches(",clockwise,").count(), 2, "{metrics}");
    let fit_csv = std::fs::read_to_string(tmp.path().join("fit.csv")).unwrap();
    for contour in ["0", "1", "2"] {
        assert!(fit_csv
            .lines()
            .any(|l| l.starts_with(&format!("{contour},"))));
    }
    // Quadratic TrueType glyphs at their own breaks, with the default
    // parameterisation (auto: the samples' own, uniform, parameters) and G1:
    // recovered to 1e-6 font units. The 'a' has a segment too short for a
    // rational cubic at the default sampling; it gets more samples of the
    // exact outline instead of stopping the fit.
    for (glyph, function) in [
        ("S", "quadratic"),
        ("o", "quadratic"),
        ("8", "cubic"),
        ("a", "rational-cubic"),
    ] {
        let input = format!("font:DejaVuSans.ttf:{glyph}");
        let (ok, _, err) = cli(&[
            "fit",
            &input,
            "--true-breaks",
            "--algorithm",
            "lm",
            "--function",
            function,
            "--out",
            out,
        ]);
        assert!(ok, "{glyph}: {err}");
        let all = all_row(tmp.path());
        assert_eq!(all["parameterisation"], "uniform");
        let max: f64 = all["max_distance"].parse().unwrap();
        assert!(max < 1e-6, "{glyph} {function}: {max}");
    }
    // With the thesis's fixed-parameter E, chord-length parameters miss the
    // same glyph by font units; the orthogonal E (the command line's
    // default) solves for the parameters and recovers it from the same start.
    for (error, bound) in [("fixed", None), ("orthogonal", Some(1e-6))] {
        let (ok, _, _) = cli(&[
            "fit",
            "font:DejaVuSans.ttf:S",
            "--true-breaks",
            "--algorithm",
            "lm",
            "--function",
            "quadratic",
            "--parameterisation",
            "chord",
            "--error",
            error,
            "--out",
            out,
        ]);
        assert!(ok);
        let all = all_row(tmp.path());
        assert_eq!(all["error"], error);
        let max: f64 = all["max_distance"].parse().unwrap();
        match bound {
            None => assert!(max > 1.0, "{max}"),
            Some(b) => assert!(max < b, "{max}"),
        }
    }
}

/// A closed square of side 10 with `n` points per side, as a CSV file.
fn square_csv(dir: &Path, n: usize) -> std::path::PathBuf {
    let mut text = String::from("x,y\n");
    let corners = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        for j in 0..n {
            let t = j as f64 / n as f64;
            text.push_str(&format!(
                "{},{}\n",
                a.0 + t * (b.0 - a.0),
                a.1 + t * (b.1 - a.1)
            ));
        }
    }
    text.push_str("0,0\n");
    let path = dir.join("square.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn score_measures_other_curves_against_the_same_points() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 20);
    // The square moved one unit right, in SVG's y-down user space (the
    // viewBox spans y 0..20, so y_up = 20 − y).
    let svg = tmp.path().join("shifted.svg");
    std::fs::write(
        &svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 20 20\">\n\
         <path d=\"M 1 20 H 11 V 10 H 1 Z\"/>\n</svg>\n",
    )
    .unwrap();
    let sq = square.to_str().unwrap();
    let (ok, stdout, err) = cli(&[
        "score",
        sq,
        svg.to_str().unwrap(),
        "--out",
        tmp.path().to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("4 segments"), "{stdout}");
    let csv = std::fs::read_to_string(tmp.path().join("score.csv")).unwrap();
    let all: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    assert_eq!(all[4], "all");
    assert_eq!(all[7].parse::<f64>().unwrap(), 1.0, "{csv}");
    // The offset moves it back: every point on the curves.
    let (ok, stdout, _) = cli(&["score", sq, svg.to_str().unwrap(), "--offset", "-1,0"]);
    assert!(ok);
    let all: Vec<&str> = stdout.lines().last().unwrap().split_whitespace().collect();
    assert_eq!(all[..2], ["all", "80"], "{stdout}");
    assert!(all[2].parse::<f64>().unwrap() < 1e-12, "{stdout}");

    // potrace's trace of the horse (vendored): 101 segments, pixel corners
    // at integers, hence the offset.
    let (ok, stdout, err) = cli(&[
        "score",
        "horse.png",
        "horse-potrace.svg",
        "--offset",
        "-0.5,-0.5",
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("101 segments"), "{stdout}");
    let all = stdout
        .lines()
        .last()
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>();
    let (max, rms): (f64, f64) = (all[2].parse().unwrap(), all[3].parse().unwrap());
    assert!(
        (max - 1.940).abs() < 1e-3 && (rms - 0.331).abs() < 1e-3,
        "{stdout}"
    );

    // Our own fit.svg reads back in the outline frame with no offset.
    let out = tmp.path().join("fit");
    let (ok, _, err) = cli(&[
        "fit",
        "horse.png",
        "--algorithm",
        "lm",
        "--segments",
        "101",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let fit_max: f64 = all_row(&out)["max_distance"].parse().unwrap();
    let (ok, stdout, _) = cli(&["score", "horse.png", out.join("fit.svg").to_str().unwrap()]);
    assert!(ok);
    let all = stdout
        .lines()
        .last()
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>();
    let scored: f64 = all[2].parse().unwrap();
    assert!(
        scored <= fit_max + 1e-3 && scored > fit_max - 0.05,
        "{scored} vs {fit_max}"
    );
}

#[test]
fn bad_curves_and_contours_are_named_with_their_place() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 5);
    let sq = square.to_str().unwrap();
    let write = |name: &str, text: &str| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let cases = [
        (
            "none.svg",
            "<svg>\n<rect width=\"1\" height=\"1\"/>\n</svg>\n",
            "none.svg: no <path> element with a \"d\" attribute",
        ),
        (
            "arc.svg",
            "<svg>\n<path d=\"M 0 0 A 5 5 0 0 1 10 0\"/>\n</svg>\n",
            "arc.svg:2:16: unsupported path command 'A'",
        ),
        (
            "nan.svg",
            "<svg>\n<path d=\"M 0 0 L NaN 3\"/>\n</svg>\n",
            "nan.svg:2:18: expected a number, found \"NaN\"",
        ),
    ];
    for (name, text, expected) in cases {
        let path = write(name, text);
        let (ok, _, err) = cli(&["score", sq, &path]);
        assert!(!ok);
        assert!(
            err.starts_with("metabezier: error: ") && err.contains(expected),
            "{err}"
        );
    }
    let path = write("ok.svg", "<svg><path d=\"M0 0 L 1 1\"/></svg>");
    let (ok, _, err) = cli(&["score", sq, &path, "--contour", "2"]);
    assert!(!ok);
    assert!(
        err.contains("square.csv: contour 2 was asked for, but the input has 1 contour"),
        "{err}"
    );
    let (ok, _, err) = cli(&["score", sq, &path, "--offset", "a,b"]);
    assert!(!ok);
    assert!(
        err.contains("expected an offset DX,DY of two finite numbers"),
        "{err}"
    );
}

/// `score` used to panic (exit 101) on a transform "a)b(", print `inf`
/// distances with exit 0 for an SVG that draws nothing or has 1e308
/// coordinates, and score paths inside `<defs>`.
#[test]
fn score_refuses_what_it_cannot_measure_and_skips_what_is_not_drawn() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 5);
    let sq = square.to_str().unwrap();
    let write = |name: &str, text: &str| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let cases = [
        (
            "paren.svg",
            "<svg>\n<g transform=\"a)b(\"><path d=\"M0 0 L 1 1\"/></g>\n</svg>\n",
            "paren.svg:2:15: unsupported transform \"a)b(\"",
        ),
        (
            "empty.svg",
            "<svg>\n<path d=\"M 3 3\"/>\n</svg>\n",
            "empty.svg: no drawable segment: 1 rendered <path> element(s) draw no line or curve",
        ),
        (
            "huge.svg",
            "<svg>\n<path d=\"M 0 0 L 1e308 1e308\"/>\n</svg>\n",
            "huge.svg:2:16: a coordinate (after the transforms) 1e308 is beyond ±1e15",
        ),
        (
            "defs.svg",
            "<svg>\n<defs><path d=\"M 0 0 L 10 10\"/></defs>\n</svg>\n",
            "defs.svg: no drawable segment: 0 rendered <path> element(s) draw no line or curve, and 1 <path> element(s) inside non-rendered containers",
        ),
    ];
    for (name, text, expected) in cases {
        let path = write(name, text);
        let out = metabezier()
            .current_dir(data())
            .args(["score", sq, &path])
            .output()
            .unwrap();
        let (stdout, err) = (
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        );
        assert_eq!(out.status.code(), Some(1), "{name}: {stdout}{err}");
        assert!(
            !stdout.contains("inf") && !stdout.contains("NaN"),
            "{stdout}"
        );
        assert!(
            err.starts_with("metabezier: error: ") && err.contains(expected),
            "{name}: {err}"
        );
    }
    // An offset that moves the curves out of range is refused by score.
    let ok_svg = write("ok.svg", "<svg><path d=\"M0 0 L 10 0\"/></svg>");
    let (ok, stdout, err) = cli(&["score", sq, &ok_svg, "--offset", "1e300,0"]);
    assert!(!ok, "{stdout}");
    assert!(
        err.contains("ok.svg: segment 0 of subpath 0 has the control point (1e300, 0e0)"),
        "{err}"
    );
    // A path in <defs> is skipped and the rest is scored as if it were not there.
    let with_defs = write(
        "with_defs.svg",
        "<svg viewBox=\"0 0 10 10\"><defs><path d=\"M 0 10 L 5 5\"/></defs>\n\
         <path d=\"M 0 10 H 10 V 0 H 0 Z\"/></svg>",
    );
    let (ok, stdout, err) = cli(&["score", sq, &with_defs]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains(": 4 segments (1 path(s) in non-rendered containers skipped)"),
        "{stdout}"
    );
    let all: Vec<&str> = stdout.lines().last().unwrap().split_whitespace().collect();
    assert_eq!(all[..2], ["all", "20"], "{stdout}");
    assert!(all[2].parse::<f64>().unwrap() < 1e-12, "{stdout}");
}

/// The library's `score` refuses an empty set of curves (every distance
/// would be infinite) and coordinates beyond its range.
#[test]
fn score_never_returns_an_infinite_distance() {
    use metabezier::geometry::Point;
    use metabezier::outline::{Outline, Segment};
    use metabezier::reconstruction::{score, ScoreError};
    let pts = vec![Point::ZERO, Point::new(1.0, 0.0), Point::new(0.0, 1.0)];
    let source = Source::from_outline("tri", Outline::new(pts, true));
    assert_eq!(score(&source, &[]), Err(ScoreError::NoSegment));
    assert_eq!(score(&source, &[vec![]]), Err(ScoreError::NoSegment));
    let line = |a: Point, b: Point| vec![vec![Segment::Line(a, b)]];
    let e = score(&source, &line(Point::ZERO, Point::new(f64::NAN, 0.0))).unwrap_err();
    assert!(
        matches!(
            e,
            ScoreError::CurveRange {
                subpath: 0,
                segment: 0,
                ..
            }
        ),
        "{e}"
    );
    let far = Source::from_outline(
        "far",
        Outline::new(vec![Point::new(1e300, 0.0), Point::ZERO], false),
    );
    let e = score(&far, &line(Point::ZERO, Point::new(1.0, 0.0))).unwrap_err();
    assert_eq!(
        e.to_string(),
        "data point 0 of contour 0 is (1e300, 0e0), beyond ±1e16, the range of coordinates scored"
    );
    let s = score(&source, &line(Point::ZERO, Point::new(1.0, 0.0))).unwrap();
    assert!(s.total.max_distance.is_finite() && s.total.rms_distance.is_finite());
}

/// `fit --segments 1000000` on 40 points used to fit 39 segments without a
/// word; the same rule holds for the library (and so for campaigns).
#[test]
fn more_segments_than_the_outline_allows_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let mut text = String::new();
    for i in 0..40 {
        let t = i as f64 * std::f64::consts::TAU / 40.0;
        text.push_str(&format!("{},{}\n", 10.0 * t.cos(), 10.0 * t.sin()));
    }
    let open = tmp.path().join("open40.csv");
    std::fs::write(&open, &text).unwrap();
    let e = fit_error(&[open.to_str().unwrap(), "--segments", "1000000"]);
    assert_eq!(
        e,
        format!(
            "metabezier: error: {}: contour 0: 1000000 segment(s) requested, but an open outline of 40 points allows at most 39 (each segment spans at least one gap between consecutive points); ask for at most 39\n",
            open.display()
        )
    );
    // Closed (the first point repeated at the end): 40 gaps, so 40 segments.
    text.push_str("10,0\n");
    let closed = tmp.path().join("closed40.csv");
    std::fs::write(&closed, &text).unwrap();
    let e = fit_error(&[closed.to_str().unwrap(), "--segments", "41"]);
    assert!(
        e.contains("a closed outline of 40 points allows at most 40"),
        "{e}"
    );
    let source = Source::load(
        closed.to_str().unwrap(),
        Path::new(""),
        &LoadOptions::default(),
    )
    .unwrap();
    let r = Reconstruction {
        source: &source,
        segmentation: Segmentation::Count(usize::MAX),
        corners: Some(CornerOptions::default()),
        options: FitOptions::new(FunctionType::Cubic, Continuity::G1),
    };
    let e = r.fit(&Method::Exact, 1).unwrap_err();
    assert!(e.to_string().contains("allows at most 40"), "{e}");
    let r = Reconstruction {
        segmentation: Segmentation::Count(40),
        ..r
    };
    let fit = r.fit(&Method::Exact, 1).unwrap();
    assert_eq!(fit.segments().count(), 40);
}

/// A campaign's fit problems share the rule: a spec asking for more
/// segments than the outline has gaps is refused at the `segments` field
/// when it is checked (before, its cells silently fitted fewer).
#[test]
fn a_spec_asking_for_more_segments_than_the_outline_allows_is_refused() {
    let head = "[experiment]\nname = \"x\"\nseed = 1\nruns = 1\nbudget = 100\n\n";
    let e = spec_error(&format!(
        "{head}[[fit]]\ninput = \"coin.png\"\nsegments = 1000\n\n[[algorithm]]\nname = \"hs\"\n"
    ));
    let points = source("coin.png").contours[0].outline.len();
    assert_eq!(
        e,
        format!(
            "9:12: fit[1].segments: coin/rational-cubic/g1: contour 0: 1000 segment(s) requested, but a closed outline of {points} points allows at most {points} (each segment spans at least one gap between consecutive points); ask for at most {points}"
        )
    );
}

#[test]
fn the_command_line_default_fits_the_horse_within_a_pixel() {
    // `metabezier fit` defaults to LM with the orthogonal error and the joint
    // chain: the horse at 101 rational cubics, G1, within 1 px everywhere and
    // 0.30 px RMS (potrace at 101 segments: 1.94 and 0.331 px; the thesis's
    // fixed-parameter E with the sequential chain: 1.33 and 0.316 px).
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["fit", "horse.png", "--segments", "101", "--out", out];
        args.extend_from_slice(extra);
        let (ok, _, err) = cli(&args);
        assert!(ok, "{err}");
        all_row(tmp.path())
    };
    let all = run(&[]);
    assert_eq!(
        (
            all["algorithm"].as_str(),
            all["error"].as_str(),
            all["chain"].as_str()
        ),
        ("lm", "orthogonal", "joint")
    );
    let max: f64 = all["max_distance"].parse().unwrap();
    let rms: f64 = all["rms_distance"].parse().unwrap();
    assert!(max <= 1.0 && rms <= 0.30, "max {max}, RMS {rms}");
    let e =
        |row: &std::collections::HashMap<String, String>| -> f64 { row["sse"].parse().unwrap() };
    let sequential = run(&["--chain", "sequential"]);
    assert!(
        e(&all) < 0.99 * e(&sequential),
        "{} vs {}",
        e(&all),
        e(&sequential)
    );
    let fixed = run(&["--error", "fixed", "--chain", "sequential"]);
    let fixed_max: f64 = fixed["max_distance"].parse().unwrap();
    assert!(fixed_max > 1.2, "{fixed_max}");
    // The joint chain lowers the thesis's E too, by a third.
    let fixed_joint = run(&["--error", "fixed"]);
    assert!(
        e(&fixed_joint) < 0.7 * e(&fixed),
        "{} vs {}",
        e(&fixed_joint),
        e(&fixed)
    );
}
