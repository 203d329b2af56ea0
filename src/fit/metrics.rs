//! What a fit achieved: error, distances and cost.
//!
//! Deterministic outputs only; wall time is for the caller to measure.

use crate::geometry::{nearest, Curve, Point};

/// The quality and cost of one fitted segment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentMetrics {
    /// Data points of the segment, both ends included.
    pub points: usize,
    /// `E = Σᵢ |Rᵢ − P(sᵢ)|²` at the segment's parameters.
    pub sse: f64,
    /// `√(E/N)` with `N` the segment's points.
    pub rms: f64,
    /// The largest orthogonal (closest-point) distance of a data point to the
    /// curve ([`crate::geometry::nearest`]).
    pub max_distance: f64,
    /// The local index (0-based within the segment) of that point.
    pub max_index: usize,
    /// Objective evaluations spent on the segment.
    pub evaluations: u64,
}

/// The metrics of `curve` fitted to `points` at `params`.
pub fn segment_metrics<C: Curve + ?Sized>(
    curve: &C,
    points: &[Point],
    params: &[f64],
    evaluations: u64,
) -> SegmentMetrics {
    let sse = curve.sse(points, params);
    let (max_index, max_distance) = points
        .iter()
        .map(|&p| nearest(curve, p).1)
        .enumerate()
        .fold(
            (0, 0.0),
            |best, (i, d)| if d > best.1 { (i, d) } else { best },
        );
    SegmentMetrics {
        points: points.len(),
        sse,
        rms: if points.is_empty() {
            0.0
        } else {
            (sse / points.len() as f64).sqrt()
        },
        max_distance,
        max_index,
        evaluations,
    }
}

/// The quality and cost of a whole piecewise fit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitMetrics {
    /// Distinct data points of the outline, `N`.
    pub points: usize,
    /// Number of segments.
    pub segments: usize,
    /// `E`, the sum of the segments' errors (break points, shared by two
    /// segments, are interpolated and add nothing).
    pub sse: f64,
    /// `√(E/N)`.
    pub rms: f64,
    /// The largest orthogonal distance over all segments.
    pub max_distance: f64,
    /// Objective evaluations over all segments.
    pub evaluations: u64,
}

impl FitMetrics {
    /// Totals of the per-segment metrics for an outline of `points` points.
    pub fn total(segments: &[SegmentMetrics], points: usize) -> FitMetrics {
        let sse: f64 = segments.iter().map(|s| s.sse).sum();
        FitMetrics {
            points,
            segments: segments.len(),
            sse,
            rms: if points == 0 {
                0.0
            } else {
                (sse / points as f64).sqrt()
            },
            max_distance: segments.iter().map(|s| s.max_distance).fold(0.0, f64::max),
            evaluations: segments.iter().map(|s| s.evaluations).sum(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::QuadBez;

    #[test]
    fn hand_computed() {
        // The straight quadratic (0,0)-(1,0)-(2,0) at s = 0, ½, 1 is (0,0), (1,0), (2,0).
        let q = QuadBez::new(Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 0.0));
        let pts = [Point::ZERO, Point::new(1.2, 0.5), Point::new(2.0, 0.0)];
        let m = segment_metrics(&q, &pts, &[0.0, 0.5, 1.0], 7);
        assert!((m.sse - (0.04 + 0.25)).abs() < 1e-15);
        assert!((m.rms - (0.29f64 / 3.0).sqrt()).abs() < 1e-15);
        assert!((m.max_distance - 0.5).abs() < 1e-12);
        assert_eq!(m.max_index, 1);
        let t = FitMetrics::total(&[m, m], 5);
        assert_eq!(t.segments, 2);
        assert_eq!(t.evaluations, 14);
        assert!((t.rms - (0.58f64 / 5.0).sqrt()).abs() < 1e-15);
    }
}
