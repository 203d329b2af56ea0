//! The anytime view of a campaign: COCO's average runtime aRT to each target
//! precision, from the exact hits of `hits.csv` (Hansen et al. 2021, "COCO:
//! a platform for comparing continuous optimizers in a black-box setting",
//! Optim. Methods Softw. 36(1); Auger & Hansen 2005 for aRT).
//!
//! For one algorithm on one function (pooled over its instances and
//! budgets), the aRT to a target is the evaluations of all runs until they
//! reached it, or until they ended when they did not, divided by the number
//! of runs that reached it; it is infinite when none did.

//!
//! This module computes the rows; [`tables`] renders them.

mod tables;

use std::collections::BTreeMap;

use super::best2009::{self, Best2009};
use super::data::{Dataset, Run};

pub(crate) use self::tables::{art_table, reached_table};

/// The number of `runs` that reached `target` and their aRT: the
/// evaluations of all runs until they reached it (or ended), divided by
/// that number (`None` when none did).
fn art(runs: &[&Run], target: f64) -> (usize, Option<f64>) {
    let mut spent = 0u64;
    let mut reached = 0usize;
    for r in runs {
        match r.hits.iter().find(|(p, _)| *p == target) {
            Some(&(_, e)) => {
                spent += e;
                reached += 1;
            }
            None => spent += r.evaluations,
        }
    }
    (
        reached,
        (reached > 0).then(|| spent as f64 / reached as f64),
    )
}

/// Who a row of the anytime tables is about: a configuration of the
/// results or one of COCO's references.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Who<'b> {
    /// The configuration (cell) of this index in the dataset.
    Cell(usize),
    /// A reference algorithm (best 2009, best 2009–16).
    Reference(&'b Best2009),
}

/// One target of an aRT row: the runs pooled, how many reached the target,
/// and the aRT (`None` when none did).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ArtPoint {
    /// Runs pooled.
    pub runs: usize,
    /// Runs that reached the target.
    pub reached: usize,
    /// The average runtime, `None` (infinite) when no run reached it.
    pub art: Option<f64>,
}

/// One row of the aRT table: a function at a dimension under a transform,
/// for one configuration or reference, with its aRT to every target.
#[derive(Clone, Debug)]
pub(crate) struct ArtRow<'b> {
    /// The function's name.
    pub function: String,
    /// The dimension D.
    pub dim: usize,
    /// The transform's name.
    pub transform: String,
    /// Whose runs.
    pub who: Who<'b>,
    /// The aRT to each target, in the order of the targets.
    pub points: Vec<ArtPoint>,
}

/// Whether some run of the campaign has hits.
fn any_hits(ds: &Dataset) -> bool {
    (0..ds.problems.len())
        .any(|p| (0..ds.cells.len()).any(|c| ds.runs(p, c).iter().any(|r| !r.hits.is_empty())))
}

/// The aRT to each of `targets` of every algorithm on every function,
/// dimension and transform (pooled over instances and budgets), with a row
/// of each of COCO's references in `best` (best 2009, best 2009–16) under
/// every bbob function and dimension it covers; `None` when no run has hits.
pub(crate) fn art_rows<'b>(
    ds: &Dataset,
    targets: &[f64],
    best: &'b [Best2009],
) -> Option<Vec<ArtRow<'b>>> {
    if !any_hits(ds) {
        return None;
    }
    // (function, D, transform) → problems
    let mut groups: BTreeMap<(String, usize, String), Vec<usize>> = BTreeMap::new();
    for (p, problem) in ds.problems.iter().enumerate() {
        groups
            .entry((
                problem.function.clone(),
                problem.dim,
                problem.transform.name().to_owned(),
            ))
            .or_default()
            .push(p);
    }
    let mut rows = Vec::new();
    for ((function, dim, transform), problems) in groups {
        let row = |who: Who<'b>, points: Vec<ArtPoint>| ArtRow {
            function: function.clone(),
            dim,
            transform: transform.clone(),
            who,
            points,
        };
        for c in 0..ds.cells.len() {
            let runs: Vec<&Run> = problems.iter().flat_map(|&p| ds.runs(p, c)).collect();
            if runs.is_empty() {
                continue;
            }
            let points = targets
                .iter()
                .map(|&target| {
                    let (reached, art) = art(&runs, target);
                    ArtPoint {
                        runs: runs.len(),
                        reached,
                        art,
                    }
                })
                .collect();
            rows.push(row(Who::Cell(c), points));
        }
        let Some((f, d)) = best2009::bbob_key(&function) else {
            continue;
        };
        for b in best.iter().filter(|b| b.covers(f, d)) {
            let points = targets
                .iter()
                .map(|&target| {
                    let step = b.step(f, d, target);
                    ArtPoint {
                        runs: step.map_or(15, |s| s.runs as usize),
                        reached: step.map_or(0, |s| s.successes as usize),
                        art: step.map(|s| s.art),
                    }
                })
                .collect();
            rows.push(row(Who::Reference(b), points));
        }
    }
    Some(rows)
}

/// (targets reached, pairs) at one budget, `None` where the runs stopped
/// before it.
pub(crate) type Reached = Option<(usize, usize)>;

/// The budgets, as multiples of D, at which [`reached_rows`] reads the
/// fraction of targets reached.
pub(crate) const READ_AT: [u64; 3] = [100, 1_000, 10_000];

/// One row of the targets-reached table: a dimension, a configuration or
/// reference, and the targets reached at each budget of [`READ_AT`].
#[derive(Clone, Debug)]
pub(crate) struct ReachedRow<'b> {
    /// The dimension D.
    pub dim: usize,
    /// Whose runs.
    pub who: Who<'b>,
    /// The number of functions at this dimension.
    pub functions: usize,
    /// (reached, pairs) at each budget of [`READ_AT`].
    pub counts: Vec<Reached>,
}

/// The fraction of (function, target) pairs reached within 10²·D, 10³·D and
/// 10⁴·D evaluations per dimension, for every algorithm and each of COCO's
/// references in `best` (best 2009, best 2009–16): the height of the
/// runtime ECDF over the `targets` at those budgets.
///
/// For an algorithm it is the fraction of its (run, target) pairs whose
/// target was first hit within the budget, over the runs of every function
/// and instance at that dimension (every function has as many runs, so this
/// is the mean over functions of the per-function fraction); it is left out
/// (—) when a run's budget is smaller. For a reference it is the fraction of
/// (function, target) pairs whose aRT is within the budget, as cocopp draws
/// the reference algorithm's ECDF from its aRTs (Hansen et al. 2021,
/// "COCO: a platform for comparing continuous optimizers in a black-box
/// setting", Optim. Methods Softw. 36(1):114–144). `None` unless every
/// problem is a bbob function that every reference covers and some run has
/// hits.
pub(crate) fn reached_rows<'b>(
    ds: &Dataset,
    targets: &[f64],
    best: &'b [Best2009],
) -> Option<Vec<ReachedRow<'b>>> {
    let keys: Vec<(usize, usize)> = ds
        .problems
        .iter()
        .map(|p| best2009::bbob_key(&p.function))
        .collect::<Option<_>>()?;
    if best.is_empty()
        || keys
            .iter()
            .any(|&(f, d)| best.iter().any(|b| !b.covers(f, d)))
        || !any_hits(ds)
    {
        return None;
    }
    let mut dims: Vec<usize> = keys.iter().map(|k| k.1).collect();
    dims.sort_unstable();
    dims.dedup();
    let mut rows = Vec::new();
    for d in dims {
        let problems: Vec<usize> = (0..ds.problems.len()).filter(|&p| keys[p].1 == d).collect();
        let mut functions: Vec<usize> = problems.iter().map(|&p| keys[p].0).collect();
        functions.sort_unstable();
        functions.dedup();
        for c in 0..ds.cells.len() {
            let runs: Vec<&Run> = problems.iter().flat_map(|&p| ds.runs(p, c)).collect();
            if runs.is_empty() {
                continue;
            }
            rows.push(ReachedRow {
                dim: d,
                who: Who::Cell(c),
                functions: functions.len(),
                counts: runs_reached(&runs, d, targets.len()),
            });
        }
        for b in best {
            rows.push(ReachedRow {
                dim: d,
                who: Who::Reference(b),
                functions: functions.len(),
                counts: reference_reached(b, &functions, d, targets),
            });
        }
    }
    Some(rows)
}

/// The (run, target) pairs of `runs` at dimension `d` whose target was
/// first hit within each budget of [`READ_AT`]; `None` at a budget some
/// run stopped before.
fn runs_reached(runs: &[&Run], d: usize, targets: usize) -> Vec<Reached> {
    READ_AT
        .iter()
        .map(|&m| {
            let budget = m * d as u64;
            runs.iter().all(|r| r.budget >= budget).then(|| {
                let reached = runs
                    .iter()
                    .map(|r| r.hits.iter().filter(|&&(_, e)| e <= budget).count())
                    .sum();
                (reached, runs.len() * targets)
            })
        })
        .collect()
}

/// The (function, target) pairs whose aRT by the reference `b` is within
/// each budget of [`READ_AT`] at dimension `d`.
fn reference_reached(b: &Best2009, functions: &[usize], d: usize, targets: &[f64]) -> Vec<Reached> {
    READ_AT
        .iter()
        .map(|&m| {
            let budget = (m * d as u64) as f64;
            let reached = functions
                .iter()
                .map(|&f| {
                    targets
                        .iter()
                        .filter(|&&target| b.art(f, d, target).is_some_and(|a| a <= budget))
                        .count()
                })
                .sum();
            Some((reached, functions.len() * targets.len()))
        })
        .collect()
}

/// The anytime measure of one run: the area under its ECDF of the
/// `targets` reached, over x = log10(evaluations / D) from 0 (D
/// evaluations) to log10(budget / D), normalised to [0, 1] (Hansen et al.
/// 2022, "Anytime performance assessment in blackbox optimization
/// benchmarking", IEEE TEVC 26(6):1293–1305; the ECDF is COCO's, Hansen et
/// al. 2021, Optim. Methods Softw. 36(1):114–144).
///
/// A target first reached at evaluation e ≤ budget contributes
/// (x₁ − max(0, log10(e/D))) / x₁ / |targets|, so a run that reaches every
/// target within D evaluations scores 1 and one that reaches none 0; with
/// budget ≤ D it is the fraction of targets reached within the budget.
/// Unlike aRT, which pools the runs, it is a value per run, so two
/// algorithms' runs can be tested against each other; `budget` is the
/// smaller budget of the two compared.
pub(crate) fn run_auc(run: &Run, dim: usize, budget: u64, targets: usize) -> f64 {
    if targets == 0 {
        return f64::NAN;
    }
    let d = dim.max(1) as f64;
    let x1 = (budget as f64 / d).log10();
    let mut area = 0.0;
    for &(_, e) in run.hits.iter().filter(|(_, e)| *e <= budget) {
        area += if x1 > 0.0 {
            (x1 - (e as f64 / d).log10().max(0.0)) / x1
        } else {
            1.0
        };
    }
    area / targets as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(hits: &[(f64, u64)]) -> Run {
        Run {
            run: 0,
            seed: 0,
            budget: 10_000,
            error: 0.0,
            evaluations: 10_000,
            evaluations_to_target: None,
            success: false,
            trace: Vec::new(),
            hits: hits.to_vec(),
            wall_seconds: None,
        }
    }

    #[test]
    fn the_area_under_a_runs_ecdf() {
        // D = 10, budget 10⁴: x runs over [0, 3]. One of two targets at
        // 100 evaluations (x = 1) covers 2/3 of the range: area 1/3.
        let r = run(&[(1e2, 100)]);
        assert!((run_auc(&r, 10, 10_000, 2) - 1.0 / 3.0).abs() < 1e-15);
        // Both within D evaluations: 1; none: 0; a hit after the smaller
        // budget does not count.
        assert_eq!(run_auc(&run(&[(1e2, 5), (1e1, 10)]), 10, 10_000, 2), 1.0);
        assert_eq!(run_auc(&run(&[]), 10, 10_000, 2), 0.0);
        assert_eq!(run_auc(&run(&[(1e2, 5_000)]), 10, 1_000, 2), 0.0);
        // Budget at most D: the fraction reached.
        assert_eq!(run_auc(&run(&[(1e2, 5)]), 10, 10, 2), 0.5);
        assert!(run_auc(&run(&[]), 10, 10, 0).is_nan());
    }

    #[test]
    fn the_art_rows_pool_the_runs_of_a_function() {
        use crate::experiment::RunRecord;
        use crate::optim::TargetHit;
        // Two runs of 1000 evaluations on f at D = 2: the first reaches
        // 10² at 10 and 10⁰ at 400, the second 10² at 30 only.
        let record = |run: u32, hits: &[(f64, u64)]| RunRecord {
            hits: hits
                .iter()
                .map(|&(precision, evaluations)| TargetHit {
                    precision,
                    evaluations,
                })
                .collect(),
            ..crate::test_records::record("A", "f", run, 1.0)
        };
        let ds = Dataset::from_records(vec![
            (record(0, &[(1e2, 10), (1e0, 400)]), false),
            (record(1, &[(1e2, 30)]), false),
        ]);
        let rows = art_rows(&ds, &[1e2, 1e0, 1e-2], &[]).unwrap();
        assert_eq!(rows.len(), 1);
        assert!(matches!(rows[0].who, Who::Cell(0)));
        assert_eq!((rows[0].function.as_str(), rows[0].dim), ("f", 2));
        let points: Vec<(usize, usize, Option<f64>)> = rows[0]
            .points
            .iter()
            .map(|p| (p.runs, p.reached, p.art))
            .collect();
        // aRT: (10 + 30) / 2; (400 + 1000) / 1; none reached 10⁻².
        assert_eq!(
            points,
            [(2, 2, Some(20.0)), (2, 1, Some(1400.0)), (2, 0, None)]
        );
        // Without hits there are no rows.
        let none = Dataset::from_records(vec![(record(0, &[]), false)]);
        assert!(art_rows(&none, &[1e2], &[]).is_none());
    }
}
