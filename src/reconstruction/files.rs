//! The files of a fit: one CSV row per segment (control points, weights,
//! segment metrics), the fit's totals, and the overlay figure.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so the
//! files are byte-identical for the same fit. Wall time goes to a separate
//! `timing.csv`, as in campaign results.

use std::path::{Path, PathBuf};

use crate::error::{write_atomic, Error};
use crate::fit::{FunctionType, PiecewiseFit, Segment};
use crate::geometry::{Curve, Point};
use crate::records::csv_bytes;
use crate::report::{OverlayCurve, OverlayFigure, OverlayPanel};

/// Control points per segment row: enough for a cubic (`C0..C3`).
const MAX_CONTROL: usize = 4;

/// The per-segment columns of `fit.csv` (and of campaign `segments.csv`,
/// after its run columns).
pub const SEGMENT_HEADER: [&str; 22] = [
    "segment",
    "first",
    "last",
    "points",
    "join",
    "function",
    "c0x",
    "c0y",
    "c1x",
    "c1y",
    "c2x",
    "c2y",
    "c3x",
    "c3y",
    "w0",
    "w1",
    "w2",
    "w3",
    "sse",
    "rms",
    "max_distance",
    "evaluations",
];

/// One row per segment of `fit`, matching [`SEGMENT_HEADER`]: quadratic
/// segments leave `c3x, c3y, w3` empty, polynomial segments have unit
/// weights.
pub fn segment_rows(fit: &PiecewiseFit) -> Vec<Vec<String>> {
    fit.segments
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let mut row = vec![
                k.to_string(),
                s.first.to_string(),
                s.last.to_string(),
                s.metrics.points.to_string(),
                s.join.name().to_owned(),
                s.segment.function().name().to_owned(),
            ];
            let cps = s.segment.control_points();
            for i in 0..MAX_CONTROL {
                match cps.get(i) {
                    Some(p) => {
                        row.push(p.x.to_string());
                        row.push(p.y.to_string());
                    }
                    None => row.extend([String::new(), String::new()]),
                }
            }
            let ws = s.segment.weights();
            for i in 0..MAX_CONTROL {
                row.push(ws.get(i).map_or(String::new(), |w| w.to_string()));
            }
            row.push(s.metrics.sse.to_string());
            row.push(s.metrics.rms.to_string());
            row.push(s.metrics.max_distance.to_string());
            row.push(s.metrics.evaluations.to_string());
            row
        })
        .collect()
}

/// The fitted curve of `fit` for an overlay: each segment sampled at 65
/// points and, if `polygons`, its control polygon.
pub fn overlay_curve(label: String, fit: &PiecewiseFit, polygons: bool) -> OverlayCurve {
    OverlayCurve {
        label,
        segments: fit.segments.iter().map(|s| sample(&s.segment)).collect(),
        control_polygons: if polygons {
            fit.segments
                .iter()
                .map(|s| s.segment.control_points())
                .collect()
        } else {
            Vec::new()
        },
    }
}

/// Writes `fit.csv`, `metrics.csv`, `timing.csv`, `fit.svg` and `fit.png`
/// into `dir` (created if missing); returns the paths.
///
/// `case` holds the descriptive columns of `metrics.csv` (input, function,
/// continuity, method, seed, …), written before the fit's totals.
pub fn write_fit(
    dir: &Path,
    title: &str,
    data: &[Point],
    fit: &PiecewiseFit,
    case: &[(&str, String)],
    wall_seconds: f64,
) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(dir).map_err(|e| Error::io("create the directory", dir, e))?;
    let mut written = Vec::new();

    let fit_csv = dir.join("fit.csv");
    write_atomic(&fit_csv, &csv_bytes(&SEGMENT_HEADER, segment_rows(fit)))?;
    written.push(fit_csv);

    let m = &fit.metrics;
    let mut header: Vec<&str> = case.iter().map(|(k, _)| *k).collect();
    let mut row: Vec<String> = case.iter().map(|(_, v)| v.clone()).collect();
    let closing = fit.closing;
    for (k, v) in [
        ("points", m.points.to_string()),
        ("segments", m.segments.to_string()),
        ("sse", m.sse.to_string()),
        ("rms", m.rms.to_string()),
        ("max_distance", m.max_distance.to_string()),
        ("evaluations", m.evaluations.to_string()),
        (
            "closing_angle_degrees",
            closing.map_or(String::new(), |c| c.angle_degrees.to_string()),
        ),
        (
            "closing_relative_derivative_gap",
            closing.map_or(String::new(), |c| c.relative_derivative_gap.to_string()),
        ),
    ] {
        header.push(k);
        row.push(v);
    }
    let metrics_csv = dir.join("metrics.csv");
    write_atomic(&metrics_csv, &csv_bytes(&header, [row]))?;
    written.push(metrics_csv);

    let timing_csv = dir.join("timing.csv");
    write_atomic(
        &timing_csv,
        &csv_bytes(&["wall_seconds"], [vec![wall_seconds.to_string()]]),
    )?;
    written.push(timing_csv);

    let figure = OverlayFigure {
        title: title.to_owned(),
        panels: vec![OverlayPanel {
            title: format!(
                "{} segments, E = {:.4e}, max distance {:.3e}",
                m.segments, m.sse, m.max_distance
            ),
            data: data.to_vec(),
            curves: vec![overlay_curve("fit".into(), fit, true)],
            y_down: false,
        }],
        columns: 1,
    };
    written.extend(figure.save(dir, "fit")?);
    Ok(written)
}

/// Rebuilds a segment from the [`SEGMENT_HEADER`] columns of a row (as
/// written by [`segment_rows`]); `None` if a field is missing or invalid.
pub fn segment_from_row(row: &[String]) -> Option<Segment> {
    use crate::geometry::{CubicBez, QuadBez, RationalCubicBez, RationalQuadBez};
    let col = |name: &str| SEGMENT_HEADER.iter().position(|h| *h == name);
    let num = |name: &str| -> Option<f64> { row.get(col(name)?)?.parse().ok() };
    let point = |i: usize| -> Option<Point> {
        Some(Point::new(num(&format!("c{i}x"))?, num(&format!("c{i}y"))?))
    };
    let function = FunctionType::from_name(row.get(col("function")?)?)?;
    Some(match function {
        FunctionType::Quadratic => {
            Segment::Quadratic(QuadBez::new(point(0)?, point(1)?, point(2)?))
        }
        FunctionType::Cubic => {
            Segment::Cubic(CubicBez::new(point(0)?, point(1)?, point(2)?, point(3)?))
        }
        FunctionType::RationalQuadratic => Segment::RationalQuadratic(
            RationalQuadBez::new(point(0)?, point(1)?, point(2)?, num("w1")?).ok()?,
        ),
        FunctionType::RationalCubic => Segment::RationalCubic(
            RationalCubicBez::new(
                point(0)?,
                point(1)?,
                point(2)?,
                point(3)?,
                num("w1")?,
                num("w2")?,
            )
            .ok()?,
        ),
    })
}

/// A fitted outline read back from its segment rows, for an overlay.
pub fn overlay_from_rows(label: String, rows: &[Vec<String>]) -> Option<OverlayCurve> {
    let segments: Vec<Segment> = rows
        .iter()
        .map(|r| segment_from_row(r))
        .collect::<Option<_>>()?;
    Some(OverlayCurve {
        label,
        segments: segments.iter().map(sample).collect(),
        control_polygons: Vec::new(),
    })
}

/// A segment sampled at 65 uniform parameters, for drawing.
fn sample(s: &Segment) -> Vec<Point> {
    const SAMPLES: usize = 64;
    (0..=SAMPLES)
        .map(|j| s.eval(j as f64 / SAMPLES as f64))
        .collect()
}
