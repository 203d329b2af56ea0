//! The layout shared by the report's figures: panel sizes and fonts, the
//! grid of panels, the title-and-legend frame, and the labels of log10
//! axes. The drawing primitives themselves live in [`super::super::render`].

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::super::format::pow_tick;
use super::super::render::{draw_legend, draw_title, legend_height, PlotError};

/// Width of one panel in pixels.
pub(super) const PANEL_W: u32 = 540;
/// Height of one panel in pixels.
pub(super) const PANEL_H: u32 = 400;
/// Height of the title strip of a figure.
pub(super) const TITLE_H: u32 = 44;
/// Font size of axis descriptions.
pub(super) const AXIS_FONT: u32 = 15;
/// Font size of tick labels.
pub(super) const TICK_FONT: u32 = 13;
/// Font size of panel titles.
pub(super) const PANEL_TITLE_FONT: u32 = 17;

/// A chart with linear axes of `f64` (log-scaled axes hold log10 values).
pub(super) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A cell's polyline: (cell, points).
pub(super) type Line = (usize, Vec<(f64, f64)>);

/// How many labels to ask plotters for on a log10 axis so that they fall
/// on whole decades: one per decade, at most 9.
pub(super) fn decade_labels((lo, hi): (f64, f64)) -> usize {
    let span = hi - lo;
    if span.is_finite() && span >= 1.0 {
        (span.floor() as usize + 1).clamp(2, 9)
    } else {
        5
    }
}

/// The label of a log10-axis position: powers of ten only, unless the axis
/// spans less than a decade.
pub(super) fn decade_tick(v: f64, (lo, hi): (f64, f64)) -> String {
    if hi - lo >= 1.0 && (v - v.round()).abs() > 1e-6 {
        String::new()
    } else {
        pow_tick(v)
    }
}

/// Rows and columns of a grid of `n` panels at most `max_cols` wide.
pub(super) fn grid_shape(n: usize, max_cols: usize) -> (usize, usize) {
    let cols = n.clamp(1, max_cols.max(1));
    let rows = n.div_ceil(cols).max(1);
    (rows, cols)
}

/// `items` in order, in pages of at most `per_page` each (at least one item
/// per page; a single page when they fit): how a figure's panels are split
/// into pages that fit a screen.
pub(super) fn pages_of<T>(mut items: Vec<T>, per_page: usize) -> Vec<Vec<T>> {
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
pub(super) fn frame<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    legend: &[(String, RGBColor)],
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
pub(super) fn frame_height(width: u32, legend: &[(String, RGBColor)]) -> u32 {
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
    fn grid_shapes() {
        assert_eq!(grid_shape(1, 3), (1, 1));
        assert_eq!(grid_shape(4, 3), (2, 3));
        assert_eq!(grid_shape(0, 3), (1, 1));
    }
}
