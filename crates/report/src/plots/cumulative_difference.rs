//! The cumulative difference-plot of `compare` (the estimator is
//! [`crate::cumulative_difference`]): the curve, its pointwise bootstrap
//! band, the zero line and the range a difference can take.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{framed_chart, Axes, Chart};
use crate::cumulative_difference::CumulativeDifference;
use crate::render::{draw_line, font, Draw, DrawResult};
use crate::style::{LegendEntry, SeriesStyle};
use metabezier_plot::layout::{frame_height, TICK_FONT};

/// The band's colour.
pub(crate) const BAND: RGBColor = RGBColor(190, 190, 190);

/// The range a cumulative difference can take (|diff(x)| ≤ 2 min(x, 1 − x)
/// for equal sample sizes), drawn beneath.
const RANGE: RGBColor = RGBColor(224, 238, 250);

/// The drawn cumulative difference-plot.
pub(crate) struct DifferenceFigure {
    /// The title drawn above the chart.
    pub title: String,
    /// The curve's and the band's legend.
    pub legend: Vec<LegendEntry>,
    /// The estimate with its band.
    pub curve: CumulativeDifference,
    /// The label of the upper half (A better).
    pub above: String,
    /// The label of the lower half (the other better).
    pub below: String,
}

impl Draw for DifferenceFigure {
    fn size(&self) -> (u32, u32) {
        let w = 900;
        (w, frame_height(w, &self.legend) + 520)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let axes = Axes {
            x: (0.0, 1.0),
            y: (-1.05, 1.05),
            x_desc: "position in the pooled ranking of the errors (0 best, 1 worst)",
            y_desc: "F_A(x) − F_other(x)",
            x_labels: 11,
            x_tick: &|v| format!("{v:.1}"),
            y_tick: &|v| format!("{:.1}", if v.abs() < 1e-9 { 0.0 } else { v }),
        };
        framed_chart(root, &self.title, &self.legend, &axes, |chart| {
            self.draw_curve(chart)
        })
    }
}

impl DifferenceFigure {
    /// The range, the band, the zero line, the curve and the labels.
    fn draw_curve<DB: DrawingBackend>(&self, chart: &mut Chart<'_, DB>) -> DrawResult {
        chart.draw_series(std::iter::once(Polygon::new(
            vec![(0.0, 0.0), (0.5, 1.0), (1.0, 0.0), (0.5, -1.0)],
            RANGE.filled(),
        )))?;
        let c = &self.curve;
        let mut band: Vec<(f64, f64)> = c.x.iter().copied().zip(c.high.iter().copied()).collect();
        band.extend(c.x.iter().copied().zip(c.low.iter().copied()).rev());
        chart.draw_series(std::iter::once(Polygon::new(band, BAND.mix(0.7).filled())))?;
        draw_line(
            chart,
            vec![(0.0, 0.0), (1.0, 0.0)],
            SeriesStyle {
                colour: RGBColor(90, 90, 90),
                dashed: true,
            },
            1,
        )?;
        let pts: Vec<(f64, f64)> = c.x.iter().copied().zip(c.diff.iter().copied()).collect();
        draw_line(chart, pts, SeriesStyle::solid(RGBColor(0, 0, 0)), 2)?;
        for (text, y) in [(&self.above, 0.92), (&self.below, -0.92)] {
            chart.draw_series(std::iter::once(Text::new(
                text.clone(),
                (0.02, y),
                font(TICK_FONT),
            )))?;
        }
        Ok(())
    }
}
