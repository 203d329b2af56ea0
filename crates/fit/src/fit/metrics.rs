//! What a fit achieved: error, distances and cost.
//!
//! Deterministic outputs only; wall time is for the caller to measure.

use crate::geometry::{nearest, segment_foot, Curve, Point};

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
    /// Curve → data: the largest distance from a sample of the curve
    /// ([`OUTLINE_SAMPLES`] per data gap) to the polyline of its data
    /// points ([`outline_distance`]). Large where the curve leaves the
    /// outline between data points (a whisker past a corner, a loop), which
    /// `max_distance` cannot see.
    pub curve_distance: f64,
    /// The two-sided (Hausdorff) distance between the curve and the polyline
    /// of its data: the larger of data → curve (the data points and the
    /// polyline's samples) and curve → data ([`OutlineDistance::distance`]).
    pub hausdorff: f64,
    /// The Hausdorff distance beyond the polyline's own sagitta, the pixel
    /// staircase's allowance ([`OutlineDistance::excess`]): what a
    /// tolerance is held to.
    pub excess: f64,
    /// The local gap (between local points `i` and `i + 1`) of `excess`.
    pub excess_gap: usize,
    /// The local gap of `hausdorff`.
    pub hausdorff_gap: usize,
    /// Objective evaluations spent on the segment.
    pub evaluations: u64,
}

/// The metrics of `curve` fitted to `points` (in order, the first and last
/// at the curve's ends) at `params`, data → curve and curve → data.
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
    let mut feet = Vec::with_capacity(points.len());
    for (i, &p) in points.iter().enumerate() {
        let (s, d) = nearest(curve, p);
        feet.push(s);
        sum_sq_distance += d * d;
        if d > max_distance {
            (max_index, max_distance) = (i, d);
        }
    }
    let o = outline_distance_from(curve, points, &mut feet);
    SegmentMetrics {
        points: points.len(),
        sse,
        rms: per_point(sse, points.len()),
        max_distance,
        max_index,
        sum_sq_distance,
        rms_distance: per_point(sum_sq_distance, points.len()),
        curve_distance: o.curve_side,
        hausdorff: o.distance.max(max_distance),
        excess: o.excess.max(max_distance),
        excess_gap: if o.excess >= max_distance {
            o.gap
        } else {
            max_index.min(points.len().saturating_sub(2))
        },
        hausdorff_gap: if o.distance >= max_distance {
            o.distance_gap
        } else {
            max_index.min(points.len().saturating_sub(2))
        },
        evaluations,
    }
}

/// Samples per data gap of [`outline_distance`], on each side.
pub const OUTLINE_SAMPLES: usize = 8;

/// Edges on each side of a curve sample's gap that [`outline_distance`]
/// searches first.
const WINDOW: usize = 16;

/// How far a curve and the outline polyline of its data points are apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutlineDistance {
    /// The sampled two-sided distance (an upper bound of each sample's
    /// true distance, so never below what the samples show).
    pub distance: f64,
    /// The same beyond the polyline's own sagitta: each sample's distance
    /// less `σᵢ = max(|Δ²Rᵢ|, |Δ²Rᵢ₊₁|)/8` of its gap, with
    /// `Δ²Rⱼ = Rⱼ₋₁ − 2Rⱼ + Rⱼ₊₁` (0 at the ends), the distance by which a
    /// chord of a smooth curve through those points misses the curve
    /// (`h²κ/8` for points `h` apart on a curvature `κ`). No smooth curve
    /// through the points can be nearer the polyline than that, so a
    /// tolerance below the sagitta is met here rather than refused.
    pub excess: f64,
    /// The gap `i` (between points `i` and `i + 1`) of the largest excess.
    pub gap: usize,
    /// The curve's side alone: the largest distance from a curve sample to
    /// the polyline (curve → data).
    pub curve_side: f64,
    /// The gap of the largest `distance`.
    pub distance_gap: usize,
}

/// The two-sided distance between `curve` and the polyline through `points`
/// (in order, the first and last at the curve's ends): the Hausdorff
/// distance of the two, checked on the polyline at [`OUTLINE_SAMPLES`]
/// points of every edge (each projected on the curve by Newton's method,
/// Piegl & Tiller, *The NURBS Book*, §6.1, from its end points' foot
/// parameters and from between them, the closest kept) and on the curve at
/// as many points per edge, equally spaced in its parameter, each against
/// every edge. Every sample's distance is to a point actually on the other
/// side, so the result never understates what it samples; between samples
/// it can miss at most the bulge of one sample spacing. The data points'
/// own distances are included (with no sagitta: they lie on the outline).
pub fn outline_distance<C: Curve + ?Sized>(curve: &C, points: &[Point]) -> OutlineDistance {
    let mut feet: Vec<f64> = points.iter().map(|&p| nearest(curve, p).0).collect();
    outline_distance_from(curve, points, &mut feet)
}

/// [`outline_distance`] with the data points' foot parameters `feet`
/// already found ([`nearest`]); the ends are set to the curve's ends.
fn outline_distance_from<C: Curve + ?Sized>(
    curve: &C,
    points: &[Point],
    feet: &mut [f64],
) -> OutlineDistance {
    let mut worst = OutlineDistance {
        distance: 0.0,
        excess: 0.0,
        gap: 0,
        curve_side: 0.0,
        distance_gap: 0,
    };
    if points.len() < 2 {
        return worst;
    }
    let edges = points.len() - 1;
    let bend = |j: usize| {
        if j == 0 || j == edges {
            0.0
        } else {
            (points[j - 1] - points[j] * 2.0 + points[j + 1]).hypot() / 8.0
        }
    };
    let sagitta: Vec<f64> = (0..edges).map(|i| bend(i).max(bend(i + 1))).collect();

    // The ends are the curve's ends (a closed one-segment contour starts and
    // ends at the same point, whose nearest parameter is ambiguous).
    feet[0] = 0.0;
    feet[edges] = 1.0;
    let k = OUTLINE_SAMPLES as f64;
    for i in 0..edges {
        note(&mut worst, curve.eval(feet[i]).distance(points[i]), i, 0.0);
        for j in 1..OUTLINE_SAMPLES {
            let f = j as f64 / k;
            let q = points[i].lerp(points[i + 1], f);
            let from = |s0: f64| curve.eval(local_foot(curve, q, s0)).distance(q);
            let mut d = from(feet[i] + (feet[i + 1] - feet[i]) * f);
            // The other starts only where this one could raise the result.
            if d > worst.distance || d - sagitta[i] > worst.excess {
                d = d.min(from(feet[i])).min(from(feet[i + 1]));
            }
            note(&mut worst, d, i, sagitta[i]);
        }
    }
    note(
        &mut worst,
        curve.eval(1.0).distance(points[edges]),
        edges - 1,
        0.0,
    );
    let samples = OUTLINE_SAMPLES * edges;
    // Each curve sample against the edges near its gap (found from the foot
    // parameters), and against every edge only where that nearby distance
    // could raise the result: the true distance is at most the nearby one.
    let nearest_edge = |c: Point, range: std::ops::Range<usize>| {
        let (d2, e) = range
            // Squared, so that the search over edges takes no root per edge.
            .map(|e| {
                (
                    (segment_foot(c, points[e], points[e + 1]).1 - c).hypot2(),
                    e,
                )
            })
            .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
        (d2.sqrt(), e)
    };
    let mut at = 0;
    for j in 1..samples {
        let t = j as f64 / samples as f64;
        while at + 1 < edges && feet[at + 1] < t {
            at += 1;
        }
        let c = curve.eval(t);
        let window = at.saturating_sub(WINDOW)..(at + WINDOW + 1).min(edges);
        let (mut best, mut gap) = nearest_edge(c, window);
        if best > worst.distance || best - sagitta[gap] > worst.excess {
            (best, gap) = nearest_edge(c, 0..edges);
        }
        worst.curve_side = worst.curve_side.max(best);
        note(&mut worst, best, gap, sagitta[gap]);
    }
    worst
}

/// Takes a sample's distance `d` in gap `gap`, with the sagitta `allowed`
/// there, into `worst`.
fn note(worst: &mut OutlineDistance, d: f64, gap: usize, allowed: f64) {
    if d > worst.distance {
        worst.distance = d;
        worst.distance_gap = gap;
    }
    if d - allowed > worst.excess {
        worst.excess = d - allowed;
        worst.gap = gap;
    }
}

/// A local foot parameter of `q` on `curve` near `s0`: Newton's method on
/// `g = (C(s) − q)·C′(s)`, clamped to `[0, 1]`, a step kept only if it
/// brings the curve closer; at most 8 steps.
fn local_foot<C: Curve + ?Sized>(curve: &C, q: Point, s0: f64) -> f64 {
    let mut s = s0.clamp(0.0, 1.0);
    let mut d = curve.eval(s).distance_squared(q);
    for _ in 0..8 {
        let (p, d1, d2) = (curve.eval(s), curve.deriv(s), curve.deriv2(s));
        let e = p - q;
        let gp = d1.hypot2() + e.dot(d2);
        let gp = if gp > 0.0 { gp } else { d1.hypot2() };
        if !(gp > 0.0 && gp.is_finite()) {
            break;
        }
        let next = (s - e.dot(d1) / gp).clamp(0.0, 1.0);
        let dn = curve.eval(next).distance_squared(q);
        if dn.is_nan() || dn >= d {
            break;
        }
        (s, d) = (next, dn);
    }
    s
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
    /// Curve → data: the largest [`SegmentMetrics::curve_distance`].
    pub curve_distance: f64,
    /// The two-sided distance: the largest [`SegmentMetrics::hausdorff`]
    /// (never below `max_distance`).
    pub hausdorff: f64,
    /// The same beyond the staircase's allowance: the largest
    /// [`SegmentMetrics::excess`], what a tolerance is held to.
    pub excess: f64,
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
            curve_distance: largest(segments.iter().map(|s| s.curve_distance)),
            hausdorff: largest(segments.iter().map(|s| s.hausdorff)),
            excess: largest(segments.iter().map(|s| s.excess)),
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
            curve_distance: largest(parts.iter().map(|m| m.curve_distance)),
            hausdorff: largest(parts.iter().map(|m| m.hausdorff)),
            excess: largest(parts.iter().map(|m| m.excess)),
            evaluations: parts.iter().map(|m| m.evaluations).sum(),
        }
    }
}

/// The largest of `values`, 0 for none.
fn largest(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, f64::max)
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
