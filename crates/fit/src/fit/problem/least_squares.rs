//! The segment problem as a least-squares problem for
//! Levenberg–Marquardt: the residuals `Rᵢ − P(sᵢ)` and their analytic
//! Jacobian, at fixed parameters or at the foot points
//! ([`ErrorMeasure::Orthogonal`]).

use super::layout::C1Var;
use super::SegmentProblem;
use crate::fit::controls::{cubic, quad, rcubic, rquad};
use crate::fit::{ErrorMeasure, FunctionType};
use crate::geometry::Point;
use crate::optim::lm::LeastSquares;

impl SegmentProblem {
    /// Writes the residuals `Rᵢ − P(sᵢ)` as `(x, y)` pairs into `out`
    /// (`out.len() == 2(n + 1)`), without allocation; under
    /// [`ErrorMeasure::Orthogonal`] the `sᵢ` are the foot points.
    pub fn residuals(&self, x: &[f64], out: &mut [f64]) {
        let k = self.controls(x);
        debug_assert_eq!(out.len(), 2 * self.points.len());
        if self.error == ErrorMeasure::Orthogonal {
            for (i, (o, &r)) in out.chunks_exact_mut(2).zip(&self.points).enumerate() {
                let p = self.measured(&k, i).1;
                o[0] = r.x - p.x;
                o[1] = r.y - p.y;
            }
            return;
        }
        let pairs = out.chunks_exact_mut(2).zip(&self.points).zip(&self.params);
        macro_rules! fill {
            ($eval:expr) => {
                for ((o, &r), &s) in pairs {
                    let p = $eval(s);
                    o[0] = r.x - p.x;
                    o[1] = r.y - p.y;
                }
            };
        }
        match self.function {
            FunctionType::Quadratic => fill!(|s| quad(&k, s)),
            FunctionType::Cubic => fill!(|s| cubic(&k, s)),
            FunctionType::RationalQuadratic => fill!(|s| rquad(&k, s)),
            FunctionType::RationalCubic => fill!(|s| rcubic(&k, s)),
        }
    }

    /// Writes the Jacobian `∂rₖ/∂x_j` of [`SegmentProblem::residuals`]
    /// row-major (`2(n + 1)` rows, `dim` columns) into `jac`.
    ///
    /// With `P = Σ w_k B_k C_k / W`, `W = Σ w_k B_k`:
    /// `∂P/∂C_k = w_k B_k / W` (times the identity), `∂P/∂w_k = B_k (C_k − P)/W`,
    /// and through the joins `∂C₁/∂T = L` (G¹), `∂C₁/∂w₁ = −D/(m w₁²)` (C¹);
    /// the residual's derivative is minus that of `P`.
    ///
    /// Under [`ErrorMeasure::Orthogonal`] the rows are taken at the foot
    /// points and projected onto the normal, `−(I − t tᵀ) ∂P/∂x` with `t` the
    /// unit tangent there: the foot point moves along the curve to first
    /// order, `∂s/∂x = −t·∂P/∂x / |P′|` (Kaufman's 1975 variable-projection
    /// Jacobian; exact where the residual is zero).
    pub fn jacobian(&self, x: &[f64], jac: &mut [f64]) {
        let dim = self.layout.dim;
        debug_assert_eq!(jac.len(), 2 * self.points.len() * dim);
        if dim == 0 {
            return;
        }
        let k = self.controls(x);
        let m = self.function.degree();
        let orthogonal = self.error == ErrorMeasure::Orthogonal;
        for i in 0..self.params.len() {
            let (s, tangent) = if orthogonal {
                let (s, _, d1) = self.measured(&k, i);
                let len = d1.hypot();
                (s, (len > 0.0 && len.is_finite()).then(|| d1 / len))
            } else {
                (self.params[i], None)
            };
            let q = k.partials(m, s);
            let (a1, a2) = (q.c1, q.c2);
            let (rx, ry) = jac[2 * i * dim..2 * (i + 1) * dim].split_at_mut(dim);
            let mut put = |j: usize, d: Point| {
                rx[j] = -d.x;
                ry[j] = -d.y;
            };
            let mut lin = |var: C1Var, a: f64| match var {
                C1Var::Free(j) => {
                    put(j, Point::new(a, 0.0));
                    put(j + 1, Point::new(0.0, a));
                }
                C1Var::Derived(_) | C1Var::EndDerived(_) | C1Var::Fixed(_) => {}
                C1Var::Ratio(j, leg) => put(j, leg * a),
                C1Var::EndRatio(j, dir) => put(j, dir * -a),
            };
            lin(self.layout.c1, a1);
            if let Some(var) = self.layout.c2 {
                lin(var, a2);
            }
            // ∂C/∂w of a derived control point: −D/(m w²) from the start,
            // +D/(m w²) from the end.
            let derived = |var: C1Var, wk: f64, a: f64| match var {
                C1Var::Derived(dv) => dv * (-a / (m as f64 * wk * wk)),
                C1Var::EndDerived(dv) => dv * (a / (m as f64 * wk * wk)),
                _ => Point::ZERO,
            };
            if let Some(j) = self.layout.w1 {
                put(j, q.w1 + derived(self.layout.c1, k.w1, a1));
            }
            if let Some(j) = self.layout.w2 {
                let var = self.layout.c2.unwrap_or(C1Var::Free(0));
                put(j, q.w2 + derived(var, k.w2, a2));
            }
            if let Some(t) = tangent {
                for (x, y) in rx.iter_mut().zip(ry.iter_mut()) {
                    let along = *x * t.x + *y * t.y;
                    *x -= along * t.x;
                    *y -= along * t.y;
                }
            }
        }
    }
}

impl LeastSquares for SegmentProblem {
    fn residual_count(&self) -> usize {
        2 * self.points.len()
    }

    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        SegmentProblem::residuals(self, x, out)
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> bool {
        SegmentProblem::jacobian(self, x, jac);
        true
    }
}
