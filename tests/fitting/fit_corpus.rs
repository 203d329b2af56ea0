//! `metabezier fit` as a new user runs it: plain `fit INPUT`, no options, on
//! outlines it was not tuned on. Every input of the corpus must exit 0 with
//! its Hausdorff distance held to the default tolerance (1 unit), checked
//! from the files it writes; the traced images' figures are checked again
//! by brute force.
//!
//! The corpus: 12 glyphs of each of two font families (DejaVu Sans, a
//! TrueType font of quadratic outlines, and Cantarell, an OpenType CFF font
//! of cubic ones) and three scikit-image pictures (the horse, a coin, the
//! scikit-image logo, whose dark shape covers most of the image). All are
//! vendored in `data/outlines/` with their licences and provenance
//! (`data/outlines/PROVENANCE.md`).

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::geometry::{nearest, Curve, Point};
use metabezier::outline::{Foreground, ImageOptions};
use metabezier::reconstruction::{LoadOptions, Method, Reconstruction, Segmentation, Source};

/// The glyphs fitted of each font.
const GLYPHS: &str = "aAgG@&8%BRQS";

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/outlines")
        .join(name)
}

/// The corpus's inputs as `metabezier fit` takes them.
fn corpus() -> Vec<String> {
    let mut inputs = Vec::new();
    for font in ["DejaVuSans.ttf", "Cantarell-Regular.otf"] {
        for g in GLYPHS.chars() {
            inputs.push(format!("font:{}:{g}", data(font).display()));
        }
    }
    for image in ["horse.png", "coin.png", "logo.png"] {
        inputs.push(data(image).display().to_string());
    }
    inputs
}

/// The `all` row of a fit's `metrics.csv`, column by name.
fn all_row(out: &Path) -> impl Fn(&str) -> String {
    let text = std::fs::read_to_string(out.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let all = lines.last().unwrap();
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(all.as_bytes());
    let row: Vec<String> = reader
        .records()
        .next()
        .unwrap()
        .unwrap()
        .iter()
        .map(str::to_owned)
        .collect();
    move |name: &str| {
        let k = header.iter().position(|h| h == name).expect(name);
        row[k].clone()
    }
}

#[test]
fn plain_fit_holds_one_unit_on_every_input_of_the_corpus() {
    let dir = tempfile::tempdir().unwrap();
    for (k, input) in corpus().iter().enumerate() {
        let out = dir.path().join(k.to_string());
        let run = Command::new(env!("CARGO_BIN_EXE_metabezier"))
            .args(["fit", input, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert!(run.status.success(), "{input}: {stderr}");
        let col = all_row(&out);
        let num = |name: &str| col(name).parse::<f64>().unwrap();
        // Coarse trials, `fit`'s default since issue 52.
        assert_eq!(col("segmentation"), "tolerance (coarse trials)", "{input}");
        assert_eq!(num("tolerance"), 1.0, "{input}");
        let (hausdorff, excess) = (num("hausdorff"), num("hausdorff_excess"));
        let (data_side, curve_side) = (num("max_distance"), num("curve_distance"));
        // The two sides and their maximum, as the file states them.
        assert!(hausdorff >= data_side && hausdorff >= curve_side, "{input}");
        assert!(data_side <= 1.0, "{input}: data -> curve {data_side}");
        if input.starts_with("font:") {
            // Exact samples: no allowance, the plain two-sided distance.
            assert_eq!(col("tolerance_holds"), "hausdorff", "{input}");
            assert!(hausdorff <= 1.0, "{input}: {hausdorff}");
        } else {
            // A staircase: beyond its sagitta (at most 1/4 px for
            // mid-crack points), within the tolerance.
            assert_eq!(col("tolerance_holds"), "hausdorff_excess", "{input}");
            assert!(excess <= 1.0, "{input}: {excess}");
            assert!(hausdorff <= 1.25, "{input}: {hausdorff}");
        }
        let segments: usize = col("segments").parse().unwrap();
        assert!((1..200).contains(&segments), "{input}: {segments}");
    }
}

/// The distance from `q` to the edge `[a, b]`.
fn to_edge(q: Point, a: Point, b: Point) -> f64 {
    let d = b - a;
    let t = ((q - a).dot(d) / d.hypot2().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    q.distance(a + d * t)
}

#[test]
fn the_images_two_sided_distances_agree_with_brute_force() {
    for image in ["coin.png", "logo.png"] {
        let source = Source::load(
            &data(image).display().to_string(),
            Path::new(""),
            &LoadOptions::default(),
        )
        .unwrap();
        let r = Reconstruction {
            source: &source,
            segmentation: Segmentation::Tolerance(1.0),
            corners: Some(Default::default()),
            options: metabezier::fit::FitOptions {
                error: metabezier::fit::ErrorMeasure::Orthogonal,
                chain: metabezier::fit::Chain::Joint,
                continuity: metabezier::geometry::Continuity::G1,
                ..Default::default()
            },
        };
        let shape = r.fit(&Method::Exact, 1).unwrap();
        for (c, contour) in shape.contours.iter().zip(&source.contours) {
            let pts = &contour.outline.points;
            let edges: Vec<(Point, Point)> = (0..pts.len())
                .map(|i| (pts[i], pts[(i + 1) % pts.len()]))
                .collect();
            // Curve -> data: 2,000 samples a segment against every edge.
            let mut curve_side: f64 = 0.0;
            for s in &c.fit.segments {
                for j in 0..=2000 {
                    let q = s.segment.eval(j as f64 / 2000.0);
                    let d = edges
                        .iter()
                        .map(|&(a, b)| to_edge(q, a, b))
                        .fold(f64::INFINITY, f64::min);
                    curve_side = curve_side.max(d);
                }
            }
            // Data -> curve: every point to every segment.
            let data_side = pts
                .iter()
                .map(|&p| {
                    c.fit
                        .segments
                        .iter()
                        .map(|s| nearest(&s.segment, p).1)
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0f64, f64::max);
            let m = &c.fit.metrics;
            // The fit's own figures are per segment against its own span,
            // so never below the brute force against the whole outline; its
            // samples (8 a point gap) see all but the bulge between them,
            // a few hundredths of a pixel.
            assert!(m.max_distance >= data_side - 1e-9, "{image}");
            assert!(
                m.curve_distance >= curve_side - 0.05,
                "{image} contour {}: {} vs brute force {curve_side}",
                c.contour,
                m.curve_distance
            );
            assert!(curve_side <= 1.25 && data_side <= 1.0, "{image}");
        }
    }
}

#[test]
fn the_logo_is_traced_as_its_dark_shape_not_the_image_frame() {
    let logo = data("logo.png").display().to_string();
    let load = |foreground| {
        let options = LoadOptions {
            image: ImageOptions {
                foreground,
                ..ImageOptions::default()
            },
            ..LoadOptions::default()
        };
        Source::load(&logo, Path::new(""), &options).unwrap()
    };
    let touches_frame = |s: &Source| {
        let p = &s.contours[0].outline.points;
        let (lo, hi) = p.iter().fold((f64::MAX, f64::MIN), |(lo, hi), q| {
            (lo.min(q.x.min(q.y)), hi.max(q.x.max(q.y)))
        });
        lo <= 0.5 && hi >= 498.5
    };
    // The dark class is the larger one, but it does not touch the border.
    let auto = load(Foreground::Auto);
    assert!(!touches_frame(&auto), "auto traced the frame");
    assert_eq!(
        auto.contours[0].outline.points,
        load(Foreground::Dark).contours[0].outline.points
    );
    // Light is the background: its largest contour is the frame.
    assert!(touches_frame(&load(Foreground::Light)));
}

#[test]
fn foreground_is_refused_for_a_csv_outline() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("square.csv");
    std::fs::write(&csv, "x,y\n0,0\n10,0\n10,10\n0,10\n0,0\n").unwrap();
    let run = Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .arg("fit")
        .arg(&csv)
        .args(["--foreground", "dark", "--out"])
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    assert!(!run.status.success());
    let e = String::from_utf8_lossy(&run.stderr);
    assert!(
        e.contains("--foreground") && e.contains("not an image"),
        "{e}"
    );
    assert!(!dir.path().join("out").exists());
}
