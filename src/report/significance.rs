//! Significance of the differences in final error: Wilcoxon signed-rank and
//! Mann–Whitney U tests of every algorithm against a reference on every
//! problem (Holm-corrected per problem), "+ / ≈ / −" marks and their tallies,
//! and the Friedman test over problems with the Nemenyi critical difference.

use std::collections::BTreeMap;

use crate::stats::{
    friedman, holm_bonferroni, mann_whitney_u, nemenyi_critical_difference, wilcoxon, Alternative,
    FriedmanResult, MannWhitneyResult, Mark, MarkTally, StatsError, WilcoxonResult,
};

use super::data::Dataset;
use super::descriptive::{mean_error, mean_sd, CellStats};
use super::format::{csv_opt, csv_real, fixed2, p_value, Table};

/// Why a test of a cell against the reference has no result; the text is
/// shown in the test tables.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum NoTest {
    /// The paired test found no run number that both cells ran.
    #[error("no run number in common with the reference")]
    NoCommonRun,
    /// The test rejected its samples.
    #[error(transparent)]
    Test(#[from] StatsError),
    /// Holm's correction of the problem's family failed.
    #[error("Holm correction failed: {0}")]
    Holm(#[source] StatsError),
}

/// One test of a cell against the reference on a problem.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Comparison<R> {
    /// Problem index.
    pub problem: usize,
    /// Compared cell index.
    pub cell: usize,
    /// The test result, or why it could not be computed.
    pub result: Result<R, NoTest>,
    /// Holm-adjusted p-value within the problem's family.
    pub p_holm: Option<f64>,
    /// The mark from the compared cell's point of view at the adjusted p.
    pub mark: Option<Mark>,
}

/// The tests against the reference.
#[derive(Clone, Debug)]
pub(crate) struct Significance {
    /// The reference cell.
    pub reference: usize,
    /// Paired Wilcoxon signed-rank tests (pairs by run number).
    pub wilcoxon: Vec<Comparison<WilcoxonResult>>,
    /// Unpaired Mann–Whitney U tests.
    pub mann_whitney: Vec<Comparison<MannWhitneyResult>>,
    /// Problems that the reference did not run.
    pub skipped_problems: Vec<usize>,
}

/// Runs `test` for every (problem, cell ≠ reference) that both ran, then
/// adjusts the p-values with Holm's method within each problem and marks
/// each comparison; `p_and_direction` gives (raw p, signed direction A − R).
fn compare<R>(
    ds: &Dataset,
    reference: usize,
    alpha: f64,
    test: impl Fn(usize, usize) -> Result<R, NoTest>,
    p_and_direction: impl Fn(&R) -> (f64, f64),
) -> (Vec<Comparison<R>>, Vec<usize>) {
    let mut out = Vec::new();
    let mut skipped = Vec::new();
    for p in 0..ds.problems.len() {
        if ds.runs(p, reference).is_empty() {
            skipped.push(p);
            continue;
        }
        let start = out.len();
        for c in 0..ds.cells.len() {
            if c == reference || ds.runs(p, c).is_empty() {
                continue;
            }
            out.push(Comparison {
                problem: p,
                cell: c,
                result: test(p, c),
                p_holm: None,
                mark: None,
            });
        }
        let family: Vec<usize> = (start..out.len())
            .filter(|&i| out[i].result.is_ok())
            .collect();
        let raw: Vec<f64> = family
            .iter()
            .filter_map(|&i| out[i].result.as_ref().ok().map(|r| p_and_direction(r).0))
            .collect();
        match holm_bonferroni(&raw) {
            Ok(adjusted) => {
                for (&i, &ph) in family.iter().zip(&adjusted) {
                    let direction = match &out[i].result {
                        Ok(r) => p_and_direction(r).1,
                        Err(_) => 0.0,
                    };
                    out[i].p_holm = Some(ph);
                    out[i].mark = Some(Mark::from_p_value(ph, alpha, direction));
                }
            }
            Err(e) => {
                for &i in &family {
                    out[i].result = Err(NoTest::Holm(e.clone()));
                }
            }
        }
    }
    (out, skipped)
}

/// Runs both tests of every cell against `reference`.
pub(crate) fn significance(ds: &Dataset, reference: usize, alpha: f64) -> Significance {
    let (wilcoxon_rows, skipped) = compare(
        ds,
        reference,
        alpha,
        |p, c| {
            let by_run: BTreeMap<u32, f64> = ds
                .runs(p, reference)
                .iter()
                .map(|r| (r.run, r.error))
                .collect();
            let (a, r): (Vec<f64>, Vec<f64>) = ds
                .runs(p, c)
                .iter()
                .filter_map(|x| by_run.get(&x.run).map(|&y| (x.error, y)))
                .unzip();
            if a.is_empty() {
                return Err(NoTest::NoCommonRun);
            }
            Ok(wilcoxon(&a, &r, Alternative::TwoSided)?)
        },
        |w| (w.p_value, w.r_plus - w.r_minus),
    );
    let (mw_rows, _) = compare(
        ds,
        reference,
        alpha,
        |p, c| {
            Ok(mann_whitney_u(
                &ds.errors(p, c),
                &ds.errors(p, reference),
                Alternative::TwoSided,
            )?)
        },
        |m| (m.p_value, m.statistic - (m.n1 * m.n2) as f64 / 2.0),
    );
    Significance {
        reference,
        wilcoxon: wilcoxon_rows,
        mann_whitney: mw_rows,
        skipped_problems: skipped,
    }
}

/// Mark counts per cell.
pub(crate) fn tally<R>(rows: &[Comparison<R>], cells: usize) -> Vec<MarkTally> {
    let mut t = vec![MarkTally::default(); cells];
    for row in rows {
        if let (Some(m), Some(slot)) = (row.mark, t.get_mut(row.cell)) {
            slot.add(m);
        }
    }
    t
}

fn mark_text(m: Option<Mark>) -> String {
    m.map_or_else(|| "n/a".into(), |m| m.symbol().to_owned())
}

fn mark_csv(m: Option<Mark>) -> String {
    m.map_or_else(String::new, |m| m.ascii().to_owned())
}

fn tally_text(t: &MarkTally) -> String {
    format!("{}/{}/{}", t.better, t.same, t.worse)
}

fn family_text(ds: &Dataset, s: &Significance, alpha: f64) -> String {
    let k = ds.cells.len().saturating_sub(1);
    format!(
        "Holm's step-down correction is applied per problem, over the family of the \
         {k} comparison(s) of the other algorithms with the reference {ref_name} on \
         that problem; a mark is significant when the adjusted p-value is below \
         α = {alpha}. Marks are from the compared algorithm's point of view (lower \
         error is better): + significantly better than the reference, − significantly \
         worse, ≈ no significant difference.",
        ref_name = ds.cells[s.reference].name,
    )
}

/// A warning when some Wilcoxon comparison pairs so few runs m that even
/// the most extreme outcome has a two-sided p-value 2/2ᵐ ≥ α, so it cannot
/// be significant.
fn small_sample_note(s: &Significance, alpha: f64) -> Option<String> {
    let n = s
        .wilcoxon
        .iter()
        .filter_map(|r| r.result.as_ref().ok())
        .map(|w| w.n + w.n_zero)
        .min()?;
    let smallest = 2f64.powi(1 - n.min(1000) as i32);
    if smallest < alpha {
        return None;
    }
    let mut needed = 1usize;
    while 2f64.powi(1 - needed as i32) >= alpha && needed < 64 {
        needed += 1;
    }
    Some(format!(
        "Some comparisons pair only {n} runs: the smallest two-sided p-value the \
         signed-rank test can then give is 2/2^{n} = {}, not below α = {alpha}, so they \
         cannot be significant whatever the data (at least {needed} runs are needed, \
         more after Holm's correction).",
        super::format::p_value(smallest)
    ))
}

/// The empty paper-style table, with its headers and paragraphs.
fn comparison_frame(ds: &Dataset, s: &Significance, alpha: f64) -> Table {
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
            "Mean final error (standard deviation) with Wilcoxon marks against {}",
            ds.cells[reference].name
        ),
        intro: vec![
            "Each entry is the mean (sample standard deviation) of the final error f − f* \
             over the runs, followed by the mark of the paired Wilcoxon signed-rank test \
             against the reference (see the next section)."
                .into(),
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
            "wilcoxon_mark",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    t.intro.extend(small_sample_note(s, alpha));
    t
}

/// The paper-style table: mean (sd) of each algorithm per problem, with the
/// Wilcoxon mark against the reference and a +/≈/− row.
pub(crate) fn comparison_table(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    s: &Significance,
    alpha: f64,
) -> Table {
    let reference = s.reference;
    let mut t = comparison_frame(ds, s, alpha);
    let mut marks: BTreeMap<(usize, usize), Option<Mark>> = BTreeMap::new();
    for row in &s.wilcoxon {
        marks.insert((row.problem, row.cell), row.mark);
    }
    for (p, problem) in ds.problems.iter().enumerate() {
        let mut md = vec![problem.short(), problem.dim.to_string()];
        for (c, cell) in ds.cells.iter().enumerate() {
            let st = stats.get(p).and_then(|r| r.get(c)).and_then(|x| x.as_ref());
            let mark = marks.get(&(p, c)).copied().flatten();
            let mut entry = mean_sd(st);
            if st.is_some() && c != reference {
                entry.push(' ');
                entry.push_str(&mark_text(mark));
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
                    if c == reference {
                        "reference".into()
                    } else {
                        mark_csv(mark)
                    },
                ]);
            }
        }
        t.md_rows.push(md);
    }
    let tallies = tally(&s.wilcoxon, ds.cells.len());
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

/// The empty Wilcoxon table, with its headers and paragraphs.
fn wilcoxon_frame(ds: &Dataset, s: &Significance, alpha: f64) -> Table {
    let mut t = Table {
        stem: "wilcoxon".into(),
        title: format!(
            "Wilcoxon signed-rank tests against {}",
            ds.cells[s.reference].name
        ),
        intro: vec![
            "Two-sided Wilcoxon signed-rank test on the paired final errors, runs paired \
             by run number (the runs themselves are independent: each cell derives its \
             own seeds, so the pairing is by index, as is usual in metaheuristics \
             papers); zero differences are dropped (n counts the non-zero differences). \
             R+ and R− are the rank sums of the positive and negative differences \
             algorithm − reference; W = min(R+, R−)."
                .into(),
            family_text(ds, s, alpha),
        ],
        md_header: [
            "Problem",
            "D",
            "Algorithm",
            "n",
            "R+",
            "R−",
            "W",
            "p",
            "p (Holm)",
            "Mark",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "dim",
            "algorithm",
            "kind",
            "params",
            "reference",
            "n",
            "n_zero",
            "r_plus",
            "r_minus",
            "statistic",
            "z",
            "method",
            "p_value",
            "p_holm",
            "mark",
            "note",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    t.intro.extend(small_sample_note(s, alpha));
    t
}

/// The Wilcoxon signed-rank table, one row per comparison.
pub(crate) fn wilcoxon_table(ds: &Dataset, s: &Significance, alpha: f64) -> Table {
    let mut t = wilcoxon_frame(ds, s, alpha);
    comparison_rows(
        ds,
        s,
        &s.wilcoxon,
        &mut t,
        |w| {
            vec![
                w.n.to_string(),
                format!("{}", w.r_plus),
                format!("{}", w.r_minus),
                format!("{}", w.statistic),
                p_value(w.p_value),
            ]
        },
        |w| {
            vec![
                w.n.to_string(),
                w.n_zero.to_string(),
                csv_real(w.r_plus),
                csv_real(w.r_minus),
                csv_real(w.statistic),
                csv_opt(w.z),
                w.method.to_string(),
                csv_real(w.p_value),
            ]
        },
    );
    t
}

/// The Mann–Whitney U table, one row per comparison.
pub(crate) fn mann_whitney_table(ds: &Dataset, s: &Significance, alpha: f64) -> Table {
    let mut t = Table {
        stem: "mann_whitney".into(),
        title: format!(
            "Mann–Whitney U tests against {}",
            ds.cells[s.reference].name
        ),
        intro: vec![
            "Two-sided Mann–Whitney U test on the final errors as independent samples \
             (unpaired); U is the statistic of the compared algorithm, so U < n₁n₂/2 \
             means it tends to reach lower errors than the reference."
                .into(),
            family_text(ds, s, alpha),
        ],
        md_header: [
            "Problem",
            "D",
            "Algorithm",
            "n₁",
            "n₂",
            "U",
            "p",
            "p (Holm)",
            "Mark",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "dim",
            "algorithm",
            "kind",
            "params",
            "reference",
            "n1",
            "n2",
            "u",
            "z",
            "method",
            "p_value",
            "p_holm",
            "mark",
            "note",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    comparison_rows(
        ds,
        s,
        &s.mann_whitney,
        &mut t,
        |m| {
            vec![
                m.n1.to_string(),
                m.n2.to_string(),
                format!("{}", m.statistic),
                p_value(m.p_value),
            ]
        },
        |m| {
            vec![
                m.n1.to_string(),
                m.n2.to_string(),
                csv_real(m.statistic),
                csv_opt(m.z),
                m.method.to_string(),
                csv_real(m.p_value),
            ]
        },
    );
    t
}

/// The rows of a test table, one per comparison: the problem and the
/// algorithm, the test's own columns (`md`, `csv`), the Holm-adjusted
/// p-value and the mark. A comparison without a result has dashes in the
/// test's columns and says why in the last one.
fn comparison_rows<R>(
    ds: &Dataset,
    s: &Significance,
    rows: &[Comparison<R>],
    t: &mut Table,
    md: impl Fn(&R) -> Vec<String>,
    csv: impl Fn(&R) -> Vec<String>,
) {
    let reference = &ds.cells[s.reference];
    // Columns besides problem, D, algorithm and the last (mark or note).
    let md_blanks = t.md_header.len() - 4;
    // Columns besides the six leading ones and the note.
    let csv_blanks = t.csv_header.len() - 7;
    for row in rows {
        let problem = &ds.problems[row.problem];
        let cell = &ds.cells[row.cell];
        let mut md_row = vec![problem.short(), problem.dim.to_string(), cell.name.clone()];
        let mut csv_row = vec![
            problem.label(),
            problem.dim.to_string(),
            cell.label.clone(),
            cell.kind.clone(),
            cell.params.clone(),
            reference.label.clone(),
        ];
        match &row.result {
            Ok(r) => {
                md_row.extend(md(r));
                md_row.push(row.p_holm.map_or_else(|| "n/a".into(), p_value));
                md_row.push(mark_text(row.mark));
                csv_row.extend(csv(r));
                csv_row.extend([csv_opt(row.p_holm), mark_csv(row.mark), String::new()]);
            }
            Err(e) => {
                md_row.extend(std::iter::repeat_n("\u{2014}".to_owned(), md_blanks));
                md_row.push(format!("n/a ({e})"));
                csv_row.extend(std::iter::repeat_n(String::new(), csv_blanks));
                csv_row.push(e.to_string());
            }
        }
        t.md_rows.push(md_row);
        t.csv_rows.push(csv_row);
    }
}

/// Win/tie/loss counts of both tests per algorithm.
pub(crate) fn marks_summary_table(ds: &Dataset, s: &Significance) -> Table {
    let w = tally(&s.wilcoxon, ds.cells.len());
    let m = tally(&s.mann_whitney, ds.cells.len());
    let mut t = Table {
        stem: "marks_summary".into(),
        title: format!(
            "Wins, ties and losses against {}",
            ds.cells[s.reference].name
        ),
        intro: vec![
            "Number of problems on which each algorithm is significantly better (+), not \
             significantly different (≈) or significantly worse (−) than the reference, \
             after Holm's correction, written +/≈/−."
                .into(),
        ],
        md_header: ["Algorithm", "Wilcoxon +/≈/−", "Mann–Whitney +/≈/−"]
            .map(String::from)
            .to_vec(),
        csv_header: [
            "algorithm",
            "kind",
            "params",
            "test",
            "better",
            "same",
            "worse",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    for (c, cell) in ds.cells.iter().enumerate() {
        if c == s.reference {
            continue;
        }
        t.md_rows.push(vec![
            cell.name.clone(),
            tally_text(&w[c]),
            tally_text(&m[c]),
        ]);
        for (test, tl) in [("wilcoxon", &w[c]), ("mann_whitney", &m[c])] {
            t.csv_rows.push(vec![
                cell.label.clone(),
                cell.kind.clone(),
                cell.params.clone(),
                test.into(),
                tl.better.to_string(),
                tl.same.to_string(),
                tl.worse.to_string(),
            ]);
        }
    }
    t
}

/// Why there is no Friedman ranking; the text is shown in the report.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum NoRanking {
    /// There is one algorithm only.
    #[error("a single algorithm: there is nothing to rank")]
    SingleAlgorithm,
    /// No problem has a defined mean final error for every algorithm.
    #[error("no problem was run by every algorithm")]
    NoCommonProblem,
    /// The test rejected the blocks.
    #[error(transparent)]
    Test(#[from] StatsError),
}

/// The Friedman test and the Nemenyi critical difference that goes with it.
#[derive(Clone, Debug)]
pub(crate) struct Ranking {
    /// The Friedman test.
    pub test: FriedmanResult,
    /// The critical difference at α, or why it is not available.
    pub cd: Result<f64, StatsError>,
}

/// The Friedman test over problems and the Nemenyi critical difference.
#[derive(Clone, Debug)]
pub(crate) struct FriedmanReport {
    /// The problems used as blocks.
    pub blocks: Vec<usize>,
    /// The test and critical difference, or why there are none.
    pub ranking: Result<Ranking, NoRanking>,
}

/// Friedman test with blocks = problems on which every algorithm has a
/// defined mean final error, values = those means.
pub(crate) fn friedman_report(
    ds: &Dataset,
    stats: &[Vec<Option<CellStats>>],
    alpha: f64,
) -> FriedmanReport {
    let k = ds.cells.len();
    let mut blocks = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for p in 0..ds.problems.len() {
        let row: Option<Vec<f64>> = (0..k)
            .map(|c| mean_error(stats, p, c).filter(|m| !m.is_nan()))
            .collect();
        if let Some(row) = row {
            blocks.push(p);
            rows.push(row);
        }
    }
    let ranking = if k < 2 {
        Err(NoRanking::SingleAlgorithm)
    } else if rows.is_empty() {
        Err(NoRanking::NoCommonProblem)
    } else {
        friedman(&rows)
            .map_err(NoRanking::from)
            .map(|test| Ranking {
                test,
                cd: nemenyi_critical_difference(k, rows.len(), alpha),
            })
    };
    FriedmanReport { blocks, ranking }
}

/// The empty average-rank table, with its headers.
fn friedman_table_frame() -> Table {
    Table {
        stem: "friedman".into(),
        title: "Friedman test and average ranks over problems".into(),
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

/// The paragraphs on the blocks: which problems they are, and how many
/// problems are left out.
fn blocks_intro(ds: &Dataset, f: &FriedmanReport) -> Vec<String> {
    let names: Vec<String> = f.blocks.iter().map(|&p| ds.problems[p].title()).collect();
    let mut intro = vec![format!(
        "Blocks are the {} problem(s) on which every algorithm has a defined mean final \
         error ({}); the value of an algorithm on a block is its mean final error over \
         the runs, ranked within the block (rank 1 = lowest error, ties share the \
         average rank).",
        f.blocks.len(),
        if names.is_empty() {
            "none".to_owned()
        } else {
            names.join("; ")
        }
    )];
    let omitted = ds.problems.len() - f.blocks.len();
    if omitted > 0 && ds.cells.len() >= 2 {
        intro.push(format!(
            "{omitted} problem(s) are left out because some algorithm did not run them or \
             has an undefined mean."
        ));
    }
    intro
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
             the algorithms on that problem."
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
    t.intro = blocks_intro(ds, f);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::RunRecord;
    use crate::report::descriptive::compute;

    fn rec(alg: &str, problem: &str, run: u32, error: f64) -> (RunRecord, bool) {
        (
            RunRecord {
                algorithm: alg.into(),
                kind: "hs".into(),
                params: String::new(),
                problem: problem.into(),
                dim: 2,
                budget: 100,
                transform: crate::functions::Transform::None,
                instance: 1,
                run,
                seed: 0,
                best: error,
                error,
                evaluations: 100,
                evaluations_to_target: None,
                success: false,
                trace: Vec::new(),
                hits: Vec::new(),
                fit: None,
                wall_seconds: 0.0,
            },
            false,
        )
    }

    fn dataset() -> Dataset {
        let mut v = Vec::new();
        for run in 0..10 {
            let x = f64::from(run);
            // On "a": A always better than R, B always worse, C equal.
            v.push(rec("R", "a", run, 1.0 + x));
            v.push(rec("A", "a", run, 0.5 + x * 0.9));
            v.push(rec("B", "a", run, 2.0 + x * 1.1));
            v.push(rec("C", "a", run, 1.0 + x));
            // On "b": no clear difference.
            v.push(rec(
                "R",
                "b",
                run,
                [3., 1., 4., 1., 5., 9., 2., 6., 5., 3.][run as usize],
            ));
            v.push(rec(
                "A",
                "b",
                run,
                [2., 7., 1., 8., 2., 8., 1., 8., 2., 8.][run as usize],
            ));
            v.push(rec(
                "B",
                "b",
                run,
                [5., 3., 5., 8., 9., 7., 9., 3., 2., 3.][run as usize],
            ));
            v.push(rec(
                "C",
                "b",
                run,
                [8., 4., 6., 2., 6., 4., 3., 3., 8., 3.][run as usize],
            ));
        }
        Dataset::from_records(v)
    }

    #[test]
    fn marks_are_from_the_compared_algorithms_view() {
        let ds = dataset();
        let s = significance(&ds, 0, 0.05);
        let mark = |rows: &[Comparison<WilcoxonResult>], alg: &str, prob: &str| {
            rows.iter()
                .find(|r| ds.cells[r.cell].label == alg && ds.problems[r.problem].function == prob)
                .and_then(|r| r.mark)
        };
        assert_eq!(mark(&s.wilcoxon, "A", "a"), Some(Mark::Better));
        assert_eq!(mark(&s.wilcoxon, "B", "a"), Some(Mark::Worse));
        assert_eq!(mark(&s.wilcoxon, "C", "a"), Some(Mark::Same));
        // Ten pairs (some with all differences zero) are enough at α = 0.05.
        assert_eq!(small_sample_note(&s, 0.05), None);
        let few: Vec<_> = (0..3)
            .flat_map(|run| [rec("R", "a", run, 1.0), rec("A", "a", run, 0.5)])
            .collect();
        let few = Dataset::from_records(few);
        let s3 = significance(&few, 0, 0.05);
        let note = small_sample_note(&s3, 0.05).unwrap();
        assert!(note.contains("pair only 3 runs"), "{note}");
        assert!(note.contains("at least 6 runs"), "{note}");
        let t = tally(&s.wilcoxon, ds.cells.len());
        assert_eq!(
            t[1],
            MarkTally {
                better: 1,
                same: 1,
                worse: 0
            }
        );
        assert_eq!(
            t[2],
            MarkTally {
                better: 0,
                same: 1,
                worse: 1
            }
        );
        // Holm: the adjusted p-value is never below the raw one.
        for r in &s.wilcoxon {
            let raw = r.result.as_ref().unwrap().p_value;
            assert!(r.p_holm.unwrap() >= raw);
        }
        // Mann–Whitney: B is worse on "a" (shifted by +1 with larger spread).
        let mw = s
            .mann_whitney
            .iter()
            .find(|r| ds.cells[r.cell].label == "A" && r.problem == 0)
            .unwrap();
        assert!(mw.result.is_ok());
    }

    #[test]
    fn friedman_ranks_and_single_algorithm() {
        let ds = dataset();
        let stats = compute(&ds);
        let f = friedman_report(&ds, &stats, 0.05);
        let r = f.ranking.as_ref().unwrap();
        assert_eq!(r.test.n_blocks, 2);
        assert_eq!(r.test.n_treatments, 4);
        assert!(r.cd.is_ok());
        let t = friedman_table(&ds, &f, 0.05);
        assert_eq!(t.md_rows.len(), 4);
        assert_eq!(t.md_rows[0][4], "best");

        let one = Dataset::from_records(vec![rec("R", "a", 0, 1.0)]);
        let stats = compute(&one);
        let f = friedman_report(&one, &stats, 0.05);
        assert_eq!(f.ranking.as_ref().unwrap_err(), &NoRanking::SingleAlgorithm);
        let t = friedman_table(&one, &f, 0.05);
        assert!(t.md_rows.is_empty());
        let s = significance(&one, 0, 0.05);
        assert!(s.wilcoxon.is_empty() && s.mann_whitney.is_empty());
    }

    #[test]
    fn nemenyi_out_of_table_is_reported_not_fatal() {
        let mut v = Vec::new();
        for i in 0..11 {
            v.push(rec(&format!("X{i}"), "a", 0, f64::from(i)));
        }
        let ds = Dataset::from_records(v);
        let stats = compute(&ds);
        let f = friedman_report(&ds, &stats, 0.05);
        assert!(matches!(
            f.ranking.as_ref().unwrap().cd,
            Err(StatsError::OutOfTable { k: 11, .. })
        ));
        let t = friedman_table(&ds, &f, 0.05);
        assert!(t.intro.iter().any(|s| s.contains("not available")));
        assert_eq!(t.md_rows[1][4], "n/a");
    }
}
