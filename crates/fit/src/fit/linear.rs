//! Linear least squares for the control points once the weights are fixed.
//!
//! With the parameters `sᵢ`, the end points and the weights fixed, every
//! remaining decision variable (inner control point coordinates, the G¹
//! ratio `T`) enters `P(sᵢ)` linearly: for a polynomial segment
//! `P(sᵢ) = Σ_k B_k(sᵢ) C_k`, so minimising `E` is a linear least-squares
//! problem on the Bernstein matrix, solved here by the normal equations
//! `(AᵀA) y = Aᵀb` and a small dense Cholesky factorisation (the classic
//! fixed-parameter Bézier fit, e.g. Schneider 1990, "An algorithm for
//! automatically fitting digitized curves", *Graphics Gems*, whose 2×2
//! system for the tangent lengths is the same construction).

use super::SegmentProblem;
use crate::linalg::cholesky_solve;
use crate::problem::Problem;

/// The least-squares decision vector of `problem` with every weight fixed at
/// 1 (clipped into the weight range): exact for polynomial functions, and
/// the polynomial (unit-weight) fit used to start Levenberg–Marquardt for
/// rational ones.
///
/// The linear variables are solved from the normal equations of the
/// residuals' Jacobian columns, which with fixed weights are constant: for a
/// free `C_k` the column is `−w_k B_k(sᵢ)/W(sᵢ)` (the Bernstein matrix when
/// `w = 1`), for `T` it is `−B₁(sᵢ)·L`. The result is **not** clipped into
/// the box (a caller that needs that clips it). If the normal matrix is
/// singular (too few distinct parameters), a ridge of `10⁻¹²·trace` is added.
pub fn linear_fit(problem: &SegmentProblem) -> Vec<f64> {
    let dim = problem.dim();
    let mut x: Vec<f64> = problem.guess().to_vec();
    for (j, v) in x.iter_mut().enumerate() {
        if problem.is_weight(j) {
            *v = problem.bounds()[j].clip(1.0);
        }
    }
    let lin: Vec<usize> = (0..dim).filter(|&j| !problem.is_weight(j)).collect();
    let k = lin.len();
    if k == 0 {
        return x;
    }
    let m = 2 * problem.points().len();
    let mut r = vec![0.0; m];
    let mut jac = vec![0.0; m * dim];
    problem.residuals(&x, &mut r);
    problem.jacobian(&x, &mut jac);
    // Normal equations over the linear columns: (JᵀJ) δ = −Jᵀr.
    let mut a = vec![0.0; k * k];
    let mut g = vec![0.0; k];
    for row in 0..m {
        let jr = &jac[row * dim..(row + 1) * dim];
        for (p, &jp) in lin.iter().enumerate() {
            g[p] -= jr[jp] * r[row];
            for (q, &jq) in lin.iter().enumerate().take(p + 1) {
                a[p * k + q] += jr[jp] * jr[jq];
            }
        }
    }
    for p in 0..k {
        for q in 0..p {
            a[q * k + p] = a[p * k + q];
        }
    }
    let mut delta = g.clone();
    let mut work = a.clone();
    if !cholesky_solve(&mut work, &mut delta, k) {
        let trace: f64 = (0..k).map(|p| a[p * k + p]).sum();
        let mut work = a;
        for p in 0..k {
            work[p * k + p] += 1e-12 * trace.max(f64::MIN_POSITIVE);
        }
        delta = g;
        if !cholesky_solve(&mut work, &mut delta, k) {
            return x;
        }
    }
    for (p, &j) in lin.iter().enumerate() {
        x[j] += delta[p];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{FunctionType, SearchSpaceOptions, Start};
    use crate::geometry::{CubicBez, Curve, Point, QuadBez};

    #[test]
    fn recovers_polynomials_exactly() {
        let c = CubicBez::new(
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(4.0, -1.0),
            Point::new(5.0, 2.0),
        );
        // Uneven parameters, not multiples of 1/4.
        let params: Vec<f64> = (0..=37).map(|k| (k as f64 / 37.0).powf(1.3)).collect();
        let pts: Vec<Point> = params.iter().map(|&s| c.eval(s)).collect();
        let o = SearchSpaceOptions::default();
        let p = SegmentProblem::new(
            FunctionType::Cubic,
            pts.clone(),
            params.clone(),
            Start::Free,
            &o,
        )
        .unwrap();
        let x = linear_fit(&p);
        for (a, b) in x.iter().zip([1.0, 3.0, 4.0, -1.0]) {
            assert!((a - b).abs() < 1e-10, "{x:?}");
        }
        assert!(p.objective(&x) < 1e-20);
        // G¹: C₁ = C₀ + T·L with L = (1, 3)/2 gives T = 2.
        let p = SegmentProblem::new(
            FunctionType::Cubic,
            pts,
            params.clone(),
            Start::G1 {
                leg: Point::new(0.5, 1.5),
            },
            &o,
        )
        .unwrap();
        let x = linear_fit(&p);
        assert!(
            (x[0] - 2.0).abs() < 1e-10 && (x[1] - 4.0).abs() < 1e-10,
            "{x:?}"
        );
        let q = QuadBez::new(Point::ZERO, Point::new(2.0, 4.0), Point::new(3.0, 0.0));
        let pts: Vec<Point> = params.iter().map(|&s| q.eval(s)).collect();
        let p = SegmentProblem::new(FunctionType::Quadratic, pts, params, Start::Free, &o).unwrap();
        let x = linear_fit(&p);
        assert!((x[0] - 2.0).abs() < 1e-10 && (x[1] - 4.0).abs() < 1e-10);
    }
}
