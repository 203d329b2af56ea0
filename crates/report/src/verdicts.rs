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
//! 9:2677–2694). A verdict is `better` or `worse` only where the corrected
//! test rejects; otherwise `no detectable difference`, with the counts and
//! the smallest p the units allow beside it.

use std::collections::BTreeMap;

use crate::stats::{
    across_units, decide_family, finner, friedman, friedman_control_posthoc, holm_bonferroni,
    median, smallest_friedman_control_p, AcrossUnits, Verdict, VerdictRow, VerdictTest,
    VERDICT_COLUMNS,
};

use super::design::{scopes, varying, Levels};
use super::format::{p_value, sci, Table};

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

/// The comparison set of the algorithms beyond the thesis (CMA-ES, L-SHADE,
/// random search) against the reference: a family of its own, so that
/// adding the state of the art to a campaign leaves the Holm families and
/// the Friedman post-hoc test of the thesis's comparisons (table
/// `reference`) as they were; each question is corrected within its own
/// family (Bender & Lange 2001, "Adjusting for multiple testing — when and
/// how?", J. Clin. Epidemiol. 54(4):343–349).
pub(crate) const STATE_OF_THE_ART: &str = "state-of-the-art";

/// The spec names of the algorithms whose comparisons go to
/// [`STATE_OF_THE_ART`] (a fitting method `cmaes+lm` by its optimiser).
pub(crate) const STATE_OF_THE_ART_KINDS: [&str; 3] = ["cmaes", "lshade", "random"];

/// The comparison set of a cell of kind `kind` against the reference:
/// [`STATE_OF_THE_ART`] for the algorithms beyond the thesis, else
/// `reference`.
/// When the reference itself is beyond the thesis (`--reference CMA-ES`),
/// every comparison is in `reference`.
pub(crate) fn comparison_set(kind: &str, reference_kind: &str) -> &'static str {
    if beyond_the_thesis(kind) && !beyond_the_thesis(reference_kind) {
        STATE_OF_THE_ART
    } else {
        "reference"
    }
}

/// The comparisons of two fitting methods of which at least one is beyond
/// the thesis: a family of its own beside `method-pairs`, for the reason
/// of [`STATE_OF_THE_ART`].
pub(crate) const STATE_OF_THE_ART_PAIRS: &str = "state-of-the-art-pairs";

/// Whether a cell of kind `kind` (`cmaes+lm` by its optimiser) is one of
/// [`STATE_OF_THE_ART_KINDS`].
pub(crate) fn beyond_the_thesis(kind: &str) -> bool {
    STATE_OF_THE_ART_KINDS.contains(&kind.split('+').next().unwrap_or(kind))
}

/// The comparison set of the pair of methods of kinds `a` and `b`:
/// [`STATE_OF_THE_ART_PAIRS`] when either is beyond the thesis, else
/// `method-pairs`.
pub(crate) fn pair_set(a: &str, b: &str) -> &'static str {
    if beyond_the_thesis(a) || beyond_the_thesis(b) {
        STATE_OF_THE_ART_PAIRS
    } else {
        "method-pairs"
    }
}

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
            let mut family = Vec::new();
            for &(alg, reference) in &pairs {
                let in_scope = obs.iter().copied().filter(|o| {
                    o.algorithm == alg && o.reference == reference && scope.within(&o.levels)
                });
                let (units, n) = unit_summaries(in_scope);
                if units.is_empty() {
                    continue;
                }
                let d: Vec<f64> = units.iter().map(|u| u.1).collect();
                let Ok(across) = across_units(&d, measure.lower_is_better()) else {
                    continue;
                };
                family.push(VerdictRow {
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
                    verdict: Verdict::NoDetectableDifference,
                });
            }
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
    post.iter()
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
            VerdictRow {
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
                verdict: Verdict::from_p(pa, settings.alpha, c.z),
            }
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

/// A verdict in a table cell: `better (6/0/2, p_Holm 0.012)`.
pub(crate) fn short(r: &VerdictRow) -> String {
    format!(
        "{} ({}/{}/{}, p_Holm {})",
        r.verdict,
        r.across.better,
        r.across.equal,
        r.across.worse,
        p_value(r.p_adjusted)
    )
}

/// The `verdicts` table: every verdict row, with its Markdown rendering.
pub(crate) fn table(rows: &[VerdictRow], unit_noun: &str, alpha: f64) -> Table {
    let mut t = Table {
        stem: "verdicts".into(),
        title: "Verdicts across problems".into(),
        intro: vec![
            format!(
                "Every verdict across problems, from a test whose units are independent \
                 {unit_noun}s. A problem's summary is, for the final error, log10 of the ratio \
                 of the two median errors (floored at the success threshold, so two solved \
                 problems give 0) and, for the anytime measure, the difference of the median \
                 areas under the runs' target ECDFs; the problems of a {unit_noun} within the \
                 scope are summarised by their median. wilcoxon-signed-rank: the Wilcoxon \
                 signed-rank test of the per-{unit_noun} summaries against zero, Holm-corrected \
                 over the rows of one table, measure and scope; friedman-holm and \
                 friedman-finner: Friedman's test over the {unit_noun}s with the z-test of \
                 average ranks against the reference, Holm- or Finner-corrected."
            ),
            format!(
                "better/equal/worse count the {unit_noun}s whose summary favours the algorithm, \
                 is exactly zero, or favours the reference; effect is the median summary. \
                 A verdict is better or worse only where the corrected p is below α = {alpha}; \
                 p_min is the smallest p the number of units allows (2/2ⁿ for the signed-rank \
                 test with n non-zero units), and family is the number of rows corrected \
                 together: no adjusted p can fall below family × the family's smallest p_min, \
                 so where that product is at least α no verdict of the family can be better or \
                 worse by construction."
            ),
        ],
        md_header: [
            "Table",
            "Measure",
            "Algorithm",
            "Reference",
            "Scope",
            "Test",
            "Units +/=/−",
            "Effect",
            "p",
            "p (adjusted)",
            "p_min",
            "Family",
            "Verdict",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: VERDICT_COLUMNS.map(String::from).to_vec(),
        ..Table::default()
    };
    for r in rows {
        t.csv_rows.push(r.csv_fields());
        t.md_rows.push(vec![
            r.table.clone(),
            r.measure.clone(),
            r.algorithm.clone(),
            r.reference.clone(),
            r.scope.clone(),
            r.test.as_str().to_owned(),
            format!("{}/{}/{}", r.across.better, r.across.equal, r.across.worse),
            sci(r.across.effect_size),
            p_value(r.across.p_value),
            p_value(r.p_adjusted),
            p_value(r.across.p_min),
            r.family.to_string(),
            r.verdict.to_string(),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::Level;

    fn obs(alg: &str, unit: &str, budget: u64, value: f64) -> Observation {
        Observation {
            table: "reference",
            measure: Measure::FinalError,
            algorithm: alg.into(),
            reference: "R".into(),
            unit: unit.into(),
            levels: Levels(vec![("budget", Level::Number(budget))]),
            value,
        }
    }

    #[test]
    fn four_equal_four_better_is_no_detectable_difference_eight_better_is_better() {
        let mut o = Vec::new();
        for (i, f) in ["f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8"]
            .iter()
            .enumerate()
        {
            o.push(obs("X", f, 1000, if i < 4 { 0.0 } else { -3.0 }));
            o.push(obs("Y", f, 1000, -3.0));
        }
        let rows = verdicts(
            &o,
            &[],
            Settings {
                alpha: 0.05,
                post_hoc: PostHoc::Holm,
                reference: Some("R"),
            },
        );
        assert_eq!(rows.len(), 2, "one scope, two rows: {rows:?}");
        let x = &rows[0];
        assert_eq!((x.across.better, x.across.equal, x.across.worse), (4, 4, 0));
        assert!((x.across.p_value - 0.125).abs() < 1e-12);
        assert_eq!(x.verdict, Verdict::NoDetectableDifference);
        let y = &rows[1];
        assert!((y.p_adjusted - 0.015625).abs() < 1e-12, "{}", y.p_adjusted);
        assert_eq!(y.verdict, Verdict::Better);
    }

    #[test]
    fn instances_of_a_function_are_one_unit_and_scopes_split_by_level() {
        // Five instances of one function better at budget 1000, worse at
        // 2000: one unit per scope, never significant.
        let mut o = Vec::new();
        for i in 0..5 {
            o.push(obs("X", "f", 1000, -1.0 - f64::from(i)));
            o.push(obs("X", "f", 2000, 1.0));
        }
        let rows = verdicts(
            &o,
            &[],
            Settings {
                alpha: 0.05,
                post_hoc: PostHoc::Holm,
                reference: None,
            },
        );
        let scopes: Vec<&str> = rows.iter().map(|r| r.scope.as_str()).collect();
        assert_eq!(scopes, ["all", "budget=1000", "budget=2000"]);
        assert!(rows.iter().all(|r| r.across.units == 1));
        assert_eq!(rows[0].problems, 10);
        // The unit's summary at scope all is the median of its ten values.
        assert_eq!(rows[0].across.effect_size, 0.0);
        assert_eq!(rows[1].across.effect_size, -3.0);
        assert!(rows
            .iter()
            .all(|r| r.verdict == Verdict::NoDetectableDifference));
    }

    #[test]
    fn the_state_of_the_art_is_a_family_of_its_own_unless_it_is_the_reference() {
        assert_eq!(comparison_set("cmaes", "mhs"), STATE_OF_THE_ART);
        assert_eq!(comparison_set("lshade", "mhs"), STATE_OF_THE_ART);
        assert_eq!(comparison_set("random", "hs"), STATE_OF_THE_ART);
        assert_eq!(comparison_set("cmaes+lm", "mhs"), STATE_OF_THE_ART);
        assert_eq!(comparison_set("hs", "mhs"), "reference");
        assert_eq!(comparison_set("mhs+lm", "mhs"), "reference");
        assert_eq!(pair_set("hs", "mhs"), "method-pairs");
        assert_eq!(pair_set("mhs+lm", "lm"), "method-pairs");
        assert_eq!(pair_set("mhs", "cmaes+lm"), STATE_OF_THE_ART_PAIRS);
        assert_eq!(pair_set("lshade", "cmaes"), STATE_OF_THE_ART_PAIRS);
        assert_eq!(comparison_set("hs", "cmaes"), "reference");
        assert_eq!(comparison_set("lshade", "cmaes"), "reference");
    }
}
