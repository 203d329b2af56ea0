//! Why a benchmark function cannot be set up at a dimension or with a
//! transform.

use std::fmt;

use super::{Function, Transform, MAX_ROTATION_DIM};

/// Why a [`TestProblem`](super::TestProblem) could not be built: the
/// requested dimension is not one the benchmark function of Yao et al.
/// (1999) is defined for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FunctionError {
    /// Dimension 0 was requested for a scalable function (which needs `D ≥ 1`).
    ZeroDimension {
        /// The function requested.
        function: Function,
    },
    /// A fixed-dimension function (the camel-back, `D = 2`) was requested at another dimension.
    WrongDimension {
        /// The function requested.
        function: Function,
        /// The only dimension it is defined for.
        required: usize,
        /// The dimension that was asked for.
        requested: usize,
    },
    /// A transform was asked for a function that does not admit one
    /// ([`Function::is_transformable`]).
    NotTransformable {
        /// The function requested.
        function: Function,
        /// The transform requested.
        transform: Transform,
    },
    /// A rotation was asked above [`MAX_ROTATION_DIM`].
    RotationTooLarge {
        /// The dimension that was asked for.
        requested: usize,
    },
}

impl fmt::Display for FunctionError {
    /// A sentence naming the function and the valid dimension(s).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FunctionError::ZeroDimension { function } => write!(
                f,
                "{function} is defined only for dimension 1 or more, not 0"
            ),
            FunctionError::WrongDimension {
                function,
                required,
                requested,
            } => write!(
                f,
                "{function} is defined only for dimension {required}, not {requested}"
            ),
            FunctionError::NotTransformable {
                function,
                transform,
            } => write!(
                f,
                "{function} has no \"{transform}\" instances: only sphere, schwefel_2_22, rosenbrock, step, schwefel_1_2, rastrigin, ackley and griewank are shifted or rotated ({})",
                match function {
                    Function::SixHumpCamel => "the camel-back has two global minimisers and a fixed dimension",
                    _ => "Schwefel 2.26's minimiser lies near a corner of the box, so a shift would move it out",
                }
            ),
            FunctionError::RotationTooLarge { requested } => write!(
                f,
                "a rotation needs D ≤ {MAX_ROTATION_DIM} (it has D² entries and costs O(D³) to draw), not {requested}; use \"shift\""
            ),
        }
    }
}

impl std::error::Error for FunctionError {}
