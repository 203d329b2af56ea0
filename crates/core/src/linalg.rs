//! Dense linear algebra the solvers share: the Cholesky solve of the normal
//! equations, used by Levenberg–Marquardt and by the linear least-squares
//! first guess of a fitting segment, and the symmetric eigendecomposition
//! CMA-ES samples with.
//!
//! A leaf of the crate: it imports nothing of it. Everything here is plain
//! scalar `f64` code without threads; every loop computes each element by a
//! fixed sequence of operations (no reassociation, no fused multiply-add),
//! so a caller may inline it into code compiled for wider vector units and
//! get the same bits.

mod banded;

pub use banded::BandedArrow;

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

/// `Σ a_i b_i` over the common length, in a fixed order that vector units
/// can follow: eight partial sums, partial sum `r` taking the terms
/// `i ≡ r (mod 8)` of the leading multiple of eight in index order, then
/// combined as `((s₀ + s₄) + (s₂ + s₆)) + ((s₁ + s₅) + (s₃ + s₇))`, then
/// the remaining terms added in index order. The same bits whatever the
/// vector width the loop is compiled for.
#[inline(always)]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut acc = [0.0f64; 8];
    let mut ca = a.chunks_exact(8);
    let mut cb = b.chunks_exact(8);
    for (x, y) in (&mut ca).zip(&mut cb) {
        for r in 0..8 {
            acc[r] += x[r] * y[r];
        }
    }
    let mut s = ((acc[0] + acc[4]) + (acc[2] + acc[6])) + ((acc[1] + acc[5]) + (acc[3] + acc[7]));
    for (x, y) in ca.remainder().iter().zip(cb.remainder()) {
        s += x * y;
    }
    s
}

/// `√(a² + b²)`, through [`f64::hypot`] only where the squares would
/// overflow or lose precision to underflow (the QL iteration calls it once
/// per rotation, and `hypot` costs several times more).
#[inline(always)]
fn pythag(a: f64, b: f64) -> f64 {
    let s = a * a + b * b;
    if s < f64::MAX && s > 1e-290 {
        s.sqrt()
    } else {
        a.hypot(b)
    }
}

/// The eigendecomposition `A = V Λ Vᵀ` of a symmetric `n × n` matrix.
///
/// On entry `w` (row-major, `n²` values) holds `A` in its upper triangle,
/// `w[j·n + k]` for `k ≥ j`; the strict lower triangle is not read. On return
/// `values` holds the eigenvalues in ascending order and row `k` of `w`
/// (`w[k·n..(k+1)·n]`) the unit eigenvector of `values[k]`; the rows are
/// orthonormal. `e` is `n` values of scratch. Returns `false` (with `w`,
/// `values` and `e` in an unspecified state) if `A` has a non-finite entry
/// or the QL iteration does not converge in 60 steps for some eigenvalue.
///
/// Householder reduction to tridiagonal form with the transformations
/// accumulated, then the QL algorithm with implicit shifts: the Algol
/// procedures `tred2` and `tql2` of Bowdler, Martin, Reinsch & Wilkinson
/// (1968, "The QR and QL algorithms for symmetric matrices", Numer. Math.
/// 11:293–306; Martin, Reinsch & Wilkinson 1968, "Householder's
/// tridiagonalization of a symmetric matrix", Numer. Math. 11:181–195),
/// in the form of EISPACK and JAMA, with the matrix of eigenvectors stored
/// transposed: the columns those routines update are rows here, so every
/// inner loop runs over contiguous memory. About `9n³` flops. Two
/// departures change rounding only: `√(p² + e²)` replaces `hypot` where
/// that is safe, and each rotation divides once, `1/r`, instead of twice;
/// the inner products are [`dot`]'s.
#[inline(always)]
pub fn symmetric_eigen(w: &mut [f64], n: usize, values: &mut [f64], e: &mut [f64]) -> bool {
    debug_assert!(w.len() >= n * n && values.len() >= n && e.len() >= n);
    if n == 0 {
        return true;
    }
    for j in 0..n {
        if !w[j * n + j..(j + 1) * n].iter().all(|v| v.is_finite()) {
            return false;
        }
    }
    tridiagonalise(w, n, values, e);
    if !tridiagonal_ql(w, n, values, e) {
        return false;
    }
    // Sort ascending (selection sort, as JAMA), swapping eigenvector rows.
    for i in 0..n - 1 {
        let mut k = i;
        for j in i + 1..n {
            if values[j] < values[k] {
                k = j;
            }
        }
        if k != i {
            values.swap(i, k);
            let (head, tail) = w.split_at_mut(k * n);
            head[i * n..(i + 1) * n].swap_with_slice(&mut tail[..n]);
        }
    }
    true
}

/// `tred2`: reduces the symmetric matrix in the upper triangle of `w` to
/// tridiagonal form (diagonal `d`, sub-diagonal `e[1..]`) and leaves in `w`
/// the transpose of the orthogonal transformation (row `j` of `w` is column
/// `j` of EISPACK's `Z`).
#[inline(always)]
fn tridiagonalise(w: &mut [f64], n: usize, d: &mut [f64], e: &mut [f64]) {
    // `v(r, c)` of the routines is `w[c·n + r]`.
    for j in 0..n {
        d[j] = w[j * n + n - 1];
    }
    for i in (1..n).rev() {
        let mut scale = 0.0;
        let mut h = 0.0;
        for dk in &d[..i] {
            scale += dk.abs();
        }
        if scale == 0.0 {
            e[i] = d[i - 1];
            for j in 0..i {
                d[j] = w[j * n + i - 1];
                w[j * n + i] = 0.0;
                w[i * n + j] = 0.0;
            }
        } else {
            for dk in &mut d[..i] {
                *dk /= scale;
                h += *dk * *dk;
            }
            let mut f = d[i - 1];
            let mut g = h.sqrt();
            if f > 0.0 {
                g = -g;
            }
            e[i] = scale * g;
            h -= f * g;
            d[i - 1] = f - g;
            for ej in &mut e[..i] {
                *ej = 0.0;
            }
            // Apply the similarity transformation to the remaining columns.
            for j in 0..i {
                f = d[j];
                w[i * n + j] = f;
                let row = &w[j * n + j + 1..j * n + i];
                g = e[j] + w[j * n + j] * f + dot(row, &d[j + 1..i]);
                for (ek, &vkj) in e[j + 1..i].iter_mut().zip(row) {
                    *ek += vkj * f;
                }
                e[j] = g;
            }
            f = 0.0;
            for (ej, &dj) in e[..i].iter_mut().zip(&d[..i]) {
                *ej /= h;
                f += *ej * dj;
            }
            let hh = f / (h + h);
            for (ej, &dj) in e[..i].iter_mut().zip(&d[..i]) {
                *ej -= hh * dj;
            }
            for j in 0..i {
                let (f, g) = (d[j], e[j]);
                let row = &mut w[j * n + j..j * n + i];
                for ((vkj, &ek), &dk) in row.iter_mut().zip(&e[j..i]).zip(&d[j..i]) {
                    *vkj -= f * ek + g * dk;
                }
                d[j] = w[j * n + i - 1];
                w[j * n + i] = 0.0;
            }
        }
        d[i] = h;
    }
    // Accumulate the transformations.
    for i in 0..n - 1 {
        w[i * n + n - 1] = w[i * n + i];
        w[i * n + i] = 1.0;
        let h = d[i + 1];
        if h != 0.0 {
            let (head, tail) = w.split_at_mut((i + 1) * n);
            let u = &mut tail[..i + 1];
            for (dk, &uk) in d[..=i].iter_mut().zip(u.iter()) {
                *dk = uk / h;
            }
            for j in 0..=i {
                let row = &mut head[j * n..j * n + i + 1];
                let g = dot(u, row);
                for (vk, &dk) in row.iter_mut().zip(&d[..=i]) {
                    *vk -= g * dk;
                }
            }
        }
        for uk in &mut w[(i + 1) * n..(i + 1) * n + i + 1] {
            *uk = 0.0;
        }
    }
    for j in 0..n {
        d[j] = w[j * n + n - 1];
        w[j * n + n - 1] = 0.0;
    }
    w[n * n - 1] = 1.0;
    e[0] = 0.0;
}

/// `tql2`: the eigenvalues (into `d`) and eigenvectors (rotating the rows
/// of `w`) of the tridiagonal matrix of [`tridiagonalise`], by QL with
/// implicit shifts; `false` if an eigenvalue needs more than 60 steps.
#[inline(always)]
fn tridiagonal_ql(w: &mut [f64], n: usize, d: &mut [f64], e: &mut [f64]) -> bool {
    for i in 1..n {
        e[i - 1] = e[i];
    }
    e[n - 1] = 0.0;
    let mut f = 0.0;
    let mut tst1: f64 = 0.0;
    let eps = f64::EPSILON;
    for l in 0..n {
        // Find a small sub-diagonal element.
        tst1 = tst1.max(d[l].abs() + e[l].abs());
        let mut m = l;
        while m < n && e[m].abs() > eps * tst1 {
            m += 1;
        }
        if m == n {
            return false;
        }
        if m > l {
            let mut steps = 0;
            loop {
                steps += 1;
                if steps > 60 {
                    return false;
                }
                // The implicit shift.
                let mut g = d[l];
                let mut p = (d[l + 1] - g) / (2.0 * e[l]);
                let mut r = pythag(p, 1.0);
                if p < 0.0 {
                    r = -r;
                }
                d[l] = e[l] / (p + r);
                d[l + 1] = e[l] * (p + r);
                let dl1 = d[l + 1];
                let mut h = g - d[l];
                for di in &mut d[l + 2..n] {
                    *di -= h;
                }
                f += h;
                // The implicit QL transformation.
                p = d[m];
                let mut c = 1.0;
                let mut c2 = c;
                let mut c3 = c;
                let el1 = e[l + 1];
                let mut s = 0.0;
                let mut s2 = 0.0;
                for i in (l..m).rev() {
                    c3 = c2;
                    c2 = c;
                    s2 = s;
                    g = c * e[i];
                    h = c * p;
                    r = pythag(p, e[i]);
                    e[i + 1] = s * r;
                    let inv = 1.0 / r;
                    s = e[i] * inv;
                    c = p * inv;
                    p = c * d[i] - s * g;
                    d[i + 1] = h + s * (c * g + s * d[i]);
                    // Accumulate the rotation into rows i and i + 1.
                    let (head, tail) = w.split_at_mut((i + 1) * n);
                    let (zi, zi1) = (&mut head[i * n..], &mut tail[..n]);
                    for (a, b) in zi.iter_mut().zip(zi1.iter_mut()) {
                        let hb = *b;
                        *b = s * *a + c * hb;
                        *a = c * *a - s * hb;
                    }
                }
                p = -s * s2 * c3 * el1 * e[l] / dl1;
                e[l] = s * p;
                d[l] = c * p;
                if e[l].abs() <= eps * tst1 {
                    break;
                }
            }
        }
        d[l] += f;
        e[l] = 0.0;
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

    /// `A = V Λ Vᵀ` and `V Vᵀ = I` to `tol`, `A` given in full.
    fn check_eigen(a: &[f64], n: usize, tol: f64) -> Vec<f64> {
        let mut w = a.to_vec();
        // Only the upper triangle may be read: spoil the lower one.
        for j in 0..n {
            for k in 0..j {
                w[j * n + k] = f64::NAN;
            }
        }
        let mut values = vec![0.0; n];
        let mut e = vec![0.0; n];
        assert!(symmetric_eigen(&mut w, n, &mut values, &mut e));
        assert!(values.windows(2).all(|p| p[0] <= p[1]), "{values:?}");
        let scale = a.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            for j in 0..n {
                let dot: f64 = (0..n).map(|k| w[i * n + k] * w[j * n + k]).sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!((dot - want).abs() < tol, "V Vᵀ [{i}][{j}] = {dot}");
                let rebuilt: f64 = (0..n)
                    .map(|k| w[k * n + i] * values[k] * w[k * n + j])
                    .sum();
                assert!(
                    (rebuilt - a[i * n + j]).abs() < tol * scale,
                    "A[{i}][{j}] = {} rebuilt as {rebuilt}",
                    a[i * n + j]
                );
            }
        }
        values
    }

    #[test]
    fn eigen_decomposes_symmetric_matrices() {
        // A known spectrum: the 2 × 2 matrix [[2, 1], [1, 2]] has 1 and 3.
        let v = check_eigen(&[2.0, 1.0, 1.0, 2.0], 2, 1e-15);
        assert!((v[0] - 1.0).abs() < 1e-15 && (v[1] - 3.0).abs() < 1e-15);
        // 1 × 1, the identity (a repeated eigenvalue), zero, a diagonal.
        assert_eq!(check_eigen(&[-4.5], 1, 1e-15), vec![-4.5]);
        let mut id = vec![0.0; 25];
        for i in 0..5 {
            id[i * 5 + i] = 1.0;
        }
        assert_eq!(check_eigen(&id, 5, 1e-15), vec![1.0; 5]);
        assert_eq!(check_eigen(&[0.0; 9], 3, 1e-15), vec![0.0; 3]);
        let v = check_eigen(&[3.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0, 2.0], 3, 1e-15);
        assert_eq!(v, vec![-1.0, 2.0, 3.0]);
        // Pseudo-random symmetric matrices, and an ill-conditioned one
        // (eigenvalues 10^0 … 10^12 in a rotated basis, as CMA-ES meets).
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for n in [2, 3, 7, 10, 31] {
            let mut a = vec![0.0; n * n];
            for i in 0..n {
                for j in i..n {
                    let x = next();
                    a[i * n + j] = x;
                    a[j * n + i] = x;
                }
            }
            check_eigen(&a, n, 1e-13);
        }
        let n = 12;
        let mut q = vec![0.0; n * n];
        for v in q.iter_mut() {
            *v = next();
        }
        // Gram–Schmidt rows of q into an orthonormal basis.
        for i in 0..n {
            for j in 0..i {
                let d: f64 = (0..n).map(|k| q[i * n + k] * q[j * n + k]).sum();
                for k in 0..n {
                    q[i * n + k] -= d * q[j * n + k];
                }
            }
            let norm = (0..n).map(|k| q[i * n + k].powi(2)).sum::<f64>().sqrt();
            for k in 0..n {
                q[i * n + k] /= norm;
            }
        }
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..n)
                    .map(|k| q[k * n + i] * 10f64.powi(k as i32) * q[k * n + j])
                    .sum();
            }
        }
        let v = check_eigen(&a, n, 1e-12);
        for (k, value) in v.iter().enumerate() {
            let want = 10f64.powi(k as i32);
            assert!((value - want).abs() < 1e-3 + 1e-12 * want, "{k}: {value}");
        }
    }

    #[test]
    fn eigen_refuses_non_finite_matrices() {
        let mut w = [1.0, f64::NAN, 0.0, 1.0];
        assert!(!symmetric_eigen(&mut w, 2, &mut [0.0; 2], &mut [0.0; 2]));
        let mut w = [f64::INFINITY, 0.0, 0.0, 1.0];
        assert!(!symmetric_eigen(&mut w, 2, &mut [0.0; 2], &mut [0.0; 2]));
        assert!(symmetric_eigen(&mut [], 0, &mut [], &mut []));
    }
}
