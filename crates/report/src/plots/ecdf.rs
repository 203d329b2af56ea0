//! The runtime ECDF (the COCO view): for every algorithm, the fraction of
//! its (run, problem) pairs that reached the target within a number of
//! objective evaluations, over all problems of one dimension (one figure
//! per dimension: runtimes at D = 2 and D = 30 are not pooled).

use std::collections::BTreeSet;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::super::best2009::{self, Best2009};
use super::super::data::Dataset;
use super::super::format::{pow_tick, sci_digits};
use super::super::render::{draw_line, draw_minor_decades, font, lg, Draw, DrawResult};
use super::super::style::{LegendEntry, SeriesStyle};
use super::layout::{decade_labels, decade_tick, frame, frame_height, Line, AXIS_FONT, TICK_FONT};
use super::{Figure, NoPlot, Page, Plot, SeriesSet};

/// The runtime ECDF figure.
pub(crate) struct Ecdf {
    title: String,
    legend: Vec<LegendEntry>,
    /// The curves, each with its cell's style.
    series: Vec<(SeriesStyle, Vec<(f64, f64)>)>,
    /// Reference curves drawn under the others, each in its colour
    /// (COCO's best 2009 and best 2009–16).
    reference: Vec<(RGBColor, Vec<(f64, f64)>)>,
    x: (f64, f64),
    x_desc: &'static str,
    y_desc: &'static str,
}

impl Draw for Ecdf {
    fn size(&self) -> (u32, u32) {
        let w = 900;
        (w, frame_height(w, &self.legend) + 540)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        let axes = Axes {
            x: self.x,
            y: (-0.02, 1.02),
            x_desc: self.x_desc,
            y_desc: self.y_desc,
            x_labels: decade_labels(self.x),
            x_tick: &|v| decade_tick(v, self.x),
            y_tick: &|v| format!("{v:.1}"),
        };
        framed_chart(root, &self.title, &self.legend, &axes, |chart| {
            self.draw_curves(chart)
        })
    }
}

/// The axes of a chart of [`framed_chart`]: ranges, descriptions, the
/// number of x labels and the tick texts (11 y labels).
pub(crate) struct Axes<'a> {
    /// The x range.
    pub x: (f64, f64),
    /// The y range.
    pub y: (f64, f64),
    /// The x axis' description.
    pub x_desc: &'a str,
    /// The y axis' description.
    pub y_desc: &'a str,
    /// How many x labels.
    pub x_labels: usize,
    /// The text of an x tick.
    pub x_tick: &'a dyn Fn(f64) -> String,
    /// The text of a y tick.
    pub y_tick: &'a dyn Fn(f64) -> String,
}

/// The chart of a one-panel figure (the runtime ECDF, `compare`'s
/// cumulative difference): `root` framed with `title` and `legend`, a
/// mesh of light grey lines on `axes`, and `body` drawing into it.
pub(crate) fn framed_chart<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    legend: &[LegendEntry],
    axes: &Axes<'_>,
    body: impl FnOnce(&mut Chart<'_, DB>) -> DrawResult,
) -> DrawResult {
    let area = frame(root, title, legend)?;
    let mut chart = ChartBuilder::on(&area)
        .margin(12)
        .margin_right(30)
        .x_label_area_size(56)
        .y_label_area_size(80)
        .build_cartesian_2d(axes.x.0..axes.x.1, axes.y.0..axes.y.1)?;
    chart
        .configure_mesh()
        .x_desc(axes.x_desc)
        .y_desc(axes.y_desc)
        .x_label_formatter(&|v| (axes.x_tick)(*v))
        .y_label_formatter(&|v| (axes.y_tick)(*v))
        .x_labels(axes.x_labels)
        .y_labels(11)
        .label_style(font(TICK_FONT))
        .axis_desc_style(font(AXIS_FONT))
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()?;
    body(&mut chart)
}

/// A chart of real x and y.
pub(crate) type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

impl Ecdf {
    /// The minor decades, the reference curve and the curves.
    fn draw_curves<DB: DrawingBackend>(&self, chart: &mut Chart<'_, DB>) -> DrawResult {
        draw_minor_decades(chart, self.x, (-0.02, 1.02), true, false)?;
        for (colour, pts) in &self.reference {
            chart.draw_series(LineSeries::new(pts.iter().copied(), colour.stroke_width(6)))?;
        }
        for (style, pts) in &self.series {
            draw_line(chart, pts.clone(), *style, 2)?;
        }
        Ok(())
    }
}

/// The colour of the reference curve: a wide light gold, as cocopp draws
/// its reference algorithm behind the others, apart from the palette's grey.
const REFERENCE: RGBColor = RGBColor(238, 203, 110);

/// The colour of the second reference curve (best 2009–16): a darker gold.
const REFERENCE_2: RGBColor = RGBColor(196, 150, 40);

/// The steps of an ECDF over `total` pairs, from the sorted runtimes of
/// the solved ones, starting at (1, 0).
fn steps(times: &[u64], total: usize) -> Vec<(f64, f64)> {
    let mut pts = vec![(1.0, 0.0)];
    let mut solved = 0usize;
    let mut i = 0;
    while i < times.len() {
        let t = times[i];
        while i < times.len() && times[i] == t {
            i += 1;
            solved += 1;
        }
        let prev = pts.last().map_or(0.0, |p| p.1);
        let x = t as f64;
        pts.push((x, prev));
        pts.push((x, solved as f64 / total as f64));
    }
    pts
}

/// One cell's ECDF before it is extended to the largest budget.
struct CellSteps {
    /// The cell.
    cell: usize,
    /// The steps, from (1, 0).
    steps: Vec<(f64, f64)>,
    /// Its number of (run, problem) pairs.
    pairs: usize,
}

/// The ECDF steps of every drawn cell that ran a problem of `scope`, the
/// largest evaluation count or budget (at least 1), and whether any run
/// succeeded.
fn cell_steps(ds: &Dataset, shown: &SeriesSet, scope: Scope<'_>) -> (Vec<CellSteps>, f64, bool) {
    let mut series = Vec::new();
    let mut xmax = 1.0f64;
    let mut any_success = false;
    for &c in &shown.cells {
        let mut total = 0usize;
        let mut times: Vec<u64> = Vec::new();
        for p in (0..ds.problems.len()).filter(|&p| scope.covers(&ds.problems[p])) {
            for r in ds.runs(p, c) {
                total += 1;
                xmax = xmax.max(r.evaluations as f64).max(r.budget as f64);
                if r.success {
                    times.push(r.evaluations_to_target.unwrap_or(r.evaluations).max(1));
                }
            }
        }
        if total == 0 {
            continue;
        }
        any_success |= !times.is_empty();
        times.sort_unstable();
        series.push(CellSteps {
            cell: c,
            steps: steps(&times, total),
            pairs: total,
        });
    }
    (series, xmax, any_success)
}

/// The caption: what the target is and how the curves are normalised.
fn caption(threshold: Option<f64>, unequal_counts: bool) -> String {
    let target = threshold.map_or_else(
        || "the success threshold of the campaign (the success column of runs.csv)".to_owned(),
        |t| format!("the target f − f* ≤ {}", sci_digits(t, 2)),
    );
    let mut caption = format!(
        "Empirical cumulative distribution of the runtime to {target} (the \
         COCO view): for each algorithm, the fraction of all its (run, problem) pairs \
         whose error reached the target within the given number of objective \
         evaluations (log scale), aggregated over all problems; the curve ends at the \
         largest budget and stays below 1 when some runs never reached the target. \
         Evaluations are not divided by the dimension."
    );
    if unequal_counts {
        caption.push_str(
            " The algorithms do not have the same number of (run, problem) pairs; each \
             curve is normalised by its own count.",
        );
    }
    caption
}

/// The figure's title, naming the target and the problems.
fn title(threshold: Option<f64>, scope: &str) -> String {
    format!(
        "Runtime to the target {}, {scope}",
        threshold.map_or_else(
            || "success threshold".to_owned(),
            |t| if t > 0.0 {
                format!("f − f* ≤ {}", pow_tick(lg(t)))
            } else {
                format!("f − f* ≤ {t}")
            }
        )
    )
}

/// The dimensions of the problems, sorted.
fn dimensions(ds: &Dataset) -> Vec<usize> {
    let mut dims: Vec<usize> = ds.problems.iter().map(|p| p.dim).collect();
    dims.sort_unstable();
    dims.dedup();
    dims
}

/// The runtime ECDFs, one per dimension when there are several (`ecdf_d2`,
/// …; `ecdf` otherwise), or why there are none.
pub(super) fn ecdf(
    ds: &Dataset,
    shown: &SeriesSet,
    threshold: Option<f64>,
) -> Result<Vec<Plot>, NoPlot> {
    let dims = dimensions(ds);
    let scopes: Vec<Scope<'_>> = if dims.len() > 1 {
        dims.iter().map(|&d| Scope::Dim(d)).collect()
    } else {
        vec![Scope::All]
    };
    let plots: Vec<Plot> = scopes
        .into_iter()
        .filter_map(|scope| threshold_ecdf(ds, shown, threshold, scope))
        .collect();
    if plots.is_empty() {
        Err(NoPlot::NoSuccess)
    } else {
        Ok(plots)
    }
}

/// The runtime ECDFs `compare` overlays for one cell of several campaigns
/// (the cells of `ds`): to the success threshold ([`ecdf`], one per
/// dimension) and, where the runs carry their target hits, over all 51
/// targets (one per dimension, or one over all problems); a note for each
/// that cannot be drawn.
pub(crate) fn overlaid_ecdfs(
    ds: &Dataset,
    shown: &SeriesSet,
    threshold: Option<f64>,
) -> (Vec<Plot>, Vec<String>) {
    let mut notes = Vec::new();
    let mut plots = ecdf(ds, shown, threshold).unwrap_or_else(|n| {
        notes.push(n.to_string());
        Vec::new()
    });
    let hits = (0..ds.problems.len())
        .any(|p| (0..ds.cells.len()).any(|c| ds.runs(p, c).iter().any(|r| !r.hits.is_empty())));
    if hits {
        let dims = dimensions(ds);
        let scopes: Vec<Scope<'_>> = if dims.len() > 1 {
            dims.iter().map(|&d| Scope::Dim(d)).collect()
        } else {
            vec![Scope::All]
        };
        let targets = crate::experiment::records::default_targets();
        plots.extend(
            scopes
                .into_iter()
                .map(|scope| target_ecdf(ds, shown, &targets, &[], scope)),
        );
    } else {
        notes.push(NoPlot::NoHits.to_string());
    }
    (plots, notes)
}

/// The runtime ECDF of the problems of `scope`, or `None` when no run
/// there reached the target.
fn threshold_ecdf(
    ds: &Dataset,
    shown: &SeriesSet,
    threshold: Option<f64>,
    scope: Scope<'_>,
) -> Option<Plot> {
    let (series, xmax, any_success) = cell_steps(ds, shown, scope);
    if !any_success {
        return None;
    }
    let pair_counts: BTreeSet<usize> = series.iter().map(|s| s.pairs).collect();
    let xmax = xmax.max(2.0);
    let legend = shown.legend(series.iter().map(|s| s.cell));
    let series = series
        .into_iter()
        .map(|mut s| {
            let last = s.steps.last().map_or(0.0, |p| p.1);
            s.steps.push((xmax, last));
            (
                shown.style(s.cell),
                s.steps.into_iter().map(|(x, y)| (lg(x), y)).collect(),
            )
        })
        .collect();
    let (stem, scope_text) = match scope {
        Scope::Dim(d) => (format!("ecdf_d{d}"), format!("all problems at D = {d}")),
        _ => ("ecdf".to_owned(), "all problems".to_owned()),
    };
    Some(Plot {
        page: Page::SINGLE,
        stem,
        title: format!("Runtime ECDF, {scope_text}"),
        caption: caption(threshold, pair_counts.len() > 1).replace("all problems", &scope_text)
            + &shown.caption_note(),
        figure: Figure::Ecdf(Ecdf {
            title: title(threshold, &scope_text),
            legend,
            series,
            reference: Vec::new(),
            x: (0.0, lg(xmax)),
            x_desc: "objective evaluations (log scale)",
            y_desc: "fraction of (run, problem) pairs solved",
        }),
    })
}

/// The steps of an ECDF over `total` pairs from the sorted runtimes of the
/// solved ones (any positive reals), starting at the smallest runtime.
fn real_steps(times: &[f64], total: usize, start: f64) -> Vec<(f64, f64)> {
    let mut pts = vec![(start, 0.0)];
    for (i, &t) in times.iter().enumerate() {
        let prev = pts.last().map_or(0.0, |p| p.1);
        pts.push((t, prev));
        pts.push((t, (i + 1) as f64 / total as f64));
    }
    pts
}

/// The COCO runtime ECDFs over all targets (Hansen et al. 2021): for each
/// algorithm, the fraction of (run, target) pairs whose target precision
/// `Δf` (from `hits.csv`, `targets` in all) was reached within a number of
/// evaluations divided by the dimension; one figure over all problems and,
/// when there are several functions, one per function.
pub(super) fn target_ecdfs(
    ds: &Dataset,
    shown: &SeriesSet,
    targets: &[f64],
    best: &[Best2009],
) -> Result<Vec<Plot>, NoPlot> {
    if !(0..ds.problems.len())
        .any(|p| (0..ds.cells.len()).any(|c| ds.runs(p, c).iter().any(|r| !r.hits.is_empty())))
    {
        return Err(NoPlot::NoHits);
    }
    let mut functions: Vec<&str> = ds.problems.iter().map(|p| p.function.as_str()).collect();
    functions.sort_unstable();
    functions.dedup();
    let dims = dimensions(ds);
    let plots = if dims.len() > 1 {
        // Runtimes at different dimensions are not pooled: one per dimension.
        dims.iter()
            .map(|&d| target_ecdf(ds, shown, targets, best, Scope::Dim(d)))
            .collect()
    } else {
        let mut plots = vec![target_ecdf(ds, shown, targets, best, Scope::All)];
        if functions.len() > 1 && functions.len() <= MAX_FUNCTION_PLOTS {
            plots.extend(
                functions
                    .iter()
                    .map(|f| target_ecdf(ds, shown, targets, best, Scope::Function(f))),
            );
        }
        plots
    };
    Ok(plots)
}

/// Up to this many functions at one dimension, each gets its own target
/// ECDF as well.
const MAX_FUNCTION_PLOTS: usize = 12;

/// Which problems a target ECDF covers.
#[derive(Clone, Copy)]
enum Scope<'a> {
    All,
    Function(&'a str),
    Dim(usize),
}

impl Scope<'_> {
    fn covers(self, p: &super::super::data::Problem) -> bool {
        match self {
            Scope::All => true,
            Scope::Function(f) => p.function == f,
            Scope::Dim(d) => p.dim == d,
        }
    }
}

/// The ECDF of COCO's best 2009 over the (function, target) pairs of the
/// bbob problems in `scope`, a pair reached at its aRT / D (as cocopp draws
/// its reference algorithm); `None` unless the reference covers every
/// problem in scope.
fn reference_steps(
    ds: &Dataset,
    targets: &[f64],
    best: &Best2009,
    scope: Scope<'_>,
) -> Option<Vec<(f64, f64)>> {
    let mut keys: Vec<(usize, usize)> = Vec::new();
    for p in ds.problems.iter().filter(|p| scope.covers(p)) {
        let key = best2009::bbob_key(&p.function)?;
        if !best.covers(key.0, key.1) {
            return None;
        }
        keys.push(key);
    }
    keys.sort_unstable();
    keys.dedup();
    if keys.is_empty() {
        return None;
    }
    let mut times: Vec<f64> = keys
        .iter()
        .flat_map(|&(f, d)| {
            targets
                .iter()
                .filter_map(move |&t| best.art(f, d, t).map(|a| a / d.max(1) as f64))
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let start = times.first().copied().unwrap_or(1.0).min(1.0);
    Some(real_steps(&times, keys.len() * targets.len(), start))
}

/// The runtime ECDF of every shown configuration over the problems of
/// `scope` (x in log10 of evaluations / D), each ended at the largest
/// budget seen so far, and that largest budget over all of them.
fn cell_curves(
    ds: &Dataset,
    shown: &SeriesSet,
    targets: usize,
    scope: Scope<'_>,
) -> (Vec<Line>, f64) {
    let mut series: Vec<Line> = Vec::new();
    let mut xmax = 1.0f64;
    for &c in &shown.cells {
        if ds.cells[c].external && !ds.external_anytime {
            // Its hits were not read: it would show as reaching nothing.
            continue;
        }
        let mut total = 0usize;
        let mut times: Vec<f64> = Vec::new();
        for (p, problem) in ds.problems.iter().enumerate() {
            if !scope.covers(problem) {
                continue;
            }
            let d = problem.dim.max(1) as f64;
            for r in ds.runs(p, c) {
                total += targets;
                xmax = xmax.max(r.budget.max(r.evaluations) as f64 / d);
                times.extend(r.hits.iter().map(|&(_, e)| e.max(1) as f64 / d));
            }
        }
        if total == 0 {
            continue;
        }
        times.sort_by(f64::total_cmp);
        let start = times.first().copied().unwrap_or(1.0).min(1.0);
        let mut steps = real_steps(&times, total, start);
        let last = steps.last().map_or(0.0, |p| p.1);
        steps.push((xmax, last));
        series.push((c, steps.into_iter().map(|(x, y)| (lg(x), y)).collect()));
    }
    (series, xmax)
}

/// A reference's curve: its colour and its points (log10 of evaluations
/// / D, fraction reached).
type ReferenceCurve = (RGBColor, Vec<(f64, f64)>);

/// The curves of COCO's references in `best` that cover the problems of
/// `scope`, cut at `xmax` (x in log10 of evaluations / D), with their
/// colours: light gold for the first, dark for the second.
fn reference_curves<'b>(
    ds: &Dataset,
    target_values: &[f64],
    best: &'b [Best2009],
    scope: Scope<'_>,
    xmax: f64,
) -> (Vec<&'b Best2009>, Vec<ReferenceCurve>) {
    let mut drawn: Vec<&Best2009> = Vec::new();
    let mut reference: Vec<ReferenceCurve> = Vec::new();
    for (b, colour) in best.iter().zip([REFERENCE, REFERENCE_2]) {
        let Some(mut steps) = reference_steps(ds, target_values, b, scope) else {
            continue;
        };
        let last = steps.last().map_or(0.0, |p| p.1);
        steps.retain(|p| p.0 <= xmax);
        steps.push((xmax, steps.last().map_or(last, |p| p.1)));
        for p in steps.iter_mut() {
            p.0 = lg(p.0);
        }
        drawn.push(b);
        reference.push((colour, steps));
    }
    (drawn, reference)
}

/// The caption's sentences on the reference curves drawn.
fn reference_note(drawn: &[&Best2009]) -> String {
    drawn
        .iter()
        .zip(["light", "dark"])
        .map(|(b, shade)| {
            format!(
                " The wide {shade} gold curve is {}, {}, a (function, target) pair counted \
                 at its aRT / D as cocopp draws it ({}; beyond the thesis), cut at the \
                 campaign's largest budget.",
                b.label, b.what, b.source
            )
        })
        .collect()
}

/// The file stem and the caption's words of a target ECDF's scope.
fn scope_names(scope: Scope<'_>) -> (String, String) {
    match scope {
        Scope::Function(f) => (
            format!("ecdf_targets_{}", f.replace('/', "_")),
            f.to_owned(),
        ),
        Scope::Dim(d) => (
            format!("ecdf_targets_d{d}"),
            format!("all problems at D = {d}"),
        ),
        Scope::All => ("ecdf_targets".to_owned(), "all problems".to_owned()),
    }
}

/// One runtime ECDF over all targets, for the problems of `scope`, with
/// each of COCO's references beneath that covers them.
fn target_ecdf(
    ds: &Dataset,
    shown: &SeriesSet,
    target_values: &[f64],
    best: &[Best2009],
    scope: Scope<'_>,
) -> Plot {
    let targets = target_values.len();
    let (series, xmax) = cell_curves(ds, shown, targets, scope);
    let (drawn, reference) = reference_curves(ds, target_values, best, scope, xmax);
    let x0 = series
        .iter()
        .map(|(_, pts)| pts)
        .chain(reference.iter().map(|(_, pts)| pts))
        .filter_map(|pts| pts.first().map(|p| p.0))
        .fold(0.0f64, f64::min)
        .floor();
    let mut legend = shown.legend(series.iter().map(|(c, _)| *c));
    for (b, (colour, _)) in drawn.iter().zip(&reference) {
        legend.push((b.label.to_owned(), SeriesStyle::solid(*colour)));
    }
    let series = series
        .into_iter()
        .map(|(c, pts)| (shown.style(c), pts))
        .collect();
    let reference_note = reference_note(&drawn);
    let (stem, scope) = scope_names(scope);
    Plot {
        page: Page::SINGLE,
        stem,
        title: format!("Runtime ECDF over {targets} targets, {scope}"),
        caption: format!(
            "Empirical cumulative distribution of the runtimes to {targets} target \
             precisions Δf = 10² … 10⁻⁸ (five per decade) above f*, the anytime view \
             of COCO (Hansen et al. 2021): for each algorithm, the fraction of all its \
             (run, target) pairs on {scope} whose best error reached the target within \
             the given number of objective evaluations divided by the dimension (log \
             scale). The curve ends at the largest budget; its height there is the \
             fraction of targets reached, so budget dependence is visible without \
             rerunning.{reference_note}{}",
            shown.caption_note()
        ),
        figure: Figure::Ecdf(Ecdf {
            title: format!("Runtime to {targets} targets, {scope}"),
            legend,
            series,
            reference,
            x: (x0, lg(xmax).max(x0 + 1.0)),
            x_desc: "objective evaluations / D (log scale)",
            y_desc: "fraction of (run, target) pairs reached",
        }),
    }
}
