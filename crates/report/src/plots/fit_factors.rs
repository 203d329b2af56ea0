//! The figures that answer chapter 5's questions, drawn only when the
//! design has their factor:
//!
//! - `fit_budget`: the median fitting error E of each outline against the
//!   budget per segment, one line per method (ch5_mhs: does MHS beat HS,
//!   and from which budget on?). Each budget is its own set of runs, so a
//!   point is a final E, not a point of one run's convergence curve.
//! - `fit_alpha_size`: E with the search-space technique at each α_size
//!   relative to E in the naive bounding box (ch5_search_space: is the
//!   technique worth it, and at which α_size?): per unit (a segment of a
//!   per-segment campaign, else an outline), the ratio of the method's
//!   median E over its runs with the technique to its median E in the
//!   bounding box at the same budget — the observation the segment-level
//!   verdicts test ([`super::super::fit_units`]) — summarised over the
//!   units by its median and interquartile range; below 1 the technique
//!   fits better. Without a bounding-box twin, the median E itself.

use std::collections::BTreeMap;

use crate::fit::ALPHA_SIZE;
use crate::stats::{median, summarize};

use super::super::data::Dataset;
use super::super::fit_runs::{split, Case, FitRuns};
use super::super::fit_units::unit_runs;
use super::factor_lines::{FactorLines, FactorPanel, FactorSeries, Spread};
use super::{paginate, Figure, Page, Plot, SeriesSet};

/// The stems of the answer figures, which the summary names first.
pub(crate) const ANSWER_STEMS: [&str; 2] = ["fit_budget", "fit_alpha_size"];

/// (level, q1, median, q3) of `values`, or `None` when there are none (or
/// a NaN).
fn quartiles(level: f64, values: &[f64]) -> Option<(f64, f64, f64, f64)> {
    let s = summarize(values).ok()?;
    Some((level, s.q1, s.median, s.q3))
}

/// The dataset cell of every method of `fr` (by name).
fn dataset_cells(ds: &Dataset, fr: &FitRuns<'_>) -> Vec<Option<usize>> {
    fr.cells
        .iter()
        .map(|name| ds.cells.iter().position(|c| !c.external && c.name == *name))
        .collect()
}

/// The segments of problem `p` (from its first run).
fn segments(fr: &FitRuns<'_>, p: usize) -> Option<usize> {
    fr.runs
        .iter()
        .find(|((q, _), _)| *q == p)
        .and_then(|(_, rs)| rs.first())
        .map(|r| r.dim)
}

/// A case as a panel title: `coin: rational-cubic G1, 8 segments` with its
/// variant and search space when they are not the thesis's.
fn case_title(c: &Case<'_>, segments: Option<usize>) -> String {
    let mut t = format!(
        "{}: {} {}",
        c.source,
        c.function,
        c.continuity.to_uppercase()
    );
    let variant = c.variant();
    if !variant.is_empty() {
        t.push_str(&format!(" {variant}"));
    }
    if c.space.is_some() || c.alpha.is_some() {
        t.push_str(&format!(" ({})", c.space_level()));
    }
    if let Some(n) = segments {
        t.push_str(&format!(", {n} segments"));
    }
    t
}

/// The lines of one panel: for every method drawn (in the order of
/// `series`), its points from `point(fit cell)`, skipping methods without
/// any; the dataset cells drawn are added to `used`.
fn panel_series(
    series: &SeriesSet,
    cells: &[Option<usize>],
    used: &mut Vec<usize>,
    mut points: impl FnMut(usize) -> Vec<(f64, f64, f64, f64)>,
) -> Vec<FactorSeries> {
    let mut out = Vec::new();
    for &c in &series.cells {
        let Some(fc) = cells.iter().position(|d| *d == Some(c)) else {
            continue;
        };
        let pts = points(fc);
        if pts.is_empty() {
            continue;
        }
        if !used.contains(&c) {
            used.push(c);
        }
        out.push(FactorSeries {
            style: series.style(c),
            points: pts,
        });
    }
    out
}

/// The legend of the cells in `used`, in the order of `series`.
fn legend(series: &SeriesSet, used: &[usize]) -> Vec<super::super::style::LegendEntry> {
    series.legend(series.cells.iter().copied().filter(|c| used.contains(c)))
}

/// A panel of the median E (log axis) with no reference line.
fn e_panel(title: String, series: Vec<FactorSeries>) -> FactorPanel {
    FactorPanel {
        title,
        y_label: "median E".into(),
        y_log: true,
        series,
        reference: None,
    }
}

/// The figure of the median E against the budget per segment, one panel per
/// case run at two budgets or more (the technique at its default α_size
/// when the campaign also varies the search space); `None` when no case
/// has two budgets.
fn budget_figure(ds: &Dataset, series: &SeriesSet, fr: &FitRuns<'_>) -> Option<Plot> {
    // Case name → its problems at each budget.
    let mut by_case: Vec<(&str, Vec<(u64, usize)>)> = Vec::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(b) = problem.budget else { continue };
        match by_case.iter_mut().find(|(n, _)| *n == problem.name) {
            Some((_, v)) => v.push((b, p)),
            None => by_case.push((&problem.name, vec![(b, p)])),
        }
    }
    by_case.retain(|(_, v)| v.len() >= 2);
    let default_space =
        |name: &str| split(name).is_some_and(|c| c.space.is_none() && c.alpha.is_none());
    let mut space_note = String::new();
    if by_case.iter().any(|(n, _)| default_space(n))
        && !by_case.iter().all(|(n, _)| default_space(n))
    {
        by_case.retain(|(n, _)| default_space(n));
        space_note = format!(
            " The campaign also varies the search space: drawn here is the technique at its \
             default α_size {} (the α_size figure compares the search spaces).",
            crate::files::fmt_real(ALPHA_SIZE.default)
        );
    }
    if by_case.is_empty() {
        return None;
    }
    let cells = dataset_cells(ds, fr);
    let mut used = Vec::new();
    let mut panels = Vec::new();
    let mut runs = 0usize;
    for (name, mut problems) in by_case {
        problems.sort_unstable();
        let title = split(name).map_or_else(
            || name.to_owned(),
            |c| case_title(&c, segments(fr, problems[0].1)),
        );
        let lines = panel_series(series, &cells, &mut used, |fc| {
            problems
                .iter()
                .filter_map(|&(b, p)| {
                    let e = fr.errors(p, fc)?;
                    runs = runs.max(e.len());
                    quartiles(b as f64, &e)
                })
                .collect()
        });
        if !lines.is_empty() {
            panels.push(e_panel(title, lines));
        }
    }
    if panels.is_empty() {
        return None;
    }
    Some(Plot {
        stem: ANSWER_STEMS[0].into(),
        title: "Median E against the budget per segment".into(),
        caption: format!(
            "The fitting error E = Σ|Rᵢ − P(sᵢ)|² of the whole outline (the sum over its \
             segments; pixels² for images, font units² for glyphs): its median over the runs \
             of each method (up to {runs}) at each budget per segment, with the \
             interquartile band (25 % to 75 %, type-7 quantiles), both axes on log scales. \
             Each budget is its own set of runs (with the seeds the spec pairs across \
             budgets), so a point is a final E, not a point of one run's convergence curve \
             (convergence.png shows those). Lower is better; where two lines cross, the \
             order of those two methods flips with the budget.{space_note}{}",
            series.caption_note()
        ),
        figure: Figure::FactorLines(FactorLines {
            title: "Median E against the budget per segment (band: interquartile range)".into(),
            legend: legend(series, &used),
            x_label: "evaluations per segment".into(),
            x_log: true,
            spread: Spread::Band,
            columns: 3,
            panels,
        }),
        page: Page::SINGLE,
    })
}

/// The α_size of a technique case (the default when its name has none).
fn alpha_of(c: &Case<'_>) -> Option<f64> {
    match c.alpha {
        Some(a) => a.parse().ok(),
        None => Some(ALPHA_SIZE.default),
    }
}

/// What the panels of the α_size figure are keyed by: the case without its
/// source (function, continuity, mode, variant) and the budget per segment.
type AlphaKey = (String, Option<u64>);

/// The panel title of an α_size key.
fn alpha_title(c: &Case<'_>, budget: Option<u64>) -> String {
    let mut t = format!("{} {}", c.function, c.continuity.to_uppercase());
    let variant = c.variant();
    if !variant.is_empty() {
        t.push_str(&format!(" {variant}"));
    }
    if let Some(b) = budget {
        t.push_str(&format!(", budget {b} per segment"));
    }
    t
}

/// The ratios of median E (technique problem `pt` over bounding-box
/// problem `pb`) of method `fc`, per unit: per segment when both have
/// segment rows for it, else the whole outline.
fn unit_ratios(fr: &FitRuns<'_>, pt: usize, pb: usize, fc: usize, per_segment: bool) -> Vec<f64> {
    let ratio = |a: &[f64], b: &[f64]| {
        let (ma, mb) = (median(a), median(b));
        (mb > 0.0 && ma.is_finite() && mb.is_finite()).then(|| ma / mb)
    };
    if per_segment {
        if let (Some(a), Some(b)) = (unit_runs(fr, pt, fc), unit_runs(fr, pb, fc)) {
            return a
                .iter()
                .filter_map(|(u, ea)| ratio(ea, b.get(u)?))
                .collect();
        }
    }
    match (fr.errors(pt, fc), fr.errors(pb, fc)) {
        (Some(a), Some(b)) => ratio(&a, &b).into_iter().collect(),
        _ => Vec::new(),
    }
}

/// A technique problem of the α_size figure: (problem, case, α_size).
type TechniqueRun<'a> = (usize, Case<'a>, f64);

/// The panels of the α_size figure and what they were drawn from.
struct AlphaPanels<'s, 'f> {
    /// The shown configurations.
    series: &'s SeriesSet,
    /// The fitting runs.
    fr: &'f FitRuns<'f>,
    /// The dataset cell of every fitting method ([`dataset_cells`]).
    cells: Vec<Option<usize>>,
    /// The technique problems.
    technique: Vec<TechniqueRun<'f>>,
    /// The configurations drawn in some panel.
    used: Vec<usize>,
    /// The most units behind a point.
    units: usize,
}

/// The bounding-box twin of the technique problem `pt` (the same case and
/// budget with the naive bounding box), if the campaign ran it.
fn twin(fr: &FitRuns<'_>, pt: usize, c: &Case<'_>) -> Option<usize> {
    fr.problems.iter().enumerate().position(|(pb, bb)| {
        pb != pt
            && bb.budget == fr.problems[pt].budget
            && split(&bb.name)
                .is_some_and(|d| d.space == Some("bounding-box") && d.base() == c.base())
    })
}

impl AlphaPanels<'_, '_> {
    /// Panels by (function/continuity/mode/variant, budget), pooling the
    /// sources (a ratio has no unit): the ratio of E with the technique to
    /// E in the bounding box, per α_size.
    fn ratio_panels(&mut self) -> Vec<FactorPanel> {
        let fr = self.fr;
        let mut keys: Vec<(AlphaKey, Case<'_>)> = Vec::new();
        for (p, c, _) in &self.technique {
            let base = c.base();
            let tail = base.split_once('/').map_or(base.as_str(), |(_, t)| t);
            let key = (tail.to_owned(), fr.problems[*p].budget);
            if !keys.iter().any(|(k, _)| *k == key) {
                keys.push((key, *c));
            }
        }
        keys.sort_by(|a, b| a.0.cmp(&b.0));
        let mut panels = Vec::new();
        for ((tail, budget), case) in keys {
            let technique = &self.technique;
            let points = |fc: usize, units: &mut usize| {
                let mut by_alpha: BTreeMap<u64, (f64, Vec<f64>)> = BTreeMap::new();
                for (pt, c, a) in technique {
                    let base = c.base();
                    let t = base.split_once('/').map_or(base.as_str(), |(_, t)| t);
                    if t != tail || fr.problems[*pt].budget != budget {
                        continue;
                    }
                    let Some(pb) = twin(fr, *pt, c) else { continue };
                    let r = unit_ratios(fr, *pt, pb, fc, c.per_segment);
                    by_alpha
                        .entry(a.to_bits())
                        .or_insert((*a, Vec::new()))
                        .1
                        .extend(r);
                }
                let mut pts: Vec<(f64, f64, f64, f64)> = by_alpha
                    .into_values()
                    .filter_map(|(a, r)| {
                        *units = (*units).max(r.len());
                        quartiles(a, &r)
                    })
                    .collect();
                pts.sort_by(|x, y| x.0.total_cmp(&y.0));
                pts
            };
            let mut units = self.units;
            let lines = panel_series(self.series, &self.cells, &mut self.used, |fc| {
                points(fc, &mut units)
            });
            self.units = units;
            if !lines.is_empty() {
                panels.push(FactorPanel {
                    title: alpha_title(&case, budget),
                    y_label: "E (technique) / E (bounding box)".into(),
                    y_log: true,
                    series: lines,
                    reference: Some((1.0, "bounding box".into())),
                });
            }
        }
        panels
    }

    /// Panels by case (with its source) and budget: the median E per
    /// α_size.
    fn median_panels(&mut self) -> Vec<FactorPanel> {
        let fr = self.fr;
        let mut keys: Vec<(String, Option<u64>, usize, Case<'_>)> = Vec::new();
        for (p, c, _) in &self.technique {
            let key = (c.base(), fr.problems[*p].budget);
            if !keys.iter().any(|k| (&k.0, k.1) == (&key.0, key.1)) {
                keys.push((key.0, key.1, *p, *c));
            }
        }
        let mut panels = Vec::new();
        for (base, budget, first, case) in keys {
            let technique = &self.technique;
            let mut units = self.units;
            let lines = panel_series(self.series, &self.cells, &mut self.used, |fc| {
                let mut pts: Vec<(f64, f64, f64, f64)> = technique
                    .iter()
                    .filter(|(p, c, _)| c.base() == base && fr.problems[*p].budget == budget)
                    .filter_map(|(p, _, a)| {
                        let e = fr.errors(*p, fc)?;
                        units = units.max(e.len());
                        quartiles(*a, &e)
                    })
                    .collect();
                pts.sort_by(|x, y| x.0.total_cmp(&y.0));
                pts
            });
            self.units = units;
            if !lines.is_empty() {
                let title = Case {
                    alpha: None,
                    ..case
                };
                let mut t = case_title(&title, segments(fr, first));
                if let Some(b) = budget {
                    t.push_str(&format!(", budget {b}"));
                }
                panels.push(e_panel(t, lines));
            }
        }
        panels
    }

    /// The caption of the α_size figure: of the ratios to the bounding box
    /// when `relative`, else of the median E.
    fn caption(&self, relative: bool) -> String {
        let units = self.units;
        if relative {
            format!(
                "The search-space technique against the naive bounding box, per α_size (the \
                 half-width of the technique's boxes is α_size × the chord), both axes on log \
                 scales: for each {unit} and method, the ratio of its median E over the runs \
                 with the technique at that α_size to its median E in the bounding box at the \
                 same budget (the observation the {unit}-level verdicts test); the line is the \
                 median of the ratios over the {unit}s (up to {units}) and the band their \
                 interquartile range. Below the dashed line at 1 the technique fits better than \
                 the bounding box; above it, worse.{}",
                self.series.caption_note(),
                unit = if self.technique.iter().any(|t| t.1.per_segment) {
                    "segment"
                } else {
                    "outline"
                },
            )
        } else {
            format!(
                "The median fitting error E = Σ|Rᵢ − P(sᵢ)|² of the whole outline (pixels² for \
                 images, font units² for glyphs) over the runs of each method (up to {units}) \
                 with the search-space technique at each α_size, with the interquartile band, \
                 both axes on log scales (no bounding-box run to compare with).{}",
                self.series.caption_note()
            )
        }
    }
}

/// The figure of E per α_size against the bounding box; `None` unless the
/// technique ran at two α_size values or more.
fn alpha_figure(ds: &Dataset, series: &SeriesSet, fr: &FitRuns<'_>) -> Option<Plot> {
    let technique: Vec<TechniqueRun<'_>> = fr
        .problems
        .iter()
        .enumerate()
        .filter_map(|(p, problem)| {
            let c = split(&problem.name).filter(|c| c.space.is_none())?;
            Some((p, c, alpha_of(&c)?))
        })
        .collect();
    let mut alphas: Vec<f64> = technique.iter().map(|t| t.2).collect();
    alphas.sort_by(f64::total_cmp);
    alphas.dedup();
    if alphas.len() < 2 {
        return None;
    }
    let mut a = AlphaPanels {
        series,
        fr,
        cells: dataset_cells(ds, fr),
        technique,
        used: Vec::new(),
        units: 0,
    };
    let relative = a
        .technique
        .iter()
        .any(|(p, c, _)| twin(fr, *p, c).is_some());
    let panels = if relative {
        a.ratio_panels()
    } else {
        a.median_panels()
    };
    if panels.is_empty() {
        return None;
    }
    let caption = a.caption(relative);
    let title = if relative {
        "E per α_size against the bounding box"
    } else {
        "Median E per α_size"
    };
    Some(Plot {
        stem: ANSWER_STEMS[1].into(),
        title: title.into(),
        caption,
        figure: Figure::FactorLines(FactorLines {
            title: format!("{title} (band: interquartile range)"),
            legend: legend(series, &a.used),
            x_label: "α_size".into(),
            x_log: true,
            spread: Spread::Band,
            columns: 2,
            panels,
        }),
        page: Page::SINGLE,
    })
}

/// The answer figures of a fitting campaign whose design has their factor
/// (the budget per segment, the technique's α_size), split into pages that
/// fit a screen.
pub(crate) fn figures(ds: &Dataset, series: &SeriesSet, fr: &FitRuns<'_>) -> Vec<Plot> {
    [budget_figure(ds, series, fr), alpha_figure(ds, series, fr)]
        .into_iter()
        .flatten()
        .flat_map(paginate)
        .collect()
}
