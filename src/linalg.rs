//! Dense linear algebra the solvers share: the Cholesky solve of the normal
//! equations, used by Levenberg–Marquardt and by the linear least-squares
//! first guess of a fitting segment.
//!
//! A leaf of the crate: it imports nothing of it.

/// Solves `A y = b` in place for a symmetric positive definite `n × n` matrix
/// `A` (row-major, overwritten by its Cholesky factor `L`, `A = LLᵀ`), leaving
/// `y` in `b`. Returns `false` (with `a` and `b` in an unspecified state) if
/// `A` is not numerically positive definite (Golub & Van Loan 2013,
/// *Matrix Computations*, 4th ed., Alg. 4.2.1).
pub fn cholesky_solve(a: &mut [f64], b: &mut [f64], n: usize) -> bool {
    debug_assert!(a.len() >= n * n && b.len() >= n);
    for j in 0..n {
        let mut d = a[j * n + j];
        for k in 0..j {
            d -= a[j * n + k] * a[j * n + k];
        }
        if d.is_nan() || d <= 0.0 || !d.is_finite() {
            return false;
        }
        let d = d.sqrt();
        a[j * n + j] = d;
        for i in j + 1..n {
            let mut s = a[i * n + j];
            for k in 0..j {
                s -= a[i * n + k] * a[j * n + k];
            }
            a[i * n + j] = s / d;
        }
    }
    // Forward substitution L z = b, then back substitution Lᵀ y = z.
    for i in 0..n {
        let mut s = b[i];
        for k in 0..i {
            s -= a[i * n + k] * b[k];
        }
        b[i] = s / a[i * n + i];
    }
    for i in (0..n).rev() {
        let mut s = b[i];
        for k in i + 1..n {
            s -= a[k * n + i] * b[k];
        }
        b[i] = s / a[i * n + i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solves_spd_and_rejects_indefinite() {
        let mut a = [4.0, 2.0, 0.6, 2.0, 5.0, 1.0, 0.6, 1.0, 3.0];
        let orig = a;
        let mut b = [1.0, -2.0, 0.5];
        let rhs = b;
        assert!(cholesky_solve(&mut a, &mut b, 3));
        for i in 0..3 {
            let s: f64 = (0..3).map(|j| orig[i * 3 + j] * b[j]).sum();
            assert!((s - rhs[i]).abs() < 1e-14);
        }
        let mut bad = [1.0, 2.0, 2.0, 1.0];
        assert!(!cholesky_solve(&mut bad, &mut [1.0, 1.0], 2));
    }
}
