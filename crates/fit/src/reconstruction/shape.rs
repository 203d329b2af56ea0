//! A fitted shape: every contour's piecewise fit with the totals.

use crate::fit::{outline_trace, FitError, FitMetrics, FittedSegment, PiecewiseFit};
use crate::geometry::Orientation;
use crate::optim::TracePoint;

/// One fitted contour of a shape.
#[derive(Clone, Debug, PartialEq)]
pub struct ContourFit {
    /// Its number in the input's list of contours (by decreasing area).
    pub contour: usize,
    /// Counter-clockwise (outer boundary) or clockwise (hole).
    pub orientation: Orientation,
    /// The fit.
    pub fit: PiecewiseFit,
    /// The segment count asked for, where it was below the contour's span
    /// count (one segment per span between corners) and so raised to it
    /// ([`crate::reconstruction::Segmentation::Count`]); `None` otherwise.
    pub raised_from: Option<usize>,
}

/// A fit of every contour that could be fitted, and why the others could
/// not ([`crate::reconstruction::Reconstruction::fit_each`]).
#[derive(Clone, Debug, PartialEq)]
pub struct PartialShapeFit {
    /// The contours fitted.
    pub fit: ShapeFit,
    /// The contours not fitted: their numbers and errors, in order.
    pub failed: Vec<(usize, FitError)>,
}

/// A fitted shape: its contours in order, with the totals.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeFit {
    /// The contours.
    pub contours: Vec<ContourFit>,
    /// Totals over the contours ([`FitMetrics::combine`]).
    pub metrics: FitMetrics,
}

impl ShapeFit {
    /// The shape of `contours`, with its totals.
    pub fn new(contours: Vec<ContourFit>) -> ShapeFit {
        let parts: Vec<FitMetrics> = contours.iter().map(|c| c.fit.metrics).collect();
        ShapeFit {
            metrics: FitMetrics::combine(&parts),
            contours,
        }
    }

    /// Every segment with its contour's number, contour after contour.
    pub fn segments(&self) -> impl Iterator<Item = (usize, &FittedSegment)> + '_ {
        self.contours
            .iter()
            .flat_map(|c| c.fit.segments.iter().map(move |s| (c.contour, s)))
    }

    /// The best-so-far `E` of the whole shape against evaluations, every
    /// segment of every contour at equal evaluations ([`outline_trace`]).
    pub fn trace(&self) -> Vec<TracePoint> {
        outline_trace(self.segments().map(|(_, s)| s))
    }

    /// Whether every interior joint of every contour holds its continuity
    /// to relative tolerance `tol`.
    pub fn joins_hold(&self, tol: f64) -> bool {
        self.contours.iter().all(|c| c.fit.joins_hold(tol))
    }

    /// The largest closing-joint angle over the contours, in degrees (NaN
    /// when a derivative vanishes; `None` without closed contours).
    pub fn closing_angle_degrees(&self) -> Option<f64> {
        self.contours
            .iter()
            .filter_map(|c| c.fit.closing.map(|j| j.angle_degrees))
            .reduce(|a, b| if a.is_nan() || b > a { b } else { a })
    }
}
