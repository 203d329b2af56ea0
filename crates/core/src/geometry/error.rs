//! Errors raised when constructing geometry from user data.

use std::fmt;

/// Why a curve, weight set, join or parameter range was rejected.
#[derive(Clone, Debug, PartialEq)]
pub enum GeometryError {
    /// A curve needs at least one control point.
    Empty,
    /// The number of weights differs from the number of control points.
    LengthMismatch {
        /// Number of control points given.
        points: usize,
        /// Number of weights given.
        weights: usize,
    },
    /// A control point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// Index of the offending control point.
        index: usize,
    },
    /// A rational weight is not finite and strictly positive (Farin 2002,
    /// §13.1: positive weights keep the curve inside the convex hull).
    InvalidWeight {
        /// Index of the offending weight in `w_0..w_m`.
        index: usize,
        /// The rejected value.
        value: f64,
    },
    /// A scalar parameter is outside its documented domain.
    InvalidParameter {
        /// Name of the parameter (e.g. `"T"`).
        name: &'static str,
        /// The rejected value.
        value: f64,
    },
    /// The wrong number of free parameters was supplied to a join.
    FreeParamCount {
        /// Number the continuity needs.
        expected: usize,
        /// Number supplied.
        found: usize,
    },
    /// A sub-range `a..=b` is empty or runs past the end of the data.
    InvalidRange {
        /// First index.
        a: usize,
        /// Last index (inclusive).
        b: usize,
        /// Length of the data.
        len: usize,
    },
}

impl fmt::Display for GeometryError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Empty => write!(f, "a curve needs at least one control point"),
            Self::LengthMismatch { points, weights } => write!(
                f,
                "{points} control points but {weights} weights (they must match)"
            ),
            Self::NonFinitePoint { index } => {
                write!(f, "control point {index} has a non-finite coordinate")
            }
            Self::InvalidWeight { index, value } => write!(
                f,
                "weight w{index} = {value} is invalid: weights must be finite and > 0"
            ),
            Self::InvalidParameter { name, value } => {
                write!(f, "parameter {name} = {value} is outside its domain")
            }
            Self::FreeParamCount { expected, found } => write!(
                f,
                "this join needs {expected} free parameter(s) but {found} were given"
            ),
            Self::InvalidRange { a, b, len } => write!(
                f,
                "index range {a}..={b} is invalid for {len} values (need a ≤ b < len)"
            ),
        }
    }
}

impl std::error::Error for GeometryError {}

/// Checks that a weight is finite and strictly positive.
#[inline]
pub(crate) fn check_weight(index: usize, value: f64) -> Result<(), GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(GeometryError::InvalidWeight { index, value })
    }
}

/// Checks that every point is finite.
#[inline]
pub(crate) fn check_points(points: &[crate::geometry::Point]) -> Result<(), GeometryError> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(GeometryError::NonFinitePoint { index }),
        None => Ok(()),
    }
}
