//! The tables of the first level, rendered from the computed comparisons:
//! the paper-style comparison table, the tests of each measure, the marks
//! summary and the Friedman ranking.

use std::collections::BTreeMap;

use super::super::data::Dataset;
use super::super::descriptive::{mean_sd, CellStats};
use super::super::format::{csv_opt, csv_real, fixed2, p_value, sci, Table};
use super::super::verdicts::Measure;
use super::friedman::{FriedmanReport, Ranking};
use super::tally::{tally, Tally};
use super::{Comparison, Outcome, Significance, TestKind, BOOTSTRAP_RESAMPLES};

/// A tally in a cell: `b/s/w`, with ` (n both solved)` when there are
/// some.
pub(crate) fn tally_text(t: &Tally) -> String {
    let mut s = format!("{}/{}/{}", t.better, t.same, t.worse);
    if t.both_solved > 0 {
        s.push_str(&format!(" ({} both solved)", t.both_solved));
    }
    s
}

fn outcome_text(o: Option<Outcome>) -> String {
    o.map_or_else(|| "n/a".into(), |o| o.symbol().to_owned())
}

fn outcome_csv(o: Option<Outcome>) -> String {
    o.map_or_else(String::new, |o| o.ascii().to_owned())
}

fn family_text(ds: &Dataset, s: &Significance, alpha: f64) -> String {
    let k = ds.cells.len().saturating_sub(1);
    format!(
        "Holm's step-down correction is applied per problem, over the family of the \
         {k} comparison(s) of the other algorithms with the reference {ref_name} on \
         that problem; a mark is significant when the adjusted p-value is below \
         α = {alpha}. Marks are from the compared algorithm's point of view (lower \
         error is better): + significantly better than the reference, − significantly \
         worse, ≈ no significant difference; \"both solved\" where every run of both \
         reached the success threshold. Marks describe one problem each; verdicts \
         across problems are in the Verdicts section.",
        ref_name = ds.cells[s.reference].name,
    )
}

/// A warning when some signed-rank comparison pairs so few runs m that
/// even the most extreme outcome has a two-sided p-value 2/2ᵐ ≥ α.
fn small_sample_note(s: &Significance, alpha: f64) -> Option<String> {
    let n = s
        .tests
        .iter()
        .filter_map(|r| r.result.as_ref().ok())
        .filter(|r| r.kind == TestKind::SignedRank)
        .map(|r| r.n1)
        .min()?;
    let smallest = crate::stats::smallest_signed_rank_p(n);
    if smallest < alpha {
        return None;
    }
    let mut needed = 1usize;
    while crate::stats::smallest_signed_rank_p(needed) >= alpha && needed < 64 {
        needed += 1;
    }
    Some(format!(
        "Some paired comparisons have only {n} pairs: the smallest two-sided p-value the \
         signed-rank test can then give is 2/2^{n} = {}, not below α = {alpha}, so they \
         cannot be significant whatever the data (at least {needed} pairs are needed, \
         more after Holm's correction).",
        p_value(smallest)
    ))
}

/// How the pairing was decided, and how many comparisons used each test.
fn design_text(rows: &[Comparison]) -> String {
    let count = |k: TestKind| {
        rows.iter()
            .filter(|r| r.result.as_ref().is_ok_and(|t| t.kind == k))
            .count()
    };
    format!(
        "Each comparison uses the test its design allows: the Wilcoxon signed-rank test \
         where the two algorithms' runs share their seeds run by run (common random \
         numbers: paired by design), else the Mann–Whitney U test on independent samples. \
         Here {} comparison(s) are paired and {} unpaired. Mann–Whitney is used, not \
         Brunner–Munzel, also where the spreads differ: it then tests stochastic order \
         (A₁₂ ≠ 0.5), not a shift of location.",
        count(TestKind::SignedRank),
        count(TestKind::MannWhitney)
    )
}

/// The paper-style table: mean (sd) of each algorithm per problem, with the
/// first-level mark against the reference and a +/≈/− row.
pub(crate) fn comparison_table(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    s: &Significance,
    alpha: f64,
) -> Table {
    let reference = s.reference;
    let mut md_header = vec!["Problem".to_owned(), "D".to_owned()];
    for (c, cell) in ds.cells.iter().enumerate() {
        md_header.push(if c == reference {
            format!("{} (reference)", cell.name)
        } else {
            cell.name.clone()
        });
    }
    let mut t = Table {
        stem: "comparison".into(),
        title: format!(
            "Mean final error (standard deviation) with marks against {}",
            ds.cells[reference].name
        ),
        intro: vec![
            format!(
                "Each entry is the mean (sample standard deviation) of the final error {} \
                 over the runs, followed by the mark of the first-level test against the \
                 reference (next section).",
                ds.error_symbol()
            ),
            family_text(ds, s, alpha),
        ],
        md_header,
        csv_header: [
            "problem",
            "dim",
            "algorithm",
            "kind",
            "params",
            "mean",
            "sd",
            "test",
            "mark",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    let mut by: BTreeMap<(usize, usize), &Comparison> = BTreeMap::new();
    for row in &s.tests {
        by.insert((row.problem, row.cell), row);
    }
    for (p, problem) in ds.problems.iter().enumerate() {
        let mut md = vec![problem.short(), problem.dim.to_string()];
        for (c, cell) in ds.cells.iter().enumerate() {
            let st = stats.get(p).and_then(|r| r.get(c)).and_then(|x| x.as_ref());
            let row = by.get(&(p, c));
            let outcome = row.and_then(|r| r.outcome);
            let mut entry = mean_sd(st);
            if st.is_some() && c != reference {
                entry.push(' ');
                entry.push_str(&outcome_text(outcome));
            }
            md.push(entry);
            if let Some(st) = st {
                let sm = st.summary.as_ref();
                t.csv_rows.push(vec![
                    problem.label(),
                    problem.dim.to_string(),
                    cell.label.clone(),
                    cell.kind.clone(),
                    cell.params.clone(),
                    csv_opt(sm.map(|x| x.mean)),
                    csv_opt(sm.and_then(|x| x.std_dev)),
                    row.and_then(|r| r.result.as_ref().ok())
                        .map_or(String::new(), |t| t.kind.name().into()),
                    if c == reference {
                        "reference".into()
                    } else {
                        outcome_csv(outcome)
                    },
                ]);
            }
        }
        t.md_rows.push(md);
    }
    let tallies = tally(&s.tests, ds.cells.len());
    let mut last = vec!["+/≈/−".to_owned(), String::new()];
    for (c, tl) in tallies.iter().enumerate() {
        last.push(if c == reference {
            "\u{2014}".into()
        } else {
            tally_text(tl)
        });
    }
    t.md_rows.push(last);
    t
}

/// A real in a Markdown cell, `—` when absent or NaN.
fn md_real(x: Option<f64>) -> String {
    match x {
        Some(v) if !v.is_nan() => sci(v),
        _ => "\u{2014}".into(),
    }
}

/// The table of first-level tests of one measure: one row per comparison,
/// with its test, p-values, mark and effect sizes.
pub(crate) fn tests_table(ds: &Dataset, s: &Significance, measure: Measure, alpha: f64) -> Table {
    let (stem, title, rows, effect, effect_md) = match measure {
        Measure::FinalError => (
            "tests",
            "Tests of the final error on every problem",
            &s.tests,
            "median_ratio",
            "Median ratio [95 % CI]",
        ),
        Measure::AnytimeAuc => (
            "anytime_tests",
            "Tests of the anytime measure on every problem",
            &s.anytime,
            "median_difference",
            "Median AUC difference [95 % CI]",
        ),
    };
    let reference = &ds.cells[s.reference];
    let mut t = Table {
        stem: stem.into(),
        title: format!("{title} against {}", reference.name),
        intro: tests_intro(ds, s, rows, measure, alpha),
        md_header: tests_md_header(effect_md),
        csv_header: tests_csv_header(effect),
        ..Table::default()
    };
    for row in rows {
        let (md, csv) = test_row(ds, &reference.label, row);
        t.md_rows.push(md);
        t.csv_rows.push(csv);
    }
    t
}

/// The paragraphs of a tests table: the design, the effect sizes of the
/// measure, the correction and, for the final error, the small-sample
/// warning.
fn tests_intro(
    ds: &Dataset,
    s: &Significance,
    rows: &[Comparison],
    measure: Measure,
    alpha: f64,
) -> Vec<String> {
    let mut intro = vec![
        design_text(rows),
        match measure {
            Measure::FinalError => format!(
                "A₁₂ = P(A > R) + ½P(A = R) over the final errors (Vargha & Delaney 2000; \
                 below 0.5 the algorithm tends to the lower error); the median ratio is \
                 median(A)/median(R) with both medians floored at {} (the success threshold), \
                 with its 95 % percentile bootstrap interval ({BOOTSTRAP_RESAMPLES} resamples, \
                 seeded from the row's names, so the report is reproducible).",
                sci(s.floor)
            ),
            Measure::AnytimeAuc => format!(
                "The anytime measure of a run is the area under its ECDF of the 51 targets \
                 over log10(evaluations / D), from D evaluations to the smaller budget of the \
                 two compared, normalised to [0, 1] (higher is better; aRT pools the runs, so \
                 it is not a per-run measure). A₁₂ = P(A > R) + ½P(A = R) over the areas \
                 (above 0.5 the algorithm tends to the larger area); the difference of the \
                 median areas has its 95 % percentile bootstrap interval \
                 ({BOOTSTRAP_RESAMPLES} resamples)."
            ),
        },
        family_text(ds, s, alpha),
    ];
    if measure == Measure::FinalError {
        intro.extend(small_sample_note(s, alpha));
    }
    intro
}

/// The Markdown header of a tests table; `effect` names the effect column.
fn tests_md_header(effect: &str) -> Vec<String> {
    [
        "Problem",
        "D",
        "Algorithm",
        "Test",
        "n₁/n₂",
        "p",
        "p (Holm)",
        "Mark",
        "A₁₂",
        effect,
    ]
    .map(String::from)
    .to_vec()
}

/// The CSV header of a tests table; `effect` names the effect column.
fn tests_csv_header(effect: &str) -> Vec<String> {
    [
        "problem",
        "dim",
        "algorithm",
        "kind",
        "params",
        "reference",
        "test",
        "n1",
        "n2",
        "statistic",
        "z",
        "method",
        "p_value",
        "p_holm",
        "mark",
        "a12",
        effect,
        "ci_low",
        "ci_high",
        "note",
    ]
    .map(String::from)
    .to_vec()
}

/// The Markdown and CSV rows of one comparison against the reference
/// labelled `reference`.
fn test_row(ds: &Dataset, reference: &str, row: &Comparison) -> (Vec<String>, Vec<String>) {
    let problem = &ds.problems[row.problem];
    let cell = &ds.cells[row.cell];
    let ci_md = match row.ci {
        Some(ci) => format!("{} [{}, {}]", sci(row.effect), sci(ci.low), sci(ci.high)),
        None => md_real(Some(row.effect)),
    };
    let mut md = vec![problem.short(), problem.dim.to_string(), cell.name.clone()];
    let mut csv = vec![
        problem.label(),
        problem.dim.to_string(),
        cell.label.clone(),
        cell.kind.clone(),
        cell.params.clone(),
        reference.to_owned(),
    ];
    match &row.result {
        Ok(r) => {
            md.extend([
                r.kind.name().to_owned(),
                format!("{}/{}", r.n1, r.n2),
                p_value(r.p_value),
                row.p_holm.map_or_else(|| "n/a".into(), p_value),
                outcome_text(row.outcome),
            ]);
            csv.extend([
                r.kind.name().to_owned(),
                r.n1.to_string(),
                r.n2.to_string(),
                csv_real(r.statistic),
                csv_opt(r.z),
                r.method.to_string(),
                csv_real(r.p_value),
                csv_opt(row.p_holm),
                outcome_csv(row.outcome),
            ]);
        }
        Err(e) => {
            md.extend(std::iter::repeat_n("\u{2014}".to_owned(), 4));
            md.push(format!("n/a ({e})"));
            csv.extend(std::iter::repeat_n(String::new(), 9));
        }
    }
    md.extend([md_real(row.a12), ci_md]);
    csv.extend([
        csv_opt(row.a12),
        csv_real(row.effect),
        csv_opt(row.ci.map(|c| c.low)),
        csv_opt(row.ci.map(|c| c.high)),
        row.result
            .as_ref()
            .err()
            .map_or(String::new(), |e| e.to_string()),
    ]);
    (md, csv)
}

/// Win/tie/loss counts of the first-level tests per algorithm and measure.
pub(crate) fn marks_summary_table(ds: &Dataset, s: &Significance) -> Table {
    let mut t = Table {
        stem: "marks_summary".into(),
        title: format!(
            "Problems better, tied and worse against {}",
            ds.cells[s.reference].name
        ),
        intro: vec![
            "Number of problems on which each algorithm's first-level mark is + \
             (significantly better), ≈ or − (significantly worse) after Holm's correction, \
             written +/≈/−, and where both solved every run. These counts describe the \
             problems; they are not a test across problems (see the Verdicts section)."
                .into(),
        ],
        md_header: ["Algorithm", "Final error +/≈/−", "Anytime +/≈/−"]
            .map(String::from)
            .to_vec(),
        csv_header: [
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
    let e = tally(&s.tests, ds.cells.len());
    let a = tally(&s.anytime, ds.cells.len());
    for (c, cell) in ds.cells.iter().enumerate() {
        if c == s.reference {
            continue;
        }
        t.md_rows.push(vec![
            cell.name.clone(),
            tally_text(&e[c]),
            if a[c].total() == 0 {
                "\u{2014}".into()
            } else {
                tally_text(&a[c])
            },
        ]);
        for (measure, tl) in [(Measure::FinalError, &e[c]), (Measure::AnytimeAuc, &a[c])] {
            if tl.total() == 0 && measure == Measure::AnytimeAuc {
                continue;
            }
            t.csv_rows.push(vec![
                cell.label.clone(),
                cell.kind.clone(),
                cell.params.clone(),
                measure.name().into(),
                tl.better.to_string(),
                tl.same.to_string(),
                tl.worse.to_string(),
                tl.both_solved.to_string(),
            ]);
        }
    }
    t
}

/// The empty average-rank table, with its headers.
fn friedman_table_frame() -> Table {
    Table {
        stem: "friedman".into(),
        title: "Friedman test and average ranks over the units".into(),
        md_header: [
            "Rank",
            "Algorithm",
            "Average rank",
            "Rank − best",
            "Differs from best (Nemenyi)",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "position",
            "algorithm",
            "kind",
            "params",
            "average_rank",
            "difference_to_best",
            "differs_from_best",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// The paragraphs on the blocks: which units they are.
fn blocks_intro(f: &FriedmanReport) -> Vec<String> {
    let noun = f.noun;
    vec![format!(
        "Blocks are the {} {noun}(s) on which every algorithm has a final error ({}); the \
         value of an algorithm on a {noun} is the median over the {noun}'s problems of log10 \
         of its median final error (floored at the success threshold), ranked within the \
         {noun} (rank 1 = lowest error, ties share the average rank). Instances and \
         other levels of a {noun} are not counted as blocks of their own. The post-hoc \
         tests against the reference are in the Verdicts section (friedman-holm rows).",
        f.blocks.len(),
        if f.blocks.is_empty() {
            "none".to_owned()
        } else {
            f.blocks.join("; ")
        }
    )]
}

/// The paragraphs on the test: its statistic, the critical difference and
/// a warning when there is a single block.
fn ranking_intro(r: &Ranking, alpha: f64) -> Vec<String> {
    let fr = &r.test;
    let mut intro = vec![format!(
        "Friedman χ²_F = {:.4} with {} degree(s) of freedom, p = {} (k = {} algorithms, N \
         = {} blocks).",
        fr.statistic,
        fr.df,
        p_value(fr.p_value),
        fr.n_treatments,
        fr.n_blocks
    )];
    intro.push(match &r.cd {
        Ok(cd) => format!(
            "Nemenyi critical difference at α = {alpha}: CD = {cd:.3}; two algorithms \
             whose average ranks differ by at least CD differ significantly (Demšar \
             2006)."
        ),
        Err(e) => format!("The Nemenyi critical difference is not available: {e}."),
    });
    if fr.n_blocks < 2 {
        intro.push(
            "With a single block the Friedman test has no power; the ranks only order \
             the algorithms on that unit."
                .into(),
        );
    }
    intro
}

/// The rows of the algorithms by average rank, each compared with the best
/// by the critical difference.
fn ranking_rows(ds: &Dataset, r: &Ranking, t: &mut Table) {
    let ranks = &r.test.average_ranks;
    let mut order: Vec<usize> = (0..ranks.len()).collect();
    order.sort_by(|&a, &b| ranks[a].total_cmp(&ranks[b]).then(a.cmp(&b)));
    let best = order.first().map_or(f64::NAN, |&i| ranks[i]);
    for (pos, &c) in order.iter().enumerate() {
        let Some(cell) = ds.cells.get(c) else {
            continue;
        };
        let rank = ranks[c];
        let diff = rank - best;
        let differs = match &r.cd {
            Ok(cd) if pos > 0 => Some(diff >= *cd),
            Ok(_) | Err(_) => None,
        };
        t.md_rows.push(vec![
            (pos + 1).to_string(),
            cell.name.clone(),
            fixed2(rank),
            fixed2(diff),
            match (pos, differs) {
                (0, _) => "best".into(),
                (_, Some(true)) => "yes".into(),
                (_, Some(false)) => "no".into(),
                (_, None) => "n/a".into(),
            },
        ]);
        t.csv_rows.push(vec![
            (pos + 1).to_string(),
            cell.label.clone(),
            cell.kind.clone(),
            cell.params.clone(),
            csv_real(rank),
            csv_real(diff),
            differs.map_or_else(String::new, |d| d.to_string()),
        ]);
    }
}

/// The average-rank table of the Friedman test.
pub(crate) fn friedman_table(ds: &Dataset, f: &FriedmanReport, alpha: f64) -> Table {
    let mut t = friedman_table_frame();
    t.intro = blocks_intro(f);
    match &f.ranking {
        Ok(r) => {
            t.intro.extend(ranking_intro(r, alpha));
            ranking_rows(ds, r, &mut t);
        }
        Err(e) => t
            .intro
            .push(format!("The Friedman test is not available: {e}.")),
    }
    t
}
