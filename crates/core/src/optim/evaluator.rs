//! The evaluation budget: counts objective evaluations, keeps the best-so-far
//! and records the convergence trace.
//!
//! This is the "executor" of the argmin split: an optimiser asks the
//! [`Evaluator`] for every objective value, so budgets are counted in
//! evaluations for every algorithm alike, and the trace is recorded the same
//! way for all of them.

use super::interrupt;
use crate::problem::{Bounds, Problem};

/// The best-so-far value after a given number of evaluations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TracePoint {
    /// Evaluations used so far.
    pub evaluations: u64,
    /// The smallest objective value seen in those evaluations.
    pub best: f64,
}

/// The first evaluation at which a run's best value came within a target
/// precision of `f*` (`f ≤ f* + Δf`), as COCO records runtimes
/// (Hansen et al. 2021, "COCO: a platform for comparing continuous
/// optimizers in a black-box setting", Optim. Methods Softw. 36(1)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetHit {
    /// The target precision `Δf`.
    pub precision: f64,
    /// The first evaluation count with `f − f* ≤ Δf`.
    pub evaluations: u64,
}

/// What an optimiser run produced.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The best decision vector found.
    pub best_x: Vec<f64>,
    /// Its objective value (`+∞` if no finite value was ever seen).
    pub best_value: f64,
    /// Objective evaluations used (never more than the budget).
    pub evaluations: u64,
    /// The first evaluation count at which the best value reached the
    /// target, if a target was set and reached.
    pub evaluations_to_target: Option<u64>,
    /// Best-so-far at the checkpoints (log-spaced by default), ending at the
    /// last evaluation.
    pub trace: Vec<TracePoint>,
    /// The first evaluation at which each target precision was reached, in
    /// the order of the targets (see [`Evaluator::with_targets`]).
    pub hits: Vec<TargetHit>,
}

/// Log-spaced evaluation counts `round(10^(k/per_decade))`, deduplicated, up
/// to and including `budget`; the convergence checkpoints of a run.
pub fn log_checkpoints(budget: u64, per_decade: u32) -> Vec<u64> {
    let mut out: Vec<u64> = Vec::new();
    let per_decade = per_decade.max(1);
    let mut k = 0u32;
    loop {
        let e = 10f64.powf(f64::from(k) / f64::from(per_decade)).round() as u64;
        if e >= budget {
            break;
        }
        if out.last() != Some(&e) {
            out.push(e);
        }
        k += 1;
    }
    if budget > 0 {
        out.push(budget);
    }
    out
}

/// Maps a NaN to `+∞`, so that a NaN objective ranks worse than any finite
/// value under `<` and never wins a comparison.
#[inline]
pub fn sanitise(value: f64) -> f64 {
    if value.is_nan() {
        f64::INFINITY
    } else {
        value
    }
}

/// Why a run ended before its budget was spent ([`Evaluator::ended_early`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EarlyEnd {
    /// The best value reached the target and the run was asked to stop
    /// there ([`Evaluator::stop_at_target`]), as COCO's experiments stop at
    /// their final target.
    Target,
    /// The observer asked for the end ([`Evaluator::with_observer`]).
    Observer,
    /// A host asked every run to end ([`interrupt::request`]).
    Interrupt,
}

/// What an observer of a run sees at each checkpoint: the evaluations so
/// far, the best value and its point; it returns `false` to end the run.
pub type Observer = Box<dyn FnMut(u64, f64, &[f64]) -> bool>;

/// Counts evaluations against a budget, tracks the best-so-far and records
/// the trace. Optimisers call [`Evaluator::evaluate`] for every objective
/// value and stop when [`Evaluator::remaining`] is zero.
///
/// ```
/// use metabezier_core::functions::{Function, TestProblem};
/// use metabezier_core::optim::Evaluator;
///
/// let sphere = TestProblem::new(Function::Sphere, 2).unwrap();
/// let mut eval = Evaluator::new(&sphere, 3).with_target(0.5);
/// eval.evaluate(&[1.0, 1.0]);
/// eval.evaluate(&[0.5, 0.0]);
/// assert_eq!(eval.remaining(), 1);
/// let out = eval.finish();
/// assert_eq!((out.best_value, out.evaluations_to_target), (0.25, Some(2)));
/// ```
pub struct Evaluator<'p, P: Problem + ?Sized> {
    problem: &'p P,
    budget: u64,
    /// Where the run ends: the budget, or the evaluation at which an
    /// interrupt was seen ([`interrupt::requested`]).
    end: u64,
    used: u64,
    best_value: f64,
    best_x: Vec<f64>,
    target: f64,
    hit: Option<u64>,
    checkpoints: Vec<u64>,
    next_checkpoint: usize,
    trace: Vec<TracePoint>,
    f_star: f64,
    precisions: Vec<f64>,
    next_precision: usize,
    hits: Vec<TargetHit>,
    start: Option<Vec<f64>>,
    stop_at_target: bool,
    observer: Option<Observer>,
    early: Option<EarlyEnd>,
}

impl<'p, P: Problem + ?Sized> Evaluator<'p, P> {
    /// An evaluator for `problem` allowing `budget` evaluations, with
    /// log-spaced checkpoints (10 per decade) and no target.
    pub fn new(problem: &'p P, budget: u64) -> Self {
        let dim = problem.dim();
        Self {
            problem,
            budget,
            end: budget,
            used: 0,
            best_value: f64::INFINITY,
            best_x: vec![f64::NAN; dim],
            target: f64::NEG_INFINITY,
            hit: None,
            checkpoints: log_checkpoints(budget, 10),
            next_checkpoint: 0,
            trace: Vec::new(),
            f_star: 0.0,
            precisions: Vec::new(),
            next_precision: 0,
            hits: Vec::new(),
            start: None,
            stop_at_target: false,
            observer: None,
            early: None,
        }
    }

    /// Starts the run at `x0` (inside the bounds, `dim` values): the
    /// optimiser's first evaluated point is `x0` (the first member of an
    /// initial population or memory, as SciPy's `differential_evolution`
    /// places it, drawn after the same random numbers as without it, so the
    /// rest of the initial population is unchanged; CMA-ES's first mean, as
    /// pycma's `x0`, evaluated once before the first generation).
    pub fn with_start(mut self, x0: Vec<f64>) -> Self {
        debug_assert_eq!(x0.len(), self.problem.dim());
        self.start = Some(x0);
        self
    }

    /// Ends the run at the first evaluation whose value reaches the target
    /// of [`Evaluator::with_target`] (COCO's experiments stop at their final
    /// target; Hansen et al. 2021).
    pub fn stop_at_target(mut self) -> Self {
        self.stop_at_target = true;
        self
    }

    /// Calls `observer` at every checkpoint of the trace (log-spaced, 10 a
    /// decade by default, and the budget) with the evaluations, the best
    /// value and its point; `false` ends the run there, as SciPy's
    /// `callback` returning `True` does.
    pub fn with_observer(mut self, observer: Observer) -> Self {
        self.observer = Some(observer);
        self
    }

    /// The start point while nothing has been evaluated, else `None` (a
    /// restart draws its own).
    #[inline]
    pub fn start(&self) -> Option<&[f64]> {
        self.start.as_deref().filter(|_| self.used == 0)
    }

    /// Writes the start point over the first point of `points` (row-major,
    /// [`Evaluator::dim`] values a point) if nothing has been evaluated yet
    /// and `points` holds one; optimisers call it on the first points they
    /// draw.
    #[inline]
    pub fn place_start(&self, points: &mut [f64]) {
        if let (Some(s), Some(first)) = (self.start(), points.get_mut(..self.dim())) {
            first.copy_from_slice(s);
        }
    }

    /// Why the run ended before its budget, if it did.
    pub fn ended_early(&self) -> Option<EarlyEnd> {
        self.early
    }

    /// Ends the run at the current evaluation for `why` (the first reason
    /// is kept).
    fn end_early(&mut self, why: EarlyEnd) {
        self.end = self.end.min(self.used);
        self.early.get_or_insert(why);
    }

    /// Records the first evaluation at which the best value is within each
    /// of `precisions` (descending `Δf`) of `f_star`: the runtimes of
    /// COCO's anytime view, exact to the evaluation.
    pub fn with_targets(mut self, f_star: f64, precisions: Vec<f64>) -> Self {
        debug_assert!(precisions.windows(2).all(|w| w[0] >= w[1]));
        self.f_star = f_star;
        self.precisions = precisions;
        self
    }

    /// Records the first evaluation count at which the best value is `≤ target`
    /// (`f* + threshold` in a benchmark study).
    pub fn with_target(mut self, target: f64) -> Self {
        self.target = target;
        self
    }

    /// Replaces the checkpoints at which the best-so-far is recorded; they
    /// must be ascending. The final evaluation is always recorded too.
    pub fn with_checkpoints(mut self, mut checkpoints: Vec<u64>) -> Self {
        checkpoints.retain(|&c| c > 0 && c <= self.budget);
        checkpoints.dedup();
        self.checkpoints = checkpoints;
        self
    }

    /// The problem being minimised.
    #[inline]
    pub fn problem(&self) -> &'p P {
        self.problem
    }

    /// The problem's bounds.
    #[inline]
    pub fn bounds(&self) -> &'p [Bounds] {
        self.problem.bounds()
    }

    /// The problem's dimension.
    #[inline]
    pub fn dim(&self) -> usize {
        self.problem.dim()
    }

    /// The total budget in evaluations.
    #[inline]
    pub fn budget(&self) -> u64 {
        self.budget
    }

    /// Evaluations used so far.
    #[inline]
    pub fn used(&self) -> u64 {
        self.used
    }

    /// Evaluations left in the budget (none once an interrupt was seen).
    #[inline]
    pub fn remaining(&self) -> u64 {
        self.end.saturating_sub(self.used)
    }

    /// Whether the run was ended early by [`interrupt::request`]: its
    /// outcome is not a result.
    pub fn interrupted(&self) -> bool {
        self.early == Some(EarlyEnd::Interrupt)
    }

    /// The fraction of the budget used, `t/NI` in the thesis's notation.
    #[inline]
    pub fn progress(&self) -> f64 {
        if self.budget == 0 {
            1.0
        } else {
            self.used as f64 / self.budget as f64
        }
    }

    /// The best value seen so far.
    #[inline]
    pub fn best_value(&self) -> f64 {
        self.best_value
    }

    /// Evaluates `f(x)`, counts it, and returns the value with NaN mapped to
    /// `+∞`. Once the budget is spent it returns `+∞` without evaluating.
    #[inline]
    pub fn evaluate(&mut self, x: &[f64]) -> f64 {
        debug_assert_eq!(x.len(), self.problem.dim());
        if self.used >= self.end {
            return f64::INFINITY;
        }
        let value = sanitise(self.problem.objective(x));
        self.record(x, value)
    }

    /// Evaluates the rows of the row-major `xs` (`out.len()` points of
    /// [`Evaluator::dim`] variables) with [`Problem::objective_batch`], as
    /// many as the budget allows, and writes their values into `out` (`+∞`
    /// for rows past the budget). The counts, best-so-far, trace and target
    /// hits are exactly those of calling [`Evaluator::evaluate`] row by row.
    /// Returns the number of rows evaluated.
    pub fn evaluate_batch(&mut self, xs: &[f64], out: &mut [f64]) -> usize {
        let dim = self.problem.dim();
        debug_assert_eq!(xs.len(), out.len() * dim);
        let n = out
            .len()
            .min(usize::try_from(self.remaining()).unwrap_or(usize::MAX));
        self.problem.objective_batch(&xs[..n * dim], &mut out[..n]);
        for (i, o) in out.iter_mut().enumerate() {
            *o = if i < n {
                self.record(&xs[i * dim..(i + 1) * dim], sanitise(*o))
            } else {
                f64::INFINITY
            };
        }
        n
    }

    /// Counts one evaluation of `x` with (sanitised) `value` and updates the
    /// best-so-far, the target hits and the trace.
    #[inline]
    fn record(&mut self, x: &[f64], value: f64) -> f64 {
        self.used += 1;
        if self.used & (interrupt::POLL_EVALUATIONS - 1) == 0 && interrupt::requested() {
            self.end_early(EarlyEnd::Interrupt);
        }
        if value < self.best_value {
            self.best_value = value;
            self.best_x.copy_from_slice(x);
            if self.hit.is_none() && value <= self.target {
                self.hit = Some(self.used);
                if self.stop_at_target {
                    self.end_early(EarlyEnd::Target);
                }
            }
            while let Some(&p) = self.precisions.get(self.next_precision) {
                if value - self.f_star > p {
                    break;
                }
                self.hits.push(TargetHit {
                    precision: p,
                    evaluations: self.used,
                });
                self.next_precision += 1;
            }
        }
        if self.checkpoints.get(self.next_checkpoint) == Some(&self.used) {
            self.trace.push(TracePoint {
                evaluations: self.used,
                best: self.best_value,
            });
            self.next_checkpoint += 1;
            if let Some(observe) = self.observer.as_mut().filter(|_| self.early.is_none()) {
                if !observe(self.used, self.best_value, &self.best_x) {
                    self.end_early(EarlyEnd::Observer);
                }
            }
        }
        value
    }

    /// Ends the run and returns its [`Outcome`].
    pub fn finish(mut self) -> Outcome {
        if self.used > 0 && self.trace.last().map(|p| p.evaluations) != Some(self.used) {
            self.trace.push(TracePoint {
                evaluations: self.used,
                best: self.best_value,
            });
        }
        Outcome {
            best_x: self.best_x,
            best_value: self.best_value,
            evaluations: self.used,
            evaluations_to_target: self.hit,
            trace: self.trace,
            hits: self.hits,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Line;
    impl Problem for Line {
        fn dim(&self) -> usize {
            1
        }
        fn bounds(&self) -> &[Bounds] {
            const B: [Bounds; 1] = [Bounds::new(-1.0, 1.0)];
            &B
        }
        fn objective(&self, x: &[f64]) -> f64 {
            if x[0] == 0.5 {
                f64::NAN
            } else {
                x[0]
            }
        }
    }

    #[test]
    fn checkpoints_are_log_spaced_and_end_at_budget() {
        assert_eq!(log_checkpoints(10, 1), vec![1, 10]);
        assert_eq!(log_checkpoints(1000, 1), vec![1, 10, 100, 1000]);
        assert_eq!(log_checkpoints(3, 10), vec![1, 2, 3]);
        let c = log_checkpoints(100_000, 10);
        assert!(c.windows(2).all(|w| w[0] < w[1]));
        // 51 grid points 10^(k/10), k = 0..=50, less the three that round
        // onto their predecessor (1.26→1, 1.995→2, 3.16→3).
        assert_eq!(c.len(), 48);
        assert_eq!(log_checkpoints(0, 10), Vec::<u64>::new());
    }

    #[test]
    fn counts_budget_tracks_best_and_target() {
        let mut ev = Evaluator::new(&Line, 4).with_target(-0.5);
        assert_eq!(ev.evaluate(&[0.5]), f64::INFINITY, "NaN ranks worst");
        assert_eq!(ev.evaluate(&[0.2]), 0.2);
        assert_eq!(ev.evaluate(&[-0.7]), -0.7);
        assert_eq!(ev.evaluate(&[0.9]), 0.9);
        assert_eq!(ev.remaining(), 0);
        assert_eq!(
            ev.evaluate(&[-1.0]),
            f64::INFINITY,
            "no evaluation past the budget"
        );
        let out = ev.finish();
        assert_eq!(out.evaluations, 4);
        assert_eq!(out.best_value, -0.7);
        assert_eq!(out.best_x, vec![-0.7]);
        assert_eq!(out.evaluations_to_target, Some(3));
        let evals: Vec<u64> = out.trace.iter().map(|p| p.evaluations).collect();
        assert_eq!(evals, vec![1, 2, 3, 4]);
        assert_eq!(out.trace[0].best, f64::INFINITY);
        assert_eq!(out.trace[3].best, -0.7);
    }
}
