//! The scalability figure: for every function run at several dimensions,
//! the mean final error (log scale) and, when timing data exist, the mean
//! wall time per run against the dimension.

use std::collections::{BTreeMap, BTreeSet};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::stats::summarize;

use super::super::data::Dataset;
use super::super::descriptive::{mean_error, CellStats};
use super::super::format::sci_digits;
use super::super::render::{
    colour, draw_minor_decades, font, lg, lg_range, log_floor, log_range, on_log_axis, Draw,
    DrawResult,
};
use super::layout::{
    decade_labels, decade_tick, frame, frame_height, pages_of, Chart, Line, AXIS_FONT, PANEL_H,
    PANEL_TITLE_FONT, PANEL_W, TICK_FONT,
};
use super::{Figure, NoPlot, Plot};

/// One function's scalability row: mean error and (if known) mean wall time
/// against dimension, per cell.
pub(crate) struct ScalabilityRow {
    function: String,
    error: Vec<Line>,
    time: Option<Vec<Line>>,
    x: (f64, f64),
    y_error: (f64, f64),
    y_time: (f64, f64),
    time_unit: &'static str,
    dims: Vec<usize>,
}

/// The scalability figure.
pub(crate) struct Scalability {
    title: String,
    legend: Vec<(String, RGBColor)>,
    rows: Vec<ScalabilityRow>,
    with_time: bool,
}

impl Scalability {
    /// The figure split into pages of whole rows (one function each), none
    /// taller than `max` pixels (one page when it fits).
    pub(super) fn pages(self, max: u32) -> Vec<Scalability> {
        let cols = if self.with_time { 2 } else { 1 };
        let head = frame_height(cols * PANEL_W, &self.legend);
        let per_page = (max.saturating_sub(head) / PANEL_H).max(1) as usize;
        let Scalability {
            title,
            legend,
            rows,
            with_time,
        } = self;
        pages_of(rows, per_page)
            .into_iter()
            .map(|rows| Scalability {
                title: title.clone(),
                legend: legend.clone(),
                rows,
                with_time,
            })
            .collect()
    }
}

impl Draw for Scalability {
    fn size(&self) -> (u32, u32) {
        let cols = if self.with_time { 2 } else { 1 };
        let w = cols * PANEL_W;
        (
            w,
            frame_height(w, &self.legend) + self.rows.len() as u32 * PANEL_H,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend)?;
        let cols = if self.with_time { 2 } else { 1 };
        let areas = area.split_evenly((self.rows.len().max(1), cols));
        for (r, row) in self.rows.iter().enumerate() {
            if let Some(a) = areas.get(r * cols) {
                draw_error_panel(row, a)?;
            }
            if let (Some(times), Some(a)) = (&row.time, areas.get(r * cols + 1)) {
                draw_time_panel(row, times, a)?;
            }
        }
        Ok(())
    }
}

/// The chart of a row's panel titled `what`, with the rows' dimension axis
/// and the vertical range `y`.
fn panel_chart<'a, DB: DrawingBackend>(
    a: &'a DrawingArea<DB, Shift>,
    row: &ScalabilityRow,
    what: &str,
    y: (f64, f64),
) -> Result<Chart<'a, DB>, super::super::render::PlotError> {
    Ok(ChartBuilder::on(a)
        .caption(format!("{}: {what}", row.function), font(PANEL_TITLE_FONT))
        .margin(10)
        .margin_right(22)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(row.x.0..row.x.1, y.0..y.1)?)
}

/// Draws a cell's polyline with a dot at every dimension.
fn draw_lines<DB: DrawingBackend>(chart: &mut Chart<'_, DB>, lines: &[Line]) -> DrawResult {
    for (c, pts) in lines {
        let col = colour(*c);
        chart.draw_series(LineSeries::new(pts.iter().copied(), col.stroke_width(2)))?;
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
    }
    Ok(())
}

/// Draws a row's mean-error panel (log10 vertical axis).
fn draw_error_panel<DB: DrawingBackend>(
    row: &ScalabilityRow,
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
    let mut chart = panel_chart(a, row, "mean final error", row.y_error)?;
    chart
        .configure_mesh()
        .x_desc("dimension D (log scale)")
        .y_desc("mean f − f* (log scale)")
        .x_labels(0)
        .y_label_formatter(&|v| decade_tick(*v, row.y_error))
        .y_labels(decade_labels(row.y_error))
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_minor_decades(&mut chart, row.x, row.y_error, false, true)?;
    dimension_ticks(a, &mut chart, &row.dims, row.y_error)?;
    draw_lines(&mut chart, &row.error)
}

/// Draws a row's mean-wall-time panel (linear vertical axis).
fn draw_time_panel<DB: DrawingBackend>(
    row: &ScalabilityRow,
    times: &[Line],
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
    let mut chart = panel_chart(a, row, "mean wall time", row.y_time)?;
    chart
        .configure_mesh()
        .x_desc("dimension D (log scale)")
        .y_desc(format!("wall time per run [{}]", row.time_unit))
        .x_labels(0)
        .y_label_formatter(&|v| plain_number(*v))
        .y_labels(8)
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    dimension_ticks(a, &mut chart, &row.dims, row.y_time)?;
    draw_lines(&mut chart, times)
}

/// A tick label of a linear axis: up to four significant digits, no
/// exponent for ordinary magnitudes.
fn plain_number(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    if v.abs() >= 1e6 || v.abs() < 1e-3 {
        return sci_digits(v, 2);
    }
    let s = format!("{v:.3}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// Tick labels and light vertical lines at the dimensions actually run
/// (the horizontal axis is log10 D).
fn dimension_ticks<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &mut Chart<'_, DB>,
    dims: &[usize],
    y: (f64, f64),
) -> DrawResult {
    let base = area.get_base_pixel();
    let style = font(TICK_FONT).pos(Pos::new(HPos::Center, VPos::Top));
    for &d in dims {
        let x = lg(d as f64);
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(x, y.0), (x, y.1)],
            RGBColor(215, 215, 215).stroke_width(1),
        )))?;
        let (px, py) = chart.backend_coord(&(x, y.0));
        area.draw(&PathElement::new(
            vec![(px - base.0, py - base.1), (px - base.0, py - base.1 + 5)],
            BLACK.stroke_width(1),
        ))?;
        area.draw_text(&d.to_string(), &style, (px - base.0, py - base.1 + 8))?;
    }
    Ok(())
}

/// The problems of every function (with its transform, instance and
/// budget, which D does not vary), in order of first appearance.
fn problems_by_function(ds: &Dataset) -> Vec<(String, Vec<usize>)> {
    let mut by_function: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let mut order: Vec<String> = Vec::new();
    for (p, problem) in ds.problems.iter().enumerate() {
        let e = by_function.entry(problem.short()).or_default();
        if e.is_empty() {
            order.push(problem.short());
        }
        e.push(p);
    }
    order
        .into_iter()
        .map(|f| {
            let ps = by_function.get(&f).cloned().unwrap_or_default();
            (f, ps)
        })
        .collect()
}

/// Points (log10 D, value) of one cell.
type Points = Vec<(f64, f64)>;

/// A cell's points against log10 D over `probs`: (mean error, mean wall
/// time), each where defined and finite.
fn cell_points(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    c: usize,
    probs: &[usize],
) -> (Points, Points) {
    let mut pe = Vec::new();
    let mut pt = Vec::new();
    for &p in probs {
        let d = lg(ds.problems[p].dim as f64);
        if let Some(m) = mean_error(stats, p, c).filter(|m| m.is_finite()) {
            pe.push((d, m));
        }
        let walls: Option<Vec<f64>> = ds.runs(p, c).iter().map(|r| r.wall_seconds).collect();
        if let Some(w) = walls.filter(|w| !w.is_empty()) {
            if let Ok(s) = summarize(&w) {
                if s.mean.is_finite() {
                    pt.push((d, s.mean));
                }
            }
        }
    }
    (pe, pt)
}

/// The unit of wall times whose largest value is `tmax` seconds, and the
/// factor from seconds to it.
fn time_unit(tmax: f64) -> (&'static str, f64) {
    if tmax < 1e-3 {
        ("µs", 1e6)
    } else if tmax < 1.0 {
        ("ms", 1e3)
    } else {
        ("s", 1.0)
    }
}

/// The row of one function over its problems `probs` (sorted by dimension),
/// with raw mean errors (floored later); `None` when no cell has an error.
/// Cells with an error are added to `used`.
fn row(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    function: &str,
    probs: &[usize],
    used: &mut BTreeSet<usize>,
) -> Option<ScalabilityRow> {
    let mut error = Vec::new();
    let mut time = Vec::new();
    for c in 0..ds.cells.len() {
        let (pe, pt) = cell_points(ds, stats, c, probs);
        if !pe.is_empty() {
            used.insert(c);
            error.push((c, pe));
        }
        if !pt.is_empty() {
            time.push((c, pt));
        }
    }
    if error.is_empty() {
        return None;
    }
    let dims: Vec<usize> = probs.iter().map(|&p| ds.problems[p].dim).collect();
    let (dlo, dhi) = (
        lg(dims.first().copied().unwrap_or(1).max(1) as f64),
        lg(dims.last().copied().unwrap_or(1).max(1) as f64),
    );
    let tmax = time
        .iter()
        .flat_map(|(_, v)| v.iter().map(|p| p.1))
        .fold(0.0f64, f64::max);
    let (time_unit, scale) = time_unit(tmax);
    for (_, pts) in &mut time {
        for p in pts.iter_mut() {
            p.1 *= scale;
        }
    }
    let tmax = tmax * scale;
    let pad = ((dhi - dlo) * 0.08).max(0.05);
    Some(ScalabilityRow {
        function: function.to_owned(),
        error,
        time: if time.is_empty() { None } else { Some(time) },
        x: (dlo - pad, dhi + pad),
        y_error: (0.0, 0.0),
        y_time: (0.0, if tmax > 0.0 { tmax * 1.1 } else { 1.0 }),
        time_unit,
        dims,
    })
}

/// Puts the row's mean errors on a log10 axis above `floor` and sets its
/// error range; returns whether some error was at or below the floor.
fn floor_errors(row: &mut ScalabilityRow, floor: f64) -> bool {
    let mut floored = false;
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for (_, pts) in &mut row.error {
        for p in pts.iter_mut() {
            if p.1 <= floor {
                floored = true;
            }
            p.1 = on_log_axis(p.1, floor);
            lo = lo.min(p.1);
            hi = hi.max(p.1);
            p.1 = lg(p.1);
        }
    }
    row.y_error = lg_range(log_range(lo, hi));
    floored
}

/// The caption: what is drawn, the floor when some mean errors are drawn
/// at it, and whether wall times are shown.
fn caption(floor: Option<f64>, with_time: bool) -> String {
    let mut caption = "Mean final error f − f* (log scale) and, when timing.csv is \
                       available, mean wall-clock time per run against the dimension, \
                       for every function run at several dimensions."
        .to_owned();
    if let Some(floor) = floor {
        caption.push_str(&format!(
            " Mean errors ≤ {} are drawn at {}.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    if !with_time {
        caption.push_str(" No wall times are available, so only errors are shown.");
    } else {
        caption.push_str(
            " Wall times depend on the machine and its load; they are not part of the \
             reproducible output.",
        );
    }
    caption
}

/// The scalability plot, or why there is none.
pub(super) fn scalability(ds: &Dataset, stats: &[Vec<Option<CellStats>>]) -> Result<Plot, NoPlot> {
    let mut rows = Vec::new();
    let mut used = BTreeSet::new();
    for (f, mut probs) in problems_by_function(ds) {
        probs.retain(|&p| ds.problems[p].dim >= 1);
        if probs.len() < 2 {
            continue;
        }
        probs.sort_by_key(|&p| ds.problems[p].dim);
        rows.extend(row(ds, stats, &f, &probs, &mut used));
    }
    if rows.is_empty() {
        return Err(NoPlot::SingleDimension);
    }
    let error_values = rows
        .iter()
        .flat_map(|r| r.error.iter().flat_map(|(_, pts)| pts.iter().map(|p| p.1)));
    let floor = log_floor(error_values);
    let mut floored_any = false;
    for row in &mut rows {
        floored_any |= floor_errors(row, floor);
    }
    let with_time = rows.iter().any(|r| r.time.is_some());
    let legend = used
        .iter()
        .map(|&c| (ds.cells[c].name.clone(), colour(c)))
        .collect();
    Ok(Plot {
        stem: "scalability".into(),
        title: "Scalability".into(),
        caption: caption(floored_any.then_some(floor), with_time),
        figure: Figure::Scalability(Scalability {
            title: "Scalability with the dimension".into(),
            legend,
            rows,
            with_time,
        }),
    })
}
