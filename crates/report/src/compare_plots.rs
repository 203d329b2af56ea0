//! The figures of `compare`: per shared algorithm configuration, the runtime
//! ECDFs of the campaigns overlaid (the report's own ECDF code,
//! [`crate::plots::overlaid_ecdfs`], on a dataset of that cell's runs in
//! each campaign) and the cumulative difference-plot of their final errors
//! ([`crate::cumulative_difference`]).

use plotters::prelude::RGBColor;

use crate::cumulative_difference::CumulativeDifference;
use crate::data::Dataset;
use crate::plots::{overlaid_ecdfs, DifferenceFigure, Figure, Page, Plot, SeriesSet};
use crate::style::{LegendEntry, SeriesStyle};

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
                    SeriesStyle::solid(crate::plots::cumulative_difference::BAND),
                ),
            ],
            curve: c,
            above: "A better".to_owned(),
            below: format!("{other} better"),
        }),
        page: Page::SINGLE,
    }
}
