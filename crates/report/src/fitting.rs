//! The curve-fitting part of a report, for campaigns with `[[fit]]`
//! problems: fit quality beyond `E`, the gap of every method to the best
//! `E` found by any method, whether the hybrid beats both of its parts, the
//! search-space technique against the bounding box, overlays of the best
//! fit of each function on each outline and, for campaigns in the
//! per-segment mode, the segment-level tests ([`super::fit_units`]).
//!
//! Problem names of fitting campaigns are `source/function/continuity`,
//! then `/bounding-box` for the naive search space, `/alpha=A` for a listed
//! α_size other than 0.5, `/per-segment` in the per-segment mode. When runs
//! of one name differ in budget, each budget per segment is its own problem
//! here, as in the rest of the report.

use std::collections::BTreeMap;
use std::path::Path;

use super::data::Dataset;
use super::fit_runs::{cell_name, same_seeds, split, two_sample_test, Case, FitRuns, SpaceTest};
use super::format::{sci, Table};
use super::plots::{Figure, Page, Plot};
use super::verdicts::Observation;
use crate::experiment::reading::{open_csv, RESULT_LIMITS};
use crate::experiment::records::{read_results, FitDetail, RunRecord};
use crate::experiment::segments::segment_from_row;
use crate::experiment::{DataError, DataProblem, ReadError};
use crate::files::fmt_real;
use crate::fit::Segment;
use crate::geometry::Point;
use crate::reconstruction::{OverlayCurve, OverlayFigure, OverlayPanel};
use crate::stats::{holm_bonferroni, median, Mark, VerdictRow};

/// What the fitting section adds to a report.
pub(crate) struct FittingSection {
    /// Its tables.
    pub tables: Vec<Table>,
    /// Its figures (one overlay per source).
    pub figures: Vec<Plot>,
    /// Remarks.
    pub notes: Vec<String>,
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// A fitted outline read back from its segment rows, for an overlay;
/// `None` if a row does not describe a segment.
fn overlay_from_rows(label: String, rows: &[Vec<String>]) -> Option<OverlayCurve> {
    let segments: Vec<Segment> = rows
        .iter()
        .map(|r| segment_from_row(r))
        .collect::<Option<_>>()?;
    Some(OverlayCurve::of_segments(label, &segments))
}

/// Reads `outlines.csv` (source, x, y): the data points of every source.
fn read_outlines(dir: &Path) -> Result<BTreeMap<String, Vec<Point>>, ReadError> {
    let path = dir.join("outlines.csv");
    let mut out: BTreeMap<String, Vec<Point>> = BTreeMap::new();
    if !path.exists() {
        return Ok(out);
    }
    let mut reader = open_csv(&path, RESULT_LIMITS, true)?;
    for (i, row) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let row = row.map_err(|e| DataError::new(&path, line, DataProblem::Csv(e)))?;
        let num = |k: usize| -> Result<f64, DataError> {
            row.get(k)
                .unwrap_or("")
                .parse()
                .map_err(|_| DataError::new(&path, line, DataProblem::NotANumber(k + 1)))
        };
        out.entry(row.get(0).unwrap_or("").to_owned())
            .or_default()
            .push(Point::new(num(1)?, num(2)?));
    }
    Ok(out)
}

/// The empty fit-quality table, with its headers.
fn quality_frame() -> Table {
    Table {
        stem: "fit_quality".into(),
        title: "Fit quality and the gap to the best E found".into(),
        intro: vec![
            "For each fitting problem (source/function/continuity) and method: the mean and \
             best E = Σ|Rᵢ − P(sᵢ)|² over the runs, the relative gap of the mean to the best E \
             found by any method on that problem (the exact reference LM included), the mean \
             RMS √(E/N) (measured at the parameters sᵢ), the mean RMS of the orthogonal \
             distances (each data point to its segment; with the current fitting records), \
             the mean largest orthogonal distance of a data point to the curve (data → curve), \
             with the current fitting records the mean largest distance of the curve to the \
             outline polyline (curve → data, which sees curve where no data point is) and the \
             mean of the larger of the two (the fit's Hausdorff distance), and the mean \
             tangent angle at the closing joint of a closed outline (the largest over its \
             contours): near 0 where the chain closes smoothly, a kink where it closes C⁰ \
             or at a corner (data units: pixels for images, font units for glyphs)."
                .into(),
        ],
        md_header: [
            "Problem",
            "Method",
            "Runs",
            "Mean E",
            "Best E",
            "Gap of mean",
            "Mean RMS",
            "Mean max dist",
            "Closing angle (°)",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "method",
            "runs",
            "mean_sse",
            "best_sse",
            "best_known_sse",
            "gap",
            "mean_rms",
            "mean_max_distance",
            "mean_closing_angle_degrees",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// The means of one method's runs on one problem.
struct Quality {
    mean: f64,
    best: f64,
    gap: f64,
    rms: f64,
    rms_distance: f64,
    max_distance: f64,
    curve_distance: f64,
    hausdorff: f64,
    angle: f64,
}

impl Quality {
    /// The quality of `runs` against the best E found, `known`.
    fn of(runs: &[&RunRecord], known: f64) -> Quality {
        let e: Vec<f64> = runs.iter().map(|r| r.best).collect();
        let fit = |f: fn(&FitDetail) -> Option<f64>| -> f64 {
            let v: Vec<f64> = runs
                .iter()
                .filter_map(|r| r.fit.as_ref().and_then(f))
                .collect();
            if v.is_empty() {
                f64::NAN
            } else {
                mean(&v)
            }
        };
        let m = mean(&e);
        Quality {
            mean: m,
            best: e.iter().copied().fold(f64::INFINITY, f64::min),
            gap: if known > 0.0 {
                m / known - 1.0
            } else {
                f64::NAN
            },
            rms: fit(|d| Some(d.rms)),
            rms_distance: fit(|d| d.rms_distance),
            max_distance: fit(|d| Some(d.max_distance)),
            curve_distance: fit(|d| d.two_sided.map(|t| t.0)),
            hausdorff: fit(|d| d.two_sided.map(|t| t.1)),
            angle: fit(|d| d.closing_angle_degrees.filter(|a| a.is_finite())),
        }
    }
}

/// The fit quality of every method on every problem, with the gap of its
/// mean E to the best E found (`known`); the orthogonal RMS when the
/// records have it.
fn quality_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
    let mut quality = quality_frame();
    let orthogonal = fr
        .runs
        .values()
        .flatten()
        .any(|r| r.fit.as_ref().is_some_and(|f| f.rms_distance.is_some()));
    let two_sided = fr
        .runs
        .values()
        .flatten()
        .any(|r| r.fit.as_ref().is_some_and(|f| f.two_sided.is_some()));
    if two_sided {
        // After the mean max distance (data -> curve): curve -> data and
        // the larger of the two.
        quality.md_header.insert(8, "Mean curve→data".into());
        quality.md_header.insert(9, "Mean Hausdorff".into());
        quality.csv_header.insert(9, "mean_curve_distance".into());
        quality.csv_header.insert(10, "mean_hausdorff".into());
    }
    if orthogonal {
        quality.md_header.insert(7, "Mean RMS distance".into());
        quality.csv_header.insert(8, "mean_rms_distance".into());
    }
    for (p, problem) in fr.problems.iter().enumerate() {
        for (c, cell) in fr.cells.iter().enumerate() {
            let Some(rs) = fr.runs.get(&(p, c)) else {
                continue;
            };
            let q = Quality::of(rs, best[p].0);
            let mut md = vec![
                problem.label(),
                cell.clone(),
                rs.len().to_string(),
                sci(q.mean),
                sci(q.best),
                sci(q.gap),
                sci(q.rms),
                sci(q.max_distance),
                if q.angle.is_nan() {
                    "—".into()
                } else {
                    format!("{:.2}", q.angle)
                },
            ];
            let mut csv = vec![
                problem.label(),
                cell.clone(),
                rs.len().to_string(),
                fmt_real(q.mean),
                fmt_real(q.best),
                fmt_real(best[p].0),
                fmt_real(q.gap),
                fmt_real(q.rms),
                fmt_real(q.max_distance),
                fmt_real(q.angle),
            ];
            if two_sided {
                md.insert(8, sci(q.curve_distance));
                md.insert(9, sci(q.hausdorff));
                csv.insert(9, fmt_real(q.curve_distance));
                csv.insert(10, fmt_real(q.hausdorff));
            }
            if orthogonal {
                md.insert(7, sci(q.rms_distance));
                csv.insert(8, fmt_real(q.rms_distance));
            }
            quality.md_rows.push(md);
            quality.csv_rows.push(csv);
        }
    }
    quality
}

/// Which function fits each source best, per continuity (and space): the
/// best E per problem, grouped by source.
fn functions_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
    let mut functions = Table {
        stem: "fit_functions".into(),
        title: "Best E per fitting function".into(),
        intro: vec![
            "For each source, continuity and search space, the best E that any method reached \
             with each fitting function, and the method that reached it. The lowest E of a \
             row group is the function that fits that outline best."
                .into(),
        ],
        md_header: ["Source", "Continuity", "Function", "Best E", "Found by"]
            .map(String::from)
            .to_vec(),
        csv_header: [
            "source",
            "continuity",
            "variant",
            "search_space",
            "budget_per_segment",
            "function",
            "best_sse",
            "found_by",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    let problems = &fr.problems;
    let mut order: Vec<usize> = (0..problems.len()).collect();
    order.sort_by_key(|&p| {
        split(&problems[p].name).map(|c| {
            (
                c.source,
                c.variant(),
                c.space_level(),
                problems[p].budget,
                c.continuity,
                p,
            )
        })
    });
    for p in order {
        let Some(case) = split(&problems[p].name) else {
            continue;
        };
        let mut cont = case.continuity.to_uppercase();
        let variant = case.variant();
        if !variant.is_empty() {
            cont = format!("{cont} {variant}");
        }
        if case.space.is_some() || case.alpha.is_some() {
            cont = format!("{cont} ({})", case.space_level());
        }
        if let Some(b) = problems[p].budget {
            cont = format!("{cont}, budget {b}");
        }
        functions.md_rows.push(vec![
            case.source.into(),
            cont,
            case.function.into(),
            sci(best[p].0),
            best[p].1.clone(),
        ]);
        functions.csv_rows.push(vec![
            case.source.into(),
            case.continuity.into(),
            variant,
            case.space_level(),
            problems[p].budget.map_or(String::new(), |b| b.to_string()),
            case.function.into(),
            fmt_real(best[p].0),
            best[p].1.clone(),
        ]);
    }
    functions
}

/// The empty hybrid table, with its headers.
fn hybrid_frame() -> Table {
    Table {
        stem: "fit_hybrid".into(),
        title: "Hybrid against its parts".into(),
        intro: vec![
            "For each metaheuristic X run both alone and as X+LM (X on 80 % of the budget, \
             then a Levenberg–Marquardt polish), with LM alone also run: the median E of X, LM \
             and X+LM, and whether the hybrid's median is below both."
                .into(),
        ],
        md_header: [
            "Problem",
            "X",
            "Median E of X",
            "Median E of LM",
            "Median E of X+LM",
            "Beats both",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "x",
            "median_x",
            "median_lm",
            "median_hybrid",
            "beats_both",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// Hybrids against their two parts: for every X+LM whose X and LM also
/// ran, whether its median E is below both of theirs.
fn hybrid_table(fr: &FitRuns<'_>) -> Table {
    let mut hybrid = hybrid_frame();
    let kinds = fr.kinds();
    let Some(lm) = kinds.iter().position(|k| k.as_deref() == Some("lm")) else {
        return hybrid;
    };
    for (p, problem) in fr.problems.iter().enumerate() {
        let med = |c: usize| fr.errors(p, c).map(|e| median(&e));
        for (h, kind) in kinds.iter().enumerate() {
            let Some(base) = kind.as_deref().and_then(|k| k.strip_suffix("+lm")) else {
                continue;
            };
            let Some(x) = kinds.iter().position(|k| k.as_deref() == Some(base)) else {
                continue;
            };
            let (Some(mx), Some(ml), Some(mh)) = (med(x), med(lm), med(h)) else {
                continue;
            };
            let beats = mh < mx.min(ml) * (1.0 - 1e-9);
            hybrid.md_rows.push(vec![
                problem.label(),
                fr.cells[x].clone(),
                sci(mx),
                sci(ml),
                sci(mh),
                if beats { "yes" } else { "no" }.into(),
            ]);
            hybrid.csv_rows.push(vec![
                problem.label(),
                fr.cells[x].clone(),
                fmt_real(mx),
                fmt_real(ml),
                fmt_real(mh),
                beats.to_string(),
            ]);
        }
    }
    hybrid
}

/// The empty search-space table, with its headers.
fn search_space_frame(alpha: f64) -> Table {
    Table {
        stem: "fit_search_space".into(),
        title: "Search-space technique against the bounding box".into(),
        intro: vec![format!(
            "For each problem run with the technique (at each α_size) and with the bounding \
             box, at the same budget, and each method: the median E inside the technique's \
             boxes and inside the naive bounding box, and a two-sided test with Holm's \
             correction over all rows — the Wilcoxon signed-rank test paired by run where \
             the runs of the two problems share their seeds (the spec pairs the search space \
             and α_size), else the Mann–Whitney U test. The mark is from the technique's \
             point of view at α = {alpha}: + significantly lower E with the technique, − \
             significantly higher, ≈ no significant difference. Here the whole outline is \
             the unit; the segment-level table, where there is one, has segments as units."
        )],
        md_header: [
            "Problem",
            "Method",
            "Median E (technique)",
            "Median E (bounding box)",
            "Test",
            "p",
            "p (Holm)",
            "Mark",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "search_space",
            "budget_per_segment",
            "method",
            "median_technique",
            "median_bounding_box",
            "test",
            "statistic",
            "p_value",
            "p_holm",
            "mark",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// A method's runs on a problem in both search spaces: (the technique's
/// problem, method, median E with the technique, median E in the
/// bounding box, the test).
type SpacePair = (usize, String, f64, f64, SpaceTest);

/// Every technique problem (each α_size) with a bounding-box twin at the
/// same budget, and every method run on both, with the test of its two
/// samples.
fn space_pairs(fr: &FitRuns<'_>) -> Vec<SpacePair> {
    let mut pairs = Vec::new();
    for (pb, bb) in fr.problems.iter().enumerate() {
        let Some(c) = split(&bb.name) else { continue };
        if c.space != Some("bounding-box") {
            continue;
        }
        for (pt, tech) in fr.problems.iter().enumerate() {
            let twin = split(&tech.name).is_some_and(|t| {
                t.space.is_none() && t.base() == c.base() && tech.budget == bb.budget
            });
            if !twin {
                continue;
            }
            for (cell, cell_name) in fr.cells.iter().enumerate() {
                let (Some(ea), Some(eb)) = (fr.errors(pt, cell), fr.errors(pb, cell)) else {
                    continue;
                };
                if let Some(t) = two_sample_test(&ea, &eb, same_seeds(fr, pt, pb, cell)) {
                    pairs.push((pt, cell_name.clone(), median(&ea), median(&eb), t));
                }
            }
        }
    }
    pairs
}

/// The search-space technique against the naive bounding box, with Holm's
/// correction over all rows.
fn search_space_table(fr: &FitRuns<'_>, alpha: f64) -> Table {
    let mut space = search_space_frame(alpha);
    let pairs = space_pairs(fr);
    if pairs.is_empty() {
        return space;
    }
    let p: Vec<f64> = pairs.iter().map(|x| x.4.p_value).collect();
    let adjusted = holm_bonferroni(&p).unwrap_or(p);
    for ((pt, method, ma, mb, t), ph) in pairs.into_iter().zip(adjusted) {
        let mark = Mark::from_p_value(ph, alpha, t.direction);
        let problem = &fr.problems[pt];
        let level = split(&problem.name).map_or(String::new(), |c| c.space_level());
        space.md_rows.push(vec![
            problem.label(),
            method.clone(),
            sci(ma),
            sci(mb),
            t.test.into(),
            sci(t.p_value),
            sci(ph),
            mark.symbol().into(),
        ]);
        space.csv_rows.push(vec![
            problem.name.clone(),
            level,
            problem.budget.map_or(String::new(), |b| b.to_string()),
            method,
            fmt_real(ma),
            fmt_real(mb),
            t.test.into(),
            fmt_real(t.statistic),
            fmt_real(t.p_value),
            fmt_real(ph),
            mark.symbol().into(),
        ]);
    }
    space
}

/// The overlay panel of one function on one source: the best fit of each
/// continuity (technique search space at its default α_size, any budget),
/// titled with their E and method.
fn overlay_panel(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    source: &str,
    function: &str,
    data: &[Point],
) -> OverlayPanel {
    let mut best: Vec<(String, &RunRecord)> = Vec::new();
    for ((p, _), rs) in &fr.runs {
        let Some(c) = split(&fr.problems[*p].name) else {
            continue;
        };
        // At equal segments only: a panel compares the continuities and
        // the variants (error, chain) of one function.
        if c.source != source
            || c.function != function
            || c.space.is_some()
            || c.alpha.is_some()
            || c.params.is_some()
        {
            continue;
        }
        let variant = c.variant();
        let cont = if variant.is_empty() {
            c.continuity.to_uppercase()
        } else {
            format!("{} {variant}", c.continuity.to_uppercase())
        };
        for r in rs {
            match best.iter_mut().find(|(k, _)| *k == cont) {
                Some((_, b)) if r.best < b.best => *b = r,
                Some(_) => {}
                None => best.push((cont.clone(), r)),
            }
        }
    }
    let mut curves = Vec::new();
    let mut bests = Vec::new();
    for (cont, r) in best {
        if let Some(curve) = r
            .fit
            .as_ref()
            .and_then(|f| overlay_from_rows(cont.clone(), &f.segments))
        {
            bests.push(format!("{cont} E = {} ({})", sci(r.best), cell_name(ds, r)));
            curves.push(curve);
        }
    }
    OverlayPanel {
        title: format!("{function}: {}", bests.join(", ")),
        data: data.to_vec(),
        curves,
        y_down: false,
    }
}

/// The overlay plot of one source: a panel per fitting function, or
/// `None` when it has none.
fn overlay_plot(ds: &Dataset, fr: &FitRuns<'_>, source: &str, data: &[Point]) -> Option<Plot> {
    let mut function_names: Vec<&str> = Vec::new();
    for p in &fr.problems {
        if let Some(c) = split(&p.name) {
            if c.source == source
                && c.space.is_none()
                && c.alpha.is_none()
                && !function_names.contains(&c.function)
            {
                function_names.push(c.function);
            }
        }
    }
    let panels: Vec<OverlayPanel> = function_names
        .into_iter()
        .map(|function| overlay_panel(ds, fr, source, function, data))
        .collect();
    if panels.is_empty() {
        return None;
    }
    let slug: String = source
        .chars()
        .map(|ch| if ch.is_ascii_alphanumeric() { ch } else { '_' })
        .collect();
    Some(Plot {
        page: Page::SINGLE,
        stem: format!("overlay_{slug}"),
        title: format!("Best fits of {source}"),
        caption: format!(
            "The data points of {source} (grey) and, for each fitting function, the fit \
             with the lowest E over all methods and runs for each continuity (circles mark \
             the segments' start points; the legend gives E and the method). Equal scale \
             in x and y."
        ),
        figure: Figure::Overlay(OverlayFigure {
            title: format!("{source}: best fit of each function"),
            panels,
            columns: 2,
        }),
    })
}

/// Overlays: per source, a panel per function with the best fit of each
/// continuity (technique search space). A source whose points are not in
/// `outlines` gets a note instead.
fn overlays(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    outlines: &BTreeMap<String, Vec<Point>>,
    notes: &mut Vec<String>,
) -> Vec<Plot> {
    let mut sources: Vec<&str> = fr
        .problems
        .iter()
        .filter_map(|p| split(&p.name).map(|c| c.source))
        .collect();
    sources.dedup();
    let mut seen = std::collections::BTreeSet::new();
    sources.retain(|s| seen.insert(*s));
    let mut figures = Vec::new();
    for source in sources {
        let Some(data) = outlines.get(source) else {
            notes.push(format!(
                "no overlay for {source}: outlines.csv does not hold its points"
            ));
            continue;
        };
        figures.extend(overlay_plot(ds, fr, source, data));
    }
    figures
}

/// The observations of the comparisons between fitting functions and
/// between continuities on whole outlines, outlines as units: every
/// function against the rational cubic (table `fitting-function`) and G1
/// against C1 (table `continuity`), each method's median E on one case
/// against its median E on the twin case (same source, search space and
/// budget), log10 of the ratio. With four outlines no such verdict can
/// reject at α = 0.05 (p_min = 0.125): the claims they test stay
/// descriptive, and the report says so. Only the thesis's methods enter:
/// the thesis's claims are about them, and the methods beyond it (CMA-ES,
/// L-SHADE, random search, alone or before LM) are judged against the
/// reference instead, so adding them leaves these verdicts as they were.
pub(crate) fn treatment_observations(fr: &FitRuns<'_>) -> Vec<Observation> {
    use super::design::{Level, Levels};
    use super::verdicts::Measure;
    let thesis: Vec<bool> = fr
        .kinds()
        .iter()
        .map(|k| !fr.families.beyond_the_thesis(k.as_deref().unwrap_or("")))
        .collect();
    // Cases of whole outlines by (source, space level, budget, variant).
    type CaseKey = (String, String, Option<u64>, String);
    let mut cases: BTreeMap<CaseKey, Vec<(usize, Case<'_>)>> = BTreeMap::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(c) = split(&problem.name).filter(|c| !c.per_segment) else {
            continue;
        };
        cases
            .entry((
                c.source.to_owned(),
                c.space_level(),
                problem.budget,
                c.variant(),
            ))
            .or_default()
            .push((p, c));
    }
    let mut obs = Vec::new();
    let mut compare = |table: &'static str,
                       (pa, a): (usize, &str),
                       (pb, b): (usize, &str),
                       source: &str,
                       fixed: (&'static str, &str),
                       case: &Case<'_>| {
        for (c, cell) in fr.cells.iter().enumerate() {
            if !thesis[c] {
                continue;
            }
            let (Some(ea), Some(eb)) = (fr.errors(pa, c), fr.errors(pb, c)) else {
                continue;
            };
            let value = (median(&ea) / median(&eb)).log10();
            if value.is_nan() {
                continue;
            }
            obs.push(Observation {
                table,
                measure: Measure::FinalError,
                algorithm: a.to_owned(),
                reference: b.to_owned(),
                unit: source.to_owned(),
                levels: Levels(vec![
                    (fixed.0, Level::Text(fixed.1.to_owned())),
                    ("error", Level::Text(case.error().to_owned())),
                    ("chain", Level::Text(case.chain().to_owned())),
                    ("size", Level::Text(case.size().into())),
                    ("method", Level::Text(cell.clone())),
                ]),
                value,
            });
        }
    };
    for ((source, _, _, _), list) in &cases {
        for &(p, c) in list {
            // Every function against the rational cubic of the same continuity.
            if c.function != "rational-cubic" {
                if let Some(&(q, _)) = list
                    .iter()
                    .find(|(_, d)| d.function == "rational-cubic" && d.continuity == c.continuity)
                {
                    let a = (p, c.function);
                    let b = (q, "rational-cubic");
                    compare(
                        "fitting-function",
                        a,
                        b,
                        source,
                        ("continuity", c.continuity),
                        &c,
                    );
                }
            }
            // G1 against C1 with the same function.
            if c.continuity == "g1" {
                if let Some(&(q, _)) = list
                    .iter()
                    .find(|(_, d)| d.function == c.function && d.continuity == "c1")
                {
                    compare(
                        "continuity",
                        (p, "g1"),
                        (q, "c1"),
                        source,
                        ("function", c.function),
                        &c,
                    );
                }
            }
        }
    }
    obs
}

/// The records of a fitting campaign in `dir` (runs with their fit
/// details), or `None` when it has no `fits.csv`.
pub(crate) fn records(dir: &Path) -> Result<Option<Vec<RunRecord>>, ReadError> {
    if !dir.join("fits.csv").exists() {
        return Ok(None);
    }
    read_results(dir).map(Some)
}

/// The fitting section of the report in `dir`, or `None` if the campaign
/// has no fitting runs; `observations` and `verdicts` are those of the
/// report, whose segment-level rows the per-segment tables show.
pub(crate) fn section(
    dir: &Path,
    ds: &Dataset,
    fits: Option<&FitRuns<'_>>,
    observations: &[Observation],
    verdicts: &[VerdictRow],
    alpha: f64,
) -> Result<Option<FittingSection>, ReadError> {
    let Some(fr) = fits else {
        return Ok(None);
    };
    let best = fr.best();
    let mut notes = Vec::new();
    let mut tables = vec![quality_table(fr, &best), functions_table(fr, &best)];
    let space = search_space_table(fr, alpha);
    if !space.md_rows.is_empty() {
        tables.push(space);
    }
    let (units, unit_notes) = super::fit_units::tables(fr, observations, verdicts, alpha);
    tables.extend(units);
    notes.extend(unit_notes);
    let hybrid = hybrid_table(fr);
    if hybrid.md_rows.is_empty() {
        notes.push(
            "no hybrid table: the campaign does not run a metaheuristic X, LM and X+lm together"
                .into(),
        );
    } else {
        tables.push(hybrid);
    }
    let outlines = read_outlines(dir)?;
    let figures = overlays(ds, fr, &outlines, &mut notes);
    Ok(Some(FittingSection {
        tables,
        figures,
        notes,
    }))
}
