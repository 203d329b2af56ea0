//! The first level of the report's inference: on every problem, a test of
//! every algorithm against the reference that matches the design, with
//! effect sizes, Holm-corrected per problem and written as "+ / ≈ / −"
//! marks; and Friedman's ranking over the independent units.
//!
//! Two samples are paired only when the design pairs them: when their runs
//! share their seeds run by run (common random numbers, `paired` in the
//! spec, or an external file that reused our seeds). Then the Wilcoxon
//! signed-rank test is used (Wilcoxon 1945), otherwise the Mann–Whitney U
//! test (Mann & Whitney 1947); every row says which. Each row has the
//! Vargha–Delaney A₁₂, the ratio of the medians (floored at the success
//! threshold) and its 95 % percentile bootstrap interval, resampled pairs
//! or samples as the test does and seeded from the row's names, so a report
//! is byte-identical from the same files. Where every run of both
//! algorithms reached the success threshold the row is "both solved", not
//! a mark: a difference below the target on both sides is not a result.
//!
//! These marks describe problems. A verdict across problems comes from
//! [`super::verdicts`], whose units are independent problems.

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::rng::{fnv1a64, run_rng, Draw};
use crate::stats::{
    bootstrap_interval, friedman, holm_bonferroni, mann_whitney_u, median, median_in_place,
    nemenyi_critical_difference, ratio_of_medians, vargha_delaney_a12, wilcoxon, Alternative,
    FriedmanResult, Interval, Mark, PValueMethod, Resampling, StatsError,
};

use super::anytime::run_auc;
use super::data::{Dataset, Run};
use super::descriptive::{mean_sd, CellStats};
use super::design::{factors, unit, Levels};
use super::format::{csv_opt, csv_real, fixed2, p_value, sci, Table};
use super::verdicts::{Measure, Observation, Standing, STATE_OF_THE_ART};

/// Resamples of every bootstrap interval.
pub(crate) const BOOTSTRAP_RESAMPLES: usize = 1000;

/// The confidence level of the bootstrap intervals.
pub(crate) const CONFIDENCE: f64 = 0.95;

/// Why a test of a cell against the reference has no result; the text is
/// shown in the test tables.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum NoTest {
    /// The test rejected its samples.
    #[error(transparent)]
    Test(#[from] StatsError),
    /// Holm's correction of the problem's family failed.
    #[error("Holm correction failed: {0}")]
    Holm(#[source] StatsError),
}

/// The first-level test a comparison used.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum TestKind {
    /// The Wilcoxon signed-rank test on runs paired by their shared seeds.
    SignedRank,
    /// The Mann–Whitney U test on independent samples.
    MannWhitney,
}

impl TestKind {
    /// `wilcoxon-signed-rank` or `mann-whitney-u`.
    pub fn name(self) -> &'static str {
        match self {
            TestKind::SignedRank => "wilcoxon-signed-rank",
            TestKind::MannWhitney => "mann-whitney-u",
        }
    }
}

/// A test's numbers.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TestResult {
    /// Which test.
    pub kind: TestKind,
    /// Runs of the compared cell (pairs for the signed-rank test).
    pub n1: usize,
    /// Runs of the reference (pairs for the signed-rank test).
    pub n2: usize,
    /// R⁺ − R⁻ of the differences A − R, or U of the compared cell.
    pub statistic: f64,
    /// The standard score, when the normal approximation was used.
    pub z: Option<f64>,
    /// How the p-value was computed.
    pub method: PValueMethod,
    /// The two-sided p-value.
    pub p_value: f64,
    /// Negative when the compared cell's values tend to be the lower.
    pub direction: f64,
}

/// The outcome of a first-level comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Outcome {
    /// A mark at the Holm-adjusted p.
    Mark(Mark),
    /// Every run of both reached the success threshold: no mark.
    BothSolved,
}

impl Outcome {
    /// `+`, `−`, `≈` or `both solved`.
    pub fn symbol(self) -> &'static str {
        match self {
            Outcome::Mark(m) => m.symbol(),
            Outcome::BothSolved => "both solved",
        }
    }

    /// `+`, `-`, `=` or `both solved`.
    pub fn ascii(self) -> &'static str {
        match self {
            Outcome::Mark(m) => m.ascii(),
            Outcome::BothSolved => "both solved",
        }
    }
}

/// One comparison of a cell with the reference on a problem.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Comparison {
    /// Problem index.
    pub problem: usize,
    /// Compared cell index.
    pub cell: usize,
    /// The test, or why it could not be computed.
    pub result: Result<TestResult, NoTest>,
    /// Holm-adjusted p-value within the problem's family.
    pub p_holm: Option<f64>,
    /// The mark at the adjusted p, or "both solved".
    pub outcome: Option<Outcome>,
    /// The Vargha–Delaney A₁₂ of the compared cell's values over the
    /// reference's.
    pub a12: Option<f64>,
    /// For the final error the ratio of the floored medians (compared /
    /// reference), for the AUC their difference.
    pub effect: f64,
    /// The bootstrap interval of `effect`.
    pub ci: Option<Interval>,
}

/// The first-level tests against the reference.
#[derive(Clone, Debug)]
pub(crate) struct Significance {
    /// The reference cell.
    pub reference: usize,
    /// The final-error comparisons, problem by problem.
    pub tests: Vec<Comparison>,
    /// The anytime comparisons (empty without hits).
    pub anytime: Vec<Comparison>,
    /// Problems that the reference did not run.
    pub skipped_problems: Vec<usize>,
    /// The floor of the error medians: the success threshold (or the
    /// smallest positive real when there is none).
    pub floor: f64,
}

/// The floor of error medians for a success threshold: the threshold, or
/// the smallest positive real when it is absent or 0.
pub(crate) fn floor_of(threshold: Option<f64>) -> f64 {
    threshold
        .filter(|t| *t > 0.0 && t.is_finite())
        .unwrap_or(f64::MIN_POSITIVE)
}

/// The runs of two cells on one problem, aligned by run number when they
/// are paired by design: same run numbers, and equal seeds run by run.
pub(crate) fn paired_by_design(a: &[Run], r: &[Run]) -> bool {
    a.len() == r.len()
        && a.iter()
            .zip(r)
            .all(|(x, y)| x.run == y.run && x.seed == y.seed)
}

/// The test of `a` against `r` that matches the design.
pub(crate) fn design_test(a: &[f64], r: &[f64], paired: bool) -> Result<TestResult, StatsError> {
    if paired {
        let w = wilcoxon(a, r, Alternative::TwoSided)?;
        Ok(TestResult {
            kind: TestKind::SignedRank,
            n1: a.len(),
            n2: r.len(),
            statistic: w.r_plus - w.r_minus,
            z: w.z,
            method: w.method,
            p_value: w.p_value,
            direction: w.r_plus - w.r_minus,
        })
    } else {
        let m = mann_whitney_u(a, r, Alternative::TwoSided)?;
        Ok(TestResult {
            kind: TestKind::MannWhitney,
            n1: m.n1,
            n2: m.n2,
            statistic: m.statistic,
            z: m.z,
            method: m.method,
            p_value: m.p_value,
            direction: m.statistic - (m.n1 * m.n2) as f64 / 2.0,
        })
    }
}

/// The values a measure compares of one cell's runs on a problem;
/// `budget` bounds the anytime measure (the smaller budget of the two).
pub(crate) fn values(
    runs: &[Run],
    measure: Measure,
    dim: usize,
    budget: u64,
    targets: usize,
) -> Vec<f64> {
    match measure {
        Measure::FinalError => runs.iter().map(|r| r.error).collect(),
        Measure::AnytimeAuc => runs
            .iter()
            .map(|r| run_auc(r, dim, budget, targets))
            .collect(),
    }
}

/// The smallest budget of some runs.
pub(crate) fn min_budget<'r>(runs: impl IntoIterator<Item = &'r Run>) -> u64 {
    runs.into_iter().map(|r| r.budget).min().unwrap_or(0)
}

/// What every comparison of one report needs to know.
struct Context<'a> {
    ds: &'a Dataset,
    reference: usize,
    floor: f64,
    targets: usize,
}

impl Context<'_> {
    /// One comparison, before Holm's correction.
    fn compare(&self, p: usize, c: usize, measure: Measure) -> Comparison {
        let ds = self.ds;
        let (a_runs, r_runs) = (ds.runs(p, c), ds.runs(p, self.reference));
        let paired = paired_by_design(a_runs, r_runs);
        let budget = min_budget(a_runs.iter().chain(r_runs));
        let dim = ds.problems[p].dim;
        let a = values(a_runs, measure, dim, budget, self.targets);
        let r = values(r_runs, measure, dim, budget, self.targets);
        let floor = self.floor;
        let effect_of = |x: &mut [f64], y: &mut [f64]| match measure {
            Measure::FinalError => ratio_of_medians(x, y, floor),
            Measure::AnytimeAuc => median_in_place(x) - median_in_place(y),
        };
        let effect = effect_of(&mut a.clone(), &mut r.clone());
        let seed = fnv1a64(&format!(
            "bootstrap|{}|{}|{}|{}",
            measure.name(),
            ds.problems[p].label(),
            ds.cells[c].name,
            ds.cells[self.reference].name
        ));
        let mut rng = run_rng(seed);
        let resampling = if paired {
            Resampling::Paired
        } else {
            Resampling::Independent
        };
        let ci = bootstrap_interval(
            &a,
            &r,
            resampling,
            BOOTSTRAP_RESAMPLES,
            CONFIDENCE,
            effect_of,
            |n| rng.index(n),
        )
        .ok();
        let both_solved =
            measure == Measure::FinalError && a_runs.iter().chain(r_runs).all(|x| x.success);
        // Solved on both sides, the two are equal whatever the floor.
        let (effect, ci) = if both_solved {
            (1.0, None)
        } else {
            (effect, ci)
        };
        Comparison {
            problem: p,
            cell: c,
            result: design_test(&a, &r, paired).map_err(NoTest::from),
            p_holm: None,
            outcome: both_solved.then_some(Outcome::BothSolved),
            a12: vargha_delaney_a12(&a, &r).ok(),
            effect,
            ci,
        }
    }
}

/// Holm's correction within every problem's family and the marks; rows
/// are grouped by problem.
fn correct_per_problem(rows: &mut [Comparison], alpha: f64, lower_is_better: bool) {
    let mut start = 0;
    while start < rows.len() {
        let p = rows[start].problem;
        let end = start + rows[start..].iter().take_while(|r| r.problem == p).count();
        let family: Vec<usize> = (start..end).filter(|&i| rows[i].result.is_ok()).collect();
        let raw: Vec<f64> = family
            .iter()
            .filter_map(|&i| rows[i].result.as_ref().ok().map(|r| r.p_value))
            .collect();
        match holm_bonferroni(&raw) {
            Ok(adjusted) => {
                for (&i, &ph) in family.iter().zip(&adjusted) {
                    let d = rows[i].result.as_ref().map_or(0.0, |r| r.direction);
                    let d = if lower_is_better { d } else { -d };
                    rows[i].p_holm = Some(ph);
                    if rows[i].outcome.is_none() {
                        rows[i].outcome = Some(Outcome::Mark(Mark::from_p_value(ph, alpha, d)));
                    }
                }
            }
            Err(e) => {
                for &i in &family {
                    rows[i].result = Err(NoTest::Holm(e.clone()));
                }
            }
        }
        start = end;
    }
}

/// Every first-level comparison of the cells with `reference`: the final
/// error always, the anytime AUC when `hits.csv` was read (external cells,
/// which have no hits, are left out of it). `threshold` floors the error
/// medians of the ratios.
pub(crate) fn significance(
    ds: &Dataset,
    reference: usize,
    alpha: f64,
    threshold: Option<f64>,
) -> Significance {
    let ctx = Context {
        ds,
        reference,
        floor: floor_of(threshold),
        targets: crate::experiment::records::default_targets().len(),
    };
    let mut skipped = Vec::new();
    let mut pairs = Vec::new();
    for p in 0..ds.problems.len() {
        if ds.runs(p, reference).is_empty() {
            skipped.push(p);
            continue;
        }
        for c in 0..ds.cells.len() {
            if c != reference && !ds.runs(p, c).is_empty() {
                pairs.push((p, c));
            }
        }
    }
    let run = |measure: Measure, pairs: &[(usize, usize)]| -> Vec<Comparison> {
        let mut rows: Vec<Comparison> = pairs
            .par_iter()
            .map(|&(p, c)| ctx.compare(p, c, measure))
            .collect();
        correct_per_problem(&mut rows, alpha, measure.lower_is_better());
        rows
    };
    let tests = run(Measure::FinalError, &pairs);
    let anytime = if ds.has_hits && !ds.cells[reference].external {
        let internal: Vec<(usize, usize)> = pairs
            .iter()
            .copied()
            .filter(|&(_, c)| !ds.cells[c].external)
            .collect();
        run(Measure::AnytimeAuc, &internal)
    } else {
        Vec::new()
    };
    Significance {
        reference,
        tests,
        anytime,
        skipped_problems: skipped,
        floor: ctx.floor,
    }
}

/// The per-problem summaries of the comparisons with the reference for
/// [`super::verdicts`] (per-segment fitting problems excepted: their units
/// are segments, see [`super::fit_units`]), and every cell's standing for
/// Friedman's ranking.
pub(crate) fn observations(ds: &Dataset, s: &Significance) -> (Vec<Observation>, Vec<Standing>) {
    let reference = &ds.cells[s.reference].name;
    let targets = crate::experiment::records::default_targets().len();
    let mut obs = Vec::new();
    let mut standings = Vec::new();
    for (measure, rows) in [
        (Measure::FinalError, &s.tests),
        (Measure::AnytimeAuc, &s.anytime),
    ] {
        let mut problems: Vec<usize> = rows.iter().map(|r| r.problem).collect();
        problems.dedup();
        for &p in &problems {
            let problem = &ds.problems[p];
            let Some(u) = unit(problem) else { continue };
            let levels: Levels = factors(problem);
            let cells: Vec<usize> = std::iter::once(s.reference)
                .chain(rows.iter().filter(|r| r.problem == p).map(|r| r.cell))
                .collect();
            let budget = min_budget(cells.iter().flat_map(|&c| ds.runs(p, c)));
            for &c in &cells {
                let mut v = values(ds.runs(p, c), measure, problem.dim, budget, targets);
                let value = match measure {
                    Measure::FinalError => {
                        v.iter_mut().for_each(|x| *x = x.max(s.floor));
                        median_in_place(&mut v).log10()
                    }
                    Measure::AnytimeAuc => median_in_place(&mut v),
                };
                if !value.is_nan() {
                    standings.push(Standing {
                        table: ds
                            .families
                            .comparison_set(&ds.cells[c].kind, &ds.cells[s.reference].kind),
                        measure,
                        algorithm: ds.cells[c].name.clone(),
                        unit: u.clone(),
                        levels: levels.clone(),
                        value,
                    });
                }
            }
            for r in rows.iter().filter(|r| r.problem == p) {
                let value = match measure {
                    Measure::FinalError => r.effect.log10(),
                    Measure::AnytimeAuc => r.effect,
                };
                if value.is_nan() {
                    continue;
                }
                obs.push(Observation {
                    table: ds
                        .families
                        .comparison_set(&ds.cells[r.cell].kind, &ds.cells[s.reference].kind),
                    measure,
                    algorithm: ds.cells[r.cell].name.clone(),
                    reference: reference.clone(),
                    unit: u.clone(),
                    levels: levels.clone(),
                    value,
                });
            }
        }
    }
    (obs, standings)
}

/// Mark counts per cell (the "both solved" rows are not marks).
pub(crate) fn tally(rows: &[Comparison], cells: usize) -> Vec<Tally> {
    let mut t = vec![Tally::default(); cells];
    for row in rows {
        if let (Some(o), Some(slot)) = (row.outcome, t.get_mut(row.cell)) {
            slot.add(o);
        }
    }
    t
}

/// Counts of first-level outcomes: marks and "both solved".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tally {
    /// `+` marks.
    pub better: usize,
    /// `≈` marks.
    pub same: usize,
    /// `−` marks.
    pub worse: usize,
    /// Problems both solved on every run.
    pub both_solved: usize,
}

impl Tally {
    /// Adds one outcome.
    pub fn add(&mut self, o: Outcome) {
        match o {
            Outcome::Mark(Mark::Better) => self.better += 1,
            Outcome::Mark(Mark::Same) => self.same += 1,
            Outcome::Mark(Mark::Worse) => self.worse += 1,
            Outcome::BothSolved => self.both_solved += 1,
        }
    }

    /// Adds another tally.
    pub fn merge(&mut self, o: &Tally) {
        self.better += o.better;
        self.same += o.same;
        self.worse += o.worse;
        self.both_solved += o.both_solved;
    }

    /// The number of outcomes counted.
    pub fn total(&self) -> usize {
        self.better + self.same + self.worse + self.both_solved
    }

    /// `b/s/w`, with `, n both solved` when there are some.
    pub fn text(&self) -> String {
        let mut s = format!("{}/{}/{}", self.better, self.same, self.worse);
        if self.both_solved > 0 {
            s.push_str(&format!(" ({} both solved)", self.both_solved));
        }
        s
    }
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
            tl.text()
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
    let mut t = Table {
        stem: stem.into(),
        title: format!("{title} against {}", reference.name),
        intro,
        md_header: [
            "Problem",
            "D",
            "Algorithm",
            "Test",
            "n₁/n₂",
            "p",
            "p (Holm)",
            "Mark",
            "A₁₂",
            effect_md,
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
        .to_vec(),
        ..Table::default()
    };
    for row in rows {
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
            reference.label.clone(),
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
        t.md_rows.push(md);
        t.csv_rows.push(csv);
    }
    t
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
            e[c].text(),
            if a[c].total() == 0 {
                "\u{2014}".into()
            } else {
                a[c].text()
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

/// Why there is no Friedman ranking; the text is shown in the report.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum NoRanking {
    /// There is one algorithm only.
    #[error("a single algorithm: there is nothing to rank")]
    SingleAlgorithm,
    /// No unit has a value for every algorithm.
    #[error("no unit was run by every algorithm")]
    NoCommonUnit,
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

/// The Friedman test over the units and the Nemenyi critical difference.
#[derive(Clone, Debug)]
pub(crate) struct FriedmanReport {
    /// The units used as blocks.
    pub blocks: Vec<String>,
    /// The test and critical difference, or why there are none.
    pub ranking: Result<Ranking, NoRanking>,
    /// What the units are called.
    pub noun: &'static str,
}

/// Friedman's test with blocks = the units on which every algorithm has a
/// final-error standing (the median over the unit's problems of log10 of
/// the floored median error), ranked within each unit.
pub(crate) fn friedman_report(
    ds: &Dataset,
    standings: &[Standing],
    alpha: f64,
    noun: &'static str,
) -> FriedmanReport {
    let k = ds.cells.len();
    let mut by: BTreeMap<(&str, &str), Vec<f64>> = BTreeMap::new();
    for s in standings.iter().filter(|s| {
        (s.table == "reference" || s.table == STATE_OF_THE_ART) && s.measure == Measure::FinalError
    }) {
        by.entry((&s.unit, &s.algorithm)).or_default().push(s.value);
    }
    let mut units: Vec<&str> = by.keys().map(|(u, _)| *u).collect();
    units.dedup();
    let mut blocks = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for u in units {
        let row: Option<Vec<f64>> = ds
            .cells
            .iter()
            .map(|c| by.get(&(u, c.name.as_str())).map(|v| median(v)))
            .collect();
        if let Some(row) = row {
            blocks.push(u.to_owned());
            rows.push(row);
        }
    }
    let ranking = if k < 2 {
        Err(NoRanking::SingleAlgorithm)
    } else if rows.is_empty() {
        Err(NoRanking::NoCommonUnit)
    } else {
        friedman(&rows)
            .map_err(NoRanking::from)
            .map(|test| Ranking {
                test,
                cd: nemenyi_critical_difference(k, rows.len(), alpha),
            })
    };
    FriedmanReport {
        blocks,
        ranking,
        noun,
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::RunRecord;

    fn rec(alg: &str, problem: &str, run: u32, seed: u64, error: f64) -> (RunRecord, bool) {
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
                seed,
                best: error,
                error,
                evaluations: 100,
                evaluations_to_target: None,
                success: error <= 1e-8,
                trace: Vec::new(),
                hits: Vec::new(),
                fit: None,
                wall_seconds: 0.0,
            },
            false,
        )
    }

    fn dataset(shared_seeds: bool) -> Dataset {
        let mut v = Vec::new();
        for run in 0..10 {
            let x = f64::from(run);
            let seed = |alg: u64| {
                if shared_seeds {
                    u64::from(run)
                } else {
                    alg * 100 + u64::from(run)
                }
            };
            // On "a": A always better than R, B always worse, C equal.
            v.push(rec("R", "a", run, seed(0), 1.0 + x));
            v.push(rec("A", "a", run, seed(1), 0.5 + x * 0.9));
            v.push(rec("B", "a", run, seed(2), 20.0 + x));
            v.push(rec("C", "a", run, seed(3), 1.0 + x));
            // On "s": every run of R and A solved, B not.
            v.push(rec("R", "s", run, seed(0), 1e-9));
            v.push(rec("A", "s", run, seed(1), 1e-12));
            v.push(rec("B", "s", run, seed(2), 1.0));
            v.push(rec("C", "s", run, seed(3), 1e-10));
        }
        Dataset::from_records(v)
    }

    fn row<'s>(ds: &Dataset, s: &'s Significance, alg: &str, prob: &str) -> &'s Comparison {
        s.tests
            .iter()
            .find(|r| ds.cells[r.cell].label == alg && ds.problems[r.problem].function == prob)
            .unwrap()
    }

    #[test]
    fn the_test_follows_the_design_and_marks_are_from_the_compared_view() {
        for shared in [false, true] {
            let ds = dataset(shared);
            let s = significance(&ds, 0, 0.05, Some(1e-8));
            let kind = row(&ds, &s, "A", "a").result.as_ref().unwrap().kind;
            assert_eq!(
                kind,
                if shared {
                    TestKind::SignedRank
                } else {
                    TestKind::MannWhitney
                }
            );
            let mark = |alg| row(&ds, &s, alg, "a").outcome.unwrap();
            assert_eq!(mark("B"), Outcome::Mark(Mark::Worse));
            assert_eq!(mark("C"), Outcome::Mark(Mark::Same));
            // Paired, A is better on every run; unpaired, its shift is small
            // against the spread (MW cannot tell).
            if shared {
                assert_eq!(mark("A"), Outcome::Mark(Mark::Better));
            }
            // Below the threshold on both sides: both solved, not a mark.
            assert_eq!(row(&ds, &s, "A", "s").outcome, Some(Outcome::BothSolved));
            assert_eq!(row(&ds, &s, "C", "s").outcome, Some(Outcome::BothSolved));
            assert_eq!(
                row(&ds, &s, "B", "s").outcome,
                Some(Outcome::Mark(Mark::Worse))
            );
            // The ratio of floored medians is 1 when both solved.
            assert_eq!(row(&ds, &s, "A", "s").effect, 1.0);
            let c = row(&ds, &s, "C", "a");
            assert_eq!(c.effect, 1.0);
            assert_eq!(c.a12, Some(0.5));
            let ci = c.ci.unwrap();
            assert!(ci.low <= 1.0 && ci.high >= 1.0, "{ci:?}");
            let b = row(&ds, &s, "B", "a");
            assert!(b.a12.unwrap() > 0.5 && b.ci.unwrap().low > 1.0);
            for r in &s.tests {
                let raw = r.result.as_ref().unwrap().p_value;
                assert!(r.p_holm.unwrap() >= raw);
            }
            assert!(s.anytime.is_empty(), "no hits were read");
        }
    }

    #[test]
    fn the_same_data_gives_the_same_intervals() {
        let ds = dataset(false);
        let a = significance(&ds, 0, 0.05, Some(1e-8));
        let b = significance(&ds, 0, 0.05, Some(1e-8));
        assert_eq!(a.tests, b.tests);
    }

    #[test]
    fn friedman_ranks_units_and_single_algorithm() {
        let ds = dataset(false);
        let s = significance(&ds, 0, 0.05, Some(1e-8));
        let (_, standings) = observations(&ds, &s);
        let f = friedman_report(&ds, &standings, 0.05, "function");
        let r = f.ranking.as_ref().unwrap();
        assert_eq!(r.test.n_blocks, 2);
        assert_eq!(r.test.n_treatments, 4);
        let t = friedman_table(&ds, &f, 0.05);
        assert_eq!(t.md_rows.len(), 4);
        assert_eq!(t.md_rows[0][4], "best");

        let one = Dataset::from_records(vec![rec("R", "a", 0, 0, 1.0)]);
        let s = significance(&one, 0, 0.05, None);
        assert!(s.tests.is_empty());
        let (_, standings) = observations(&one, &s);
        let f = friedman_report(&one, &standings, 0.05, "function");
        assert_eq!(f.ranking.as_ref().unwrap_err(), &NoRanking::SingleAlgorithm);
    }
}
