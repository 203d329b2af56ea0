//! A CT volume: a regular grid of Hounsfield units, and 2D views of its
//! axial slices.
//!
//! Voxel `(z, y, x)` is stored at `data[(z·ny + y)·nx + x]` (x fastest, as in
//! the `.inv3` `matrix.dat` and in DICOM pixel data). In a slice, `row = y`
//! and `col = x`. The slice frame in millimetres is `x = col·sx`,
//! `y = row·sy` (the image's row direction is +y, so the frame is y-down when
//! shown as an image); the volume origin is not added.

use super::error::CtError;
use crate::geometry::Point;

/// Voxel spacing in millimetres along x (columns), y (rows) and z (slices).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spacing {
    /// Column spacing in mm.
    pub x: f64,
    /// Row spacing in mm.
    pub y: f64,
    /// Slice spacing in mm.
    pub z: f64,
}

/// A CT volume of `nz` axial slices of `ny` rows by `nx` columns, in HU.
#[derive(Clone, Debug, PartialEq)]
pub struct Volume {
    /// Columns per slice.
    pub nx: usize,
    /// Rows per slice.
    pub ny: usize,
    /// Number of slices.
    pub nz: usize,
    /// Voxel spacing in mm.
    pub spacing: Spacing,
    /// Position (x, y, z) in mm of voxel (0, 0, 0), in the scanner frame when
    /// known (DICOM ImagePositionPatient), else zero.
    pub origin: [f64; 3],
    data: Vec<i16>,
}

impl Volume {
    /// A volume from its samples in z/y/x order; fails unless
    /// `data.len() = nx·ny·nz`, every size is positive and the spacing is
    /// positive and finite.
    pub fn new(
        nx: usize,
        ny: usize,
        nz: usize,
        spacing: Spacing,
        origin: [f64; 3],
        data: Vec<i16>,
    ) -> Result<Volume, CtError> {
        if nx == 0 || ny == 0 || nz == 0 {
            return Err(CtError::ZeroDimension { nx, ny, nz });
        }
        let n = nx
            .checked_mul(ny)
            .and_then(|v| v.checked_mul(nz))
            .ok_or(CtError::VolumeOverflow { nx, ny, nz })?;
        if data.len() != n {
            return Err(CtError::VoxelCount {
                nx,
                ny,
                nz,
                expected: n,
                found: data.len(),
            });
        }
        for s in [spacing.x, spacing.y, spacing.z] {
            if !(s.is_finite() && s > 0.0) {
                return Err(CtError::BadSpacing { value: s });
            }
        }
        Ok(Volume {
            nx,
            ny,
            nz,
            spacing,
            origin,
            data,
        })
    }

    /// All samples, z/y/x order.
    pub fn data(&self) -> &[i16] {
        &self.data
    }

    /// The HU value of voxel `(z, y, x)`; panics when out of range.
    #[inline]
    pub fn get(&self, z: usize, y: usize, x: usize) -> i16 {
        assert!(
            z < self.nz && y < self.ny && x < self.nx,
            "voxel out of range"
        );
        self.data[(z * self.ny + y) * self.nx + x]
    }

    /// The axial slice `z` as a 2D view; panics when `z ≥ nz`.
    pub fn slice(&self, z: usize) -> Slice<'_> {
        assert!(z < self.nz, "slice {z} out of range 0..{}", self.nz);
        let n = self.nx * self.ny;
        Slice {
            z,
            nx: self.nx,
            ny: self.ny,
            sx: self.spacing.x,
            sy: self.spacing.y,
            data: &self.data[z * n..(z + 1) * n],
        }
    }

    /// A copy of slices `z0..z1` (origin moved by `z0·sz`); panics when the
    /// range is empty or out of bounds.
    pub fn sub_z(&self, z0: usize, z1: usize) -> Volume {
        assert!(z0 < z1 && z1 <= self.nz, "bad slice range {z0}..{z1}");
        let n = self.nx * self.ny;
        let mut origin = self.origin;
        origin[2] += z0 as f64 * self.spacing.z;
        Volume {
            nx: self.nx,
            ny: self.ny,
            nz: z1 - z0,
            spacing: self.spacing,
            origin,
            data: self.data[z0 * n..z1 * n].to_vec(),
        }
    }
}

/// A borrowed axial slice: `ny` rows by `nx` columns of HU.
#[derive(Clone, Copy, Debug)]
pub struct Slice<'a> {
    /// Index of the slice in its volume.
    pub z: usize,
    /// Columns.
    pub nx: usize,
    /// Rows.
    pub ny: usize,
    /// Column spacing in mm.
    pub sx: f64,
    /// Row spacing in mm.
    pub sy: f64,
    /// Row-major samples, `ny·nx`.
    pub data: &'a [i16],
}

impl Slice<'_> {
    /// The HU value at `(row, col)`; panics when out of range.
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> i16 {
        assert!(row < self.ny && col < self.nx, "pixel out of range");
        self.data[row * self.nx + col]
    }

    /// The millimetre position `(col·sx, row·sy)` of pixel centre `(row, col)`
    /// (fractional indices allowed).
    #[inline]
    pub fn to_mm(&self, row: f64, col: f64) -> Point {
        Point::new(col * self.sx, row * self.sy)
    }

    /// The fractional `(row, col)` of the millimetre point `p`
    /// (inverse of [`Slice::to_mm`]).
    #[inline]
    pub fn to_pixel(&self, p: Point) -> (f64, f64) {
        (p.y / self.sy, p.x / self.sx)
    }
}
