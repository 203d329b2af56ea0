//! The convergence figure: per problem, the median best-so-far error of
//! every algorithm against objective evaluations, with the interquartile
//! band, both axes on log scales.

use std::collections::BTreeSet;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::stats::summarize;

use super::super::data::{Dataset, Run};
use super::super::format::sci_digits;
use super::super::render::{
    draw_line, draw_minor_decades, font, lg, lg_range, log_floor, log_range, on_log_axis, Draw,
    DrawResult, FloorTick,
};
use super::super::style::{LegendEntry, SeriesStyle};
use super::layout::{
    decade_labels, decade_tick, draw_floor_label, floored_tick, frame, frame_height, grid_shape,
    pages_of, Axis, AXIS_FONT, PANEL_H, PANEL_TITLE_FONT, PANEL_W, TICK_FONT,
};
use super::{Figure, NoPlot, Page, Plot, SeriesSet};

/// (evaluations, q1, median, q3) of a convergence curve.
type Quartiles = Vec<(u64, f64, f64, f64)>;

/// One problem's raw curves: (problem, [(cell, quartiles)]).
type ProblemCurves = (usize, Vec<(usize, Quartiles)>);

/// One algorithm's curve: (evaluations, q1, median, q3), floored.
pub(crate) struct Band {
    /// How the curve is drawn (its cell's style).
    pub style: SeriesStyle,
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
    /// The error's name on the axis (`f − f*`, or `E` for fitting).
    symbol: &'static str,
    legend: Vec<LegendEntry>,
    /// The tick of the error axis's floor, when some error is drawn at it.
    floor: Option<FloorTick>,
    panels: Vec<ConvergencePanel>,
}

impl Convergence {
    /// The figure split into pages of whole panels, none taller than
    /// `max` pixels (one page when it fits).
    pub(super) fn pages(self, max: u32) -> Vec<Convergence> {
        let (_, cols) = grid_shape(self.panels.len(), 3);
        let head = frame_height(cols as u32 * PANEL_W, &self.legend);
        let rows = (max.saturating_sub(head) / PANEL_H).max(1) as usize;
        let Convergence {
            title,
            symbol,
            legend,
            floor,
            panels,
        } = self;
        pages_of(panels, rows * cols)
            .into_iter()
            .map(|panels| Convergence {
                title: title.clone(),
                symbol,
                legend: legend.clone(),
                floor,
                panels,
            })
            .collect()
    }
}

impl Draw for Convergence {
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.panels.len(), 3);
        let w = cols as u32 * PANEL_W;
        (w, frame_height(w, &self.legend) + rows as u32 * PANEL_H)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend)?;
        let areas = area.split_evenly(grid_shape(self.panels.len(), 3));
        for (panel, a) in self.panels.iter().zip(&areas) {
            draw_panel(panel, self.symbol, self.floor, a)?;
        }
        Ok(())
    }
}

/// Draws one problem's panel: axes, then a band and a median line per cell.
fn draw_panel<DB: DrawingBackend>(
    panel: &ConvergencePanel,
    symbol: &str,
    floor: Option<FloorTick>,
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
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
        .y_desc(format!("{symbol} (log scale)"))
        .x_label_formatter(&|v| decade_tick(*v, panel.x))
        .y_label_formatter(&|v| floored_tick(*v, panel.y, floor))
        .x_labels(decade_labels(panel.x))
        .y_labels(decade_labels(panel.y))
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    draw_minor_decades(&mut chart, panel.x, panel.y, true, true)?;
    draw_floor_label(a, &chart, floor, (Axis::Y, panel.y), panel.x.0)?;
    for band in &panel.bands {
        let c = band.style.colour;
        if band.points.len() >= 2 {
            let mut poly: Vec<(f64, f64)> = band.points.iter().map(|p| (p.0, p.3)).collect();
            poly.extend(band.points.iter().rev().map(|p| (p.0, p.1)));
            chart.draw_series(std::iter::once(Polygon::new(poly, c.mix(0.18).filled())))?;
        }
        draw_line(
            &mut chart,
            band.points.iter().map(|p| (p.0, p.2)).collect(),
            band.style,
            2,
        )?;
        if band.points.len() == 1 {
            let p = band.points[0];
            chart.draw_series(std::iter::once(Circle::new((p.0, p.2), 3, c.filled())))?;
        }
    }
    Ok(())
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

/// The (q1, median, q3) curve of `runs` over their checkpoints, at the
/// checkpoints where every run has a finite best-so-far value.
fn quartile_curve(runs: &[&Run]) -> Quartiles {
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
    pts
}

/// The raw quartile curves of every problem that has one, the cells that
/// have a curve, and the largest number of runs behind a curve.
fn raw_curves(ds: &Dataset, series: &SeriesSet) -> (Vec<ProblemCurves>, BTreeSet<usize>, usize) {
    let mut raw = Vec::new();
    let mut used_cells = BTreeSet::new();
    let mut max_runs = 0usize;
    for p in 0..ds.problems.len() {
        let mut curves = Vec::new();
        for &c in &series.cells {
            let runs: Vec<&Run> = ds
                .runs(p, c)
                .iter()
                .filter(|r| !r.trace.is_empty())
                .collect();
            if runs.is_empty() {
                continue;
            }
            max_runs = max_runs.max(runs.len());
            let pts = quartile_curve(&runs);
            if !pts.is_empty() {
                used_cells.insert(c);
                curves.push((c, pts));
            }
        }
        if !curves.is_empty() {
            raw.push((p, curves));
        }
    }
    (raw, used_cells, max_runs)
}

/// One problem's panel: its curves on log10 axes, errors at least `floor`.
fn panel(
    ds: &Dataset,
    series: &SeriesSet,
    (p, curves): ProblemCurves,
    floor: f64,
) -> ConvergencePanel {
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
        bands.push(Band {
            style: series.style(c),
            points,
        });
    }
    let x = if xmax > 0.0 { (0.0, xmax) } else { (-0.3, 0.3) };
    ConvergencePanel {
        title: ds.problems[p].title(),
        bands,
        x,
        y: lg_range(log_range(10f64.powf(ylo), 10f64.powf(yhi))),
    }
}

/// The caption: how the curves are computed, and the floor when some
/// errors are drawn at it.
fn caption(symbol: &str, max_runs: usize, floor: Option<f64>) -> String {
    let mut caption = format!(
        "Median best-so-far error {symbol} against objective evaluations, both on log \
         scales, over the runs of each algorithm (up to {max_runs} per problem); the \
         shaded band is the interquartile range (25 % to 75 %, type-7 quantiles). A \
         checkpoint is drawn once every run has a finite best-so-far value."
    );
    if let Some(floor) = floor {
        caption.push_str(&format!(
            " Errors ≤ {} (including exact zeros) are drawn at {} so that the log scale \
             can show them.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    caption
}

/// The convergence plot, or why there is none.
pub(super) fn convergence(ds: &Dataset, series: &SeriesSet) -> Result<Plot, NoPlot> {
    if !ds.has_convergence {
        return Err(NoPlot::NoTrace);
    }
    // Raw (q1, median, q3) curves first, then floor them together.
    let (raw, used_cells, max_runs) = raw_curves(ds, series);
    if raw.is_empty() {
        return Err(NoPlot::NoFiniteTrace);
    }
    let all = raw
        .iter()
        .flat_map(|(_, cs)| cs.iter().flat_map(|(_, pts)| pts.iter()))
        .flat_map(|&(_, a, b, c)| [a, b, c]);
    let floor = log_floor(all.clone());
    let floor_tick = FloorTick::of(all, floor);
    let panels = raw
        .into_iter()
        .map(|r| panel(ds, series, r, floor))
        .collect();
    let legend = series.legend(used_cells);
    Ok(Plot {
        page: Page::SINGLE,
        stem: "convergence".into(),
        title: "Convergence".into(),
        caption: caption(ds.error_symbol(), max_runs, floor_tick.map(|_| floor))
            + &series.caption_note(),
        figure: Figure::Convergence(Convergence {
            symbol: ds.error_symbol(),
            title: "Median best-so-far error (band: interquartile range)".into(),
            legend,
            floor: floor_tick,
            panels,
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_at_takes_the_last_checkpoint() {
        let r = Run {
            run: 0,
            seed: 0,
            budget: 100,
            error: 0.1,
            evaluations: 100,
            evaluations_to_target: None,
            success: false,
            trace: vec![(1, 5.0), (10, 1.0), (100, 0.1)],
            hits: Vec::new(),
            wall_seconds: None,
        };
        assert_eq!(value_at(&r, 0), None);
        assert_eq!(value_at(&r, 1), Some(5.0));
        assert_eq!(value_at(&r, 50), Some(1.0));
        assert_eq!(value_at(&r, 1000), Some(0.1));
    }
}
