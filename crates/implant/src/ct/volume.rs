//! A CT volume: a regular grid of Hounsfield units, and 2D views of its
//! axial slices.
//!
//! Voxel `(z, y, x)` is stored at `data[(z·ny + y)·nx + x]` (x fastest, as in
//! the `.inv3` `matrix.dat` and in DICOM pixel data). In a slice, `row = y`
//! and `col = x`. The slice frame in millimetres is `x = col·sx`,
//! `y = row·sy` (the image's row direction is +y, so the frame is y-down when
//! shown as an image); in 3D, `z = slice·sz`. These *voxel millimetres* are
//! the frame every computation uses; the volume's [`Frame`] maps them to
//! the scanner's patient coordinates (DICOM PS3.3 C.7.6.2:
//! `P = origin + x·X + y·Y + z·Z` with the unit axes `X`, `Y` of
//! ImageOrientationPatient and `Z` along the slice positions), which is the
//! frame of the written STL.

use super::error::CtError;
use super::mesh::Mesh;
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

/// Where a volume's geometry came from (written into the STL header).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameSource {
    /// Built in memory: origin and axes as given.
    Given,
    /// DICOM ImagePositionPatient and ImageOrientationPatient.
    Dicom,
    /// An InVesalius `.inv3` project: it stores only the spacing and an
    /// orientation flag (the `orientation` key of `main.plist`), so the
    /// origin is 0 and the axes are the voxel axes.
    Inv3 {
        /// The project's `orientation` value, when present.
        orientation: Option<i64>,
    },
}

/// The map from voxel millimetres `(x, y, z) = (col·sx, row·sy, slice·sz)`
/// to patient coordinates: `P = origin + x·axes[0] + y·axes[1] + z·axes[2]`
/// (DICOM PS3.3 C.7.6.2.1.1; the axes are unit vectors, the third one along
/// the slice positions, so a gantry tilt gives a non-orthogonal frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Patient position (mm) of voxel (0, 0, 0).
    pub origin: [f64; 3],
    /// Unit vectors of the column (x), row (y) and slice (z) directions.
    pub axes: [[f64; 3]; 3],
    /// Where the frame came from.
    pub source: FrameSource,
}

/// A direction in the patient: DICOM's patient frame is LPS, `+X` towards
/// the patient's left, `+Y` posterior, `+Z` superior (DICOM PS3.3
/// C.7.6.1.1.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatientDirection {
    /// Towards the patient's left (`+X`).
    Left,
    /// Towards the patient's right (`−X`).
    Right,
    /// Towards the back of the head (`+Y`).
    Posterior,
    /// Towards the face (`−Y`).
    Anterior,
    /// Towards the top of the head (`+Z`).
    Superior,
    /// Towards the feet (`−Z`).
    Inferior,
}

impl PatientDirection {
    /// The direction a patient-frame unit vector mostly points to (its
    /// largest LPS component and that component's sign).
    pub fn of(v: [f64; 3]) -> PatientDirection {
        let i = (0..3)
            .max_by(|&a, &b| v[a].abs().total_cmp(&v[b].abs()))
            .unwrap_or(0);
        let plus = v[i] >= 0.0;
        match (i, plus) {
            (0, true) => PatientDirection::Left,
            (0, false) => PatientDirection::Right,
            (1, true) => PatientDirection::Posterior,
            (1, false) => PatientDirection::Anterior,
            (_, true) => PatientDirection::Superior,
            (_, false) => PatientDirection::Inferior,
        }
    }

    /// The opposite direction.
    pub fn opposite(self) -> PatientDirection {
        use PatientDirection::*;
        match self {
            Left => Right,
            Right => Left,
            Posterior => Anterior,
            Anterior => Posterior,
            Superior => Inferior,
            Inferior => Superior,
        }
    }

    /// The label of a picture's edge: `anterior (face)`, `posterior`,
    /// `left`, `right`, `superior`, `inferior` (left and right are the
    /// patient's).
    pub fn label(self) -> &'static str {
        use PatientDirection::*;
        match self {
            Left => "patient left",
            Right => "patient right",
            Posterior => "posterior",
            Anterior => "anterior (face)",
            Superior => "superior",
            Inferior => "inferior",
        }
    }

    /// The LPS unit vector of the direction.
    fn unit(self) -> [f64; 3] {
        let mut v = [0.0; 3];
        v[self.axis()] = match self {
            PatientDirection::Left | PatientDirection::Posterior | PatientDirection::Superior => {
                1.0
            }
            _ => -1.0,
        };
        v
    }

    /// The LPS axis (0, 1, 2) of the direction.
    fn axis(self) -> usize {
        use PatientDirection::*;
        match self {
            Left | Right => 0,
            Posterior | Anterior => 1,
            Superior | Inferior => 2,
        }
    }
}

/// Where the volume's voxel axes `+x` (columns), `+y` (rows) and `+z`
/// (slices) point in the patient: the one place the pictures' flips and
/// edge labels come from ([`Frame::anatomy`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Anatomy {
    /// The direction of `+x`.
    pub x: PatientDirection,
    /// The direction of `+y`.
    pub y: PatientDirection,
    /// The direction of `+z`.
    pub z: PatientDirection,
}

impl Anatomy {
    /// Whether `+x`, `+y`, `+z` form a right-handed frame in the patient
    /// (as LPS does): the determinant of their LPS unit vectors is +1. A
    /// left-handed volume (an `.inv3`'s rows flipped, say) drawn with a
    /// right-handed camera would show a mirror image.
    pub fn right_handed(&self) -> bool {
        det3([self.x.unit(), self.y.unit(), self.z.unit()]) > 0.0
    }
}

/// The anatomy an `.inv3` project declares by convention (it stores no
/// patient axes): InVesalius flips the rows of the axial DICOM series it
/// imports, so `+y` is anterior (the face, as in ProMED CT 0051), `+x` the
/// patient's left and `+z` superior (RECONSTRUCTION: the convention of the
/// InVesalius import, not a field of the file).
pub const INV3_ANATOMY: Anatomy = Anatomy {
    x: PatientDirection::Left,
    y: PatientDirection::Anterior,
    z: PatientDirection::Superior,
};

/// The identity axes.
pub const IDENTITY_AXES: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[1][0] * (m[0][1] * m[2][2] - m[0][2] * m[2][1])
        + m[2][0] * (m[0][1] * m[1][2] - m[0][2] * m[1][1])
}

impl Frame {
    /// The patient position of the voxel-millimetre point `p`.
    pub fn to_patient(&self, p: [f64; 3]) -> [f64; 3] {
        let a = self.axes;
        std::array::from_fn(|i| self.origin[i] + p[0] * a[0][i] + p[1] * a[1][i] + p[2] * a[2][i])
    }

    /// The voxel-millimetre point of the patient position `q` (the inverse
    /// of [`Frame::to_patient`], by Cramer's rule).
    pub fn to_voxel_mm(&self, q: [f64; 3]) -> [f64; 3] {
        let d: [f64; 3] = std::array::from_fn(|i| q[i] - self.origin[i]);
        let det = det3(self.axes);
        std::array::from_fn(|k| {
            let mut m = self.axes;
            m[k] = d;
            det3(m) / det
        })
    }

    /// A mesh in voxel millimetres moved into patient coordinates (a frame
    /// with a negative determinant reverses the triangles so that they stay
    /// outward oriented).
    pub fn mesh_to_patient(&self, mesh: &Mesh) -> Mesh {
        let flip = det3(self.axes) < 0.0;
        Mesh {
            vertices: mesh.vertices.iter().map(|&v| self.to_patient(v)).collect(),
            triangles: mesh
                .triangles
                .iter()
                .map(|&[a, b, c]| if flip { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// A mesh in patient coordinates moved back into voxel millimetres.
    pub fn mesh_to_voxel_mm(&self, mesh: &Mesh) -> Mesh {
        let flip = det3(self.axes) < 0.0;
        Mesh {
            vertices: mesh.vertices.iter().map(|&v| self.to_voxel_mm(v)).collect(),
            triangles: mesh
                .triangles
                .iter()
                .map(|&[a, b, c]| if flip { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// Where the voxel axes point in the patient: from the axes
    /// (ImageOrientationPatient and the slice positions, already in the
    /// LPS patient frame) for DICOM and a given frame, from
    /// [`INV3_ANATOMY`] for an `.inv3`. Errors with
    /// [`CtError::AmbiguousOrientation`] when two axes point mostly along
    /// the same patient axis (an orientation that is not orthogonal).
    pub fn anatomy(&self) -> Result<Anatomy, CtError> {
        if let FrameSource::Inv3 { .. } = self.source {
            return Ok(INV3_ANATOMY);
        }
        let [x, y, z] = self.axes.map(PatientDirection::of);
        if x.axis() == y.axis() || x.axis() == z.axis() || y.axis() == z.axis() {
            return Err(CtError::AmbiguousOrientation { axes: self.axes });
        }
        Ok(Anatomy { x, y, z })
    }

    /// A one-line description for an 80-byte STL header: the frame's source
    /// and origin.
    pub fn stl_header(&self) -> String {
        let o = self.origin;
        match self.source {
            FrameSource::Dicom => format!(
                "metabezier implant, mm, DICOM patient frame, origin {:.2} {:.2} {:.2}",
                o[0], o[1], o[2]
            ),
            FrameSource::Inv3 { .. } => {
                "metabezier implant, mm, .inv3 has no origin: origin 0, voxel axes".to_string()
            }
            FrameSource::Given => format!(
                "metabezier implant, mm, frame origin {:.2} {:.2} {:.2}",
                o[0], o[1], o[2]
            ),
        }
    }
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
    /// Unit vectors of the column, row and slice directions in patient
    /// coordinates (identity unless read from DICOM or set by
    /// [`Volume::with_frame`]).
    pub axes: [[f64; 3]; 3],
    /// Where the origin and axes came from.
    pub frame_source: FrameSource,
    /// Whether `spacing.z` is the study's own: false for a one-slice DICOM
    /// study without SliceThickness (0018,0050), whose 1 mm is a
    /// placeholder (a one-slice design then needs `[defect] thickness_mm`).
    pub z_spacing_known: bool,
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
            axes: IDENTITY_AXES,
            frame_source: FrameSource::Given,
            z_spacing_known: true,
            data,
        })
    }

    /// The same volume placed in patient coordinates by `origin` and `axes`
    /// (normalised here); fails with [`CtError::BadAxes`] when an axis is
    /// zero or not finite or the three are (nearly) coplanar.
    pub fn with_frame(
        mut self,
        origin: [f64; 3],
        axes: [[f64; 3]; 3],
        source: FrameSource,
    ) -> Result<Volume, CtError> {
        let mut unit = axes;
        for a in unit.iter_mut() {
            let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            if !(l.is_finite() && l > 0.0) || origin.iter().any(|o| !o.is_finite()) {
                return Err(CtError::BadAxes { axes });
            }
            a.iter_mut().for_each(|c| *c /= l);
        }
        if det3(unit).abs() < 0.1 {
            return Err(CtError::BadAxes { axes });
        }
        self.origin = origin;
        self.axes = unit;
        self.frame_source = source;
        Ok(self)
    }

    /// The volume's frame: voxel millimetres to patient coordinates.
    pub fn frame(&self) -> Frame {
        Frame {
            origin: self.origin,
            axes: self.axes,
            source: self.frame_source,
        }
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

    /// A copy with the samples `data` (same size, spacing and frame); panics
    /// when the length differs.
    pub fn with_data(&self, data: Vec<i16>) -> Volume {
        assert_eq!(data.len(), self.data.len(), "sample count");
        Volume {
            data,
            ..self.clone()
        }
    }

    /// A copy with every slice rotated in its plane by `angle_deg` (counter-
    /// clockwise in the `(x, y)` frame, x towards y) about the millimetre
    /// point `centre`: each output pixel samples the input at the inversely
    /// rotated position by bilinear interpolation (−1024 HU, air, outside).
    /// Used to test the tilted midline on a head turned by a known angle.
    pub fn rotated_in_plane(&self, angle_deg: f64, centre: Point) -> Volume {
        let (s, c) = angle_deg.to_radians().sin_cos();
        let (sx, sy) = (self.spacing.x, self.spacing.y);
        let mut data = Vec::with_capacity(self.data.len());
        for z in 0..self.nz {
            let sl = self.slice(z);
            for r in 0..self.ny {
                for col in 0..self.nx {
                    let d = Point::new(col as f64 * sx, r as f64 * sy) - centre;
                    let q = centre + Point::new(c * d.x + s * d.y, -s * d.x + c * d.y);
                    data.push(sl.bilinear(q.y / sy, q.x / sx, -1024.0).round() as i16);
                }
            }
        }
        self.with_data(data)
    }

    /// A copy of slices `z0..z1` (origin moved by `z0·sz` along the slice
    /// axis); panics when the
    /// range is empty or out of bounds.
    pub fn sub_z(&self, z0: usize, z1: usize) -> Volume {
        assert!(z0 < z1 && z1 <= self.nz, "bad slice range {z0}..{z1}");
        let n = self.nx * self.ny;
        let origin = self
            .frame()
            .to_patient([0.0, 0.0, z0 as f64 * self.spacing.z]);
        Volume {
            nx: self.nx,
            ny: self.ny,
            nz: z1 - z0,
            spacing: self.spacing,
            origin,
            axes: self.axes,
            frame_source: self.frame_source,
            z_spacing_known: self.z_spacing_known,
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

    /// The HU value at the fractional `(row, col)` by bilinear
    /// interpolation of the pixel centres; `outside` beyond the image.
    pub fn bilinear(&self, row: f64, col: f64, outside: f64) -> f64 {
        let (r0, c0) = (row.floor(), col.floor());
        let (fr, fc) = (row - r0, col - c0);
        let at = |r: f64, c: f64| {
            if r < 0.0 || c < 0.0 || r >= self.ny as f64 || c >= self.nx as f64 {
                outside
            } else {
                self.get(r as usize, c as usize) as f64
            }
        };
        let top = at(r0, c0) * (1.0 - fc) + at(r0, c0 + 1.0) * fc;
        let bottom = at(r0 + 1.0, c0) * (1.0 - fc) + at(r0 + 1.0, c0 + 1.0) * fc;
        top * (1.0 - fr) + bottom * fr
    }

    /// The fractional `(row, col)` of the millimetre point `p`
    /// (inverse of [`Slice::to_mm`]).
    #[inline]
    pub fn to_pixel(&self, p: Point) -> (f64, f64) {
        (p.y / self.sy, p.x / self.sx)
    }
}
