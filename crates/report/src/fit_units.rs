//! Segment-level inference for fitting campaigns in the per-segment mode:
//! every segment is its own problem (joined to the exact fit's neighbours),
//! so a segment is a unit of the test, not the whole outline.
//!
//! For each comparison (every algorithm against the reference; the
//! search-space technique at each α_size against the bounding box; every
//! pair of methods) this module gives [`super::verdicts`] one observation
//! per segment: log10 of the ratio of the two median E over the runs. The
//! verdicts (Wilcoxon signed-rank over the segments, Holm over the rows of
//! one scope) are then shown beside the first-level description: per
//! segment, the two samples of E over the runs tested two-sided (Wilcoxon
//! signed-rank paired by run when the runs share their seeds, else
//! Mann–Whitney U), Holm-corrected over the segments of the row and
//! counted as better / same / worse.

use std::collections::{BTreeMap, BTreeSet};

use super::design::{fit_levels, restrict, varying, without, Levels};
use super::fit_runs::{same_seeds, split, two_sample_test, FitRuns};
use super::format::{p_value, sci, Table};
use super::verdicts::{find, Measure, Observation, Standing};
use crate::experiment::segments::FIT_SEGMENT_HEADER;
use crate::files::fmt_real;
use crate::fit::ALPHA_SIZE;
use crate::stats::{holm_bonferroni, median, Mark, Verdict, VerdictRow};

/// A segment of a source: (source, contour, segment).
pub(super) type Unit = (String, String, String);

/// The E of every run of one (problem, cell) per segment: unit → E by run.
pub(super) type UnitRuns = BTreeMap<Unit, Vec<f64>>;

/// The segment E's of the runs of cell `c` on problem `p`, by segment
/// (rows in the layout of [`FIT_SEGMENT_HEADER`]).
pub(super) fn unit_runs(fr: &FitRuns<'_>, p: usize, c: usize) -> Option<UnitRuns> {
    let sse = FIT_SEGMENT_HEADER.iter().position(|h| *h == "sse")?;
    let source = split(&fr.problems[p].name)?.source.to_owned();
    let mut runs: Vec<_> = fr.runs.get(&(p, c))?.clone();
    runs.sort_by_key(|r| r.run);
    let mut out: UnitRuns = BTreeMap::new();
    for r in runs {
        for row in &r.fit.as_ref()?.segments {
            if row.len() != FIT_SEGMENT_HEADER.len() {
                return None;
            }
            let e: f64 = row[sse].parse().ok()?;
            out.entry((source.clone(), row[0].clone(), row[1].clone()))
                .or_default()
                .push(e);
        }
    }
    Some(out)
}

/// The name of a segment unit: `source/contour/segment`.
fn unit_name(u: &Unit) -> String {
    format!("{}/{}/{}", u.0, u.1, u.2)
}

/// log10 of the ratio of two medians, both floored.
fn log_ratio(a: &[f64], b: &[f64], floor: f64) -> f64 {
    (median(a).max(floor) / median(b).max(floor)).log10()
}

/// The first-level description of one comparison (A against B) over the
/// segments they share: the per-segment tests (paired when `paired`)
/// Holm-corrected and counted, and the median ratio of E.
struct UnitRow {
    units: usize,
    median_ratio: f64,
    better: usize,
    same: usize,
    worse: usize,
}

fn describe(a: &UnitRuns, b: &UnitRuns, paired: bool, alpha: f64) -> Option<UnitRow> {
    let mut ratios = Vec::new();
    let mut tests = Vec::new();
    let mut units = 0;
    for (unit, ea) in a {
        let Some(eb) = b.get(unit) else { continue };
        units += 1;
        let (ma, mb) = (median(ea), median(eb));
        if mb > 0.0 {
            ratios.push(ma / mb);
        }
        if let Some(t) = two_sample_test(ea, eb, paired) {
            tests.push((t.p_value, t.direction));
        }
    }
    if units == 0 {
        return None;
    }
    let p: Vec<f64> = tests.iter().map(|t| t.0).collect();
    let adjusted = holm_bonferroni(&p).unwrap_or(p);
    let (mut better, mut same, mut worse) = (0, 0, 0);
    for (ph, (_, d)) in adjusted.iter().zip(&tests) {
        match Mark::from_p_value(*ph, alpha, *d) {
            Mark::Better => better += 1,
            Mark::Same => same += 1,
            Mark::Worse => worse += 1,
        }
    }
    Some(UnitRow {
        units,
        median_ratio: if ratios.is_empty() {
            f64::NAN
        } else {
            median(&ratios)
        },
        better,
        same,
        worse,
    })
}

/// A group of per-segment problems pooled over the sources: function,
/// continuity and variant (`function/continuity` with the name's tail:
/// `orthogonal` and the like, see [`super::fit_runs::Case::variant`]),
/// search-space level and budget per segment.
type Group = (String, String, String, Option<u64>);

/// The per-segment problems of each group, with their sources.
fn groups(fr: &FitRuns<'_>) -> BTreeMap<Group, Vec<usize>> {
    let mut out: BTreeMap<Group, Vec<usize>> = BTreeMap::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(c) = split(&problem.name).filter(|c| c.per_segment) else {
            continue;
        };
        let variant = c.variant();
        let continuity = if variant.is_empty() {
            c.continuity.to_owned()
        } else {
            format!("{}/{variant}", c.continuity)
        };
        let key = (
            c.function.to_owned(),
            continuity,
            c.space_level(),
            problem.budget,
        );
        out.entry(key).or_default().push(p);
    }
    out
}

/// The unit E's of cell `c` pooled over the problems `ps` (one per source).
fn pooled(fr: &FitRuns<'_>, ps: &[usize], c: usize) -> Option<UnitRuns> {
    let mut out = UnitRuns::new();
    for &p in ps {
        out.extend(unit_runs(fr, p, c)?);
    }
    Some(out)
}

/// The design levels of fitting problem `p`.
fn levels_of(fr: &FitRuns<'_>, p: usize) -> Levels {
    fit_levels(&fr.problems[p].name, fr.problems[p].budget)
}

/// The technique's α_size of a level text (`technique, α = 0.1`; 0.5 when
/// it is the default).
fn alpha_of(level: &str) -> String {
    level
        .strip_prefix("technique, α = ")
        .map_or_else(|| fmt_real(ALPHA_SIZE.default), str::to_owned)
}

/// The names of a search-space comparison: (algorithm, reference).
fn space_names(cell: &str, alpha_size: &str) -> (String, String) {
    (
        format!("{cell}: technique α_size {alpha_size}"),
        format!("{cell}: bounding box"),
    )
}

/// Every (technique problem, its bounding-box twin) of the per-segment
/// problems: same case and budget.
fn space_twins(groups: &BTreeMap<Group, Vec<usize>>) -> Vec<(&Group, &Vec<usize>, &Vec<usize>)> {
    let mut out = Vec::new();
    for (key, ps) in groups {
        let (function, continuity, level, budget) = key;
        if !level.starts_with("technique") {
            continue;
        }
        let bb_key = (
            function.clone(),
            continuity.clone(),
            "bounding-box".to_owned(),
            *budget,
        );
        if let Some(bs) = groups.get(&bb_key) {
            out.push((key, ps, bs));
        }
    }
    out
}

/// The segment observations of the per-segment problems: every cell
/// against `reference` (with every cell's standing), every pair of methods,
/// and the technique against the bounding box per method.
pub(crate) fn observations(
    fr: &FitRuns<'_>,
    reference: Option<&str>,
    floor: f64,
) -> (Vec<Observation>, Vec<Standing>) {
    let mut obs = Vec::new();
    let mut standings = Vec::new();
    let groups = groups(fr);
    let kinds = fr.kinds();
    let kind = |c: usize| kinds[c].as_deref().unwrap_or("");
    let observe = |obs: &mut Vec<Observation>,
                   table: &'static str,
                   names: (String, String),
                   levels: &Levels,
                   a: &UnitRuns,
                   b: &UnitRuns| {
        for (unit, ea) in a {
            if let Some(eb) = b.get(unit) {
                let value = log_ratio(ea, eb, floor);
                if !value.is_nan() {
                    obs.push(Observation {
                        table,
                        measure: Measure::FinalError,
                        algorithm: names.0.clone(),
                        reference: names.1.clone(),
                        unit: unit_name(unit),
                        levels: levels.clone(),
                        value,
                    });
                }
            }
        }
    };
    // Against the reference: the methods beyond the thesis (CMA-ES,
    // L-SHADE, random search, alone or before LM) in their own set.
    if let Some(r) = reference.and_then(|r| fr.cells.iter().position(|c| c == r)) {
        for ps in groups.values() {
            for &p in ps {
                let levels = levels_of(fr, p);
                let Some(rr) = unit_runs(fr, p, r) else {
                    continue;
                };
                for (c, cell) in fr.cells.iter().enumerate() {
                    let Some(cr) = unit_runs(fr, p, c) else {
                        continue;
                    };
                    let table = fr.families.comparison_set(kind(c), kind(r));
                    for (unit, e) in &cr {
                        standings.push(Standing {
                            table,
                            measure: Measure::FinalError,
                            algorithm: cell.clone(),
                            unit: unit_name(unit),
                            levels: levels.clone(),
                            value: median(e).max(floor).log10(),
                        });
                    }
                    if c != r {
                        let names = (cell.clone(), fr.cells[r].clone());
                        observe(&mut obs, table, names, &levels, &cr, &rr);
                    }
                }
            }
        }
    }
    // Every pair of methods (those with a method beyond the thesis in
    // their own set).
    for ps in groups.values() {
        for &p in ps {
            let levels = levels_of(fr, p);
            let units: Vec<Option<UnitRuns>> =
                (0..fr.cells.len()).map(|c| unit_runs(fr, p, c)).collect();
            for (i, a) in units.iter().enumerate() {
                for (j, b) in units.iter().enumerate().skip(i + 1) {
                    if let (Some(a), Some(b)) = (a, b) {
                        let names = (fr.cells[i].clone(), fr.cells[j].clone());
                        let table = fr.families.pair_set(kind(i), kind(j));
                        observe(&mut obs, table, names, &levels, a, b);
                    }
                }
            }
        }
    }
    // The technique against the bounding box.
    for ((_, _, level, _), ps, bs) in space_twins(&groups) {
        let alpha_size = alpha_of(level);
        for (&p, &q) in ps.iter().zip(bs) {
            let levels = without(&levels_of(fr, p), &["search_space", "alpha_size"]);
            for (c, cell) in fr.cells.iter().enumerate() {
                if let (Some(a), Some(b)) = (unit_runs(fr, p, c), unit_runs(fr, q, c)) {
                    let names = space_names(cell, &alpha_size);
                    observe(&mut obs, "search-space", names, &levels, &a, &b);
                }
            }
        }
    }
    (obs, standings)
}

/// The scope text of a design point within one table's observations.
fn scope_within(obs: &[Observation], table: &str, levels: &Levels) -> String {
    let points: Vec<Levels> = obs
        .iter()
        .filter(|o| o.table == table)
        .map(|o| o.levels.clone())
        .collect();
    let keep: BTreeSet<&'static str> = varying(&points);
    restrict(levels, &keep).scope()
}

/// The frame of a segment-level table whose rows start with `labels`.
fn frame(stem: &str, title: &str, intro: String, labels: &[&str]) -> Table {
    let md_tail = [
        "Segments",
        "Median ratio of E",
        "Segments +/≈/− (tests)",
        "p (over segments)",
        "p (Holm)",
        "p_min",
        "Verdict",
    ];
    let csv_tail = [
        "segments",
        "median_ratio",
        "segments_better",
        "segments_same",
        "segments_worse",
        "p_value",
        "p_holm",
        "p_min",
        "verdict",
    ];
    Table {
        stem: stem.into(),
        title: title.into(),
        intro: vec![intro],
        md_header: labels
            .iter()
            .chain(&md_tail)
            .map(|s| s.to_string())
            .collect(),
        csv_header: labels
            .iter()
            .map(|s| s.to_lowercase().replace(' ', "_"))
            .chain(csv_tail.iter().map(|s| s.to_string()))
            .collect(),
        ..Table::default()
    }
}

/// Appends one row: the labels, the first-level description and the
/// verdict found for it.
fn push_row(table: &mut Table, labels: Vec<String>, r: &UnitRow, v: Option<&VerdictRow>) {
    let (p, ph, pmin, verdict) = match v {
        Some(v) => (
            v.across.p_value,
            v.p_adjusted,
            v.across.p_min,
            v.verdict.to_string(),
        ),
        None => (f64::NAN, f64::NAN, f64::NAN, String::new()),
    };
    let mut md = labels.clone();
    md.extend([
        r.units.to_string(),
        sci(r.median_ratio),
        format!("{}/{}/{}", r.better, r.same, r.worse),
        p_value(p),
        p_value(ph),
        p_value(pmin),
        verdict.clone(),
    ]);
    table.md_rows.push(md);
    let mut csv = labels;
    csv.extend([
        r.units.to_string(),
        fmt_real(r.median_ratio),
        r.better.to_string(),
        r.same.to_string(),
        r.worse.to_string(),
        fmt_real(p),
        fmt_real(ph),
        fmt_real(pmin),
        verdict,
    ]);
    table.csv_rows.push(csv);
}

/// What the two tables share in their introductions: how to read a row.
const HOW_TO_READ: &str = "Segments are the units: every segment is its own problem, joined \
     to the exact (LM) fit's neighbours. Per segment, the runs' E are tested two-sided \
     (Wilcoxon signed-rank paired by run where the runs share their seeds, else \
     Mann–Whitney U), Holm-corrected over the segments of the row, and counted +/≈/−: a \
     description. The verdict is the test across the segments: the Wilcoxon signed-rank \
     test of the per-segment log10 ratios of the median E against zero, Holm-corrected over \
     the rows of one scope (tables/verdicts.csv); p_min is the smallest p the number of \
     segments allows. The median ratio is the median over the segments of (median E of the \
     first) / (median E of the second).";

/// Every segment-level table the per-segment problems allow, and notes.
pub(crate) fn tables(
    fr: &FitRuns<'_>,
    obs: &[Observation],
    rows: &[VerdictRow],
    alpha: f64,
) -> (Vec<Table>, Vec<String>) {
    let groups = groups(fr);
    if groups.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut tables = Vec::new();
    let mut notes = Vec::new();
    let (mut space, keys) = space_table(fr, &groups, obs, rows, alpha);
    if !space.md_rows.is_empty() {
        let lines = verdict_lines(&keys, |(cell, a)| {
            format!("{cell}, α_size {a}: the technique against the bounding box")
        });
        space.intro.extend(lines);
        tables.push(space);
    }
    let (mut methods, keys) = methods_table(fr, &groups, obs, rows, alpha);
    if methods.md_rows.is_empty() {
        notes.push(
            "no segment-level method table: a single method ran the per-segment problems".into(),
        );
    } else {
        methods.intro.extend(verdict_lines(&keys, |(pair, level)| {
            format!("{pair} ({level})")
        }));
        tables.push(methods);
    }
    (tables, notes)
}

/// The verdict of a row at its budget per segment.
type BudgetVerdict = (Option<u64>, Option<Verdict>);

/// A row's identity for the verdict lines: ((name, level), budget, verdict).
type Keyed = ((String, String), Option<u64>, Option<Verdict>);

/// The technique (each α_size) against the bounding box, per budget and
/// method, segments as units; and the keys of its rows.
fn space_table(
    fr: &FitRuns<'_>,
    groups: &BTreeMap<Group, Vec<usize>>,
    obs: &[Observation],
    rows: &[VerdictRow],
    alpha: f64,
) -> (Table, Vec<Keyed>) {
    let mut table = frame(
        "fit_segments_search_space",
        "Search space per segment: the technique against the bounding box",
        format!(
            "For every α_size of the technique, budget per segment and method: the technique \
             against the bounding box. {HOW_TO_READ} A ratio below 1 and + mean lower E with \
             the technique (marks and verdicts at α = {alpha})."
        ),
        &["Function", "α_size", "Budget", "Method"],
    );
    let mut keys = Vec::new();
    for ((function, continuity, level, budget), ps, bs) in space_twins(groups) {
        let alpha_size = alpha_of(level);
        let Some(&first) = ps.first() else { continue };
        let levels = without(&levels_of(fr, first), &["search_space", "alpha_size"]);
        let scope = scope_within(obs, "search-space", &levels);
        for (c, cell) in fr.cells.iter().enumerate() {
            let (Some(a), Some(b)) = (pooled(fr, ps, c), pooled(fr, bs, c)) else {
                continue;
            };
            let paired = ps.iter().zip(bs).all(|(&p, &q)| same_seeds(fr, p, q, c));
            let Some(r) = describe(&a, &b, paired, alpha) else {
                continue;
            };
            let (name, reference) = space_names(cell, &alpha_size);
            let v = find(
                rows,
                "search-space",
                Measure::FinalError,
                &name,
                &reference,
                &scope,
            );
            let labels = vec![
                format!("{function}/{continuity}"),
                alpha_size.clone(),
                budget.map_or("—".into(), |b| b.to_string()),
                cell.clone(),
            ];
            keys.push((
                (cell.clone(), alpha_size.clone()),
                *budget,
                v.map(|v| v.verdict),
            ));
            push_row(&mut table, labels, &r, v);
        }
    }
    (table, keys)
}

/// Every pair of methods (each against every later one, in the report's
/// order), per search space and budget, segments as units.
fn methods_table(
    fr: &FitRuns<'_>,
    groups: &BTreeMap<Group, Vec<usize>>,
    obs: &[Observation],
    rows: &[VerdictRow],
    alpha: f64,
) -> (Table, Vec<Keyed>) {
    let mut table = frame(
        "fit_segments_methods",
        "Methods per segment, in pairs",
        format!(
            "For every search space, budget per segment and pair of methods: the first \
             against the second. {HOW_TO_READ} A ratio below 1 and + mean lower E with the \
             first (marks and verdicts at α = {alpha})."
        ),
        &["Function", "Search space", "Budget", "Method", "Against"],
    );
    let mut keys = Vec::new();
    let kinds = fr.kinds();
    let kind = |c: usize| kinds[c].as_deref().unwrap_or("");
    for ((function, continuity, level, budget), ps) in groups {
        let Some(&first) = ps.first() else { continue };
        let scope = scope_within(obs, "method-pairs", &levels_of(fr, first));
        let units: Vec<Option<UnitRuns>> = (0..fr.cells.len()).map(|c| pooled(fr, ps, c)).collect();
        for (i, a) in units.iter().enumerate() {
            for (j, b) in units.iter().enumerate().skip(i + 1) {
                let (Some(a), Some(b)) = (a, b) else { continue };
                let Some(r) = describe(a, b, false, alpha) else {
                    continue;
                };
                let (x, y) = (&fr.cells[i], &fr.cells[j]);
                let v = find(
                    rows,
                    fr.families.pair_set(kind(i), kind(j)),
                    Measure::FinalError,
                    x,
                    y,
                    &scope,
                );
                let labels = vec![
                    format!("{function}/{continuity}"),
                    level.clone(),
                    budget.map_or("—".into(), |b| b.to_string()),
                    x.clone(),
                    y.clone(),
                ];
                keys.push((
                    (format!("{x} against {y}"), level.clone()),
                    *budget,
                    v.map(|v| v.verdict),
                ));
                push_row(&mut table, labels, &r, v);
            }
        }
    }
    (table, keys)
}

/// One line per (comparison, level): at which budgets its verdict is
/// better, not detectably different and worse, e.g. "HS against MHS
/// (technique): better at budgets 1000, 3000; no detectable difference at
/// budget 10000 (of 3 budgets)."
fn verdict_lines(keys: &[Keyed], name: impl Fn(&(String, String)) -> String) -> Vec<String> {
    let mut by: BTreeMap<&(String, String), Vec<BudgetVerdict>> = BTreeMap::new();
    let mut order: Vec<&(String, String)> = Vec::new();
    for (id, b, v) in keys {
        if !order.contains(&id) {
            order.push(id);
        }
        by.entry(id).or_default().push((*b, *v));
    }
    order
        .into_iter()
        .map(|id| {
            let at = &by[id];
            let mut parts = Vec::new();
            for v in [
                Verdict::Better,
                Verdict::Equivalent,
                Verdict::Undecided,
                Verdict::Worse,
            ] {
                let l: Vec<String> = at
                    .iter()
                    .filter(|(_, x)| *x == Some(v))
                    .map(|(b, _)| b.map_or("—".into(), |b| b.to_string()))
                    .collect();
                if !l.is_empty() {
                    parts.push(format!(
                        "{v} at budget{} {}",
                        if l.len() == 1 { "" } else { "s" },
                        l.join(", ")
                    ));
                }
            }
            format!(
                "{}: {} (of {} budgets).",
                name(id),
                parts.join("; "),
                at.len()
            )
        })
        .collect()
}
