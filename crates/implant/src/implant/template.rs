//! Explicit templates (`template = "file.csv"` in a spec's `[defect]`): for
//! a defect the mirror technique cannot serve (one crossing the midline, or
//! a strongly asymmetric head), one ordered outer-contour polyline per
//! defect slice, drawn by the user or taken from a reference skull.
//!
//! The file is CSV with the header `z,x_mm,y_mm`: `z` the slice (original
//! numbering, as in the spec), `x_mm = col·sx` and `y_mm = row·sy` the
//! point in the slice's millimetre frame (the frame of the overlays and of
//! `metrics.csv`). The rows of one slice are consecutive and run from near
//! A to near B (either direction is accepted). Every defect slice needs a
//! polyline of at least two points, and no other slice may appear; errors
//! name the file and line.

use std::collections::BTreeMap;
use std::path::Path;

use super::pipeline::Templates;
use crate::geometry::{Point, Polyline};
use metabezier_spec::SpecError;

/// A template-file error at `line` (1-based; 0 for the whole file).
fn error(path: &Path, line: usize, message: String) -> SpecError {
    SpecError {
        path: path.to_owned(),
        line,
        column: usize::from(line > 0),
        field: "defect.template".into(),
        message,
    }
}

/// One parsed row: `(z, point)`.
fn row(path: &Path, line: usize, rec: &csv::StringRecord) -> Result<(usize, Point), SpecError> {
    if rec.len() != 3 {
        return Err(error(
            path,
            line,
            format!("expected 3 fields z,x_mm,y_mm, found {}", rec.len()),
        ));
    }
    let z = rec[0].trim().parse::<usize>().map_err(|_| {
        error(
            path,
            line,
            format!("z: expected a slice number, found \"{}\"", &rec[0]),
        )
    })?;
    let num = |i: usize, name: &str| {
        rec[i]
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(|| {
                error(
                    path,
                    line,
                    format!("{name}: expected a finite number, found \"{}\"", &rec[i]),
                )
            })
    };
    Ok((z, Point::new(num(1, "x_mm")?, num(2, "y_mm")?)))
}

/// Reads the explicit templates of the defect slices `z0..=z1` from the
/// CSV file at `path` (see the module documentation).
pub fn read_templates(path: &Path, (z0, z1): (usize, usize)) -> Result<Templates, SpecError> {
    let text =
        crate::files::read_text_limited(path, crate::files::MAX_TEXT_BYTES, "a template file")
            .map_err(|e| SpecError::unreadable(path, &e))?;
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(true)
        .from_reader(text.as_bytes());
    let header: Vec<String> = rdr
        .headers()
        .map_err(|e| error(path, 1, format!("unreadable header: {e}")))?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    if header != ["z", "x_mm", "y_mm"] {
        return Err(error(
            path,
            1,
            format!(
                "expected the header z,x_mm,y_mm, found {}",
                header.join(",")
            ),
        ));
    }
    let mut slices: BTreeMap<usize, Vec<Point>> = BTreeMap::new();
    let mut last: Option<usize> = None;
    for (i, rec) in rdr.records().enumerate() {
        let line = i + 2;
        let rec = rec.map_err(|e| error(path, line, format!("unreadable row: {e}")))?;
        let (z, p) = row(path, line, &rec)?;
        if !(z0..=z1).contains(&z) {
            return Err(error(
                path,
                line,
                format!("slice z = {z} is not a defect slice ({z0}..={z1})"),
            ));
        }
        if last != Some(z) && slices.contains_key(&z) {
            return Err(error(
                path,
                line,
                format!("the rows of slice z = {z} are not consecutive"),
            ));
        }
        last = Some(z);
        slices.entry(z).or_default().push(p);
    }
    if let Some(z) = (z0..=z1).find(|z| !slices.contains_key(z)) {
        let held: Vec<String> = slices.keys().map(|z| z.to_string()).collect();
        return Err(error(path, 0, format!("no template polyline for defect slice z = {z} (the defect slices are {z0}..={z1}; the file holds z = {})", if held.is_empty() { "none".into() } else { held.join(", ") })));
    }
    if let Some((z, _)) = slices.iter().find(|(_, p)| p.len() < 2) {
        return Err(error(
            path,
            0,
            format!("the template polyline of slice z = {z} has fewer than 2 points"),
        ));
    }
    Ok(Templates {
        source: path.to_owned(),
        slices: slices
            .into_iter()
            .map(|(z, p)| (z, Polyline::open(p)))
            .collect(),
    })
}

/// The CSV text of templates (header `z,x_mm,y_mm`, shortest round-trip
/// reals), as [`read_templates`] reads it.
pub fn templates_csv(slices: &BTreeMap<usize, Polyline>) -> String {
    let mut out = String::from("z,x_mm,y_mm\n");
    for (z, p) in slices {
        for q in &p.points {
            out.push_str(&format!(
                "{z},{},{}\n",
                crate::files::fmt_real(q.x),
                crate::files::fmt_real(q.y)
            ));
        }
    }
    out
}
