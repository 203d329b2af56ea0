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
use crate::linalg::cholesky_solve;
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
        let m = problem.residual_count();
        let bounds = problem.bounds();
        let mut x: Vec<f64> = x0.iter().zip(bounds).map(|(&v, b)| b.clip(v)).collect();
        x.resize(n, 0.0);
        if n == 0 {
            let mut r = vec![0.0; m];
            let (value, evaluations) = if budget > 0 {
                problem.residuals(&x, &mut r);
                (sum_sq(&r), 1)
            } else {
                (f64::INFINITY, 0)
            };
            return LmOutcome {
                x,
                value,
                evaluations,
                iterations: 0,
                termination: Termination::NoVariables,
            };
        }
        let dim = n as u64;
        let mut used = 0u64;
        let mut r = vec![0.0; m];
        let mut r_new = vec![0.0; m];
        let mut r_fd = vec![0.0; m];
        let mut jac = vec![0.0; m * n];
        let mut a = vec![0.0; n * n];
        let mut chol = vec![0.0; n * n];
        let mut g = vec![0.0; n];
        let mut h = vec![0.0; n];
        let mut x_new = vec![0.0; n];
        if budget == 0 {
            return LmOutcome {
                x,
                value: f64::INFINITY,
                evaluations: 0,
                iterations: 0,
                termination: Termination::Budget,
            };
        }
        problem.residuals(&x, &mut r);
        used += 1;
        let mut e = sanitise(sum_sq(&r));
        let mut mu = self.tau;
        let mut nu = 2.0;
        let mut iterations = 0u64;
        let mut need_jacobian = true;
        let termination = loop {
            if e <= self.value_tol {
                break Termination::Value;
            }
            if iterations >= self.max_iterations {
                break Termination::Iterations;
            }
            if need_jacobian {
                // A Jacobian plus at least one trial must fit in the budget.
                if used + dim + 1 > budget {
                    break Termination::Budget;
                }
                if !problem.jacobian(&x, &mut jac) {
                    forward_differences(problem, bounds, &x, &r, &mut r_fd, &mut jac);
                }
                used += dim;
                iterations += 1;
                normal_equations(&jac, &r, m, n, &mut a, &mut g);
                need_jacobian = false;
                if projected_gradient_norm(&g, &x, bounds) <= self.gradient_tol {
                    break Termination::Gradient;
                }
            }
            if used >= budget {
                break Termination::Budget;
            }
            let max_diag = (0..n).map(|j| a[j * n + j]).fold(0.0, f64::max);
            let floor = (max_diag * 1e-12).max(f64::MIN_POSITIVE);
            chol.copy_from_slice(&a);
            for j in 0..n {
                chol[j * n + j] += mu * a[j * n + j].max(floor);
            }
            for (hj, gj) in h.iter_mut().zip(&g) {
                *hj = -gj;
            }
            // Variables held at a bound by the gradient are fixed for this
            // step (the active set of projected Newton methods, Bertsekas
            // 1982): their rows and columns become the identity, their step 0.
            for j in 0..n {
                if is_held(g[j], x[j], bounds[j]) {
                    for k in 0..n {
                        chol[j * n + k] = 0.0;
                        chol[k * n + j] = 0.0;
                    }
                    chol[j * n + j] = 1.0;
                    h[j] = 0.0;
                }
            }
            if !cholesky_solve(&mut chol, &mut h, n) || !h.iter().all(|v| v.is_finite()) {
                mu *= nu;
                nu *= 2.0;
                if !mu.is_finite() {
                    break Termination::Step;
                }
                continue;
            }
            for j in 0..n {
                x_new[j] = bounds[j].clip(x[j] + h[j]);
                h[j] = x_new[j] - x[j];
            }
            let h_norm = h.iter().map(|v| v * v).sum::<f64>().sqrt();
            let x_norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            if h_norm <= self.step_tol * (x_norm + self.step_tol) {
                break Termination::Step;
            }
            problem.residuals(&x_new, &mut r_new);
            used += 1;
            let e_new = sanitise(sum_sq(&r_new));
            // Predicted decrease of F = ½E by the linear model:
            // L(0) − L(h) = −gᵀh − ½ hᵀ(JᵀJ)h.
            let gh: f64 = g.iter().zip(&h).map(|(a, b)| a * b).sum();
            let mut hah = 0.0;
            for i in 0..n {
                let row: f64 = (0..n).map(|j| a[i * n + j] * h[j]).sum();
                hah += h[i] * row;
            }
            let predicted = -gh - 0.5 * hah;
            let actual = 0.5 * (e - e_new);
            let rho = if predicted > 0.0 {
                actual / predicted
            } else {
                -1.0
            };
            if rho > 0.0 && e_new < e {
                x.copy_from_slice(&x_new);
                std::mem::swap(&mut r, &mut r_new);
                e = e_new;
                mu *= f64::max(1.0 / 3.0, 1.0 - (2.0 * rho - 1.0).powi(3));
                nu = 2.0;
                need_jacobian = true;
            } else {
                mu *= nu;
                nu *= 2.0;
                if !mu.is_finite() || mu > 1e300 {
                    break Termination::Step;
                }
            }
        };
        LmOutcome {
            x,
            value: e,
            evaluations: used,
            iterations,
            termination,
        }
    }
}

/// `Σ r_k²`.
#[inline]
fn sum_sq(r: &[f64]) -> f64 {
    r.iter().map(|v| v * v).sum()
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
