//! Piecewise fitting of an outline: segments fitted in sequence, each joined
//! to the previous one with the required continuity.
//!
//! Three ways to choose the break points:
//! * [`fit_piecewise`]: the caller gives them;
//! * [`fit_segment_count`]: a fixed number of segments, split at equal arc
//!   length between corner points;
//! * [`super::fit_adaptive`]: Schneider's recursive split (Schneider 1990, "An
//!   algorithm for automatically fitting digitized curves", *Graphics Gems*):
//!   fit, and while the largest orthogonal distance exceeds a tolerance,
//!   split at the point of largest error and refit. A corner-free closed
//!   contour (one span, cut by the splits) closes smoothly as well.
//!
//! Segment `k > 0` starts where segment `k − 1` ends and inherits its join
//! from it ([`Start::after`]), so interior joints hold C¹ or G¹ *by
//! construction*. On a closed outline the chain must also close
//! ([`Closing`]): closed smoothly (the default), it starts at a corner when
//! the outline has one, so it closes at that corner (C⁰ is right there);
//! without a corner the last segment is fitted with an end join to the
//! first segment's start ([`End`]), so the closing joint is G¹ or C¹ by
//! construction too, at no extra solve. Quadratic functions have one inner
//! control point: they close G¹ where the two tangent lines meet in front
//! of both ends ([`crate::fit::tangent_meet`]) and C⁰ otherwise, and with
//! C¹ joins they close C⁰ (C¹ would fix that point twice). Closed C⁰
//! ([`Closing::C0`]) the chain starts at the first break and only C⁰ is
//! imposed at the closing joint, as the thesis's sequential fitting does.
//! [`PiecewiseFit::closing`] reports the closing joint's mismatch either way.
//!
//! With [`Chain::Joint`] the sequential chain is the start of one solve of
//! all its segments with shared joins (see `chain.rs`); [`super::fit_adaptive`]
//! keeps the joint result only where it stays within its tolerance.
//!
//! [`fit_independent`] refits every segment of a reference fit as its own
//! problem, joined to the reference's neighbours (the per-segment mode).

use super::chain::{solve_joint, Fitted};
use super::metrics::{FitMetrics, SegmentMetrics};
use super::span::{fit_guarded, fit_one, strays, Outline, Piece};
use super::{
    outline_trace, Chain, Closing, End, FitError, FitOptions, FittedSegment, SegmentSolver, Start,
};
use crate::geometry::{check_join, Continuity, Curve, Point};
use crate::optim::lm::LevenbergMarquardt;
use crate::optim::TracePoint;

/// The mismatch at the closing joint of a closed outline (last segment's end
/// → first segment's start).
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
    /// The continuity imposed there: C⁰ at a corner or for a chain closed
    /// C⁰ ([`Closing::C0`]), else the fit's continuity.
    pub imposed: Continuity,
    /// Whether the chain starts, and so closes, at a detected corner.
    pub at_corner: bool,
}

impl ClosingJoint {
    /// The mismatch between the end of `last` and the start of `first`
    /// (imposed C⁰, not at a corner; see [`ClosingJoint::imposed`]).
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
            imposed: Continuity::C0,
            at_corner: false,
        }
    }
}

/// A fitted outline.
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseFit {
    /// The segments in fitting order along the outline (on a closed outline
    /// closed smoothly, starting at a corner when there is one).
    pub segments: Vec<FittedSegment>,
    /// Whether the outline is closed.
    pub closed: bool,
    /// The closing joint's mismatch (closed outlines only).
    pub closing: Option<ClosingJoint>,
    /// Evaluations spent on fits that [`super::fit_adaptive`] split and discarded
    /// (included in `metrics.evaluations`; 0 for the other methods).
    pub discarded_evaluations: u64,
    /// The chain that made the segments: [`Chain::Joint`] when the joint
    /// solve was asked for and kept, else [`Chain::Sequential`].
    pub chain: Chain,
    /// Evaluations of the joint solve (included in `metrics.evaluations`;
    /// the segments' own count their sequential fits).
    pub chain_evaluations: u64,
    /// Rational weights at a bound of the search box's weight range
    /// ([`crate::fit::SearchSpaceOptions::weight_range`], within 10⁻⁹
    /// relative): a segment whose shape the box, not the data, decided.
    pub weights_at_bounds: usize,
    /// The tolerance the fit was held to ([`super::fit_adaptive`]): every
    /// segment's two-sided distance beyond the staircase's allowance
    /// (`metrics.excess`) is within it. `None` for the other methods.
    pub tolerance: Option<f64>,
    /// When the joint solve was asked for and rejected because it strayed
    /// from the outline ([`Chain::Joint`]; see `keep_joint_unless_it_strays`):
    /// its largest two-sided distance, against which the sequential chain
    /// was kept.
    pub joint_rejected: Option<f64>,
    /// Whether the tolerance allowed curve samples the staircase's sagitta
    /// ([`crate::fit::SplitOptions::staircase`]): `metrics.excess` is what
    /// it holds, else `metrics.hausdorff`.
    pub staircase: bool,
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

    /// The best-so-far `E` of the whole fit against evaluations
    /// ([`outline_trace`]); after a joint solve, its `E` at the end.
    pub fn trace(&self) -> Vec<TracePoint> {
        let mut trace = outline_trace(&self.segments);
        if self.chain_evaluations > 0 && !trace.is_empty() {
            trace.push(TracePoint {
                evaluations: self.metrics.evaluations - self.discarded_evaluations,
                best: self.metrics.sse,
            });
        }
        trace
    }
}

/// The start of the next segment after `previous` at a joint of `join`.
pub(super) fn start_after(previous: Option<&FittedSegment>, join: Continuity) -> Start {
    previous.map_or(Start::Free, |p| Start::after(&p.segment, join))
}

/// The end join of a segment that closes the chain before `first`: the
/// first segment's start tangent (G¹) or derivative (C¹).
pub(super) fn end_before(first: &FittedSegment, continuity: Continuity) -> End {
    let d = first.segment.deriv(0.0);
    match continuity {
        Continuity::C0 => End::Free,
        Continuity::C1 => End::C1 { derivative: d },
        Continuity::G1 => End::G1 { dir: d },
    }
}

/// Assembles the result; `at_corner` says whether the chain starts (and
/// closes) at a corner.
pub(super) fn finish(
    outline: &Outline<'_>,
    segments: Vec<FittedSegment>,
    discarded: u64,
    at_corner: bool,
    joint: Option<u64>,
    options: &FitOptions,
) -> PiecewiseFit {
    let weights_at_bounds = segments
        .iter()
        .map(|s| weights_at_bounds(&s.segment, options.search.weight_range))
        .sum();
    let per: Vec<SegmentMetrics> = segments.iter().map(|s| s.metrics).collect();
    let mut metrics = FitMetrics::total(&per, outline.len());
    let chain_evaluations = joint.unwrap_or(0);
    metrics.evaluations += discarded + chain_evaluations;
    let closing = match (outline.closed, segments.first(), segments.last()) {
        (true, Some(f), Some(l)) => {
            let mut c = ClosingJoint::between(&l.segment, &f.segment);
            c.at_corner = at_corner;
            c.imposed = match l.end {
                End::Free => Continuity::C0,
                End::C1 { .. } => Continuity::C1,
                End::G1 { .. } => Continuity::G1,
            };
            Some(c)
        }
        _ => None,
    };
    PiecewiseFit {
        segments,
        closed: outline.closed,
        closing,
        discarded_evaluations: discarded,
        chain: if joint.is_some() {
            Chain::Joint
        } else {
            Chain::Sequential
        },
        chain_evaluations,
        weights_at_bounds,
        tolerance: None,
        joint_rejected: None,
        staircase: false,
        metrics,
    }
}

/// How many of `segment`'s free weights (all but the ends') lie at a bound
/// of `range`, within 10⁻⁹ relative.
fn weights_at_bounds(segment: &super::Segment, range: (f64, f64)) -> usize {
    let w = segment.weights();
    let at = |x: f64, b: f64| (x - b).abs() <= 1e-9 * b;
    let inner = &w[1..w.len() - 1];
    match segment.function() {
        super::FunctionType::RationalQuadratic | super::FunctionType::RationalCubic => inner
            .iter()
            .filter(|&&x| at(x, range.0) || at(x, range.1))
            .count(),
        _ => 0,
    }
}

/// The largest two-sided distance beyond the staircase's allowance of
/// `segments` (`metrics.excess`).
fn worst_excess(segments: &[FittedSegment]) -> f64 {
    segments
        .iter()
        .map(|s| s.metrics.excess)
        .fold(0.0, f64::max)
}

/// The joint solve's result, or the sequential `segments` where the joint
/// one strays: its `worst` two-sided distance above `limit` (a tolerance)
/// and above the sequential chain's own, and, in a chain of fixed count
/// (`limit` 0), where some segment leaves the outline where no data point
/// is ([`super::span::strays`]; a marginally larger distance along the data
/// is the price of the joint solve's lower `E` there). The joint solve
/// minimises the data's distances only, so it can park curve past a corner
/// where no data point is (a whisker); the sequential chain, fitted piece
/// by piece with [`fit_guarded`], is the fallback. Returns the segments,
/// the joint evaluations (`None` when the sequential ones are kept) and,
/// for a rejected joint solve, its evaluations and its `worst` distance.
pub(super) struct Kept {
    /// The segments kept.
    pub(super) segments: Vec<FittedSegment>,
    /// The joint solve's evaluations, when its result is kept.
    pub(super) joint: Option<u64>,
    /// A rejected joint solve's evaluations and `worst` distance.
    pub(super) rejected: Option<(u64, f64)>,
}

/// See [`Kept`].
pub(super) fn keep_joint_unless_it_strays(
    outline: &Outline<'_>,
    segments: Vec<FittedSegment>,
    options: &FitOptions,
    limit: f64,
    worst: impl Fn(&[FittedSegment]) -> f64,
) -> Result<Kept, FitError> {
    let spans = spans_of(outline, &segments);
    let kept = |segments, joint, rejected| Kept {
        segments,
        joint,
        rejected,
    };
    Ok(match joint_chain(outline, &segments, &spans, options)? {
        Some((refit, used)) => {
            let strayed = worst(&refit);
            let whisker = limit > 0.0 || refit.iter().any(strays);
            if !whisker || strayed <= limit.max(worst(&segments)) {
                kept(refit, Some(used), None)
            } else {
                kept(segments, None, Some((used, strayed)))
            }
        }
        None => kept(segments, None, None),
    })
}

/// The spans of `segments` on `outline`, wrapping indices kept increasing.
pub(super) fn spans_of(outline: &Outline<'_>, segments: &[FittedSegment]) -> Vec<(usize, usize)> {
    let n = outline.len();
    segments
        .iter()
        .map(|s| {
            let last = if outline.closed && s.last <= s.first {
                s.last + n
            } else {
                s.last
            };
            (s.first, last)
        })
        .collect()
}

/// The joint solve of a sequential chain's `segments` when the options ask
/// for it ([`Chain::Joint`]): Levenberg–Marquardt over all of them with a
/// budget of `budget_per_segment` per segment (as much again as the
/// sequential fit was given). Returns the refitted segments and the joint
/// evaluations, or `None` when the chain is sequential or the joint
/// variables cannot describe it (a straight quadratic).
pub(super) fn joint_chain(
    outline: &Outline<'_>,
    segments: &[FittedSegment],
    spans: &[(usize, usize)],
    options: &FitOptions,
) -> Result<Option<(Vec<FittedSegment>, u64)>, FitError> {
    if options.chain != Chain::Joint || segments.is_empty() {
        return Ok(None);
    }
    let fitted: Vec<Fitted<'_>> = segments
        .iter()
        .zip(spans)
        .map(|(segment, &span)| Fitted { segment, span })
        .collect();
    // A step gaining less than 10⁻⁶ of E ends the solve: on the horse at
    // 101 rational cubics that costs 1.0 % of the fixed E (0.0 % of the
    // orthogonal) and saves 73 % (15 %) of the joint evaluations.
    let lm = LevenbergMarquardt {
        reduction_tol: 1e-6,
        ..LevenbergMarquardt::default()
    };
    let budget = options
        .budget_per_segment
        .saturating_mul(segments.len() as u64);
    solve_joint(outline, &fitted, options, &lm, budget)
}

/// How an open chain joins what lies beyond its ends: the first segment's
/// start and the last segment's end, each joined to a known curve outside
/// the data (as the cranial implant's outer wall joins the intact bone at
/// A′ and B′, thesis chapter 6). The default joins nothing: both ends free.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChainEnds {
    /// How the first segment starts ([`Start::Free`]: C⁰, nothing before).
    pub start: Start,
    /// How the last segment ends ([`End::Free`]: nothing after).
    pub end: End,
}

impl Default for ChainEnds {
    fn default() -> Self {
        ChainEnds {
            start: Start::Free,
            end: End::Free,
        }
    }
}

impl ChainEnds {
    /// The continuity the start join imposes: C⁰ when free.
    fn start_continuity(&self) -> Continuity {
        match self.start {
            Start::Free => Continuity::C0,
            Start::C1 { .. } => Continuity::C1,
            Start::G1 { .. } => Continuity::G1,
        }
    }
}

/// The spans of a chain in fitting order, the continuity at each start,
/// whether the first starts at a corner, and the joins beyond the ends of
/// an open chain.
pub(super) struct Plan {
    pub(super) spans: Vec<(usize, usize)>,
    pub(super) joins: Vec<Continuity>,
    pub(super) at_corner: bool,
    pub(super) ends: ChainEnds,
}

impl Plan {
    /// The chain of `spans` (in outline order) whose starts are corners
    /// where `corner[k]`: C⁰ there, the options' continuity elsewhere, the
    /// first segment free. A closed outline closed smoothly starts at its
    /// first corner, if any (the spans rotated, wrapping indices kept
    /// increasing); otherwise the chain starts at the first span.
    pub(super) fn new(
        outline: &Outline<'_>,
        spans: Vec<(usize, usize)>,
        corner: &[bool],
        options: &FitOptions,
    ) -> Plan {
        let mut joins: Vec<Continuity> = corner
            .iter()
            .map(|&c| {
                if c {
                    Continuity::C0
                } else {
                    options.continuity
                }
            })
            .collect();
        let smooth = outline.closed && options.closing == Closing::Smooth;
        let first = if smooth {
            corner.iter().position(|&c| c).unwrap_or(0)
        } else {
            0
        };
        let n = outline.len();
        let mut spans = spans;
        spans.rotate_left(first);
        joins.rotate_left(first);
        // Indices after the rotation point wrap: keep them increasing.
        let base = spans.first().map_or(0, |s| s.0);
        for s in spans.iter_mut() {
            if s.0 < base {
                *s = (s.0 + n, s.1 + n);
            }
        }
        let at_corner = outline.closed && corner.get(first).copied().unwrap_or(false);
        if let Some(j) = joins.first_mut() {
            *j = Continuity::C0;
        }
        Plan {
            spans,
            joins,
            at_corner,
            ends: ChainEnds::default(),
        }
    }

    /// [`Plan::new`] with the spans that start at one of `corners` (outline
    /// indices) as corners.
    pub(super) fn at_corners(
        outline: &Outline<'_>,
        spans: Vec<(usize, usize)>,
        corners: &[usize],
        options: &FitOptions,
    ) -> Plan {
        let corner: Vec<bool> = spans
            .iter()
            .map(|&(a, _)| corners.contains(&(a % outline.len())))
            .collect();
        Plan::new(outline, spans, &corner, options)
    }

    /// Whether the last segment of a split fit ([`super::fit_adaptive`]) joins the
    /// first one's start: a closed outline closed smoothly, not at a
    /// corner, with a smooth continuity.
    pub(super) fn closes_smoothly_split(
        &self,
        outline: &Outline<'_>,
        options: &FitOptions,
    ) -> bool {
        outline.closed
            && options.closing == Closing::Smooth
            && !self.at_corner
            && options.continuity != Continuity::C0
    }

    /// Whether the last segment of a chain of spans joins the first one's
    /// start: as [`Plan::closes_smoothly_split`], with more than one span.
    fn closes_smoothly(&self, outline: &Outline<'_>, options: &FitOptions) -> bool {
        self.closes_smoothly_split(outline, options) && self.spans.len() > 1
    }
}

/// Fits the chain's spans in order, each inheriting its join; the first
/// one starts and the last one ends as the plan's [`ChainEnds`] say, and
/// the last one joins the first when the chain closes smoothly.
fn fit_chain<S: SegmentSolver + ?Sized>(
    outline: &Outline<'_>,
    chain: &Plan,
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    let close = chain.closes_smoothly(outline, options);
    let n = chain.spans.len();
    let mut segments: Vec<FittedSegment> = Vec::with_capacity(n);
    let mut discarded = 0;
    for (k, (&(first, last), &join)) in chain.spans.iter().zip(&chain.joins).enumerate() {
        let given = k + 1 == n && chain.ends.end != End::Free;
        let end = match segments.first() {
            Some(f) if close && k + 1 == n => end_before(f, options.continuity),
            _ if given => chain.ends.end,
            _ => End::Free,
        };
        let start = match segments.last() {
            None => chain.ends.start,
            previous => start_after(previous, join),
        };
        let piece = Piece {
            first,
            last,
            join,
            start,
            end,
            hold_end: given,
            coarse: false,
        };
        let (fit, spent) = fit_guarded(outline, piece, options, solver)?;
        discarded += spent;
        segments.push(fit);
    }
    let kept = keep_joint_unless_it_strays(outline, segments, options, 0.0, worst_excess)?;
    let mut fit = finish(
        outline,
        kept.segments,
        discarded + kept.rejected.map_or(0, |r| r.0),
        chain.at_corner,
        kept.joint,
        options,
    );
    fit.joint_rejected = kept.rejected.map(|r| r.1);
    Ok(fit)
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
    let chain = Plan::at_corners(&outline, outline.spans(breaks)?, corners, options);
    fit_chain(&outline, &chain, options, solver)
}

/// [`fit_piecewise`] on an open outline whose ends join known curves
/// outside it: the first segment starts as `ends.start` says and the last
/// ends as `ends.end` says, every interior joint with `options.continuity`,
/// segments in sequence, each solved by `solver` with
/// `options.budget_per_segment` evaluations. The end join must hold: one
/// the function cannot hold (a quadratic joined at both ends, a zero end
/// tangent) fails with [`FitError::InvalidOption`] named `"end"`.
///
/// Used by the cranial implant's outer wall, a chain between the intact
/// bone at A′ and at B′ (thesis chapter 6).
pub fn fit_between<S: SegmentSolver + ?Sized>(
    points: &[Point],
    breaks: &[usize],
    ends: ChainEnds,
    options: &FitOptions,
    solver: &mut S,
) -> Result<PiecewiseFit, FitError> {
    options.validate()?;
    let outline = Outline::new(points, false, options.function.min_points())?;
    let spans = outline.spans(breaks)?;
    let corner = vec![false; spans.len()];
    let mut chain = Plan::new(&outline, spans, &corner, options);
    if let Some(j) = chain.joins.first_mut() {
        *j = ends.start_continuity();
    }
    chain.ends = ends;
    fit_chain(&outline, &chain, options, solver)
}

/// The break indices of `count` segments: the spans between `corners` get
/// segments in proportion to their arc length (each at least one, handed out
/// one at a time to the span with the largest length per segment), and each
/// span is split at equal arc length (the data point nearest to each
/// target). Returns the breaks (sorted, `< points.len()`) and which of them
/// are corners. Fails with fewer segments than spans, or more than the
/// outline's gaps between consecutive points ([`FitError::TooManySegments`]:
/// `n − 1` for `n` open points, `n` closed).
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
    // Each segment spans at least one gap between consecutive points: the
    // spans hold `n − 1` gaps in all (open) or `n` (closed), whatever the
    // corners; asking for more used to be cut down to that silently.
    let maximum = spans.iter().map(|&(a, b)| b - a).sum::<usize>();
    if count > maximum {
        return Err(FitError::TooManySegments {
            requested: count,
            maximum,
            points: points.len(),
            closed,
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
        // A span starts at a corner, or at point 0 of an outline without
        // corners (open, or closed and smooth all round).
        out.push((a % n, corners.contains(&(a % n))));
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
    let corner: Vec<bool> = spans
        .iter()
        .map(|&(a, _)| {
            breaks
                .iter()
                .position(|&b| b == a)
                .is_some_and(|p| is_corner[p])
        })
        .collect();
    let chain = Plan::new(&outline, spans, &corner, options);
    fit_chain(&outline, &chain, options, solver)
}

/// Fits every segment of `reference` again as its own problem: the same
/// data span, the same joins, but each segment's start joined to the
/// *reference's* previous segment (and a smoothly closing last segment to
/// the reference's first), so that no segment inherits anything from how
/// its neighbours were fitted now. Segment `k` is solved by
/// `solver_for(k)`; with the exact fit (LM) as the reference, this is the
/// per-segment problem mode of the chapter-5 studies, where segments are
/// the units of the tests.
///
/// The segments of the result meet their *reference* neighbours with the
/// required continuity, not one another (their joints are C⁰ only).
pub fn fit_independent<S, F>(
    points: &[Point],
    closed: bool,
    reference: &PiecewiseFit,
    options: &FitOptions,
    mut solver_for: F,
) -> Result<PiecewiseFit, FitError>
where
    S: SegmentSolver,
    F: FnMut(usize) -> S,
{
    options.validate()?;
    let outline = Outline::new(points, closed, options.function.min_points())?;
    let refs = &reference.segments;
    let spans = spans_of(&outline, refs);
    let mut segments = Vec::with_capacity(refs.len());
    for (k, (r, &(_, last))) in refs.iter().zip(&spans).enumerate() {
        let start = match k.checked_sub(1) {
            Some(p) if r.join != Continuity::C0 => Start::after(&refs[p].segment, r.join),
            _ => Start::Free,
        };
        let piece = Piece {
            first: r.first,
            last,
            join: r.join,
            start,
            end: r.end,
            hold_end: false,
            coarse: false,
        };
        segments.push(fit_one(&outline, piece, options, &mut solver_for(k))?);
    }
    let at_corner = reference.closing.is_some_and(|c| c.at_corner);
    Ok(finish(&outline, segments, 0, at_corner, None, options))
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
    fn a_chain_between_given_ends_holds_them() {
        use crate::fit::LmSolver;
        // A quarter circle, sampled at 61 points: two cubics between the
        // given end tangents (+y at the start, −x at the end), G¹ inside.
        let pts: Vec<Point> = (0..=60)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64 / 60.0;
                Point::new(a.cos(), a.sin())
            })
            .collect();
        let ends = ChainEnds {
            start: Start::G1 {
                leg: Point::new(0.0, 1.0),
            },
            end: End::G1 {
                dir: Point::new(-1.0, 0.0),
            },
        };
        let options = FitOptions::new(super::super::FunctionType::Cubic, Continuity::G1);
        let fit = fit_between(&pts, &[0, 30], ends, &options, &mut LmSolver::default()).unwrap();
        assert_eq!(fit.breaks(), vec![0, 30]);
        assert!(fit.joins_hold(1e-9));
        let (first, last) = (&fit.segments[0], &fit.segments[1]);
        assert_eq!(first.join, Continuity::G1);
        assert_eq!(last.end, ends.end);
        let d0 = first.segment.deriv(0.0);
        let d1 = last.segment.deriv(1.0);
        assert!(d0.x.abs() < 1e-12 && d0.y > 0.0, "{d0:?}");
        assert!(d1.y.abs() < 1e-12 && d1.x < 0.0, "{d1:?}");
        assert!(fit.metrics.max_distance < 1e-3);
        // A quadratic cannot be joined C¹ at both ends: the given end fails
        // instead of being left free.
        let quadratic = FitOptions::new(super::super::FunctionType::Quadratic, Continuity::C1);
        let both = ChainEnds {
            start: Start::C1 {
                derivative: Point::new(0.0, 1.0),
            },
            end: End::C1 {
                derivative: Point::new(-1.0, 0.0),
            },
        };
        let e = fit_between(&pts, &[], both, &quadratic, &mut LmSolver::default()).unwrap_err();
        assert!(
            matches!(e, FitError::InvalidOption { name: "end", .. }),
            "{e:?}"
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
