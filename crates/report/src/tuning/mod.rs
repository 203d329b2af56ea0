//! Parameter tuning: grids of cells that share a label and differ in their
//! parameters (e.g. MHS over hmcr × bw), the best setting per problem and
//! overall, and the data of the heat maps.

mod heat_map;
mod pick;
mod tables;
#[cfg(test)]
mod tests;

use std::collections::BTreeMap;

use crate::stats::friedman;

use super::data::{param_value, varying_params, Dataset};
use super::descriptive::{mean_error, CellStats};

pub(crate) use self::heat_map::{cell_label, heat_map, HeatMap, HeatPanel};
pub(crate) use self::tables::{overview, tables};

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
