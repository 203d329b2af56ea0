//! Segment-level tests of fitting campaigns in the per-segment mode: every
//! segment is its own problem (joined to the exact fit's neighbours), so a
//! segment is a unit of the test, not the whole outline.
//!
//! For each comparison (the search-space technique at each α_size against
//! the bounding box; every pair of methods) at each budget,
//! pooled over the sources:
//!
//! * per segment, the two samples of E over the runs, tested two-sided
//!   (Wilcoxon signed-rank paired by run when the runs share their seeds,
//!   else Mann–Whitney U), Holm-corrected over the segments of the row and
//!   counted as better / same / worse;
//! * over the segments, the Wilcoxon signed-rank test of the per-segment
//!   medians paired by segment, Holm-corrected over the rows, with its mark.
//!
//! A one-line verdict per comparison then says at which budgets (and α_size)
//! it is better, tied or worse.

use std::collections::BTreeMap;

use super::fitting::{same_seeds, split, two_sample_test, FitRuns};
use super::format::{sci, Table};
use crate::experiment::segments::FIT_SEGMENT_HEADER;
use crate::files::fmt_real;
use crate::stats::{holm_bonferroni, median, wilcoxon, Alternative, Mark};

/// A segment of a source: (source, contour, segment).
type Unit = (String, String, String);

/// The E of every run of one (problem, cell) per segment: unit → E by run.
type UnitRuns = BTreeMap<Unit, Vec<f64>>;

/// The segment E's of the runs of cell `c` on problem `p`, by segment
/// (rows in the layout of [`FIT_SEGMENT_HEADER`]).
fn unit_runs(fr: &FitRuns<'_>, p: usize, c: usize) -> Option<UnitRuns> {
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

/// One comparison (A against B) over the units they share.
struct UnitRow {
    units: usize,
    median_ratio: f64,
    better: usize,
    same: usize,
    worse: usize,
    p_value: f64,
    direction: f64,
}

/// A against B: per-unit tests (paired when `paired`) Holm-corrected and
/// counted, and the Wilcoxon test of the per-unit medians over the units.
fn compare(a: &UnitRuns, b: &UnitRuns, paired: bool, alpha: f64) -> Option<UnitRow> {
    let mut meds = (Vec::new(), Vec::new());
    let mut ratios = Vec::new();
    let mut tests = Vec::new();
    for (unit, ea) in a {
        let Some(eb) = b.get(unit) else { continue };
        let (ma, mb) = (median(ea), median(eb));
        meds.0.push(ma);
        meds.1.push(mb);
        if mb > 0.0 {
            ratios.push(ma / mb);
        }
        if let Some(t) = two_sample_test(ea, eb, paired) {
            tests.push((t.p_value, t.direction));
        }
    }
    if meds.0.is_empty() {
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
    let over = wilcoxon(&meds.0, &meds.1, Alternative::TwoSided).ok();
    Some(UnitRow {
        units: meds.0.len(),
        median_ratio: if ratios.is_empty() {
            f64::NAN
        } else {
            median(&ratios)
        },
        better,
        same,
        worse,
        p_value: over.as_ref().map_or(1.0, |w| w.p_value),
        direction: over.map_or(0.0, |w| w.r_plus - w.r_minus),
    })
}

/// A group of per-segment problems pooled over the sources: function,
/// continuity, search-space level and budget per segment.
type Group = (String, String, String, Option<u64>);

/// The per-segment problems of each group, with their sources.
fn groups(fr: &FitRuns<'_>) -> BTreeMap<Group, Vec<usize>> {
    let mut out: BTreeMap<Group, Vec<usize>> = BTreeMap::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(c) = split(&problem.name).filter(|c| c.per_segment) else {
            continue;
        };
        let key = (
            c.function.to_owned(),
            c.continuity.to_owned(),
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

/// One row of a segment-level table before Holm's correction over rows:
/// (labels for the Markdown and CSV, the comparison).
type Pending = (Vec<String>, UnitRow);

/// Holm over the rows' p-values, then the Markdown and CSV rows and the
/// mark of each row.
fn finish(table: &mut Table, rows: Vec<Pending>, alpha: f64) -> Vec<Mark> {
    let p: Vec<f64> = rows.iter().map(|r| r.1.p_value).collect();
    let adjusted = holm_bonferroni(&p).unwrap_or(p);
    let mut marks = Vec::new();
    for ((labels, r), ph) in rows.into_iter().zip(adjusted) {
        let mark = Mark::from_p_value(ph, alpha, r.direction);
        marks.push(mark);
        let mut md = labels.clone();
        md.extend([
            r.units.to_string(),
            sci(r.median_ratio),
            format!("{}/{}/{}", r.better, r.same, r.worse),
            sci(r.p_value),
            sci(ph),
            mark.symbol().into(),
        ]);
        table.md_rows.push(md);
        let mut csv = labels;
        csv.extend([
            r.units.to_string(),
            fmt_real(r.median_ratio),
            r.better.to_string(),
            r.same.to_string(),
            r.worse.to_string(),
            fmt_real(r.p_value),
            fmt_real(ph),
            mark.symbol().into(),
        ]);
        table.csv_rows.push(csv);
    }
    marks
}

/// The frame of a segment-level table whose rows start with `labels`.
fn frame(stem: &str, title: &str, intro: String, labels: &[&str]) -> Table {
    let md_tail = [
        "Segments",
        "Median ratio of E",
        "Segments +/≈/−",
        "p (over segments)",
        "p (Holm)",
        "Mark",
    ];
    let csv_tail = [
        "segments",
        "median_ratio",
        "segments_better",
        "segments_same",
        "segments_worse",
        "p_value",
        "p_holm",
        "mark",
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

/// What the two tables share in their introductions: how to read a row.
const HOW_TO_READ: &str = "Segments are the units: every segment is its own problem, joined \
     to the exact (LM) fit's neighbours. Per segment, the runs' E are tested two-sided \
     (Wilcoxon signed-rank paired by run where the runs share their seeds, else \
     Mann–Whitney U), Holm-corrected over the segments of the row, and counted +/≈/−; \
     over the segments, the Wilcoxon signed-rank test of the per-segment medians, paired \
     by segment and Holm-corrected over the rows, gives the row's mark. The median ratio \
     is the median over the segments of (median E of the first) / (median E of the second).";

/// Every segment-level table the per-segment problems allow, and notes.
pub(crate) fn tables(fr: &FitRuns<'_>, alpha: f64) -> (Vec<Table>, Vec<String>) {
    let groups = groups(fr);
    if groups.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let mut tables = Vec::new();
    let mut notes = Vec::new();
    let (space, lines) = space_table(fr, &groups, alpha);
    if !space.md_rows.is_empty() {
        let mut space = space;
        space.intro.extend(lines);
        tables.push(space);
    }
    let mut methods = methods_table(fr, &groups, alpha);
    if methods.md_rows.is_empty() {
        notes.push(
            "no segment-level method table: a single method ran the per-segment problems".into(),
        );
    } else {
        let lines = method_verdicts(&methods);
        methods.intro.extend(lines);
        tables.push(methods);
    }
    (tables, notes)
}

/// The technique (each α_size) against the bounding box, per budget and
/// method, segments as units; and the verdict lines.
fn space_table(
    fr: &FitRuns<'_>,
    groups: &BTreeMap<Group, Vec<usize>>,
    alpha: f64,
) -> (Table, Vec<String>) {
    let mut table = frame(
        "fit_segments_search_space",
        "Search space per segment: the technique against the bounding box",
        format!(
            "For every α_size of the technique, budget per segment and method: the technique \
             against the bounding box. {HOW_TO_READ} A ratio below 1 and + mean lower E with \
             the technique (marks at α = {alpha})."
        ),
        &["Function", "α_size", "Budget", "Method"],
    );
    let mut rows: Vec<Pending> = Vec::new();
    let mut keys: Vec<(String, String, Option<u64>)> = Vec::new();
    for ((function, continuity, level, budget), ps) in groups {
        if !level.starts_with("technique") {
            continue;
        }
        let bb_key = (
            function.clone(),
            continuity.clone(),
            "bounding-box".to_owned(),
            *budget,
        );
        let Some(bs) = groups.get(&bb_key) else {
            continue;
        };
        let alpha_size = level
            .strip_prefix("technique, α = ")
            .unwrap_or("0.5")
            .to_owned();
        for (c, cell) in fr.cells.iter().enumerate() {
            let (Some(a), Some(b)) = (pooled(fr, ps, c), pooled(fr, bs, c)) else {
                continue;
            };
            let paired = ps.iter().zip(bs).all(|(&p, &q)| same_seeds(fr, p, q, c));
            if let Some(r) = compare(&a, &b, paired, alpha) {
                let labels = vec![
                    format!("{function}/{continuity}"),
                    alpha_size.clone(),
                    budget.map_or("—".into(), |b| b.to_string()),
                    cell.clone(),
                ];
                keys.push((cell.clone(), alpha_size.clone(), *budget));
                rows.push((labels, r));
            }
        }
    }
    let marks = finish(&mut table, rows, alpha);
    let lines = verdict_lines(&keys, &marks, |(cell, a, _)| {
        format!("{cell}, α_size {a}: the technique against the bounding box")
    });
    (table, lines)
}

/// Every pair of methods (each against every later one, in the report's
/// order), per search space and budget, segments as units.
fn methods_table(fr: &FitRuns<'_>, groups: &BTreeMap<Group, Vec<usize>>, alpha: f64) -> Table {
    let mut table = frame(
        "fit_segments_methods",
        "Methods per segment, in pairs",
        format!(
            "For every search space, budget per segment and pair of methods: the first \
             against the second. {HOW_TO_READ} A ratio below 1 and + mean lower E with the \
             first (marks at α = {alpha})."
        ),
        &["Function", "Search space", "Budget", "Method", "Against"],
    );
    let mut rows: Vec<Pending> = Vec::new();
    for ((function, continuity, level, budget), ps) in groups {
        let units: Vec<Option<UnitRuns>> = (0..fr.cells.len()).map(|c| pooled(fr, ps, c)).collect();
        for (i, a) in units.iter().enumerate() {
            for (j, b) in units.iter().enumerate().skip(i + 1) {
                let (Some(a), Some(b)) = (a, b) else { continue };
                if let Some(row) = compare(a, b, false, alpha) {
                    let labels = vec![
                        format!("{function}/{continuity}"),
                        level.clone(),
                        budget.map_or("—".into(), |b| b.to_string()),
                        fr.cells[i].clone(),
                        fr.cells[j].clone(),
                    ];
                    rows.push((labels, row));
                }
            }
        }
    }
    finish(&mut table, rows, alpha);
    table
}

/// The verdict lines of the methods table: per pair and search space,
/// the budgets at which the first is better, tied and worse.
fn method_verdicts(t: &Table) -> Vec<String> {
    let n = t.md_header.len();
    let keys: Vec<(String, String, Option<u64>)> = t
        .md_rows
        .iter()
        .map(|r| {
            (
                format!("{} against {}", r[3], r[4]),
                r[1].clone(),
                r[2].parse().ok(),
            )
        })
        .collect();
    let marks: Vec<Mark> = t
        .md_rows
        .iter()
        .map(|r| match r[n - 1].as_str() {
            "+" => Mark::Better,
            "−" => Mark::Worse,
            _ => Mark::Same,
        })
        .collect();
    verdict_lines(&keys, &marks, |(pair, level, _)| {
        format!("{pair} ({level})")
    })
}

/// The mark of a row at its budget per segment.
type BudgetMark = (Option<u64>, Mark);

/// One line per (cell, level): at which budgets its rows are better, tied
/// and worse, e.g. "HS against MHS (technique): better at budgets 1000,
/// 3000; tied at 10000; worse at 30000 (of 4)."
fn verdict_lines(
    keys: &[(String, String, Option<u64>)],
    marks: &[Mark],
    name: impl Fn(&(String, String, Option<u64>)) -> String,
) -> Vec<String> {
    let mut by: BTreeMap<(String, String), Vec<BudgetMark>> = BTreeMap::new();
    let mut order: Vec<(String, String)> = Vec::new();
    for (k, &m) in keys.iter().zip(marks) {
        let id = (k.0.clone(), k.1.clone());
        if !order.contains(&id) {
            order.push(id.clone());
        }
        by.entry(id).or_default().push((k.2, m));
    }
    order
        .into_iter()
        .map(|id| {
            let at = &by[&id];
            let list = |want: Mark| -> Vec<String> {
                at.iter()
                    .filter(|(_, m)| *m == want)
                    .map(|(b, _)| b.map_or("—".into(), |b| b.to_string()))
                    .collect()
            };
            let mut parts = Vec::new();
            for (mark, word) in [
                (Mark::Better, "better"),
                (Mark::Same, "tied"),
                (Mark::Worse, "worse"),
            ] {
                let l = list(mark);
                if !l.is_empty() {
                    parts.push(format!(
                        "{word} at budget{} {}",
                        if l.len() == 1 { "" } else { "s" },
                        l.join(", ")
                    ));
                }
            }
            let first = (id.0.clone(), id.1.clone(), None);
            format!(
                "{}: {} (of {} budgets).",
                name(&first),
                parts.join("; "),
                at.len()
            )
        })
        .collect()
}
