//! The rotation `y = M d` of a rotated instance, laid out and computed for
//! the cache and the vector lanes, with the bits of the plain left-to-right
//! sums.
//!
//! Each `y_i = Σ_j M_ij d_j` is summed left to right, `j = 0, 1, …` (the
//! order that fixes the bits of every campaign). Summed one row after the
//! other, each sum waits on its own additions; summed one column at a time
//! into all of `y` (as before), every step loads and stores `y` from
//! memory, which bounds the product by the stores. Here the rows are taken
//! in *panels* of `B` rows held in registers: for each panel, the columns
//! stream through it, `acc[k] += M_{i₀+k, j}·d_j`, and the panel is stored
//! once. `M` is stored panel by panel, column by column within a panel,
//! its last panel padded with zero rows, so that the stream is contiguous
//! (the blocking of Goto & van de Geijn 2008, "Anatomy of high-performance
//! matrix multiplication", ACM TOMS 34(3), reduced to a matrix-vector
//! product). The kernel is compiled for the CPU's vector level
//! ([`crate::simd::dispatch`]); no sum is reassociated and no
//! multiply-add is fused, so the bits are those of the plain loop on every
//! level.

/// `M` (`d × d`) in panels of [`Panels::block`] rows.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Panels {
    dim: usize,
    block: usize,
    data: Vec<f64>,
}

impl Panels {
    /// The panels of the row-major `d × d` matrix `m` (empty for empty):
    /// 8, 16 or 32 rows each, the smallest that holds `d` (32 above 16).
    pub(crate) fn new(m: &[f64], d: usize) -> Panels {
        let block = match d {
            0..=8 => 8,
            9..=16 => 16,
            _ => 32,
        };
        let count = if m.is_empty() { 0 } else { d.div_ceil(block) };
        let mut data = vec![0.0; count * d * block];
        for p in 0..count {
            for j in 0..d {
                for k in 0..block {
                    let i = p * block + k;
                    if i < d {
                        data[(p * d + j) * block + k] = m[i * d + j];
                    }
                }
            }
        }
        Panels {
            dim: d,
            block,
            data,
        }
    }

    /// Whether there is no matrix (an instance without a rotation).
    pub(crate) fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// `y = M d` (`d` and `y` of length `dim`), each `y_i` the
    /// left-to-right sum `(…((0 + M_i0 d_0) + M_i1 d_1) + …)`.
    #[inline]
    pub(crate) fn apply(&self, d: &[f64], y: &mut [f64]) {
        let (d, y) = (&d[..self.dim], &mut y[..self.dim]);
        crate::simd::dispatch(
            #[inline(always)]
            |_| match self.block {
                8 => product::<8>(&self.data, d, y),
                16 => product::<16>(&self.data, d, y),
                _ => product::<32>(&self.data, d, y),
            },
        )
    }
}

/// `y = M d` from `M`'s panels of `B` rows (see the module).
#[inline(always)]
fn product<const B: usize>(data: &[f64], d: &[f64], y: &mut [f64]) {
    let dim = d.len();
    for (panel, out) in data.chunks_exact(dim * B).zip(y.chunks_mut(B)) {
        let mut acc = [0.0f64; B];
        for (column, &dj) in panel.chunks_exact(B).zip(d) {
            let column: &[f64; B] = column.try_into().expect("chunks of B");
            for (a, &m) in acc.iter_mut().zip(column) {
                *a += m * dj;
            }
        }
        for (o, a) in out.iter_mut().zip(acc) {
            *o = a;
        }
    }
}
