//! The layout shared by the report's figures: panel sizes and fonts, the
//! grid of panels, the title-and-legend frame, and the labels of log10
//! axes. The drawing primitives themselves live in [`crate::render`].

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::format::pow_tick;
use crate::render::{draw_legend, draw_title, font, legend_height, FloorTick, PlotError};
use crate::style::LegendEntry;

/// Width of one panel in pixels.
pub const PANEL_W: u32 = 540;
/// Height of one panel in pixels.
pub const PANEL_H: u32 = 400;
/// Height of the title strip of a figure.
pub const TITLE_H: u32 = 44;
/// Font size of axis descriptions.
pub const AXIS_FONT: u32 = 15;
/// Font size of tick labels.
pub const TICK_FONT: u32 = 13;
/// Font size of panel titles.
pub const PANEL_TITLE_FONT: u32 = 17;

/// A chart with linear axes of `f64` (log-scaled axes hold log10 values).
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A cell's polyline: (cell, points).
pub type Line = (usize, Vec<(f64, f64)>);

/// How many labels to ask plotters for on a log10 axis so that they fall
/// on whole decades: one per decade, at most 9.
pub fn decade_labels((lo, hi): (f64, f64)) -> usize {
    let span = hi - lo;
    if span.is_finite() && span >= 1.0 {
        (span.floor() as usize + 1).clamp(2, 9)
    } else {
        5
    }
}

/// The label of a log10-axis position: powers of ten only, unless the axis
/// spans less than a decade.
pub fn decade_tick(v: f64, (lo, hi): (f64, f64)) -> String {
    if hi - lo >= 1.0 && (v - v.round()).abs() > 1e-6 {
        String::new()
    } else {
        pow_tick(v)
    }
}

/// [`decade_tick`] on an axis with a floor: blank at the floor, whose label
/// [`draw_floor_label`] draws whether or not plotters puts a tick there,
/// and, on an axis over more than 12 decades, blank within a decade per 12
/// of the floor so that the two labels do not overlap.
pub fn floored_tick(v: f64, range: (f64, f64), floor: Option<FloorTick>) -> String {
    let clear = ((range.1 - range.0) / 12.0).floor().max(0.0) + 1e-6;
    match floor {
        Some(f) if (v - f.at).abs() < clear => String::new(),
        _ => decade_tick(v, range),
    }
}

/// The label of a log axis's floor: "0" when only exact zeros are drawn
/// there, else "≤" and its power of ten.
fn floor_text(f: FloorTick) -> String {
    if f.zeros_only {
        "0".to_owned()
    } else {
        format!("≤{}", pow_tick(f.at))
    }
}

/// Which axis of a chart carries a floor.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// The horizontal axis (box plots).
    X,
    /// The vertical axis (convergence, scalability).
    Y,
}

/// Draws the floor's tick mark and label on `axis` of `chart` (whose
/// range on that axis is `range` and whose other axis starts at
/// `other_lo`), outside the plotting area as the other tick labels are;
/// nothing when the floor is outside `range`.
pub fn draw_floor_label<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    chart: &Chart<'_, DB>,
    floor: Option<FloorTick>,
    (axis, range): (Axis, (f64, f64)),
    other_lo: f64,
) -> Result<(), PlotError> {
    let Some(f) = floor.filter(|f| f.at >= range.0 && f.at <= range.1) else {
        return Ok(());
    };
    let base = area.get_base_pixel();
    let point = match axis {
        Axis::X => (f.at, other_lo),
        Axis::Y => (other_lo, f.at),
    };
    let (px, py) = chart.backend_coord(&point);
    let (x, y) = (px - base.0, py - base.1);
    let text = floor_text(f);
    match axis {
        Axis::X => {
            area.draw(&PathElement::new(
                vec![(x, y), (x, y + 5)],
                BLACK.stroke_width(1),
            ))?;
            let style = font(TICK_FONT).pos(Pos::new(HPos::Center, VPos::Top));
            area.draw_text(&text, &style, (x, y + 8))?;
        }
        Axis::Y => {
            area.draw(&PathElement::new(
                vec![(x - 5, y), (x, y)],
                BLACK.stroke_width(1),
            ))?;
            let style = font(TICK_FONT).pos(Pos::new(HPos::Right, VPos::Center));
            area.draw_text(&text, &style, (x - 8, y))?;
        }
    }
    Ok(())
}

/// Rows and columns of a grid of `n` panels at most `max_cols` wide.
pub fn grid_shape(n: usize, max_cols: usize) -> (usize, usize) {
    let cols = n.clamp(1, max_cols.max(1));
    let rows = n.div_ceil(cols).max(1);
    (rows, cols)
}

/// `items` in order, in pages of at most `per_page` each (at least one item
/// per page; a single page when they fit): how a figure's panels are split
/// into pages that fit a screen.
pub fn pages_of<T>(mut items: Vec<T>, per_page: usize) -> Vec<Vec<T>> {
    let per_page = per_page.max(1);
    let mut pages = Vec::with_capacity(items.len().div_ceil(per_page).max(1));
    while items.len() > per_page {
        let rest = items.split_off(per_page);
        pages.push(std::mem::replace(&mut items, rest));
    }
    pages.push(items);
    pages
}

/// Splits the canvas into a title strip, a legend strip and the panels area.
pub fn frame<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    legend: &[LegendEntry],
) -> Result<DrawingArea<DB, Shift>, PlotError> {
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

/// Height of the title and legend strips of [`frame`] at `width`.
pub fn frame_height(width: u32, legend: &[LegendEntry]) -> u32 {
    TITLE_H
        + if legend.is_empty() {
            0
        } else {
            legend_height(legend, width)
        }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_keep_the_order_and_fill_all_but_the_last() {
        assert_eq!(
            pages_of(vec![1, 2, 3, 4, 5], 2),
            [vec![1, 2], vec![3, 4], vec![5]]
        );
        assert_eq!(pages_of(vec![1, 2], 2), [vec![1, 2]]);
        assert_eq!(pages_of(vec![1, 2], 0), [vec![1], vec![2]]);
        assert_eq!(pages_of(Vec::<u8>::new(), 3), [Vec::<u8>::new()]);
    }

    #[test]
    fn the_floor_label_replaces_the_ticks_next_to_it() {
        let zero = FloorTick {
            at: -16.0,
            zeros_only: true,
        };
        let zeros = Some(zero);
        assert_eq!(floored_tick(-16.0, (-16.2, 2.0), zeros), "");
        assert_eq!(floored_tick(-15.0, (-16.2, 2.0), zeros), "");
        assert_eq!(floored_tick(-10.0, (-16.2, 2.0), zeros), pow_tick(-10.0));
        assert_eq!(floored_tick(-3.0, (-4.2, 2.0), zeros), pow_tick(-3.0));
        assert_eq!(floor_text(zero), "0");
        let tiny = FloorTick {
            at: -16.0,
            zeros_only: false,
        };
        assert_eq!(floor_text(tiny), format!("≤{}", pow_tick(-16.0)));
    }

    #[test]
    fn grid_shapes() {
        assert_eq!(grid_shape(1, 3), (1, 1));
        assert_eq!(grid_shape(4, 3), (2, 3));
        assert_eq!(grid_shape(0, 3), (1, 1));
    }
}
