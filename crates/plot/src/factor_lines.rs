//! Lines over a design factor: in each panel, the median of a measure at
//! every level of one factor (the evaluation budget, the technique's
//! α_size, a defect's width) with its interquartile range, one line per
//! method in the method's fixed colour ([`crate::style`]). The
//! spread is a shaded band (levels read as a continuum) or a vertical bar
//! per method, the methods set side by side at each level (a few discrete
//! levels). Either axis may be log10; ticks of the factor axis are at its
//! levels. An optional horizontal reference line (ratio 1: the bounding
//! box) carries its own label.
//!
//! The quartiles are type-7 (Hyndman & Fan 1996, as in
//! `metabezier_core::stats::summarize`); the figures that use this drawing
//! are built in the report's `plots::fit_factors` (chapter 5) and in the
//! implant's `implant::render` (chapter 6).

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::files::fmt_real;

use crate::format::pow_tick;
use crate::layout::{
    decade_labels, draw_floor_label, floored_tick, frame, frame_height, grid_shape, pages_of, Axis,
    Chart, AXIS_FONT, PANEL_H, PANEL_TITLE_FONT, PANEL_W, TICK_FONT,
};
use crate::render::{
    draw_line, draw_minor_decades, font, lg, log_floor, log_range, on_log_axis, Draw, DrawResult,
    FloorTick, PlotError,
};
use crate::style::{LegendEntry, SeriesStyle};

/// One method's line: (level, q1, median, q3) in data units, in increasing
/// level.
pub struct FactorSeries {
    /// The method's colour and dash.
    pub style: SeriesStyle,
    /// (level, first quartile, median, third quartile).
    pub points: Vec<(f64, f64, f64, f64)>,
}

/// How the interquartile range is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spread {
    /// A shaded band between the quartiles.
    Band,
    /// A vertical bar from q1 to q3 at each level, the methods side by side.
    Bars,
}

/// One panel: its title, the description of its vertical axis, its lines
/// and an optional labelled horizontal reference line.
pub struct FactorPanel {
    /// The panel title.
    pub title: String,
    /// The vertical axis's description (without "(log scale)").
    pub y_label: String,
    /// Whether the vertical axis is log10.
    pub y_log: bool,
    /// The lines.
    pub series: Vec<FactorSeries>,
    /// A horizontal reference line: (value, label).
    pub reference: Option<(f64, String)>,
}

/// The figure: a title, a shared legend, the factor axis, and panels in a
/// grid of at most `columns` columns.
pub struct FactorLines {
    /// The title over the legend.
    pub title: String,
    /// The legend (one entry per method).
    pub legend: Vec<LegendEntry>,
    /// The factor axis's description (without "(log scale)").
    pub x_label: String,
    /// Whether the factor axis is log10.
    pub x_log: bool,
    /// The spread's drawing.
    pub spread: Spread,
    /// At most this many panels side by side.
    pub columns: usize,
    /// The panels.
    pub panels: Vec<FactorPanel>,
}

impl FactorLines {
    /// The figure split into pages of whole panels, none taller than `max`
    /// pixels (one page when it fits).
    pub fn pages(self, max: u32) -> Vec<FactorLines> {
        let (_, cols) = grid_shape(self.panels.len(), self.columns);
        let head = frame_height(cols as u32 * PANEL_W, &self.legend);
        let rows = (max.saturating_sub(head) / PANEL_H).max(1) as usize;
        let FactorLines {
            title,
            legend,
            x_label,
            x_log,
            spread,
            columns,
            panels,
        } = self;
        pages_of(panels, rows * cols)
            .into_iter()
            .map(|panels| FactorLines {
                title: title.clone(),
                legend: legend.clone(),
                x_label: x_label.clone(),
                x_log,
                spread,
                columns,
                panels,
            })
            .collect()
    }
}

impl FactorPanel {
    /// The levels of the factor in this panel, sorted and distinct
    /// (positive ones only on a log axis).
    fn levels(&self, x_log: bool) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|q| q.0))
            .filter(|x| x.is_finite() && (!x_log || *x > 0.0))
            .collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }
}

impl Draw for FactorLines {
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.panels.len(), self.columns);
        let w = cols as u32 * PANEL_W;
        (w, frame_height(w, &self.legend) + rows as u32 * PANEL_H)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &self.legend)?;
        let areas = area.split_evenly(grid_shape(self.panels.len(), self.columns));
        for (panel, a) in self.panels.iter().zip(&areas) {
            draw_panel(self, &panel.levels(self.x_log), panel, a)?;
        }
        Ok(())
    }
}

/// A factor level on the drawing's horizontal axis (log10 when `log`).
fn x_of(x: f64, log: bool) -> f64 {
    if log {
        lg(x)
    } else {
        x
    }
}

/// The horizontal range over `levels` (drawing units) with half the
/// smallest gap between levels (or a fixed margin) on either side, and the
/// offset between methods set side by side.
fn x_range(levels: &[f64], n_series: usize, spread: Spread) -> ((f64, f64), f64) {
    let gap = levels
        .windows(2)
        .map(|w| w[1] - w[0])
        .fold(f64::INFINITY, f64::min);
    let gap = if gap.is_finite() && gap > 0.0 {
        gap
    } else {
        1.0
    };
    let (lo, hi) = match (levels.first(), levels.last()) {
        (Some(&a), Some(&b)) => (a, b),
        _ => (0.0, 1.0),
    };
    let dodge = match spread {
        Spread::Bars if n_series > 1 => 0.5 * gap / n_series as f64,
        _ => 0.0,
    };
    ((lo - 0.45 * gap, hi + 0.45 * gap), dodge)
}

/// The vertical range of `panel` (drawing units), its floor (log axes) and
/// the floor's tick when some value is drawn at it.
fn y_range(panel: &FactorPanel) -> ((f64, f64), f64, Option<FloorTick>) {
    let values: Vec<f64> = panel
        .series
        .iter()
        .flat_map(|s| s.points.iter().flat_map(|q| [q.1, q.2, q.3]))
        .chain(panel.reference.iter().map(|r| r.0))
        .filter(|v| !v.is_nan())
        .collect();
    if panel.y_log {
        let floor = log_floor(values.iter().copied());
        let tick = FloorTick::of(values.iter().copied(), floor);
        let on = |v: f64| on_log_axis(v, floor);
        let lo = values.iter().map(|&v| on(v)).fold(f64::INFINITY, f64::min);
        let hi = values
            .iter()
            .map(|&v| on(v))
            .fold(f64::NEG_INFINITY, f64::max);
        let (a, b) = log_range(lo, hi);
        ((lg(a), lg(b)), floor, tick)
    } else {
        let finite = values.iter().filter(|v| v.is_finite());
        let lo = finite.clone().fold(f64::INFINITY, |a, &b| a.min(b));
        let hi = finite.fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        let (lo, hi) = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        let pad = if hi > lo { 0.08 * (hi - lo) } else { 0.5 };
        ((lo - pad, hi + pad), f64::NEG_INFINITY, None)
    }
}

/// The positions (log10) of 2 × 10ᵏ and 5 × 10ᵏ inside `range` when it
/// spans fewer than 3 decades, clear of the floor's label.
fn between_decades(range: (f64, f64), floor: Option<FloorTick>) -> Vec<(f64, String)> {
    let span = range.1 - range.0;
    if span.is_nan() || span >= 3.0 {
        return Vec::new();
    }
    let (k0, k1) = (range.0.floor() as i32, range.1.ceil() as i32);
    (k0..=k1)
        .flat_map(|k| [2f64, 5.0].map(|m| (k as f64 + m.log10(), m, k)))
        .filter(|(v, _, _)| *v > range.0 && *v < range.1)
        .filter(|(v, _, _)| floor.is_none_or(|f| (v - f.at).abs() > 0.2))
        .map(|(v, m, k)| {
            // Plain decimals between 0.001 and 10⁴, powers of ten beyond.
            let text = if (-3..4).contains(&k) {
                fmt_real(format!("{:.3}", m * 10f64.powi(k)).parse().unwrap_or(0.0))
            } else {
                pow_tick(v)
            };
            (v, text)
        })
        .collect()
}

/// A tick label of a factor level: its shortest decimal text.
fn level_text(x: f64) -> String {
    fmt_real(x)
}

/// Draws one panel: axes with a tick at every level, the reference line,
/// then each method's spread and median line with markers.
fn draw_panel<DB: DrawingBackend>(
    fig: &FactorLines,
    levels: &[f64],
    panel: &FactorPanel,
    a: &DrawingArea<DB, Shift>,
) -> DrawResult {
    let xs: Vec<f64> = levels.iter().map(|&l| x_of(l, fig.x_log)).collect();
    let (x, dodge) = x_range(&xs, panel.series.len(), fig.spread);
    let (y, floor, floor_tick) = y_range(panel);
    let mut chart = panel_chart(fig, panel, a, (x, y), floor_tick)?;
    draw_levels(&mut chart, a, levels, &xs, y)?;
    let y_log = panel.y_log;
    let on_y = |v: f64| {
        if y_log {
            lg(on_log_axis(v, floor))
        } else {
            v
        }
    };
    if let Some((value, label)) = &panel.reference {
        draw_reference(&mut chart, a, on_y(*value), label, x)?;
    }
    let n = panel.series.len();
    for (i, s) in panel.series.iter().enumerate() {
        let shift = dodge * (i as f64 - (n as f64 - 1.0) / 2.0);
        let pts: Vec<(f64, f64, f64, f64)> = s
            .points
            .iter()
            .filter(|q| q.2.is_finite() || (y_log && q.2 <= 0.0))
            .map(|q| {
                (
                    x_of(q.0, fig.x_log) + shift,
                    on_y(q.1),
                    on_y(q.2),
                    on_y(q.3),
                )
            })
            .filter(|q| q.0.is_finite())
            .collect();
        draw_method(&mut chart, fig.spread, s.style, &pts)?;
    }
    Ok(())
}

/// The chart of a panel over `x` × `y` (data ranges, log10 where the axis
/// is): its title, axes and mesh, on a log axis the minor decades, the
/// floor's label and, on fewer than 3 decades, labels at 2 and 5 times
/// each decade.
fn panel_chart<'a, DB: DrawingBackend>(
    fig: &FactorLines,
    panel: &FactorPanel,
    a: &'a DrawingArea<DB, Shift>,
    (x, y): ((f64, f64), (f64, f64)),
    floor_tick: Option<FloorTick>,
) -> Result<Chart<'a, DB>, PlotError> {
    let y_desc = if panel.y_log {
        format!("{} (log scale)", panel.y_label)
    } else {
        panel.y_label.clone()
    };
    let x_desc = if fig.x_log {
        format!("{} (log scale)", fig.x_label)
    } else {
        fig.x_label.clone()
    };
    let mut chart = ChartBuilder::on(a)
        .caption(&panel.title, font(PANEL_TITLE_FONT))
        .margin(10)
        .margin_right(22)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    let y_log = panel.y_log;
    let y_fmt = move |v: &f64| {
        if y_log {
            floored_tick(*v, y, floor_tick)
        } else {
            let step = (y.1 - y.0) / 8.0;
            let digits = if step > 0.0 {
                (-step.log10().floor()).clamp(0.0, 6.0) as usize
            } else {
                2
            };
            format!("{v:.digits$}")
        }
    };
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|_| String::new())
        .y_label_formatter(&y_fmt)
        .x_labels(0)
        .y_labels(if y_log { decade_labels(y) } else { 8 })
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .disable_x_mesh()
        .draw()?;
    if y_log {
        draw_minor_decades(&mut chart, x, y, false, true)?;
        draw_floor_label(a, &chart, floor_tick, (Axis::Y, y), x.0)?;
        // On an axis of fewer than 3 decades, 2 and 5 times each decade are
        // labelled too, so that every panel reads at least two values.
        let base = a.get_base_pixel();
        let style = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Center));
        for (v, text) in between_decades(y, floor_tick) {
            let (px, py) = chart.backend_coord(&(x.0, v));
            let (px, py) = (px - base.0, py - base.1);
            a.draw(&PathElement::new(
                vec![(px - 5, py), (px, py)],
                BLACK.stroke_width(1),
            ))?;
            a.draw_text(&text, &style, (px - 8, py))?;
        }
    }
    Ok(chart)
}

/// The factor's levels: a light vertical line and a tick label at each
/// (`xs` their positions on the horizontal axis, `y` the vertical axis's
/// range).
fn draw_levels<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    a: &DrawingArea<DB, Shift>,
    levels: &[f64],
    xs: &[f64],
    y: (f64, f64),
) -> DrawResult {
    let grid = RGBColor(215, 215, 215).stroke_width(1);
    chart.draw_series(
        xs.iter()
            .map(|&v| PathElement::new(vec![(v, y.0), (v, y.1)], grid)),
    )?;
    let base = a.get_base_pixel();
    let tick = font(TICK_FONT).pos(Pos::new(HPos::Center, VPos::Top));
    for (&l, &v) in levels.iter().zip(xs) {
        let (px, py) = chart.backend_coord(&(v, y.0));
        let (px, py) = (px - base.0, py - base.1);
        a.draw(&PathElement::new(
            vec![(px, py), (px, py + 5)],
            BLACK.stroke_width(1),
        ))?;
        a.draw_text(&level_text(l), &tick, (px, py + 8))?;
    }
    Ok(())
}

/// The horizontal reference line at `at` (on the axis) across `x`, dashed
/// grey, with its label at the right end.
fn draw_reference<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    a: &DrawingArea<DB, Shift>,
    at: f64,
    label: &str,
    x: (f64, f64),
) -> DrawResult {
    let grey = SeriesStyle {
        colour: RGBColor(90, 90, 90),
        dashed: true,
    };
    draw_line(chart, vec![(x.0, at), (x.1, at)], grey, 2)?;
    let base = a.get_base_pixel();
    let (px, py) = chart.backend_coord(&(x.1, at));
    let style = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Bottom));
    a.draw_text(label, &style, (px - base.0 - 4, py - base.1 - 3))?;
    Ok(())
}

/// One method's spread (band or bars), its median line and markers, from
/// its points (x, q1, median, q3) on the axes.
fn draw_method<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    spread: Spread,
    style: SeriesStyle,
    pts: &[(f64, f64, f64, f64)],
) -> DrawResult {
    let c = style.colour;
    match spread {
        Spread::Band if pts.len() >= 2 => {
            let mut poly: Vec<(f64, f64)> = pts.iter().map(|p| (p.0, p.3)).collect();
            poly.extend(pts.iter().rev().map(|p| (p.0, p.1)));
            chart.draw_series(std::iter::once(Polygon::new(poly, c.mix(0.15).filled())))?;
        }
        Spread::Band => {}
        Spread::Bars => {
            chart.draw_series(
                pts.iter()
                    .map(|p| PathElement::new(vec![(p.0, p.1), (p.0, p.3)], c.stroke_width(2))),
            )?;
        }
    }
    // Beside bars the line only links a method's medians: thinner.
    let width = if spread == Spread::Bars { 1 } else { 2 };
    draw_line(
        chart,
        pts.iter().map(|p| (p.0, p.2)).collect(),
        style,
        width,
    )?;
    chart.draw_series(pts.iter().map(|p| Circle::new((p.0, p.2), 4, c.filled())))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_are_set_side_by_side_within_a_level() {
        let ((lo, hi), dodge) = x_range(&[20.0, 30.0, 40.0], 4, Spread::Bars);
        assert!(lo < 20.0 && hi > 40.0);
        // Four methods side by side stay inside half the gap between widths.
        assert!(dodge > 0.0 && 3.0 * dodge < 10.0);
        assert_eq!(x_range(&[1.0, 2.0], 3, Spread::Band).1, 0.0);
        let between = between_decades((-0.8, 1.2), None);
        let texts: Vec<&str> = between.iter().map(|b| b.1.as_str()).collect();
        assert_eq!(texts, ["0.2", "0.5", "2", "5"]);
        assert_eq!(
            between_decades((5.5, 6.5), None)[0].1,
            pow_tick(5.0 + 5f64.log10())
        );
        assert!(between_decades((-10.0, 2.0), None).is_empty());
        let ((lo, hi), _) = x_range(&[], 2, Spread::Band);
        assert!(lo < hi);
    }

    #[test]
    fn a_log_panel_floors_zeros_and_covers_its_reference() {
        let panel = FactorPanel {
            title: String::new(),
            y_label: "E".into(),
            y_log: true,
            series: vec![FactorSeries {
                style: SeriesStyle::solid(BLACK),
                points: vec![(1.0, 0.0, 0.5, 2.0), (2.0, 0.1, 0.2, 0.3)],
            }],
            reference: Some((10.0, "bounding box".into())),
        };
        let ((lo, hi), floor, tick) = y_range(&panel);
        assert_eq!(floor, 1e-2);
        assert_eq!(
            tick,
            Some(FloorTick {
                at: -2.0,
                zeros_only: true
            })
        );
        assert!(lo <= -2.0 && hi >= 1.0, "{lo} {hi}");
    }
}
