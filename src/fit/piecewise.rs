//! Piecewise fitting of an outline: segments fitted in sequence, each joined
//! to the previous one with the required continuity.
//!
//! Three ways to choose the break points:
//! * [`fit_piecewise`]: the caller gives them;
//! * [`fit_segment_count`]: a fixed number of segments, split at equal arc
//!   length between corner points;
//! * [`fit_adaptive`]: Schneider's recursive split (Schneider 1990, "An
//!   algorithm for automatically fitting digitized curves", *Graphics Gems*):
//!   fit, and while the largest orthogonal distance exceeds a tolerance,
//!   split at the point of largest error and refit.
//!
//! Segment `k > 0` starts where segment `k − 1` ends and inherits its join
//! from it ([`Start::after`]), so interior joints hold C¹ or G¹ *by
//! construction*. On a closed outline the last segment must also end at the
//! first segment's start, which is all that can be imposed there without
//! solving the segments simultaneously: the closing joint is only C⁰, and
//! [`PiecewiseFit::closing`] reports its tangent and derivative mismatch.

use super::metrics::{segment_metrics, FitMetrics, SegmentMetrics};
use super::{FitError, FitOptions, Segment, SegmentProblem, SegmentSolver, Solution, Start};
use crate::geometry::{check_join, Continuity, Curve, Point};
use crate::problem::Problem;

/// One fitted segment of an outline.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedSegment {
    /// The geometry.
    pub segment: Segment,
    /// Outline index of its first data point.
    pub first: usize,
    /// Outline index of its last data point (on a closed outline the last
    /// segment wraps around, so `last` may be smaller than `first`).
    pub last: usize,
    /// The continuity imposed at its start (C⁰ for the first segment and
    /// after a corner).
    pub join: Continuity,
    /// The decision vector found.
    pub x: Vec<f64>,
    /// The local parameters `sᵢ` the error was measured at (after any
    /// parameter correction).
    pub params: Vec<f64>,
    /// What the solver reported (with parameter correction, the last solve;
    /// `evaluations` counts all of them).
    pub solution: Solution,
    /// Its error, distances and cost.
    pub metrics: SegmentMetrics,
}

/// The mismatch at the closing joint of a closed outline (last segment's end
/// → first segment's start), where only C⁰ is imposed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosingJoint {
    /// `|Q_last(1) − Q_first(0)|` (zero by construction, up to rounding).
    pub position_gap: f64,
    /// The angle between `Q_last′(1)` and `Q_first′(0)`, in degrees
    /// (0 = G¹; NaN if a derivative vanishes).
    pub angle_degrees: f64,
    /// `|Q_last′(1) − Q_first′(0)|` (0 = C¹).
    pub derivative_gap: f64,
    /// The derivative gap relative to the larger derivative's length.
    pub relative_derivative_gap: f64,
}

impl ClosingJoint {
    /// The mismatch between the end of `last` and the start of `first`.
    pub fn between<L: Curve + ?Sized, F: Curve + ?Sized>(last: &L, first: &F) -> ClosingJoint {
        let (d1, d2) = (last.deriv(1.0), first.deriv(0.0));
        let (l1, l2) = (d1.hypot(), d2.hypot());
        let angle = if l1 > 0.0 && l2 > 0.0 {
            d1.cross(d2).atan2(d1.dot(d2)).abs().to_degrees()
        } else {
            f64::NAN
        };
        let gap = (d1 - d2).hypot();
        let scale = l1.max(l2);
        ClosingJoint {
            position_gap: last.end().distance(first.start()),
            angle_degrees: angle,
            derivative_gap: gap,
            relative_derivative_gap: if scale > 0.0 { gap / scale } else { 0.0 },
        }
    }
}

/// A fitted outline.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseFit {
    /// The segments in order along the outline.
    pub segments: Vec<FittedSegment>,
    /// Whether the outline is closed.
    pub closed: bool,
    /// The closing joint's mismatch (closed outlines only).
    pub closing: Option<ClosingJoint>,
    /// Evaluations spent on fits that [`fit_adaptive`] split and discarded
    /// (included in `metrics.evaluations`; 0 for the other methods).
    pub discarded_evaluations: u64,
    /// The totals.
    pub metrics: FitMetrics,
}

impl PiecewiseFit {
    /// The break indices (each segment's first point).
    pub fn breaks(&self) -> Vec<usize> {
        self.segments.iter().map(|s| s.first).collect()
    }

    /// Whether every interior joint satisfies its continuity to relative
    /// tolerance `tol` ([`check_join`]); the closing joint is not included.
    pub fn joins_hold(&self, tol: f64) -> bool {
        self.segments
            .windows(2)
            .all(|w| check_join(&w[0].segment, &w[1].segment, w[1].join, tol))
    }
}

/// The outline and how to read a segment's data from it.
struct Outline<'a> {
    points: &'a [Point],
    closed: bool,
}

impl Outline<'_> {
    fn new(points: &[Point], closed: bool, function_min: usize) -> Result<Outline<'_>, FitError> {
        let needed = if closed {
            function_min - 1
        } else {
            function_min
        };
        if points.len() < needed.max(2) {
            return Err(FitError::TooFewOutlinePoints {
                found: points.len(),
                needed: needed.max(2),
            });
        }
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(FitError::NonFinitePoint { index });
        }
        Ok(Outline { points, closed })
    }

    fn len(&self) -> usize {
        self.points.len()
    }

    /// The points `first..=last` (`last ≥ first`, possibly `≥ len` for a
    /// wrap on a closed outline).
    fn gather(&self, first: usize, last: usize) -> Vec<Point> {
        (first..=last)
            .map(|i| self.points[i % self.len()])
            .collect()
    }

    /// Cumulative chord length from `first` over `first..=last`.
    fn cumulative(&self, first: usize, last: usize) -> Vec<f64> {
        let pts = self.gather(first, last);
        let mut acc = 0.0;
        let mut out = Vec::with_capacity(pts.len());
        out.push(0.0);
        for w in pts.windows(2) {
            acc += w[0].distance(w[1]);
            out.push(acc);
        }
        out
    }

    /// The spans `(first, last)` between consecutive breaks: on an open
    /// outline the ends are breaks too; on a closed one the last span wraps
    /// to the first break (no breaks: one span from point 0 round to itself).
    fn spans(&self, breaks: &[usize]) -> Result<Vec<(usize, usize)>, FitError> {
        let n = self.len();
        for (k, &b) in breaks.iter().enumerate() {
            if b >= n {
                return Err(FitError::BreakOutOfRange { index: b, len: n });
            }
            if k > 0 && b <= breaks[k - 1] {
                return Err(FitError::BreaksNotSorted {
                    position: k,
                    previous: breaks[k - 1],
                    index: b,
                });
            }
        }
        let mut b = breaks.to_vec();
        if self.closed {
            if b.is_empty() {
                b.push(0);
            }
            let mut spans: Vec<(usize, usize)> = b.windows(2).map(|w| (w[0], w[1])).collect();
            spans.push((b[b.len() - 1], b[0] + n));
            Ok(spans)
        } else {
            if b.first() != Some(&0) {
                b.insert(0, 0);
            }
            if b.last() != Some(&(n - 1)) {
                b.push(n - 1);
            }
            Ok(b.windows(2).map(|w| (w[0], w[1])).collect())
        }
    }
}

/// Checks that a span has enough points for `options.function`.
fn check_span(
    outline: &Outline<'_>,
    segment: usize,
    first: usize,
    last: usize,
    options: &FitOptions,
) -> Result<(), FitError> {
    let found = last - first + 1;
    let needed = options.function.min_points();
    if found < needed {
        return Err(FitError::TooFewPoints {
            segment,
            first,
            last: last % outline.len(),
            found,
            needed,
            function: options.function,
        });
    }
    Ok(())
}

/// Fits one segment on `first..=last` starting as `start` says.
#[allow(clippy::too_many_arguments)]
fn fit_one<S: SegmentSolver + ?Sized>(
    outline: &Outline<'_>,
    index: usize,
    first: usize,
    last: usize,
    start: Start,
    join: Continuity,
    options: &FitOptions,
    solver: &mut S,
) -> Result<FittedSegment, FitError> {
    check_span(outline, index, first, last, options)?;
    let pts = outline.gather(first, last);
    let mut problem = SegmentProblem::with_parameterisation(
        options.function,
        pts,
        options.parameterisation,
        start,
        &options.search,
    )?;
    let solve = |problem: &SegmentProblem, solver: &mut S| {
        if problem.dim() == 0 {
            // Fully determined (a quadratic with a C¹ join): no optimiser.
            Solution::fixed(problem, options.budget_per_segment)
        } else {
            solver.solve(problem, options.budget_per_segment)
        }
    };
    let mut solution = solve(&problem, solver);
    let mut spent = solution.evaluations;
    for _ in 0..options.reparameterise {
        let seg = problem.segment(&solution.x);
        problem = problem.with_params(problem.corrected_params(&seg))?;
        solution = solve(&problem, solver);
        spent += solution.evaluations;
    }
    solution.evaluations = spent;
    let segment = problem.segment(&solution.x);
    let metrics = segment_metrics(&segment, problem.points(), problem.params(), spent);
    Ok(FittedSegment {
        segment,
        first,
        last: last % outline.len(),
        join,
        x: solution.x.clone(),
        params: problem.params().to_vec(),
        solution,
        metrics,
    })
}

/// The start of the next segment after `previous` at a joint of `join`.
fn start_after(previous: Option<&FittedSegment>, join: Continuity) -> Start {
    previous.map_or(Start::Free, |p| Start::after(&p.segment, join))
}

/// Assembles the result.
fn finish(outline: &Outline<'_>, segments: Vec<FittedSegment>, discarded: u64) -> PiecewiseFit {
    let per: Vec<SegmentMetrics> = segments.iter().map(|s| s.metrics).collect();
    let mut metrics = FitMetrics::total(&per, outline.len());
    metrics.evaluations += discarded;
    let closing = match (outline.closed, segments.first(), segments.last()) {
        (true, Some(f), Some(l)) => Some(ClosingJoint::between(&l.segment, &f.segment)),
        _ => None,
    };
    PiecewiseFit {
        segments,
        closed: outline.closed,
        closing,
        discarded_evaluations: discarded,
        metrics,
    }
}

/// Fits the spans in order; `joins[k]` is the continuity at the start of span `k`.
fn fit_chain<S: SegmentSolver + ?Sized>(
    outline: &Outline<'_>,
    spans: &[(usize, usize)],
    joins: &[Continuity],
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    for (k, &(a, b)) in spans.iter().enumerate() {
        check_span(outline, k, a, b, options)?;
    }
    let mut segments: Vec<FittedSegment> = Vec::with_capacity(spans.len());
    for (k, (&(a, b), &join)) in spans.iter().zip(joins).enumerate() {
        let start = start_after(segments.last(), join);
        let seg = fit_one(outline, k, a, b, start, join, options, solver)?;
        segments.push(seg);
    }
    Ok(finish(outline, segments, 0))
}

/// Fits `options.function` to `points` split at `breaks`, every interior
/// joint with `options.continuity`, segments in sequence, each solved by
/// `solver` with `options.budget_per_segment` evaluations.
///
/// `breaks` are strictly increasing indices into `points`. On an open
/// outline the first and last points are breaks whether listed or not; on a
/// closed outline (`points` not repeating the first point at the end) the
/// last segment runs from the last break round to the first, and no breaks
/// means one segment from point 0 round to itself.
pub fn fit_piecewise<S: SegmentSolver + ?Sized>(
    points: &[Point],
    closed: bool,
    breaks: &[usize],
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    fit_breaks(points, closed, breaks, &[], options, solver)
}

/// [`fit_piecewise`] with known corners: a segment starting at one of the
/// `corners` (a subset of `breaks`) joins its predecessor with C⁰ only,
/// every other interior joint with `options.continuity`. Used for glyphs,
/// whose exact segments meet at smooth joints and at corners.
pub fn fit_breaks<S: SegmentSolver + ?Sized>(
    points: &[Point],
    closed: bool,
    breaks: &[usize],
    corners: &[usize],
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    options.validate()?;
    let outline = Outline::new(points, closed, options.function.min_points())?;
    let spans = outline.spans(breaks)?;
    let joins: Vec<Continuity> = spans
        .iter()
        .enumerate()
        .map(|(k, &(a, _))| {
            if k == 0 || corners.contains(&(a % points.len())) {
                Continuity::C0
            } else {
                options.continuity
            }
        })
        .collect();
    fit_chain(&outline, &spans, &joins, options, solver)
}

/// The break indices of `count` segments: the spans between `corners` get
/// segments in proportion to their arc length (each at least one, handed out
/// one at a time to the span with the largest length per segment), and each
/// span is split at equal arc length (the data point nearest to each
/// target). Returns the breaks (sorted, `< points.len()`) and which of them
/// are corners.
pub fn equal_arc_breaks(
    points: &[Point],
    closed: bool,
    corners: &[usize],
    count: usize,
) -> Result<(Vec<usize>, Vec<bool>), FitError> {
    let outline = Outline { points, closed };
    let spans = outline.spans(corners)?;
    if count < spans.len() {
        return Err(FitError::TooFewSegments {
            requested: count,
            minimum: spans.len(),
        });
    }
    let lengths: Vec<Vec<f64>> = spans
        .iter()
        .map(|&(a, b)| outline.cumulative(a, b))
        .collect();
    let total = |c: &Vec<f64>| *c.last().unwrap_or(&0.0);
    let mut alloc = vec![1usize; spans.len()];
    for _ in spans.len()..count {
        let k = (0..spans.len())
            .max_by(|&i, &j| {
                let (li, lj) = (
                    total(&lengths[i]) / alloc[i] as f64,
                    total(&lengths[j]) / alloc[j] as f64,
                );
                li.partial_cmp(&lj)
                    .unwrap_or(std::cmp::Ordering::Equal)
                    .then(j.cmp(&i))
            })
            .expect("at least one span");
        alloc[k] += 1;
    }
    let n = points.len();
    let mut out: Vec<(usize, bool)> = Vec::new();
    for ((&(a, b), cum), &parts) in spans.iter().zip(&lengths).zip(&alloc) {
        out.push((a % n, true));
        let len = total(cum);
        let mut prev = 0usize;
        for j in 1..parts {
            let target = len * j as f64 / parts as f64;
            // The local index nearest the target, strictly after the previous
            // break and leaving room for the rest.
            let mut best = prev + 1;
            for (i, &c) in cum.iter().enumerate().take(b - a).skip(prev + 1) {
                if (c - target).abs() < (cum[best] - target).abs() {
                    best = i;
                }
            }
            let best = best.min(b - a - (parts - j)).max(prev + 1);
            out.push(((a + best) % n, false));
            prev = best;
        }
    }
    // Spans on an open outline start at 0, which is not a corner unless listed.
    if !closed {
        if let Some(first) = out.first_mut() {
            first.1 = corners.contains(&0);
        }
    }
    out.sort_by_key(|&(i, _)| i);
    out.dedup_by_key(|&mut (i, _)| i);
    Ok(out.into_iter().unzip())
}

/// Fits exactly `count` segments: breaks at the `corners` (joined C⁰ — a
/// corner is a tangent discontinuity) and, when more segments than corner
/// spans are asked for, at equal arc length within the spans
/// ([`equal_arc_breaks`]), joined with `options.continuity`.
pub fn fit_segment_count<S: SegmentSolver + ?Sized>(
    points: &[Point],
    closed: bool,
    corners: &[usize],
    count: usize,
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    options.validate()?;
    let outline = Outline::new(points, closed, options.function.min_points())?;
    let (breaks, is_corner) = equal_arc_breaks(points, closed, corners, count)?;
    let spans = outline.spans(&breaks)?;
    let joins: Vec<Continuity> = spans
        .iter()
        .enumerate()
        .map(|(k, &(a, _))| {
            let corner = breaks
                .iter()
                .position(|&b| b == a)
                .is_some_and(|p| is_corner[p]);
            if k == 0 || corner {
                Continuity::C0
            } else {
                options.continuity
            }
        })
        .collect();
    fit_chain(&outline, &spans, &joins, options, solver)
}

/// The stopping rule of [`fit_adaptive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitOptions {
    /// Split while the largest orthogonal distance exceeds this (data
    /// units, `> 0`).
    pub tolerance: f64,
    /// How many times the fit starting at one data point may be rejected
    /// and split (the left part starts at the same point, the rest starts
    /// afresh at the split point); default 8.
    pub max_depth: u32,
    /// The fewest points a segment made by a split may have; the function's
    /// own minimum applies if that is larger. Default 0.
    pub min_points: usize,
}

impl SplitOptions {
    /// Splitting to `tolerance` with the default depth and size limits.
    pub fn new(tolerance: f64) -> SplitOptions {
        SplitOptions {
            tolerance,
            max_depth: 8,
            min_points: 0,
        }
    }
}

/// Schneider-style adaptive fitting: each span between `corners` is fitted
/// as one segment; while its largest orthogonal distance exceeds
/// `split.tolerance` (and the depth and size limits allow), it is split at
/// the data point of largest distance and the left part is refitted, then
/// the right part, in sequence so every joint keeps its continuity.
/// Corners are C⁰ joints. Fails if the tolerance is not finite and positive.
///
/// The limits can stop the splitting above the tolerance; the result then
/// says so through `metrics.max_distance`. This happens in particular with
/// C¹ joins of polynomial functions: each segment runs on its own `[0, 1]`,
/// so the derivative a short segment inherits from a long one fixes a first
/// leg proportional to the long one, which only a rational function can
/// compensate (through `w′₁`). G¹ joins do not have this problem.
pub fn fit_adaptive<S: SegmentSolver + ?Sized>(
    points: &[Point],
    closed: bool,
    corners: &[usize],
    split: &SplitOptions,
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    if !(split.tolerance.is_finite() && split.tolerance > 0.0) {
        return Err(FitError::InvalidTolerance(split.tolerance));
    }
    options.validate()?;
    let outline = Outline::new(points, closed, options.function.min_points())?;
    let spans = outline.spans(corners)?;
    for (k, &(a, b)) in spans.iter().enumerate() {
        check_span(&outline, k, a, b, options)?;
    }
    let min_pts = split.min_points.max(options.function.min_points());
    let mut segments: Vec<FittedSegment> = Vec::new();
    let mut discarded = 0u64;
    for &(a, b) in &spans {
        // Pending pieces, the next one on top: (first, last, depth).
        let mut stack = vec![(a, b, 0u32)];
        while let Some((p, q, depth)) = stack.pop() {
            let join = if segments.is_empty() || p == a {
                Continuity::C0
            } else {
                options.continuity
            };
            let start = start_after(segments.last(), join);
            let fit = fit_one(&outline, segments.len(), p, q, start, join, options, solver)?;
            let lo = p + min_pts - 1;
            let hi = q + 1 - min_pts.min(q + 1);
            if fit.metrics.max_distance > split.tolerance && depth < split.max_depth && lo <= hi {
                let m = (p + fit.metrics.max_index).clamp(lo, hi);
                discarded += fit.metrics.evaluations;
                // The rest starts afresh at m; the piece starting at p has
                // been rejected once more.
                stack.push((m, q, 0));
                stack.push((p, m, depth + 1));
            } else {
                segments.push(fit);
            }
        }
    }
    Ok(finish(&outline, segments, discarded))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(n: usize) -> Vec<Point> {
        (0..n).map(|k| Point::new(k as f64, 0.0)).collect()
    }

    #[test]
    fn spans_add_ends_and_wrap() {
        let pts = line(10);
        let open = Outline {
            points: &pts,
            closed: false,
        };
        assert_eq!(open.spans(&[]).unwrap(), vec![(0, 9)]);
        assert_eq!(open.spans(&[4]).unwrap(), vec![(0, 4), (4, 9)]);
        assert_eq!(open.spans(&[0, 4, 9]).unwrap(), vec![(0, 4), (4, 9)]);
        let closed = Outline {
            points: &pts,
            closed: true,
        };
        assert_eq!(closed.spans(&[]).unwrap(), vec![(0, 10)]);
        assert_eq!(closed.spans(&[2, 6]).unwrap(), vec![(2, 6), (6, 12)]);
        assert_eq!(closed.gather(6, 12)[4..], [pts[0], pts[1], pts[2]]);
        assert!(matches!(
            closed.spans(&[3, 3]),
            Err(FitError::BreaksNotSorted { .. })
        ));
        assert!(matches!(
            closed.spans(&[10]),
            Err(FitError::BreakOutOfRange { index: 10, len: 10 })
        ));
    }

    #[test]
    fn equal_arc_length_breaks() {
        // 31 equally spaced points, 3 segments: breaks at 10 and 20.
        let pts = line(31);
        let (b, corner) = equal_arc_breaks(&pts, false, &[], 3).unwrap();
        assert_eq!(b, vec![0, 10, 20]);
        assert_eq!(corner, vec![false, false, false]);
        // A corner at 6 takes a break; the longer span gets the extra segments.
        let (b, corner) = equal_arc_breaks(&pts, false, &[6], 4).unwrap();
        assert_eq!(b, vec![0, 6, 14, 22]);
        assert_eq!(corner, vec![false, true, false, false]);
        // Closed, no corners: a regular 30-gon.
        let pts: Vec<Point> = (0..30)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 30.0;
                Point::new(a.cos(), a.sin())
            })
            .collect();
        let (b, _) = equal_arc_breaks(&pts, true, &[], 3).unwrap();
        assert_eq!(b, vec![0, 10, 20]);
        assert_eq!(
            equal_arc_breaks(&pts, true, &[0, 10, 20], 2),
            Err(FitError::TooFewSegments {
                requested: 2,
                minimum: 3
            })
        );
    }

    #[test]
    fn closing_joint_measures_angle_and_gap() {
        use crate::geometry::QuadBez;
        let last = QuadBez::new(Point::new(-1.0, -1.0), Point::new(0.0, -1.0), Point::ZERO);
        // The last segment arrives along +y; the first leaves along +x.
        let first = QuadBez::new(Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 1.0));
        let c = ClosingJoint::between(&last, &first);
        assert_eq!(c.position_gap, 0.0);
        assert!((c.angle_degrees - 90.0).abs() < 1e-12);
        assert!((c.derivative_gap - 8f64.sqrt()).abs() < 1e-12);
        assert!((c.relative_derivative_gap - 8f64.sqrt() / 2.0).abs() < 1e-12);
    }
}
