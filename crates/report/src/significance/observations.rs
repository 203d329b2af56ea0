//! The observations of the first-level comparisons that the verdicts
//! across problems are made from, and the standings of every algorithm on
//! every unit that Friedman's ranking uses.

use crate::stats::median_in_place;

use super::super::data::Dataset;
use super::super::design::{factors, unit, Levels};
use super::super::verdicts::{Measure, Observation, Standing};
use super::{min_budget, values, Significance};

/// The per-problem summaries of the comparisons with the reference for
/// [`crate::verdicts`] (per-segment fitting problems excepted: their units
/// are segments, see [`crate::fit_units`]), and every cell's standing for
/// Friedman's ranking.
pub(crate) fn observations(ds: &Dataset, s: &Significance) -> (Vec<Observation>, Vec<Standing>) {
    let reference = &ds.cells[s.reference].name;
    let targets = crate::experiment::records::default_targets().len();
    let mut obs = Vec::new();
    let mut standings = Vec::new();
    for (measure, rows) in [
        (Measure::FinalError, &s.tests),
        (Measure::AnytimeAuc, &s.anytime),
    ] {
        let mut problems: Vec<usize> = rows.iter().map(|r| r.problem).collect();
        problems.dedup();
        for &p in &problems {
            let problem = &ds.problems[p];
            let Some(u) = unit(problem) else { continue };
            let levels: Levels = factors(problem);
            let cells: Vec<usize> = std::iter::once(s.reference)
                .chain(rows.iter().filter(|r| r.problem == p).map(|r| r.cell))
                .collect();
            let budget = min_budget(cells.iter().flat_map(|&c| ds.runs(p, c)));
            for &c in &cells {
                let mut v = values(ds.runs(p, c), measure, problem.dim, budget, targets);
                let value = match measure {
                    Measure::FinalError => {
                        v.iter_mut().for_each(|x| *x = x.max(s.floor));
                        median_in_place(&mut v).log10()
                    }
                    Measure::AnytimeAuc => median_in_place(&mut v),
                };
                if !value.is_nan() {
                    standings.push(Standing {
                        table: ds
                            .families
                            .comparison_set(&ds.cells[c].kind, &ds.cells[s.reference].kind),
                        measure,
                        algorithm: ds.cells[c].name.clone(),
                        unit: u.clone(),
                        levels: levels.clone(),
                        value,
                    });
                }
            }
            for r in rows.iter().filter(|r| r.problem == p) {
                let value = match measure {
                    Measure::FinalError => r.effect.log10(),
                    Measure::AnytimeAuc => r.effect,
                };
                if value.is_nan() {
                    continue;
                }
                obs.push(Observation {
                    table: ds
                        .families
                        .comparison_set(&ds.cells[r.cell].kind, &ds.cells[s.reference].kind),
                    measure,
                    algorithm: ds.cells[r.cell].name.clone(),
                    reference: reference.clone(),
                    unit: u.clone(),
                    levels: levels.clone(),
                    value,
                });
            }
        }
    }
    (obs, standings)
}
