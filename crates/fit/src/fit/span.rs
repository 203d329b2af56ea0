//! One segment of a piecewise fit: its data span on the outline, its joins,
//! and the solve that fits it.
//!
//! A span with fewer data points than its function needs
//! ([`FunctionType::min_points`]) is not refused: points are inserted at
//! the midpoints of its longest gaps (more samples of the outline polyline
//! between its data points) until it has enough, so that the problem is
//! determined. The inserted points guide the solve only; the segment's
//! metrics are measured on its data points.

use super::metrics::{segment_metrics, SegmentMetrics};
use super::{
    End, ErrorMeasure, FitError, FitOptions, Segment, SegmentProblem, SegmentSolver, Solution,
    Start,
};
use crate::geometry::{Continuity, Curve, Point};
use crate::optim::TracePoint;
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
    /// The join imposed at its end: [`End::Free`] except for the last
    /// segment of a smoothly closed chain, which joins the first segment's
    /// start.
    pub end: End,
    /// The decision vector found; after a joint solve
    /// ([`crate::fit::Chain::Joint`]), the values of the chain's variables
    /// this segment depends on.
    pub x: Vec<f64>,
    /// The local parameters `sᵢ` of its data points, the error was measured
    /// at (after any parameter correction).
    pub params: Vec<f64>,
    /// Points inserted into a span too short for its function (0 usually).
    pub inserted: usize,
    /// What the solver reported (with parameter correction, the last solve;
    /// `evaluations` counts all of them).
    pub solution: Solution,
    /// The best-so-far `E` against the evaluations spent on this segment
    /// (with parameter correction, each round's trace after the previous
    /// rounds' evaluations).
    pub trace: Vec<TracePoint>,
    /// Its error, distances and cost.
    pub metrics: SegmentMetrics,
}

/// The outline and how to read a segment's data from it.
pub(super) struct Outline<'a> {
    pub(super) points: &'a [Point],
    pub(super) closed: bool,
}

impl Outline<'_> {
    /// The outline of `points`, checked: enough points for `function_min`
    /// (one fewer when closed), all finite.
    pub(super) fn new(
        points: &[Point],
        closed: bool,
        function_min: usize,
    ) -> Result<Outline<'_>, FitError> {
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

    pub(super) fn len(&self) -> usize {
        self.points.len()
    }

    /// The points `first..=last` (`last ≥ first`, possibly `≥ len` for a
    /// wrap on a closed outline).
    pub(super) fn gather(&self, first: usize, last: usize) -> Vec<Point> {
        (first..=last)
            .map(|i| self.points[i % self.len()])
            .collect()
    }

    /// Cumulative chord length from `first` over `first..=last`.
    pub(super) fn cumulative(&self, first: usize, last: usize) -> Vec<f64> {
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
    pub(super) fn spans(&self, breaks: &[usize]) -> Result<Vec<(usize, usize)>, FitError> {
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

/// What one segment's fit is asked for: its span and its joins.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Piece {
    /// Outline index of the first data point.
    pub first: usize,
    /// Outline index of the last one (`≥ first`, `≥ len` for a wrap).
    pub last: usize,
    /// The continuity at its start.
    pub join: Continuity,
    /// How it starts (from the previous segment and `join`).
    pub start: Start,
    /// How it ends.
    pub end: End,
    /// Whether the end join must hold (a given end of an open chain,
    /// [`super::ChainEnds`]): a join the function cannot hold fails the fit
    /// instead of leaving the end free, as a closing joint's does.
    pub hold_end: bool,
    /// Whether the solve may stop early ([`SegmentSolver::solve_coarse`]):
    /// a trial of the tolerance search ([`super::SplitOptions::coarse`]).
    pub coarse: bool,
}

/// `points` with midpoints inserted into the longest gaps (the first of
/// equal ones) until there are `needed`, and the positions of the original
/// points; `None` when nothing had to be inserted.
pub fn densify(points: Vec<Point>, needed: usize) -> (Vec<Point>, Option<Vec<usize>>) {
    if points.len() >= needed || points.len() < 2 {
        return (points, None);
    }
    let mut pts = points;
    let mut original = vec![true; pts.len()];
    while pts.len() < needed {
        let mut k = 0;
        for i in 1..pts.len() - 1 {
            if pts[i].distance(pts[i + 1]) > pts[k].distance(pts[k + 1]) {
                k = i;
            }
        }
        let mid = pts[k].lerp(pts[k + 1], 0.5);
        pts.insert(k + 1, mid);
        original.insert(k + 1, false);
    }
    let index = original
        .iter()
        .enumerate()
        .filter_map(|(i, &o)| o.then_some(i))
        .collect();
    (pts, Some(index))
}

/// The problem of `piece`: its data (densified if short), the start join,
/// and the end join when the function admits it (else the end is free).
fn piece_problem(
    outline: &Outline<'_>,
    piece: &Piece,
    options: &FitOptions,
) -> Result<(SegmentProblem, Option<Vec<usize>>, End), FitError> {
    let (pts, original) = densify(
        outline.gather(piece.first, piece.last),
        options.function.min_points(),
    );
    let problem = SegmentProblem::with_parameterisation(
        options.function,
        pts,
        options.parameterisation,
        piece.start,
        &options.search,
    )?
    .with_error(options.error);
    if piece.end == End::Free {
        return Ok((problem, original, End::Free));
    }
    if piece.hold_end {
        return Ok((problem.with_end(piece.end)?, original, piece.end));
    }
    Ok(match problem.clone().with_end(piece.end) {
        Ok(joined) => (joined, original, piece.end),
        // A quadratic joined C¹ at both ends, or G¹ with tangent lines that
        // do not meet in front: the end stays free (the closing joint C⁰).
        Err(_) => (problem, original, End::Free),
    })
}

/// Solves `problem` with the solver (coarsely if `coarse`), or without one
/// when nothing is free.
fn solve<S: SegmentSolver + ?Sized>(
    problem: &SegmentProblem,
    solver: &mut S,
    budget: u64,
    coarse: bool,
) -> Solution {
    if problem.dim() == 0 {
        // Fully determined (a quadratic with a C¹ join): no optimiser.
        Solution::fixed(problem, budget)
    } else if coarse {
        solver.solve_coarse(problem, budget)
    } else {
        solver.solve(problem, budget)
    }
}

/// Fits one segment as `piece` says, with parameter correction rounds.
pub(super) fn fit_one<S: SegmentSolver + ?Sized>(
    outline: &Outline<'_>,
    piece: Piece,
    options: &FitOptions,
    solver: &mut S,
) -> Result<FittedSegment, FitError> {
    let (mut problem, original, end) = piece_problem(outline, &piece, options)?;
    let budget = options.budget_per_segment;
    let mut solution = solve(&problem, solver, budget, piece.coarse);
    let mut trace = solution.trace.clone();
    let mut spent = solution.evaluations;
    for _ in 0..options.reparameterise {
        let seg = problem.segment(&solution.x);
        let params = match (options.error, solution.params.take()) {
            (ErrorMeasure::Fixed, _) => problem.corrected_params(&seg),
            // The foot points start the next round's projections.
            (ErrorMeasure::Orthogonal, Some(params)) => params,
            (ErrorMeasure::Orthogonal, None) => problem.measured_params(&solution.x),
        };
        problem = problem.with_params(params)?;
        solution = solve(&problem, solver, budget, piece.coarse);
        trace.extend(solution.trace.iter().map(|p| TracePoint {
            evaluations: p.evaluations + spent,
            best: p.best,
        }));
        spent += solution.evaluations;
    }
    solution.evaluations = spent;
    if options.error == ErrorMeasure::Orthogonal {
        // The parameters the solution's E was measured at: its foot points.
        let params = match solution.params.take() {
            Some(params) => params,
            None => problem.measured_params(&solution.x),
        };
        problem = problem.with_params(params)?;
    }
    let segment = problem.segment(&solution.x);
    let (points, params, inserted) = match &original {
        None => (problem.points().to_vec(), problem.params().to_vec(), 0),
        Some(index) => (
            index.iter().map(|&i| problem.points()[i]).collect(),
            index.iter().map(|&i| problem.params()[i]).collect(),
            problem.points().len() - index.len(),
        ),
    };
    let metrics = segment_metrics(&segment, &points, &params, spent);
    Ok(FittedSegment {
        segment,
        first: piece.first % outline.len(),
        last: piece.last % outline.len(),
        join: piece.join,
        end,
        x: solution.x.clone(),
        params,
        inserted,
        solution,
        trace,
        metrics,
    })
}

/// How far beyond its data's own largest distance a segment's curve may run
/// from the outline polyline (beyond the staircase's allowance) before
/// [`fit_guarded`] calls it a whisker and tries the fixed-parameter error.
pub(super) const WHISKER_RATIO: f64 = 1.5;

/// Whether `fit` leaves the outline where its data does not: its two-sided
/// distance beyond the staircase ([`SegmentMetrics::excess`]) more than
/// [`WHISKER_RATIO`] times its data points' largest distance, and more
/// than rounding (10⁻⁹ of its chord).
pub(super) fn strays(fit: &FittedSegment) -> bool {
    let m = &fit.metrics;
    let chord = fit.segment.start().distance(fit.segment.end());
    m.excess > WHISKER_RATIO * m.max_distance && m.excess > 1e-9 * chord.max(1.0)
}

/// [`fit_one`], guarded against whiskers: under the orthogonal error a
/// rational segment can park curve past a corner or loop out between its
/// data points, every data point still on it ([`strays`]). The
/// fixed-parameter error spreads the curve along its data at their
/// parameters and cannot do that; where the orthogonal fit strays, the
/// segment is fitted again with it and the one whose two-sided distance
/// beyond the staircase is smaller is kept. Returns the segment and the
/// evaluations of the fit not kept (0 when there was none).
pub(super) fn fit_guarded<S: SegmentSolver + ?Sized>(
    outline: &Outline<'_>,
    piece: Piece,
    options: &FitOptions,
    solver: &mut S,
) -> Result<(FittedSegment, u64), FitError> {
    let fit = fit_one(outline, piece, options, solver)?;
    if options.error != ErrorMeasure::Orthogonal || !strays(&fit) {
        return Ok((fit, 0));
    }
    let fixed = FitOptions {
        error: ErrorMeasure::Fixed,
        ..*options
    };
    let other = fit_one(outline, piece, &fixed, solver)?;
    Ok(if other.metrics.excess < fit.metrics.excess {
        let spent = fit.metrics.evaluations;
        (other, spent)
    } else {
        let spent = other.metrics.evaluations;
        (fit, spent)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_spans_get_midpoints_in_their_longest_gaps() {
        let pts = vec![Point::ZERO, Point::new(1.0, 0.0), Point::new(4.0, 0.0)];
        let (d, index) = densify(pts.clone(), 5);
        assert_eq!(
            d,
            [0.0, 1.0, 1.75, 2.5, 4.0]
                .map(|x| Point::new(x, 0.0))
                .to_vec()
        );
        assert_eq!(index, Some(vec![0, 1, 4]));
        let (same, none) = densify(pts.clone(), 3);
        assert_eq!((same, none), (pts, None));
    }
}
