//! The anytime view of a campaign: COCO's average runtime aRT to each target
//! precision, from the exact hits of `hits.csv` (Hansen et al. 2021, "COCO:
//! a platform for comparing continuous optimizers in a black-box setting",
//! Optim. Methods Softw. 36(1); Auger & Hansen 2005 for aRT).
//!
//! For one algorithm on one function (pooled over its instances and
//! budgets), the aRT to a target is the evaluations of all runs until they
//! reached it, or until they ended when they did not, divided by the number
//! of runs that reached it; it is infinite when none did.

use std::collections::BTreeMap;

use super::best2009::{self, Best2009};
use super::data::{Dataset, Run};
use super::format::{csv_real, evaluations, percent, pow_tick, Table};

/// The targets shown in the Markdown table (all are in the CSV file).
const SHOWN: [f64; 6] = [1e2, 1e0, 1e-2, 1e-4, 1e-6, 1e-8];

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

/// The aRT to each of `targets` of every algorithm on every function,
/// dimension and transform, with a row of each of COCO's references in
/// `best` (best 2009, best 2009–16) under every bbob function and dimension
/// it covers; `None` when no run has hits.
pub(crate) fn art_table(ds: &Dataset, targets: &[f64], best: &[Best2009]) -> Option<Table> {
    let any = (0..ds.problems.len())
        .any(|p| (0..ds.cells.len()).any(|c| ds.runs(p, c).iter().any(|r| !r.hits.is_empty())));
    if !any {
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
    let shown: Vec<usize> = SHOWN
        .iter()
        .filter_map(|s| targets.iter().position(|t| (t / s - 1.0).abs() < 1e-9))
        .collect();
    let mut t = Table {
        stem: "art_targets".into(),
        title: "Average runtime to each target".into(),
        intro: vec![format!(
            "COCO's average runtime aRT (evaluations of all runs until they reached the \
             target, or until they ended, divided by the number of runs that reached it; \
             — when none did) to the target precisions Δf above f*, per algorithm and \
             function, pooled over instances and budgets. The table shows six of the {} \
             targets; tables/art_targets.csv has all of them.{}",
            targets.len(),
            best.iter()
                .map(|b| format!(
                    " The row {} is {}, the smallest aRT any of them reached on the \
                     function ({}; beyond the thesis).",
                    b.label, b.what, b.source
                ))
                .chain((!best.is_empty()).then(|| {
                    " In the CSV file a reference's `runs` and `reached` are those of \
                     the algorithm that was best for the target."
                        .to_owned()
                }))
                .collect::<String>()
        )],
        md_header: ["Function", "D", "Transform", "Algorithm"]
            .map(String::from)
            .into_iter()
            .chain(shown.iter().map(|&i| format!("aRT Δf={:.0e}", targets[i])))
            .collect(),
        csv_header: [
            "function",
            "dim",
            "transform",
            "algorithm",
            "kind",
            "params",
            "target",
            "runs",
            "reached",
            "art",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    for ((function, dim, transform), problems) in &groups {
        for (c, cell) in ds.cells.iter().enumerate() {
            let runs: Vec<&Run> = problems.iter().flat_map(|&p| ds.runs(p, c)).collect();
            if runs.is_empty() {
                continue;
            }
            let arts: Vec<(usize, Option<f64>)> =
                targets.iter().map(|&target| art(&runs, target)).collect();
            let mut md = vec![
                function.clone(),
                dim.to_string(),
                transform.clone(),
                cell.name.clone(),
            ];
            md.extend(shown.iter().map(|&i| evaluations(arts[i].1)));
            t.md_rows.push(md);
            for (target, (reached, art)) in targets.iter().zip(&arts) {
                t.csv_rows.push(vec![
                    function.clone(),
                    dim.to_string(),
                    transform.clone(),
                    cell.label.clone(),
                    cell.kind.clone(),
                    cell.params.clone(),
                    csv_real(*target),
                    runs.len().to_string(),
                    reached.to_string(),
                    art.map_or_else(|| "inf".into(), csv_real),
                ]);
            }
        }
        for (b, (f, d)) in best
            .iter()
            .zip(std::iter::repeat(best2009::bbob_key(function)))
            .filter_map(|(b, k)| Some((b, k?)))
        {
            if b.covers(f, d) {
                let steps: Vec<Option<best2009::Step>> =
                    targets.iter().map(|&target| b.step(f, d, target)).collect();
                let mut md = vec![
                    function.clone(),
                    dim.to_string(),
                    transform.clone(),
                    b.label.to_owned(),
                ];
                md.extend(shown.iter().map(|&i| evaluations(steps[i].map(|s| s.art))));
                t.md_rows.push(md);
                for (target, step) in targets.iter().zip(&steps) {
                    t.csv_rows.push(vec![
                        function.clone(),
                        dim.to_string(),
                        transform.clone(),
                        b.label.to_owned(),
                        "reference".to_owned(),
                        b.source.to_owned(),
                        csv_real(*target),
                        step.map_or(15, |s| s.runs).to_string(),
                        step.map_or(0, |s| s.successes).to_string(),
                        step.map_or_else(|| "inf".into(), |s| csv_real(s.art)),
                    ]);
                }
            }
        }
    }
    Some(t)
}

/// (targets reached, pairs) at one budget, `None` where the runs stopped
/// before it.
type Reached = Option<(usize, usize)>;

/// The budgets, as multiples of D, at which [`reached_table`] reads the
/// fraction of targets reached.
const READ_AT: [u64; 3] = [100, 1_000, 10_000];

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
pub(crate) fn reached_table(ds: &Dataset, targets: &[f64], best: &[Best2009]) -> Option<Table> {
    let keys: Vec<(usize, usize)> = ds
        .problems
        .iter()
        .map(|p| best2009::bbob_key(&p.function))
        .collect::<Option<_>>()?;
    if best.is_empty()
        || keys
            .iter()
            .any(|&(f, d)| best.iter().any(|b| !b.covers(f, d)))
        || !(0..ds.problems.len())
            .any(|p| (0..ds.cells.len()).any(|c| ds.runs(p, c).iter().any(|r| !r.hits.is_empty())))
    {
        return None;
    }
    let mut dims: Vec<usize> = keys.iter().map(|k| k.1).collect();
    dims.sort_unstable();
    dims.dedup();
    let mut t = Table {
        stem: "targets_reached".into(),
        title: "Targets reached at 10²·D, 10³·D and 10⁴·D evaluations".into(),
        intro: vec![format!(
            "The fraction of (function, target) pairs reached within 10²·D, 10³·D and \
             10⁴·D evaluations, over the {n} targets Δf = 10² … 10⁻⁸ and the functions of \
             the campaign at each D: for an algorithm, the fraction of its (run, target) \
             pairs over all instances (the height of its runtime ECDF there); for {label}, \
             the fraction of (function, target) pairs whose aRT is within the budget, as \
             cocopp draws the reference's ECDF. — where the runs' budget is smaller.{refs}",
            n = targets.len(),
            label = best
                .iter()
                .map(|b| b.label)
                .collect::<Vec<_>>()
                .join(" and "),
            refs = best
                .iter()
                .map(|b| format!(
                    " {} is {} ({}), beyond the thesis.",
                    b.label, b.what, b.source
                ))
                .collect::<String>(),
        )],
        md_header: ["D", "Algorithm", "functions"]
            .map(String::from)
            .into_iter()
            .chain(
                READ_AT
                    .iter()
                    .map(|&m| format!("at {}·D", pow_tick((m as f64).log10()))),
            )
            .collect(),
        csv_header: [
            "dim",
            "algorithm",
            "kind",
            "functions",
            "evaluations_per_dim",
            "pairs",
            "reached",
            "fraction",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    for &d in &dims {
        let problems: Vec<usize> = (0..ds.problems.len()).filter(|&p| keys[p].1 == d).collect();
        let mut functions: Vec<usize> = problems.iter().map(|&p| keys[p].0).collect();
        functions.sort_unstable();
        functions.dedup();
        let mut rows: Vec<(String, String, Vec<Reached>)> = Vec::new();
        for (c, cell) in ds.cells.iter().enumerate() {
            let runs: Vec<&Run> = problems.iter().flat_map(|&p| ds.runs(p, c)).collect();
            if runs.is_empty() {
                continue;
            }
            let counts = READ_AT
                .iter()
                .map(|&m| {
                    let budget = m * d as u64;
                    runs.iter().all(|r| r.budget >= budget).then(|| {
                        let reached = runs
                            .iter()
                            .map(|r| r.hits.iter().filter(|&&(_, e)| e <= budget).count())
                            .sum();
                        (reached, runs.len() * targets.len())
                    })
                })
                .collect();
            rows.push((cell.label.clone(), cell.kind.clone(), counts));
        }
        for best in best {
            let counts = READ_AT
                .iter()
                .map(|&m| {
                    let budget = (m * d as u64) as f64;
                    let reached = functions
                        .iter()
                        .map(|&f| {
                            targets
                                .iter()
                                .filter(|&&target| {
                                    best.art(f, d, target).is_some_and(|a| a <= budget)
                                })
                                .count()
                        })
                        .sum();
                    Some((reached, functions.len() * targets.len()))
                })
                .collect();
            rows.push((best.label.to_owned(), "reference".to_owned(), counts));
        }
        for (label, kind, counts) in rows {
            let mut md = vec![d.to_string(), label.clone(), functions.len().to_string()];
            md.extend(
                counts.iter().map(|c| {
                    c.map_or_else(|| "—".to_owned(), |(r, n)| percent(r as f64 / n as f64))
                }),
            );
            t.md_rows.push(md);
            for (&m, c) in READ_AT.iter().zip(&counts) {
                let Some((reached, pairs)) = c else { continue };
                t.csv_rows.push(vec![
                    d.to_string(),
                    label.clone(),
                    kind.clone(),
                    functions.len().to_string(),
                    m.to_string(),
                    pairs.to_string(),
                    reached.to_string(),
                    csv_real(*reached as f64 / *pairs as f64),
                ]);
            }
        }
    }
    Some(t)
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
}
