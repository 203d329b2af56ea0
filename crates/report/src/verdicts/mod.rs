//! The second level of the report's inference: verdicts across problems.
//!
//! The first level ([`super::significance`]) describes each problem with a
//! test of its runs. Here every comparison (an algorithm against the
//! reference, a pair of methods, a search space against another) becomes
//! one summary per problem, for the final error the log10 of the ratio of
//! the two medians (floored at the success threshold) and for the anytime
//! measure the difference of the median areas under the runs' ECDFs. The
//! problems of one unit within a scope are summarised by their median, and
//! the per-unit summaries are tested against zero: the Wilcoxon
//! signed-rank test, Holm-corrected over the rows of one scope of one
//! table, and, where three or more algorithms share the units, Friedman's
//! test with the z-test of average ranks against the reference, Holm- or
//! Finner-corrected (Demšar 2006, JMLR 7:1–30; García & Herrera 2008, JMLR
//! 9:2677–2694). Beside every row: the Hodges–Lehmann estimate of the
//! per-unit summaries with its exact signed-rank 95 % interval, and the
//! Bayesian signed-rank test with a region of practical equivalence per
//! measure ([`Ropes`]; Benavoli, Corani, Demšar & Zaffalon 2017, JMLR
//! 18(77)). A verdict is `equivalent` where P(rope) ≥ 0.95, `better` or
//! `worse` where the corrected test rejects, `undecided` otherwise, with
//! the counts and the smallest p the units allow beside it.
//!
//! The units: ch4's campaigns keep each function instance a problem and
//! pool a function's instances (and its dimensions and budgets within the
//! scope) into one unit by their median; bbob's campaign pools likewise,
//! its 24 functions being the units (its instances 1–5 of one function are
//! not independent problems); fitting campaigns use the outline or the
//! segment ([`super::design::unit_noun`]).
//!
//! This module decides the verdicts; [`table`] renders them.

mod table;
#[cfg(test)]
mod tests;

use std::collections::BTreeMap;

use rayon::prelude::*;

use crate::stats::{
    across_units, decide_family, finner, friedman, friedman_control_posthoc, holm_bonferroni,
    median, smallest_friedman_control_p, AcrossUnits, Equivalence, ShiftInterval, Verdict,
    VerdictRow, VerdictTest,
};

use super::design::{scopes, varying, Levels};

pub(crate) use self::table::{short, table};

/// What a comparison measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Measure {
    /// The final error f − f* (or E): lower is better; a problem's summary
    /// is log10(median A / median R), medians floored at the threshold.
    FinalError,
    /// The area under the run's ECDF of the targets over log10(evaluations
    /// / D) ([`super::anytime::run_auc`]): higher is better; a problem's
    /// summary is median A − median R.
    AnytimeAuc,
}

impl Measure {
    /// `final-error` or `anytime-auc`.
    pub fn name(self) -> &'static str {
        match self {
            Measure::FinalError => "final-error",
            Measure::AnytimeAuc => "anytime-auc",
        }
    }

    /// Whether a lower value of the measure is the better.
    pub fn lower_is_better(self) -> bool {
        self == Measure::FinalError
    }

    /// The default half-width of the region of practical equivalence of
    /// the measure's per-unit summaries: ±0.3 decades of the error ratio
    /// (a factor of 2, the resolution a reader of a log-scale convergence
    /// plot distinguishes), ±0.05 of the anytime AUC (5 % of the targets
    /// reached, about 2½ of COCO's 51).
    pub fn default_rope(self) -> f64 {
        match self {
            Measure::FinalError => 0.3,
            Measure::AnytimeAuc => 0.05,
        }
    }

    /// How the effect size reads: `median log10 ratio` or `median AUC
    /// difference`.
    pub fn effect_text(self) -> &'static str {
        match self {
            Measure::FinalError => "median log10 ratio of median errors",
            Measure::AnytimeAuc => "median difference of median AUC",
        }
    }
}

/// The post-hoc correction after Friedman's test.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PostHoc {
    /// Holm's step-down method (Holm 1979).
    #[default]
    Holm,
    /// Finner's step-down method (Finner 1993).
    Finner,
}

impl PostHoc {
    /// The accepted names, for the command line.
    pub const NAMES: [&'static str; 2] = ["holm", "finner"];

    /// The post-hoc method of a name, if it is one of [`PostHoc::NAMES`].
    pub fn from_name(name: &str) -> Option<PostHoc> {
        match name {
            "holm" => Some(PostHoc::Holm),
            "finner" => Some(PostHoc::Finner),
            _ => None,
        }
    }

    fn test(self) -> VerdictTest {
        match self {
            PostHoc::Holm => VerdictTest::FriedmanHolm,
            PostHoc::Finner => VerdictTest::FriedmanFinner,
        }
    }
}

pub use super::families::Families;
pub(crate) use super::families::STATE_OF_THE_ART;

/// One problem's summary of a comparison, with the unit and the design
/// levels it belongs to.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Observation {
    /// The comparison set (`reference`, `method-pairs`, `search-space`).
    pub table: &'static str,
    /// The measure compared.
    pub measure: Measure,
    /// The compared algorithm's name.
    pub algorithm: String,
    /// The reference's name.
    pub reference: String,
    /// The unit the problem belongs to.
    pub unit: String,
    /// The problem's design levels.
    pub levels: Levels,
    /// The summary (see [`Measure`]).
    pub value: f64,
}

/// One problem's value of one algorithm, for Friedman's ranking: for the
/// final error log10 of the floored median, for the anytime measure the
/// median AUC.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Standing {
    /// The comparison set.
    pub table: &'static str,
    /// The measure.
    pub measure: Measure,
    /// The algorithm's name.
    pub algorithm: String,
    /// The unit.
    pub unit: String,
    /// The problem's design levels.
    pub levels: Levels,
    /// The value (lower is better for the final error, higher for the AUC).
    pub value: f64,
}

/// The half-widths of the regions of practical equivalence of the
/// measures (the `rope` of the Bayesian signed-rank test beside every
/// verdict; Benavoli et al. 2017, JMLR 18(77), §5). In a fitting campaign
/// the final error is the fitting error E, so `final_error` is its rope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ropes {
    /// Decades of the ratio of median final errors (default 0.3).
    pub final_error: f64,
    /// Difference of the median anytime AUC (default 0.05).
    pub anytime_auc: f64,
}

impl Default for Ropes {
    fn default() -> Self {
        Ropes {
            final_error: Measure::FinalError.default_rope(),
            anytime_auc: Measure::AnytimeAuc.default_rope(),
        }
    }
}

impl Ropes {
    /// The measures' names as the command line and the spec write them.
    pub const NAMES: [&'static str; 2] = ["final-error", "anytime-auc"];

    /// The rope of `measure`.
    pub(crate) fn of(&self, measure: Measure) -> f64 {
        match measure {
            Measure::FinalError => self.final_error,
            Measure::AnytimeAuc => self.anytime_auc,
        }
    }

    /// Sets the rope of the measure named `name` (one of [`Ropes::NAMES`])
    /// to `value` (finite, ≥ 0); the error says what was expected.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), RopeError> {
        if !(value.is_finite() && value >= 0.0) {
            return Err(RopeError::Value(name.to_owned(), value));
        }
        match name {
            "final-error" => self.final_error = value,
            "anytime-auc" => self.anytime_auc = value,
            _ => return Err(RopeError::Measure(name.to_owned())),
        }
        Ok(())
    }
}

/// Why a rope cannot be set.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RopeError {
    /// The measure is not one of [`Ropes::NAMES`].
    #[error("no measure \"{0}\" has a rope: expected one of \"final-error\", \"anytime-auc\"")]
    Measure(String),
    /// The half-width is negative or not finite.
    #[error("the rope of {0} must be a finite number ≥ 0, got {1}")]
    Value(String, f64),
}

/// What the engine needs besides the observations.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Settings<'a> {
    /// The significance level.
    pub alpha: f64,
    /// The correction after Friedman's test.
    pub post_hoc: PostHoc,
    /// The reference of the `reference` table (the control of Friedman's
    /// post-hoc test).
    pub reference: Option<&'a str>,
    /// The regions of practical equivalence.
    pub ropes: Ropes,
}

/// The per-unit medians of the observations of one comparison within a
/// scope, units in name order; and the number of observations pooled.
fn unit_summaries<'o>(obs: impl Iterator<Item = &'o Observation>) -> (Vec<(String, f64)>, usize) {
    let mut by_unit: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    let mut n = 0;
    for o in obs {
        by_unit.entry(&o.unit).or_default().push(o.value);
        n += 1;
    }
    (
        by_unit
            .into_iter()
            .map(|(u, v)| (u.to_owned(), median(&v)))
            .collect(),
        n,
    )
}

/// The key of a row before it is decided: (table, measure, scope index).
type FamilyKey = (&'static str, Measure, usize);

/// Every verdict the observations allow: per table and measure, at every
/// scope of its design, one Wilcoxon row per comparison and, for the
/// `reference` table with three or more algorithms, one Friedman post-hoc
/// row per compared algorithm. Rows are in the order table, measure,
/// scope, test, then the order in which comparisons first appear.
pub(crate) fn verdicts(
    observations: &[Observation],
    standings: &[Standing],
    settings: Settings<'_>,
) -> Vec<VerdictRow> {
    let mut tables: Vec<(&'static str, Measure)> = Vec::new();
    for o in observations {
        if !tables.contains(&(o.table, o.measure)) {
            tables.push((o.table, o.measure));
        }
    }
    let mut rows = Vec::new();
    for (table, measure) in tables {
        let obs: Vec<&Observation> = observations
            .iter()
            .filter(|o| o.table == table && o.measure == measure)
            .collect();
        let points: Vec<Levels> = obs.iter().map(|o| o.levels.clone()).collect();
        let keep = varying(&points);
        let scope_list: Vec<Levels> = scopes(
            &points
                .iter()
                .map(|p| super::design::restrict(p, &keep))
                .collect::<Vec<_>>(),
        );
        let mut pairs: Vec<(&str, &str)> = Vec::new();
        for o in &obs {
            if !pairs.contains(&(o.algorithm.as_str(), o.reference.as_str())) {
                pairs.push((&o.algorithm, &o.reference));
            }
        }
        for (si, scope) in scope_list.iter().enumerate() {
            let key: FamilyKey = (table, measure, si);
            // Each row's evidence is seeded by its own names, so the rows
            // are weighed in parallel with the same bits as one by one.
            let mut family: Vec<VerdictRow> = pairs
                .par_iter()
                .filter_map(|&(alg, reference)| {
                    let in_scope = obs.iter().copied().filter(|o| {
                        o.algorithm == alg && o.reference == reference && scope.within(&o.levels)
                    });
                    let (units, n) = unit_summaries(in_scope);
                    if units.is_empty() {
                        return None;
                    }
                    let d: Vec<f64> = units.iter().map(|u| u.1).collect();
                    let across = across_units(&d, measure.lower_is_better()).ok()?;
                    let mut row = VerdictRow {
                        table: key.0.to_owned(),
                        measure: measure.name().to_owned(),
                        algorithm: alg.to_owned(),
                        reference: reference.to_owned(),
                        scope: scope.scope(),
                        problems: n,
                        test: VerdictTest::WilcoxonSignedRank,
                        across,
                        p_adjusted: f64::NAN,
                        family: 0,
                        shift: ShiftInterval::unknown(),
                        equivalence: Equivalence::unknown(f64::NAN),
                        verdict: Verdict::Undecided,
                    };
                    row.weigh(&d, measure.lower_is_better(), settings.ropes.of(measure));
                    Some(row)
                })
                .collect();
            decide_family(&mut family, settings.alpha);
            rows.extend(family);
            if table == "reference" {
                if let Some(reference) = settings.reference {
                    rows.extend(friedman_rows(
                        &obs, standings, table, measure, scope, reference, settings,
                    ));
                }
            }
        }
    }
    rows
}

/// Friedman's test over the units of `scope` on which every algorithm has
/// a standing, and the post-hoc test of every algorithm against the
/// reference; empty with fewer than three algorithms or two units.
fn friedman_rows(
    obs: &[&Observation],
    standings: &[Standing],
    table: &'static str,
    measure: Measure,
    scope: &Levels,
    reference: &str,
    settings: Settings<'_>,
) -> Vec<VerdictRow> {
    let mut algorithms: Vec<&str> = vec![reference];
    let mut values: BTreeMap<(&str, &str), Vec<f64>> = BTreeMap::new();
    for s in standings
        .iter()
        .filter(|s| s.table == table && s.measure == measure && scope.within(&s.levels))
    {
        if !algorithms.contains(&s.algorithm.as_str()) {
            algorithms.push(&s.algorithm);
        }
        values
            .entry((&s.algorithm, &s.unit))
            .or_default()
            .push(s.value);
    }
    let k = algorithms.len();
    let units: Vec<&str> = {
        let mut u: Vec<&str> = values.keys().map(|(_, u)| *u).collect();
        u.sort_unstable();
        u.dedup();
        u.into_iter()
            .filter(|u| algorithms.iter().all(|a| values.contains_key(&(*a, *u))))
            .collect()
    };
    if k < 3 || units.len() < 2 {
        return Vec::new();
    }
    let sign = if measure.lower_is_better() { 1.0 } else { -1.0 };
    let blocks: Vec<Vec<f64>> = units
        .iter()
        .map(|u| {
            algorithms
                .iter()
                .map(|a| sign * median(&values[&(*a, *u)]))
                .collect()
        })
        .collect();
    let Ok(f) = friedman(&blocks) else {
        return Vec::new();
    };
    let Ok(post) = friedman_control_posthoc(&f.average_ranks, units.len(), 0) else {
        return Vec::new();
    };
    let raw: Vec<f64> = post.iter().map(|c| c.p_value).collect();
    let adjusted = match settings.post_hoc {
        PostHoc::Holm => holm_bonferroni(&raw),
        PostHoc::Finner => finner(&raw),
    }
    .unwrap_or_else(|_| vec![f64::NAN; raw.len()]);
    let p_min = smallest_friedman_control_p(k, units.len());
    post.par_iter()
        .zip(adjusted)
        .map(|(c, pa)| {
            let alg = algorithms[c.treatment];
            // The summary effect over the same blocks, from the observations.
            let (summaries, n) = unit_summaries(obs.iter().copied().filter(|o| {
                o.algorithm == alg
                    && o.reference == reference
                    && scope.within(&o.levels)
                    && units.contains(&o.unit.as_str())
            }));
            let d: Vec<f64> = summaries.iter().map(|u| u.1).collect();
            let favours = |x: f64| {
                if measure.lower_is_better() {
                    x < 0.0
                } else {
                    x > 0.0
                }
            };
            let better = d.iter().filter(|&&x| favours(x)).count();
            let equal = d.iter().filter(|&&x| x == 0.0).count();
            let mut row = VerdictRow {
                table: table.to_owned(),
                measure: measure.name().to_owned(),
                algorithm: alg.to_owned(),
                reference: reference.to_owned(),
                scope: scope.scope(),
                problems: n,
                test: settings.post_hoc.test(),
                across: AcrossUnits {
                    units: units.len(),
                    better,
                    equal,
                    worse: d.len() - better - equal,
                    p_value: c.p_value,
                    p_min,
                    effect_size: if d.is_empty() { f64::NAN } else { median(&d) },
                    improvement: c.z,
                },
                p_adjusted: pa,
                family: post.len(),
                shift: ShiftInterval::unknown(),
                equivalence: Equivalence::unknown(f64::NAN),
                verdict: Verdict::Undecided,
            };
            row.weigh(&d, measure.lower_is_better(), settings.ropes.of(measure));
            row.verdict = Verdict::decide(pa, settings.alpha, c.z, &row.equivalence);
            row
        })
        .collect()
}

/// The verdict of the Wilcoxon row of `algorithm` against `reference` in
/// `table` on `measure` at `scope`, if there is one; `table` `reference`
/// also finds the algorithm's row in [`STATE_OF_THE_ART`], where the
/// algorithms beyond the thesis are compared with the same reference.
pub(crate) fn find<'v>(
    rows: &'v [VerdictRow],
    table: &str,
    measure: Measure,
    algorithm: &str,
    reference: &str,
    scope: &str,
) -> Option<&'v VerdictRow> {
    rows.iter().find(|r| {
        r.test == VerdictTest::WilcoxonSignedRank
            && (r.table == table || (table == "reference" && r.table == STATE_OF_THE_ART))
            && r.measure == measure.name()
            && r.algorithm == algorithm
            && r.reference == reference
            && r.scope == scope
    })
}
