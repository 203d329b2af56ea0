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

mod friedman;
mod observations;
mod tables;
mod tally;
#[cfg(test)]
mod tests;

use rayon::prelude::*;

use crate::rng::{fnv1a64, run_rng, Draw};
use crate::stats::{
    bootstrap_interval, holm_bonferroni, mann_whitney_u, median_in_place, ratio_of_medians,
    vargha_delaney_a12, wilcoxon, Alternative, Interval, Mark, PValueMethod, Resampling,
    StatsError,
};

use super::anytime::run_auc;
use super::data::{Dataset, Run};
use super::verdicts::Measure;

pub(crate) use self::friedman::friedman_report;
pub(crate) use self::observations::observations;
pub(crate) use self::tables::{
    comparison_table, friedman_table, marks_summary_table, tally_text, tests_table,
};
pub(crate) use self::tally::Tally;

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
