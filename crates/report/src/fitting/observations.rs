//! The observations of the comparisons between fitting functions and
//! between continuities, which need one method only.

use std::collections::BTreeMap;

use super::super::fit_runs::{split, Case, FitRuns};
use super::super::verdicts::Observation;
use crate::stats::median;

/// The observations of the comparisons between fitting functions and
/// between continuities on whole outlines, outlines as units: every
/// function against the rational cubic (table `fitting-function`) and G1
/// against C1 (table `continuity`), each method's median E on one case
/// against its median E on the twin case (same source, search space and
/// budget), log10 of the ratio. With four outlines no such verdict can
/// reject at α = 0.05 (p_min = 0.125): the claims they test stay
/// descriptive, and the report says so. Only the thesis's methods enter:
/// the thesis's claims are about them, and the methods beyond it (CMA-ES,
/// L-SHADE, random search, alone or before LM) are judged against the
/// reference instead, so adding them leaves these verdicts as they were.
pub(crate) fn treatment_observations(fr: &FitRuns<'_>) -> Vec<Observation> {
    use super::super::design::{Level, Levels};
    use super::super::verdicts::Measure;
    let thesis: Vec<bool> = fr
        .kinds()
        .iter()
        .map(|k| !fr.families.beyond_the_thesis(k.as_deref().unwrap_or("")))
        .collect();
    // Cases of whole outlines by (source, space level, budget, variant).
    type CaseKey = (String, String, Option<u64>, String);
    let mut cases: BTreeMap<CaseKey, Vec<(usize, Case<'_>)>> = BTreeMap::new();
    for (p, problem) in fr.problems.iter().enumerate() {
        let Some(c) = split(&problem.name).filter(|c| !c.per_segment) else {
            continue;
        };
        cases
            .entry((
                c.source.to_owned(),
                c.space_level(),
                problem.budget,
                c.variant(),
            ))
            .or_default()
            .push((p, c));
    }
    let mut obs = Vec::new();
    let mut compare = |table: &'static str,
                       (pa, a): (usize, &str),
                       (pb, b): (usize, &str),
                       source: &str,
                       fixed: (&'static str, &str),
                       case: &Case<'_>| {
        for (c, cell) in fr.cells.iter().enumerate() {
            if !thesis[c] {
                continue;
            }
            let (Some(ea), Some(eb)) = (fr.errors(pa, c), fr.errors(pb, c)) else {
                continue;
            };
            let value = (median(&ea) / median(&eb)).log10();
            if value.is_nan() {
                continue;
            }
            obs.push(Observation {
                table,
                measure: Measure::FinalError,
                algorithm: a.to_owned(),
                reference: b.to_owned(),
                unit: source.to_owned(),
                levels: Levels(vec![
                    (fixed.0, Level::Text(fixed.1.to_owned())),
                    ("error", Level::Text(case.error().to_owned())),
                    ("chain", Level::Text(case.chain().to_owned())),
                    ("size", Level::Text(case.size().into())),
                    ("method", Level::Text(cell.clone())),
                ]),
                value,
            });
        }
    };
    for ((source, _, _, _), list) in &cases {
        for &(p, c) in list {
            // Every function against the rational cubic of the same continuity.
            if c.function != "rational-cubic" {
                if let Some(&(q, _)) = list
                    .iter()
                    .find(|(_, d)| d.function == "rational-cubic" && d.continuity == c.continuity)
                {
                    let a = (p, c.function);
                    let b = (q, "rational-cubic");
                    compare(
                        "fitting-function",
                        a,
                        b,
                        source,
                        ("continuity", c.continuity),
                        &c,
                    );
                }
            }
            // G1 against C1 with the same function.
            if c.continuity == "g1" {
                if let Some(&(q, _)) = list
                    .iter()
                    .find(|(_, d)| d.function == c.function && d.continuity == "c1")
                {
                    compare(
                        "continuity",
                        (p, "g1"),
                        (q, "c1"),
                        source,
                        ("function", c.function),
                        &c,
                    );
                }
            }
        }
    }
    obs
}
