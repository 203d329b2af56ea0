//! Piecewise Bézier fitting of outline points: the thesis's curve
//! reconstruction problem.
//!
//! Data points `R₀..R_N` along an outline are split at break points into
//! segments; each segment is fitted with a quadratic, cubic, rational
//! quadratic or rational cubic Bézier function whose end control points are
//! the segment's first and last data points, minimising
//! `E = Σᵢ |Rᵢ − P(sᵢ)|²` at parameters `sᵢ` (chord length by default), or
//! with [`ErrorMeasure::Orthogonal`] (beyond the thesis) the orthogonal
//! `Σᵢ min_s |Rᵢ − P(s)|²`, the `sᵢ` solved with the curve.
//! Segments are fitted in sequence; each joins the previous one with C⁰, C¹
//! or G¹ continuity (Farin 2002, §10.2 and §13.6), and a closed outline's
//! chain closes smoothly ([`Closing`]). With [`Chain::Joint`] (beyond the
//! thesis) the sequential chain is then solved again as one problem, every
//! join a shared variable (a G¹ joint's unit tangent and its two legs, a C¹
//! joint's derivative), so that no segment inherits its predecessor's
//! error; Levenberg–Marquardt solves it through the banded normal equations
//! ([`crate::linalg::BandedArrow`]) in time linear in the segments.
//!
//! The split follows argmin's: a [`SegmentProblem`] is an ordinary
//! box-bounded [`crate::problem::Problem`] (and a
//! [`crate::optim::lm::LeastSquares`] problem) that knows nothing of the
//! algorithm solving it, and a [`SegmentSolver`] — any of the
//! metaheuristics ([`OptimiserSolver`]), Levenberg–Marquardt ([`LmSolver`])
//! or both ([`HybridSolver`]) — knows nothing of curves.
//!
//! | module | concept |
//! |---|---|
//! | [`FunctionType`], [`Segment`] | the four curve families and a fitted segment |
//! | [`SegmentProblem`], [`Start`] | one segment's decision variables, box and objective |
//! | [`ErrorMeasure`] | what E measures: at fixed parameters, or orthogonally (foot points) |
//! | [`Chain`] | segments solved in sequence, or jointly with shared joins |
//! | [`search_space`] | the thesis's search-space technique (reconstructed) |
//! | [`linear_fit`] | fixed-weight linear least squares |
//! | [`SegmentSolver`] | metaheuristic, LM and hybrid solvers |
//! | [`fit_piecewise`], [`fit_segment_count`], [`fit_adaptive`] | whole outlines, closed smoothly or C⁰ ([`Closing`]) |
//! | [`fit_between`], [`ChainEnds`] | an open chain joined to known curves beyond its ends |
//! | [`fit_independent`] | every segment of a reference fit as its own problem |
//! | [`densify`] | points inserted into a span too short for its function |
//! | [`SegmentMetrics`], [`FitMetrics`] | E, RMS, data → curve and curve → data distances (Hausdorff), evaluations |
//! | [`outline_trace`] | the best-so-far E of a whole fit |
//!
//! ```
//! use std::f64::consts::FRAC_PI_2;
//! use metabezier_fit::fit::{fit_piecewise, FitOptions, FunctionType, LmSolver};
//! use metabezier_core::geometry::{Continuity, Curve, Parameterisation, Point, RationalQuadBez};
//!
//! // A unit circle: four quarter arcs, each sampled at 50 uniform parameters.
//! let mut pts = Vec::new();
//! for k in 0..4 {
//!     let arc = RationalQuadBez::circular_arc(Point::ZERO, 1.0, k as f64 * FRAC_PI_2, FRAC_PI_2)?;
//!     pts.extend((0..50).map(|j| arc.eval(j as f64 / 50.0)));
//! }
//! // Four rational quadratics joined G¹ recover the circle exactly.
//! let mut options = FitOptions::new(FunctionType::RationalQuadratic, Continuity::G1);
//! options.parameterisation = Parameterisation::Uniform;
//! let fit = fit_piecewise(&pts, true, &[0, 50, 100, 150], &options, &mut LmSolver::default())
//!     .expect("valid input");
//! assert_eq!(fit.metrics.segments, 4);
//! assert!(fit.joins_hold(1e-9));
//! assert!(fit.metrics.max_distance < 1e-9);
//! # Ok::<(), metabezier_core::geometry::GeometryError>(())
//! ```

mod adaptive;
mod chain;
mod controls;
mod error;
mod function;
mod linear;
mod metrics;
mod options;
mod piecewise;
mod problem;
pub mod search_space;
mod segment;
mod solver;
mod span;
mod trace;

pub use adaptive::{fit_adaptive, SplitOptions, COARSE_RECHECK};
pub use error::FitError;
pub use function::FunctionType;
pub use linear::linear_fit;
pub use metrics::{
    outline_distance, segment_metrics, FitMetrics, OutlineDistance, SegmentMetrics, OUTLINE_SAMPLES,
};
pub use options::{
    Chain, Closing, ErrorMeasure, FitOptions, GuessRule, RealOption, SearchSpace,
    SearchSpaceOptions, ALPHA_SIZE, MARGIN, PT,
};
pub use piecewise::{
    equal_arc_breaks, fit_between, fit_breaks, fit_independent, fit_piecewise, fit_segment_count,
    ChainEnds, ClosingJoint, PiecewiseFit,
};
pub use problem::{tangent_meet, End, SegmentProblem, Start};
pub use segment::Segment;
pub use solver::{
    HybridSolver, LmSolver, LmStart, OptimiserSolver, SegmentSolver, Solution, SolvePart,
    COARSE_REDUCTION,
};
pub use span::{densify, FittedSegment};
pub use trace::outline_trace;
