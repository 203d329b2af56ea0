//! The per-segment columns of fitting results: one row per segment with its
//! control points, weights and metrics, in `fit.csv` of `metabezier fit`
//! and, after the run key, in `segments.csv` of a fitting campaign.
//!
//! Numbers are written with Rust's shortest round-trip formatting, so a
//! segment read back with [`segment_from_row`] is bit-identical.

use crate::fit::{FunctionType, PiecewiseFit, Segment};
use crate::geometry::{CubicBez, Point, QuadBez, RationalCubicBez, RationalQuadBez};

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

/// Rebuilds a segment from the [`SEGMENT_HEADER`] columns of a row (as
/// written by [`segment_rows`]); `None` if a field is missing or invalid.
pub fn segment_from_row(row: &[String]) -> Option<Segment> {
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
