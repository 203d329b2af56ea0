//! Fitting to a tolerance: Schneider's recursive split (Schneider 1990, "An
//! algorithm for automatically fitting digitized curves", *Graphics Gems*),
//! held to the two-sided distance, then a merge pass for fewer segments.
//!
//! 1. **Split.** Each span between corners is fitted as one segment; while
//!    its two-sided distance to the outline beyond the staircase's
//!    allowance ([`crate::fit::SegmentMetrics::excess`]) exceeds the
//!    tolerance, it is split where that distance is largest and the left
//!    part refitted, then the right part, in sequence so every joint keeps
//!    its continuity. A closed contour without corners is first cut at half
//!    its arc length (one segment cannot close on itself), and so is any
//!    piece whose outline turns by more than 270° (one segment would loop).
//! 2. **Merge.** The split leaves more segments than needed where a split
//!    point fell badly (a circle: 3 where 2 rational cubics are exact). The
//!    chain is fitted again over the split's breaks, each segment reaching
//!    over as many of them as its fit stays within the tolerance (greedy,
//!    never across a corner); a piece that no longer fits is split again.
//!    The merged chain is kept when it has fewer segments.
//! 3. **Joint.** With [`Chain::Joint`] all segments are solved at once and
//!    the result kept where it stays within the tolerance
//!    ([`keep_joint_unless_it_strays`]).
//! 4. **Guarantee.** Every segment ends within the tolerance, or the fit
//!    fails with [`FitError::ToleranceNotMet`] naming the segment and where.
//!
//! The staircase's allowance is computed, not a constant: a sample of the
//! curve in the gap between data points `i` and `i + 1` may lie the
//! polyline's sagitta `σᵢ = max(|Δ²Rᵢ|, |Δ²Rᵢ₊₁|)/8` further from the
//! polyline than the tolerance, the distance by which a chord of a smooth
//! curve through those points misses it ([`crate::fit::OutlineDistance`]).
//! Data points themselves get no allowance.
//!
//! With [`SplitOptions::coarse`] the trials of steps 1 and 2 are solved
//! coarsely (Levenberg–Marquardt stopped at a 0.3 % gain of `E`) and only
//! those near the tolerance again fully: the trials far beyond it, on the
//! longest spans, cost most and decide nothing close.

use super::piecewise::{end_before, finish, keep_joint_unless_it_strays, start_after, Plan};
use super::span::{fit_guarded, Outline, Piece};
#[cfg(doc)]
use super::{Chain, ErrorMeasure};
use super::{End, FitError, FitOptions, FittedSegment, PiecewiseFit, SegmentSolver};
use crate::geometry::{Continuity, Point};

/// The stopping rule of [`fit_adaptive`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitOptions {
    /// Split while a segment's two-sided distance beyond the staircase's
    /// allowance exceeds this (data units, `> 0`).
    pub tolerance: f64,
    /// How many times the fit starting at one data point may be rejected
    /// and split (the left part starts at the same point, the rest starts
    /// afresh at the split point); default 32. Reaching it above the
    /// tolerance fails the fit.
    pub max_depth: u32,
    /// The fewest points a segment made by a split may have; the function's
    /// own minimum applies if that is larger. Default 0.
    pub min_points: usize,
    /// Whether the merge pass runs (default `true`).
    pub merge: bool,
    /// Whether a curve sample may lie the polyline's sagitta further from
    /// it than the tolerance (see the module notes): for a pixel outline,
    /// whose staircase is not the shape (default `true`). Without it the
    /// tolerance holds the plain two-sided distance
    /// ([`crate::fit::SegmentMetrics::hausdorff`]): for points sampled
    /// from exact curves, where a sharp turn is a corner of the shape and
    /// its sagitta no allowance.
    pub staircase: bool,
    /// Coarse trial fits (`None`, the default: every trial solved fully).
    /// With `Some(r)` every trial of the split and merge passes that could
    /// be split again is solved by [`SegmentSolver::solve_coarse`] (for
    /// Levenberg–Marquardt under [`ErrorMeasure::Orthogonal`]: stopping
    /// once a step gains less than 0.3 % of `E`,
    /// [`super::COARSE_REDUCTION`]); one that then misses the
    /// tolerance by at most the factor `r` is solved again fully before it
    /// is rejected, so a trial near the tolerance is judged as without
    /// them. The trials far beyond the tolerance, which the search makes
    /// first on the longest spans, are the costly ones: a full orthogonal
    /// solve creeps along the near-reparameterisations of a curve that
    /// cannot fit (hundreds of evaluations) and a coarse one stops far
    /// sooner. The kept segments are then polished together by the joint
    /// solve ([`Chain::Joint`]) as before. [`COARSE_RECHECK`] is
    /// `metabezier fit`'s `r`.
    pub coarse: Option<f64>,
}

/// The recheck factor of [`SplitOptions::coarse`] in `metabezier fit`:
/// 1.5. A coarse trial within 1.5 times the tolerance is solved again
/// fully before it is rejected. On the peer-potrace inputs 1.3, 1.5, 1.7
/// and 2.5 took the same segment counts within one; 1.5 the fewest on the
/// logo at 0.5 px short of 2.5, which costs more full solves.
pub const COARSE_RECHECK: f64 = 1.5;

impl SplitOptions {
    /// Splitting to `tolerance` with the default depth and size limits and
    /// the merge pass.
    pub fn new(tolerance: f64) -> SplitOptions {
        SplitOptions {
            tolerance,
            max_depth: 32,
            min_points: 0,
            merge: true,
            staircase: true,
            coarse: None,
        }
    }
}

/// A chain being built: its segments in order, their spans (indices
/// increasing along the chain, past the outline's length after a wrap),
/// whether each starts at a corner, and the evaluations of fits that were
/// discarded.
#[derive(Default)]
struct Built {
    segments: Vec<FittedSegment>,
    spans: Vec<(usize, usize)>,
    corner: Vec<bool>,
    discarded: u64,
    /// The evaluations of segments taken over from another chain (the
    /// merge pass's unmerged pieces), spent there and not again.
    reused: u64,
    /// The spans fitted and rejected for the tolerance, each after the
    /// segments kept before it.
    rejected: Vec<(usize, usize)>,
}

impl Built {
    /// Appends a kept segment.
    fn push(&mut self, fit: FittedSegment, span: (usize, usize), corner: bool) {
        self.segments.push(fit);
        self.spans.push(span);
        self.corner.push(corner);
    }
}

/// The fixed context of one adaptive fit.
struct Splitter<'a, 'p, S: ?Sized> {
    outline: &'a Outline<'p>,
    options: &'a FitOptions,
    split: &'a SplitOptions,
    /// The fewest points of a segment.
    min_pts: usize,
    /// Whether the piece ending at `closing_point` joins the first
    /// segment's start.
    close: bool,
    closing_point: usize,
    solver: &'a mut S,
}

impl<S: SegmentSolver + ?Sized> Splitter<'_, '_, S> {
    /// Fits `p..=q` after the chain built so far (C⁰ after a corner), with
    /// the fit not kept by [`fit_guarded`] counted as discarded. A `trial`
    /// (one whose rejection can be split again) is solved coarsely when
    /// [`SplitOptions::coarse`] asks for it, and again fully when it then
    /// misses the tolerance by at most the recheck factor.
    fn fit(
        &mut self,
        built: &mut Built,
        p: usize,
        q: usize,
        corner: bool,
        trial: bool,
    ) -> Result<FittedSegment, FitError> {
        let join = if built.segments.is_empty() || corner {
            Continuity::C0
        } else {
            self.options.continuity
        };
        let end = match built.segments.first() {
            Some(f) if self.close && q == self.closing_point => {
                end_before(f, self.options.continuity)
            }
            _ => End::Free,
        };
        let piece = Piece {
            first: p,
            last: q,
            join,
            start: start_after(built.segments.last(), join),
            end,
            hold_end: false,
            coarse: trial && self.split.coarse.is_some(),
        };
        let (fit, spent) = fit_guarded(self.outline, piece, self.options, &mut *self.solver)?;
        built.discarded += spent;
        let Some(recheck) = self.split.coarse.filter(|_| piece.coarse) else {
            return Ok(fit);
        };
        let (tolerance, measured) = (self.split.tolerance, self.split.measure(&fit));
        if measured <= tolerance || measured > recheck * tolerance {
            return Ok(fit);
        }
        built.discarded += fit.metrics.evaluations;
        let full = Piece {
            coarse: false,
            ..piece
        };
        let (fit, spent) = fit_guarded(self.outline, full, self.options, &mut *self.solver)?;
        built.discarded += spent;
        Ok(fit)
    }

    /// Fits `a..=b` (starting at a corner if `corner`), split while a piece
    /// is beyond the tolerance and the limits allow; appends the pieces.
    fn split(
        &mut self,
        built: &mut Built,
        a: usize,
        b: usize,
        corner: bool,
    ) -> Result<(), FitError> {
        // Pending pieces, the next one on top: (first, last, depth, whether
        // it starts at a corner).
        let mut stack = vec![(a, b, 0u32, corner)];
        while let Some((p, q, depth, corner)) = stack.pop() {
            let lo = p + self.min_pts - 1;
            let hi = q + 1 - self.min_pts.min(q + 1);
            let splittable = depth < self.split.max_depth && lo <= hi;
            let fit = self.fit(built, p, q, corner, splittable)?;
            if self.split.measure(&fit) <= self.split.tolerance {
                built.push(fit, (p, q), corner);
            } else if splittable {
                let m = (p + self.split.split_at(&fit)).clamp(lo, hi);
                built.discarded += fit.metrics.evaluations;
                built.rejected.push((p, q));
                // The rest starts afresh at m; the piece starting at p has
                // been rejected once more.
                stack.push((m, q, 0, false));
                stack.push((p, m, depth + 1, corner));
            } else if let Some(m) = self.corner_split(&fit, p, q) {
                // Too short to split smoothly: the turn inside it is a
                // corner the detector missed.
                built.discarded += fit.metrics.evaluations;
                built.rejected.push((p, q));
                stack.push((m, q, 0, true));
                stack.push((p, m, depth + 1, corner));
            } else {
                built.push(fit, (p, q), corner);
            }
        }
        Ok(())
    }

    /// Where to cut a piece `p..=q` that is beyond the tolerance and too
    /// short to split with a smooth joint: at the point after the gap where
    /// it strays furthest, made a C⁰ joint — where the outline turns there
    /// by at least [`MIN_CORNER_TURN`] over two points each side (a corner
    /// the detector missed; a staircase's steps cancel in that sum). The
    /// shorter parts get points inserted ([`super::densify`]). `None` when
    /// the piece has a single gap or the outline does not turn there: the
    /// requested continuity is not given up on a smooth stretch.
    fn corner_split(&self, fit: &FittedSegment, p: usize, q: usize) -> Option<usize> {
        if q - p < 2 {
            return None;
        }
        let m = (p + self.split.split_at(fit)).clamp(p + 1, q - 1);
        let turn = turning(self.outline, m.saturating_sub(2).max(p), (m + 2).min(q));
        (turn.abs() >= MIN_CORNER_TURN).then_some(m)
    }

    /// The chain fitted again over the breaks of `first`, each segment
    /// reaching over as many of them as stays within the tolerance (never
    /// round a whole closed loop, which one segment cannot close). A piece
    /// that merges with nothing and meets the same neighbours as in `first`
    /// keeps its fit from there.
    fn merge(&mut self, first: &Built) -> Result<Built, FitError> {
        let spans = &first.spans;
        let n = spans.len();
        let loop_len = self.outline.len();
        let mut built = Built::default();
        let mut i = 0;
        while i < n {
            let mut best: Option<(usize, FittedSegment)> = None;
            let mut j = i + 1;
            while j < n && !first.corner[j] && spans[j].1 - spans[i].0 < loop_len {
                // A span the split already fitted and rejected after the
                // same neighbours would be rejected again.
                let again = (spans[i].0, spans[j].1);
                if first.rejected.contains(&again) && self.same_neighbours(first, &built, i) {
                    break;
                }
                if turning(self.outline, again.0, again.1).abs() > MAX_TURN {
                    break;
                }
                let fit = self.fit(&mut built, spans[i].0, spans[j].1, first.corner[i], true)?;
                if self.split.measure(&fit) > self.split.tolerance {
                    built.discarded += fit.metrics.evaluations;
                    break;
                }
                if let Some((_, old)) = best.replace((j, fit)) {
                    built.discarded += old.metrics.evaluations;
                }
                j += 1;
            }
            match best {
                Some((j, fit)) => {
                    built.push(fit, (spans[i].0, spans[j].1), first.corner[i]);
                    i = j + 1;
                }
                None if self.same_neighbours(first, &built, i) => {
                    built.reused += first.segments[i].metrics.evaluations;
                    built.push(first.segments[i].clone(), spans[i], first.corner[i]);
                    i += 1;
                }
                None => {
                    self.split(&mut built, spans[i].0, spans[i].1, first.corner[i])?;
                    i += 1;
                }
            }
        }
        Ok(built)
    }

    /// Whether piece `i` of `first` meets the same joins in `built` as it
    /// did there: the same previous segment and, for the piece that closes
    /// the chain, the same first one.
    fn same_neighbours(&self, first: &Built, built: &Built, i: usize) -> bool {
        let previous = match i.checked_sub(1) {
            None => built.segments.is_empty(),
            Some(p) => built.segments.last() == first.segments.get(p),
        };
        let closes = self.close && first.spans[i].1 == self.closing_point;
        previous && (!closes || built.segments.first() == first.segments.first())
    }
}

impl SplitOptions {
    /// What the tolerance holds for `fit`: its two-sided distance, beyond
    /// the staircase's allowance if [`SplitOptions::staircase`].
    pub(super) fn measure(&self, fit: &FittedSegment) -> f64 {
        if self.staircase {
            fit.metrics.excess
        } else {
            fit.metrics.hausdorff
        }
    }

    /// The local index to split a rejected `fit` at: the data point of
    /// largest distance, or the point after the gap where the curve strays
    /// furthest.
    fn split_at(&self, fit: &FittedSegment) -> usize {
        let m = &fit.metrics;
        let (d, gap) = if self.staircase {
            (m.excess, m.excess_gap)
        } else {
            (m.hausdorff, m.hausdorff_gap)
        };
        if d > m.max_distance {
            gap + 1
        } else {
            m.max_index
        }
    }

    /// The largest [`SplitOptions::measure`] over `segments`.
    fn worst(&self, segments: &[FittedSegment]) -> f64 {
        segments.iter().map(|s| self.measure(s)).fold(0.0, f64::max)
    }
}

/// The least turn of the outline (radians, net over two points each side)
/// at which a piece that cannot meet the tolerance smoothly is cut with a
/// C⁰ joint: 30°, half the corner detector's default.
const MIN_CORNER_TURN: f64 = std::f64::consts::PI / 6.0;

/// The most a piece's outline may turn (net, radians) for one segment to be
/// tried on it: 270°. A cubic segment that turns further closes into a
/// loop; such a piece is cut at half its arc length first (and never
/// merged back), which spares a fit that cannot hold any tolerance — on an
/// open circle of 3·10⁵ points, a solve of all of them.
const MAX_TURN: f64 = 1.5 * std::f64::consts::PI;

/// The net turning of the outline's polyline over points `a..=b`: the sum
/// of the signed angles between consecutive edges (radians; a pixel
/// staircase's steps cancel).
fn turning(outline: &Outline<'_>, a: usize, b: usize) -> f64 {
    let pts = outline.gather(a, b);
    pts.windows(3)
        .map(|w| {
            let (u, v) = (w[1] - w[0], w[2] - w[1]);
            u.cross(v).atan2(u.dot(v))
        })
        .sum()
}

/// The point of `a..=b` nearest half its arc length (local index, in
/// `1..b − a`).
fn half_way(outline: &Outline<'_>, a: usize, b: usize) -> usize {
    let cum = outline.cumulative(a, b);
    let half = cum[b - a] / 2.0;
    (1..b - a)
        .min_by(|&i, &j| (cum[i] - half).abs().total_cmp(&(cum[j] - half).abs()))
        .unwrap_or((b - a) / 2)
}

/// The initial pieces of `chain`: its spans, each cut at half its arc
/// length while it is a whole closed loop or turns more than [`MAX_TURN`]
/// (down to 8 points a piece).
fn initial_pieces(outline: &Outline<'_>, chain: &Plan) -> Vec<(usize, usize, bool)> {
    let n = outline.len();
    let mut pieces = Vec::with_capacity(chain.spans.len() + 1);
    for (k, &(a, b)) in chain.spans.iter().enumerate() {
        let corner = k > 0 && chain.joins[k] == Continuity::C0;
        let mut stack = vec![(a, b, corner)];
        while let Some((p, q, corner)) = stack.pop() {
            let loops = outline.closed && q - p == n;
            if q - p >= 8 && (loops || turning(outline, p, q).abs() > MAX_TURN) {
                let m = p + half_way(outline, p, q);
                stack.push((m, q, false));
                stack.push((p, m, corner));
            } else {
                pieces.push((p, q, corner));
            }
        }
    }
    pieces
}

/// Fits `points` to a tolerance (see the module notes): split, merge,
/// joint solve, and the guarantee that every segment's two-sided distance
/// to the outline beyond the staircase's allowance is within
/// `split.tolerance`, or [`FitError::ToleranceNotMet`]. Corners are C⁰
/// joints. Fails if the tolerance is not finite and positive.
///
/// With C¹ joins of polynomial functions the split can reach its limits
/// above the tolerance: each segment runs on its own `[0, 1]`, so the
/// derivative a short segment inherits from a long one fixes a first leg
/// proportional to the long one, which only a rational function can
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
    let chain = Plan::at_corners(&outline, outline.spans(corners)?, corners, options);
    let mut splitter = Splitter {
        outline: &outline,
        options,
        split,
        min_pts: split.min_points.max(options.function.min_points()),
        // A corner-free contour is one span, which the splits cut into
        // several segments: it closes smoothly too (the last piece joins
        // the first segment's start once that exists).
        close: chain.closes_smoothly_split(&outline, options),
        closing_point: chain.spans.last().map_or(0, |s| s.1),
        solver,
    };
    let mut first = Built::default();
    for (a, b, corner) in initial_pieces(&outline, &chain) {
        splitter.split(&mut first, a, b, corner)?;
    }
    let mut built = first;
    if split.merge && built.segments.len() > 1 {
        let mut merged = splitter.merge(&built)?;
        let fewer = merged.segments.len() < built.segments.len();
        // Every fit counts once: the chain not kept is discarded, less
        // what the merged chain took over from the split's.
        if fewer && split.worst(&merged.segments) <= split.tolerance {
            merged.discarded += built.discarded + evaluations(&built.segments) - merged.reused;
            built = merged;
        } else {
            built.discarded += merged.discarded + evaluations(&merged.segments) - merged.reused;
        }
    }
    let kept = keep_joint_unless_it_strays(
        &outline,
        built.segments,
        options,
        split.tolerance,
        |s: &[FittedSegment]| split.worst(s),
    )?;
    let segments = kept.segments;
    if let Some((k, s)) = segments
        .iter()
        .enumerate()
        .find(|(_, s)| split.measure(s) > split.tolerance)
    {
        let gap = if split.staircase {
            s.metrics.excess_gap
        } else {
            s.metrics.hausdorff_gap
        };
        return Err(FitError::ToleranceNotMet {
            tolerance: split.tolerance,
            excess: split.measure(s),
            segment: k,
            first: s.first,
            last: s.last,
            at: points[(s.first + gap) % points.len()],
        });
    }
    let discarded = built.discarded + kept.rejected.map_or(0, |r| r.0);
    let mut fit = finish(
        &outline,
        segments,
        discarded,
        chain.at_corner,
        kept.joint,
        options,
    );
    fit.tolerance = Some(split.tolerance);
    fit.staircase = split.staircase;
    fit.joint_rejected = kept.rejected.map(|r| r.1);
    Ok(fit)
}

/// The evaluations of `segments`' own fits.
fn evaluations(segments: &[FittedSegment]) -> u64 {
    segments.iter().map(|s| s.metrics.evaluations).sum()
}
