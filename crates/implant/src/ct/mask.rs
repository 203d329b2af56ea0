//! Binary voxel masks: 2D (one slice) and 3D (a stack, with its spacing).

use super::volume::Spacing;

/// A binary image of `ny` rows by `nx` columns, row-major.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Mask2 {
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// Row-major flags, `ny·nx`.
    pub data: Vec<bool>,
}

impl Mask2 {
    /// An all-false mask.
    pub fn new(nx: usize, ny: usize) -> Mask2 {
        Mask2 {
            nx,
            ny,
            data: vec![false; nx * ny],
        }
    }

    /// The mask `f(row, col)`.
    pub fn from_fn(nx: usize, ny: usize, f: impl Fn(usize, usize) -> bool) -> Mask2 {
        let mut m = Mask2::new(nx, ny);
        for r in 0..ny {
            for c in 0..nx {
                m.data[r * nx + c] = f(r, c);
            }
        }
        m
    }

    /// The flag at `(row, col)`; panics when out of range.
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> bool {
        assert!(row < self.ny && col < self.nx, "pixel out of range");
        self.data[row * self.nx + col]
    }

    /// The flag at signed `(row, col)`, false outside the image.
    #[inline]
    pub fn get_or_false(&self, row: i64, col: i64) -> bool {
        row >= 0
            && col >= 0
            && (row as usize) < self.ny
            && (col as usize) < self.nx
            && self.data[row as usize * self.nx + col as usize]
    }

    /// Sets the flag at `(row, col)`.
    #[inline]
    pub fn set(&mut self, row: usize, col: usize, v: bool) {
        assert!(row < self.ny && col < self.nx, "pixel out of range");
        self.data[row * self.nx + col] = v;
    }

    /// Number of true pixels.
    pub fn count(&self) -> usize {
        self.data.iter().filter(|&&b| b).count()
    }

    /// The true pixels as `(row, col)`, row-major order.
    pub fn pixels(&self) -> Vec<(usize, usize)> {
        (0..self.data.len())
            .filter(|&i| self.data[i])
            .map(|i| (i / self.nx, i % self.nx))
            .collect()
    }
}

/// A binary volume of `nz` slices of `ny × nx`, z/y/x order, with spacing.
#[derive(Clone, Debug, PartialEq)]
pub struct Mask3 {
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// Slices.
    pub nz: usize,
    /// Voxel spacing in mm.
    pub spacing: Spacing,
    /// Flags, `(z·ny + y)·nx + x`.
    pub data: Vec<bool>,
}

impl Mask3 {
    /// An all-false mask.
    pub fn new(nx: usize, ny: usize, nz: usize, spacing: Spacing) -> Mask3 {
        Mask3 {
            nx,
            ny,
            nz,
            spacing,
            data: vec![false; nx * ny * nz],
        }
    }

    /// The mask `f(z, y, x)`.
    pub fn from_fn(
        nx: usize,
        ny: usize,
        nz: usize,
        spacing: Spacing,
        f: impl Fn(usize, usize, usize) -> bool,
    ) -> Mask3 {
        let mut m = Mask3::new(nx, ny, nz, spacing);
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    m.data[(z * ny + y) * nx + x] = f(z, y, x);
                }
            }
        }
        m
    }

    /// A stack of equally sized 2D masks.
    pub fn from_slices(slices: &[Mask2], spacing: Spacing) -> Mask3 {
        assert!(!slices.is_empty(), "no slices");
        let (nx, ny) = (slices[0].nx, slices[0].ny);
        let mut data = Vec::with_capacity(nx * ny * slices.len());
        for s in slices {
            assert!(s.nx == nx && s.ny == ny, "slice sizes differ");
            data.extend_from_slice(&s.data);
        }
        Mask3 {
            nx,
            ny,
            nz: slices.len(),
            spacing,
            data,
        }
    }

    /// The linear index of `(z, y, x)`.
    #[inline]
    pub fn index(&self, z: usize, y: usize, x: usize) -> usize {
        (z * self.ny + y) * self.nx + x
    }

    /// The flag at `(z, y, x)`; panics when out of range.
    #[inline]
    pub fn get(&self, z: usize, y: usize, x: usize) -> bool {
        assert!(
            z < self.nz && y < self.ny && x < self.nx,
            "voxel out of range"
        );
        self.data[self.index(z, y, x)]
    }

    /// Sets the flag at `(z, y, x)`.
    #[inline]
    pub fn set(&mut self, z: usize, y: usize, x: usize, v: bool) {
        let i = self.index(z, y, x);
        self.data[i] = v;
    }

    /// Slice `z` as a 2D mask.
    pub fn slice(&self, z: usize) -> Mask2 {
        let n = self.nx * self.ny;
        Mask2 {
            nx: self.nx,
            ny: self.ny,
            data: self.data[z * n..(z + 1) * n].to_vec(),
        }
    }

    /// Number of true voxels.
    pub fn count(&self) -> usize {
        self.data.iter().filter(|&&b| b).count()
    }

    /// Whether `other` has the same grid (sizes; spacing equal).
    pub fn same_grid(&self, other: &Mask3) -> bool {
        self.nx == other.nx
            && self.ny == other.ny
            && self.nz == other.nz
            && self.spacing == other.spacing
    }
}
