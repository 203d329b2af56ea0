//! The segment-level tables of a per-segment fitting campaign, rendered
//! from the per-segment descriptions and the verdicts: the search-space
//! technique against the bounding box, and every pair of methods.

use std::collections::{BTreeMap, BTreeSet};

use super::super::design::{restrict, varying, without, Levels};
use super::super::fit_runs::{same_seeds, FitRuns};
use super::super::format::{p_value, sci, Table};
use super::super::verdicts::{find, Measure, Observation};
use super::{
    alpha_of, describe, groups, levels_of, pooled, space_names, space_twins, Group, UnitRow,
    UnitRuns,
};
use crate::files::fmt_real;
use crate::stats::{Verdict, VerdictRow};

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
