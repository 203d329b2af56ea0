//! Where each quantity of a segment's fit sits in its decision vector:
//! the inner control points (free, derived from a C¹ join, or a G¹ join's
//! ratio) and the weights.

use super::{End, Start};
use crate::fit::FunctionType;
use crate::geometry::Point;

/// How an inner control point (`C₁`, or `C_{m−1}` for an end join) is
/// obtained from the decision vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum C1Var {
    /// `C_k = (x[i], x[i+1])`.
    Free(usize),
    /// `C₁ = C₀ + D/(m w₁)` (C¹ join).
    Derived(Point),
    /// `C₁ = C₀ + x[i]·L` (G¹ join).
    Ratio(usize, Point),
    /// `C_{m−1} = C_m − D/(m w_{m−1})` (C¹ join at the end).
    EndDerived(Point),
    /// `C_{m−1} = C_m − x[i]·dir` (G¹ join at the end).
    EndRatio(usize, Point),
    /// A fixed point: the inner control point of a quadratic joined G¹ at
    /// both ends, where the two tangent lines meet.
    Fixed(Point),
}

/// Where each quantity sits in the decision vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Layout {
    pub(super) c1: C1Var,
    pub(super) c2: Option<C1Var>,
    pub(super) w1: Option<usize>,
    pub(super) w2: Option<usize>,
    pub(super) dim: usize,
}

impl Layout {
    /// The layout; a quadratic with an end join must start [`Start::Free`],
    /// and its `C₁` then comes from the end, or [`Start::G1`] with a G¹ end,
    /// and its `C₁` is then `meet`, where the two tangent lines cross
    /// (checked by the caller).
    pub(super) fn new(
        function: FunctionType,
        start: Start,
        end: End,
        meet: Option<Point>,
    ) -> Layout {
        let mut dim = 0;
        let mut take = |k: usize| {
            let i = dim;
            dim += k;
            i
        };
        let end_var = |take: &mut dyn FnMut(usize) -> usize| match end {
            End::Free => C1Var::Free(take(2)),
            End::C1 { derivative } => C1Var::EndDerived(derivative),
            End::G1 { dir } => C1Var::EndRatio(take(1), dir),
        };
        let c1 = match (start, meet) {
            (_, Some(p)) => C1Var::Fixed(p),
            (start, None) => match start {
                Start::Free if function.degree() == 2 => end_var(&mut take),
                Start::Free => C1Var::Free(take(2)),
                Start::C1 { derivative } => C1Var::Derived(derivative),
                Start::G1 { leg } => C1Var::Ratio(take(1), leg),
            },
        };
        let c2 = (function.degree() == 3).then(|| end_var(&mut take));
        let w1 = function.is_rational().then(|| take(1));
        let w2 = (function == FunctionType::RationalCubic).then(|| take(1));
        Layout {
            c1,
            c2,
            w1,
            w2,
            dim,
        }
    }
}
