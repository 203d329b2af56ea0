//! The statistics of `compare`: per shared cell and problem a test of A's
//! runs against the other campaign's, and the verdicts across problems.
//!
//! **Measures.** The final error is compared as log10(max(f − f*, τ)), τ
//! the success threshold of A's spec (the report's floor,
//! [`crate::significance::floor_of`]): below the target two runs are
//! equal. The anytime measure, where both campaigns wrote their target
//! hits, is the report's area under a run's target ECDF
//! ([`crate::anytime::run_auc`]).
//!
//! **Paired only where the design pairs.** On one problem the runs of the
//! two campaigns pair when they have the same run numbers and, run by run,
//! the same seed ([`crate::significance::paired_by_design`]: the same spec
//! and experiment seed, whatever the thread count or machine); then the
//! Wilcoxon signed-rank test of the per-run differences, else the
//! Mann–Whitney U test (different seeds, or another spec). Where every run
//! agrees bit for bit (final error, evaluations, the evaluation that
//! reached the target, the targets hit) the problem is **identical**: the
//! differences are all zero and no test is run. The first-level p-values
//! are Holm-corrected over the shared cells on one problem (the report's
//! per-problem family).
//!
//! **Across problems.** Each problem's summary is the report's: for the
//! final error log10 of the ratio of the two floored medians (0 where every
//! run of both reached the threshold), for the anytime measure the
//! difference of the median AUCs. [`crate::verdicts::verdicts`] turns them
//! into verdicts: per-function units, the Wilcoxon signed-rank test
//! Holm-corrected over the shared cells of one pair of campaigns (one
//! family per measure and scope), the Hodges–Lehmann interval and the
//! Bayesian signed-rank test with its rope ([`crate::stats::Verdict`]:
//! better, worse, equivalent, undecided). A shared cell whose every problem
//! is identical is not tested: its verdict is `identical`.

use std::collections::BTreeMap;

use crate::compare_sides::{Shared, Side};
use crate::design::{factors, unit};
use crate::significance::{
    design_test, floor_of, min_budget, paired_by_design, values, TestResult,
};
use crate::stats::{
    holm_bonferroni, median, ratio_of_medians, Mark, StatsError, Verdict, VerdictRow,
};
use crate::verdicts::{verdicts, Measure, Observation, Ropes, Settings};
use crate::PostHoc;

/// How the runs of one shared cell on one problem were compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Design {
    /// Every run agrees bit for bit: no test.
    Identical,
    /// Paired by run number and seed: Wilcoxon signed-rank.
    Paired,
    /// Not paired: Mann–Whitney U.
    Unpaired,
}

impl Design {
    /// `identical`, `paired` or `unpaired`.
    pub fn name(self) -> &'static str {
        match self {
            Design::Identical => "identical",
            Design::Paired => "paired",
            Design::Unpaired => "unpaired",
        }
    }
}

/// One first-level comparison: a shared cell on one problem, one measure.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct ProblemTest {
    /// Index into the shared cells.
    pub shared: usize,
    /// The problem (index into the shared cell's dataset).
    pub problem: usize,
    /// The measure.
    pub measure: Measure,
    /// The design of the comparison.
    pub design: Design,
    /// Runs of A and of the other campaign.
    pub runs: (usize, usize),
    /// Medians of the measure (the floored error, not its log).
    pub medians: (f64, f64),
    /// The problem's summary (see the module's documentation).
    pub summary: f64,
    /// The test, none where identical, or why it failed.
    pub test: Option<Result<TestResult, StatsError>>,
    /// The Holm-adjusted p within the problem's family.
    pub p_holm: Option<f64>,
    /// The mark at the adjusted p, from A's point of view.
    pub mark: Option<Mark>,
}

/// Everything `compare` concludes.
pub(crate) struct Analysis {
    /// Every first-level comparison, by shared cell, measure, problem.
    pub tests: Vec<ProblemTest>,
    /// The verdicts across problems (tables `A vs B`, …), identical cells
    /// left out.
    pub verdicts: Vec<VerdictRow>,
    /// Whether each shared cell is identical on every problem.
    pub identical: Vec<bool>,
    /// The floor of the final errors.
    pub floor: f64,
}

impl Analysis {
    /// Whether every shared cell of every campaign is identical to A's.
    pub fn all_identical(&self) -> bool {
        self.identical.iter().all(|&i| i)
    }

    /// The verdict at scope `all` on the final error of every shared cell,
    /// `B: cell: verdict`, or `identical`.
    pub fn verdict_lines(&self, sides: &[Side], shared: &[Shared]) -> Vec<String> {
        shared
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let verdict = self
                    .verdict_of(s, sides, Measure::FinalError)
                    .map_or("no verdict", |r| r.verdict.as_str());
                let verdict = if self.identical[i] {
                    "identical"
                } else {
                    verdict
                };
                format!("A vs {}: {}: {verdict}", sides[s.side].letter, s.cell)
            })
            .collect()
    }

    /// The verdict row at scope `all` of a shared cell on `measure`.
    pub fn verdict_of(&self, s: &Shared, sides: &[Side], measure: Measure) -> Option<&VerdictRow> {
        self.verdicts.iter().find(|r| {
            r.table == table_name(sides, s.side)
                && r.measure == measure.name()
                && r.scope == "all"
                && r.algorithm == s.ds.cells[0].name
        })
    }
}

/// The name of the verdict table of A against campaign `side`.
pub(crate) fn table_name(sides: &[Side], side: usize) -> String {
    format!("A vs {}", sides[side].letter)
}

/// Whether two runs agree bit for bit on what the comparison reads.
fn same_run(x: &crate::data::Run, y: &crate::data::Run) -> bool {
    x.run == y.run
        && x.seed == y.seed
        && x.error.to_bits() == y.error.to_bits()
        && x.evaluations == y.evaluations
        && x.evaluations_to_target == y.evaluations_to_target
        && x.success == y.success
        && x.hits.len() == y.hits.len()
        && x.hits
            .iter()
            .zip(&y.hits)
            .all(|(p, q)| p.0.to_bits() == q.0.to_bits() && p.1 == q.1)
}

/// The first-level comparison of a shared cell on one problem.
fn problem_test(s: &Shared, index: usize, p: usize, measure: Measure, floor: f64) -> ProblemTest {
    let (a, b) = (s.ds.runs(p, 0), s.ds.runs(p, 1));
    let identical = a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_run(x, y));
    let design = if identical {
        Design::Identical
    } else if paired_by_design(a, b) {
        Design::Paired
    } else {
        Design::Unpaired
    };
    let targets = crate::experiment::records::default_targets().len();
    let budget = min_budget(a.iter().chain(b));
    let dim = s.ds.problems[p].dim;
    let mut va = values(a, measure, dim, budget, targets);
    let mut vb = values(b, measure, dim, budget, targets);
    let (summary, medians, compared) = match measure {
        Measure::FinalError => {
            va.iter_mut().for_each(|x| *x = x.max(floor));
            vb.iter_mut().for_each(|x| *x = x.max(floor));
            let solved = a.iter().chain(b).all(|r| r.success);
            let ratio = ratio_of_medians(&mut va.clone(), &mut vb.clone(), floor);
            let lg = |v: &[f64]| v.iter().map(|x| x.log10()).collect::<Vec<f64>>();
            let summary = if solved { 0.0 } else { ratio.log10() };
            (summary, (median(&va), median(&vb)), (lg(&va), lg(&vb)))
        }
        Measure::AnytimeAuc => {
            let (ma, mb) = (median(&va), median(&vb));
            (ma - mb, (ma, mb), (va, vb))
        }
    };
    let test = (design != Design::Identical)
        .then(|| design_test(&compared.0, &compared.1, design == Design::Paired));
    ProblemTest {
        shared: index,
        problem: p,
        measure,
        design,
        runs: (a.len(), b.len()),
        medians,
        summary,
        test,
        p_holm: None,
        mark: None,
    }
}

/// Holm's correction over the shared cells of one campaign on one problem
/// and measure (the report's per-problem family), and the marks.
fn correct(tests: &mut [ProblemTest], shared: &[Shared], alpha: f64) {
    let mut families: BTreeMap<(usize, String, Measure), Vec<usize>> = BTreeMap::new();
    for (i, t) in tests.iter().enumerate() {
        if let Some(Ok(_)) = &t.test {
            let s = &shared[t.shared];
            families
                .entry((s.side, s.ds.problems[t.problem].label(), t.measure))
                .or_default()
                .push(i);
        }
    }
    for members in families.values() {
        let raw: Vec<f64> = members
            .iter()
            .filter_map(|&i| tests[i].test.as_ref()?.as_ref().ok().map(|r| r.p_value))
            .collect();
        let Ok(adjusted) = holm_bonferroni(&raw) else {
            continue;
        };
        for (&i, p) in members.iter().zip(adjusted) {
            let t = &mut tests[i];
            let direction = t
                .test
                .as_ref()
                .and_then(|r| r.as_ref().ok())
                .map_or(0.0, |r| r.direction);
            let direction = if t.measure.lower_is_better() {
                direction
            } else {
                -direction
            };
            t.p_holm = Some(p);
            t.mark = Some(Mark::from_p_value(p, alpha, direction));
        }
    }
}

/// Every comparison of `compare`: the first level on every shared cell and
/// problem (the anytime measure only where both campaigns wrote hits), then
/// the verdicts across problems of the cells that are not identical.
pub(crate) fn analyse(sides: &[Side], shared: &[Shared], alpha: f64, ropes: Ropes) -> Analysis {
    let floor = floor_of(sides[0].provenance.threshold);
    let mut tests = Vec::new();
    for (i, s) in shared.iter().enumerate() {
        let mut measures = vec![Measure::FinalError];
        if sides[0].ds.has_hits && sides[s.side].ds.has_hits {
            measures.push(Measure::AnytimeAuc);
        }
        for measure in measures {
            for p in 0..s.ds.problems.len() {
                tests.push(problem_test(s, i, p, measure, floor));
            }
        }
    }
    correct(&mut tests, shared, alpha);
    let identical: Vec<bool> = (0..shared.len())
        .map(|i| {
            tests
                .iter()
                .filter(|t| t.shared == i)
                .all(|t| t.design == Design::Identical)
        })
        .collect();
    let settings = Settings {
        alpha,
        post_hoc: PostHoc::Holm,
        reference: None,
        ropes,
    };
    let mut rows = Vec::new();
    for side in 1..sides.len() {
        let observations: Vec<Observation> = tests
            .iter()
            .filter(|t| shared[t.shared].side == side && !identical[t.shared])
            .filter(|t| !t.summary.is_nan())
            .filter_map(|t| observation(&shared[t.shared], t))
            .collect();
        let mut side_rows = verdicts(&observations, &[], settings);
        for r in &mut side_rows {
            r.table = table_name(sides, side);
        }
        rows.extend(side_rows);
    }
    Analysis {
        tests,
        verdicts: rows,
        identical,
        floor,
    }
}

/// The observation of one problem's summary for the verdicts.
fn observation(s: &Shared, t: &ProblemTest) -> Option<Observation> {
    let problem = &s.ds.problems[t.problem];
    Some(Observation {
        table: "compare",
        measure: t.measure,
        algorithm: s.ds.cells[0].name.clone(),
        reference: s.ds.cells[1].name.clone(),
        unit: unit(problem)?,
        levels: factors(problem),
        value: t.summary,
    })
}

/// Whether a verdict decides for one side.
pub(crate) fn decisive(v: Verdict) -> bool {
    matches!(v, Verdict::Better | Verdict::Worse)
}
