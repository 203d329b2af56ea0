//! `--tolerance T` holds on the continuous curve: every data point is within
//! `T` of its segment, and every segment and the outline polyline of its
//! data are within `T` plus the polyline's own sagitta of each other on
//! both sides (the sagitta `|Δ²R|/8`, which no smooth curve through the
//! points can beat: 0 on straight runs, at most a quarter pixel at a pixel
//! staircase's turn). Checked here independently of the fit's own sampled
//! measure: a dense sampling of each curve against every edge, and of every
//! edge against the curve by the global closest-point search.

use std::path::Path;

use metabezier::fit::{outline_distance, ErrorMeasure, FitOptions, FunctionType, PiecewiseFit};
use metabezier::geometry::{nearest, Continuity, Curve, Point};
use metabezier::outline::CornerOptions;
use metabezier::reconstruction::{LoadOptions, Method, Reconstruction, Segmentation, Source};

/// The distance from `q` to the segment `[a, b]`.
fn to_edge(q: Point, a: Point, b: Point) -> f64 {
    let d = b - a;
    let t = ((q - a).dot(d) / d.hypot2().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    q.distance(a + d * t)
}

/// The two-sided distance of every segment of `fit` to its data polyline on
/// `points` (closed), by brute force: 4,000 curve samples against every
/// edge, 32 samples of every edge to the curve.
fn brute_force(fit: &PiecewiseFit, points: &[Point]) -> f64 {
    let n = points.len();
    let mut worst: f64 = 0.0;
    for s in &fit.segments {
        let last = if s.last <= s.first {
            s.last + n
        } else {
            s.last
        };
        let data: Vec<Point> = (s.first..=last).map(|i| points[i % n]).collect();
        for j in 0..=4000 {
            let c = s.segment.eval(j as f64 / 4000.0);
            let d = data
                .windows(2)
                .map(|w| to_edge(c, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        for w in data.windows(2) {
            for j in 0..=32 {
                let q = w[0].lerp(w[1], j as f64 / 32.0);
                worst = worst.max(nearest(&s.segment, q).1);
            }
        }
    }
    worst
}

#[test]
fn the_tolerance_holds_between_the_data_points() {
    let source = Source::load(
        "data/outlines/horse.png",
        Path::new(env!("CARGO_MANIFEST_DIR")),
        &LoadOptions::default(),
    )
    .unwrap();
    let points = source.contours[0].outline.points.clone();
    let n = points.len();
    // The largest sagitta of the closed pixel polyline.
    let sagitta = (0..n)
        .map(|j| {
            let (a, b, c) = (points[(j + n - 1) % n], points[j], points[(j + 1) % n]);
            (a - b * 2.0 + c).hypot() / 8.0
        })
        .fold(0.0f64, f64::max);
    assert!(sagitta > 0.1 && sagitta <= 0.25, "{sagitta}");
    for (tolerance, error) in [
        (0.5, ErrorMeasure::Orthogonal),
        (1.0, ErrorMeasure::Orthogonal),
        (2.0, ErrorMeasure::Fixed),
    ] {
        let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::G1);
        options.error = error;
        let r = Reconstruction {
            source: &source,
            segmentation: Segmentation::Tolerance(tolerance),
            corners: Some(CornerOptions::default()),
            options,
        };
        let shape = r.fit(&Method::Exact, 1).unwrap();
        let fit = &shape.contours[0].fit;
        let own = fit.metrics.hausdorff;
        assert!(
            fit.metrics.excess <= tolerance,
            "{tolerance}: {:?}",
            fit.metrics
        );
        let checked = brute_force(fit, &points);
        // Every data point within the tolerance; the two-sided distance
        // within it plus the sagitta, by the fit's own measure and by the
        // dense check, which agree to the fit's sampling.
        assert!(fit.metrics.max_distance <= tolerance, "{tolerance}");
        assert!(own <= tolerance + sagitta, "{tolerance}: {own}");
        assert!(
            checked <= own + 0.01 * tolerance,
            "{tolerance}: {checked} vs {own}"
        );
        assert!(fit.metrics.max_distance <= own);
    }
}

#[test]
fn a_loop_between_data_points_is_seen() {
    // A cubic through (0,0) and (3,0) that passes the data points (1, 0)
    // and (2, 0) nowhere near: it bulges 3/4 above the line.
    let c = metabezier::geometry::CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 1.0),
        Point::new(2.0, 1.0),
        Point::new(3.0, 0.0),
    );
    let pts: Vec<Point> = (0..=3).map(|k| Point::new(k as f64, 0.0)).collect();
    let d = outline_distance(&c, &pts);
    assert!((d.distance - 0.75).abs() < 1e-3, "{d:?}");
    // A straight polyline has no sagitta: all of it is excess.
    assert_eq!(d.excess, d.distance);
    assert_eq!(d.gap, 1);
    // The data points alone are within 0.67 of it.
    let at_points = pts.iter().map(|&p| nearest(&c, p).1).fold(0.0f64, f64::max);
    assert!(at_points < 0.7);
}
