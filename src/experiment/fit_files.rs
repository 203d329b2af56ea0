//! The record files of a single `metabezier fit`: `fit.csv` (one row per
//! segment, the columns of [`SEGMENT_HEADER`]), `metrics.csv` (the case and
//! the fit's totals) and `timing.csv` (wall time, apart as in campaigns).
//! The overlay figure beside them is drawn by the report.

use std::path::{Path, PathBuf};

use super::segments::{segment_rows, SEGMENT_HEADER};
use crate::files::{create_dir, csv_bytes, write_atomic, IoError};
use crate::fit::PiecewiseFit;

/// Writes `fit.csv`, `metrics.csv` and `timing.csv` into `dir` (created if
/// missing); returns the paths.
///
/// `case` holds the descriptive columns of `metrics.csv` (input, function,
/// continuity, method, seed, …), written before the fit's totals.
pub fn write_fit_records(
    dir: &Path,
    fit: &PiecewiseFit,
    case: &[(&str, String)],
    wall_seconds: f64,
) -> Result<Vec<PathBuf>, IoError> {
    create_dir(dir)?;
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
    Ok(written)
}
