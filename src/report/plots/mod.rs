//! The report's figures: convergence curves, box plots of the final error,
//! the ECDF of runtimes to the threshold, scalability with the dimension and
//! parameter-tuning heat maps. Each is computed from the [`Dataset`] into a
//! plain figure description, then drawn on any plotters backend.

use std::collections::{BTreeMap, BTreeSet};

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::stats::summarize;

use super::data::{Dataset, Run};
use super::descriptive::{mean_error, CellStats};
use super::format::{pow_tick, sci_digits};
use super::render::{
    colour, draw_legend, draw_minor_decades, draw_title, font, legend_height, lg, lg_range,
    log_floor, log_range, on_log_axis, text_width, viridis, Draw, DrawResult,
};
use super::tuning::{cell_label, HeatMap};

const PANEL_W: u32 = 540;
const PANEL_H: u32 = 400;
const TITLE_H: u32 = 44;
const AXIS_FONT: u32 = 15;
const TICK_FONT: u32 = 13;
const PANEL_TITLE_FONT: u32 = 17;

/// A figure of the report, with the text that goes with it.
pub(crate) struct Plot {
    /// File stem under `plots/`.
    pub stem: String,
    /// Short title (alt text and heading).
    pub title: String,
    /// Caption: what is drawn and how to read it.
    pub caption: String,
    /// The figure.
    pub figure: Figure,
}

/// The kinds of figures.
pub(crate) enum Figure {
    /// Median best-so-far error with interquartile band.
    Convergence(Convergence),
    /// Box plots of the final error.
    Boxes(Boxes),
    /// Runtime ECDF.
    Ecdf(Ecdf),
    /// Error and time against dimension.
    Scalability(Scalability),
    /// Mean error over a two-parameter grid.
    Heat(Heat),
    /// Fitted outlines over their data.
    Overlay(crate::reconstruction::OverlayFigure),
}

impl Draw for Figure {
    fn size(&self) -> (u32, u32) {
        match self {
            Figure::Convergence(f) => f.size(),
            Figure::Boxes(f) => f.size(),
            Figure::Ecdf(f) => f.size(),
            Figure::Scalability(f) => f.size(),
            Figure::Heat(f) => f.size(),
            Figure::Overlay(f) => f.size(),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        match self {
            Figure::Convergence(f) => f.draw(root),
            Figure::Boxes(f) => f.draw(root),
            Figure::Ecdf(f) => f.draw(root),
            Figure::Scalability(f) => f.draw(root),
            Figure::Heat(f) => f.draw(root),
            Figure::Overlay(f) => f.draw(root),
        }
    }
}

/// How many labels to ask plotters for on a log10 axis so that they fall
/// on whole decades: one per decade, at most 9.
fn decade_labels((lo, hi): (f64, f64)) -> usize {
    let span = hi - lo;
    if span.is_finite() && span >= 1.0 {
        (span.floor() as usize + 1).clamp(2, 9)
    } else {
        5
    }
}

/// The label of a log10-axis position: powers of ten only, unless the axis
/// spans less than a decade.
fn decade_tick(v: f64, (lo, hi): (f64, f64)) -> String {
    if hi - lo >= 1.0 && (v - v.round()).abs() > 1e-6 {
        String::new()
    } else {
        pow_tick(v)
    }
}

/// (evaluations, q1, median, q3) of a convergence curve.
type Quartiles = Vec<(u64, f64, f64, f64)>;

/// A cell's polyline: (cell, points).
type Line = (usize, Vec<(f64, f64)>);

fn grid_shape(n: usize, max_cols: usize) -> (usize, usize) {
    let cols = n.clamp(1, max_cols.max(1));
    let rows = n.div_ceil(cols).max(1);
    (rows, cols)
}

/// Splits the canvas into a title strip, a legend strip and the panels area.
fn frame<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    legend: &[(String, RGBColor)],
) -> Result<DrawingArea<DB, Shift>, super::render::PlotError> {
    root.fill(&WHITE)?;
    let (w, _) = root.dim_in_pixel();
    let (top, rest) = root.split_vertically(TITLE_H);
    draw_title(&top, title, 20)?;
    if legend.is_empty() {
        return Ok(rest);
    }
    let (leg, panels) = rest.split_vertically(legend_height(legend, w));
    draw_legend(&leg, legend)?;
    Ok(panels)
}

fn frame_height(width: u32, legend: &[(String, RGBColor)]) -> u32 {
    TITLE_H
        + if legend.is_empty() {
            0
        } else {
            legend_height(legend, width)
        }
}

// ---------------------------------------------------------------- convergence

/// One algorithm's curve: (evaluations, q1, median, q3), floored.
pub(crate) struct Band {
    /// Colour index (the cell).
    pub cell: usize,
    /// Points in increasing evaluations.
    pub points: Vec<(f64, f64, f64, f64)>,
}

/// One problem's convergence panel.
pub(crate) struct ConvergencePanel {
    /// Panel title.
    pub title: String,
    /// The curves.
    pub bands: Vec<Band>,
    /// Horizontal range.
    pub x: (f64, f64),
    /// Vertical range.
    pub y: (f64, f64),
}

/// The convergence figure.
pub(crate) struct Convergence {
    title: String,
    legend: Vec<(String, RGBColor)>,
    panels: Vec<ConvergencePanel>,
}

impl Convergence {
    fn cols(&self) -> usize {
        grid_shape(self.panels.len(), 3).1
    }
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.panels.len(), 3);
        let w = cols as u32 * PANEL_W;
        (w, frame_height(w, &self.legend) + rows as u32 * PANEL_H)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend)?;
        let rows = grid_shape(self.panels.len(), 3).0;
        let areas = area.split_evenly((rows, self.cols()));
        for (panel, a) in self.panels.iter().zip(&areas) {
            let mut chart = ChartBuilder::on(a)
                .caption(&panel.title, font(PANEL_TITLE_FONT))
                .margin(10)
                .margin_right(22)
                .x_label_area_size(52)
                .y_label_area_size(78)
                .build_cartesian_2d(panel.x.0..panel.x.1, panel.y.0..panel.y.1)?;
            chart
                .configure_mesh()
                .x_desc("objective evaluations (log scale)")
                .y_desc("f − f* (log scale)")
                .x_label_formatter(&|v| decade_tick(*v, panel.x))
                .y_label_formatter(&|v| decade_tick(*v, panel.y))
                .x_labels(decade_labels(panel.x))
                .y_labels(decade_labels(panel.y))
                .label_style(font(TICK_FONT))
                .axis_desc_style(font(AXIS_FONT))
                .light_line_style(TRANSPARENT)
                .bold_line_style(RGBColor(215, 215, 215))
                .draw()?;
            draw_minor_decades(&mut chart, panel.x, panel.y, true, true)?;
            for band in &panel.bands {
                let c = colour(band.cell);
                if band.points.len() >= 2 {
                    let mut poly: Vec<(f64, f64)> =
                        band.points.iter().map(|p| (p.0, p.3)).collect();
                    poly.extend(band.points.iter().rev().map(|p| (p.0, p.1)));
                    chart.draw_series(std::iter::once(Polygon::new(poly, c.mix(0.18).filled())))?;
                }
                chart.draw_series(LineSeries::new(
                    band.points.iter().map(|p| (p.0, p.2)),
                    c.stroke_width(2),
                ))?;
                if band.points.len() == 1 {
                    let p = band.points[0];
                    chart.draw_series(std::iter::once(Circle::new((p.0, p.2), 3, c.filled())))?;
                }
            }
        }
        Ok(())
    }
}

/// The best-so-far error of a run after `t` evaluations (the last
/// checkpoint at or before `t`).
fn value_at(run: &Run, t: u64) -> Option<f64> {
    run.trace
        .iter()
        .take_while(|(e, _)| *e <= t)
        .last()
        .map(|&(_, v)| v)
}

fn convergence(ds: &Dataset) -> Result<Plot, String> {
    if !ds.has_convergence {
        return Err(
            "convergence plot skipped: no run has a best-so-far trace (convergence.csv is missing or empty; fitting runs record none)".into(),
        );
    }
    // Raw (q1, median, q3) curves first, then floor them together.
    let mut raw: Vec<(usize, Vec<(usize, Quartiles)>)> = Vec::new();
    let mut used_cells = BTreeSet::new();
    let mut max_runs = 0usize;
    for p in 0..ds.problems.len() {
        let mut curves = Vec::new();
        for c in 0..ds.cells.len() {
            let runs: Vec<&Run> = ds
                .runs(p, c)
                .iter()
                .filter(|r| !r.trace.is_empty())
                .collect();
            if runs.is_empty() {
                continue;
            }
            max_runs = max_runs.max(runs.len());
            let checkpoints: BTreeSet<u64> = runs
                .iter()
                .flat_map(|r| r.trace.iter().map(|&(e, _)| e))
                .filter(|&e| e >= 1)
                .collect();
            let mut pts = Vec::new();
            for t in checkpoints {
                let vals: Vec<f64> = runs.iter().filter_map(|r| value_at(r, t)).collect();
                if vals.len() != runs.len() || vals.iter().any(|v| !v.is_finite()) {
                    continue;
                }
                if let Ok(s) = summarize(&vals) {
                    pts.push((t, s.q1, s.median, s.q3));
                }
            }
            if !pts.is_empty() {
                used_cells.insert(c);
                curves.push((c, pts));
            }
        }
        if !curves.is_empty() {
            raw.push((p, curves));
        }
    }
    if raw.is_empty() {
        return Err("convergence plot skipped: no run has a finite best-so-far error".into());
    }
    let all = raw
        .iter()
        .flat_map(|(_, cs)| cs.iter().flat_map(|(_, pts)| pts.iter()))
        .flat_map(|&(_, a, b, c)| [a, b, c]);
    let floor = log_floor(all.clone());
    let floored = all.clone().any(|v| v <= floor);
    let mut panels = Vec::new();
    for (p, curves) in raw {
        let mut bands = Vec::new();
        let (mut xmax, mut ylo, mut yhi) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
        for (c, pts) in curves {
            let points: Vec<(f64, f64, f64, f64)> = pts
                .into_iter()
                .map(|(t, a, b, d)| {
                    (
                        lg(t as f64),
                        lg(on_log_axis(a, floor)),
                        lg(on_log_axis(b, floor)),
                        lg(on_log_axis(d, floor)),
                    )
                })
                .collect();
            for q in &points {
                xmax = xmax.max(q.0);
                ylo = ylo.min(q.1);
                yhi = yhi.max(q.3);
            }
            bands.push(Band { cell: c, points });
        }
        let x = if xmax > 0.0 { (0.0, xmax) } else { (-0.3, 0.3) };
        panels.push(ConvergencePanel {
            title: ds.problems[p].title(),
            bands,
            x,
            y: lg_range(log_range(10f64.powf(ylo), 10f64.powf(yhi))),
        });
    }
    let legend = used_cells
        .iter()
        .map(|&c| (ds.cells[c].name.clone(), colour(c)))
        .collect();
    let mut caption = format!(
        "Median best-so-far error f − f* against objective evaluations, both on log \
         scales, over the runs of each algorithm (up to {max_runs} per problem); the \
         shaded band is the interquartile range (25 % to 75 %, type-7 quantiles). A \
         checkpoint is drawn once every run has a finite best-so-far value."
    );
    if floored {
        caption.push_str(&format!(
            " Errors ≤ {} (including exact zeros) are drawn at {} so that the log scale \
             can show them.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    Ok(Plot {
        stem: "convergence".into(),
        title: "Convergence".into(),
        caption,
        figure: Figure::Convergence(Convergence {
            title: "Median best-so-far error (band: interquartile range)".into(),
            legend,
            panels,
        }),
    })
}

// ------------------------------------------------------------------ box plots

/// A box: quartiles, whiskers and outliers (floored), or `None` without data.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct BoxStat {
    q1: f64,
    median: f64,
    q3: f64,
    lo: f64,
    hi: f64,
    outliers: Vec<f64>,
}

/// One problem's box-plot panel.
pub(crate) struct BoxPanel {
    title: String,
    boxes: Vec<Option<BoxStat>>,
    x: (f64, f64),
}

/// The box-plot figure; categories are the cells in order.
pub(crate) struct Boxes {
    title: String,
    names: Vec<String>,
    panels: Vec<BoxPanel>,
}

impl Boxes {
    fn label_width(&self) -> u32 {
        self.names
            .iter()
            .map(|n| text_width(n, TICK_FONT))
            .max()
            .unwrap_or(40)
            + 16
    }
    fn panel_size(&self) -> (u32, u32) {
        let w = PANEL_W.max(self.label_width() + 360);
        let h = (110 + 34 * self.names.len() as u32).max(220);
        (w, h)
    }
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.panels.len(), 2);
        let (pw, ph) = self.panel_size();
        (cols as u32 * pw, TITLE_H + rows as u32 * ph)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &[])?;
        let (rows, cols) = grid_shape(self.panels.len(), 2);
        let areas = area.split_evenly((rows, cols));
        let k = self.names.len();
        let yk = |i: usize| (k - 1 - i) as f64;
        for (panel, a) in self.panels.iter().zip(&areas) {
            let mut chart = ChartBuilder::on(a)
                .caption(&panel.title, font(PANEL_TITLE_FONT))
                .margin(10)
                .margin_right(24)
                .x_label_area_size(52)
                .y_label_area_size(self.label_width())
                .build_cartesian_2d(panel.x.0..panel.x.1, -0.6f64..(k as f64 - 0.4))?;
            chart
                .configure_mesh()
                .x_desc("final f − f* (log scale)")
                .x_label_formatter(&|v| decade_tick(*v, panel.x))
                .x_labels(decade_labels(panel.x))
                .y_labels(0)
                .disable_y_mesh()
                .label_style(font(TICK_FONT))
                .axis_desc_style(font(AXIS_FONT))
                .light_line_style(TRANSPARENT)
                .bold_line_style(RGBColor(215, 215, 215))
                .draw()?;
            draw_minor_decades(&mut chart, panel.x, (-0.6, k as f64 - 0.4), true, false)?;
            let label_style = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Center));
            for (i, name) in self.names.iter().enumerate() {
                let (px, py) = chart.backend_coord(&(panel.x.0, yk(i)));
                let base = a.get_base_pixel();
                a.draw_text(name, &label_style, (px - base.0 - 8, py - base.1))?;
            }
            for (i, b) in panel.boxes.iter().enumerate() {
                let Some(b) = b else {
                    let (px, py) = chart.backend_coord(&(panel.x.0, yk(i)));
                    let base = a.get_base_pixel();
                    a.draw_text(
                        "no data",
                        &font(TICK_FONT).pos(Pos::new(HPos::Left, VPos::Center)),
                        (px - base.0 + 8, py - base.1),
                    )?;
                    continue;
                };
                let c = colour(i);
                let y = yk(i);
                let h = 0.3;
                chart.draw_series([
                    PathElement::new(vec![(b.lo, y), (b.q1, y)], BLACK.stroke_width(1)),
                    PathElement::new(vec![(b.q3, y), (b.hi, y)], BLACK.stroke_width(1)),
                    PathElement::new(
                        vec![(b.lo, y - h / 2.0), (b.lo, y + h / 2.0)],
                        BLACK.stroke_width(1),
                    ),
                    PathElement::new(
                        vec![(b.hi, y - h / 2.0), (b.hi, y + h / 2.0)],
                        BLACK.stroke_width(1),
                    ),
                ])?;
                chart.draw_series([
                    Rectangle::new([(b.q1, y - h), (b.q3, y + h)], c.mix(0.45).filled()),
                    Rectangle::new([(b.q1, y - h), (b.q3, y + h)], c.stroke_width(2)),
                ])?;
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(b.median, y - h), (b.median, y + h)],
                    BLACK.stroke_width(3),
                )))?;
                chart.draw_series(
                    b.outliers
                        .iter()
                        .map(|&o| Circle::new((o, y), 3, c.stroke_width(1))),
                )?;
            }
        }
        Ok(())
    }
}

/// Box statistics of a sample: type-7 quartiles of the library summary,
/// whiskers to the most extreme values within 1.5 IQR of the box (Tukey).
fn box_stat(values: &[f64]) -> Option<BoxStat> {
    let s = summarize(values).ok()?;
    let iqr = s.q3 - s.q1;
    let (lo_fence, hi_fence) = (s.q1 - 1.5 * iqr, s.q3 + 1.5 * iqr);
    let inside: Vec<f64> = values
        .iter()
        .copied()
        .filter(|v| *v >= lo_fence && *v <= hi_fence)
        .collect();
    let lo = inside.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = inside.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut outliers: Vec<f64> = values
        .iter()
        .copied()
        .filter(|v| *v < lo_fence || *v > hi_fence)
        .collect();
    outliers.sort_by(f64::total_cmp);
    Some(BoxStat {
        q1: s.q1,
        median: s.median,
        q3: s.q3,
        lo: if lo.is_finite() { lo } else { s.q1 },
        hi: if hi.is_finite() { hi } else { s.q3 },
        outliers,
    })
}

fn boxes(ds: &Dataset) -> Result<Plot, String> {
    let mut raw: Vec<(usize, Vec<Option<BoxStat>>)> = Vec::new();
    let mut dropped = 0usize;
    for p in 0..ds.problems.len() {
        let mut row = Vec::new();
        for c in 0..ds.cells.len() {
            let errors = ds.errors(p, c);
            let finite: Vec<f64> = errors.iter().copied().filter(|v| v.is_finite()).collect();
            dropped += errors.len() - finite.len();
            row.push(box_stat(&finite));
        }
        if row.iter().any(Option::is_some) {
            raw.push((p, row));
        }
    }
    if raw.is_empty() {
        return Err("box plots skipped: no finite final error".into());
    }
    let all = raw.iter().flat_map(|(_, r)| {
        r.iter().flatten().flat_map(|b| {
            [b.q1, b.median, b.q3, b.lo, b.hi]
                .into_iter()
                .chain(b.outliers.iter().copied())
        })
    });
    let floor = log_floor(all.clone());
    let floored = all.clone().any(|v| v <= floor);
    let panels = raw
        .into_iter()
        .map(|(p, row)| {
            let row: Vec<Option<BoxStat>> = row
                .into_iter()
                .map(|b| {
                    b.map(|b| BoxStat {
                        q1: lg(on_log_axis(b.q1, floor)),
                        median: lg(on_log_axis(b.median, floor)),
                        q3: lg(on_log_axis(b.q3, floor)),
                        lo: lg(on_log_axis(b.lo, floor)),
                        hi: lg(on_log_axis(b.hi, floor)),
                        outliers: b
                            .outliers
                            .iter()
                            .map(|&o| lg(on_log_axis(o, floor)))
                            .collect(),
                    })
                })
                .collect();
            let lo = row
                .iter()
                .flatten()
                .map(|b| b.lo)
                .chain(
                    row.iter()
                        .flatten()
                        .flat_map(|b| b.outliers.iter().copied()),
                )
                .fold(f64::INFINITY, f64::min);
            let hi = row
                .iter()
                .flatten()
                .map(|b| b.hi)
                .chain(
                    row.iter()
                        .flatten()
                        .flat_map(|b| b.outliers.iter().copied()),
                )
                .fold(f64::NEG_INFINITY, f64::max);
            BoxPanel {
                title: ds.problems[p].title(),
                boxes: row,
                x: lg_range(log_range(10f64.powf(lo), 10f64.powf(hi))),
            }
        })
        .collect();
    let mut caption = "Final error f − f* of the runs per algorithm and problem (log scale): \
                       the box spans the first to third quartile (type-7), the thick line \
                       is the median, whiskers reach the most extreme runs within 1.5 \
                       interquartile ranges of the box, circles are runs beyond them."
        .to_owned();
    if floored {
        caption.push_str(&format!(
            " Errors ≤ {} (including exact zeros) are drawn at {}.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    if dropped > 0 {
        caption.push_str(&format!(" {dropped} non-finite error(s) are not drawn."));
    }
    Ok(Plot {
        stem: "boxplots".into(),
        title: "Final error distributions".into(),
        caption,
        figure: Figure::Boxes(Boxes {
            title: "Final error f − f* per algorithm".into(),
            names: ds.cells.iter().map(|c| c.name.clone()).collect(),
            panels,
        }),
    })
}

// ----------------------------------------------------------------------- ECDF

/// The runtime ECDF figure.
pub(crate) struct Ecdf {
    title: String,
    legend: Vec<(String, RGBColor)>,
    series: Vec<Line>,
    x: (f64, f64),
}

impl Ecdf {
    fn size(&self) -> (u32, u32) {
        let w = 900;
        (w, frame_height(w, &self.legend) + 540)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend)?;
        let mut chart = ChartBuilder::on(&area)
            .margin(12)
            .margin_right(30)
            .x_label_area_size(56)
            .y_label_area_size(80)
            .build_cartesian_2d(self.x.0..self.x.1, -0.02f64..1.02)?;
        chart
            .configure_mesh()
            .x_desc("objective evaluations (log scale)")
            .y_desc("fraction of (run, problem) pairs solved")
            .x_label_formatter(&|v| decade_tick(*v, self.x))
            .y_label_formatter(&|v| format!("{v:.1}"))
            .x_labels(decade_labels(self.x))
            .y_labels(11)
            .label_style(font(TICK_FONT))
            .axis_desc_style(font(AXIS_FONT))
            .light_line_style(TRANSPARENT)
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        draw_minor_decades(&mut chart, self.x, (-0.02, 1.02), true, false)?;
        for (c, pts) in &self.series {
            chart.draw_series(LineSeries::new(
                pts.iter().copied(),
                colour(*c).stroke_width(2),
            ))?;
        }
        Ok(())
    }
}

fn ecdf(ds: &Dataset, threshold: Option<f64>) -> Result<Plot, String> {
    let mut series = Vec::new();
    let mut xmax = 1.0f64;
    let mut any_success = false;
    let mut pair_counts = BTreeSet::new();
    for c in 0..ds.cells.len() {
        let mut total = 0usize;
        let mut times: Vec<u64> = Vec::new();
        for p in 0..ds.problems.len() {
            for r in ds.runs(p, c) {
                total += 1;
                xmax = xmax.max(r.evaluations as f64).max(r.budget as f64);
                if r.success {
                    times.push(r.evaluations_to_target.unwrap_or(r.evaluations).max(1));
                }
            }
        }
        if total == 0 {
            continue;
        }
        pair_counts.insert(total);
        any_success |= !times.is_empty();
        times.sort_unstable();
        let mut pts = vec![(1.0, 0.0)];
        let mut solved = 0usize;
        let mut i = 0;
        while i < times.len() {
            let t = times[i];
            while i < times.len() && times[i] == t {
                i += 1;
                solved += 1;
            }
            let prev = pts.last().map_or(0.0, |p| p.1);
            let x = t as f64;
            pts.push((x, prev));
            pts.push((x, solved as f64 / total as f64));
        }
        series.push((c, pts, total));
    }
    if !any_success {
        return Err("runtime ECDF skipped: no run reached the success threshold".into());
    }
    let xmax = xmax.max(2.0);
    let series: Vec<Line> = series
        .into_iter()
        .map(|(c, mut pts, _)| {
            let last = pts.last().map_or(0.0, |p| p.1);
            pts.push((xmax, last));
            (c, pts.into_iter().map(|(x, y)| (lg(x), y)).collect())
        })
        .collect();
    let legend = series
        .iter()
        .map(|(c, _)| (ds.cells[*c].name.clone(), colour(*c)))
        .collect();
    let target = threshold.map_or_else(
        || "the success threshold of the campaign (the success column of runs.csv)".to_owned(),
        |t| format!("the target f − f* ≤ {}", sci_digits(t, 2)),
    );
    let mut caption = format!(
        "Empirical cumulative distribution of the runtime to {target} (the \
         COCO view): for each algorithm, the fraction of all its (run, problem) pairs \
         whose error reached the target within the given number of objective \
         evaluations (log scale), aggregated over all problems; the curve ends at the \
         largest budget and stays below 1 when some runs never reached the target. \
         Evaluations are not divided by the dimension."
    );
    if pair_counts.len() > 1 {
        caption.push_str(
            " The algorithms do not have the same number of (run, problem) pairs; each \
             curve is normalised by its own count.",
        );
    }
    Ok(Plot {
        stem: "ecdf".into(),
        title: "Runtime ECDF".into(),
        caption,
        figure: Figure::Ecdf(Ecdf {
            title: format!(
                "Runtime to the target {}, all problems",
                threshold.map_or_else(
                    || "success threshold".to_owned(),
                    |t| if t > 0.0 {
                        format!("f − f* ≤ {}", pow_tick(lg(t)))
                    } else {
                        format!("f − f* ≤ {t}")
                    }
                )
            ),
            legend,
            series,
            x: (0.0, lg(xmax)),
        }),
    })
}

// ---------------------------------------------------------------- scalability

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
                let mut chart = ChartBuilder::on(a)
                    .caption(
                        format!("{}: mean final error", row.function),
                        font(PANEL_TITLE_FONT),
                    )
                    .margin(10)
                    .margin_right(22)
                    .x_label_area_size(52)
                    .y_label_area_size(78)
                    .build_cartesian_2d(row.x.0..row.x.1, row.y_error.0..row.y_error.1)?;
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
                for (c, pts) in &row.error {
                    let col = colour(*c);
                    chart.draw_series(LineSeries::new(pts.iter().copied(), col.stroke_width(2)))?;
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
                }
            }
            if let (Some(times), Some(a)) = (&row.time, areas.get(r * cols + 1)) {
                let mut chart = ChartBuilder::on(a)
                    .caption(
                        format!("{}: mean wall time", row.function),
                        font(PANEL_TITLE_FONT),
                    )
                    .margin(10)
                    .margin_right(22)
                    .x_label_area_size(52)
                    .y_label_area_size(78)
                    .build_cartesian_2d(row.x.0..row.x.1, row.y_time.0..row.y_time.1)?;
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
                for (c, pts) in times {
                    let col = colour(*c);
                    chart.draw_series(LineSeries::new(pts.iter().copied(), col.stroke_width(2)))?;
                    chart.draw_series(pts.iter().map(|&p| Circle::new(p, 4, col.filled())))?;
                }
            }
        }
        Ok(())
    }
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
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
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

fn scalability(ds: &Dataset, stats: &[Vec<Option<CellStats>>]) -> Result<Plot, String> {
    let mut by_function: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    let mut order: Vec<&str> = Vec::new();
    for (p, problem) in ds.problems.iter().enumerate() {
        let e = by_function.entry(problem.function.as_str()).or_default();
        if e.is_empty() {
            order.push(problem.function.as_str());
        }
        e.push(p);
    }
    let mut rows = Vec::new();
    let mut used = BTreeSet::new();
    let mut error_values = Vec::new();
    let mut floored_any = false;
    for f in order {
        let mut probs = by_function.get(f).cloned().unwrap_or_default();
        probs.retain(|&p| ds.problems[p].dim >= 1);
        if probs.len() < 2 {
            continue;
        }
        probs.sort_by_key(|&p| ds.problems[p].dim);
        let mut error = Vec::new();
        let mut time = Vec::new();
        for c in 0..ds.cells.len() {
            let mut pe = Vec::new();
            let mut pt = Vec::new();
            for &p in &probs {
                let d = lg(ds.problems[p].dim as f64);
                if let Some(m) = mean_error(stats, p, c).filter(|m| m.is_finite()) {
                    pe.push((d, m));
                    error_values.push(m);
                }
                let walls: Option<Vec<f64>> =
                    ds.runs(p, c).iter().map(|r| r.wall_seconds).collect();
                if let Some(w) = walls.filter(|w| !w.is_empty()) {
                    if let Ok(s) = summarize(&w) {
                        if s.mean.is_finite() {
                            pt.push((d, s.mean));
                        }
                    }
                }
            }
            if !pe.is_empty() {
                used.insert(c);
                error.push((c, pe));
            }
            if !pt.is_empty() {
                time.push((c, pt));
            }
        }
        if error.is_empty() {
            continue;
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
        let (time_unit, scale) = if tmax < 1e-3 {
            ("µs", 1e6)
        } else if tmax < 1.0 {
            ("ms", 1e3)
        } else {
            ("s", 1.0)
        };
        for (_, pts) in &mut time {
            for p in pts.iter_mut() {
                p.1 *= scale;
            }
        }
        let tmax = tmax * scale;
        rows.push(ScalabilityRow {
            function: f.to_owned(),
            error,
            time: if time.is_empty() { None } else { Some(time) },
            x: {
                let pad = ((dhi - dlo) * 0.08).max(0.05);
                (dlo - pad, dhi + pad)
            },
            y_error: (0.0, 0.0),
            y_time: (0.0, if tmax > 0.0 { tmax * 1.1 } else { 1.0 }),
            time_unit,
            dims,
        });
    }
    if rows.is_empty() {
        return Err(
            "scalability plot skipped: no function was run at more than one dimension".into(),
        );
    }
    let floor = log_floor(error_values.iter().copied());
    for row in &mut rows {
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for (_, pts) in &mut row.error {
            for p in pts.iter_mut() {
                if p.1 <= floor {
                    floored_any = true;
                }
                p.1 = on_log_axis(p.1, floor);
                lo = lo.min(p.1);
                hi = hi.max(p.1);
                p.1 = lg(p.1);
            }
        }
        row.y_error = lg_range(log_range(lo, hi));
    }
    let with_time = rows.iter().any(|r| r.time.is_some());
    let legend = used
        .iter()
        .map(|&c| (ds.cells[c].name.clone(), colour(c)))
        .collect();
    let mut caption = "Mean final error f − f* (log scale) and, when timing.csv is \
                       available, mean wall-clock time per run against the dimension, \
                       for every function run at several dimensions."
        .to_owned();
    if floored_any {
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
    Ok(Plot {
        stem: "scalability".into(),
        title: "Scalability".into(),
        caption,
        figure: Figure::Scalability(Scalability {
            title: "Scalability with the dimension".into(),
            legend,
            rows,
            with_time,
        }),
    })
}

// ------------------------------------------------------------------ heat maps

/// A parameter-grid heat-map figure.
pub(crate) struct Heat {
    title: String,
    map: HeatMap,
}

impl Heat {
    fn panel_size(&self) -> (u32, u32) {
        let ylab = self
            .map
            .y_values
            .iter()
            .map(|v| text_width(v, TICK_FONT))
            .max()
            .unwrap_or(20);
        let w = (110 + ylab + 70 * self.map.x_values.len() as u32 + 110).max(420);
        let h = (150 + 46 * self.map.y_values.len() as u32).max(300);
        (w, h)
    }
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.map.panels.len(), 3);
        let (pw, ph) = self.panel_size();
        (cols as u32 * pw, TITLE_H + rows as u32 * ph)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &[])?;
        let (rows, cols) = grid_shape(self.map.panels.len(), 3);
        let areas = area.split_evenly((rows, cols));
        let nx = self.map.x_values.len();
        let ny = self.map.y_values.len();
        let ylab = self
            .map
            .y_values
            .iter()
            .map(|v| text_width(v, TICK_FONT))
            .max()
            .unwrap_or(20);
        for (panel, a) in self.map.panels.iter().zip(&areas) {
            let (title, m, best) = (&panel.title, &panel.mean, &panel.best);
            let (w, _) = a.dim_in_pixel();
            let (plot_area, bar_area) = a.split_horizontally(w.saturating_sub(110));
            let mut chart = ChartBuilder::on(&plot_area)
                .caption(title, font(PANEL_TITLE_FONT))
                .margin(10)
                .x_label_area_size(58)
                .y_label_area_size(ylab + 50)
                .build_cartesian_2d(0f64..nx as f64, 0f64..ny as f64)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_labels(0)
                .y_labels(0)
                .x_desc(self.map.x_param.as_str())
                .y_desc(self.map.y_param.as_str())
                .axis_desc_style(font(AXIS_FONT))
                .draw()?;
            let logs: Vec<f64> = m
                .iter()
                .flatten()
                .flatten()
                .filter(|v| v.is_finite() && **v > 0.0)
                .map(|v| v.log10())
                .collect();
            let lmin = logs.iter().copied().fold(f64::INFINITY, f64::min);
            let lmax = logs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let t_of = |v: f64| -> f64 {
                if !(v.is_finite() && v > 0.0 && lmin.is_finite()) {
                    return 0.0;
                }
                if lmax - lmin < 1e-12 {
                    0.5
                } else {
                    (v.log10() - lmin) / (lmax - lmin)
                }
            };
            for (yi, row) in m.iter().enumerate() {
                for (xi, v) in row.iter().enumerate() {
                    let (x0, y0) = (xi as f64, yi as f64);
                    let (fill, text, text_colour) = match v {
                        Some(v) => {
                            let t = t_of(*v);
                            let tc = if t < 0.6 { WHITE } else { BLACK };
                            (viridis(t), cell_label(*v), tc)
                        }
                        None => (RGBColor(225, 225, 225), "n/a".to_owned(), BLACK),
                    };
                    chart.draw_series([
                        Rectangle::new([(x0, y0), (x0 + 1.0, y0 + 1.0)], fill.filled()),
                        Rectangle::new([(x0, y0), (x0 + 1.0, y0 + 1.0)], WHITE.stroke_width(1)),
                    ])?;
                    chart.draw_series(std::iter::once(Text::new(
                        text,
                        (x0 + 0.5, y0 + 0.5),
                        font(TICK_FONT)
                            .color(&text_colour)
                            .pos(Pos::new(HPos::Center, VPos::Center)),
                    )))?;
                }
            }
            if let Some((yi, xi)) = best {
                let (x0, y0) = (*xi as f64, *yi as f64);
                chart.draw_series(std::iter::once(Rectangle::new(
                    [(x0 + 0.03, y0 + 0.03), (x0 + 0.97, y0 + 0.97)],
                    RGBColor(220, 20, 60).stroke_width(4),
                )))?;
            }
            let base = plot_area.get_base_pixel();
            let xs = font(TICK_FONT).pos(Pos::new(HPos::Center, VPos::Top));
            for (xi, v) in self.map.x_values.iter().enumerate() {
                let (px, py) = chart.backend_coord(&(xi as f64 + 0.5, 0.0));
                plot_area.draw_text(v, &xs, (px - base.0, py - base.1 + 6))?;
            }
            let ys = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Center));
            for (yi, v) in self.map.y_values.iter().enumerate() {
                let (px, py) = chart.backend_coord(&(0.0, yi as f64 + 0.5));
                plot_area.draw_text(v, &ys, (px - base.0 - 8, py - base.1))?;
            }
            // Colour bar.
            let (_, bh) = bar_area.dim_in_pixel();
            let (top, bottom) = (60i32, bh as i32 - 70);
            if bottom > top + 20 && lmin.is_finite() {
                let steps = 40;
                let span = (bottom - top) as f64 / steps as f64;
                for s in 0..steps {
                    let t = 1.0 - s as f64 / (steps - 1) as f64;
                    let y0 = top + (s as f64 * span) as i32;
                    let y1 = top + ((s + 1) as f64 * span).ceil() as i32;
                    bar_area.draw(&Rectangle::new([(14, y0), (32, y1)], viridis(t).filled()))?;
                }
                let ls = font(TICK_FONT).pos(Pos::new(HPos::Left, VPos::Center));
                bar_area.draw_text(&cell_label(10f64.powf(lmax)), &ls, (38, top + 4))?;
                bar_area.draw_text(&cell_label(10f64.powf(lmin)), &ls, (38, bottom - 4))?;
                bar_area.draw_text(
                    "mean error",
                    &font(TICK_FONT).pos(Pos::new(HPos::Left, VPos::Bottom)),
                    (6, top - 10),
                )?;
            }
        }
        Ok(())
    }
}

fn heat(map: HeatMap) -> Plot {
    let kv: Vec<String> = map.fixed.iter().map(|(k, v)| format!("{k}={v}")).collect();
    let (fixed, suffix) = if kv.is_empty() {
        (String::new(), String::new())
    } else {
        (
            format!(
                " The grid varies more parameters; the map is its slice through the \
                 overall best setting, with {} fixed.",
                kv.join(", ")
            ),
            format!(" ({})", kv.join(", ")),
        )
    };
    let caption = format!(
        "Mean final error f − f* of {} over its {} × {} grid ({} horizontally, {} \
         vertically), one panel per problem; colours follow log10 of the mean error on \
         a per-panel scale (dark = low error), the value is printed in each cell and the \
         red frame marks the best setting of the panel (lowest mean error).{fixed}",
        map.label, map.x_param, map.y_param, map.x_param, map.y_param
    );

    Plot {
        stem: format!("tuning_{}", map.slug),
        title: format!("Parameter grid of {}", map.label),
        caption,
        figure: Figure::Heat(Heat {
            title: format!(
                "{}: mean final error over {} × {}{suffix}",
                map.label, map.x_param, map.y_param
            ),
            map,
        }),
    }
}

/// Every figure of the report that the data allows, and a note for each one
/// that it does not.
pub(crate) fn figures(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    heat_maps: Vec<HeatMap>,
    threshold: Option<f64>,
) -> (Vec<Plot>, Vec<String>) {
    let mut plots = Vec::new();
    let mut notes = Vec::new();
    for result in [
        convergence(ds),
        boxes(ds),
        ecdf(ds, threshold),
        scalability(ds, stats),
    ] {
        match result {
            Ok(p) => plots.push(p),
            Err(n) => notes.push(n),
        }
    }
    plots.extend(heat_maps.into_iter().map(heat));
    (plots, notes)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_statistics_use_tukey_whiskers() {
        let b = box_stat(&[1.0, 2.0, 3.0, 4.0, 100.0]).unwrap();
        assert_eq!((b.q1, b.median, b.q3), (2.0, 3.0, 4.0));
        assert_eq!((b.lo, b.hi), (1.0, 4.0));
        assert_eq!(b.outliers, vec![100.0]);
        assert!(box_stat(&[]).is_none());
        let one = box_stat(&[5.0]).unwrap();
        assert_eq!((one.lo, one.hi), (5.0, 5.0));
    }

    #[test]
    fn value_at_takes_the_last_checkpoint() {
        let r = Run {
            run: 0,
            budget: 100,
            error: 0.1,
            evaluations: 100,
            evaluations_to_target: None,
            success: false,
            trace: vec![(1, 5.0), (10, 1.0), (100, 0.1)],
            wall_seconds: None,
        };
        assert_eq!(value_at(&r, 0), None);
        assert_eq!(value_at(&r, 1), Some(5.0));
        assert_eq!(value_at(&r, 50), Some(1.0));
        assert_eq!(value_at(&r, 1000), Some(0.1));
    }

    #[test]
    fn grid_shapes() {
        assert_eq!(grid_shape(1, 3), (1, 1));
        assert_eq!(grid_shape(4, 3), (2, 3));
        assert_eq!(grid_shape(0, 3), (1, 1));
    }
}
