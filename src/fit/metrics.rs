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
    /// `Σᵢ dᵢ²`, the orthogonal distances `dᵢ` of the data points squared
    /// and summed (compare `sse`, measured at the parameters `sᵢ`).
    pub sum_sq_distance: f64,
    /// `√(Σᵢ dᵢ²/N)`: the RMS of the orthogonal distances (what tools such
    /// as potrace, FontForge and Inkscape are judged by); `rms` is measured
    /// at the parameters `sᵢ` and is never smaller.
    pub rms_distance: f64,
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
    let mut max_index = 0;
    let mut max_distance = 0.0;
    let mut sum_sq_distance = 0.0;
    for (i, &p) in points.iter().enumerate() {
        let d = nearest(curve, p).1;
        sum_sq_distance += d * d;
        if d > max_distance {
            (max_index, max_distance) = (i, d);
        }
    }
    SegmentMetrics {
        points: points.len(),
        sse,
        rms: per_point(sse, points.len()),
        max_distance,
        max_index,
        sum_sq_distance,
        rms_distance: per_point(sum_sq_distance, points.len()),
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
    /// `√(Σ d²/N)`: the RMS of the orthogonal distances of the data points
    /// (break points count once: their distance is 0 in both segments).
    pub rms_distance: f64,
    /// `Σ d²` over the data points.
    pub sum_sq_distance: f64,
    /// Objective evaluations over all segments.
    pub evaluations: u64,
}

impl FitMetrics {
    /// Totals of the per-segment metrics for an outline of `points` points.
    pub fn total(segments: &[SegmentMetrics], points: usize) -> FitMetrics {
        let sse: f64 = segments.iter().map(|s| s.sse).sum();
        let sum_sq: f64 = segments.iter().map(|s| s.sum_sq_distance).sum();
        FitMetrics {
            points,
            segments: segments.len(),
            sse,
            rms: per_point(sse, points),
            max_distance: segments.iter().map(|s| s.max_distance).fold(0.0, f64::max),
            rms_distance: per_point(sum_sq, points),
            sum_sq_distance: sum_sq,
            evaluations: segments.iter().map(|s| s.evaluations).sum(),
        }
    }

    /// The totals of several fits (the contours of one shape): sums of
    /// points, segments, `E`, `Σ d²` and evaluations; the largest distance.
    pub fn combine(parts: &[FitMetrics]) -> FitMetrics {
        let points: usize = parts.iter().map(|m| m.points).sum();
        let sse: f64 = parts.iter().map(|m| m.sse).sum();
        let sum_sq: f64 = parts.iter().map(|m| m.sum_sq_distance).sum();
        FitMetrics {
            points,
            segments: parts.iter().map(|m| m.segments).sum(),
            sse,
            rms: per_point(sse, points),
            max_distance: parts.iter().map(|m| m.max_distance).fold(0.0, f64::max),
            rms_distance: per_point(sum_sq, points),
            sum_sq_distance: sum_sq,
            evaluations: parts.iter().map(|m| m.evaluations).sum(),
        }
    }
}

/// `√(total/n)`, 0 for no points.
fn per_point(total: f64, n: usize) -> f64 {
    if n == 0 {
        0.0
    } else {
        (total / n as f64).sqrt()
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
