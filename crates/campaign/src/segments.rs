//! The per-segment columns of fitting results: one row per segment with its
//! control points, weights and metrics, in `fit.csv` of `metabezier fit`
//! and, after the run key, in `segments.csv` of a fitting campaign.
//!
//! Two layouts: [`FIT_SEGMENT_HEADER`], with the segment's `contour` first
//! and the orthogonal `rms_distance` after `max_distance` (`fit.csv`, and
//! campaigns with the current fitting records), and the legacy
//! [`SEGMENT_HEADER`] of campaigns whose specs use none of the keys that
//! came with them (the files they gave before, bit for bit).
//!
//! Numbers are written with Rust's shortest round-trip formatting, so a
//! segment read back with [`segment_from_row`] is bit-identical.

use crate::fit::{FittedSegment, FunctionType, Segment};
use crate::geometry::{CubicBez, Point, QuadBez, RationalCubicBez, RationalQuadBez};
use crate::reconstruction::ShapeFit;

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

/// The per-segment columns with the contour and the orthogonal RMS: the
/// layout of `fit.csv` and of current campaigns' `segments.csv`.
pub const FIT_SEGMENT_HEADER: [&str; 24] = [
    "contour",
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
    "rms_distance",
    "evaluations",
];

/// One row of segment `k` in the legacy [`SEGMENT_HEADER`] columns.
fn legacy_row(k: usize, s: &FittedSegment) -> Vec<String> {
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
}

/// One row per segment of every contour of `fit`: in the columns of
/// [`FIT_SEGMENT_HEADER`] with `current`, else of [`SEGMENT_HEADER`]
/// (segments numbered within their contour). Quadratic segments leave
/// `c3x, c3y, w3` empty, polynomial segments have unit weights.
pub fn segment_rows(fit: &ShapeFit, current: bool) -> Vec<Vec<String>> {
    fit.contours
        .iter()
        .flat_map(|c| {
            c.fit.segments.iter().enumerate().map(move |(k, s)| {
                let mut row = legacy_row(k, s);
                if current {
                    row.insert(row.len() - 1, s.metrics.rms_distance.to_string());
                    row.insert(0, c.contour.to_string());
                }
                row
            })
        })
        .collect()
}

/// Rebuilds a segment from a row in either layout (as written by
/// [`segment_rows`], told apart by their lengths); `None` if a field is
/// missing or invalid.
pub fn segment_from_row(row: &[String]) -> Option<Segment> {
    let header: &[&str] = if row.len() == FIT_SEGMENT_HEADER.len() {
        &FIT_SEGMENT_HEADER
    } else {
        &SEGMENT_HEADER
    };
    let col = |name: &str| header.iter().position(|h| *h == name);
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
