//! The report's figures: convergence curves, box plots of the final error,
//! the ECDF of runtimes to the threshold, scalability with the dimension and
//! parameter-tuning heat maps. Each is computed from the [`Dataset`] into a
//! plain figure description, then drawn on any plotters backend.
//!
//! One file per kind of figure; [`layout`] holds what they share (panel
//! sizes, the title-and-legend frame, log-axis labels) and
//! [`super::render`] the drawing plumbing.

mod boxes;
mod convergence;
mod ecdf;
mod heat_map;
mod layout;
mod scalability;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::best2009::Best2009;
use super::data::Dataset;
use super::descriptive::CellStats;
use super::render::{Draw, DrawResult};
use super::tuning::HeatMap;
use crate::experiment::records::default_targets;

pub(crate) use self::boxes::Boxes;
pub(crate) use self::convergence::Convergence;
pub(crate) use self::ecdf::Ecdf;
pub(crate) use self::heat_map::Heat;
pub(crate) use self::scalability::Scalability;

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

/// Why a figure is not drawn; its text is the note in the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub(crate) enum NoPlot {
    /// No run has a best-so-far trace.
    #[error(
        "convergence plot skipped: no run has a best-so-far trace (convergence.csv is \
         missing or empty; fitting runs record none)"
    )]
    NoTrace,
    /// Traces exist, but no checkpoint has a finite error in every run.
    #[error("convergence plot skipped: no run has a finite best-so-far error")]
    NoFiniteTrace,
    /// No run ended with a finite error.
    #[error("box plots skipped: no finite final error")]
    NoFiniteError,
    /// No run reached the success threshold.
    #[error("runtime ECDF skipped: no run reached the success threshold")]
    NoSuccess,
    /// No function was run at two dimensions or more.
    #[error("scalability plot skipped: no function was run at more than one dimension")]
    SingleDimension,
    /// No run reached any target precision (or `hits.csv` is absent).
    #[error(
        "runtime ECDFs over all targets skipped: no run reached a target precision \
         (hits.csv is missing or empty; fitting runs record none)"
    )]
    NoHits,
}

/// The largest side of a figure, in pixels: a taller grid of panels is
/// split into pages (`stem`, `stem_2`, …) that fit a screen.
pub(crate) const MAX_SIDE: u32 = 3000;

/// `plot` as pages of whole panels, each at most [`MAX_SIDE`] tall: the
/// first keeps the stem and title, the others get `_k` and "(k of n)".
/// Figures other than grids of panels are returned as they are.
fn paginate(plot: Plot) -> Vec<Plot> {
    let Plot {
        stem,
        title,
        caption,
        figure,
    } = plot;
    let figures: Vec<Figure> = match figure {
        Figure::Convergence(f) => f
            .pages(MAX_SIDE)
            .into_iter()
            .map(Figure::Convergence)
            .collect(),
        Figure::Boxes(f) => f.pages(MAX_SIDE).into_iter().map(Figure::Boxes).collect(),
        Figure::Scalability(f) => f
            .pages(MAX_SIDE)
            .into_iter()
            .map(Figure::Scalability)
            .collect(),
        other => vec![other],
    };
    let n = figures.len();
    figures
        .into_iter()
        .enumerate()
        .map(|(i, figure)| Plot {
            stem: if i == 0 {
                stem.clone()
            } else {
                format!("{stem}_{}", i + 1)
            },
            title: if n == 1 {
                title.clone()
            } else {
                format!("{title} ({} of {n})", i + 1)
            },
            caption: if n == 1 {
                caption.clone()
            } else {
                format!(
                    "{caption} Page {} of {n}, in the order of the problems.",
                    i + 1
                )
            },
            figure,
        })
        .collect()
}

/// Every figure of the report that the data allows, and a note for each one
/// that it does not.
pub(crate) fn figures(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    heat_maps: Vec<HeatMap>,
    threshold: Option<f64>,
    best: Option<&Best2009>,
) -> (Vec<Plot>, Vec<String>) {
    let mut plots = Vec::new();
    let mut notes = Vec::new();
    for result in [
        convergence::convergence(ds),
        boxes::boxes(ds),
        ecdf::ecdf(ds, threshold),
        scalability::scalability(ds, stats),
    ] {
        match result {
            Ok(p) => plots.extend(paginate(p)),
            Err(n) => notes.push(n.to_string()),
        }
    }
    match ecdf::target_ecdfs(ds, &default_targets(), best) {
        Ok(p) => plots.extend(p),
        Err(n) => notes.push(n.to_string()),
    }
    plots.extend(heat_maps.into_iter().map(heat_map::heat));
    (plots, notes)
}
