//! The box plots of the final error: per problem, one horizontal box per
//! algorithm on a log scale, with Tukey whiskers and outliers.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::stats::summarize;

use super::super::data::Dataset;
use super::super::format::sci_digits;
use super::super::render::{
    draw_line, draw_minor_decades, font, lg, lg_range, log_floor, log_range, on_log_axis,
    text_width, Draw, DrawResult, FloorTick,
};
use super::super::style::SeriesStyle;
use super::layout::{
    decade_labels, draw_floor_label, floored_tick, frame, grid_shape, pages_of, Axis, Chart,
    AXIS_FONT, PANEL_TITLE_FONT, PANEL_W, TICK_FONT, TITLE_H,
};
use super::{Figure, NoPlot, Page, Plot, SeriesSet};

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
    /// The error's name on the axis (`f − f*`, or `E` for fitting).
    symbol: &'static str,
    names: Vec<String>,
    /// The style of each category's box.
    styles: Vec<SeriesStyle>,
    /// The tick of the axis floor, when some error is drawn at it.
    floor: Option<FloorTick>,
    panels: Vec<BoxPanel>,
}

impl Boxes {
    /// The figure split into pages of whole panels, none taller than
    /// `max` pixels (one page when it fits).
    pub(super) fn pages(self, max: u32) -> Vec<Boxes> {
        let (_, cols) = grid_shape(self.panels.len(), 2);
        let (_, ph) = self.panel_size();
        let rows = (max.saturating_sub(TITLE_H) / ph).max(1) as usize;
        let Boxes {
            title,
            symbol,
            names,
            styles,
            floor,
            panels,
        } = self;
        pages_of(panels, rows * cols)
            .into_iter()
            .map(|panels| Boxes {
                title: title.clone(),
                symbol,
                names: names.clone(),
                styles: styles.clone(),
                floor,
                panels,
            })
            .collect()
    }

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

    /// Draws one problem's panel: axes, the algorithm names, then the boxes.
    fn draw_panel<DB: DrawingBackend>(
        &self,
        panel: &BoxPanel,
        a: &DrawingArea<DB, Shift>,
    ) -> DrawResult {
        let k = self.names.len();
        let yk = |i: usize| (k - 1 - i) as f64;
        let mut chart = ChartBuilder::on(a)
            .caption(&panel.title, font(PANEL_TITLE_FONT))
            .margin(10)
            .margin_right(24)
            .x_label_area_size(52)
            .y_label_area_size(self.label_width())
            .build_cartesian_2d(panel.x.0..panel.x.1, -0.6f64..(k as f64 - 0.4))?;
        chart
            .configure_mesh()
            .x_desc(format!("final {} (log scale)", self.symbol))
            .x_label_formatter(&|v| floored_tick(*v, panel.x, self.floor))
            .x_labels(decade_labels(panel.x))
            .y_labels(0)
            .disable_y_mesh()
            .label_style(font(TICK_FONT))
            .axis_desc_style(font(AXIS_FONT))
            .light_line_style(TRANSPARENT)
            .bold_line_style(RGBColor(215, 215, 215))
            .draw()?;
        draw_minor_decades(&mut chart, panel.x, (-0.6, k as f64 - 0.4), true, false)?;
        draw_floor_label(a, &chart, self.floor, (Axis::X, panel.x), -0.6)?;
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
            draw_box(&mut chart, b, yk(i), self.styles[i])?;
        }
        Ok(())
    }
}

/// Draws one box at height `y`: whiskers, the box, the median and outliers.
fn draw_box<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    b: &BoxStat,
    y: f64,
    style: SeriesStyle,
) -> DrawResult {
    let h = 0.3;
    let c = style.colour;
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
    chart.draw_series([Rectangle::new(
        [(b.q1, y - h), (b.q3, y + h)],
        c.mix(0.45).filled(),
    )])?;
    let edge = vec![
        (b.q1, y - h),
        (b.q3, y - h),
        (b.q3, y + h),
        (b.q1, y + h),
        (b.q1, y - h),
    ];
    draw_line(chart, edge, style, 2)?;
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(b.median, y - h), (b.median, y + h)],
        BLACK.stroke_width(3),
    )))?;
    chart.draw_series(
        b.outliers
            .iter()
            .map(|&o| Circle::new((o, y), 3, c.stroke_width(1))),
    )?;
    Ok(())
}

impl Draw for Boxes {
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.panels.len(), 2);
        let (pw, ph) = self.panel_size();
        (cols as u32 * pw, TITLE_H + rows as u32 * ph)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &[])?;
        let areas = area.split_evenly(grid_shape(self.panels.len(), 2));
        for (panel, a) in self.panels.iter().zip(&areas) {
            self.draw_panel(panel, a)?;
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

/// The box of `b` on a log10 axis, values at least `floor`.
fn on_log10_axis(b: BoxStat, floor: f64) -> BoxStat {
    let at = |v: f64| lg(on_log_axis(v, floor));
    BoxStat {
        q1: at(b.q1),
        median: at(b.median),
        q3: at(b.q3),
        lo: at(b.lo),
        hi: at(b.hi),
        outliers: b.outliers.iter().map(|&o| at(o)).collect(),
    }
}

/// One problem's panel from its raw boxes, on log10 axes above `floor`.
fn panel(ds: &Dataset, p: usize, row: Vec<Option<BoxStat>>, floor: f64) -> BoxPanel {
    let row: Vec<Option<BoxStat>> = row
        .into_iter()
        .map(|b| b.map(|b| on_log10_axis(b, floor)))
        .collect();
    let outliers = || {
        row.iter()
            .flatten()
            .flat_map(|b| b.outliers.iter().copied())
    };
    let lo = row
        .iter()
        .flatten()
        .map(|b| b.lo)
        .chain(outliers())
        .fold(f64::INFINITY, f64::min);
    let hi = row
        .iter()
        .flatten()
        .map(|b| b.hi)
        .chain(outliers())
        .fold(f64::NEG_INFINITY, f64::max);
    BoxPanel {
        title: ds.problems[p].title(),
        x: lg_range(log_range(10f64.powf(lo), 10f64.powf(hi))),
        boxes: row,
    }
}

/// The caption: how the boxes are drawn, the floor when some errors are
/// drawn at it, and how many non-finite errors are left out.
fn caption(symbol: &str, floor: Option<f64>, dropped: usize) -> String {
    let mut caption = format!(
        "Final error {symbol} of the runs per algorithm and problem (log scale): the box \
         spans the first to third quartile (type-7), the thick line is the median, \
         whiskers reach the most extreme runs within 1.5 interquartile ranges of the box, \
         circles are runs beyond them."
    );
    if let Some(floor) = floor {
        caption.push_str(&format!(
            " Errors ≤ {} (including exact zeros) are drawn at {}.",
            sci_digits(floor, 2),
            sci_digits(floor, 2)
        ));
    }
    if dropped > 0 {
        caption.push_str(&format!(" {dropped} non-finite error(s) are not drawn."));
    }
    caption
}

/// The box plots, or why there are none.
pub(super) fn boxes(ds: &Dataset, series: &SeriesSet) -> Result<Plot, NoPlot> {
    let mut raw: Vec<(usize, Vec<Option<BoxStat>>)> = Vec::new();
    let mut dropped = 0usize;
    for p in 0..ds.problems.len() {
        let mut row = Vec::new();
        for &c in &series.cells {
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
        return Err(NoPlot::NoFiniteError);
    }
    let all = raw.iter().flat_map(|(_, r)| {
        r.iter().flatten().flat_map(|b| {
            [b.q1, b.median, b.q3, b.lo, b.hi]
                .into_iter()
                .chain(b.outliers.iter().copied())
        })
    });
    let floor = log_floor(all.clone());
    let floor_tick = FloorTick::of(all, floor);
    let panels = raw
        .into_iter()
        .map(|(p, row)| panel(ds, p, row, floor))
        .collect();
    Ok(Plot {
        page: Page::SINGLE,
        stem: "boxplots".into(),
        title: "Final error distributions".into(),
        caption: caption(ds.error_symbol(), floor_tick.map(|_| floor), dropped)
            + &series.caption_note(),
        figure: Figure::Boxes(Boxes {
            title: format!("Final error {} per algorithm", ds.error_symbol()),
            symbol: ds.error_symbol(),
            names: series
                .legend(series.cells.iter().copied())
                .into_iter()
                .map(|e| e.0)
                .collect(),
            styles: series.cells.iter().map(|&c| series.style(c)).collect(),
            floor: floor_tick,
            panels,
        }),
    })
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
}
