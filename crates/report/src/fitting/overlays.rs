//! The overlays of the fitting section: the best fit of each function on
//! each outline, drawn over the outline's data points (`outlines.csv`).

use std::collections::BTreeMap;
use std::path::Path;

use super::super::data::Dataset;
use super::super::fit_runs::{cell_name, split, FitRuns};
use super::super::format::sci;
use super::super::plots::{Figure, Page, Plot};
use crate::experiment::reading::{open_csv, RESULT_LIMITS};
use crate::experiment::records::RunRecord;
use crate::experiment::segments::segment_from_row;
use crate::experiment::{DataError, DataProblem, ReadError};
use crate::fit::Segment;
use crate::geometry::Point;
use crate::reconstruction::{OverlayCurve, OverlayFigure, OverlayPanel};

/// A fitted outline read back from its segment rows, for an overlay;
/// `None` if a row does not describe a segment.
fn overlay_from_rows(label: String, rows: &[Vec<String>]) -> Option<OverlayCurve> {
    let segments: Vec<Segment> = rows
        .iter()
        .map(|r| segment_from_row(r))
        .collect::<Option<_>>()?;
    Some(OverlayCurve::of_segments(label, &segments))
}

/// Reads `outlines.csv` (source, x, y): the data points of every source.
pub(super) fn read_outlines(dir: &Path) -> Result<BTreeMap<String, Vec<Point>>, ReadError> {
    let path = dir.join("outlines.csv");
    let mut out: BTreeMap<String, Vec<Point>> = BTreeMap::new();
    if !path.exists() {
        return Ok(out);
    }
    let mut reader = open_csv(&path, RESULT_LIMITS, true)?;
    for (i, row) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let row = row.map_err(|e| DataError::new(&path, line, DataProblem::Csv(e)))?;
        let num = |k: usize| -> Result<f64, DataError> {
            row.get(k)
                .unwrap_or("")
                .parse()
                .map_err(|_| DataError::new(&path, line, DataProblem::NotANumber(k + 1)))
        };
        out.entry(row.get(0).unwrap_or("").to_owned())
            .or_default()
            .push(Point::new(num(1)?, num(2)?));
    }
    Ok(out)
}

/// The overlay panel of one function on one source: the best fit of each
/// continuity (technique search space at its default α_size, any budget),
/// titled with their E and method.
fn overlay_panel(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    source: &str,
    function: &str,
    data: &[Point],
) -> OverlayPanel {
    let mut best: Vec<(String, &RunRecord)> = Vec::new();
    for ((p, _), rs) in &fr.runs {
        let Some(c) = split(&fr.problems[*p].name) else {
            continue;
        };
        // At equal segments only: a panel compares the continuities and
        // the variants (error, chain) of one function.
        if c.source != source
            || c.function != function
            || c.space.is_some()
            || c.alpha.is_some()
            || c.params.is_some()
        {
            continue;
        }
        let variant = c.variant();
        let cont = if variant.is_empty() {
            c.continuity.to_uppercase()
        } else {
            format!("{} {variant}", c.continuity.to_uppercase())
        };
        for r in rs {
            match best.iter_mut().find(|(k, _)| *k == cont) {
                Some((_, b)) if r.best < b.best => *b = r,
                Some(_) => {}
                None => best.push((cont.clone(), r)),
            }
        }
    }
    let mut curves = Vec::new();
    let mut bests = Vec::new();
    for (cont, r) in best {
        if let Some(curve) = r
            .fit
            .as_ref()
            .and_then(|f| overlay_from_rows(cont.clone(), &f.segments))
        {
            bests.push(format!("{cont} E = {} ({})", sci(r.best), cell_name(ds, r)));
            curves.push(curve);
        }
    }
    OverlayPanel {
        title: format!("{function}: {}", bests.join(", ")),
        data: data.to_vec(),
        curves,
        y_down: false,
    }
}

/// The overlay plot of one source: a panel per fitting function, or
/// `None` when it has none.
fn overlay_plot(ds: &Dataset, fr: &FitRuns<'_>, source: &str, data: &[Point]) -> Option<Plot> {
    let mut function_names: Vec<&str> = Vec::new();
    for p in &fr.problems {
        if let Some(c) = split(&p.name) {
            if c.source == source
                && c.space.is_none()
                && c.alpha.is_none()
                && !function_names.contains(&c.function)
            {
                function_names.push(c.function);
            }
        }
    }
    let panels: Vec<OverlayPanel> = function_names
        .into_iter()
        .map(|function| overlay_panel(ds, fr, source, function, data))
        .collect();
    if panels.is_empty() {
        return None;
    }
    let slug: String = source
        .chars()
        .map(|ch| if ch.is_ascii_alphanumeric() { ch } else { '_' })
        .collect();
    Some(Plot {
        page: Page::SINGLE,
        stem: format!("overlay_{slug}"),
        title: format!("Best fits of {source}"),
        caption: format!(
            "The data points of {source} (grey) and, for each fitting function, the fit \
             with the lowest E over all methods and runs for each continuity (circles mark \
             the segments' start points; the legend gives E and the method). Equal scale \
             in x and y."
        ),
        figure: Figure::Overlay(OverlayFigure {
            title: format!("{source}: best fit of each function"),
            panels,
            columns: 2,
        }),
    })
}

/// Overlays: per source, a panel per function with the best fit of each
/// continuity (technique search space). A source whose points are not in
/// `outlines` gets a note instead.
pub(super) fn overlays(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    outlines: &BTreeMap<String, Vec<Point>>,
    notes: &mut Vec<String>,
) -> Vec<Plot> {
    let mut sources: Vec<&str> = fr
        .problems
        .iter()
        .filter_map(|p| split(&p.name).map(|c| c.source))
        .collect();
    sources.dedup();
    let mut seen = std::collections::BTreeSet::new();
    sources.retain(|s| seen.insert(*s));
    let mut figures = Vec::new();
    for source in sources {
        let Some(data) = outlines.get(source) else {
            notes.push(format!(
                "no overlay for {source}: outlines.csv does not hold its points"
            ));
            continue;
        };
        figures.extend(overlay_plot(ds, fr, source, data));
    }
    figures
}
