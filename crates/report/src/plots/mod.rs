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
pub(crate) mod cumulative_difference;
mod ecdf;
use metabezier_plot::factor_lines;
pub(crate) mod fit_factors;
mod heat_map;
use metabezier_plot::layout;
mod scalability;
mod verdict_map;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::best2009::Best2009;
use super::data::Dataset;
use super::descriptive::CellStats;
use super::render::{Draw, DrawResult};
use super::tuning::{grids, mean_ranks, HeatMap};
use crate::experiment::records::default_targets;
use metabezier_plot::style::{cell_styles, LegendEntry, SeriesStyle};

pub(crate) use self::boxes::Boxes;
pub(crate) use self::convergence::Convergence;
pub(crate) use self::cumulative_difference::DifferenceFigure;
pub(crate) use self::ecdf::{framed_chart, overlaid_ecdfs, Axes, Chart, Ecdf};
pub(crate) use self::heat_map::Heat;
pub(crate) use self::scalability::Scalability;
pub(crate) use self::verdict_map::VerdictMap;

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
    /// Which page of its figure this is (a grid too tall for one file is
    /// split into pages).
    pub page: Page,
}

/// The page of a figure split into several files: the `index`-th (from 1)
/// of `of`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Page {
    /// This page, from 1.
    pub index: usize,
    /// The number of pages of the figure.
    pub of: usize,
}

impl Page {
    /// The only page of a figure that fits one file.
    pub(crate) const SINGLE: Page = Page { index: 1, of: 1 };

    /// What a page adds to its figure's title: " (k of n)", nothing for a
    /// figure of one page.
    fn title_suffix(self) -> String {
        if self.of == 1 {
            String::new()
        } else {
            format!(" ({} of {})", self.index, self.of)
        }
    }

    /// What a page adds to its figure's caption.
    fn caption_suffix(self) -> String {
        if self.of == 1 {
            String::new()
        } else {
            format!(
                " Page {} of {}, in the order of the problems.",
                self.index, self.of
            )
        }
    }
}

impl Plot {
    /// The title of the whole figure: without the "(k of n)" of a page.
    fn figure_title(&self) -> &str {
        self.title
            .strip_suffix(&self.page.title_suffix())
            .unwrap_or(&self.title)
    }

    /// The caption of the whole figure: without the page sentence.
    pub(crate) fn figure_caption(&self) -> &str {
        self.caption
            .strip_suffix(&self.page.caption_suffix())
            .unwrap_or(&self.caption)
    }

    /// The figure's heading: its title, with "(n pages)" when it is split.
    pub(crate) fn figure_heading(&self) -> String {
        match self.page.of {
            1 => self.title.clone(),
            n => format!("{} ({n} pages)", self.figure_title()),
        }
    }
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
    /// Verdicts against the reference per design point.
    Verdicts(VerdictMap),
    /// A measure's median and interquartile range over a design factor's
    /// levels, one line per method.
    FactorLines(factor_lines::FactorLines),
    /// The cumulative difference of two campaigns' rank distributions
    /// (`compare`).
    CumulativeDifference(DifferenceFigure),
}

impl Draw for Figure {
    fn size(&self) -> (u32, u32) {
        match self {
            Figure::Convergence(f) => f.size(),
            Figure::Boxes(f) => f.size(),
            Figure::Ecdf(f) => f.size(),
            Figure::Scalability(f) => f.size(),
            Figure::Heat(f) => f.size(),
            Figure::Overlay(f) => super::overlay::Overlay(f).size(),
            Figure::Verdicts(f) => f.size(),
            Figure::FactorLines(f) => f.size(),
            Figure::CumulativeDifference(f) => f.size(),
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        match self {
            Figure::Convergence(f) => f.draw(root),
            Figure::Boxes(f) => f.draw(root),
            Figure::Ecdf(f) => f.draw(root),
            Figure::Scalability(f) => f.draw(root),
            Figure::Heat(f) => f.draw(root),
            Figure::Overlay(f) => super::overlay::Overlay(f).draw(root),
            Figure::Verdicts(f) => f.draw(root),
            Figure::FactorLines(f) => f.draw(root),
            Figure::CumulativeDifference(f) => f.draw(root),
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

impl NoPlot {
    /// Whether the data should have allowed the figure: runs whose every
    /// error is infinite or NaN are broken results, not a campaign without
    /// successes or without a second dimension.
    pub(crate) fn is_fault(self) -> bool {
        matches!(self, NoPlot::NoFiniteTrace | NoPlot::NoFiniteError)
    }
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
        page: _,
    } = plot;
    let figures: Vec<Figure> = match figure {
        Figure::Convergence(f) => f
            .pages(MAX_SIDE)
            .into_iter()
            .map(Figure::Convergence)
            .collect(),
        Figure::Boxes(f) => f.pages(MAX_SIDE).into_iter().map(Figure::Boxes).collect(),
        Figure::FactorLines(f) => f
            .pages(MAX_SIDE)
            .into_iter()
            .map(Figure::FactorLines)
            .collect(),
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
        .map(|(i, figure)| {
            let page = Page {
                index: i + 1,
                of: n,
            };
            Plot {
                stem: if i == 0 {
                    stem.clone()
                } else {
                    format!("{stem}_{}", i + 1)
                },
                title: format!("{title}{}", page.title_suffix()),
                caption: format!("{caption}{}", page.caption_suffix()),
                figure,
                page,
            }
        })
        .collect()
}

/// At most this many algorithms are drawn in one panel.
pub(crate) const MAX_SERIES: usize = 12;

/// The algorithms the figures draw, with their legend names and styles:
/// every cell when there are at most [`MAX_SERIES`], else, of each label
/// with several settings (a tuning grid), its best setting (lowest mean
/// rank of the mean final error over the problems) and its default one
/// (every varying parameter at the optimiser's default), and every cell
/// that is alone under its label.
pub(crate) struct SeriesSet {
    /// The cells drawn, in the order of the dataset.
    pub cells: Vec<usize>,
    /// Legend name and style, per cell of the dataset (`None`: not drawn).
    entries: Vec<Option<LegendEntry>>,
    /// How many cells are not drawn.
    pub left_out: usize,
}

impl SeriesSet {
    /// The series of `ds`: all its cells, or the best and default setting
    /// of each grid when there are more than [`MAX_SERIES`].
    pub(crate) fn of(ds: &Dataset, stats: &[Vec<Option<CellStats>>]) -> SeriesSet {
        let n = ds.cells.len();
        let mut tags: Vec<Option<&'static str>> = vec![None; n];
        let cells: Vec<usize> = if n <= MAX_SERIES {
            (0..n).collect()
        } else {
            let mut keep = vec![true; n];
            for grid in grids(ds) {
                for &c in &grid.cells {
                    keep[c] = false;
                }
                let best = mean_ranks(ds, &grid, stats).and_then(|(_, r)| {
                    (0..r.len())
                        .min_by(|&a, &b| r[a].total_cmp(&r[b]))
                        .map(|i| grid.cells[i])
                });
                let default = grid.cells.iter().copied().find(|&c| {
                    let cell = &ds.cells[c];
                    let Some(defs) = crate::optim::Algorithm::params(&cell.kind) else {
                        return false;
                    };
                    grid.varying.iter().all(|k| {
                        let d = defs.iter().find(|d| d.name == k);
                        d.is_some_and(|d| {
                            super::data::param_value(cell, k)
                                .is_some_and(|v| same_value(&v, &d.default.to_string()))
                        })
                    })
                });
                if let Some(b) = best {
                    keep[b] = true;
                    tags[b] = Some("best");
                }
                if let Some(d) = default {
                    keep[d] = true;
                    tags[d] = Some(if best == Some(d) {
                        "best, default"
                    } else {
                        "default"
                    });
                }
            }
            (0..n).filter(|&c| keep[c]).collect()
        };
        // Shades by place among the cells drawn: the best setting of a grid
        // first (its optimiser's own colour), its default lighter.
        let mut order = cells.clone();
        order.sort_by_key(|&c| tags[c] == Some("default"));
        let shown: Vec<super::data::Cell> = order.iter().map(|&c| ds.cells[c].clone()).collect();
        let mut styles = vec![SeriesStyle::solid(RGBColor(0, 0, 0)); n];
        let keys: Vec<(&str, &str)> = shown
            .iter()
            .map(|c| (c.label.as_str(), c.kind.as_str()))
            .collect();
        for (&c, style) in order.iter().zip(cell_styles(&keys)) {
            styles[c] = style;
        }
        let mut entries = vec![None; n];
        for &c in &cells {
            let style = styles[c];
            let name = match tags[c] {
                Some(tag) => format!("{} [{tag}]", ds.cells[c].name),
                None => ds.cells[c].name.clone(),
            };
            entries[c] = Some((name, style));
        }
        SeriesSet {
            left_out: n - cells.len(),
            cells,
            entries,
        }
    }

    /// Every cell of a dataset drawn with the given legend entries, one per
    /// cell in order (the sides of `compare`, whose styles tell the
    /// campaigns apart rather than the optimisers).
    pub(crate) fn explicit(entries: Vec<LegendEntry>) -> SeriesSet {
        SeriesSet {
            cells: (0..entries.len()).collect(),
            entries: entries.into_iter().map(Some).collect(),
            left_out: 0,
        }
    }

    /// The style of cell `c` (solid grey when it is not drawn).
    pub(crate) fn style(&self, c: usize) -> SeriesStyle {
        self.entries
            .get(c)
            .and_then(|e| e.as_ref())
            .map_or(SeriesStyle::solid(RGBColor(128, 128, 128)), |e| e.1)
    }

    /// The legend entry of cell `c`, when it is drawn.
    pub(crate) fn entry(&self, c: usize) -> Option<LegendEntry> {
        self.entries.get(c).and_then(|e| e.clone())
    }

    /// The legend of `cells` (those drawn), in their order.
    pub(crate) fn legend(&self, cells: impl IntoIterator<Item = usize>) -> Vec<LegendEntry> {
        cells.into_iter().filter_map(|c| self.entry(c)).collect()
    }

    /// The sentence a caption adds when some cells are not drawn.
    pub(crate) fn caption_note(&self) -> String {
        if self.left_out == 0 {
            String::new()
        } else {
            format!(
                " Of each algorithm tuned over a grid, only its best setting (lowest mean \
                 rank over the problems) and its default setting are drawn ({} of {} \
                 configurations; the tables hold them all).",
                self.cells.len(),
                self.cells.len() + self.left_out
            )
        }
    }
}

/// Whether two parameter texts are the same value (`0.9` and `0.90`).
fn same_value(a: &str, b: &str) -> bool {
    match (a.parse::<f64>(), b.parse::<f64>()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// Every figure of the report that the data allows, a note for each one
/// that it does not, and among the notes those that are faults of the data
/// ([`NoPlot::is_fault`]).
pub(crate) struct Figures {
    /// The figures.
    pub plots: Vec<Plot>,
    /// Why a figure is not drawn, one line each.
    pub notes: Vec<String>,
    /// The notes that are faults of the data.
    pub faults: Vec<String>,
}

/// Every figure of the report that the data allows, with the notes on the
/// others.
pub(crate) fn figures(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    heat_maps: Vec<HeatMap>,
    threshold: Option<f64>,
    best: &[Best2009],
    verdicts: Option<&super::format::Table>,
) -> Figures {
    let mut plots = Vec::new();
    let mut faults = Vec::new();
    let series = SeriesSet::of(ds, stats);
    if let Some(t) = verdicts {
        let shown: Vec<&str> = series
            .cells
            .iter()
            .map(|&c| ds.cells[c].name.as_str())
            .collect();
        let measure = t.csv_header.iter().position(|h| h == "measure");
        let mut measures: Vec<&str> = measure
            .map(|m| t.csv_rows.iter().map(|r| r[m].as_str()).collect())
            .unwrap_or_default();
        measures.sort_unstable();
        measures.dedup();
        // The final error first, as the verdict tables show it.
        measures.sort_by_key(|m| *m != "final-error");
        plots.extend(
            measures
                .iter()
                .filter_map(|m| verdict_map::verdict_map(t, m, &shown)),
        );
    }
    let mut notes = Vec::new();
    for result in [
        convergence::convergence(ds, &series).map(|p| vec![p]),
        boxes::boxes(ds, &series).map(|p| vec![p]),
        ecdf::ecdf(ds, &series, threshold),
        scalability::scalability(ds, &series).map(|p| vec![p]),
    ] {
        match result {
            Ok(ps) => plots.extend(ps.into_iter().flat_map(paginate)),
            Err(n) => {
                if n.is_fault() {
                    faults.push(n.to_string());
                }
                notes.push(n.to_string());
            }
        }
    }
    match ecdf::target_ecdfs(ds, &series, &default_targets(), best) {
        Ok(p) => plots.extend(p),
        Err(n) => notes.push(n.to_string()),
    }
    plots.extend(heat_maps.into_iter().map(heat_map::heat));
    Figures {
        plots,
        notes,
        faults,
    }
}
