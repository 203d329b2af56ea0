//! The scalability figure: for every function run at several dimensions,
//! the median final error with its interquartile band and, when timing
//! data exist, the median wall time per evaluation with its band, both on
//! log–log axes against the dimension, with the exponent k of a least-
//! squares fit time ∝ D^k per algorithm.

use std::collections::{BTreeMap, BTreeSet};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::stats::summarize;

use super::super::data::Dataset;
use super::super::format::sci_digits;
use super::super::render::{
    draw_line, draw_minor_decades, font, lg, lg_range, log_floor, log_range, on_log_axis, Draw,
    DrawResult, FloorTick,
};
use super::super::style::{LegendEntry, SeriesStyle};
use super::layout::{
    decade_labels, decade_tick, draw_floor_label, floored_tick, frame, frame_height, pages_of,
    Axis, Chart, AXIS_FONT, PANEL_H, PANEL_TITLE_FONT, PANEL_W, TICK_FONT,
};
use super::{Figure, NoPlot, Page, Plot, SeriesSet};

/// A cell's band against log10 D: (cell, [(log10 D, q1, median, q3)]),
/// values in log10 once floored.
type Band = (usize, Vec<(f64, f64, f64, f64)>);

/// One function's scalability row: the final error and (if known) the wall
/// time per evaluation against dimension, per cell, as quartile bands.
pub(crate) struct ScalabilityRow {
    function: String,
    error: Vec<Band>,
    time: Option<Vec<Band>>,
    /// The fitted exponent k of time per evaluation ∝ D^k, per cell.
    exponents: Vec<(usize, f64)>,
    x: (f64, f64),
    y_error: (f64, f64),
    y_time: (f64, f64),
    time_unit: &'static str,
    dims: Vec<usize>,
}

/// The scalability figure.
pub(crate) struct Scalability {
    title: String,
    legend: Vec<LegendEntry>,
    /// The style of every cell, by its index in the dataset.
    styles: Vec<SeriesStyle>,
    /// The tick of the error axis's floor, when some error is drawn at it.
    floor: Option<FloorTick>,
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
            styles,
            floor,
            rows,
            with_time,
        } = self;
        pages_of(rows, per_page)
            .into_iter()
            .map(|rows| Scalability {
                title: title.clone(),
                legend: legend.clone(),
                styles: styles.clone(),
                floor,
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
                draw_error_panel(row, &self.styles, self.floor, a)?;
            }
            if let (Some(times), Some(a)) = (&row.time, areas.get(r * cols + 1)) {
                draw_time_panel(row, times, &self.styles, a)?;
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

/// Draws a cell's band (interquartile range, shaded) and its median line
/// with a dot at every dimension.
fn draw_bands<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    bands: &[Band],
    styles: &[SeriesStyle],
) -> DrawResult {
    for (c, pts) in bands {
        let style = styles.get(*c).copied().unwrap_or(SeriesStyle::solid(BLACK));
        if pts.len() >= 2 {
            let mut poly: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.3)).collect();
            poly.extend(pts.iter().rev().map(|p| (p.0, p.1)));
            chart.draw_series(std::iter::once(Polygon::new(
                poly,
                style.colour.mix(0.15).filled(),
            )))?;
        }
        draw_line(chart, pts.iter().map(|p| (p.0, p.2)).collect(), style, 2)?;
        chart.draw_series(
            pts.iter()
                .map(|p| Circle::new((p.0, p.2), 4, style.colour.filled())),
        )?;
    }
    Ok(())
}

/// Draws a row's final-error panel (log10 vertical axis).
fn draw_error_panel<DB: DrawingBackend>(
    row: &ScalabilityRow,
    styles: &[SeriesStyle],
    floor: Option<FloorTick>,
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
    let mut chart = panel_chart(a, row, "final error", row.y_error)?;
    chart
        .configure_mesh()
        .x_desc("dimension D (log scale)")
        .y_desc("median f − f* (log scale)")
        .x_labels(0)
        .y_label_formatter(&|v| floored_tick(*v, row.y_error, floor))
        .y_labels(decade_labels(row.y_error))
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_minor_decades(&mut chart, row.x, row.y_error, false, true)?;
    draw_floor_label(a, &chart, floor, (Axis::Y, row.y_error), row.x.0)?;
    dimension_ticks(a, &mut chart, &row.dims, row.y_error)?;
    draw_bands(&mut chart, &row.error, styles)
}

/// Draws a row's time-per-evaluation panel (log–log), with the fitted
/// exponent of every cell written in its colour.
fn draw_time_panel<DB: DrawingBackend>(
    row: &ScalabilityRow,
    times: &[Band],
    styles: &[SeriesStyle],
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
    let mut chart = panel_chart(a, row, "wall time per evaluation", row.y_time)?;
    chart
        .configure_mesh()
        .x_desc("dimension D (log scale)")
        .y_desc(format!(
            "median time per evaluation [{}] (log scale)",
            row.time_unit
        ))
        .x_labels(0)
        .y_label_formatter(&|v| decade_tick(*v, row.y_time))
        .y_labels(decade_labels(row.y_time))
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_minor_decades(&mut chart, row.x, row.y_time, false, true)?;
    dimension_ticks(a, &mut chart, &row.dims, row.y_time)?;
    draw_bands(&mut chart, times, styles)?;
    let (px, py) = chart.backend_coord(&(row.x.0, row.y_time.1));
    let base = a.get_base_pixel();
    let style = font(TICK_FONT).pos(Pos::new(HPos::Left, VPos::Top));
    for (i, (c, k)) in row.exponents.iter().enumerate() {
        let colour = styles.get(*c).map_or(BLACK, |s| s.colour);
        a.draw_text(
            &format!("D^{k:.2}"),
            &style.color(&colour),
            (px - base.0 + 6, py - base.1 + 4 + 15 * i as i32),
        )?;
    }
    Ok(())
}

/// The slope of the least-squares line through `points` (x, y), or `None`
/// for fewer than two distinct x.
fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    let mx = points.iter().map(|p| p.0).sum::<f64>() / n;
    let my = points.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = points.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = points.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (points.len() >= 2 && sxx > 0.0).then(|| sxy / sxx)
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
        let name = problem.across_dimensions();
        let e = by_function.entry(name.clone()).or_default();
        if e.is_empty() {
            order.push(name);
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

/// Quartiles (log10 D, q1, median, q3) of one cell against the dimension.
type Quartiles = Vec<(f64, f64, f64, f64)>;

/// The (q1, median, q3) of the finite values of `v`.
fn quartiles(v: &[f64]) -> Option<(f64, f64, f64)> {
    let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    summarize(&finite).ok().map(|s| (s.q1, s.median, s.q3))
}

/// A cell's quartiles against log10 D over `probs`: of the final error,
/// and of the wall time per evaluation (seconds), each where defined.
fn cell_points(ds: &Dataset, c: usize, probs: &[usize]) -> (Quartiles, Quartiles) {
    let mut pe = Vec::new();
    let mut pt = Vec::new();
    for &p in probs {
        let d = lg(ds.problems[p].dim as f64);
        if let Some((a, m, b)) = quartiles(&ds.errors(p, c)) {
            pe.push((d, a, m, b));
        }
        let per_eval: Option<Vec<f64>> = ds
            .runs(p, c)
            .iter()
            .map(|r| {
                r.wall_seconds
                    .filter(|_| r.evaluations > 0)
                    .map(|w| w / r.evaluations as f64)
            })
            .collect();
        if let Some((a, m, b)) = per_eval
            .filter(|w| !w.is_empty())
            .and_then(|w| quartiles(&w))
            .filter(|q| q.0 > 0.0)
        {
            pt.push((d, a, m, b));
        }
    }
    (pe, pt)
}

/// The unit of wall times whose largest value is `tmax` seconds, and the
/// factor from seconds to it.
fn time_unit(tmax: f64) -> (&'static str, f64) {
    if tmax < 1e-6 {
        ("ns", 1e9)
    } else if tmax < 1e-3 {
        ("µs", 1e6)
    } else if tmax < 1.0 {
        ("ms", 1e3)
    } else {
        ("s", 1.0)
    }
}

/// The row of one function over its problems `probs` (sorted by dimension),
/// with raw errors (floored later) and times per evaluation on a log10
/// axis; `None` when no cell has an error. Cells with an error are added
/// to `used`.
fn row(
    ds: &Dataset,
    series: &SeriesSet,
    function: &str,
    probs: &[usize],
    used: &mut BTreeSet<usize>,
) -> Option<ScalabilityRow> {
    let mut error = Vec::new();
    let mut time = Vec::new();
    for &c in &series.cells {
        let (pe, pt) = cell_points(ds, c, probs);
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
    let all_times = || {
        time.iter()
            .flat_map(|(_, v): &Band| v.iter().flat_map(|p| [p.1, p.3]))
    };
    let tmax = all_times().fold(0.0f64, f64::max);
    let tmin = all_times().fold(f64::INFINITY, f64::min);
    let (time_unit, scale) = time_unit(tmax);
    let exponents = time
        .iter()
        .filter_map(|(c, pts)| {
            let medians: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, lg(p.2))).collect();
            slope(&medians).map(|k| (*c, k))
        })
        .collect();
    for (_, pts) in &mut time {
        for p in pts.iter_mut() {
            *p = (p.0, lg(p.1 * scale), lg(p.2 * scale), lg(p.3 * scale));
        }
    }
    let pad = ((dhi - dlo) * 0.08).max(0.05);
    Some(ScalabilityRow {
        function: function.to_owned(),
        error,
        time: if time.is_empty() { None } else { Some(time) },
        exponents,
        x: (dlo - pad, dhi + pad),
        y_error: (0.0, 0.0),
        y_time: if tmax > 0.0 {
            lg_range(log_range(tmin * scale, tmax * scale))
        } else {
            (0.0, 1.0)
        },
        time_unit,
        dims,
    })
}

/// Puts the row's errors on a log10 axis above `floor` and sets its error
/// range.
fn floor_errors(row: &mut ScalabilityRow, floor: f64) {
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for (_, pts) in &mut row.error {
        for p in pts.iter_mut() {
            let mut at = |v: f64| {
                let v = on_log_axis(v, floor);
                lo = lo.min(v);
                hi = hi.max(v);
                lg(v)
            };
            *p = (p.0, at(p.1), at(p.2), at(p.3));
        }
    }
    row.y_error = lg_range(log_range(lo, hi));
}

/// The caption: what is drawn, the floor when some errors are drawn at
/// it, and whether times are shown.
fn caption(floor: Option<f64>, with_time: bool) -> String {
    let mut caption = "Median final error f − f* with its interquartile band (25 % to 75 %, \
                       type-7) against the dimension, both on log scales, for every function \
                       run at several dimensions."
        .to_owned();
    if let Some(floor) = floor {
        caption.push_str(&format!(
            " Errors ≤ {} (including exact zeros) are drawn at {}.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    if !with_time {
        caption.push_str(" No wall times are available, so only errors are shown.");
    } else {
        caption.push_str(
            " Beside it, the median wall time per objective evaluation (a run's wall time \
             over its evaluations, timing.csv) with its interquartile band on log–log axes; \
             D^k gives each algorithm's exponent k of a least-squares fit of log time \
             against log D through the medians. Wall times depend on the machine and its \
             load; they are not part of the reproducible output.",
        );
    }
    caption
}

/// The scalability plot, or why there is none.
pub(super) fn scalability(ds: &Dataset, series: &SeriesSet) -> Result<Plot, NoPlot> {
    let mut rows = Vec::new();
    let mut used = BTreeSet::new();
    for (f, mut probs) in problems_by_function(ds) {
        probs.retain(|&p| ds.problems[p].dim >= 1);
        if probs.len() < 2 {
            continue;
        }
        probs.sort_by_key(|&p| ds.problems[p].dim);
        rows.extend(row(ds, series, &f, &probs, &mut used));
    }
    if rows.is_empty() {
        return Err(NoPlot::SingleDimension);
    }
    let error_values = rows.iter().flat_map(|r| {
        r.error
            .iter()
            .flat_map(|(_, pts)| pts.iter().flat_map(|p| [p.1, p.2, p.3]))
    });
    let floor = log_floor(error_values.clone());
    let floor_tick = FloorTick::of(error_values, floor);
    for row in &mut rows {
        floor_errors(row, floor);
    }
    let with_time = rows.iter().any(|r| r.time.is_some());
    let legend = series.legend(used);
    Ok(Plot {
        page: Page::SINGLE,
        stem: "scalability".into(),
        title: "Scalability".into(),
        caption: caption(floor_tick.map(|_| floor), with_time) + &series.caption_note(),
        figure: Figure::Scalability(Scalability {
            title: "Scalability with the dimension".into(),
            legend,
            styles: (0..ds.cells.len()).map(|c| series.style(c)).collect(),
            floor: floor_tick,
            rows,
            with_time,
        }),
    })
}
