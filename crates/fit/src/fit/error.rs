//! Why a fit was refused.

use std::fmt;

use super::FunctionType;
use crate::geometry::Point;

/// An invalid fitting request, with a message saying what to change.
#[derive(Clone, Debug, PartialEq)]
pub enum FitError {
    /// A segment has fewer data points than its function needs
    /// ([`FunctionType::min_points`]).
    TooFewPoints {
        /// The segment's position along the outline (0-based).
        segment: usize,
        /// Index of its first data point.
        first: usize,
        /// Index of its last data point (it may wrap around a closed outline).
        last: usize,
        /// Points found.
        found: usize,
        /// Points needed.
        needed: usize,
        /// The function being fitted.
        function: FunctionType,
    },
    /// The outline has too few points to fit anything.
    TooFewOutlinePoints {
        /// Points given.
        found: usize,
        /// Points needed.
        needed: usize,
    },
    /// A data point has a NaN or infinite coordinate.
    NonFinitePoint {
        /// Its index.
        index: usize,
    },
    /// A split tolerance is not finite and positive.
    InvalidTolerance(f64),
    /// The weight range `[w_min, w_max]` is not `0 < w_min < w_max < ∞`.
    InvalidWeightRange {
        /// The lower end given.
        min: f64,
        /// The upper end given.
        max: f64,
    },
    /// The G¹ ratio range `[T_min, T_max]` is not `0 < T_min < T_max < ∞`.
    InvalidTRange {
        /// The lower end given.
        min: f64,
        /// The upper end given.
        max: f64,
    },
    /// Another option is outside its domain.
    InvalidOption {
        /// The option's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The admissible values.
        expected: &'static str,
    },
    /// A break index is not a point of the outline.
    BreakOutOfRange {
        /// The index given.
        index: usize,
        /// The number of points.
        len: usize,
    },
    /// Break indices must be strictly increasing.
    BreaksNotSorted {
        /// Position in the list of the offending index.
        position: usize,
        /// The index before it.
        previous: usize,
        /// The offending index.
        index: usize,
    },
    /// Fewer segments were requested than the corners make.
    TooFewSegments {
        /// Segments requested.
        requested: usize,
        /// The least possible (one per span between corners).
        minimum: usize,
    },
    /// More segments were requested than the outline has gaps between
    /// consecutive points (each segment spans at least one).
    TooManySegments {
        /// Segments requested.
        requested: usize,
        /// The most possible: the points less one for an open outline, the
        /// points for a closed one.
        maximum: usize,
        /// The outline's points.
        points: usize,
        /// Whether the outline is closed.
        closed: bool,
    },
    /// The decision vector has the wrong length.
    DimensionMismatch {
        /// The problem's dimension.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// The joint chain ([`crate::fit::Chain::Joint`]) was asked for
    /// quadratic segments with C¹ joins, which their first segment
    /// determines (one inner control point each).
    JointQuadraticC1,
    /// A `--tolerance` fit could not hold its tolerance: the split reached
    /// its limits with a segment whose two-sided distance to the outline,
    /// beyond the staircase's allowance, is still above it.
    ToleranceNotMet {
        /// The tolerance asked for.
        tolerance: f64,
        /// The segment's two-sided distance (beyond the staircase's
        /// allowance for a traced image, [`crate::fit::SplitOptions::staircase`]).
        excess: f64,
        /// The segment's position along the contour (0-based, fitting order).
        segment: usize,
        /// Its first data point (outline index).
        first: usize,
        /// Its last data point (outline index).
        last: usize,
        /// Where the distance is largest: the data point at the start of
        /// that gap.
        at: Point,
    },
    /// A fit of one contour of a shape failed.
    Contour {
        /// The contour's number in its input.
        contour: usize,
        /// Why.
        error: Box<FitError>,
    },
}

impl FitError {
    /// `error`, located in contour `contour` of a shape.
    pub fn in_contour(contour: usize, error: FitError) -> FitError {
        FitError::Contour {
            contour,
            error: Box::new(error),
        }
    }
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::TooFewPoints {
                segment,
                first,
                last,
                found,
                needed,
                function,
            } => write!(
                f,
                "segment {segment} (points {first}..={last}) has {found} data point(s), \
                 but a {function} segment needs at least {needed}; \
                 use fewer segments or a lower-degree function"
            ),
            FitError::TooFewOutlinePoints { found, needed } => write!(
                f,
                "the outline has {found} point(s); at least {needed} are needed"
            ),
            FitError::NonFinitePoint { index } => {
                write!(f, "data point {index} has a non-finite coordinate")
            }
            FitError::InvalidTolerance(t) => write!(
                f,
                "the split tolerance must be a finite distance > 0, found {t}"
            ),
            FitError::InvalidWeightRange { min, max } => write!(
                f,
                "the weight range [{min}, {max}] is invalid: rational weights must stay \
                 strictly positive, so it needs 0 < w_min < w_max (finite), e.g. [0.01, 10]"
            ),
            FitError::InvalidTRange { min, max } => write!(
                f,
                "the G1 ratio range [{min}, {max}] is invalid: it needs 0 < T_min < T_max \
                 (finite), e.g. [0.05, 5]"
            ),
            FitError::InvalidOption {
                name,
                value,
                expected,
            } => write!(f, "option {name} = {value} is invalid: expected {expected}"),
            FitError::BreakOutOfRange { index, len } => write!(
                f,
                "break index {index} is out of range for an outline of {len} points \
                 (valid: 0..={})",
                len.saturating_sub(1)
            ),
            FitError::BreaksNotSorted {
                position,
                previous,
                index,
            } => write!(
                f,
                "break indices must be strictly increasing, but break {position} is {index} \
                 after {previous}"
            ),
            FitError::TooFewSegments { requested, minimum } => write!(
                f,
                "{requested} segment(s) requested, but the corners split the outline into \
                 {minimum} span(s); ask for at least {minimum}"
            ),
            FitError::TooManySegments {
                requested,
                maximum,
                points,
                closed,
            } => write!(
                f,
                "{requested} segment(s) requested, but {} outline of {points} points allows at \
                 most {maximum} (each segment spans at least one gap between consecutive \
                 points); ask for at most {maximum}",
                if *closed { "a closed" } else { "an open" }
            ),
            FitError::DimensionMismatch { expected, found } => write!(
                f,
                "the decision vector has {found} value(s), the problem {expected}"
            ),
            FitError::JointQuadraticC1 => write!(
                f,
                "the joint chain cannot join quadratic segments C1: each has one inner control \
                 point, so C1 joins fix every segment from the first; use chain \"sequential\", \
                 G1 joins, or a cubic or rational cubic function"
            ),
            FitError::ToleranceNotMet {
                tolerance,
                excess,
                segment,
                first,
                last,
                at,
            } => write!(
                f,
                "the tolerance {tolerance} is not met: segment {segment} (points {first}..{last}) \
                 is {excess:.4} from the outline near ({:.2}, {:.2}) and the split limits stop \
                 there; raise --tolerance or use --segments",
                at.x, at.y
            ),
            FitError::Contour { contour, error } => write!(f, "contour {contour}: {error}"),
        }
    }
}

impl std::error::Error for FitError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            FitError::Contour { error, .. } => Some(error.as_ref()),
            _ => None,
        }
    }
}
