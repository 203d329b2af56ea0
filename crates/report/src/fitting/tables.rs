//! The tables of the fitting section, rendered from the fitting runs: fit
//! quality beyond E, the gap of every method to the best E, the hybrid
//! against its parts and the search-space technique against the bounding
//! box.

use super::super::fit_runs::{same_seeds, split, two_sample_test, FitRuns, SpaceTest};
use super::super::format::{sci, Table};
use crate::experiment::records::{FitDetail, RunRecord};
use crate::files::fmt_real;
use crate::stats::{holm_bonferroni, median, Mark};

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
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
pub(super) fn quality_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
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
pub(super) fn functions_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
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
pub(super) fn hybrid_table(fr: &FitRuns<'_>) -> Table {
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
pub(super) fn search_space_table(fr: &FitRuns<'_>, alpha: f64) -> Table {
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
