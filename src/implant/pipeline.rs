//! The real-defect pipeline: per-slice contours and defect ends, the
//! mid-sagittal line, one [`Wall`] per slice, the lofted mesh and its
//! voxelisation (thesis chapter 6).

use super::wall::{reconstruct_wall, Wall, WallInput, WallKind, WallOptions};
use crate::ct::{
    bone_loops, bone_mask_slice, detect_defect, estimate_midline, loft, table_contours, voxelise,
    CtError, DefectParams, Mask2, Mask3, Mesh, Polyline, Volume,
};
use crate::files::IoError;
use crate::fit::SegmentSolver;
use crate::geometry::Point;
use crate::stats::StatsError;

/// How a slice's defect ends are found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ends {
    /// Given as pixels `(row, col)`, as the thesis's user clicks them.
    Pixels {
        /// A as (row, col).
        a: (f64, f64),
        /// B as (row, col).
        b: (f64, f64),
    },
    /// Detected by [`crate::ct::detect_defect`] on the slice's bone mask.
    Auto,
}

/// The mid-sagittal line.
#[derive(Clone, Debug, PartialEq)]
pub enum MidlineSpec {
    /// Given: `x = M_x` in mm.
    Given(f64),
    /// Estimated by [`crate::ct::estimate_midline`] from the bone masks of
    /// these slices (volume numbering; empty = the defect slices).
    Auto(Vec<usize>),
}

/// One slice to reconstruct.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceSpec {
    /// The slice index in the original numbering (volume index + `first_z`).
    pub z: usize,
    /// Its defect ends.
    pub ends: Ends,
}

/// Everything the real-defect pipeline needs besides the volume and solver.
#[derive(Clone, Debug, PartialEq)]
pub struct DefectConfig {
    /// The original index of the volume's slice 0 (40 for the vendored
    /// CT 0051 extract).
    pub first_z: usize,
    /// The defect slices, increasing `z`, consecutive or not.
    pub slices: Vec<SliceSpec>,
    /// The mid-sagittal line.
    pub midline: MidlineSpec,
    /// The bone threshold in HU.
    pub threshold: i16,
    /// The wall options.
    pub wall: WallOptions,
    /// Points per ring of the lofted mesh.
    pub ring_points: usize,
}

/// An error of the implant pipeline, naming the slice it concerns.
#[derive(Debug, thiserror::Error)]
pub enum ImplantError {
    /// A CT-layer error not tied to one slice (reading the volume, writing).
    #[error(transparent)]
    Ct(#[from] CtError),
    /// An output file or directory could not be written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// An error on one slice (original numbering).
    #[error("{}", slice_message(*z, source))]
    Slice {
        /// The slice.
        z: usize,
        /// What went wrong there.
        #[source]
        source: CtError,
    },
    /// A slice lies outside the volume.
    #[error(
        "{what} z = {z} is outside the volume (it holds z = {}..={})",
        first,
        last
    )]
    SliceOutside {
        /// Which slice: "slice" or "validation slice".
        what: &'static str,
        /// The slice asked for (original numbering).
        z: usize,
        /// The volume's first slice.
        first: usize,
        /// The volume's last slice.
        last: usize,
    },
    /// None of the slices of the midline estimate holds bone.
    #[error("cannot estimate the midline: no bone in its slices")]
    NoMidline,
    /// Fewer than two defect slices.
    #[error("an implant needs at least two defect slices")]
    TooFewSlices,
    /// The defect slices do not increase strictly.
    #[error("the defect slices must increase strictly in z")]
    SlicesNotIncreasing,
    /// The lofted mesh failed its checks, so no STL is written.
    #[error("the lofted implant mesh is not watertight and consistently oriented; no STL written")]
    BadMesh {
        /// Vertices of the mesh.
        vertices: usize,
        /// Triangles of the mesh.
        triangles: usize,
        /// Whether every edge is shared by exactly two triangles.
        watertight: bool,
        /// Whether every directed edge appears once and the volume is positive.
        oriented: bool,
    },
    /// A statistic of the validation could not be computed.
    #[error("statistics: {0}")]
    Stats(#[from] StatsError),
}

/// The message of an error on slice `z`.
fn slice_message(z: usize, source: &CtError) -> String {
    match source {
        // NoBone already names its slice (volume index): say both.
        CtError::NoBone { threshold, .. } => format!(
            "slice z = {z}: no bone: no voxel at or above {threshold} HU (lower `threshold` or check the slice range)"
        ),
        e => format!("slice z = {z}: {e}"),
    }
}

/// One reconstructed slice.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceResult {
    /// The slice (original numbering).
    pub z: usize,
    /// A and B as given or detected, in mm.
    pub ends_mm: (Point, Point),
    /// The intact outer table (open arc from one defect end to the other).
    pub outer: Polyline,
    /// The inner table arc.
    pub inner: Polyline,
    /// `M_x` in mm.
    pub midline_x: f64,
    /// The reconstructed cross-section.
    pub wall: Wall,
}

/// The reconstructed implant.
#[derive(Clone, Debug, PartialEq)]
pub struct Implant {
    /// Per slice, increasing `z`.
    pub slices: Vec<SliceResult>,
    /// `M_x` in mm.
    pub midline_x: f64,
    /// The reflection Dice of the midline estimate (`None` when given).
    pub midline_dice: Option<f64>,
    /// The closed, outward-oriented implant mesh in mm (`z = index·s_z`,
    /// volume indices).
    pub mesh: Mesh,
    /// The implant voxelised on the volume grid.
    pub mask: Mask3,
}

fn index_of(cfg: &DefectConfig, volume: &Volume, z: usize) -> Result<usize, ImplantError> {
    z.checked_sub(cfg.first_z)
        .filter(|&k| k < volume.nz)
        .ok_or_else(|| ImplantError::SliceOutside {
            what: "slice",
            z,
            first: cfg.first_z,
            last: cfg.first_z + volume.nz - 1,
        })
}

/// The bone mask of slice `z` (original numbering).
pub fn slice_mask(volume: &Volume, cfg: &DefectConfig, z: usize) -> Result<Mask2, ImplantError> {
    let k = index_of(cfg, volume, z)?;
    bone_mask_slice(&volume.slice(k), cfg.threshold)
        .map_err(|source| ImplantError::Slice { z, source })
}

/// Resolves the mid-sagittal line: given, or estimated from the masks of the
/// configured slices. Returns `(M_x, reflection Dice)`.
pub fn resolve_midline(
    volume: &Volume,
    cfg: &DefectConfig,
) -> Result<(f64, Option<f64>), ImplantError> {
    match &cfg.midline {
        MidlineSpec::Given(x) => Ok((*x, None)),
        MidlineSpec::Auto(zs) => {
            let zs: Vec<usize> = if zs.is_empty() {
                cfg.slices.iter().map(|s| s.z).collect()
            } else {
                zs.clone()
            };
            let masks = zs
                .iter()
                .map(|&z| slice_mask(volume, cfg, z))
                .collect::<Result<Vec<_>, _>>()?;
            let m = estimate_midline(&masks, volume.spacing.x).ok_or(ImplantError::NoMidline)?;
            Ok((m.x, Some(m.dice)))
        }
    }
}

/// Reconstructs one defect slice with `kind` (see [`reconstruct_wall`]).
pub fn reconstruct_slice<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    spec: &SliceSpec,
    midline_x: f64,
    kind: WallKind,
    solver: &mut S,
) -> Result<SliceResult, ImplantError> {
    let z = spec.z;
    let at = |source: CtError| ImplantError::Slice { z, source };
    let k = index_of(cfg, volume, z)?;
    let slice = volume.slice(k);
    let mask = bone_mask_slice(&slice, cfg.threshold).map_err(at)?;
    let (sx, sy) = (slice.sx, slice.sy);
    let (a, b) = match spec.ends {
        Ends::Pixels { a, b } => (
            Point::new(a.1 * sx, a.0 * sy),
            Point::new(b.1 * sx, b.0 * sy),
        ),
        Ends::Auto => {
            let d = detect_defect(&mask, sx, sy, &DefectParams::default())
                .ok_or_else(|| at(CtError::NoDefectFound))?;
            (d.a_mm, d.b_mm)
        }
    };
    let loops = bone_loops(&slice, &mask, cfg.threshold);
    let tables = table_contours(&loops, Some((a, b))).map_err(at)?;
    let centre = Point::new(midline_x, tables.outer.vertex_mean().y);
    let is_bone = |p: Point| {
        let (r, c) = ((p.y / sy).round(), (p.x / sx).round());
        r >= 0.0 && c >= 0.0 && mask.get_or_false(r as i64, c as i64)
    };
    let outer = [&tables.outer];
    let input = WallInput {
        outer: &outer,
        is_bone: &is_bone,
        centre,
        midline_x,
        a,
        b,
    };
    let wall = reconstruct_wall(&input, kind, &cfg.wall, solver).map_err(at)?;
    Ok(SliceResult {
        z,
        ends_mm: (a, b),
        outer: tables.outer,
        inner: tables.inner,
        midline_x,
        wall,
    })
}

/// Lofts the slices' sections into a closed mesh (`z = index·s_z`) and
/// voxelises them on the volume grid.
pub fn build_mesh(
    volume: &Volume,
    cfg: &DefectConfig,
    slices: &[SliceResult],
) -> Result<(Mesh, Mask3), ImplantError> {
    let mut sections = Vec::with_capacity(slices.len());
    let mut zs = Vec::with_capacity(slices.len());
    let mut vox = Vec::with_capacity(slices.len());
    for s in slices {
        let k = index_of(cfg, volume, s.z)?;
        sections.push(s.wall.section.clone());
        zs.push(k as f64 * volume.spacing.z);
        vox.push((k, s.wall.section.clone()));
    }
    let mesh = loft(&sections, &zs, cfg.ring_points)?;
    let mask = voxelise(&vox, volume.nx, volume.ny, volume.nz, volume.spacing);
    Ok((mesh, mask))
}

/// The whole real-defect pipeline on a loaded volume: midline, every slice
/// with the curve fit, mesh and voxels. The solver is shared by the slices
/// in order (one random stream for a seeded metaheuristic).
pub fn reconstruct_defect<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    solver: &mut S,
) -> Result<Implant, ImplantError> {
    if cfg.slices.len() < 2 {
        return Err(ImplantError::TooFewSlices);
    }
    if cfg.slices.windows(2).any(|w| w[1].z <= w[0].z) {
        return Err(ImplantError::SlicesNotIncreasing);
    }
    let (midline_x, midline_dice) = resolve_midline(volume, cfg)?;
    let slices = cfg
        .slices
        .iter()
        .map(|s| reconstruct_slice(volume, cfg, s, midline_x, WallKind::CurveFit, solver))
        .collect::<Result<Vec<_>, _>>()?;
    let (mesh, mask) = build_mesh(volume, cfg, &slices)?;
    Ok(Implant {
        slices,
        midline_x,
        midline_dice,
        mesh,
        mask,
    })
}
