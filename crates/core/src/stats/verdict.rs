//! Verdicts across problems: the second level of a two-level comparison.
//!
//! The first level describes one problem (a function instance, a fitting
//! case, a defect case) with a test of its runs. A claim that reaches
//! across problems ("A is better than B at budget 10⁴") needs a test whose
//! units are independent problems, not a vote count of first-level marks
//! (Demšar 2006, JMLR 7:1–30; García & Herrera 2008, JMLR 9:2677–2694;
//! Benavoli, Corani & Mangili 2016, JMLR 17(5):1–10). Each unit (a
//! function with its instances summarised by their median, an outline, a
//! segment, a defect position) contributes one summary of the difference
//! between the two algorithms; [`across_units`] tests those summaries
//! against zero with the Wilcoxon signed-rank test. Beside it
//! ([`unit_evidence`]): the Hodges–Lehmann estimate of the summaries with
//! its exact signed-rank interval, and the Bayesian signed-rank test with a
//! region of practical equivalence (Benavoli, Corani, Demšar & Zaffalon
//! 2017, JMLR 18(77):1–36). The verdict ([`Verdict::decide`]) is
//! `equivalent` where the posterior puts at least 0.95 within the rope,
//! `better` or `worse` where the Wilcoxon test, corrected over its family,
//! rejects at α, and `undecided` otherwise: a test that does not reject has
//! found no detectable difference, which is not a finding of equality.

use std::fmt;

use super::bayes_signed_rank::{bayesian_signed_rank, BayesSignedRank};
use super::descriptive::median;
use super::error::{check_no_nan, StatsError};
use super::hodges_lehmann::{hodges_lehmann_interval, ShiftInterval};
use super::hypothesis::Alternative;
use super::wilcoxon::wilcoxon_signed_rank;
use crate::files::fmt_real;
use crate::rng::{fnv1a64, splitmix64};

/// The verdict of a comparison across problems, from the compared
/// algorithm's point of view, decided in this order: `equivalent` where the
/// Bayesian signed-rank test puts at least [`EQUIVALENCE_PROBABILITY`] on
/// the region of practical equivalence (even where a tiny difference is
/// significant), `better` or `worse` where the corrected frequentist test
/// rejects, `undecided` otherwise (Benavoli, Corani, Demšar & Zaffalon 2017,
/// "Time for a change", JMLR 18(77):1–36, §4–5). A test that does not reject
/// shows *no detectable difference*: that is not a verdict of equality.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// The corrected test rejects and the compared algorithm is the better.
    Better,
    /// The corrected test rejects and the compared algorithm is the worse.
    Worse,
    /// P(rope) ≥ [`EQUIVALENCE_PROBABILITY`]: the two are practically
    /// equivalent on this measure.
    Equivalent,
    /// Neither equivalence nor a rejection: the data cannot decide.
    Undecided,
}

/// The posterior probability of the region of practical equivalence at or
/// above which a comparison is [`Verdict::Equivalent`] (Benavoli et al.
/// 2017, §5: decisions at 0.95).
pub const EQUIVALENCE_PROBABILITY: f64 = 0.95;

/// The fewest units on which a comparison can be [`Verdict::Equivalent`]:
/// six, the fewest with a finite 95 % signed-rank interval of the shift.
/// The Dirichlet process posterior puts its mass on the observed summaries
/// and the prior's 0 only, so one unit at 0 would give P(rope) = 1; a claim
/// of equivalence needs as many units as an interval of the effect.
pub const EQUIVALENCE_MIN_UNITS: usize = 6;

impl Verdict {
    /// The fixed vocabulary of `verdicts.csv`.
    pub const NAMES: [&'static str; 4] = ["better", "worse", "equivalent", "undecided"];

    /// The frequentist half of a verdict: an adjusted p-value at level α,
    /// given the sign of the compared algorithm's improvement (positive: it
    /// is the better). A rejection needs `p_adjusted < alpha` and a non-zero
    /// improvement; NaN p-values never reject ([`Verdict::Undecided`]).
    pub fn from_p(p_adjusted: f64, alpha: f64, improvement: f64) -> Verdict {
        let rejects = p_adjusted.partial_cmp(&alpha) == Some(std::cmp::Ordering::Less);
        if !rejects || improvement == 0.0 || improvement.is_nan() {
            Verdict::Undecided
        } else if improvement > 0.0 {
            Verdict::Better
        } else {
            Verdict::Worse
        }
    }

    /// The whole verdict: [`Verdict::Equivalent`] where
    /// `equivalence.within` ≥ [`EQUIVALENCE_PROBABILITY`] over at least
    /// [`EQUIVALENCE_MIN_UNITS`] units, else [`Verdict::from_p`].
    pub fn decide(
        p_adjusted: f64,
        alpha: f64,
        improvement: f64,
        equivalence: &Equivalence,
    ) -> Verdict {
        if equivalence.within >= EQUIVALENCE_PROBABILITY
            && equivalence.units >= EQUIVALENCE_MIN_UNITS
        {
            Verdict::Equivalent
        } else {
            Verdict::from_p(p_adjusted, alpha, improvement)
        }
    }

    /// The verdict's text: `better`, `worse`, `equivalent` or `undecided`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Better => Self::NAMES[0],
            Verdict::Worse => Self::NAMES[1],
            Verdict::Equivalent => Self::NAMES[2],
            Verdict::Undecided => Self::NAMES[3],
        }
    }
}

impl fmt::Display for Verdict {
    /// Writes [`Verdict::as_str`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// The smallest two-sided p-value the Wilcoxon signed-rank test can give
/// with `n` non-zero differences: every sign alike has probability 2/2ⁿ
/// under the null hypothesis (Wilcoxon 1945), whatever the ranks and ties.
/// With no non-zero difference it is 1. Eight units give 2/256 ≈ 0.0078;
/// four give 0.125, so no verdict on four units can reject at α = 0.05.
pub fn smallest_signed_rank_p(n: usize) -> f64 {
    if n == 0 {
        1.0
    } else {
        2f64.powi(1 - n.min(1000) as i32).min(1.0)
    }
}

/// The test of per-unit summaries against zero.
#[derive(Clone, Debug, PartialEq)]
pub struct AcrossUnits {
    /// The number of units.
    pub units: usize,
    /// Units whose summary favours the compared algorithm.
    pub better: usize,
    /// Units whose summary is exactly zero (dropped by the test).
    pub equal: usize,
    /// Units whose summary favours the reference.
    pub worse: usize,
    /// The two-sided Wilcoxon signed-rank p-value of the summaries.
    pub p_value: f64,
    /// The smallest p-value the test can give with these units
    /// ([`smallest_signed_rank_p`] of the non-zero summaries).
    pub p_min: f64,
    /// The median of the summaries over the units.
    pub effect_size: f64,
    /// Positive when the compared algorithm tends to be the better (by the
    /// signed ranks: R⁻ − R⁺ when lower is better, R⁺ − R⁻ otherwise).
    pub improvement: f64,
}

/// The Wilcoxon signed-rank test (SciPy's defaults, zeros dropped) of the
/// per-unit summaries `d` against zero, with the counts of units on either
/// side, the smallest attainable p and the median summary as effect size.
/// `lower_is_better` says which sign favours the compared algorithm: for a
/// summary log10(median A / median R) of errors a negative value does.
///
/// Errors on an empty slice or a NaN summary.
pub fn across_units(d: &[f64], lower_is_better: bool) -> Result<AcrossUnits, StatsError> {
    if d.is_empty() {
        return Err(StatsError::EmptyInput {
            what: "per-unit summaries",
        });
    }
    check_no_nan(d, "per-unit summaries")?;
    let favours = |x: f64| if lower_is_better { x < 0.0 } else { x > 0.0 };
    let better = d.iter().filter(|&&x| favours(x)).count();
    let equal = d.iter().filter(|&&x| x == 0.0).count();
    let worse = d.len() - better - equal;
    let w = wilcoxon_signed_rank(d, Alternative::TwoSided)?;
    let signed = w.r_plus - w.r_minus;
    Ok(AcrossUnits {
        units: d.len(),
        better,
        equal,
        worse,
        p_value: w.p_value,
        p_min: smallest_signed_rank_p(w.n),
        effect_size: median(d),
        improvement: if lower_is_better { -signed } else { signed },
    })
}

/// The posterior of the Bayesian signed-rank test of a comparison's
/// per-unit summaries, from the compared algorithm's point of view
/// (Benavoli, Corani, Demšar & Zaffalon 2017, JMLR 18(77):1–36, §5.2): the
/// probabilities that the algorithm is better by more than the region of
/// practical equivalence (rope) ±r, that the difference lies within it, and
/// that the reference is better by more than r. NaN where the comparison
/// has no unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Equivalence {
    /// The half-width r of the rope, in the units of the per-unit summaries
    /// (decades of the error ratio, AUC, Dice, mm).
    pub rope: f64,
    /// P(the compared algorithm is better by more than r).
    pub better: f64,
    /// P(the difference lies within ±r).
    pub within: f64,
    /// P(the reference is better by more than r).
    pub worse: f64,
    /// The number of units the posterior is over.
    pub units: usize,
}

impl Equivalence {
    /// No posterior (no unit): every probability NaN.
    pub fn unknown(rope: f64) -> Equivalence {
        Equivalence {
            rope,
            better: f64::NAN,
            within: f64::NAN,
            worse: f64::NAN,
            units: 0,
        }
    }
}

impl ShiftInterval {
    /// No estimate (no unit): every field NaN.
    pub fn unknown() -> ShiftInterval {
        ShiftInterval {
            estimate: f64::NAN,
            low: f64::NAN,
            high: f64::NAN,
            level: f64::NAN,
        }
    }
}

/// The confidence of the Hodges–Lehmann interval beside every verdict.
pub const EFFECT_CONFIDENCE: f64 = 0.95;

/// The seed of a verdict row's Monte Carlo sample: SplitMix64 of the FNV-1a
/// hash of its table, measure, algorithm, reference, scope and test, so a
/// row's probabilities do not depend on the order or the number of rows.
pub fn verdict_seed(row: &VerdictRow) -> u64 {
    let key = [
        row.table.as_str(),
        &row.measure,
        &row.algorithm,
        &row.reference,
        &row.scope,
        row.test.as_str(),
    ]
    .join("\u{1f}");
    splitmix64(fnv1a64(&key))
}

/// The evidence beside a verdict, from the per-unit summaries `d` in the
/// measure's own sign: the Hodges–Lehmann estimate with its exact
/// signed-rank 95 % interval ([`hodges_lehmann_interval`]) and the
/// Bayesian signed-rank posterior with rope ±`rope` ([`bayesian_signed_rank`],
/// baycomp's prior and its 50,000 samples, [`BayesSignedRank::with_rope`],
/// from `seed`; the Monte Carlo error of a probability is at most
/// 0.5/√50,000 ≈ 0.0022), turned to the algorithm's
/// point of view by `lower_is_better`. Empty or NaN summaries give NaN
/// evidence.
pub fn unit_evidence(
    d: &[f64],
    lower_is_better: bool,
    rope: f64,
    seed: u64,
) -> (ShiftInterval, Equivalence) {
    let shift =
        hodges_lehmann_interval(d, EFFECT_CONFIDENCE).unwrap_or_else(|_| ShiftInterval::unknown());
    let test = BayesSignedRank {
        seed,
        ..BayesSignedRank::with_rope(rope)
    };
    let equivalence = match bayesian_signed_rank(d, &test) {
        Ok(p) => {
            let (better, worse) = if lower_is_better {
                (p.left, p.right)
            } else {
                (p.right, p.left)
            };
            Equivalence {
                rope,
                better,
                within: p.rope,
                worse,
                units: d.len(),
            }
        }
        Err(_) => Equivalence::unknown(rope),
    };
    (shift, equivalence)
}

/// The columns of `verdicts.csv`, the one file every verdict across
/// problems is written to (by `report` and by `implant`).
pub const VERDICT_COLUMNS: [&str; 24] = [
    "table",
    "measure",
    "algorithm",
    "reference",
    "scope",
    "units",
    "problems",
    "better",
    "equal",
    "worse",
    "test",
    "p_value",
    "p_adjusted",
    "p_min",
    "family",
    "effect_size",
    "effect_hl",
    "effect_ci_low",
    "effect_ci_high",
    "rope",
    "prob_better",
    "prob_equivalent",
    "prob_worse",
    "verdict",
];

/// The test of a verdict row, with the fixed vocabulary of `verdicts.csv`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VerdictTest {
    /// The Wilcoxon signed-rank test of the per-unit summaries against zero,
    /// Holm-corrected over the rows of its family ([`across_units`]).
    WilcoxonSignedRank,
    /// Friedman's test over the units with the z-test of average ranks
    /// against the reference, Holm-corrected ([`crate::stats::friedman_control_posthoc`]).
    FriedmanHolm,
    /// As [`VerdictTest::FriedmanHolm`] with Finner's correction.
    FriedmanFinner,
}

impl VerdictTest {
    /// `wilcoxon-signed-rank`, `friedman-holm` or `friedman-finner`.
    pub fn as_str(self) -> &'static str {
        match self {
            VerdictTest::WilcoxonSignedRank => "wilcoxon-signed-rank",
            VerdictTest::FriedmanHolm => "friedman-holm",
            VerdictTest::FriedmanFinner => "friedman-finner",
        }
    }
}

/// One verdict across problems: who is compared with whom, on which
/// measure, over which scope, by which test, and the verdict.
#[derive(Clone, Debug, PartialEq)]
pub struct VerdictRow {
    /// The comparison set the row belongs to. The report's correction family
    /// is the rows of one table, measure, test and scope (accuracy and
    /// convergence are separate claims); the implant's is the rows of one
    /// table and scope, its metrics together.
    pub table: String,
    /// What is compared: `final-error`, `anytime-auc`, a metric name.
    pub measure: String,
    /// The compared algorithm (or treatment).
    pub algorithm: String,
    /// The reference it is compared with.
    pub reference: String,
    /// `all`, or `factor=level;factor=level`.
    pub scope: String,
    /// The first-level observations (problems, segments, cases) pooled
    /// into the units.
    pub problems: usize,
    /// The test.
    pub test: VerdictTest,
    /// The units, their counts, the unadjusted p, p_min and the effect.
    pub across: AcrossUnits,
    /// The p-value after the family's correction.
    pub p_adjusted: f64,
    /// The number of rows of the correction family: no adjusted p of the
    /// family can be below `family` × the family's smallest `p_min`.
    pub family: usize,
    /// The Hodges–Lehmann estimate of the per-unit summaries with its
    /// exact signed-rank 95 % interval.
    pub shift: ShiftInterval,
    /// The Bayesian signed-rank posterior with its rope.
    pub equivalence: Equivalence,
    /// The verdict ([`Verdict::decide`]).
    pub verdict: Verdict,
}

impl VerdictRow {
    /// The row's fields in the order of [`VERDICT_COLUMNS`], reals in their
    /// shortest round-trip form.
    pub fn csv_fields(&self) -> Vec<String> {
        let a = &self.across;
        vec![
            self.table.clone(),
            self.measure.clone(),
            self.algorithm.clone(),
            self.reference.clone(),
            self.scope.clone(),
            a.units.to_string(),
            self.problems.to_string(),
            a.better.to_string(),
            a.equal.to_string(),
            a.worse.to_string(),
            self.test.as_str().to_owned(),
            fmt_real(a.p_value),
            fmt_real(self.p_adjusted),
            fmt_real(a.p_min),
            self.family.to_string(),
            fmt_real(a.effect_size),
            fmt_real(self.shift.estimate),
            fmt_real(self.shift.low),
            fmt_real(self.shift.high),
            fmt_real(self.equivalence.rope),
            fmt_real(self.equivalence.better),
            fmt_real(self.equivalence.within),
            fmt_real(self.equivalence.worse),
            self.verdict.as_str().to_owned(),
        ]
    }

    /// Sets the row's interval and posterior from its per-unit summaries
    /// `d` with rope ±`rope` ([`unit_evidence`], seeded by [`verdict_seed`]).
    /// Call it once the row's names are set.
    pub fn weigh(&mut self, d: &[f64], lower_is_better: bool, rope: f64) {
        let (shift, equivalence) = unit_evidence(d, lower_is_better, rope, verdict_seed(self));
        self.shift = shift;
        self.equivalence = equivalence;
    }
}

/// Holm-adjusts the p-values of a family of verdict rows (Holm 1979) and
/// sets each verdict at level α with its equivalence ([`Verdict::decide`]).
/// A family with a NaN p-value keeps it unadjusted, and no verdict of the
/// family is better or worse.
pub fn decide_family(rows: &mut [VerdictRow], alpha: f64) {
    let p: Vec<f64> = rows.iter().map(|r| r.across.p_value).collect();
    let adjusted = super::holm::holm_bonferroni(&p).unwrap_or_else(|_| vec![f64::NAN; p.len()]);
    let family = rows.len();
    for (r, pa) in rows.iter_mut().zip(adjusted) {
        r.p_adjusted = pa;
        r.family = family;
        r.verdict = Verdict::decide(pa, alpha, r.across.improvement, &r.equivalence);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_p_is_out_of_reach_on_four_units() {
        assert_eq!(smallest_signed_rank_p(0), 1.0);
        assert_eq!(smallest_signed_rank_p(1), 1.0);
        assert_eq!(smallest_signed_rank_p(4), 0.125);
        assert_eq!(smallest_signed_rank_p(8), 2.0 / 256.0);
        assert!(smallest_signed_rank_p(5000) > 0.0);
    }

    #[test]
    fn four_equal_and_four_better_units_cannot_reject() {
        // Four units with the reference's values, four 1000× better:
        // SciPy 1.17.1 `wilcoxon([0,0,0,0,-3,-3,-3,-3])` gives p = 0.125.
        let d = [0.0, 0.0, 0.0, 0.0, -3.0, -3.0, -3.0, -3.0];
        let t = across_units(&d, true).unwrap();
        assert_eq!((t.units, t.better, t.equal, t.worse), (8, 4, 4, 0));
        assert!((t.p_value - 0.125).abs() < 1e-12, "{}", t.p_value);
        assert_eq!(t.p_min, 0.125);
        assert_eq!(t.effect_size, -1.5);
        assert!(t.improvement > 0.0);
        assert_eq!(
            Verdict::from_p(t.p_value, 0.05, t.improvement),
            Verdict::Undecided
        );
        // Eight of eight better: p = 2/256 = 0.0078125 (SciPy, exact).
        let t = across_units(&[-3.0; 8], true).unwrap();
        assert!((t.p_value - 0.0078125).abs() < 1e-12, "{}", t.p_value);
        assert_eq!(
            Verdict::from_p(t.p_value, 0.05, t.improvement),
            Verdict::Better
        );
        // The same summaries with higher-is-better read the other way.
        let t = across_units(&[-3.0; 8], false).unwrap();
        assert_eq!((t.better, t.worse), (0, 8));
        assert_eq!(
            Verdict::from_p(t.p_value, 0.05, t.improvement),
            Verdict::Worse
        );
    }

    #[test]
    fn equivalence_comes_first_and_needs_six_units() {
        let eq = |within: f64, units: usize| Equivalence {
            rope: 0.3,
            better: 0.0,
            within,
            worse: 1.0 - within,
            units,
        };
        // A tiny but significant difference within the rope: equivalent.
        assert_eq!(
            Verdict::decide(0.001, 0.05, 1.0, &eq(0.97, 24)),
            Verdict::Equivalent
        );
        assert_eq!(
            Verdict::decide(0.001, 0.05, 1.0, &eq(0.90, 24)),
            Verdict::Better
        );
        assert_eq!(
            Verdict::decide(0.2, 0.05, 1.0, &eq(0.90, 24)),
            Verdict::Undecided
        );
        // Five units are too few for equivalence, whatever the posterior.
        assert_eq!(
            Verdict::decide(0.2, 0.05, 1.0, &eq(1.0, 5)),
            Verdict::Undecided
        );
        assert_eq!(
            Verdict::decide(0.2, 0.05, 1.0, &eq(1.0, 6)),
            Verdict::Equivalent
        );
        // NaN evidence (no unit) never decides.
        let none = Equivalence::unknown(0.3);
        assert_eq!(
            Verdict::decide(f64::NAN, 0.05, 1.0, &none),
            Verdict::Undecided
        );
    }

    #[test]
    fn evidence_is_seeded_by_the_row_and_oriented_by_the_measure() {
        let d = [-0.5, -0.4, -0.45, -0.6, -0.2, -0.55, -0.5, -0.35];
        let (shift, lower) = unit_evidence(&d, true, 0.1, 7);
        let (_, higher) = unit_evidence(&d, false, 0.1, 7);
        assert!(shift.high < 0.0, "{shift:?}");
        assert!(
            lower.better > 0.9 && higher.worse > 0.9,
            "{lower:?} {higher:?}"
        );
        assert_eq!(lower.better.to_bits(), higher.worse.to_bits());
        assert_eq!(lower.units, 8);
        // No unit: NaN evidence.
        let (s, e) = unit_evidence(&[], true, 0.1, 7);
        assert!(s.estimate.is_nan() && e.within.is_nan());
    }

    #[test]
    fn bad_summaries_are_errors() {
        assert!(across_units(&[], true).is_err());
        assert!(across_units(&[1.0, f64::NAN], true).is_err());
        assert_eq!(Verdict::from_p(f64::NAN, 0.05, 1.0), Verdict::Undecided);
        assert_eq!(Verdict::from_p(0.01, 0.05, 0.0), Verdict::Undecided);
        assert_eq!(Verdict::Undecided.to_string(), "undecided");
    }
}
