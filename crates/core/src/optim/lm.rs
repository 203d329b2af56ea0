//! Levenberg–Marquardt for box-bounded nonlinear least squares, the exact
//! (local, gradient-based) reference against which the metaheuristics are
//! measured.
//!
//! Minimises `E(x) = Σ_k r_k(x)²` for `x` in a box (Levenberg 1944, "A
//! method for the solution of certain non-linear problems in least squares",
//! Q. Appl. Math. 2:164–168; Marquardt 1963, "An algorithm for least-squares
//! estimation of nonlinear parameters", J. SIAM 11:431–441). The damping
//! update is the gain-ratio rule of Madsen, Nielsen & Tingleff (2004,
//! *Methods for Non-Linear Least Squares Problems*, 2nd ed., IMM DTU,
//! Algorithm 3.16); the damping term is Marquardt's diagonal scaling
//! `μ·diag(JᵀJ)`, so that variables of very different scales (control point
//! coordinates and rational weights) are damped alike. Bounds are handled by
//! projecting every trial point onto the box.
//!
//! Like the other optimisers it knows nothing of curves: a problem only
//! supplies residuals (and, optionally, their Jacobian) through
//! [`LeastSquares`].

use super::evaluator::sanitise;
use crate::linalg::{cholesky_solve, BandedArrow};
use crate::problem::{Bounds, Problem};

/// A box-bounded least-squares problem: minimise `E(x) = Σ_k r_k(x)²`.
///
/// The [`Problem`] supertrait gives the dimension, the bounds and the
/// objective, which must equal `Σ r_k²` (it is what the metaheuristics
/// minimise, so both kinds of solver optimise the same function).
pub trait LeastSquares: Problem {
    /// The number of residuals `m`.
    fn residual_count(&self) -> usize;

    /// Writes the residuals `r_k(x)`, `k = 0..m`, into `out` (`out.len() == m`).
    fn residuals(&self, x: &[f64], out: &mut [f64]);

    /// Writes the Jacobian `J_{kj} = ∂r_k/∂x_j` row-major (`m` rows of
    /// `dim` columns) into `jac` and returns `true`, or returns `false` if
    /// the problem has no analytic Jacobian, in which case the solver uses
    /// forward differences. The default has none.
    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> bool {
        let _ = (x, jac);
        false
    }

    /// The structure of `JᵀJ` for a problem that assembles its normal
    /// equations itself ([`LeastSquares::normal_equations`]): the
    /// half-bandwidth and the border of a [`BandedArrow`]. `None`, the
    /// default, means a dense `JᵀJ` formed from [`LeastSquares::jacobian`].
    /// A chain of curve segments has a banded `JᵀJ`, so its steps cost
    /// `O(n b²)` instead of `O(n³)` and no `m × n` Jacobian is stored.
    fn normal_structure(&self) -> Option<(usize, usize)> {
        None
    }

    /// Adds `JᵀJ` into `a` and `Jᵀr` into `g` at `x`, whose residuals are
    /// `r` (both zeroed by the caller); called, in place of
    /// [`LeastSquares::jacobian`], exactly when
    /// [`LeastSquares::normal_structure`] is `Some`, and costs `dim`
    /// evaluations like a Jacobian. A problem that declares a structure
    /// must implement it; the default panics.
    fn normal_equations(&self, x: &[f64], r: &[f64], a: &mut BandedArrow, g: &mut [f64]) {
        let _ = (x, r, a, g);
        panic!("a problem with a normal_structure must assemble its normal_equations");
    }
}

/// Why a Levenberg–Marquardt run stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Termination {
    /// The projected gradient `‖P(Jᵀr)‖∞` fell below `gradient_tol`.
    Gradient,
    /// The step `‖h‖` fell below `step_tol·(‖x‖ + step_tol)`.
    Step,
    /// `E` fell below `value_tol`.
    Value,
    /// An accepted step lowered `E` by at most `reduction_tol·E`.
    Reduction,
    /// The evaluation budget is spent (or too small for another iteration).
    Budget,
    /// `max_iterations` iterations were made.
    Iterations,
    /// The problem has no variables; `x` is the empty vector.
    NoVariables,
}

/// The result of a Levenberg–Marquardt run.
#[derive(Clone, Debug, PartialEq)]
pub struct LmOutcome {
    /// The best point found (inside the bounds).
    pub x: Vec<f64>,
    /// `E(x) = Σ r_k²` at [`LmOutcome::x`].
    pub value: f64,
    /// Evaluations used: one per residual vector, plus `dim` per Jacobian
    /// (see [`LevenbergMarquardt`]).
    pub evaluations: u64,
    /// Iterations (Jacobians computed).
    pub iterations: u64,
    /// Why the run stopped.
    pub termination: Termination,
}

/// Box-constrained Levenberg–Marquardt with Marquardt's scaling and the
/// damping update of Madsen, Nielsen & Tingleff (2004, Alg. 3.16).
///
/// Each iteration solves `(JᵀJ + μ D) h = −Jᵀr` with
/// `D = diag(max(JᵀJ_jj, 10⁻¹²·max_j JᵀJ_jj))` by Cholesky, projects
/// `x + h` onto the box, and accepts the step when the gain ratio
/// `ϱ = (F(x) − F(x_new)) / (L(0) − L(h_p))` (`F = ½E`, `L` the linear model,
/// `h_p` the projected step) is positive; then `μ ← μ·max(⅓, 1 − (2ϱ − 1)³)`,
/// `ν ← 2`, else `μ ← μν`, `ν ← 2ν`. The first `μ` is `tau`.
///
/// **Budget accounting**, for fairness with the metaheuristics: every
/// residual vector costs one evaluation, and every Jacobian costs `dim`
/// evaluations, whether it comes from forward differences
/// (`J_{·j} ≈ (r(x + δ_j e_j) − r(x))/δ_j`, `δ_j = √ε·max(|x_j|, 1)`, stepping
/// backwards at an upper bound) or from the problem's analytic
/// [`LeastSquares::jacobian`] (which costs about as much as `dim` residual
/// vectors).
#[derive(Clone, Debug, PartialEq)]
pub struct LevenbergMarquardt {
    /// The initial damping `μ₀` (relative to `diag(JᵀJ)`); default `10⁻³`.
    pub tau: f64,
    /// Stop when the projected gradient's largest component is at most this; default `10⁻¹⁵`.
    pub gradient_tol: f64,
    /// Stop when the accepted step is at most `step_tol·(‖x‖ + step_tol)`; default `10⁻¹⁵`.
    pub step_tol: f64,
    /// Stop when `E ≤ value_tol`; default 0 (never).
    pub value_tol: f64,
    /// Stop when an accepted step lowers `E` by at most `reduction_tol·E`
    /// (the function-value test of Moré 1978); default 0 (never).
    pub reduction_tol: f64,
    /// At most this many iterations; default 1000.
    pub max_iterations: u64,
}

impl Default for LevenbergMarquardt {
    fn default() -> Self {
        Self {
            tau: 1e-3,
            gradient_tol: 1e-15,
            step_tol: 1e-15,
            value_tol: 0.0,
            reduction_tol: 0.0,
            max_iterations: 1000,
        }
    }
}

impl LevenbergMarquardt {
    /// Minimises `problem` from `x0` (projected onto the box first) with at
    /// most `budget` evaluations.
    pub fn minimise<P: LeastSquares + ?Sized>(
        &self,
        problem: &P,
        x0: &[f64],
        budget: u64,
    ) -> LmOutcome {
        let n = problem.dim();
        let bounds = problem.bounds();
        let mut x: Vec<f64> = x0.iter().zip(bounds).map(|(&v, b)| b.clip(v)).collect();
        x.resize(n, 0.0);
        if n == 0 {
            return without_variables(problem, x, budget);
        }
        if budget == 0 {
            return LmOutcome {
                x,
                value: f64::INFINITY,
                evaluations: 0,
                iterations: 0,
                termination: Termination::Budget,
            };
        }
        let mut state = State::start(problem, x, budget, self.tau);
        let termination = self.iterate(&mut state);
        LmOutcome {
            x: state.x,
            value: state.e,
            evaluations: state.used,
            iterations: state.iterations,
            termination,
        }
    }

    /// The iterations from the evaluated starting point until a stopping
    /// rule holds: linearise, solve the damped step, try it, and update the
    /// damping from the gain ratio.
    fn iterate<P: LeastSquares + ?Sized>(&self, s: &mut State<'_, P>) -> Termination {
        let mut need_jacobian = true;
        loop {
            if s.e <= self.value_tol {
                return Termination::Value;
            }
            if super::interrupt::requested() {
                return Termination::Budget;
            }
            if s.iterations >= self.max_iterations {
                return Termination::Iterations;
            }
            if need_jacobian {
                // A Jacobian plus at least one trial must fit in the budget.
                if s.used + s.n as u64 + 1 > s.budget {
                    return Termination::Budget;
                }
                s.linearise();
                need_jacobian = false;
                if projected_gradient_norm(&s.g, &s.x, s.bounds) <= self.gradient_tol {
                    return Termination::Gradient;
                }
            }
            if s.used >= s.budget {
                return Termination::Budget;
            }
            if !s.solve_step() {
                s.increase_damping();
                if !s.mu.is_finite() {
                    return Termination::Step;
                }
                continue;
            }
            s.project_step();
            if s.step_is_negligible(self.step_tol) {
                return Termination::Step;
            }
            let e_new = s.try_step();
            let rho = s.gain_ratio(e_new);
            if rho > 0.0 && e_new < s.e {
                let small = s.e - e_new <= self.reduction_tol * s.e;
                s.accept(e_new, rho);
                need_jacobian = true;
                if small {
                    return Termination::Reduction;
                }
            } else {
                s.increase_damping();
                if !s.mu.is_finite() || s.mu > 1e300 {
                    return Termination::Step;
                }
            }
        }
    }
}

/// The outcome for a problem without variables: the residuals at the empty
/// point, if the budget allows one evaluation.
fn without_variables<P: LeastSquares + ?Sized>(problem: &P, x: Vec<f64>, budget: u64) -> LmOutcome {
    let mut r = vec![0.0; problem.residual_count()];
    let (value, evaluations) = if budget > 0 {
        problem.residuals(&x, &mut r);
        (sum_sq(&r), 1)
    } else {
        (f64::INFINITY, 0)
    };
    LmOutcome {
        x,
        value,
        evaluations,
        iterations: 0,
        termination: Termination::NoVariables,
    }
}

/// The state of one run: the current point with its residuals and value,
/// the damping `μ, ν`, the evaluation count, and the buffers reused by
/// every iteration.
struct State<'p, P: LeastSquares + ?Sized> {
    problem: &'p P,
    bounds: &'p [Bounds],
    /// Variables.
    n: usize,
    /// Residuals.
    m: usize,
    budget: u64,
    used: u64,
    iterations: u64,
    /// The current point, its residuals and `E`.
    x: Vec<f64>,
    r: Vec<f64>,
    e: f64,
    mu: f64,
    nu: f64,
    /// The Jacobian (dense `JᵀJ` only), `JᵀJ` and `g = Jᵀr` at `x`.
    jac: Vec<f64>,
    a: Normal,
    g: Vec<f64>,
    /// The damped system's factor and the step `h`.
    chol: Normal,
    h: Vec<f64>,
    /// The trial point and its residuals.
    x_new: Vec<f64>,
    r_new: Vec<f64>,
    /// Residuals of forward differences.
    r_fd: Vec<f64>,
}

impl<'p, P: LeastSquares + ?Sized> State<'p, P> {
    /// Evaluates the residuals at `x` (one evaluation) with damping `μ = tau`.
    fn start(problem: &'p P, x: Vec<f64>, budget: u64, tau: f64) -> Self {
        let n = problem.dim();
        let m = problem.residual_count();
        let mut r = vec![0.0; m];
        problem.residuals(&x, &mut r);
        let e = sanitise(sum_sq(&r));
        let (a, jac) = match problem.normal_structure() {
            Some((width, border)) => (
                Normal::Banded(BandedArrow::new(n, width, border)),
                Vec::new(),
            ),
            None => (
                Normal::Dense {
                    n,
                    a: vec![0.0; n * n],
                },
                vec![0.0; m * n],
            ),
        };
        State {
            problem,
            bounds: problem.bounds(),
            n,
            m,
            budget,
            used: 1,
            iterations: 0,
            x,
            r,
            e,
            mu: tau,
            nu: 2.0,
            jac,
            chol: a.clone(),
            a,
            g: vec![0.0; n],
            h: vec![0.0; n],
            x_new: vec![0.0; n],
            r_new: vec![0.0; m],
            r_fd: vec![0.0; m],
        }
    }

    /// A new iteration: the Jacobian at `x` (analytic, else forward
    /// differences; `dim` evaluations either way) and the normal equations.
    fn linearise(&mut self) {
        if let Normal::Banded(a) = &mut self.a {
            a.clear();
            self.g.fill(0.0);
            self.problem
                .normal_equations(&self.x, &self.r, a, &mut self.g);
            self.used += self.n as u64;
            self.iterations += 1;
            return;
        }
        if !self.problem.jacobian(&self.x, &mut self.jac) {
            forward_differences(
                self.problem,
                self.bounds,
                &self.x,
                &self.r,
                &mut self.r_fd,
                &mut self.jac,
            );
        }
        self.used += self.n as u64;
        self.iterations += 1;
        if let Normal::Dense { a, .. } = &mut self.a {
            normal_equations(&self.jac, &self.r, self.m, self.n, a, &mut self.g);
        }
    }

    /// Solves `(JᵀJ + μ D) h = −g` for the free variables; `false` if the
    /// system is not positive definite or the step is not finite.
    fn solve_step(&mut self) -> bool {
        let n = self.n;
        let max_diag = (0..n).map(|j| self.a.diagonal(j)).fold(0.0, f64::max);
        let floor = (max_diag * 1e-12).max(f64::MIN_POSITIVE);
        self.chol.clone_from(&self.a);
        for j in 0..n {
            self.chol
                .add_diagonal(j, self.mu * self.a.diagonal(j).max(floor));
        }
        for (hj, gj) in self.h.iter_mut().zip(&self.g) {
            *hj = -gj;
        }
        // Variables held at a bound by the gradient are fixed for this
        // step (the active set of projected Newton methods, Bertsekas
        // 1982): their rows and columns become the identity, their step 0.
        for j in 0..n {
            if is_held(self.g[j], self.x[j], self.bounds[j]) {
                self.chol.fix(j);
                self.h[j] = 0.0;
            }
        }
        self.chol.solve(&mut self.h) && self.h.iter().all(|v| v.is_finite())
    }

    /// Projects `x + h` onto the box as the trial point, and `h` to the
    /// step actually taken.
    fn project_step(&mut self) {
        for j in 0..self.n {
            self.x_new[j] = self.bounds[j].clip(self.x[j] + self.h[j]);
            self.h[j] = self.x_new[j] - self.x[j];
        }
    }

    /// Whether the projected step is at most `step_tol·(‖x‖ + step_tol)`.
    fn step_is_negligible(&self, step_tol: f64) -> bool {
        let h_norm = self.h.iter().map(|v| v * v).sum::<f64>().sqrt();
        let x_norm = self.x.iter().map(|v| v * v).sum::<f64>().sqrt();
        h_norm <= step_tol * (x_norm + step_tol)
    }

    /// Evaluates the trial point (one evaluation) and returns its `E`.
    fn try_step(&mut self) -> f64 {
        self.problem.residuals(&self.x_new, &mut self.r_new);
        self.used += 1;
        sanitise(sum_sq(&self.r_new))
    }

    /// The gain ratio `ϱ` of the projected step to a trial value `e_new`:
    /// the actual decrease of `F = ½E` over the decrease the linear model
    /// predicts, or −1 when the model predicts none.
    fn gain_ratio(&self, e_new: f64) -> f64 {
        let (g, h) = (&self.g, &self.h);
        // Predicted decrease of F = ½E by the linear model:
        // L(0) − L(h) = −gᵀh − ½ hᵀ(JᵀJ)h.
        let gh: f64 = g.iter().zip(h).map(|(a, b)| a * b).sum();
        let hah = self.a.quadratic_form(h);
        let predicted = -gh - 0.5 * hah;
        let actual = 0.5 * (self.e - e_new);
        if predicted > 0.0 {
            actual / predicted
        } else {
            -1.0
        }
    }

    /// Moves to the trial point and relaxes the damping by the gain ratio
    /// `rho`: `μ ← μ·max(⅓, 1 − (2ϱ − 1)³)`, `ν ← 2`.
    fn accept(&mut self, e_new: f64, rho: f64) {
        self.x.copy_from_slice(&self.x_new);
        std::mem::swap(&mut self.r, &mut self.r_new);
        self.e = e_new;
        self.mu *= f64::max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0).powi(3));
        self.nu = 2.0;
    }

    /// After a failed solve or a rejected step: `μ ← μν`, `ν ← 2ν`.
    fn increase_damping(&mut self) {
        self.mu *= self.nu;
        self.nu *= 2.0;
    }
}

/// `Σ r_k²`.
#[inline]
fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
}

/// The normal matrix `JᵀJ` (and the damped system's factor): dense, or
/// banded with a border for problems that declare a structure.
#[derive(Clone, Debug)]
enum Normal {
    /// Row-major `n × n`.
    Dense { n: usize, a: Vec<f64> },
    /// [`LeastSquares::normal_structure`]'s shape.
    Banded(BandedArrow),
}

impl Normal {
    /// `A_jj`.
    fn diagonal(&self, j: usize) -> f64 {
        match self {
            Normal::Dense { n, a } => a[j * *n + j],
            Normal::Banded(a) => a.get(j, j),
        }
    }

    /// `A_jj += v`.
    fn add_diagonal(&mut self, j: usize, v: f64) {
        match self {
            Normal::Dense { n, a } => a[j * *n + j] += v,
            Normal::Banded(a) => a.add(j, j, v),
        }
    }

    /// Row and column `j` replaced by the identity's.
    fn fix(&mut self, j: usize) {
        match self {
            Normal::Dense { n, a } => {
                let n = *n;
                for k in 0..n {
                    a[j * n + k] = 0.0;
                    a[k * n + j] = 0.0;
                }
                a[j * n + j] = 1.0;
            }
            Normal::Banded(a) => a.fix(j),
        }
    }

    /// `hᵀAh`.
    fn quadratic_form(&self, h: &[f64]) -> f64 {
        match self {
            Normal::Dense { n, a } => {
                let n = *n;
                let mut hah = 0.0;
                for i in 0..n {
                    let row: f64 = (0..n).map(|j| a[i * n + j] * h[j]).sum();
                    hah += h[i] * row;
                }
                hah
            }
            Normal::Banded(a) => a.quadratic_form(h),
        }
    }

    /// Solves `A y = b` in place, overwriting `A` by its factor; `false`
    /// if `A` is not positive definite.
    fn solve(&mut self, b: &mut [f64]) -> bool {
        match self {
            Normal::Dense { n, a } => cholesky_solve(a, b, *n),
            Normal::Banded(a) => a.solve(b),
        }
    }
}

/// Forward-difference Jacobian, stepping backwards where the forward step
/// would leave the box.
fn forward_differences<P: LeastSquares + ?Sized>(
    problem: &P,
    bounds: &[Bounds],
    x: &[f64],
    r: &[f64],
    r_fd: &mut [f64],
    jac: &mut [f64],
) {
    let n = x.len();
    let mut xp = x.to_vec();
    for j in 0..n {
        let mut delta = f64::EPSILON.sqrt() * x[j].abs().max(1.0);
        if x[j] + delta > bounds[j].upper {
            delta = -delta;
        }
        xp[j] = x[j] + delta;
        let actual = xp[j] - x[j];
        problem.residuals(&xp, r_fd);
        for (k, (&a, &b)) in r_fd.iter().zip(r).enumerate() {
            jac[k * n + j] = (a - b) / actual;
        }
        xp[j] = x[j];
    }
}

/// `A = JᵀJ` and `g = Jᵀr` for the row-major `m × n` Jacobian.
fn normal_equations(jac: &[f64], r: &[f64], m: usize, n: usize, a: &mut [f64], g: &mut [f64]) {
    a.fill(0.0);
    g.fill(0.0);
    for k in 0..m {
        let row = &jac[k * n..(k + 1) * n];
        for i in 0..n {
            g[i] += row[i] * r[k];
            for j in 0..=i {
                a[i * n + j] += row[i] * row[j];
            }
        }
    }
    for i in 0..n {
        for j in 0..i {
            a[j * n + i] = a[i * n + j];
        }
    }
}

/// `max_j |g_j|` over the components that can still move: a component at its
/// lower bound with `g_j > 0`, or at its upper bound with `g_j < 0`, would
/// only push `x` out of the box and is left out.
fn projected_gradient_norm(g: &[f64], x: &[f64], bounds: &[Bounds]) -> f64 {
    g.iter()
        .zip(x)
        .zip(bounds)
        .map(|((&gj, &xj), &b)| if is_held(gj, xj, b) { 0.0 } else { gj.abs() })
        .fold(0.0, f64::max)
}

/// Whether variable `x_j` sits on a bound that the descent direction `−g_j`
/// points out of.
#[inline]
fn is_held(gj: f64, xj: f64, b: Bounds) -> bool {
    (xj <= b.lower && gj > 0.0) || (xj >= b.upper && gj < 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::Cell;

    /// Rosenbrock as least squares: r = (10(x₂ − x₁²), 1 − x₁); minimum 0 at (1, 1).
    struct Rosenbrock {
        bounds: [Bounds; 2],
        analytic: bool,
        calls: Cell<u64>,
    }

    impl Problem for Rosenbrock {
        fn dim(&self) -> usize {
            2
        }
        fn bounds(&self) -> &[Bounds] {
            &self.bounds
        }
        fn objective(&self, x: &[f64]) -> f64 {
            let mut r = [0.0; 2];
            self.residuals(x, &mut r);
            r[0] * r[0] + r[1] * r[1]
        }
    }

    impl LeastSquares for Rosenbrock {
        fn residual_count(&self) -> usize {
            2
        }
        fn residuals(&self, x: &[f64], out: &mut [f64]) {
            self.calls.set(self.calls.get() + 1);
            out[0] = 10.0 * (x[1] - x[0] * x[0]);
            out[1] = 1.0 - x[0];
        }
        fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> bool {
            if !self.analytic {
                return false;
            }
            jac.copy_from_slice(&[-20.0 * x[0], 10.0, -1.0, 0.0]);
            true
        }
    }

    fn rosen(lo: f64, hi: f64, analytic: bool) -> Rosenbrock {
        Rosenbrock {
            bounds: [Bounds::new(lo, hi); 2],
            analytic,
            calls: Cell::new(0),
        }
    }

    #[test]
    fn solves_rosenbrock_with_both_jacobians() {
        for analytic in [false, true] {
            let p = rosen(-5.0, 5.0, analytic);
            let out = LevenbergMarquardt::default().minimise(&p, &[-1.2, 1.0], 10_000);
            assert!(out.value < 1e-20, "{out:?}");
            assert!((out.x[0] - 1.0).abs() < 1e-9 && (out.x[1] - 1.0).abs() < 1e-9);
            assert!(out.evaluations <= 10_000);
            // Every residual vector is counted: the problem's own calls are
            // one per counted evaluation without an analytic Jacobian.
            if !analytic {
                assert_eq!(p.calls.get(), out.evaluations);
            } else {
                assert!(p.calls.get() < out.evaluations);
            }
        }
    }

    #[test]
    fn respects_bounds_and_budget() {
        // The unconstrained minimum (1, 1) is outside [−2, 0.5]²: the
        // constrained minimiser lies on x₁ = 0.5 with x₂ = 0.25.
        let p = rosen(-2.0, 0.5, false);
        let out = LevenbergMarquardt::default().minimise(&p, &[-1.2, 0.4], 10_000);
        assert!(out.x.iter().all(|&v| (-2.0..=0.5).contains(&v)));
        assert!((out.x[0] - 0.5).abs() < 1e-9, "{out:?}");
        assert!((out.x[1] - 0.25).abs() < 1e-6, "{out:?}");
        assert!((out.value - 0.25).abs() < 1e-9);
        // A tiny budget is never exceeded.
        for budget in 0..8 {
            let p = rosen(-5.0, 5.0, false);
            let out = LevenbergMarquardt::default().minimise(&p, &[-1.2, 1.0], budget);
            assert!(out.evaluations <= budget, "{budget}: {out:?}");
            assert_eq!(p.calls.get(), out.evaluations);
        }
    }
}
