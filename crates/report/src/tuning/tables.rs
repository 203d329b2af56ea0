//! The tuning tables of a grid (the best setting per problem and overall,
//! the mean ranks, the pick with its stability, edges and cost) and the
//! overview of several grids, rendered from the computed grids and picks.

use metabezier_plot::markdown::thousands;

use super::super::data::Dataset;
use super::super::descriptive::CellStats;
use super::super::format::{csv_real, fixed2, sci_opt, Table};
use super::pick::{cost, edges, pick, Pick, RESAMPLES};
use super::{best_on_problem, mean_ranks, Grid};

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

/// A wall time in seconds, with minutes or hours when long: `754.2 s
/// (12.6 min)`.
pub(super) fn duration(seconds: f64) -> String {
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
