//! The record files of a single `metabezier fit`: `fit.csv` (one row per
//! segment of every contour, the columns of [`FIT_SEGMENT_HEADER`]),
//! `metrics.csv` (the case, then one row per contour and a final `all`
//! row with the totals) and `timing.csv` (wall time, apart as in
//! campaigns). The figures beside them are drawn elsewhere.

use std::path::{Path, PathBuf};

use super::segments::{segment_rows, FIT_SEGMENT_HEADER};
use crate::files::{create_dir, csv_bytes, write_atomic, IoError};
use crate::fit::{ClosingJoint, FitMetrics};
use crate::geometry::Orientation;
use crate::reconstruction::ShapeFit;

/// The columns of `metrics.csv` after the case columns.
///
/// `max_distance` and `rms_distance` are data → curve (each data point's
/// orthogonal distance); `curve_distance` is curve → data (dense samples
/// of every segment to the polyline of its data points); `hausdorff` the
/// larger of the two sides ([`crate::fit::SegmentMetrics::hausdorff`]);
/// `hausdorff_excess` the same beyond the staircase's allowance, what a
/// tolerance holds for a traced image ([`crate::fit::SegmentMetrics::excess`]);
/// `tolerance` the tolerance held (empty without one) and `tolerance_holds`
/// which of the two it holds; `weights_at_bounds` the rational weights the
/// search box, not the data, decided.
pub const METRICS_COLUMNS: [&str; 18] = [
    "contour",
    "orientation",
    "points",
    "segments",
    "sse",
    "rms",
    "max_distance",
    "rms_distance",
    "curve_distance",
    "hausdorff",
    "hausdorff_excess",
    "tolerance",
    "tolerance_holds",
    "weights_at_bounds",
    "evaluations",
    "closing_join",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The metrics columns of one row: a contour (with its orientation and
/// closing joint) or the `all` row.
fn metrics_fields(
    contour: &str,
    orientation: Option<Orientation>,
    m: &FitMetrics,
    closing: Option<ClosingJoint>,
    tolerance: Option<(f64, bool)>,
    weights_at_bounds: usize,
) -> Vec<String> {
    let orientation = match orientation {
        Some(Orientation::CounterClockwise) => "counter-clockwise",
        Some(Orientation::Clockwise) => "clockwise",
        Some(Orientation::Degenerate) => "degenerate",
        None => "",
    };
    let join = closing.map_or(String::new(), |c| {
        if c.at_corner {
            "c0 (corner)".to_owned()
        } else {
            c.imposed.name().to_owned()
        }
    });
    vec![
        contour.to_owned(),
        orientation.to_owned(),
        m.points.to_string(),
        m.segments.to_string(),
        m.sse.to_string(),
        m.rms.to_string(),
        m.max_distance.to_string(),
        m.rms_distance.to_string(),
        m.curve_distance.to_string(),
        m.hausdorff.to_string(),
        m.excess.to_string(),
        tolerance.map_or(String::new(), |(t, _)| t.to_string()),
        tolerance.map_or(String::new(), |(_, staircase)| {
            if staircase {
                "hausdorff_excess".to_owned()
            } else {
                "hausdorff".to_owned()
            }
        }),
        weights_at_bounds.to_string(),
        m.evaluations.to_string(),
        join,
        closing.map_or(String::new(), |c| c.angle_degrees.to_string()),
        closing.map_or(String::new(), |c| c.relative_derivative_gap.to_string()),
    ]
}

/// Writes `fit.csv`, `metrics.csv` and `timing.csv` into `dir` (created if
/// missing); returns the paths.
///
/// `case` holds the descriptive columns of `metrics.csv` (input, function,
/// continuity, method, seed, …), written before the metrics of each row.
pub fn write_fit_records(
    dir: &Path,
    fit: &ShapeFit,
    case: &[(&str, String)],
    wall_seconds: f64,
) -> Result<Vec<PathBuf>, IoError> {
    create_dir(dir)?;
    let mut written = Vec::new();

    let fit_csv = dir.join("fit.csv");
    write_atomic(
        &fit_csv,
        &csv_bytes(&FIT_SEGMENT_HEADER, segment_rows(fit, true)),
    )?;
    written.push(fit_csv);

    let mut header: Vec<&str> = case.iter().map(|(k, _)| *k).collect();
    header.extend(METRICS_COLUMNS);
    let case_values: Vec<String> = case.iter().map(|(_, v)| v.clone()).collect();
    let mut rows: Vec<Vec<String>> = fit
        .contours
        .iter()
        .map(|c| {
            let mut row = case_values.clone();
            let name = c.contour.to_string();
            row.extend(metrics_fields(
                &name,
                Some(c.orientation),
                &c.fit.metrics,
                c.fit.closing,
                c.fit.tolerance.map(|t| (t, c.fit.staircase)),
                c.fit.weights_at_bounds,
            ));
            row
        })
        .collect();
    let mut all = case_values;
    let tolerance = fit
        .contours
        .iter()
        .map(|c| c.fit.tolerance.map(|t| (t, c.fit.staircase)))
        .try_fold((0.0, false), |(worst, s): (f64, bool), d| {
            d.map(|(t, staircase)| (worst.max(t), s || staircase))
        });
    let at_bounds = fit.contours.iter().map(|c| c.fit.weights_at_bounds).sum();
    all.extend(metrics_fields(
        "all",
        None,
        &fit.metrics,
        None,
        tolerance,
        at_bounds,
    ));
    rows.push(all);
    let metrics_csv = dir.join("metrics.csv");
    write_atomic(&metrics_csv, &csv_bytes(&header, rows))?;
    written.push(metrics_csv);

    let timing_csv = dir.join("timing.csv");
    write_atomic(
        &timing_csv,
        &csv_bytes(&["wall_seconds"], [vec![wall_seconds.to_string()]]),
    )?;
    written.push(timing_csv);
    Ok(written)
}
