//! Parameter tuning: grids of cells that share a label and differ in their
//! parameters (e.g. MHS over hmcr × bw), the best setting per problem and
//! overall, and the data of the heat maps.

use std::collections::BTreeMap;

use crate::rng::{fnv1a64, run_rng, Draw};
use crate::stats::friedman;
use metabezier_plot::markdown::thousands;

use super::data::{param_value, varying_params, Dataset};
use super::descriptive::{mean_error, CellStats};
use super::format::{csv_real, fixed2, sci_opt, Table};

/// Bootstrap resamples of the runs behind the stability of a pick.
const RESAMPLES: usize = 200;

/// Cells with one label that differ in their parameters.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Grid {
    /// The shared label.
    pub label: String,
    /// A file-name-safe form of the label, unique among grids.
    pub slug: String,
    /// The cells, in order of appearance.
    pub cells: Vec<usize>,
    /// The parameters whose values differ among the cells.
    pub varying: Vec<String>,
}

impl Grid {
    /// The varying parameters of `cell`: `hmcr=0.7, bw=0.01`.
    pub fn setting(&self, ds: &Dataset, cell: usize) -> String {
        let Some(c) = ds.cells.get(cell) else {
            return String::new();
        };
        self.varying
            .iter()
            .map(|k| format!("{k}={}", param_value(c, k).unwrap_or_else(|| "-".into())))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A file-name part from a label: lower-case letters and digits, `_` for
/// the rest (`grid` when nothing is left).
pub(crate) fn slug(label: &str) -> String {
    let s: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    let s = s.trim_matches('_').to_owned();
    if s.is_empty() {
        "grid".into()
    } else {
        s
    }
}

/// The parameter grids of a dataset, in order of their first cell.
pub(crate) fn grids(ds: &Dataset) -> Vec<Grid> {
    let mut by_label: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    let mut order: Vec<&str> = Vec::new();
    for (i, c) in ds.cells.iter().enumerate() {
        let entry = by_label.entry(c.label.as_str()).or_default();
        if entry.is_empty() {
            order.push(c.label.as_str());
        }
        entry.push(i);
    }
    let mut out: Vec<Grid> = Vec::new();
    let mut slugs: BTreeMap<String, usize> = BTreeMap::new();
    for label in order {
        let cells = by_label.get(label).cloned().unwrap_or_default();
        if cells.len() < 2 {
            continue;
        }
        let refs: Vec<_> = cells.iter().map(|&i| &ds.cells[i]).collect();
        let varying = varying_params(&refs);
        if varying.is_empty() {
            continue;
        }
        let mut s = slug(label);
        let n = slugs.entry(s.clone()).or_insert(0);
        *n += 1;
        if *n > 1 {
            s = format!("{s}_{n}");
        }
        out.push(Grid {
            label: label.to_owned(),
            slug: s,
            cells,
            varying,
        });
    }
    out
}

/// The best cell of `grid` on problem `p`: lowest mean final error, ties
/// broken by the median and then by the order of the cells.
pub(crate) fn best_on_problem(
    grid: &Grid,
    stats: &[Vec<Option<CellStats>>],
    p: usize,
) -> Option<usize> {
    let mut best: Option<(usize, f64, f64)> = None;
    for &c in &grid.cells {
        let Some(s) = stats
            .get(p)
            .and_then(|r| r.get(c))
            .and_then(|x| x.as_ref())
            .and_then(|x| x.summary.as_ref())
        else {
            continue;
        };
        let better = match best {
            None => true,
            Some((_, m, med)) => s.mean.total_cmp(&m).then(s.median.total_cmp(&med)).is_lt(),
        };
        if better {
            best = Some((c, s.mean, s.median));
        }
    }
    best.map(|b| b.0)
}

/// Mean ranks of the grid's settings over the problems on which every
/// setting has a defined mean error: (problems used, rank per grid cell).
pub(crate) fn mean_ranks(
    ds: &Dataset,
    grid: &Grid,
    stats: &[Vec<Option<CellStats>>],
) -> Option<(Vec<usize>, Vec<f64>)> {
    let mut blocks = Vec::new();
    let mut rows = Vec::new();
    for p in 0..ds.problems.len() {
        let row: Option<Vec<f64>> = grid
            .cells
            .iter()
            .map(|&c| mean_error(stats, p, c).filter(|m| !m.is_nan()))
            .collect();
        if let Some(row) = row {
            blocks.push(p);
            rows.push(row);
        }
    }
    let f = friedman(&rows).ok()?;
    Some((blocks, f.average_ranks))
}

/// The best setting of a grid per problem, without the overall row.
fn best_table(ds: &Dataset, grid: &Grid, stats: &[Vec<Option<CellStats>>]) -> Table {
    let params = grid.varying.join(" × ");
    let mut best = Table {
        stem: format!("tuning_best_{}", grid.slug),
        title: format!(
            "Parameter tuning of {}: best setting ({params})",
            grid.label
        ),
        intro: vec![format!(
            "{} settings of {} vary {}. Per problem, the best setting has the lowest \
             mean final error (ties: lowest median). Overall, the best setting has the \
             lowest mean rank over the problems (settings ranked by mean final error \
             within each problem, rank 1 = best).",
            grid.cells.len(),
            grid.label,
            params
        )],
        md_header: ["Problem", "D", "Best setting", "Mean error", "Median error"]
            .map(String::from)
            .to_vec(),
        csv_header: [
            "problem",
            "dim",
            "algorithm",
            "params",
            "setting",
            "mean",
            "median",
            "mean_rank",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    for (p, problem) in ds.problems.iter().enumerate() {
        let Some(c) = best_on_problem(grid, stats, p) else {
            continue;
        };
        let s = stats[p][c].as_ref().and_then(|x| x.summary.as_ref());
        best.md_rows.push(vec![
            problem.short(),
            problem.dim.to_string(),
            grid.setting(ds, c),
            sci_opt(s.map(|x| x.mean)),
            sci_opt(s.map(|x| x.median)),
        ]);
        best.csv_rows.push(vec![
            problem.label(),
            problem.dim.to_string(),
            grid.label.clone(),
            ds.cells[c].params.clone(),
            grid.setting(ds, c),
            s.map_or_else(String::new, |x| csv_real(x.mean)),
            s.map_or_else(String::new, |x| csv_real(x.median)),
            String::new(),
        ]);
    }
    best
}

/// The empty table of the mean ranks of a grid's settings.
fn ranks_frame(grid: &Grid) -> Table {
    Table {
        stem: format!("tuning_ranks_{}", grid.slug),
        title: format!(
            "Parameter tuning of {}: mean rank of every setting",
            grid.label
        ),
        md_header: ["Position", "Setting", "Mean rank"]
            .map(String::from)
            .to_vec(),
        csv_header: ["position", "algorithm", "params", "setting", "mean_rank"]
            .map(String::from)
            .to_vec(),
        ..Table::default()
    }
}

/// Adds the overall row to the best-setting table: the setting of grid
/// index `i`, which has the lowest mean rank of `r`.
fn overall_row(ds: &Dataset, grid: &Grid, r: &[f64], i: usize, best: &mut Table) {
    let c = grid.cells[i];
    let tied = r.iter().filter(|&&x| x == r[i]).count() - 1;
    let mut setting = grid.setting(ds, c);
    if tied > 0 {
        setting.push_str(&format!(
            " (tied with {tied} other setting(s); the first in spec order is shown)"
        ));
    }
    best.md_rows.push(vec![
        "overall (mean rank)".into(),
        String::new(),
        setting,
        format!("rank {}", fixed2(r[i])),
        String::new(),
    ]);
    best.csv_rows.push(vec![
        "overall".into(),
        String::new(),
        grid.label.clone(),
        ds.cells[c].params.clone(),
        grid.setting(ds, c),
        String::new(),
        String::new(),
        csv_real(r[i]),
    ]);
}

/// The tables of a grid: the best setting per problem and overall, the
/// mean rank of every setting, and the pick with its stability, its edges
/// and its cost.
pub(crate) fn tables(ds: &Dataset, grid: &Grid, stats: &[Vec<Option<CellStats>>]) -> Vec<Table> {
    let mut best = best_table(ds, grid, stats);
    let mut ranks = ranks_frame(grid);
    let mut picks = picks_frame(ds, grid);
    let Some((blocks, r)) = mean_ranks(ds, grid, stats) else {
        ranks.intro.push(
            "No problem was run by every setting with a defined mean error: no ranks.".into(),
        );
        picks.intro.insert(
            0,
            "No problem was run by every setting with a defined mean error: no pick.".into(),
        );
        return vec![best, ranks, picks];
    };
    let pick = pick(ds, grid, &blocks, &r);
    picks_rows(ds, grid, &blocks, &r, &pick, &mut picks);
    ranks.intro.push(format!(
        "Mean rank of the mean final error over the {} problem(s) run by every \
         setting (rank 1 = lowest error, ties share the average rank).",
        blocks.len()
    ));
    let mut order: Vec<usize> = (0..r.len()).collect();
    order.sort_by(|&a, &b| r[a].total_cmp(&r[b]).then(a.cmp(&b)));
    for (pos, &i) in order.iter().enumerate() {
        let c = grid.cells[i];
        ranks.md_rows.push(vec![
            (pos + 1).to_string(),
            grid.setting(ds, c),
            fixed2(r[i]),
        ]);
        ranks.csv_rows.push(vec![
            (pos + 1).to_string(),
            grid.label.clone(),
            ds.cells[c].params.clone(),
            grid.setting(ds, c),
            csv_real(r[i]),
        ]);
    }
    if let Some(&i) = order.first() {
        overall_row(ds, grid, &r, i, &mut best);
    }
    vec![best, ranks, picks]
}

/// The overview of several grids, which `report.md` shows in place of
/// their own tables (those stay in `tables/`): the pick of every grid, one
/// row each, and the best setting of every grid per problem, one column
/// each. `per_grid` holds each grid's [`tables`] (best, ranks, picks).
pub(crate) fn overview(per_grid: &[(Grid, Vec<Table>)]) -> Vec<Table> {
    let mut picks = Table {
        stem: "tuning_picks".into(),
        title: "Parameter tuning: the pick of every algorithm".into(),
        intro: Vec::new(),
        md_header: vec!["Algorithm".into()],
        md_rows: Vec::new(),
        csv_header: vec!["grid".into()],
        csv_rows: Vec::new(),
    };
    let mut best = Table {
        stem: "tuning_best".into(),
        title: "Parameter tuning: the best setting of every algorithm per problem".into(),
        intro: vec![
            "Per problem, the setting of each algorithm's grid with the lowest mean final \
             error (ties: lowest median); the last row is the pick over all problems \
             (lowest mean rank). Each grid's errors are in tables/tuning_best_<algorithm>.csv."
                .into(),
        ],
        md_header: vec!["Problem".into(), "D".into()],
        ..Table::default()
    };
    let mut rows: Vec<(String, String)> = Vec::new();
    for (_, tables) in per_grid {
        let Some(b) = tables.first() else { continue };
        for r in &b.md_rows {
            let key = (r[0].clone(), r[1].clone());
            if !rows.contains(&key) {
                rows.push(key);
            }
        }
    }
    best.md_rows = rows
        .iter()
        .map(|(p, d)| vec![p.clone(), d.clone()])
        .collect();
    best.csv_header = vec!["problem".into(), "dim".into()];
    for (grid, tables) in per_grid {
        best.md_header.push(grid.label.clone());
        best.csv_header.push(grid.label.clone());
        let b = tables.first();
        for (row, (p, d)) in best.md_rows.iter_mut().zip(&rows) {
            let setting = b
                .and_then(|b| b.md_rows.iter().find(|r| r[0] == *p && r[1] == *d))
                .map_or_else(|| "—".to_owned(), |r| r[2].clone());
            row.push(setting);
        }
        let Some(t) = tables.get(2) else { continue };
        if picks.md_header.len() == 1 {
            picks.md_header.extend(t.md_header.iter().cloned());
            picks.csv_header.extend(t.csv_header.iter().cloned());
            picks.intro = t.intro.iter().take(1).cloned().collect();
            picks.intro.push(
                "The cost of each grid and the caution on an unstable pick are beside its \
                 own table, tables/tuning_picks_<algorithm>.csv."
                    .into(),
            );
        }
        for r in &t.md_rows {
            picks.md_rows.push(
                std::iter::once(grid.label.clone())
                    .chain(r.iter().cloned())
                    .collect(),
            );
        }
        for r in &t.csv_rows {
            picks.csv_rows.push(
                std::iter::once(grid.label.clone())
                    .chain(r.iter().cloned())
                    .collect(),
            );
        }
    }
    best.csv_rows = best.md_rows.clone();
    vec![picks, best]
}

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
fn argmin(values: &[f64]) -> usize {
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
fn add_midranks(row: &[f64], order: &mut Vec<usize>, sums: &mut [f64]) {
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
fn pick(ds: &Dataset, grid: &Grid, blocks: &[usize], r: &[f64]) -> Pick {
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
fn edges(ds: &Dataset, grid: &Grid, cell: usize) -> Vec<String> {
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
fn cost(ds: &Dataset, grid: &Grid) -> (usize, u128, Option<f64>) {
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

/// A wall time in seconds, with minutes or hours when long: `754.2 s
/// (12.6 min)`.
fn duration(seconds: f64) -> String {
    if seconds >= 3600.0 {
        format!("{seconds:.1} s ({:.2} h)", seconds / 3600.0)
    } else if seconds >= 60.0 {
        format!("{seconds:.1} s ({:.1} min)", seconds / 60.0)
    } else {
        format!("{seconds:.1} s")
    }
}

/// The picks table of a grid, with its headers and the paragraph on its
/// cost; the rows come from [`picks_rows`].
fn picks_frame(ds: &Dataset, grid: &Grid) -> Table {
    let (runs, evaluations, wall) = cost(ds, grid);
    let wall = match wall {
        Some(w) => format!(
            "{} of wall time (the sum of the runs' times, i.e. on one thread)",
            duration(w)
        ),
        None => "wall time not recorded (no timing.csv)".to_owned(),
    };
    Table {
        stem: format!("tuning_picks_{}", grid.slug),
        title: format!(
            "Parameter tuning of {}: the pick, its stability and its edges",
            grid.label
        ),
        intro: vec![format!(
            "Cost of the tuning: the {} runs of the {} settings of {} used {} \
             evaluations and {wall}.",
            thousands(runs as u128),
            grid.cells.len(),
            grid.label,
            thousands(evaluations)
        )],
        md_header: [
            "Pick",
            "Mean rank",
            "Runner-up",
            "Its mean rank",
            "Stability",
            "Picked instead",
            "On the edge of its grid",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "algorithm",
            "params",
            "setting",
            "mean_rank",
            "runner_up",
            "runner_up_params",
            "runner_up_mean_rank",
            "stability",
            "instead",
            "instead_share",
            "resamples",
            "edge",
            "problems",
            "runs",
            "evaluations",
            "wall_seconds",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// Fills the picks table of a grid: the paragraphs on the pick and its
/// stability, the warning of an edge, and the row.
fn picks_rows(ds: &Dataset, grid: &Grid, blocks: &[usize], r: &[f64], pick: &Pick, t: &mut Table) {
    let c = grid.cells[pick.index];
    t.intro.insert(
        0,
        format!(
            "The pick is the setting with the lowest mean rank over the {} problem(s) \
             (ties: the first in spec order), the runner-up the next. Stability is the \
             fraction of {RESAMPLES} bootstrap resamples of the runs that pick the same \
             setting: each resample draws, within every setting and problem, as many runs \
             as it has, with replacement, and recomputes the mean final errors, the ranks \
             and the pick (seeded by the grid's label, so the same results give the same \
             table). Well below 1, the runs do not single the pick out: \"picked instead\" \
             names the setting the resamples chose most often in its place.",
            blocks.len()
        ),
    );
    if pick.stability < 0.5 {
        let instead = pick.instead.map_or_else(String::new, |(i, share)| {
            format!(
                ", and {} is picked in {share:.3} of them",
                grid.setting(ds, grid.cells[i])
            )
        });
        t.intro.push(format!(
            "Caution: only {:.3} of the resamples pick {}{instead}: these runs do not \
             single out a best setting.",
            pick.stability,
            grid.setting(ds, c)
        ));
    }
    let edge = edges(ds, grid, c);
    if !edge.is_empty() {
        t.intro.push(format!(
            "Warning: the pick {} is on the edge of its grid ({}): the best setting \
             may lie outside it.",
            grid.setting(ds, c),
            edge.join("; ")
        ));
    }
    let (runs, evaluations, wall) = cost(ds, grid);
    let runner = pick.runner_up;
    let setting =
        |i: Option<usize>| i.map_or_else(String::new, |i| grid.setting(ds, grid.cells[i]));
    let rank = |i: Option<usize>| i.map(|i| r[i]);
    let instead = match pick.instead {
        Some((i, share)) => format!("{} ({share:.3})", grid.setting(ds, grid.cells[i])),
        None => "none".into(),
    };
    t.md_rows.push(vec![
        grid.setting(ds, c),
        fixed2(r[pick.index]),
        setting(runner),
        rank(runner).map_or_else(String::new, fixed2),
        format!("{:.3}", pick.stability),
        instead,
        if edge.is_empty() {
            "no".into()
        } else {
            edge.join("; ")
        },
    ]);
    t.csv_rows.push(vec![
        grid.label.clone(),
        ds.cells[c].params.clone(),
        grid.setting(ds, c),
        csv_real(r[pick.index]),
        setting(runner),
        runner.map_or_else(String::new, |i| ds.cells[grid.cells[i]].params.clone()),
        rank(runner).map_or_else(String::new, csv_real),
        csv_real(pick.stability),
        pick.instead
            .map_or_else(String::new, |(i, _)| grid.setting(ds, grid.cells[i])),
        pick.instead.map_or_else(String::new, |(_, s)| csv_real(s)),
        RESAMPLES.to_string(),
        edge.join("; "),
        blocks.len().to_string(),
        runs.to_string(),
        evaluations.to_string(),
        wall.map_or_else(String::new, csv_real),
    ]);
}

/// One problem's panel of a heat map.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HeatPanel {
    /// The problem's title.
    pub title: String,
    /// Mean final error, `mean[y][x]`; `None` where undefined.
    pub mean: Vec<Vec<Option<f64>>>,
    /// The best cell (y, x), if any.
    pub best: Option<(usize, usize)>,
}

/// The data of one heat map: mean final error over a two-parameter grid,
/// one panel per problem.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct HeatMap {
    /// The grid's label.
    pub label: String,
    /// File-name-safe label.
    pub slug: String,
    /// Parameter on the horizontal axis.
    pub x_param: String,
    /// Parameter on the vertical axis.
    pub y_param: String,
    /// Its values, in increasing order when numeric.
    pub x_values: Vec<String>,
    /// Its values, in increasing order when numeric.
    pub y_values: Vec<String>,
    /// Per problem: title, `mean[y][x]` and the best (y, x).
    pub panels: Vec<HeatPanel>,
    /// For a grid of more than two parameters, the other parameters and the
    /// values at which the map slices the grid (those of the overall best
    /// setting); empty for a two-parameter grid.
    pub fixed: Vec<(String, String)>,
}

/// The two axes of a grid's heat map: `hmcr` × `bw` when both vary (the
/// classical HS tuning pair), else the first two varying parameters.
fn heat_axes(grid: &Grid) -> Option<(String, String)> {
    let has = |k: &str| grid.varying.iter().any(|v| v == k);
    if has("hmcr") && has("bw") {
        return Some(("hmcr".into(), "bw".into()));
    }
    match grid.varying.as_slice() {
        [a, b, ..] => Some((a.clone(), b.clone())),
        _ => None,
    }
}

fn sorted_values(values: Vec<String>) -> Vec<String> {
    let mut v: Vec<String> = Vec::new();
    for x in values {
        if !v.contains(&x) {
            v.push(x);
        }
    }
    let numeric: Option<Vec<f64>> = v.iter().map(|s| s.parse::<f64>().ok()).collect();
    if let Some(nums) = numeric {
        let mut pairs: Vec<(f64, String)> = nums.into_iter().zip(v).collect();
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        pairs.into_iter().map(|p| p.1).collect()
    } else {
        v
    }
}

/// The heat map of a grid that varies at least two parameters.
///
/// With more than two, the map is the slice of the grid through the overall
/// best setting (lowest mean rank, [`mean_ranks`]): the parameters off the
/// axes keep that setting's values, and [`HeatMap::fixed`] names them.
pub(crate) fn heat_map(
    ds: &Dataset,
    grid: &Grid,
    stats: &[Vec<Option<CellStats>>],
) -> Option<HeatMap> {
    let (xp, yp) = heat_axes(grid)?;
    let value = |c: usize, k: &str| param_value(&ds.cells[c], k).unwrap_or_else(|| "-".into());
    let mut fixed: Vec<(String, String)> = Vec::new();
    if grid.varying.len() > 2 {
        let (_, ranks) = mean_ranks(ds, grid, stats)?;
        let mut order: Vec<usize> = (0..ranks.len()).collect();
        order.sort_by(|&a, &b| ranks[a].total_cmp(&ranks[b]).then(a.cmp(&b)));
        let best = grid.cells[*order.first()?];
        fixed = grid
            .varying
            .iter()
            .filter(|k| **k != xp && **k != yp)
            .map(|k| (k.clone(), value(best, k)))
            .collect();
    }
    let slice: Vec<usize> = grid
        .cells
        .iter()
        .copied()
        .filter(|&c| fixed.iter().all(|(k, v)| value(c, k) == *v))
        .collect();
    let grid = &Grid {
        cells: slice,
        ..grid.clone()
    };
    let (xp, yp) = (&xp, &yp);
    let x_values = sorted_values(grid.cells.iter().map(|&c| value(c, xp)).collect());
    let y_values = sorted_values(grid.cells.iter().map(|&c| value(c, yp)).collect());
    let mut panels = Vec::new();
    for (p, problem) in ds.problems.iter().enumerate() {
        let mut m = vec![vec![None; x_values.len()]; y_values.len()];
        let mut any = false;
        let mut best_pos = None;
        let best = best_on_problem(grid, stats, p);
        for &c in &grid.cells {
            let xi = x_values.iter().position(|v| *v == value(c, xp));
            let yi = y_values.iter().position(|v| *v == value(c, yp));
            if let (Some(xi), Some(yi)) = (xi, yi) {
                let mean = mean_error(stats, p, c).filter(|v| !v.is_nan());
                any |= mean.is_some();
                m[yi][xi] = mean;
                if best == Some(c) {
                    best_pos = Some((yi, xi));
                }
            }
        }
        if any {
            panels.push(HeatPanel {
                title: problem.title(),
                mean: m,
                best: best_pos,
            });
        }
    }
    if panels.is_empty() {
        return None;
    }
    Some(HeatMap {
        label: grid.label.clone(),
        slug: grid.slug.clone(),
        x_param: xp.clone(),
        y_param: yp.clone(),
        x_values,
        y_values,
        panels,
        fixed,
    })
}

/// A compact text of a mean error for a heat-map cell: `1.2e-03`.
pub(crate) fn cell_label(v: f64) -> String {
    super::format::sci_digits(v, 2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::descriptive::compute;
    use crate::experiment::RunRecord;

    fn rec(alg: &str, params: &str, problem: &str, run: u32, error: f64) -> (RunRecord, bool) {
        (
            RunRecord {
                algorithm: alg.into(),
                kind: "mhs".into(),
                params: params.into(),
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

    #[test]
    fn grid_best_settings_and_heat_map() {
        let mut v = Vec::new();
        for run in 0..3 {
            for (hmcr, bw, e1, e2) in [
                ("0.9", "0.1", 1.0, 4.0),
                ("0.7", "0.1", 2.0, 1.0),
                ("0.9", "0.01", 0.5, 3.0),
                ("0.7", "0.01", 3.0, 2.0),
            ] {
                let params = format!("hms=5;hmcr={hmcr};bw={bw}");
                v.push(rec("MHS", &params, "f", run, e1));
                v.push(rec("MHS", &params, "g", run, e2));
            }
            v.push(rec("HS", "hms=5", "f", run, 9.0));
        }
        let ds = Dataset::from_records(v);
        let stats = compute(&ds);
        let g = grids(&ds);
        assert_eq!(g.len(), 1);
        assert_eq!(g[0].varying, ["hmcr", "bw"]);
        let t = tables(&ds, &g[0], &stats);
        assert_eq!(t[0].md_rows[0][2], "hmcr=0.9, bw=0.01");
        assert_eq!(t[0].md_rows[1][2], "hmcr=0.7, bw=0.1");
        // Ranks on f and g: (0.9,0.1): 2,4 → 3; (0.7,0.1): 3,1 → 2; (0.9,0.01):
        // 1,3 → 2; (0.7,0.01): 4,2 → 3. The tie goes to the first setting.
        assert_eq!(
            t[0].md_rows[2][2],
            "hmcr=0.7, bw=0.1 (tied with 1 other setting(s); the first in spec order is shown)"
        );
        assert_eq!(t[0].md_rows[2][3], "rank 2.00");
        assert_eq!(t[1].md_rows[0][1], "hmcr=0.7, bw=0.1");
        assert_eq!(t[1].md_rows[1][1], "hmcr=0.9, bw=0.01");
        assert_eq!(t[1].md_rows[3][1], "hmcr=0.7, bw=0.01");
        let h = heat_map(&ds, &g[0], &stats).unwrap();
        assert_eq!(h.x_values, ["0.7", "0.9"]);
        assert_eq!(h.y_values, ["0.01", "0.1"]);
        assert_eq!(h.panels[0].mean[0][1], Some(0.5));
        assert_eq!(h.panels[0].best, Some((0, 1)));
    }

    #[test]
    fn a_wider_grid_is_mapped_through_its_best_setting() {
        // l varies too: l=3 is better everywhere, so the hmcr × bw map is the
        // l=3 slice, whatever order the parameters come in.
        let mut v = Vec::new();
        for run in 0..2 {
            for l in ["1", "3"] {
                for (bw, hmcr, e) in [
                    ("0.1", "0.9", 4.0),
                    ("0.1", "0.7", 3.0),
                    ("0.01", "0.9", 2.0),
                ] {
                    let e = if l == "3" { e / 10.0 } else { e };
                    let params = format!("l={l};bw={bw};hmcr={hmcr}");
                    v.push(rec("MHS", &params, "f", run, e));
                }
            }
        }
        let ds = Dataset::from_records(v);
        let stats = compute(&ds);
        let g = grids(&ds);
        assert_eq!(g[0].varying, ["l", "bw", "hmcr"]);
        let h = heat_map(&ds, &g[0], &stats).unwrap();
        assert_eq!((h.x_param.as_str(), h.y_param.as_str()), ("hmcr", "bw"));
        assert_eq!(h.fixed, [("l".to_string(), "3".to_string())]);
        assert_eq!(h.y_values, ["0.01", "0.1"]);
        assert_eq!(h.panels[0].mean[1][0], Some(0.3));
        assert_eq!(
            h.panels[0].mean[0][0], None,
            "(hmcr 0.7, bw 0.01) was not run"
        );
        assert_eq!(h.panels[0].best, Some((0, 1)));
    }

    /// A grid of HS over hmcr × bw on `problems`, with `runs` runs of final
    /// error `error(hmcr, bw, problem, run)`, each run taking half a second.
    fn hs_grid(
        hmcr: &[&str],
        bw: &[&str],
        problems: &[&str],
        runs: u32,
        error: impl Fn(&str, &str, usize, u32) -> f64,
    ) -> Dataset {
        let mut v = Vec::new();
        for run in 0..runs {
            for h in hmcr {
                for b in bw {
                    for (p, problem) in problems.iter().enumerate() {
                        let params = format!("hms=5;hmcr={h};bw={b}");
                        let mut r = rec("HS", &params, problem, run, error(h, b, p, run));
                        r.0.wall_seconds = 0.5;
                        v.push(r);
                    }
                }
            }
        }
        let mut ds = Dataset::from_records(v);
        ds.has_timing = true;
        ds
    }

    #[test]
    fn a_pick_far_ahead_is_stable_and_its_edge_is_flagged() {
        let ds = hs_grid(
            &["0.7", "0.9", "0.99"],
            &["0.01", "0.1"],
            &["f", "g"],
            5,
            |h, b, p, run| {
                let spread = 1.0 + f64::from(run) + p as f64;
                if (h, b) == ("0.99", "0.01") {
                    1e-3 * spread
                } else {
                    spread + h.parse::<f64>().unwrap()
                }
            },
        );
        let stats = compute(&ds);
        let g = &grids(&ds)[0];
        let t = tables(&ds, g, &stats);
        let picks = &t[2];
        assert_eq!(picks.stem, "tuning_picks_hs");
        let row = &picks.csv_rows[0];
        let col = |name: &str| {
            let i = picks.csv_header.iter().position(|h| h == name).unwrap();
            row[i].as_str()
        };
        assert_eq!(col("setting"), "hmcr=0.99, bw=0.01");
        assert_eq!(col("params"), "hms=5;hmcr=0.99;bw=0.01");
        assert_eq!(col("mean_rank"), "1");
        assert_eq!(col("stability"), "1");
        assert_eq!(col("instead"), "");
        assert_eq!(col("resamples"), "200");
        // bw has two values only: not an edge.
        assert_eq!(col("edge"), "hmcr=0.99 (largest of 0.7, 0.9, 0.99)");
        assert_eq!(col("runs"), "60");
        assert_eq!(col("evaluations"), "6000");
        assert_eq!(col("wall_seconds"), "30");
        assert!(picks.intro[1].contains("the 60 runs of the 6 settings of HS used 6,000 evaluations and 30.0 s of wall time"), "{}", picks.intro[1]);
        assert!(picks.intro[2]
            .starts_with("Warning: the pick hmcr=0.99, bw=0.01 is on the edge of its grid"));
        assert!(picks.intro[2].ends_with("the best setting may lie outside it."));
        assert_eq!(picks.md_rows[0][4], "1.000");
        assert_eq!(picks.md_rows[0][5], "none");
    }

    #[test]
    fn a_pick_within_noise_of_another_is_unstable() {
        // Two settings whose errors are the same numbers in another order
        // (one a hair larger), on three problems: either may win a resample.
        let ds = hs_grid(
            &["0.7", "0.9"],
            &["0.01"],
            &["f", "g", "h"],
            6,
            |h, _, p, run| {
                let k = (f64::from(run) + 2.0 * p as f64) % 6.0;
                if h == "0.7" {
                    1.0 + k
                } else {
                    1.0 + (5.0 - k) + 1e-9
                }
            },
        );
        let stats = compute(&ds);
        let g = &grids(&ds)[0];
        let picks = &tables(&ds, g, &stats)[2];
        let header = |name: &str| picks.csv_header.iter().position(|h| h == name).unwrap();
        let row = &picks.csv_rows[0];
        let stability: f64 = row[header("stability")].parse().unwrap();
        assert!((0.2..0.8).contains(&stability), "stability {stability}");
        let instead = &row[header("instead")];
        assert_ne!(instead, &row[header("setting")]);
        assert!(!instead.is_empty());
        let share: f64 = row[header("instead_share")].parse().unwrap();
        assert_eq!(stability + share, 1.0);
        assert_eq!(row[header("runner_up")], *instead);
        // Two values of hmcr: no edge to flag.
        assert_eq!(row[header("edge")], "");
        assert_eq!(picks.md_rows[0][6], "no");
        // A pick that fewer than half the resamples make gets a caution.
        let caution = picks.intro.iter().any(|p| p.starts_with("Caution: only "));
        assert_eq!(caution, stability < 0.5);
        assert_eq!(picks.intro.len(), 2 + usize::from(caution));
    }

    #[test]
    fn the_tuning_tables_are_the_same_on_repeat() {
        let make = || {
            let ds = hs_grid(
                &["0.7", "0.9", "0.99"],
                &["0.001", "0.01", "0.1"],
                &["f", "g"],
                4,
                |h, b, p, run| {
                    let x = h.parse::<f64>().unwrap() * 7.0 + b.parse::<f64>().unwrap() * 13.0;
                    (x + f64::from(run) * 0.37 + p as f64).sin().abs()
                },
            );
            let stats = compute(&ds);
            let g = grids(&ds).remove(0);
            tables(&ds, &g, &stats)
                .iter()
                .map(|t| (t.csv_bytes(), t.markdown(), t.intro.clone()))
                .collect::<Vec<_>>()
        };
        let (a, b) = (make(), make());
        assert_eq!(a.len(), 3);
        assert_eq!(a, b);
    }

    #[test]
    fn mid_ranks_share_ties_and_the_first_minimum_wins() {
        let mut sums = vec![0.0; 4];
        add_midranks(&[3.0, 1.0, 1.0, 2.0], &mut Vec::new(), &mut sums);
        assert_eq!(sums, [4.0, 1.5, 1.5, 3.0]);
        assert_eq!(argmin(&sums), 1);
        assert_eq!(duration(754.2), "754.2 s (12.6 min)");
    }
}
