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
//! against zero with the Wilcoxon signed-rank test, and the verdict is
//! `better` or `worse` only where the test, corrected over its family,
//! rejects at α.

use std::fmt;

use super::descriptive::median;
use super::error::{check_no_nan, StatsError};
use super::hypothesis::Alternative;
use super::wilcoxon::wilcoxon_signed_rank;
use crate::files::fmt_real;

/// The verdict of a test across problems, from the compared algorithm's
/// point of view.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Verdict {
    /// The corrected test rejects and the compared algorithm is the better.
    Better,
    /// The corrected test rejects and the compared algorithm is the worse.
    Worse,
    /// The corrected test does not reject at α.
    NoDetectableDifference,
}

impl Verdict {
    /// The fixed vocabulary of `verdicts.csv`.
    pub const NAMES: [&'static str; 3] = ["better", "worse", "no detectable difference"];

    /// The verdict of an adjusted p-value at level α, given the sign of the
    /// compared algorithm's improvement (positive: it is the better): a
    /// rejection needs `p_adjusted < alpha` and a non-zero improvement.
    /// NaN p-values never reject.
    pub fn from_p(p_adjusted: f64, alpha: f64, improvement: f64) -> Verdict {
        let rejects = p_adjusted.partial_cmp(&alpha) == Some(std::cmp::Ordering::Less);
        if !rejects || improvement == 0.0 || improvement.is_nan() {
            Verdict::NoDetectableDifference
        } else if improvement > 0.0 {
            Verdict::Better
        } else {
            Verdict::Worse
        }
    }

    /// The verdict's text: `better`, `worse` or `no detectable difference`.
    pub fn as_str(self) -> &'static str {
        match self {
            Verdict::Better => Self::NAMES[0],
            Verdict::Worse => Self::NAMES[1],
            Verdict::NoDetectableDifference => Self::NAMES[2],
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

/// The columns of `verdicts.csv`, the one file every verdict across
/// problems is written to (by `report` and by `implant`).
pub const VERDICT_COLUMNS: [&str; 17] = [
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
    /// The verdict at α on `p_adjusted`.
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
            self.verdict.as_str().to_owned(),
        ]
    }
}

/// Holm-adjusts the p-values of a family of verdict rows (Holm 1979) and
/// sets each verdict at level α. A family with a NaN p-value keeps it
/// unadjusted and every verdict of the family undecided.
pub fn decide_family(rows: &mut [VerdictRow], alpha: f64) {
    let p: Vec<f64> = rows.iter().map(|r| r.across.p_value).collect();
    let adjusted = super::holm::holm_bonferroni(&p).unwrap_or_else(|_| vec![f64::NAN; p.len()]);
    let family = rows.len();
    for (r, pa) in rows.iter_mut().zip(adjusted) {
        r.p_adjusted = pa;
        r.family = family;
        r.verdict = Verdict::from_p(pa, alpha, r.across.improvement);
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
            Verdict::NoDetectableDifference
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
    fn bad_summaries_are_errors() {
        assert!(across_units(&[], true).is_err());
        assert!(across_units(&[1.0, f64::NAN], true).is_err());
        assert_eq!(
            Verdict::from_p(f64::NAN, 0.05, 1.0),
            Verdict::NoDetectableDifference
        );
        assert_eq!(
            Verdict::from_p(0.01, 0.05, 0.0),
            Verdict::NoDetectableDifference
        );
        assert_eq!(
            Verdict::NoDetectableDifference.to_string(),
            "no detectable difference"
        );
    }
}
