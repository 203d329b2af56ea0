//! A symmetric matrix that is banded except for a few dense last rows and
//! columns (an "arrowhead" border), and its Cholesky solve.
//!
//! This is the shape of the normal equations `JᵀJ` of a chain of curve
//! segments: each residual touches the variables of one segment and of the
//! two joints at its ends, so ordered joint by joint the matrix is banded;
//! a closed chain's last segment also touches the first joint, whose
//! variables are put last, as the border. The solve is the block
//! elimination of the border (Golub & Van Loan 2013, *Matrix Computations*,
//! 4th ed., §4.3 band Cholesky and §4.5 block elimination): with
//! `A = [[B, Cᵀ], [C, D]]`, `B` banded, first `z = B⁻¹r₁` and `Z = B⁻¹Cᵀ`,
//! then `(D − CZ) x₂ = r₂ − Cz` (dense, as small as the border), then
//! `x₁ = z − Z x₂`. It costs `O(n b²)` for half-bandwidth `b` instead of
//! the dense `O(n³)`.

/// A symmetric `n × n` matrix: the leading `n − k` rows banded with
/// half-bandwidth `b` (`A_ij = 0` for `|i − j| > b` among them), the last
/// `k` rows and columns dense.
#[derive(Clone, Debug, PartialEq)]
pub struct BandedArrow {
    n: usize,
    /// Leading (banded) size `n − k`.
    lead: usize,
    /// Half-bandwidth `b`.
    width: usize,
    /// `band[i(b + 1) + d] = A[i][i − d]`, `d = 0..=b`, `i < lead`.
    band: Vec<f64>,
    /// `border[r·n + j] = A[lead + r][j]`, `j < n` (the full row).
    border: Vec<f64>,
}

impl BandedArrow {
    /// The zero matrix of size `n` with half-bandwidth `width` and `border`
    /// dense last rows (`border ≤ n`).
    pub fn new(n: usize, width: usize, border: usize) -> BandedArrow {
        assert!(border <= n, "border larger than the matrix");
        let lead = n - border;
        BandedArrow {
            n,
            lead,
            width,
            band: vec![0.0; lead * (width + 1)],
            border: vec![0.0; border * n],
        }
    }

    /// The size `n`.
    pub fn size(&self) -> usize {
        self.n
    }

    /// Sets every entry to zero (the structure stays).
    pub fn clear(&mut self) {
        self.band.fill(0.0);
        self.border.fill(0.0);
    }

    /// The storage slot of `A[i][j]`, or `None` outside the structure.
    #[inline]
    fn slot(&self, i: usize, j: usize) -> Option<(bool, usize)> {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i >= self.lead {
            Some((false, (i - self.lead) * self.n + j))
        } else if i - j <= self.width {
            Some((true, i * (self.width + 1) + (i - j)))
        } else {
            None
        }
    }

    /// `A[i][j]` (= `A[j][i]`); zero outside the structure.
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match self.slot(i, j) {
            Some((true, s)) => self.band[s],
            Some((false, s)) => self.border[s],
            None => 0.0,
        }
    }

    /// Adds `v` to `A[i][j]` and so to `A[j][i]` (one stored entry). Panics
    /// if `(i, j)` lies outside the structure: the caller's band is wrong.
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        match self.slot(i, j) {
            Some((true, s)) => self.band[s] += v,
            Some((false, s)) => self.border[s] += v,
            None => panic!("entry ({i}, {j}) outside the band of width {}", self.width),
        }
    }

    /// Sets `A[i][j]` (and `A[j][i]`); ignored outside the structure when
    /// `v` is zero, panics otherwise.
    fn set(&mut self, i: usize, j: usize, v: f64) {
        match self.slot(i, j) {
            Some((true, s)) => self.band[s] = v,
            Some((false, s)) => self.border[s] = v,
            None if v == 0.0 => {}
            None => panic!("entry ({i}, {j}) outside the band"),
        }
    }

    /// Replaces row and column `j` by those of the identity (a variable
    /// held fixed: its step is then 0 for a zero right-hand side).
    pub fn fix(&mut self, j: usize) {
        let lo = if j < self.lead {
            j.saturating_sub(self.width)
        } else {
            0
        };
        let hi = if j < self.lead {
            (j + self.width + 1).min(self.lead)
        } else {
            self.lead
        };
        for k in lo..hi {
            self.set(j, k, 0.0);
        }
        for k in self.lead..self.n {
            self.set(j, k, 0.0);
        }
        self.set(j, j, 1.0);
    }

    /// `hᵀAh`.
    pub fn quadratic_form(&self, h: &[f64]) -> f64 {
        let mut sum = 0.0;
        for i in 0..self.n {
            // The diagonal once, the lower entries twice.
            let lo = if i < self.lead {
                i.saturating_sub(self.width)
            } else {
                0
            };
            let mut row = 0.0;
            for (j, hj) in h.iter().enumerate().take(i).skip(lo) {
                row += self.get(i, j) * hj;
            }
            sum += h[i] * (2.0 * row + self.get(i, i) * h[i]);
        }
        sum
    }

    /// Solves `A x = r` in place (`r` becomes `x`) for `A` symmetric
    /// positive definite, consuming `self` as workspace (its entries are
    /// overwritten by the factor). Returns `false` if `A` is not
    /// numerically positive definite.
    pub fn solve(&mut self, r: &mut [f64]) -> bool {
        let (n, lead, b) = (self.n, self.lead, self.width);
        let k = n - lead;
        debug_assert!(r.len() >= n);
        // Band Cholesky B = LLᵀ, L stored in the band.
        for i in 0..lead {
            let lo = i.saturating_sub(b);
            for j in lo..=i {
                let mut s = self.band[i * (b + 1) + (i - j)];
                let lo2 = lo.max(j.saturating_sub(b));
                for p in lo2..j {
                    s -= self.band[i * (b + 1) + (i - p)] * self.band[j * (b + 1) + (j - p)];
                }
                if i == j {
                    if s.is_nan() || s <= 0.0 || !s.is_finite() {
                        return false;
                    }
                    self.band[i * (b + 1)] = s.sqrt();
                } else {
                    self.band[i * (b + 1) + (i - j)] = s / self.band[j * (b + 1)];
                }
            }
        }
        // z = B⁻¹ r₁ and the columns of Z = B⁻¹Cᵀ, by the factor.
        let mut z = r[..lead].to_vec();
        self.band_solve(&mut z);
        let mut cols: Vec<Vec<f64>> = (0..k)
            .map(|q| {
                let mut c = self.border[q * n..q * n + lead].to_vec();
                self.band_solve(&mut c);
                c
            })
            .collect();
        if k > 0 {
            // S = D − C Z, rhs = r₂ − C z.
            let mut s = vec![0.0; k * k];
            let mut rhs = vec![0.0; k];
            for p in 0..k {
                let cp = &self.border[p * n..p * n + lead];
                rhs[p] = r[lead + p] - dot_plain(cp, &z);
                for q in 0..k {
                    s[p * k + q] = self.get(lead + p, lead + q) - dot_plain(cp, &cols[q]);
                }
            }
            if !super::cholesky_solve(&mut s, &mut rhs, k) {
                return false;
            }
            for (i, zi) in z.iter_mut().enumerate() {
                for (q, c) in cols.iter_mut().enumerate() {
                    *zi -= c[i] * rhs[q];
                }
            }
            r[lead..n].copy_from_slice(&rhs);
        }
        cols.clear();
        r[..lead].copy_from_slice(&z);
        r.iter().all(|v| v.is_finite())
    }

    /// Solves `LLᵀ y = y` in place with the band factor.
    fn band_solve(&self, y: &mut [f64]) {
        let b = self.width;
        for i in 0..self.lead {
            let mut s = y[i];
            for (p, yp) in y.iter().enumerate().take(i).skip(i.saturating_sub(b)) {
                s -= self.band[i * (b + 1) + (i - p)] * yp;
            }
            y[i] = s / self.band[i * (b + 1)];
        }
        for i in (0..self.lead).rev() {
            let mut s = y[i];
            let hi = (i + b + 1).min(self.lead);
            for (p, yp) in y.iter().enumerate().take(hi).skip(i + 1) {
                s -= self.band[p * (b + 1) + (p - i)] * yp;
            }
            y[i] = s / self.band[i * (b + 1)];
        }
    }
}

/// `Σ a_i b_i` in index order.
fn dot_plain(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic sequence in `[-1, 1)` (a 64-bit LCG, Knuth's MMIX constants).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A random SPD matrix with the structure, and its dense copy.
    fn random(n: usize, width: usize, border: usize, seed: u64) -> (BandedArrow, Vec<f64>) {
        let mut rng = Lcg(seed);
        let mut a = BandedArrow::new(n, width, border);
        let lead = n - border;
        // A = Σ v vᵀ over vectors supported on the structure, plus the identity.
        for start in 0..lead {
            let mut idx: Vec<usize> = (start..(start + width + 1).min(lead)).collect();
            idx.extend(lead..n);
            let v: Vec<f64> = idx.iter().map(|_| rng.next()).collect();
            for (p, &i) in idx.iter().enumerate() {
                for (q, &j) in idx.iter().enumerate().take(p + 1) {
                    a.add(i, j, v[p] * v[q]);
                }
            }
        }
        for i in 0..n {
            a.add(i, i, 0.5);
        }
        let dense = (0..n * n).map(|e| a.get(e / n, e % n)).collect();
        (a, dense)
    }

    #[test]
    fn solves_like_the_dense_cholesky() {
        for (n, width, border, seed) in [(12, 3, 2, 1), (30, 7, 1, 2), (9, 2, 0, 3), (5, 4, 5, 4)] {
            let (a, dense) = random(n, width, border, seed);
            let r: Vec<f64> = (0..n).map(|i| (i as f64 * 0.7).sin()).collect();
            let mut x = r.clone();
            assert!(a.clone().solve(&mut x));
            let mut d = dense.clone();
            let mut y = r.clone();
            assert!(crate::linalg::cholesky_solve(&mut d, &mut y, n));
            for (p, q) in x.iter().zip(&y) {
                assert!((p - q).abs() < 1e-10 * (1.0 + q.abs()), "{p} vs {q}");
            }
            let quad: f64 = (0..n)
                .map(|i| (0..n).map(|j| r[i] * dense[i * n + j] * r[j]).sum::<f64>())
                .sum();
            assert!((a.quadratic_form(&r) - quad).abs() < 1e-10 * quad.abs());
        }
    }

    #[test]
    fn a_fixed_variable_gets_a_zero_step_and_indefinite_is_refused() {
        let (mut a, _) = random(10, 2, 2, 7);
        a.fix(3);
        a.fix(9);
        let mut r = vec![1.0; 10];
        r[3] = 0.0;
        r[9] = 0.0;
        assert!(a.solve(&mut r));
        assert_eq!((r[3], r[9]), (0.0, 0.0));
        let mut bad = BandedArrow::new(3, 1, 1);
        bad.add(0, 0, 1.0);
        bad.add(1, 1, -1.0);
        bad.add(2, 2, 1.0);
        assert!(!bad.solve(&mut [1.0, 1.0, 1.0]));
    }

    #[test]
    #[should_panic(expected = "outside the band")]
    fn an_entry_outside_the_band_is_a_bug() {
        BandedArrow::new(6, 1, 0).add(4, 1, 1.0);
    }
}
