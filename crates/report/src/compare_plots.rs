//! The figures of `compare`: per shared algorithm configuration, the runtime
//! ECDFs of the campaigns overlaid (the report's own ECDF code,
//! [`crate::plots::overlaid_ecdfs`], on a dataset of that cell's runs in
//! each campaign) and the cumulative difference-plot of their final errors
//! ([`crate::cumulative_difference`]).

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::cumulative_difference::CumulativeDifference;
use crate::data::Dataset;
use crate::plots::{framed_chart, overlaid_ecdfs, Axes, Chart, Figure, Page, Plot, SeriesSet};
use crate::render::{draw_line, font, Draw, DrawResult};
use crate::style::{LegendEntry, SeriesStyle};
use metabezier_plot::layout::{frame_height, TICK_FONT};

/// The colours of the campaigns A, B, C, … (Tol's bright scheme: blue,
/// red, green, yellow, cyan, purple; Tol 2021), B onwards dashed.
const SIDE_COLOURS: [RGBColor; 6] = [
    RGBColor(0x44, 0x77, 0xaa),
    RGBColor(0xee, 0x66, 0x77),
    RGBColor(0x22, 0x88, 0x33),
    RGBColor(0xcc, 0xbb, 0x44),
    RGBColor(0x66, 0xcc, 0xee),
    RGBColor(0xaa, 0x33, 0x77),
];

/// The line style of campaign `side` (0 for A): its colour, solid for A
/// and dashed for the others, so that identical curves stay visible.
pub(crate) fn side_style(side: usize) -> SeriesStyle {
    SeriesStyle {
        colour: SIDE_COLOURS[side % SIDE_COLOURS.len()],
        dashed: side > 0,
    }
}

/// The runtime ECDFs of one shared cell in two campaigns, overlaid: `ds`
/// holds that cell's runs of A as cell 0 and of the other campaign as
/// cell 1 (named in `legend`); stems are prefixed with `prefix`. Returns the
/// figures and the notes on those that cannot be drawn.
pub(crate) fn ecdf_overlays(
    ds: &Dataset,
    legend: Vec<LegendEntry>,
    threshold: Option<f64>,
    prefix: &str,
    cell: &str,
) -> (Vec<Plot>, Vec<String>) {
    let shown = SeriesSet::explicit(legend);
    let (mut plots, notes) = overlaid_ecdfs(ds, &shown, threshold);
    for p in &mut plots {
        p.stem = format!("{prefix}_{}", p.stem);
        p.title = format!("{cell}: {}", p.title);
        if let Figure::Ecdf(_) = p.figure {
            p.caption.push_str(
                " Here the curves are one algorithm configuration in each campaign: A solid, \
                 the other campaign dashed; where the runs are identical the curves coincide.",
            );
        }
    }
    let notes = notes.into_iter().map(|n| format!("{cell}: {n}")).collect();
    (plots, notes)
}

/// The cumulative difference-plot of one shared cell: A against the
/// campaign `other` (a letter), as a figure with its caption.
pub(crate) fn difference_plot(
    c: CumulativeDifference,
    cell: &str,
    other: &str,
    stem: String,
    problems: usize,
) -> Plot {
    let caption = format!(
        "The cumulative difference-plot (Arza, Ceberio, Irurozki & Pérez 2023, JCGS; as \
         IOHanalyzer draws it) of the final errors of {cell} in A and in {other}: on each of \
         the {problems} shared problem(s) the runs of both campaigns are pooled and ranked \
         (lower error first, errors floored at the success threshold, ties sharing their \
         positions), x is the position in the pooled ranking from 0 (best) to 1 (worst), and \
         the curve is the fraction of A's runs at or below x minus the fraction of \
         {other}'s, averaged over the problems. Above 0: A holds more of the best positions \
         up to x; below: {other} does; 0 everywhere: the two are alike. The grey band is the \
         pointwise {:.1} % percentile bootstrap interval at each x (1000 seeded resamples \
         within each problem, pairs where the runs pair by seed), RVCompare's level √(1 − α) \
         for α = {:.2}; the area under the curve is {:.3} (P(A better) + ½ P(tie) − ½ with \
         equal numbers of runs). The light triangle is the range a difference can take.",
        100.0 * c.pointwise_level,
        1.0 - c.pointwise_level * c.pointwise_level,
        c.area
    );
    Plot {
        stem,
        title: format!("{cell}: cumulative difference, A − {other}"),
        caption,
        figure: Figure::CumulativeDifference(DifferenceFigure {
            title: format!("{cell}: cumulative difference of the error ranks, A − {other}"),
            legend: vec![
                (
                    "F_A − F_".to_owned() + other,
                    SeriesStyle::solid(RGBColor(0, 0, 0)),
                ),
                (
                    "pointwise bootstrap band".to_owned(),
                    SeriesStyle::solid(BAND),
                ),
            ],
            curve: c,
            above: "A better".to_owned(),
            below: format!("{other} better"),
        }),
        page: Page::SINGLE,
    }
}

/// The band's colour.
const BAND: RGBColor = RGBColor(190, 190, 190);

/// The range a cumulative difference can take (|diff(x)| ≤ 2 min(x, 1 − x)
/// for equal sample sizes), drawn beneath.
const RANGE: RGBColor = RGBColor(224, 238, 250);

/// The drawn cumulative difference-plot.
pub(crate) struct DifferenceFigure {
    title: String,
    legend: Vec<LegendEntry>,
    curve: CumulativeDifference,
    above: String,
    below: String,
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
