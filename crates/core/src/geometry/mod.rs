//! Bézier geometry: points, polylines, the Bernstein basis, polynomial and
//! rational Bézier segments, joins between segments, closest points,
//! parameterisations and offset curves.
//!
//! One concept per module, in the style of the `kurbo` crate; everything is
//! re-exported here. Curves run on `t ∈ [0, 1]`; the formulas follow Farin,
//! *Curves and Surfaces for CAGD* (5th ed., 2002) and Piegl & Tiller,
//! *The NURBS Book* (2nd ed., 1997).
//!
//! ```
//! use metabezier_core::geometry::{c1_start, Curve, Point, RationalCubicBez, RightStart};
//!
//! let left = RationalCubicBez::new(
//!     Point::new(0.0, 0.0), Point::new(1.0, 2.0),
//!     Point::new(3.0, 2.0), Point::new(4.0, 0.0), 0.5, 2.0,
//! )?;
//! // Start the next segment so that Q₁'(1) = Q₂'(0).
//! let (c0, c1) = c1_start(&left, RightStart::rational_cubic(1.5)?);
//! let right = RationalCubicBez::new(c0, c1, Point::new(7.0, -1.0), Point::new(8.0, 0.0), 1.5, 1.0)?;
//! assert!((left.deriv(1.0) - right.deriv(0.0)).hypot() < 1e-12);
//! // The objective E = Σ|Rᵢ − Q(sᵢ)|² for data Rᵢ at parameters sᵢ.
//! let e = left.sse(&[Point::new(0.0, 0.0), Point::new(4.0, 0.0)], &[0.0, 1.0]);
//! assert!(e < 1e-24);
//! # Ok::<(), metabezier_core::geometry::GeometryError>(())
//! ```

mod bernstein;
mod bezier;
mod casteljau;
mod cubicbez;
mod curve;
mod error;
mod join;
mod nearest;
mod offset;
mod param;
mod point;
mod polyline;
mod quadbez;
mod rational;
mod rcubicbez;
mod rquadbez;

pub use bernstein::{bernstein, bernstein_all, binomial};
pub use bezier::Bezier;
pub use cubicbez::CubicBez;
pub use curve::Curve;
pub use error::GeometryError;
pub use join::{
    c0_start, c1_start, check_join, g1_start, join_start, Continuity, RightStart, SegmentEnd,
};
pub use nearest::{nearest, nearest_with, DEFAULT_SAMPLES};
pub use offset::{offset_into, offset_linear, offset_point, offset_points, LinearDistance};
pub use param::{reparameterise, reparameterise_into, Parameterisation};
pub use point::Point;
pub use polyline::{bounding_box, segment_foot, Nearest, Orientation, Polyline};
pub use quadbez::QuadBez;
pub use rational::RationalBezier;
pub use rcubicbez::RationalCubicBez;
pub use rquadbez::RationalQuadBez;
