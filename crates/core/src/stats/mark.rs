//! The "+ / − / ≈" marks of metaheuristics papers: whether a compared algorithm
//! is significantly better than, worse than, or not distinguishable from a
//! reference algorithm.

use std::fmt;
use std::iter::FromIterator;

use super::mannwhitney::MannWhitneyResult;
use super::wilcoxon::WilcoxonResult;

/// The conventional significance level α = 0.05 (Fisher 1925, "Statistical
/// Methods for Research Workers").
pub const DEFAULT_ALPHA: f64 = 0.05;

/// Outcome of comparing a compared algorithm A with a reference algorithm R
/// under minimisation (lower is better), always from A's point of view: `Better`
/// (+) if A is significantly lower at level α, `Worse` (−) if significantly
/// higher, `Same` (≈) otherwise (e.g. Derrac et al. 2011, Swarm Evol. Comput. 1(1):3–18).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Mark {
    /// The compared algorithm is significantly better (lower): "+".
    Better,
    /// The compared algorithm is significantly worse (higher): "−".
    Worse,
    /// No significant difference at level α: "≈".
    Same,
}

impl Mark {
    /// Mark from a p-value and the signed difference A − R of a location measure
    /// (median of paired differences, mean rank, ...): `Better` if p < α and the
    /// difference is negative, `Worse` if p < α and it is positive, else `Same`
    /// (Derrac et al. 2011, Swarm Evol. Comput. 1(1):3–18). NaN p, α or difference give `Same`.
    pub fn from_p_value(p_value: f64, alpha: f64, difference: f64) -> Mark {
        let significant = p_value < alpha;
        if !significant {
            Mark::Same
        } else if difference < 0.0 {
            Mark::Better
        } else if difference > 0.0 {
            Mark::Worse
        } else {
            Mark::Same
        }
    }

    /// Mark from a Wilcoxon signed-rank test (Wilcoxon 1945) run on d = A − R,
    /// i.e. `wilcoxon(a, r, ..)`: the direction is R⁺ − R⁻ (negative when A
    /// tends to be lower), see [`Mark::from_p_value`].
    pub fn from_wilcoxon(result: &WilcoxonResult, alpha: f64) -> Mark {
        Mark::from_p_value(result.p_value, alpha, result.r_plus - result.r_minus)
    }

    /// Mark from a Mann–Whitney test (Mann & Whitney 1947) run as
    /// `mann_whitney_u(a, r, ..)`: the direction is U₁ − n₁n₂/2 (negative when A
    /// tends to be lower), see [`Mark::from_p_value`].
    pub fn from_mann_whitney(result: &MannWhitneyResult, alpha: f64) -> Mark {
        let half = (result.n1 * result.n2) as f64 / 2.0;
        Mark::from_p_value(result.p_value, alpha, result.statistic - half)
    }

    /// Typographic symbol: "+", "−" (U+2212) or "≈".
    pub fn symbol(self) -> &'static str {
        match self {
            Mark::Better => "+",
            Mark::Worse => "\u{2212}",
            Mark::Same => "\u{2248}",
        }
    }

    /// ASCII symbol: "+", "-" or "=".
    pub fn ascii(self) -> &'static str {
        match self {
            Mark::Better => "+",
            Mark::Worse => "-",
            Mark::Same => "=",
        }
    }
}

impl fmt::Display for Mark {
    /// Writes [`Mark::symbol`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

/// Counts of marks over many comparisons, the "+/≈/−" (win/tie/loss) line of a
/// results table (Derrac et al. 2011, Swarm Evol. Comput. 1(1):3–18).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct MarkTally {
    /// Number of `Better` marks.
    pub better: usize,
    /// Number of `Same` marks.
    pub same: usize,
    /// Number of `Worse` marks.
    pub worse: usize,
}

impl MarkTally {
    /// Adds one mark to the tally.
    pub fn add(&mut self, mark: Mark) {
        match mark {
            Mark::Better => self.better += 1,
            Mark::Same => self.same += 1,
            Mark::Worse => self.worse += 1,
        }
    }
}

impl FromIterator<Mark> for MarkTally {
    fn from_iter<I: IntoIterator<Item = Mark>>(iter: I) -> Self {
        let mut t = MarkTally::default();
        for m in iter {
            t.add(m);
        }
        t
    }
}

impl fmt::Display for MarkTally {
    /// Writes "better/same/worse", e.g. "3/5/2".
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}/{}", self.better, self.same, self.worse)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::{mann_whitney_u, wilcoxon, Alternative};

    #[test]
    fn from_p_value_directions() {
        assert_eq!(Mark::from_p_value(0.01, DEFAULT_ALPHA, -1.0), Mark::Better);
        assert_eq!(Mark::from_p_value(0.01, DEFAULT_ALPHA, 2.0), Mark::Worse);
        assert_eq!(Mark::from_p_value(0.01, DEFAULT_ALPHA, 0.0), Mark::Same);
        assert_eq!(Mark::from_p_value(0.05, DEFAULT_ALPHA, -1.0), Mark::Same);
        assert_eq!(Mark::from_p_value(0.2, DEFAULT_ALPHA, -1.0), Mark::Same);
        assert_eq!(
            Mark::from_p_value(f64::NAN, DEFAULT_ALPHA, -1.0),
            Mark::Same
        );
        assert_eq!(Mark::from_p_value(0.01, f64::NAN, -1.0), Mark::Same);
        assert_eq!(Mark::from_p_value(0.08, 0.10, 1.0), Mark::Worse);
    }

    #[test]
    fn from_tests_use_the_compared_algorithms_point_of_view() {
        let good = [0.1, 0.2, 0.15, 0.05, 0.3, 0.12, 0.22, 0.18, 0.09, 0.11];
        let bad = [1.1, 1.2, 1.15, 1.05, 1.3, 1.12, 1.22, 1.18, 1.09, 1.11];
        let w = wilcoxon(&good, &bad, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_wilcoxon(&w, DEFAULT_ALPHA), Mark::Better);
        let w = wilcoxon(&bad, &good, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_wilcoxon(&w, DEFAULT_ALPHA), Mark::Worse);
        let w = wilcoxon(&good, &good, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_wilcoxon(&w, DEFAULT_ALPHA), Mark::Same);
        let m = mann_whitney_u(&good, &bad, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_mann_whitney(&m, DEFAULT_ALPHA), Mark::Better);
        let m = mann_whitney_u(&bad, &good, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_mann_whitney(&m, DEFAULT_ALPHA), Mark::Worse);
        let m = mann_whitney_u(&good, &good, Alternative::TwoSided).unwrap();
        assert_eq!(Mark::from_mann_whitney(&m, DEFAULT_ALPHA), Mark::Same);
    }

    #[test]
    fn rendering_and_tally() {
        assert_eq!(Mark::Better.to_string(), "+");
        assert_eq!(Mark::Worse.to_string(), "\u{2212}");
        assert_eq!(Mark::Same.to_string(), "\u{2248}");
        assert_eq!(Mark::Worse.ascii(), "-");
        assert_eq!(Mark::Same.ascii(), "=");
        let t: MarkTally = [Mark::Better, Mark::Same, Mark::Better, Mark::Worse]
            .into_iter()
            .collect();
        assert_eq!(
            t,
            MarkTally {
                better: 2,
                same: 1,
                worse: 1
            }
        );
        assert_eq!(t.to_string(), "2/1/1");
    }
}
