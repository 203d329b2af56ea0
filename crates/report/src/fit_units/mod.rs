//! Segment-level inference for fitting campaigns in the per-segment mode:
//! every segment is its own problem (joined to the exact fit's neighbours),
//! so a segment is a unit of the test, not the whole outline.
//!
//! For each comparison (every algorithm against the reference; the
//! search-space technique at each α_size against the bounding box; every
//! pair of methods) this module gives [`super::verdicts`] one observation
//! per segment: log10 of the ratio of the two median E over the runs. The
//! verdicts (Wilcoxon signed-rank over the segments, Holm over the rows of
//! one scope) are then shown beside the first-level description: per
//! segment, the two samples of E over the runs tested two-sided (Wilcoxon
//! signed-rank paired by run when the runs share their seeds, else
//! Mann–Whitney U), Holm-corrected over the segments of the row and
//! counted as better / same / worse.
//!
//! This module computes the observations and the per-segment descriptions;
//! [`tables`] renders them.

mod tables;

use std::collections::BTreeMap;

use super::design::{fit_levels, without, Levels};
use super::fit_runs::{split, two_sample_test, FitRuns};
use super::verdicts::{Measure, Observation, Standing};
use crate::experiment::segments::FIT_SEGMENT_HEADER;
use crate::files::fmt_real;
use crate::fit::ALPHA_SIZE;
use crate::stats::{holm_bonferroni, median, Mark};

pub(crate) use self::tables::tables;

/// A segment of a source: (source, contour, segment).
pub(super) type Unit = (String, String, String);

/// The E of every run of one (problem, cell) per segment: unit → E by run.
pub(super) type UnitRuns = BTreeMap<Unit, Vec<f64>>;

/// The segment E's of the runs of cell `c` on problem `p`, by segment
/// (rows in the layout of [`FIT_SEGMENT_HEADER`]).
pub(super) fn unit_runs(fr: &FitRuns<'_>, p: usize, c: usize) -> Option<UnitRuns> {
    let sse = FIT_SEGMENT_HEADER.iter().position(|h| *h == "sse")?;
    let source = split(&fr.problems[p].name)?.source.to_owned();
    let mut runs: Vec<_> = fr.runs.get(&(p, c))?.clone();
    runs.sort_by_key(|r| r.run);
    let mut out: UnitRuns = BTreeMap::new();
    for r in runs {
        for row in &r.fit.as_ref()?.segments {
            if row.len() != FIT_SEGMENT_HEADER.len() {
                return None;
            }
            let e: f64 = row[sse].parse().ok()?;
            out.entry((source.clone(), row[0].clone(), row[1].clone()))
                .or_default()
                .push(e);
        }
    }
    Some(out)
}

/// The name of a segment unit: `source/contour/segment`.
fn unit_name(u: &Unit) -> String {
    format!("{}/{}/{}", u.0, u.1, u.2)
}

/// log10 of the ratio of two medians, both floored.
fn log_ratio(a: &[f64], b: &[f64], floor: f64) -> f64 {
    (median(a).max(floor) / median(b).max(floor)).log10()
}

/// The first-level description of one comparison (A against B) over the
/// segments they share: the per-segment tests (paired when `paired`)
/// Holm-corrected and counted, and the median ratio of E.
struct UnitRow {
    units: usize,
    median_ratio: f64,
    better: usize,
    same: usize,
    worse: usize,
}

fn describe(a: &UnitRuns, b: &UnitRuns, paired: bool, alpha: f64) -> Option<UnitRow> {
    let mut ratios = Vec::new();
    let mut tests = Vec::new();
    let mut units = 0;
    for (unit, ea) in a {
        let Some(eb) = b.get(unit) else { continue };
        units += 1;
        let (ma, mb) = (median(ea), median(eb));
        if mb > 0.0 {
            ratios.push(ma / mb);
        }
        if let Some(t) = two_sample_test(ea, eb, paired) {
            tests.push((t.p_value, t.direction));
        }
    }
    if units == 0 {
        return None;
    }
    let p: Vec<f64> = tests.iter().map(|t| t.0).collect();
    let adjusted = holm_bonferroni(&p).unwrap_or(p);
    let (mut better, mut same, mut worse) = (0, 0, 0);
    for (ph, (_, d)) in adjusted.iter().zip(&tests) {
        match Mark::from_p_value(*ph, alpha, *d) {
            Mark::Better => better += 1,
            Mark::Same => same += 1,
            Mark::Worse => worse += 1,
        }
    }
    Some(UnitRow {
        units,
        median_ratio: if ratios.is_empty() {
            f64::NAN
        } else {
            median(&ratios)
        },
        better,
        same,
        worse,
    })
}

/// A group of per-segment problems pooled over the sources: function,
/// continuity and variant (`function/continuity` with the name's tail:
/// `orthogonal` and the like, see [`super::fit_runs::Case::variant`]),
/// search-space level and budget per segment.
type Group = (String, String, String, Option<u64>);

/// The per-segment problems of each group, with their sources.
fn groups(fr: &FitRuns<'_>) -> BTreeMap<Group, Vec<usize>> {
    let mut out: BTreeMap<Group, Vec<usize>> = BTreeMap::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(c) = split(&problem.name).filter(|c| c.per_segment) else {
            continue;
        };
        let variant = c.variant();
        let continuity = if variant.is_empty() {
            c.continuity.to_owned()
        } else {
            format!("{}/{variant}", c.continuity)
        };
        let key = (
            c.function.to_owned(),
            continuity,
            c.space_level(),
            problem.budget,
        );
        out.entry(key).or_default().push(p);
    }
    out
}

/// The unit E's of cell `c` pooled over the problems `ps` (one per source).
fn pooled(fr: &FitRuns<'_>, ps: &[usize], c: usize) -> Option<UnitRuns> {
    let mut out = UnitRuns::new();
    for &p in ps {
        out.extend(unit_runs(fr, p, c)?);
    }
    Some(out)
}

/// The design levels of fitting problem `p`.
fn levels_of(fr: &FitRuns<'_>, p: usize) -> Levels {
    fit_levels(&fr.problems[p].name, fr.problems[p].budget)
}

/// The technique's α_size of a level text (`technique, α = 0.1`; 0.5 when
/// it is the default).
fn alpha_of(level: &str) -> String {
    level
        .strip_prefix("technique, α = ")
        .map_or_else(|| fmt_real(ALPHA_SIZE.default), str::to_owned)
}

/// The names of a search-space comparison: (algorithm, reference).
fn space_names(cell: &str, alpha_size: &str) -> (String, String) {
    (
        format!("{cell}: technique α_size {alpha_size}"),
        format!("{cell}: bounding box"),
    )
}

/// Every (technique problem, its bounding-box twin) of the per-segment
/// problems: same case and budget.
fn space_twins(groups: &BTreeMap<Group, Vec<usize>>) -> Vec<(&Group, &Vec<usize>, &Vec<usize>)> {
    let mut out = Vec::new();
    for (key, ps) in groups {
        let (function, continuity, level, budget) = key;
        if !level.starts_with("technique") {
            continue;
        }
        let bb_key = (
            function.clone(),
            continuity.clone(),
            "bounding-box".to_owned(),
            *budget,
        );
        if let Some(bs) = groups.get(&bb_key) {
            out.push((key, ps, bs));
        }
    }
    out
}

/// The segment observations of the per-segment problems: every cell
/// against `reference` (with every cell's standing), every pair of methods,
/// and the technique against the bounding box per method.
pub(crate) fn observations(
    fr: &FitRuns<'_>,
    reference: Option<&str>,
    floor: f64,
) -> (Vec<Observation>, Vec<Standing>) {
    let mut obs = Vec::new();
    let mut standings = Vec::new();
    let groups = groups(fr);
    let kinds = fr.kinds();
    let kind = |c: usize| kinds[c].as_deref().unwrap_or("");
    let observe = |obs: &mut Vec<Observation>,
                   table: &'static str,
                   names: (String, String),
                   levels: &Levels,
                   a: &UnitRuns,
                   b: &UnitRuns| {
        for (unit, ea) in a {
            if let Some(eb) = b.get(unit) {
                let value = log_ratio(ea, eb, floor);
                if !value.is_nan() {
                    obs.push(Observation {
                        table,
                        measure: Measure::FinalError,
                        algorithm: names.0.clone(),
                        reference: names.1.clone(),
                        unit: unit_name(unit),
                        levels: levels.clone(),
                        value,
                    });
                }
            }
        }
    };
    // Against the reference: the methods beyond the thesis (CMA-ES,
    // L-SHADE, random search, alone or before LM) in their own set.
    if let Some(r) = reference.and_then(|r| fr.cells.iter().position(|c| c == r)) {
        for ps in groups.values() {
            for &p in ps {
                let levels = levels_of(fr, p);
                let Some(rr) = unit_runs(fr, p, r) else {
                    continue;
                };
                for (c, cell) in fr.cells.iter().enumerate() {
                    let Some(cr) = unit_runs(fr, p, c) else {
                        continue;
                    };
                    let table = fr.families.comparison_set(kind(c), kind(r));
                    for (unit, e) in &cr {
                        standings.push(Standing {
                            table,
                            measure: Measure::FinalError,
                            algorithm: cell.clone(),
                            unit: unit_name(unit),
                            levels: levels.clone(),
                            value: median(e).max(floor).log10(),
                        });
                    }
                    if c != r {
                        let names = (cell.clone(), fr.cells[r].clone());
                        observe(&mut obs, table, names, &levels, &cr, &rr);
                    }
                }
            }
        }
    }
    // Every pair of methods (those with a method beyond the thesis in
    // their own set).
    for ps in groups.values() {
        for &p in ps {
            let levels = levels_of(fr, p);
            let units: Vec<Option<UnitRuns>> =
                (0..fr.cells.len()).map(|c| unit_runs(fr, p, c)).collect();
            for (i, a) in units.iter().enumerate() {
                for (j, b) in units.iter().enumerate().skip(i + 1) {
                    if let (Some(a), Some(b)) = (a, b) {
                        let names = (fr.cells[i].clone(), fr.cells[j].clone());
                        let table = fr.families.pair_set(kind(i), kind(j));
                        observe(&mut obs, table, names, &levels, a, b);
                    }
                }
            }
        }
    }
    // The technique against the bounding box.
    for ((_, _, level, _), ps, bs) in space_twins(&groups) {
        let alpha_size = alpha_of(level);
        for (&p, &q) in ps.iter().zip(bs) {
            let levels = without(&levels_of(fr, p), &["search_space", "alpha_size"]);
            for (c, cell) in fr.cells.iter().enumerate() {
                if let (Some(a), Some(b)) = (unit_runs(fr, p, c), unit_runs(fr, q, c)) {
                    let names = space_names(cell, &alpha_size);
                    observe(&mut obs, "search-space", names, &levels, &a, &b);
                }
            }
        }
    }
    (obs, standings)
}
