//! Where a verdict holds: the verdicts of every algorithm against the
//! reference at each design point and at each level of each factor, read
//! from [`super::verdicts`], beside the first-level marks they summarise.
//!
//! The marks (+/≈/− per problem, Holm-corrected per problem) describe the
//! problems of a design point; they are counts, not a test. Each verdict is
//! the test across the independent units of that scope (see
//! [`super::design`]): `better` or `worse` only where the Holm-corrected
//! Wilcoxon signed-rank test of the per-unit summaries rejects.

use std::collections::BTreeMap;

use crate::stats::{Verdict, VerdictRow};

use super::data::Dataset;
use super::data::Problem;
use super::design::{design_points, factor_name, Levels};
use super::format::{p_value, sci, Table};
use super::significance::{tally_text, Comparison, Significance, Tally};
use super::verdicts::{find, short, Measure};

/// The first-level tallies per (design point, cell, measure).
type Counts = BTreeMap<(usize, usize, Measure), Tally>;

/// The first-level tallies per (design point, cell, measure), the design
/// points in order.
fn counts(ds: &Dataset, s: &Significance) -> (Vec<Levels>, Counts) {
    let points = design_points(ds);
    let mut order: Vec<Levels> = points.clone();
    order.sort();
    order.dedup();
    let index: BTreeMap<&Levels, usize> = order.iter().enumerate().map(|(i, d)| (d, i)).collect();
    let mut out: Counts = BTreeMap::new();
    let mut add = |rows: &[Comparison], measure: Measure| {
        for row in rows {
            if let Some(o) = row.outcome {
                let d = index[&points[row.problem]];
                out.entry((d, row.cell, measure)).or_default().add(o);
            }
        }
    };
    add(&s.tests, Measure::FinalError);
    add(&s.anytime, Measure::AnytimeAuc);
    (order, out)
}

/// The compared cells, in order.
fn compared(ds: &Dataset, s: &Significance) -> Vec<usize> {
    (0..ds.cells.len()).filter(|&c| c != s.reference).collect()
}

/// A list of scope labels, at most four named.
fn named(list: &[String]) -> String {
    if list.len() > 4 {
        format!("{} and {} more", list[..4].join("; "), list.len() - 4)
    } else {
        list.join("; ")
    }
}

/// One line per compared algorithm and measure: its verdict over all
/// units, and at how many design points it is better, worse and not
/// detectably different, naming where.
fn verdict_lines(
    ds: &Dataset,
    s: &Significance,
    points: &[Levels],
    rows: &[VerdictRow],
    noun: &str,
) -> Vec<String> {
    let reference = &ds.cells[s.reference].name;
    let mut out = Vec::new();
    for measure in [Measure::FinalError, Measure::AnytimeAuc] {
        for c in compared(ds, s) {
            let name = &ds.cells[c].name;
            let Some(all) = find(rows, "reference", measure, name, reference, "all") else {
                continue;
            };
            let mut line = format!(
                "{name} against {reference}, {}: {} over all {} {noun}s ({}/{}/{} {noun}s, \
                 p = {}, p_Holm = {} in a family of {}, p_min = {}; {} {})",
                measure.name(),
                all.verdict,
                all.across.units,
                all.across.better,
                all.across.equal,
                all.across.worse,
                p_value(all.across.p_value),
                p_value(all.p_adjusted),
                all.family,
                p_value(all.across.p_min),
                measure.effect_text(),
                sci(all.across.effect_size)
            );
            if points.len() > 1 {
                let at: Vec<(String, Verdict)> = points
                    .iter()
                    .filter_map(|p| {
                        find(rows, "reference", measure, name, reference, &p.scope())
                            .map(|r| (p.label(), r.verdict))
                    })
                    .collect();
                let of = |v: Verdict| -> Vec<String> {
                    at.iter()
                        .filter(|(_, x)| *x == v)
                        .map(|(l, _)| l.clone())
                        .collect()
                };
                let parts: Vec<String> = [
                    Verdict::Better,
                    Verdict::Worse,
                    Verdict::Equivalent,
                    Verdict::Undecided,
                ]
                .into_iter()
                .filter_map(|v| {
                    let l = of(v);
                    (!l.is_empty()).then(|| format!("{v} at {} ({})", l.len(), named(&l)))
                })
                .collect();
                line.push_str(&format!(
                    "; of {} design points: {}",
                    at.len(),
                    parts.join("; ")
                ));
            }
            line.push('.');
            out.push(line);
        }
    }
    out
}

/// A table cell: the marks and, when there is one, the verdict.
fn cell_text(k: Option<&Tally>, v: Option<&VerdictRow>) -> String {
    match (k, v) {
        (None, None) => "\u{2014}".into(),
        (Some(k), None) => format!("marks {}", tally_text(k)),
        (None, Some(v)) => short(v),
        (Some(k), Some(v)) => format!("marks {}; {}", tally_text(k), short(v)),
    }
}

/// The most verdict lines the design-point table's introduction shows.
const MAX_VERDICT_LINES: usize = 8;

/// The robustness tables: the marks and verdicts at each design point (the
/// verdict lines as the table's introduction), and per factor level.
pub(crate) fn tables(
    ds: &Dataset,
    s: &Significance,
    rows: &[VerdictRow],
    noun: &str,
    budget_note: Option<String>,
) -> Vec<Table> {
    let (points, counts) = counts(ds, s);
    let cells = compared(ds, s);
    let reference = &ds.cells[s.reference].name;
    let factor_keys: Vec<&'static str> = points
        .first()
        .map(|d| d.0.iter().map(|(f, _)| *f).collect())
        .unwrap_or_default();
    let mut intro = vec![format!(
        "The verdict of each algorithm against {reference} at each design point (a \
         combination of the factors that vary in these results other than the algorithm, \
         the function and the run), from the test across the independent {noun}s there: \
         better/worse only where the Holm-corrected Wilcoxon signed-rank test of the \
         per-{noun} summaries rejects, with the {noun}s better/equal/worse and the adjusted \
         p beside it. \"marks\" count the first-level marks of the problems at the design \
         point (+/≈/−, each benchmark instance or fitting case one problem): they describe \
         the problems, they are not a test. The final error is shown here; the anytime \
         measure's verdicts are in tables/verdicts.csv."
    )];
    let lines = verdict_lines(ds, s, &points, rows, noun);
    let total = lines.len();
    intro.extend(lines.into_iter().take(MAX_VERDICT_LINES));
    if total > MAX_VERDICT_LINES {
        intro.push(format!(
            "The first {MAX_VERDICT_LINES} of {total} such verdict lines; every verdict is in \
             tables/verdicts.csv."
        ));
    }
    intro.extend(budget_note);
    let mut by_point = Table {
        stem: "robustness".into(),
        title: format!("Design points against {reference}"),
        intro,
        md_header: std::iter::once("Design point".to_string())
            .chain(cells.iter().map(|&c| ds.cells[c].name.clone()))
            .collect(),
        csv_header: factor_keys
            .iter()
            .map(|f| f.to_string())
            .chain(
                [
                    "algorithm",
                    "kind",
                    "params",
                    "measure",
                    "better",
                    "same",
                    "worse",
                    "both_solved",
                ]
                .map(String::from),
            )
            .collect(),
        ..Table::default()
    };
    let single = points.len() == 1;
    for (d, point) in points.iter().enumerate() {
        let scope = if single {
            "all".to_owned()
        } else {
            point.scope()
        };
        let mut md = vec![point.label()];
        for &c in &cells {
            let name = &ds.cells[c].name;
            let k = counts.get(&(d, c, Measure::FinalError));
            let v = find(
                rows,
                "reference",
                Measure::FinalError,
                name,
                reference,
                &scope,
            );
            md.push(cell_text(k, v));
            for measure in [Measure::FinalError, Measure::AnytimeAuc] {
                let Some(k) = counts.get(&(d, c, measure)) else {
                    continue;
                };
                let mut row: Vec<String> = point.0.iter().map(|(_, l)| l.to_string()).collect();
                let cell = &ds.cells[c];
                row.extend([
                    cell.label.clone(),
                    cell.kind.clone(),
                    cell.params.clone(),
                    measure.name().into(),
                    k.better.to_string(),
                    k.same.to_string(),
                    k.worse.to_string(),
                    k.both_solved.to_string(),
                ]);
                by_point.csv_rows.push(row);
            }
        }
        by_point.md_rows.push(md);
    }
    vec![
        by_point,
        by_level(ds, &cells, &points, &counts, rows, reference),
    ]
}

/// The marks summed over the design points at each level of each factor,
/// with the verdict of that level.
fn by_level(
    ds: &Dataset,
    cells: &[usize],
    points: &[Levels],
    counts: &Counts,
    rows: &[VerdictRow],
    reference: &str,
) -> Table {
    let mut t = Table {
        stem: "robustness_levels".into(),
        title: format!("Marks and verdicts per factor level against {reference}"),
        intro: vec![
            "The first-level marks of the problems that share a level of one factor, summed \
             (+/≈/−), and the verdict of the test across the units at that level."
                .into(),
        ],
        md_header: ["Factor", "Level"]
            .map(String::from)
            .into_iter()
            .chain(cells.iter().map(|&c| ds.cells[c].name.clone()))
            .collect(),
        csv_header: [
            "factor",
            "level",
            "algorithm",
            "kind",
            "params",
            "measure",
            "better",
            "same",
            "worse",
            "both_solved",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    let mut levels: BTreeMap<(&'static str, super::design::Level), Vec<usize>> = BTreeMap::new();
    for (d, p) in points.iter().enumerate() {
        for (f, l) in &p.0 {
            levels.entry((f, l.clone())).or_default().push(d);
        }
    }
    for ((factor, level), at) in &levels {
        let scope = Levels(vec![(factor, level.clone())]).scope();
        let mut md = vec![factor_name(factor).to_string(), level.to_string()];
        for &c in cells {
            let name = &ds.cells[c].name;
            for measure in [Measure::FinalError, Measure::AnytimeAuc] {
                let mut sum = Tally::default();
                let mut any = false;
                for d in at {
                    if let Some(k) = counts.get(&(*d, c, measure)) {
                        sum.merge(k);
                        any = true;
                    }
                }
                if measure == Measure::FinalError {
                    let v = find(rows, "reference", measure, name, reference, &scope);
                    md.push(cell_text(any.then_some(&sum), v));
                }
                if !any {
                    continue;
                }
                let cell = &ds.cells[c];
                t.csv_rows.push(vec![
                    factor.to_string(),
                    level.to_string(),
                    cell.label.clone(),
                    cell.kind.clone(),
                    cell.params.clone(),
                    measure.name().into(),
                    sum.better.to_string(),
                    sum.same.to_string(),
                    sum.worse.to_string(),
                    sum.both_solved.to_string(),
                ]);
            }
        }
        t.md_rows.push(md);
    }
    if t.md_rows.is_empty() {
        t.intro
            .push("No factor varies in these results: there is one design point.".into());
    }
    t
}

/// Whether two reals agree to rounding (the trace stores best − f*, the
/// run's row the error itself).
fn same_value(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

/// Where budgets are paired (`paired = ["budget"]`), whether each
/// algorithm's shorter run is the prefix of its longer twin: the longer
/// run's best-so-far at the shorter budget (from its trace) equals the
/// shorter run's final error. Algorithms whose schedules depend on the
/// budget (GA, PSO and GHS rates, a bandwidth decay) are not prefixes, so a
/// comparison of their budgets is not a prefix comparison; the note says
/// so, with the pairs in which the longer run ends worse.
pub(crate) fn budget_pairs_note(ds: &Dataset, paired: &[String]) -> Option<String> {
    if !paired.iter().any(|p| p == "budget") || !ds.has_convergence {
        return None;
    }
    // Problems that differ only in their budget.
    let mut twins: BTreeMap<Problem, Vec<usize>> = BTreeMap::new();
    for (p, problem) in ds.problems.iter().enumerate() {
        if problem.budget.is_some() {
            let key = Problem {
                budget: None,
                ..problem.clone()
            };
            twins.entry(key).or_default().push(p);
        }
    }
    let mut prefix_cells = Vec::new();
    let mut other = Vec::new();
    for (c, cell) in ds.cells.iter().enumerate() {
        let (mut pairs, mut prefixes, mut worse) = (0usize, 0usize, 0usize);
        for ps in twins.values() {
            for &p in ps {
                for &q in ps {
                    let (Some(bp), Some(bq)) = (ds.problems[p].budget, ds.problems[q].budget)
                    else {
                        continue;
                    };
                    if bp >= bq {
                        continue;
                    }
                    for short in ds.runs(p, c) {
                        let Some(long) = ds
                            .runs(q, c)
                            .iter()
                            .find(|l| l.run == short.run && l.seed == short.seed)
                        else {
                            continue;
                        };
                        let Some(&(_, at)) = long.trace.iter().find(|(e, _)| *e == bp) else {
                            continue;
                        };
                        pairs += 1;
                        prefixes += usize::from(same_value(at, short.error));
                        worse += usize::from(
                            long.error > short.error && !same_value(long.error, short.error),
                        );
                    }
                }
            }
        }
        if pairs == 0 {
            continue;
        }
        if prefixes == pairs {
            prefix_cells.push(cell.name.clone());
        } else {
            other.push(format!(
                "{} ({} of {pairs} pairs are prefixes; in {worse} the longer run ends worse \
                 than its shorter twin)",
                cell.name, prefixes
            ));
        }
    }
    if prefix_cells.is_empty() && other.is_empty() {
        return None;
    }
    let mut text = String::from(
        "Budgets are paired in this campaign (common random numbers): a run at a smaller \
         budget shares its seed with its twin at a larger one. ",
    );
    if !prefix_cells.is_empty() {
        text.push_str(&format!(
            "For {} the shorter run is the prefix of the longer in every pair, so budgets \
             compare the same runs stopped earlier. ",
            prefix_cells.join(", ")
        ));
    }
    if !other.is_empty() {
        text.push_str(&format!(
            "For {} it is not: their schedules depend on the budget, so their runs at \
             different budgets are different runs that share a seed, not prefixes.",
            other.join("; ")
        ));
    }
    Some(text.trim_end().to_owned())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Dataset;
    use crate::experiment::RunRecord;
    use crate::significance::{observations, significance};
    use crate::verdicts::{verdicts, PostHoc, Settings};

    /// Runs of `alg` on `function` at (dim, budget) with errors `base + run`.
    fn runs(
        alg: &str,
        function: &str,
        dim: usize,
        budget: u64,
        base: f64,
    ) -> Vec<(RunRecord, bool)> {
        (0..8)
            .map(|run| {
                let error = base + f64::from(run) * 1e-3;
                (
                    RunRecord {
                        kind: alg.to_lowercase(),
                        dim,
                        budget,
                        seed: u64::from(run) + if alg == "A" { 0 } else { 1000 },
                        evaluations: budget,
                        ..crate::test_records::record(alg, function, run, error)
                    },
                    false,
                )
            })
            .collect()
    }

    fn report(records: Vec<(RunRecord, bool)>) -> (Dataset, Vec<Table>, Vec<VerdictRow>) {
        let ds = Dataset::from_records(records);
        let s = significance(&ds, 0, 0.05, None);
        let (obs, standings) = observations(&ds, &s);
        let rows = verdicts(
            &obs,
            &standings,
            Settings {
                alpha: 0.05,
                post_hoc: PostHoc::Holm,
                reference: Some("A"),
                ropes: crate::verdicts::Ropes::default(),
            },
        );
        let t = tables(&ds, &s, &rows, "function", None);
        (ds, t, rows)
    }

    #[test]
    fn a_flip_with_the_budget_is_shown_with_marks_but_not_claimed_on_two_functions() {
        // B beats A on both functions at budget 1000, loses on both at
        // 10000: every mark is decided, but two functions cannot make a
        // verdict (p_min = 0.5).
        let mut records = Vec::new();
        for f in ["sphere", "ackley"] {
            records.extend(runs("A", f, 10, 1000, 1.0));
            records.extend(runs("B", f, 10, 1000, 0.5));
            records.extend(runs("A", f, 10, 10000, 0.1));
            records.extend(runs("B", f, 10, 10000, 0.2));
        }
        let (ds, t, rows) = report(records);
        assert_eq!(ds.problems.len(), 4, "{:?}", ds.problems);
        assert_eq!(t[0].md_rows[0][0], "budget 1000");
        assert!(
            t[0].md_rows[0][1].starts_with("marks 2/0/0; undecided (2/0/0"),
            "{}",
            t[0].md_rows[0][1]
        );
        assert!(t[0].md_rows[1][1].starts_with("marks 0/0/2; undecided (0/0/2"));
        let scopes: Vec<&str> = rows.iter().map(|r| r.scope.as_str()).collect();
        assert_eq!(scopes, ["all", "budget=1000", "budget=10000"]);
        assert!(rows.iter().all(|r| r.across.p_min == 0.5));
        assert!(
            t[0].intro[1].starts_with("B against A, final-error: undecided over all 2 functions"),
            "{}",
            t[0].intro[1]
        );
        assert_eq!(t[1].md_rows[0][0], "budget");
    }

    #[test]
    fn one_design_point_when_nothing_varies() {
        let mut records = runs("A", "sphere", 10, 1000, 1.0);
        records.extend(runs("B", "sphere", 10, 1000, 1.0));
        let (_, t, _) = report(records);
        assert_eq!(t[0].md_rows.len(), 1);
        assert_eq!(t[0].md_rows[0][0], "all problems");
        assert!(t[0].md_rows[0][1].starts_with("marks 0/1/0; undecided"));
        assert!(t[1].md_rows.is_empty());
    }
}
