//! The cumulative difference-plot of two samples (Arza, Ceberio, Irurozki &
//! Pérez, "Comparing two samples through stochastic dominance: a graphical
//! approach", Journal of Computational and Graphical Statistics 32(2),
//! 2023, doi:10.1080/10618600.2022.2084405; the view IOHanalyzer draws
//! through the authors' R package RVCompare).
//!
//! Pool the `n` values of A and the `m` values of B (lower is better) and
//! sort them: N = n + m positions. A value whose tie group occupies the
//! sorted positions i + 1 … j is spread uniformly over the interval
//! [i/N, j/N] of [0, 1] (so tied values of A and B sit at the same place),
//! which makes Y_A, the position of a value of A, a random variable on
//! [0, 1] with a piecewise-linear distribution function F_A; likewise F_B.
//! The plot is diff(x) = F_A(x) − F_B(x) on [0, 1]: positive where A holds
//! more of the best positions up to x (at x the best fraction x of the pooled
//! sample), negative where B does; 0 everywhere when the two samples are the
//! same. Its integral over [0, 1] is (mean position of B − mean position of
//! A), which for n = m is P(A < B) + ½ P(A = B) − ½.
//!
//! Over several problems (whose values are not comparable with one another)
//! the ranks are taken within each problem and the curves averaged: the
//! equal-weight mixture of the problems' rank distributions.

use crate::format::{csv_real, Table};
use crate::rng::{run_rng, Draw};
use crate::stats::quantile_sorted;

/// The points at which the curve is evaluated: x = k / (GRID − 1).
pub(crate) const GRID: usize = 101;

/// One problem's two samples (lower is better), and whether they pair run
/// by run (the bootstrap then resamples pairs).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Samples {
    /// The values of A.
    pub a: Vec<f64>,
    /// The values of B.
    pub b: Vec<f64>,
    /// Whether `a[i]` and `b[i]` come from the same seed.
    pub paired: bool,
}

/// The estimated cumulative difference with its confidence band.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct CumulativeDifference {
    /// The grid x = 0, 1/(GRID − 1), …, 1.
    pub x: Vec<f64>,
    /// diff(x) = F_A(x) − F_B(x), averaged over the problems.
    pub diff: Vec<f64>,
    /// The lower end of the band at each x.
    pub low: Vec<f64>,
    /// The upper end of the band at each x.
    pub high: Vec<f64>,
    /// ∫₀¹ diff(x) dx (trapezoid rule on the grid, exact for the
    /// piecewise-linear curve up to the grid's resolution).
    pub area: f64,
    /// The confidence level of each pointwise interval of the band.
    pub pointwise_level: f64,
}

/// The cumulative difference of `problems` with a bootstrap band: the
/// estimate diff(x) = mean over problems of F_A(x) − F_B(x) (see the
/// module's documentation), and at every x the percentile interval of
/// `resamples` bootstrap replicates (each problem's samples resampled with
/// replacement, as pairs where they pair by design, independently
/// otherwise) at the pointwise level √(1 − α), the level RVCompare's
/// `get_Y_AB_bounds_bootstrap` uses so that the bands of F_A and F_B hold
/// together at 1 − α. It is a pointwise band, not a simultaneous one.
/// The replicates come from `seed`, so the band is reproducible. `None`
/// when no problem has a value on both sides or a value is NaN.
pub(crate) fn cumulative_difference(
    problems: &[Samples],
    alpha: f64,
    resamples: usize,
    seed: u64,
) -> Option<CumulativeDifference> {
    let used: Vec<&Samples> = problems
        .iter()
        .filter(|s| !s.a.is_empty() && !s.b.is_empty())
        .collect();
    if used.is_empty()
        || used
            .iter()
            .any(|s| s.a.iter().chain(&s.b).any(|v| v.is_nan()))
    {
        return None;
    }
    let x: Vec<f64> = (0..GRID).map(|k| k as f64 / (GRID - 1) as f64).collect();
    let diff = mean_difference(used.iter().map(|s| (s.a.clone(), s.b.clone())), &x);
    let mut rng = run_rng(seed);
    let mut replicates: Vec<Vec<f64>> = (0..GRID).map(|_| Vec::with_capacity(resamples)).collect();
    for _ in 0..resamples {
        let drawn: Vec<(Vec<f64>, Vec<f64>)> = used.iter().map(|s| resample(s, &mut rng)).collect();
        for (column, d) in replicates
            .iter_mut()
            .zip(mean_difference(drawn.into_iter(), &x))
        {
            column.push(d);
        }
    }
    let pointwise_level = (1.0 - alpha).sqrt();
    let tail = (1.0 - pointwise_level) / 2.0;
    let mut low = Vec::with_capacity(GRID);
    let mut high = Vec::with_capacity(GRID);
    for (k, column) in replicates.iter_mut().enumerate() {
        column.sort_by(f64::total_cmp);
        low.push(quantile_sorted(column, tail).unwrap_or(diff[k]));
        high.push(quantile_sorted(column, 1.0 - tail).unwrap_or(diff[k]));
    }
    let step = 1.0 / (GRID - 1) as f64;
    let area = diff.windows(2).map(|w| (w[0] + w[1]) * step / 2.0).sum();
    Some(CumulativeDifference {
        x,
        diff,
        low,
        high,
        area,
        pointwise_level,
    })
}

/// One bootstrap replicate of a problem's samples.
fn resample(s: &Samples, rng: &mut impl Draw) -> (Vec<f64>, Vec<f64>) {
    if s.paired && s.a.len() == s.b.len() {
        let picks: Vec<usize> = (0..s.a.len()).map(|_| rng.index(s.a.len())).collect();
        (
            picks.iter().map(|&i| s.a[i]).collect(),
            picks.iter().map(|&i| s.b[i]).collect(),
        )
    } else {
        let a = (0..s.a.len()).map(|_| s.a[rng.index(s.a.len())]).collect();
        let b = (0..s.b.len()).map(|_| s.b[rng.index(s.b.len())]).collect();
        (a, b)
    }
}

/// The mean over problems of F_A − F_B at the points `x`.
fn mean_difference(problems: impl Iterator<Item = (Vec<f64>, Vec<f64>)>, x: &[f64]) -> Vec<f64> {
    let mut sum = vec![0.0; x.len()];
    let mut count = 0usize;
    for (a, b) in problems {
        let (fa, fb) = rank_cdfs(&a, &b, x);
        for (s, (p, q)) in sum.iter_mut().zip(fa.iter().zip(&fb)) {
            *s += p - q;
        }
        count += 1;
    }
    sum.iter().map(|s| s / count.max(1) as f64).collect()
}

/// F_A and F_B at the points `x` of [0, 1]: the distribution functions of
/// the positions of `a`'s and `b`'s values in the pooled sample, a tie group
/// spread uniformly over the positions it occupies.
fn rank_cdfs(a: &[f64], b: &[f64], x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut pooled: Vec<(f64, bool)> = a
        .iter()
        .map(|&v| (v, true))
        .chain(b.iter().map(|&v| (v, false)))
        .collect();
    pooled.sort_by(|p, q| p.0.total_cmp(&q.0));
    let n_total = pooled.len();
    // The share of A (and of B) in every slot [k/N, (k+1)/N]: a tie group's
    // counts spread evenly over its slots.
    let mut share_a = vec![0.0; n_total];
    let mut i = 0;
    while i < n_total {
        let j = i + pooled[i..]
            .iter()
            .take_while(|p| p.0 == pooled[i].0)
            .count();
        let in_a = pooled[i..j].iter().filter(|p| p.1).count();
        let s = in_a as f64 / (j - i) as f64;
        share_a[i..j].iter_mut().for_each(|v| *v = s);
        i = j;
    }
    let cdf = |share: &dyn Fn(usize) -> f64, size: usize| -> Vec<f64> {
        let mut knots = vec![0.0; n_total + 1];
        for k in 0..n_total {
            knots[k + 1] = knots[k] + share(k);
        }
        x.iter()
            .map(|&t| {
                let pos = (t.clamp(0.0, 1.0) * n_total as f64).min(n_total as f64);
                let k = (pos.floor() as usize).min(n_total.saturating_sub(1));
                let within = pos - k as f64;
                (knots[k] + within * share(k)) / size as f64
            })
            .collect()
    };
    (
        cdf(&|k| share_a[k], a.len()),
        cdf(&|k| 1.0 - share_a[k], b.len()),
    )
}

/// The table of the cumulative differences: in `compare.md` one row per
/// shared cell (area, extremes); in the CSV every point of every curve.
pub(crate) fn curves_table() -> Table {
    Table {
        stem: "cumulative_difference".into(),
        title: "Cumulative differences".into(),
        intro: vec![
            "The cumulative difference-plot of every shared configuration (the figures): \
             area is ∫ diff(x) dx (P(A better) + ½ P(tie) − ½ with equal numbers of runs; 0 \
             when alike), max and min the extremes of the curve, and band excludes 0 the \
             fraction of the grid where the pointwise band lies wholly above or below 0. \
             The CSV file holds every curve at x = 0, 0.01, …, 1 with its band."
                .into(),
        ],
        md_header: [
            "Campaigns",
            "Algorithm",
            "Area",
            "Max",
            "Min",
            "Band excludes 0",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: ["comparison", "algorithm", "x", "diff", "low", "high"]
            .map(String::from)
            .to_vec(),
        ..Table::default()
    }
}

/// Adds the curve `c` of `cell` in `comparison` (`A vs B`) to the table of
/// [`curves_table`].
pub(crate) fn add_curve(t: &mut Table, comparison: &str, cell: &str, c: &CumulativeDifference) {
    let max = c.diff.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let min = c.diff.iter().copied().fold(f64::INFINITY, f64::min);
    let excludes = c
        .low
        .iter()
        .zip(&c.high)
        .filter(|(l, h)| **l > 0.0 || **h < 0.0)
        .count() as f64
        / c.x.len() as f64;
    t.md_rows.push(vec![
        comparison.to_owned(),
        cell.to_owned(),
        format!("{:.3}", c.area),
        format!("{max:.3}"),
        format!("{min:.3}"),
        format!("{:.0} %", 100.0 * excludes),
    ]);
    for k in 0..c.x.len() {
        t.csv_rows.push(vec![
            comparison.to_owned(),
            cell.to_owned(),
            csv_real(c.x[k]),
            csv_real(c.diff[k]),
            csv_real(c.low[k]),
            csv_real(c.high[k]),
        ]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Vec<f64> {
        (0..GRID).map(|k| k as f64 / (GRID - 1) as f64).collect()
    }

    #[test]
    fn the_same_sample_is_zero_everywhere_with_a_zero_band_when_paired() {
        let a = vec![3.0, 1.0, 2.0, 2.0, 5.0];
        let s = Samples {
            a: a.clone(),
            b: a,
            paired: true,
        };
        let c = cumulative_difference(&[s], 0.05, 200, 7).unwrap();
        assert!(c.diff.iter().all(|&d| d.abs() < 1e-12), "{:?}", c.diff);
        assert!(c.low.iter().chain(&c.high).all(|&d| d.abs() < 1e-12));
        assert!(c.area.abs() < 1e-12);
    }

    #[test]
    fn a_dominating_sample_rises_to_one_at_the_middle_and_has_area_one_half() {
        let (fa, fb) = rank_cdfs(&[1.0, 2.0], &[3.0, 4.0], &grid());
        // A holds the positions [0, 1/2]: F_A(1/4) = 1/2, F_A(1/2) = 1.
        assert!((fa[25] - 0.5).abs() < 1e-12 && (fa[50] - 1.0).abs() < 1e-12);
        assert!(fb[50].abs() < 1e-12 && (fb[100] - 1.0).abs() < 1e-12);
        let s = Samples {
            a: vec![1.0, 2.0, 1.5],
            b: vec![3.0, 4.0, 3.5],
            paired: false,
        };
        let c = cumulative_difference(&[s], 0.05, 100, 1).unwrap();
        // P(A < B) = 1: the area is 1 − 1/2.
        assert!((c.area - 0.5).abs() < 1e-3, "{}", c.area);
        assert!(c.diff.iter().all(|&d| d >= -1e-12));
    }

    #[test]
    fn the_area_is_the_probability_of_being_better_minus_one_half() {
        // n = m = 4: P(A < B) + ½ P(tie) from the 16 pairs.
        let a = [1.0, 4.0, 6.0, 8.0];
        let b = [2.0, 3.0, 6.0, 9.0];
        let mut p = 0.0;
        for x in a {
            for y in b {
                p += if x < y {
                    1.0
                } else if x == y {
                    0.5
                } else {
                    0.0
                };
            }
        }
        p /= 16.0;
        let s = Samples {
            a: a.to_vec(),
            b: b.to_vec(),
            paired: false,
        };
        let c = cumulative_difference(&[s], 0.05, 10, 1).unwrap();
        assert!(
            (c.area - (p - 0.5)).abs() < 1e-3,
            "{} vs {}",
            c.area,
            p - 0.5
        );
        let again = cumulative_difference(&[c_samples(&a, &b)], 0.05, 10, 1).unwrap();
        assert_eq!(again.low, c.low, "the band is seeded");
    }

    fn c_samples(a: &[f64], b: &[f64]) -> Samples {
        Samples {
            a: a.to_vec(),
            b: b.to_vec(),
            paired: false,
        }
    }
}
