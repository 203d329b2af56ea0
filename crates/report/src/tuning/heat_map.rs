//! The data of a grid's heat map: the mean final error over two of its
//! parameters, one panel per problem.

use super::super::data::{param_value, Dataset};
use super::super::descriptive::{mean_error, CellStats};
use super::{best_on_problem, mean_ranks, Grid};

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

pub(super) fn sorted_values(values: Vec<String>) -> Vec<String> {
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
    super::super::format::sci_digits(v, 2)
}
