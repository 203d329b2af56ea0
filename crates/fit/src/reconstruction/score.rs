//! Scoring curves made elsewhere against the data points `fit` would use:
//! the orthogonal distance of every data point to the nearest of the
//! curves, as the maximum and the RMS, per contour and overall.
//!
//! The distances are always finite: [`score`] refuses an empty set of
//! curves and any curve control point or data point beyond
//! ±[`MAX_SCORE_COORDINATE`].

use super::Source;
use crate::geometry::{nearest, segment_foot, Point};
use crate::outline::Segment;

/// The largest coordinate magnitude [`score`] accepts, for curves (in the
/// outline frame, after any offset) and data points alike: distances of
/// points this far apart, their squares and the sum of squares over any
/// number of points stay finite. The readers keep their own coordinates
/// within ±[`crate::outline::MAX_COORDINATE`] (1e15), and reflecting an
/// SVG about its `viewBox` and adding an offset can at most quadruple that.
pub const MAX_SCORE_COORDINATE: f64 = 1e16;

/// Why curves could not be scored.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ScoreError {
    /// No curve segment at all: every data point would be infinitely far.
    #[error("no curve segment to score against; expected at least one line or curve")]
    NoSegment,
    /// A curve control point is not finite or beyond ±[`MAX_SCORE_COORDINATE`].
    #[error("segment {segment} of subpath {subpath} has the control point ({x:e}, {y:e}) (after the offset), beyond ±1e16, the range of coordinates scored; check the offset and the file's coordinates")]
    CurveRange {
        /// The subpath (0-based, in file order).
        subpath: usize,
        /// The segment within it (0-based).
        segment: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
    /// A data point is not finite or beyond ±[`MAX_SCORE_COORDINATE`].
    #[error("data point {point} of contour {contour} is ({x:e}, {y:e}), beyond ±1e16, the range of coordinates scored")]
    DataRange {
        /// The contour's number in its input.
        contour: usize,
        /// The point's index in the contour.
        point: usize,
        /// Its x.
        x: f64,
        /// Its y.
        y: f64,
    },
}

/// Whether both coordinates are within ±[`MAX_SCORE_COORDINATE`] (false for NaN).
fn in_range(p: Point) -> bool {
    p.x.abs() <= MAX_SCORE_COORDINATE && p.y.abs() <= MAX_SCORE_COORDINATE
}

/// The distances of one contour's data points (or of all of them).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Distances {
    /// Data points.
    pub points: usize,
    /// The largest orthogonal distance of a data point to the curves.
    pub max_distance: f64,
    /// `√(Σ d²/N)` over the data points.
    pub rms_distance: f64,
}

/// The score of a set of curves against a source.
#[derive(Clone, Debug, PartialEq)]
pub struct Score {
    /// The number of curve segments scored.
    pub segments: usize,
    /// Curve → data: the largest distance from a sample of the curves to
    /// the nearest outline polyline of the source (its contours' points in
    /// order, closed ones closed), the curves sampled at least
    /// [`crate::fit::OUTLINE_SAMPLES`] times per mean data gap along their
    /// control polygons' length, as `metabezier fit` samples its own.
    pub curve_distance: f64,
    /// The two-sided distance: the larger of `total.max_distance` (data →
    /// curve) and `curve_distance`, the measure `metabezier fit` reports as
    /// its Hausdorff distance.
    pub hausdorff: f64,
    /// Per contour of the source: its number and its distances.
    pub contours: Vec<(usize, Distances)>,
    /// Over all the source's data points.
    pub total: Distances,
}

/// The orthogonal distance from `p` to a segment.
pub fn segment_distance(s: &Segment, p: Point) -> f64 {
    match s {
        Segment::Line(a, b) => segment_foot(p, *a, *b).1.distance(p),
        Segment::Quad(q) => nearest(q, p).1,
        Segment::Cubic(c) => nearest(c, p).1,
    }
}

/// A segment with the bounding box of its control points, whose distance
/// from a point bounds the segment's from below.
struct Boxed<'s> {
    segment: &'s Segment,
    lo: Point,
    hi: Point,
}

impl Boxed<'_> {
    fn lower_bound(&self, p: Point) -> f64 {
        let dx = (self.lo.x - p.x).max(0.0).max(p.x - self.hi.x);
        let dy = (self.lo.y - p.y).max(0.0).max(p.y - self.hi.y);
        dx.hypot(dy)
    }
}

/// The control points of a segment.
fn control_points(s: &Segment) -> Vec<Point> {
    match *s {
        Segment::Line(a, b) => vec![a, b],
        Segment::Quad(q) => vec![q.p0, q.p1, q.p2],
        Segment::Cubic(c) => vec![c.p0, c.p1, c.p2, c.p3],
    }
}

fn boxed(s: &Segment) -> Boxed<'_> {
    let pts = control_points(s);
    let lo = pts.iter().fold(Point::new(f64::MAX, f64::MAX), |m, q| {
        Point::new(m.x.min(q.x), m.y.min(q.y))
    });
    let hi = pts.iter().fold(Point::new(f64::MIN, f64::MIN), |m, q| {
        Point::new(m.x.max(q.x), m.y.max(q.y))
    });
    Boxed { segment: s, lo, hi }
}

/// The distance from `p` to the nearest of `curves` (visited by increasing
/// lower bound, stopping when no box can be nearer); `+∞` without curves.
fn nearest_curve(curves: &[Boxed<'_>], p: Point, order: &mut Vec<(f64, usize)>) -> f64 {
    order.clear();
    order.extend(
        curves
            .iter()
            .enumerate()
            .map(|(i, b)| (b.lower_bound(p), i)),
    );
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best = f64::INFINITY;
    for &(lb, i) in order.iter() {
        if lb >= best {
            break;
        }
        best = best.min(segment_distance(curves[i].segment, p));
    }
    best
}

/// The distances of `points` to the nearest of `curves`.
fn distances(curves: &[Boxed<'_>], points: &[Point]) -> (Distances, f64) {
    let mut order = Vec::with_capacity(curves.len());
    let (mut max, mut sum_sq) = (0.0f64, 0.0);
    for &p in points {
        let d = nearest_curve(curves, p, &mut order);
        max = max.max(d);
        sum_sq += d * d;
    }
    let n = points.len();
    let rms = if n == 0 {
        0.0
    } else {
        (sum_sq / n as f64).sqrt()
    };
    (
        Distances {
            points: n,
            max_distance: max,
            rms_distance: rms,
        },
        sum_sq,
    )
}

/// Scores `curves` (subpaths of segments, in the outline frame) against the
/// data points of every contour of `source`: each point's distance is to
/// the nearest segment of any subpath. Fails when there is no segment or a
/// coordinate is beyond ±[`MAX_SCORE_COORDINATE`] (see [`ScoreError`]).
pub fn score(source: &Source, curves: &[Vec<Segment>]) -> Result<Score, ScoreError> {
    for (subpath, sub) in curves.iter().enumerate() {
        for (segment, s) in sub.iter().enumerate() {
            if let Some(p) = control_points(s).into_iter().find(|p| !in_range(*p)) {
                return Err(ScoreError::CurveRange {
                    subpath,
                    segment,
                    x: p.x,
                    y: p.y,
                });
            }
        }
    }
    for c in &source.contours {
        if let Some((point, p)) = c
            .outline
            .points
            .iter()
            .enumerate()
            .find(|(_, p)| !in_range(**p))
        {
            return Err(ScoreError::DataRange {
                contour: c.index,
                point,
                x: p.x,
                y: p.y,
            });
        }
    }
    let boxes: Vec<Boxed<'_>> = curves.iter().flatten().map(boxed).collect();
    if boxes.is_empty() {
        return Err(ScoreError::NoSegment);
    }
    let mut contours = Vec::new();
    let (mut points, mut max, mut sum_sq) = (0usize, 0.0f64, 0.0);
    for c in &source.contours {
        let (d, sq) = distances(&boxes, &c.outline.points);
        points += d.points;
        max = max.max(d.max_distance);
        sum_sq += sq;
        contours.push((c.index, d));
    }
    let rms = if points == 0 {
        0.0
    } else {
        (sum_sq / points as f64).sqrt()
    };
    let curve_distance = curve_to_outline(curves, source);
    Ok(Score {
        segments: boxes.len(),
        curve_distance,
        hausdorff: curve_distance.max(max),
        contours,
        total: Distances {
            points,
            max_distance: max,
            rms_distance: rms,
        },
    })
}

/// The largest distance from samples of `curves` to the nearest edge of
/// any outline polyline of `source` (see [`Score::curve_distance`]).
fn curve_to_outline(curves: &[Vec<Segment>], source: &Source) -> f64 {
    let mut edges: Vec<(Point, Point)> = Vec::new();
    let mut length = 0.0;
    for c in &source.contours {
        let pts = &c.outline.points;
        let closing = c.outline.closed.then(|| (pts[pts.len() - 1], pts[0]));
        for (a, b) in pts.windows(2).map(|w| (w[0], w[1])).chain(closing) {
            length += a.distance(b);
            edges.push((a, b));
        }
    }
    if edges.is_empty() {
        return 0.0;
    }
    let gap = (length / edges.len() as f64).max(f64::MIN_POSITIVE);
    let mut worst = 0.0f64;
    for s in curves.iter().flatten() {
        let polygon: f64 = control_points(s)
            .windows(2)
            .map(|w| w[0].distance(w[1]))
            .sum();
        let per = crate::fit::OUTLINE_SAMPLES as f64 * polygon / gap;
        let samples = per.ceil().clamp(16.0, 1e5) as usize;
        for j in 0..=samples {
            let q = s.eval(j as f64 / samples as f64);
            // Squared, so that the search over edges takes no root per edge.
            let d2 = edges
                .iter()
                .map(|&(a, b)| (segment_foot(q, a, b).1 - q).hypot2())
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d2.sqrt());
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::QuadBez;

    #[test]
    fn distances_to_lines_and_curves() {
        let l = Segment::Line(Point::ZERO, Point::new(10.0, 0.0));
        assert_eq!(segment_distance(&l, Point::new(5.0, 3.0)), 3.0);
        assert_eq!(segment_distance(&l, Point::new(13.0, 4.0)), 5.0);
        let q = Segment::Quad(QuadBez::new(
            Point::ZERO,
            Point::new(5.0, 0.0),
            Point::new(10.0, 0.0),
        ));
        assert!((segment_distance(&q, Point::new(5.0, 2.0)) - 2.0).abs() < 1e-12);
        let b = boxed(&l);
        assert_eq!(b.lower_bound(Point::new(5.0, -2.0)), 2.0);
        assert_eq!(b.lower_bound(Point::new(5.0, 0.0)), 0.0);
    }
}
