//! The error type shared by every function of the statistics module.

use std::fmt;

/// Why a statistic or test could not be computed; every function of
/// [`crate::stats`] reports bad input with this enum instead of panicking.
#[derive(Clone, Debug, PartialEq)]
pub enum StatsError {
    /// A sample that must hold at least one value was empty.
    EmptyInput {
        /// Which input was empty.
        what: &'static str,
    },
    /// An input value was NaN (rank statistics and summaries are undefined on NaN).
    NotANumber {
        /// Which input held the NaN.
        what: &'static str,
        /// Position of the first NaN in that input.
        index: usize,
    },
    /// Two inputs that must have the same length (paired samples, rows of a matrix) did not.
    LengthMismatch {
        /// Which inputs disagree.
        what: &'static str,
        /// The length that was required.
        expected: usize,
        /// The length that was found.
        found: usize,
    },
    /// A parameter lies outside its domain (for example a probability outside [0, 1]).
    InvalidParameter {
        /// Name of the parameter.
        name: &'static str,
        /// What was wrong with it.
        reason: &'static str,
    },
    /// A tabulated constant was requested outside its table (Nemenyi q_α: k = 2..10, α ∈ {0.05, 0.10}).
    OutOfTable {
        /// Number of treatments requested.
        k: usize,
        /// Significance level requested.
        alpha: f64,
    },
}

impl fmt::Display for StatsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StatsError::EmptyInput { what } => write!(f, "{what} is empty"),
            StatsError::NotANumber { what, index } => {
                write!(f, "{what} contains NaN at index {index}")
            }
            StatsError::LengthMismatch {
                what,
                expected,
                found,
            } => write!(f, "{what}: expected length {expected}, found {found}"),
            StatsError::InvalidParameter { name, reason } => {
                write!(f, "invalid parameter `{name}`: {reason}")
            }
            StatsError::OutOfTable { k, alpha } => write!(
                f,
                "no tabulated Nemenyi q for k = {k}, alpha = {alpha} \
                 (table covers k = 2..=10 and alpha = 0.05 or 0.10)"
            ),
        }
    }
}

impl std::error::Error for StatsError {}

/// Returns an error naming `what` if `values` contains a NaN.
pub(crate) fn check_no_nan(values: &[f64], what: &'static str) -> Result<(), StatsError> {
    match values.iter().position(|v| v.is_nan()) {
        Some(index) => Err(StatsError::NotANumber { what, index }),
        None => Ok(()),
    }
}

/// Returns an error naming `what` if `values` is empty.
pub(crate) fn check_non_empty(values: &[f64], what: &'static str) -> Result<(), StatsError> {
    if values.is_empty() {
        Err(StatsError::EmptyInput { what })
    } else {
        Ok(())
    }
}
