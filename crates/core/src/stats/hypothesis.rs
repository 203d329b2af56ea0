//! Vocabulary shared by the hypothesis tests: the alternative hypothesis and
//! how a p-value was obtained.

use std::fmt;

/// The alternative hypothesis of a two-sample or paired test, with SciPy's
/// meaning: `Less` says the first sample (or the paired differences x − y)
/// tends to be smaller, `Greater` that it tends to be larger.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Alternative {
    /// The two locations differ in either direction (the default).
    #[default]
    TwoSided,
    /// The first sample (or x − y) is stochastically smaller.
    Less,
    /// The first sample (or x − y) is stochastically larger.
    Greater,
}

impl fmt::Display for Alternative {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Alternative::TwoSided => "two-sided",
            Alternative::Less => "less",
            Alternative::Greater => "greater",
        })
    }
}

/// How a p-value was computed: from the exact null distribution of the
/// statistic (Wilcoxon 1945; Mann & Whitney 1947), from the exact conditional
/// (permutation) distribution given ties and zeros, or from the normal
/// approximation with tie and continuity corrections.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PValueMethod {
    /// Exact null distribution of the untied statistic.
    Exact,
    /// Exact permutation (sign-flip) distribution of the statistic computed
    /// with midranks, as SciPy's `method='auto'` does for small samples with ties or zeros.
    Permutation,
    /// Normal approximation with tie correction and continuity correction.
    Asymptotic,
}

impl fmt::Display for PValueMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PValueMethod::Exact => "exact",
            PValueMethod::Permutation => "permutation",
            PValueMethod::Asymptotic => "asymptotic",
        })
    }
}
