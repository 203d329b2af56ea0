//! The parameter-tuning heat maps: the mean final error of a grid of
//! settings over two parameters, one panel per problem, with a colour bar.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::super::render::{font, text_width, viridis, Draw, DrawResult};
use super::super::tuning::{cell_label, HeatMap, HeatPanel};
use super::layout::{frame, grid_shape, Chart, AXIS_FONT, PANEL_TITLE_FONT, TICK_FONT, TITLE_H};
use super::{Figure, Page, Plot};

/// A parameter-grid heat-map figure.
pub(crate) struct Heat {
    title: String,
    map: HeatMap,
}

/// The log10 range of a panel's positive finite means, which the colours
/// span (infinite ends when there are none).
#[derive(Clone, Copy)]
struct ColourScale {
    lmin: f64,
    lmax: f64,
}

impl ColourScale {
    fn of(mean: &[Vec<Option<f64>>]) -> Self {
        let logs: Vec<f64> = mean
            .iter()
            .flatten()
            .flatten()
            .filter(|v| v.is_finite() && **v > 0.0)
            .map(|v| v.log10())
            .collect();
        ColourScale {
            lmin: logs.iter().copied().fold(f64::INFINITY, f64::min),
            lmax: logs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// The position of `v` on the colour map, in [0, 1].
    fn at(self, v: f64) -> f64 {
        if !(v.is_finite() && v > 0.0 && self.lmin.is_finite()) {
            return 0.0;
        }
        if self.lmax - self.lmin < 1e-12 {
            0.5
        } else {
            (v.log10() - self.lmin) / (self.lmax - self.lmin)
        }
    }
}

impl Heat {
    /// Width of the widest label of the vertical parameter.
    fn y_label_width(&self) -> u32 {
        self.map
            .y_values
            .iter()
            .map(|v| text_width(v, TICK_FONT))
            .max()
            .unwrap_or(20)
    }

    fn panel_size(&self) -> (u32, u32) {
        let ylab = self.y_label_width();
        let w = (110 + ylab + 70 * self.map.x_values.len() as u32 + 110).max(420);
        let h = (150 + 46 * self.map.y_values.len() as u32).max(300);
        (w, h)
    }

    /// Draws one problem's panel: the grid of cells with their values, the
    /// frame of the best one, the parameter values and the colour bar.
    fn draw_panel<DB: DrawingBackend>(
        &self,
        panel: &HeatPanel,
        a: &DrawingArea<DB, Shift>,
    ) -> DrawResult {
        let nx = self.map.x_values.len();
        let ny = self.map.y_values.len();
        let (w, _) = a.dim_in_pixel();
        let (plot_area, bar_area) = a.split_horizontally(w.saturating_sub(110));
        let mut chart = ChartBuilder::on(&plot_area)
            .caption(&panel.title, font(PANEL_TITLE_FONT))
            .margin(10)
            .x_label_area_size(58)
            .y_label_area_size(self.y_label_width() + 50)
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
        let scale = ColourScale::of(&panel.mean);
        draw_cells(&mut chart, &panel.mean, scale)?;
        if let Some((yi, xi)) = panel.best {
            let (x0, y0) = (xi as f64, yi as f64);
            chart.draw_series(std::iter::once(Rectangle::new(
                [(x0 + 0.03, y0 + 0.03), (x0 + 0.97, y0 + 0.97)],
                RGBColor(220, 20, 60).stroke_width(4),
            )))?;
        }
        self.draw_values(&plot_area, &chart)?;
        draw_colour_bar(&bar_area, scale)
    }

    /// Writes the parameter values under and beside the grid.
    fn draw_values<DB: DrawingBackend>(
        &self,
        plot_area: &DrawingArea<DB, Shift>,
        chart: &Chart<'_, DB>,
    ) -> DrawResult {
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
        Ok(())
    }
}

/// Draws every cell of the grid: its colour and its value (`n/a` in grey
/// where undefined).
fn draw_cells<DB: DrawingBackend>(
    chart: &mut Chart<'_, DB>,
    mean: &[Vec<Option<f64>>],
    scale: ColourScale,
) -> DrawResult {
    for (yi, row) in mean.iter().enumerate() {
        for (xi, v) in row.iter().enumerate() {
            let (x0, y0) = (xi as f64, yi as f64);
            let (fill, text, text_colour) = match v {
                Some(v) => {
                    let t = scale.at(*v);
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
    Ok(())
}

/// Draws the colour bar of a panel with its two end values, when there is
/// room and a defined mean.
fn draw_colour_bar<DB: DrawingBackend>(
    bar_area: &DrawingArea<DB, Shift>,
    scale: ColourScale,
) -> DrawResult {
    let ColourScale { lmin, lmax } = scale;
    let (_, bh) = bar_area.dim_in_pixel();
    let (top, bottom) = (60i32, bh as i32 - 70);
    if !(bottom > top + 20 && lmin.is_finite()) {
        return Ok(());
    }
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
    Ok(())
}

impl Draw for Heat {
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = grid_shape(self.map.panels.len(), 3);
        let (pw, ph) = self.panel_size();
        (cols as u32 * pw, TITLE_H + rows as u32 * ph)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let area = frame(root, &self.title, &[])?;
        let areas = area.split_evenly(grid_shape(self.map.panels.len(), 3));
        for (panel, a) in self.map.panels.iter().zip(&areas) {
            self.draw_panel(panel, a)?;
        }
        Ok(())
    }
}

/// The heat-map plot of a parameter grid.
pub(super) fn heat(map: HeatMap) -> Plot {
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
        page: Page::SINGLE,
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
