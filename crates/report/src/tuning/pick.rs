//! The pick of a parameter grid: the setting with the lowest mean rank,
//! its runner-up, its stability over bootstrap resamples of the runs, the
//! edges of the grid it lies on and what the grid's runs cost.

use crate::rng::{fnv1a64, run_rng, Draw};

use super::super::data::{param_value, Dataset};
use super::heat_map::sorted_values;
use super::Grid;

/// Bootstrap resamples of the runs behind the stability of a pick.
pub(super) const RESAMPLES: usize = 200;

/// The pick of a grid and how far to trust it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Pick {
    /// Grid index of the pick: the lowest mean rank, the first among ties.
    pub index: usize,
    /// Grid index of the runner-up (the next lowest mean rank), if any.
    pub runner_up: Option<usize>,
    /// The fraction of the bootstrap resamples of the runs that pick the
    /// same setting.
    pub stability: f64,
    /// The setting picked most often instead (the first among ties), with
    /// its fraction of the resamples; `None` when every resample agrees.
    pub instead: Option<(usize, f64)>,
}

/// The index of the smallest value, the first among ties.
pub(super) fn argmin(values: &[f64]) -> usize {
    let mut best = 0;
    for (i, v) in values.iter().enumerate() {
        if v.total_cmp(&values[best]).is_lt() {
            best = i;
        }
    }
    best
}

/// Adds the mid-ranks of `row` (1 = lowest, ties share their average rank)
/// to `sums`; `order` is scratch space.
pub(super) fn add_midranks(row: &[f64], order: &mut Vec<usize>, sums: &mut [f64]) {
    order.clear();
    order.extend(0..row.len());
    order.sort_by(|&a, &b| row[a].total_cmp(&row[b]));
    let mut i = 0;
    while i < order.len() {
        let mut j = i + 1;
        while j < order.len() && row[order[j]] == row[order[i]] {
            j += 1;
        }
        // Positions i..j (0-based) share the ranks i+1..=j.
        let rank = (i + j + 1) as f64 / 2.0;
        for &k in &order[i..j] {
            sums[k] += rank;
        }
        i = j;
    }
}

/// The pick of a grid from its mean ranks `r` over the problems `blocks`,
/// with the runner-up and the stability over [`RESAMPLES`] bootstrap
/// resamples of the runs: each draws, within every (setting, problem), as
/// many runs as it has, with replacement, and recomputes the mean final
/// errors, the ranks and the pick. The draws are seeded by the grid's
/// label, so the same results give the same stability.
pub(super) fn pick(ds: &Dataset, grid: &Grid, blocks: &[usize], r: &[f64]) -> Pick {
    let mut order: Vec<usize> = (0..r.len()).collect();
    order.sort_by(|&a, &b| r[a].total_cmp(&r[b]).then(a.cmp(&b)));
    let index = order[0];
    let samples: Vec<Vec<Vec<f64>>> = blocks
        .iter()
        .map(|&p| grid.cells.iter().map(|&c| ds.errors(p, c)).collect())
        .collect();
    let mut rng = run_rng(fnv1a64(&format!("tuning-bootstrap/{}", grid.label)));
    let mut counts = vec![0usize; r.len()];
    let (mut row, mut sums) = (vec![0.0; r.len()], vec![0.0; r.len()]);
    let mut scratch = Vec::with_capacity(r.len());
    for _ in 0..RESAMPLES {
        sums.fill(0.0);
        for block in &samples {
            for (m, errors) in row.iter_mut().zip(block) {
                let n = errors.len();
                let total: f64 = (0..n).map(|_| errors[rng.index(n)]).sum();
                *m = total / n as f64;
            }
            add_midranks(&row, &mut scratch, &mut sums);
        }
        counts[argmin(&sums)] += 1;
    }
    let share = |k: usize| k as f64 / RESAMPLES as f64;
    let instead = (0..counts.len())
        .filter(|&i| i != index && counts[i] > 0)
        .fold(None, |best: Option<usize>, i| match best {
            Some(b) if counts[b] >= counts[i] => Some(b),
            _ => Some(i),
        })
        .map(|i| (i, share(counts[i])));
    Pick {
        index,
        runner_up: order.get(1).copied(),
        stability: share(counts[index]),
        instead,
    }
}

/// For each varying parameter with three or more numeric values in the
/// grid, whether `cell` takes its smallest or largest value:
/// `hmcr=0.99 (largest of 0.7, 0.9, 0.99)`.
pub(super) fn edges(ds: &Dataset, grid: &Grid, cell: usize) -> Vec<String> {
    let value = |c: usize, k: &str| param_value(&ds.cells[c], k).unwrap_or_default();
    let mut out = Vec::new();
    for k in &grid.varying {
        let values = sorted_values(grid.cells.iter().map(|&c| value(c, k)).collect());
        let numeric = values
            .iter()
            .all(|v| v.parse::<f64>().is_ok_and(f64::is_finite));
        if values.len() < 3 || !numeric {
            continue;
        }
        let v = value(cell, k);
        let side = if values.first() == Some(&v) {
            "smallest"
        } else if values.last() == Some(&v) {
            "largest"
        } else {
            continue;
        };
        out.push(format!("{k}={v} ({side} of {})", values.join(", ")));
    }
    out
}

/// What a grid's runs cost: (runs, evaluations, the sum of their wall
/// times when every run's was recorded).
pub(super) fn cost(ds: &Dataset, grid: &Grid) -> (usize, u128, Option<f64>) {
    let (mut runs, mut evaluations, mut wall) = (0, 0u128, Some(0.0));
    for p in 0..ds.problems.len() {
        for &c in &grid.cells {
            for run in ds.runs(p, c) {
                runs += 1;
                evaluations += u128::from(run.evaluations);
                wall = match (wall, run.wall_seconds) {
                    (Some(w), Some(s)) if ds.has_timing => Some(w + s),
                    _ => None,
                };
            }
        }
    }
    (runs, evaluations, wall.filter(|_| runs > 0))
}
