//! Solvers of one segment problem: any metaheuristic, Levenberg–Marquardt,
//! or a metaheuristic followed by an LM polish.
//!
//! A [`SegmentSolver`] only sees a [`SegmentProblem`] and a budget; the
//! piecewise fit does not know which algorithm it is driving.

use super::{linear_fit, ErrorMeasure, SegmentProblem};
use crate::optim::lm::{LeastSquares, LevenbergMarquardt, LmOutcome, Termination};
use crate::optim::{Runs, TracePoint};
use crate::problem::{Bounds, Problem};

/// One stage of a solve (a hybrid has two).
#[derive(Clone, Debug, PartialEq)]
pub struct SolvePart {
    /// What ran (`"metaheuristic"`, `"lm"`, …).
    pub name: String,
    /// The best `E` after this stage.
    pub value: f64,
    /// Evaluations this stage used.
    pub evaluations: u64,
}

/// The result of solving one segment problem.
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// The best decision vector.
    pub x: Vec<f64>,
    /// Its objective `E`.
    pub value: f64,
    /// Evaluations used in all (never more than the budget given).
    pub evaluations: u64,
    /// The stages, in order.
    pub parts: Vec<SolvePart>,
    /// The best-so-far `E` against evaluations: a metaheuristic's at
    /// log-spaced checkpoints (10 per decade) and its last evaluation;
    /// Levenberg–Marquardt's at its first evaluation (the start) and its
    /// last; a hybrid's global stage, then the polish's end.
    pub trace: Vec<TracePoint>,
    /// The data parameters `value` was measured at, where the solver chose
    /// them (the orthogonal LM, whose projections start from an earlier
    /// curve's foot points); `None`: the problem's own, or under the
    /// orthogonal error the foot points found from them.
    pub params: Option<Vec<f64>>,
}

impl Solution {
    /// The solution of a problem without variables: `E` of the only curve
    /// there is, for one evaluation (none if the budget is 0).
    pub fn fixed(problem: &SegmentProblem, budget: u64) -> Solution {
        let (value, evaluations) = if budget > 0 {
            (problem.objective(&[]), 1)
        } else {
            (f64::INFINITY, 0)
        };
        Solution {
            x: Vec::new(),
            value,
            evaluations,
            parts: vec![SolvePart {
                name: "determined".into(),
                value,
                evaluations,
            }],
            trace: end_trace(evaluations, value),
            params: None,
        }
    }
}

/// Minimises a segment problem within a budget of objective evaluations.
pub trait SegmentSolver {
    /// Solves `problem` with at most `budget` evaluations.
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution;

    /// Solves `problem` as a trial of a search that only asks whether the
    /// fit is within a tolerance ([`crate::fit::SplitOptions::coarse`]):
    /// allowed to stop earlier than [`SegmentSolver::solve`]. Default: the
    /// full solve; [`LmSolver`] stops its orthogonal stage once a step
    /// gains less than [`COARSE_REDUCTION`] of `E`.
    fn solve_coarse(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        self.solve(problem, budget)
    }
}

impl<S: SegmentSolver + ?Sized> SegmentSolver for &mut S {
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        (**self).solve(problem, budget)
    }

    fn solve_coarse(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        (**self).solve_coarse(problem, budget)
    }
}

impl<S: SegmentSolver + ?Sized> SegmentSolver for Box<S> {
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        (**self).solve(problem, budget)
    }

    fn solve_coarse(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        (**self).solve_coarse(problem, budget)
    }
}

/// Any [`crate::optim::Optimiser`] or [`crate::optim::Algorithm`] as a segment solver, drawing from its own generator
/// (successive segments continue the same random stream, so a piecewise fit
/// is reproducible from one seed).
#[derive(Clone, Debug)]
pub struct OptimiserSolver<O, R> {
    /// The optimiser.
    pub optimiser: O,
    /// Its random generator.
    pub rng: R,
    /// The name reported in [`SolvePart::name`]; default `"metaheuristic"`.
    pub label: String,
}

impl<O, R> OptimiserSolver<O, R> {
    /// The solver running `optimiser` with `rng`.
    pub fn new(optimiser: O, rng: R) -> Self {
        Self {
            optimiser,
            rng,
            label: "metaheuristic".into(),
        }
    }

    /// The same with the stage name `label`.
    pub fn with_label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }
}

impl<O: Runs<SegmentProblem, R>, R> SegmentSolver for OptimiserSolver<O, R> {
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        if problem.dim() == 0 {
            return Solution::fixed(problem, budget);
        }
        let out = self.optimiser.run_on(problem, budget, &mut self.rng);
        Solution {
            value: out.best_value,
            evaluations: out.evaluations,
            parts: vec![SolvePart {
                name: self.label.clone(),
                value: out.best_value,
                evaluations: out.evaluations,
            }],
            x: out.best_x,
            trace: out.trace,
            params: None,
        }
    }
}

/// Where Levenberg–Marquardt starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LmStart {
    /// From [`linear_fit`] (unit weights), clipped into the box.
    #[default]
    LinearFit,
    /// From the centre of the search space, [`SegmentProblem::guess`].
    Guess,
}

/// Levenberg–Marquardt ([`LevenbergMarquardt`]) as a segment solver, the
/// exact reference.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LmSolver {
    /// The LM settings.
    pub lm: LevenbergMarquardt,
    /// The starting point.
    pub start: LmStart,
}

impl LmSolver {
    /// LM with default settings from `start`.
    pub fn new(start: LmStart) -> Self {
        Self {
            lm: LevenbergMarquardt::default(),
            start,
        }
    }
}

impl SegmentSolver for LmSolver {
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        self.solve_stopping(problem, budget, FULL_REDUCTION)
    }

    fn solve_coarse(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        self.solve_stopping(problem, budget, COARSE_REDUCTION)
    }
}

/// The orthogonal stage of [`LmSolver::solve`] stops once a step gains
/// less than this fraction of `E` (see [`orthogonal_lm`]).
const FULL_REDUCTION: f64 = 1e-6;

/// The orthogonal stage of [`LmSolver`]'s [`SegmentSolver::solve_coarse`]
/// stops once a step gains less than this fraction of `E`: 3·10⁻³ (the
/// function-value test of Moré 1978, as the full solve's 10⁻⁶). A trial
/// of a tolerance search only needs to know whether the curve can come
/// within the tolerance, and the joint solve polishes the chain kept; the
/// full solve's orthogonal stage creeps along near-reparameterisations of
/// curves that cannot fit (on the horse at 1.94 px up to 1,834 evaluations
/// for one rejected trial of 323 points). Of 10⁻³, 2·10⁻³, 3·10⁻³, 5·10⁻³
/// and 10⁻² on the peer-potrace inputs, 10⁻² cost DejaVu Sans S two
/// segments more than full trials and the others the logo at 8.49 px one;
/// 3·10⁻³ took the fewest segments over all.
pub const COARSE_REDUCTION: f64 = 3e-3;

impl LmSolver {
    /// [`SegmentSolver::solve`], the orthogonal stage stopping at the
    /// relative gain `reduction` (Moré 1978's function-value test).
    fn solve_stopping(&self, problem: &SegmentProblem, budget: u64, reduction: f64) -> Solution {
        if problem.dim() == 0 {
            return Solution::fixed(problem, budget);
        }
        let x0 = match self.start {
            LmStart::LinearFit => linear_fit(problem),
            LmStart::Guess => problem.guess().to_vec(),
        };
        let local = Local::of(problem);
        let (out, params) = if problem.error() == ErrorMeasure::Orthogonal {
            let (out, params) = orthogonal_lm(&self.lm, problem, &x0, budget, reduction);
            (out, Some(params))
        } else {
            (self.lm.minimise(&local, &x0, budget), None)
        };
        Solution {
            value: out.value,
            evaluations: out.evaluations,
            parts: vec![SolvePart {
                name: "lm".into(),
                value: out.value,
                evaluations: out.evaluations,
            }],
            trace: lm_trace(&local, &x0, out.evaluations, out.value),
            x: out.x,
            params,
        }
    }
}

/// Levenberg–Marquardt on the orthogonal error, started well: first LM on
/// the fixed-parameter E from `x0` (at most half the budget; the
/// orthogonal error is non-convex far from the data), then the orthogonal
/// LM from there, its projections started at that curve's foot points
/// (about half the Newton steps of starting from the parameterisation's),
/// stopping once a step gains less than 10⁻⁶ of E: it would otherwise creep
/// along the flat valleys of near-reparameterisations (on the horse at 101
/// segments the test costs 0.02 % of E and saves a third of the
/// evaluations), while a curve the family holds converges quadratically and
/// is not stopped early. [`SegmentSolver::solve_coarse`] stops at a gain
/// of `reduction` = [`COARSE_REDUCTION`] instead. Returns the outcome and
/// the parameters its E was measured at.
fn orthogonal_lm(
    lm: &LevenbergMarquardt,
    problem: &SegmentProblem,
    x0: &[f64],
    budget: u64,
    reduction: f64,
) -> (LmOutcome, Vec<f64>) {
    let fixed = problem.clone().with_error(ErrorMeasure::Fixed);
    let first = lm.minimise(&Local::of(&fixed), x0, budget / 2);
    let started = problem
        .with_params(problem.measured_params(&first.x))
        .expect("as many parameters as points");
    let mut lm = lm.clone();
    lm.reduction_tol = lm.reduction_tol.max(reduction);
    let mut out = lm.minimise(&Local::of(&started), &first.x, budget - first.evaluations);
    out.evaluations += first.evaluations;
    let params = started.measured_params(&out.x);
    (out, params)
}

/// A metaheuristic on a share of the budget, then Levenberg–Marquardt from
/// its best point with the rest; both stages are reported.
#[derive(Clone, Debug)]
pub struct HybridSolver<O, R> {
    /// The global stage.
    pub global: OptimiserSolver<O, R>,
    /// The local polish.
    pub lm: LevenbergMarquardt,
    /// The share of the budget for the global stage, in `[0, 1]`; default 0.8.
    pub global_share: f64,
}

impl<O, R> HybridSolver<O, R> {
    /// `optimiser` on 80% of the budget, then LM.
    pub fn new(optimiser: O, rng: R) -> Self {
        Self {
            global: OptimiserSolver::new(optimiser, rng),
            lm: LevenbergMarquardt::default(),
            global_share: 0.8,
        }
    }
}

impl<O: Runs<SegmentProblem, R>, R> SegmentSolver for HybridSolver<O, R> {
    fn solve(&mut self, problem: &SegmentProblem, budget: u64) -> Solution {
        if problem.dim() == 0 {
            return Solution::fixed(problem, budget);
        }
        let share = self.global_share.clamp(0.0, 1.0);
        let first = ((budget as f64 * share).round() as u64).min(budget);
        let global = self.global.solve(problem, first);
        let rest = budget - global.evaluations;
        let x0 = if global.x.iter().all(|v| v.is_finite()) && global.evaluations > 0 {
            global.x.clone()
        } else {
            linear_fit(problem)
        };
        let polish = self.lm.minimise(&Local::of(problem), &x0, rest);
        let mut parts = global.parts.clone();
        parts.push(SolvePart {
            name: "lm".into(),
            value: polish.value,
            evaluations: polish.evaluations,
        });
        let (x, value) =
            if polish.value <= global.value || polish.termination == Termination::NoVariables {
                (polish.x, polish.value)
            } else {
                (global.x, global.value)
            };
        let evaluations = global.evaluations + polish.evaluations;
        let mut trace = global.trace;
        if polish.evaluations > 0 {
            trace.push(TracePoint {
                evaluations,
                best: value,
            });
        }
        Solution {
            x,
            value,
            evaluations,
            parts,
            trace,
            params: None,
        }
    }
}

/// The one-point trace of a solve that ends at `evaluations` with `value`
/// (none for no evaluation).
fn end_trace(evaluations: u64, value: f64) -> Vec<TracePoint> {
    if evaluations == 0 {
        return Vec::new();
    }
    vec![TracePoint {
        evaluations,
        best: value,
    }]
}

/// Levenberg–Marquardt's trace: `E(x₀)` after its first evaluation (the
/// residuals at the start, clipped into the box as LM does), then its end.
fn lm_trace(problem: &Local<'_>, x0: &[f64], evaluations: u64, value: f64) -> Vec<TracePoint> {
    if evaluations == 0 {
        return Vec::new();
    }
    let start: Vec<f64> = x0
        .iter()
        .zip(problem.bounds())
        .map(|(&v, b)| b.clip(v))
        .collect();
    let first = crate::optim::evaluator::sanitise(problem.objective(&start)).max(value);
    let mut trace = vec![TracePoint {
        evaluations: 1,
        best: first,
    }];
    if evaluations > 1 {
        trace.push(TracePoint {
            evaluations,
            best: value,
        });
    }
    trace
}

/// A segment problem as Levenberg–Marquardt sees it: the same residuals in
/// the local box ([`SegmentProblem::local_bounds`]).
struct Local<'p> {
    problem: &'p SegmentProblem,
    bounds: Vec<Bounds>,
}

impl<'p> Local<'p> {
    fn of(problem: &'p SegmentProblem) -> Local<'p> {
        Local {
            problem,
            bounds: problem.local_bounds(),
        }
    }
}

impl Problem for Local<'_> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        self.problem.objective(x)
    }
}

impl LeastSquares for Local<'_> {
    fn residual_count(&self) -> usize {
        LeastSquares::residual_count(self.problem)
    }

    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        SegmentProblem::residuals(self.problem, x, out)
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> bool {
        SegmentProblem::jacobian(self.problem, x, jac);
        true
    }
}
