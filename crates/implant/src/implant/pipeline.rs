//! The real-defect pipeline: per-slice contours and defect ends, the
//! mid-sagittal line, the outer walls, their smoothing across slices, the
//! clipped sections, the lofted mesh and its voxelisation (thesis
//! chapter 6).

use std::collections::BTreeMap;
use std::path::PathBuf;

use super::delivered::{delivered_ring, measure_delivered, Delivered};
use super::plausibility::{CheckValues, Finding};
use super::refusal::{accepted_runs, design_checks, finish_refused, slice_hull, wall_checks};
use super::seats::choose_seats;
use super::slice_error::SliceError;
use super::smooth::{lipschitz_envelope, roughness, smooth_outer_walls};
use super::surface_template::{surface_templates, DefectSlice, SurfaceTemplates, Template3dError};
use super::wall::{
    design_outer, finish_wall, seat_profiles, seat_rule, OuterDesign, Wall, WallInput, WallKind,
    WallOptions,
};
use crate::ct::{
    bone_loops, bone_mask_slice, bone_mask_slice_holding, detect_defect, estimate_tilted_midline,
    loft_rings_through, voxelise, ConvexHull, CtError, DefectParams, Frame, Mask2, Mask3, Mesh,
    MidLine, Polyline, TableContours, Volume,
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
    /// Given in the slice's millimetre frame (the artificial defects).
    Mm {
        /// A in mm.
        a: Point,
        /// B in mm.
        b: Point,
    },
    /// Detected by [`crate::ct::detect_defect`] on the slice's bone mask.
    Auto,
}

/// The mid-sagittal line.
#[derive(Clone, Debug, PartialEq)]
pub enum MidlineSpec {
    /// Given (`midline = M_x` in a spec: the vertical line `x = M_x`).
    Given(MidLine),
    /// Estimated by [`crate::ct::estimate_tilted_midline`] from the bone
    /// masks of these slices (volume numbering; empty = the defect slices).
    Auto(Vec<usize>),
}

/// Explicit templates: one outer-contour polyline per defect slice, in the
/// slice's millimetre frame (`template = "file.csv"` in a spec).
#[derive(Clone, Debug, PartialEq)]
pub struct Templates {
    /// The file they were read from (for messages).
    pub source: PathBuf,
    /// The polyline of each slice (original numbering).
    pub slices: BTreeMap<usize, Polyline>,
}

/// One slice to reconstruct.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliceSpec {
    /// The slice index in the original numbering (volume index + `first_z`).
    pub z: usize,
    /// Its defect ends.
    pub ends: Ends,
}

/// How the walls are smoothed across slices (see [`super::smooth`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Smoothing {
    /// The largest thickness change between adjacent slices (mm, default
    /// 0.5).
    pub max_thickness_step_mm: f64,
    /// The binomial half-width of the outer-wall smoothing (default 2; 0
    /// turns it off).
    pub wall_half_width: usize,
    /// The cost of moving a seat between adjacent slices (degrees of table
    /// bend per mm; default 2; 0 seats every slice on its own).
    pub seat_change_deg_per_mm: f64,
}

impl Default for Smoothing {
    fn default() -> Self {
        Smoothing {
            max_thickness_step_mm: 0.5,
            wall_half_width: 2,
            seat_change_deg_per_mm: 2.0,
        }
    }
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
    /// The largest midline tilt searched (degrees, default 20).
    pub max_tilt_deg: f64,
    /// The bone threshold in HU.
    pub threshold: i16,
    /// The wall options.
    pub wall: WallOptions,
    /// The smoothing across slices.
    pub smoothing: Smoothing,
    /// Explicit templates, replacing the mirror image.
    pub templates: Option<Templates>,
    /// The 3D mid-sagittal plane for `template_source = "mirror3d"` and
    /// `"auto3d"`; `None`: estimated from the volume
    /// ([`crate::ct::mid_sagittal_plane`]) when needed.
    pub plane: Option<crate::ct::Plane3>,
    /// Points per ring of the lofted mesh.
    pub ring_points: usize,
    /// The slab thickness of a one-slice design (mm; `[defect]
    /// thickness_mm`): used where given, else the study's slice spacing;
    /// a one-slice study without SliceThickness needs it.
    pub thickness_mm: Option<f64>,
}

/// The smallest reflection Dice of an acceptable midline estimate.
pub const MIN_MIDLINE_DICE: f64 = 0.5;

/// An error of the implant pipeline, naming the slice it concerns.
#[derive(Debug, thiserror::Error)]
pub enum ImplantError {
    /// A CT-layer error not tied to one slice (reading the volume, writing).
    #[error(transparent)]
    Ct(#[from] CtError),
    /// A design error not tied to one slice (refitting the outer walls
    /// after smoothing them across slices); boxed, as in [`Self::Slice`].
    #[error(transparent)]
    Design(Box<SliceError>),
    /// An output file or directory could not be written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// An error on one slice (original numbering).
    #[error("{}", slice_message(*z, source))]
    Slice {
        /// The slice.
        z: usize,
        /// What went wrong there (boxed: some CT errors are large).
        #[source]
        source: Box<SliceError>,
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
    /// A defect end given as a pixel lies outside the image.
    #[error("slice z = {z}: {what} = [{row}, {col}] (row, col) is outside the image ({rows} rows × {cols} columns)")]
    EndOutside {
        /// The slice (original numbering).
        z: usize,
        /// "A" or "B".
        what: &'static str,
        /// The row given.
        row: f64,
        /// The column given.
        col: f64,
        /// Rows of the image.
        rows: usize,
        /// Columns of the image.
        cols: usize,
    },
    /// A and B are the same point: no defect between them.
    #[error("slice z = {z}: A and B are the same point ({x:.2}, {y:.2}) mm (pixel row {row:.0}, col {col:.0}); a defect needs two distinct ends, one at each bone tip")]
    EndsCoincide {
        /// The slice (original numbering).
        z: usize,
        /// The point's x in mm.
        x: f64,
        /// The point's y in mm.
        y: f64,
        /// Its row.
        row: f64,
        /// Its column.
        col: f64,
    },
    /// A given midline does not cross the image.
    #[error("the midline x = {x_mm:.2} mm (tilt {tilt_deg:.2}°) does not cross the image (x = 0..={width_mm:.2} mm, {cols} columns of {sx} mm); `midline` is in mm, not pixels")]
    MidlineOutside {
        /// The line's x at the image's middle row (mm).
        x_mm: f64,
        /// Its tilt (degrees).
        tilt_deg: f64,
        /// The image's width, `(cols − 1)·s_x` (mm).
        width_mm: f64,
        /// Columns of the image.
        cols: usize,
        /// Pixel spacing along x (mm).
        sx: f64,
    },
    /// None of the slices of the midline estimate holds bone.
    #[error("cannot estimate the midline: no bone in its slices")]
    NoMidline,
    /// The best midline of the estimate is a poor mirror (the slices are
    /// not intact or the head is not symmetric there).
    #[error(
        "cannot estimate the midline: the best reflection Dice on slices {first}..={last} is {dice:.3} < {MIN_MIDLINE_DICE}; give `midline` in mm or intact `midline_slices`"
    )]
    MidlineAsymmetric {
        /// The best reflection Dice.
        dice: f64,
        /// The first slice used (original numbering).
        first: usize,
        /// The last slice used.
        last: usize,
    },
    /// No defect slice.
    #[error("an implant needs at least one defect slice")]
    TooFewSlices,
    /// A 3D template (`template_source = "mirror3d"`, `"rim"`) could not
    /// be built.
    #[error(transparent)]
    Template3d(#[from] Template3dError),
    /// The defect slices do not increase strictly.
    #[error("the defect slices must increase strictly in z")]
    SlicesNotIncreasing,
    /// An explicit template has no polyline for a defect slice.
    #[error("{}: no template polyline for slice z = {z}", file.display())]
    TemplateMissing {
        /// The template file.
        file: PathBuf,
        /// The slice.
        z: usize,
    },
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
    /// A one-slice design in a study that declares no slice thickness.
    #[error("slice z = {z}: a one-slice design is extruded by the slice thickness, but the study has none (no SliceThickness (0018,0050) in its one DICOM slice); give `thickness_mm` in [defect] (mm)")]
    NoSliceThickness {
        /// The slice.
        z: usize,
    },
    /// Slices of the design failed a plausibility check
    /// ([`super::plausibility`]): nothing is written, unless
    /// `--allow-partial` and some slice passed.
    #[error("{}", implausible_message(slices, *total, *allow_partial))]
    Implausible {
        /// The refused slices and their failed checks.
        slices: Vec<(usize, String)>,
        /// The design's slices.
        total: usize,
        /// Whether `--allow-partial` was given (then more slices failed
        /// than `max_refused_fraction` allows).
        allow_partial: bool,
    },
    /// A statistic of the validation could not be computed.
    #[error("statistics: {0}")]
    Stats(#[from] StatsError),
    /// A 3D validation case could not be cut out of the volume or
    /// prepared: every method's row of the case carries this reason, and
    /// the run goes on with the next case.
    #[error("case not built: {0}")]
    CaseNotBuilt(std::sync::Arc<ImplantError>),
}

impl From<SliceError> for ImplantError {
    fn from(e: SliceError) -> Self {
        ImplantError::Design(Box::new(e))
    }
}

impl ImplantError {
    /// The error `source` on slice `z` (original numbering).
    pub fn on_slice(z: usize, source: impl Into<SliceError>) -> Self {
        ImplantError::Slice {
            z,
            source: Box::new(source.into()),
        }
    }
}

/// The message of [`ImplantError::Implausible`]: every refused slice on
/// its own line, then what to do.
fn implausible_message(slices: &[(usize, String)], total: usize, allow_partial: bool) -> String {
    let mut m = format!(
        "the design failed its plausibility checks on {} of {total} slices; no implant was written:",
        slices.len()
    );
    for (z, why) in slices {
        m.push_str(&format!("\n  slice z = {z} refused: {why}"));
    }
    m.push_str(if allow_partial {
        "\nToo many slices are refused for the rest to be trusted (more than `max_refused_fraction` in [checks]), so --allow-partial writes nothing either: the defect's detection failed as a whole. Give A and B by hand on these slices ([[defect.end]]), check `threshold` and the defect's slice range, or loosen a limit in [checks] if the design is right."
    } else {
        "\nRerun with --allow-partial to write `implant.partial.stl` without these slices (metrics.csv then lists every check), give A and B by hand on them ([[defect.end]]), or loosen a limit in [checks] if the design is right."
    });
    m
}

/// The message of an error on slice `z`.
fn slice_message(z: usize, source: &SliceError) -> String {
    match source {
        // NoBone already names its slice (volume index): say both.
        SliceError::Ct(CtError::NoBone { threshold, .. }) => format!(
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
    /// The mid-sagittal line.
    pub midline: MidLine,
    /// The reconstructed cross-section.
    pub wall: Wall,
    /// The implant's pixels on this slice (voxelised mesh).
    pub implant_pixels: usize,
    /// Of those, the fraction at or above the bone threshold.
    pub bone_overlap_fraction: f64,
    /// The radial roughness of the outer wall across z (mm; `None` at the
    /// ends of the stack), see [`super::smooth::roughness`].
    pub roughness_mm: Option<f64>,
    /// The same roughness of the templates (the mirrored bone): what the
    /// bone itself has.
    pub template_roughness_mm: Option<f64>,
    /// The values of the plausibility checks
    /// ([`super::plausibility`]).
    pub checks: CheckValues,
    /// The checks that failed: the slice is refused (no piece of the mesh)
    /// when there is any.
    pub findings: Vec<Finding>,
    /// The slice's ring of the STL measured like the design
    /// ([`super::delivered`]; `None` for a refused slice).
    pub delivered: Option<Delivered>,
}

impl SliceResult {
    /// Whether the slice passed every plausibility check (it is in the
    /// mesh).
    pub fn accepted(&self) -> bool {
        self.findings.is_empty()
    }

    /// The 3 mm kinks at A′ and B′ as they are judged: at each end the
    /// worse of the designed wall and the delivered STL ring
    /// ([`super::delivered`]).
    pub fn judged_kinks_deg(&self) -> (f64, f64) {
        let (a, b) = self.wall.kinks_deg();
        match self.delivered {
            Some(d) => (a.max(d.kinks_deg[1].0), b.max(d.kinks_deg[1].1)),
            None => (a, b),
        }
    }
}

/// The reconstructed implant.
#[derive(Clone, Debug, PartialEq)]
pub struct Implant {
    /// Per slice, increasing `z`.
    pub slices: Vec<SliceResult>,
    /// The mid-sagittal line.
    pub midline: MidLine,
    /// The reflection Dice of the midline estimate (`None` when given).
    pub midline_dice: Option<f64>,
    /// The closed, outward-oriented implant mesh in voxel millimetres
    /// (`z = index·s_z`); [`Implant::patient_mesh`] is the STL's.
    pub mesh: Mesh,
    /// The implant voxelised on the volume grid (the mesh's rings).
    pub mask: Mask3,
    /// The volume's frame.
    pub frame: Frame,
    /// The 3D templates (`mirror3d`, `rim`, `auto3d`), with each slice's
    /// reason; `None` for the slice-wise choices.
    pub templates_3d: Option<SurfaceTemplates>,
}

impl Implant {
    /// The slices that failed a plausibility check (not in the mesh).
    pub fn refused(&self) -> impl Iterator<Item = &SliceResult> {
        self.slices.iter().filter(|s| !s.accepted())
    }

    /// The mesh in the volume's patient coordinates.
    pub fn patient_mesh(&self) -> Mesh {
        self.frame.mesh_to_patient(&self.mesh)
    }
}

/// The volume index of slice `z` (original numbering).
pub fn index_of(cfg: &DefectConfig, volume: &Volume, z: usize) -> Result<usize, ImplantError> {
    slice_index(cfg, volume, z, "slice")
}

/// The volume index of slice `z` (original numbering): `z − first_z`, or
/// [`ImplantError::SliceOutside`] naming the slice as `what` ("defect
/// slice", "validation slice", ...).
pub fn slice_index(
    cfg: &DefectConfig,
    volume: &Volume,
    z: usize,
    what: &'static str,
) -> Result<usize, ImplantError> {
    z.checked_sub(cfg.first_z)
        .filter(|&k| k < volume.nz)
        .ok_or_else(|| ImplantError::SliceOutside {
            what,
            z,
            first: cfg.first_z,
            last: cfg.first_z + volume.nz - 1,
        })
}

/// The bone mask of slice `z` (original numbering).
pub fn slice_mask(volume: &Volume, cfg: &DefectConfig, z: usize) -> Result<Mask2, ImplantError> {
    let k = index_of(cfg, volume, z)?;
    bone_mask_slice(&volume.slice(k), cfg.threshold)
        .map_err(|source| ImplantError::on_slice(z, source))
}

/// Resolves the mid-sagittal line: given, or estimated (tilted) from the
/// masks of the configured slices. Returns the line and the reflection
/// Dice; errors when the slices hold no bone or the best Dice is below
/// [`MIN_MIDLINE_DICE`].
pub fn resolve_midline(
    volume: &Volume,
    cfg: &DefectConfig,
) -> Result<(MidLine, Option<f64>), ImplantError> {
    match &cfg.midline {
        MidlineSpec::Given(line) => Ok((*line, None)),
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
            let (sx, sy) = (volume.spacing.x, volume.spacing.y);
            let m = estimate_tilted_midline(&masks, sx, sy, cfg.max_tilt_deg)
                .ok_or(ImplantError::NoMidline)?;
            if m.dice < MIN_MIDLINE_DICE {
                return Err(ImplantError::MidlineAsymmetric {
                    dice: m.dice,
                    first: zs.iter().copied().min().unwrap_or(0),
                    last: zs.iter().copied().max().unwrap_or(0),
                });
            }
            Ok((m.line, Some(m.dice)))
        }
    }
}

/// What one slice's design reads: its bone mask and table contours, the
/// defect ends and the polar centre.
#[derive(Clone, Debug)]
pub struct SliceContext {
    /// The slice (original numbering).
    pub z: usize,
    /// Its volume index.
    pub k: usize,
    /// The bone mask.
    pub mask: Mask2,
    /// The outer and inner table arcs.
    pub tables: TableContours,
    /// A and B (mm).
    pub ends: (Point, Point),
    /// The polar centre: the midline at the outer table's mean height.
    pub centre: Point,
    /// The head's hull on the slice, the plausibility checks' outline
    /// ([`super::plausibility::head_hull`]).
    pub head: ConvexHull,
}

impl SliceContext {
    /// What the 3D templates need of this slice.
    pub fn defect_slice(&self) -> DefectSlice {
        let (z, k, centre, ends) = (self.z, self.k, self.centre, self.ends);
        DefectSlice { z, k, centre, ends }
    }
}

/// The context of one defect slice: bone mask, ends (given or detected),
/// tables and centre.
pub fn slice_context(
    volume: &Volume,
    cfg: &DefectConfig,
    spec: &SliceSpec,
    midline: MidLine,
) -> Result<SliceContext, ImplantError> {
    let z = spec.z;
    let at = |source: CtError| ImplantError::on_slice(z, source);
    let k = index_of(cfg, volume, z)?;
    let slice = volume.slice(k);
    let (sx, sy) = (slice.sx, slice.sy);
    let (a, b) = match spec.ends {
        Ends::Pixels { a, b } => (
            Point::new(a.1 * sx, a.0 * sy),
            Point::new(b.1 * sx, b.0 * sy),
        ),
        Ends::Mm { a, b } => (a, b),
        Ends::Auto => {
            let mask = bone_mask_slice(&slice, cfg.threshold).map_err(at)?;
            let d = detect_defect(&mask, sx, sy, &DefectParams::default())
                .ok_or_else(|| ImplantError::on_slice(z, SliceError::NoDefectFound))?;
            (d.a_mm, d.b_mm)
        }
    };
    check_distinct_ends(z, (a, b), (sx, sy))?;
    // The largest component, and the piece holding an end when the ring is
    // broken twice (`bone_mask_slice_holding`).
    let mask = bone_mask_slice_holding(&slice, cfg.threshold, &[a, b], 2.0).map_err(at)?;
    let loops = bone_loops(&slice, &mask, cfg.threshold);
    let tables = crate::ct::table_contours(&loops, Some((a, b))).map_err(at)?;
    let centre = midline.at_y(tables.vertex_mean().y);
    let head = slice_hull(volume, &mask, &midline);
    Ok(SliceContext {
        head,
        z,
        k,
        mask,
        tables,
        ends: (a, b),
        centre,
    })
}

/// Refuses defect ends `a`, `b` (mm) closer than half a pixel of the
/// spacing `(sx, sy)`: [`ImplantError::EndsCoincide`] on slice `z`.
pub fn check_distinct_ends(
    z: usize,
    (a, b): (Point, Point),
    (sx, sy): (f64, f64),
) -> Result<(), ImplantError> {
    if a.distance(b) < 0.5 * sx.min(sy) {
        return Err(ImplantError::EndsCoincide {
            z,
            x: a.x,
            y: a.y,
            row: a.y / sy,
            col: a.x / sx,
        });
    }
    Ok(())
}

/// Runs `f` with the wall input of a slice context.
fn with_input<R>(
    volume: &Volume,
    (cfg, surfaces): (&DefectConfig, Option<&SurfaceTemplates>),
    ctx: &SliceContext,
    midline: MidLine,
    f: impl FnOnce(&WallInput<'_>) -> R,
) -> R {
    let slice = volume.slice(ctx.k);
    let (sx, sy) = (slice.sx, slice.sy);
    let is_bone = |p: Point| {
        let (r, c) = ((p.y / sy).round(), (p.x / sx).round());
        r >= 0.0 && c >= 0.0 && ctx.mask.get_or_false(r as i64, c as i64)
    };
    // The whole bone loop: its envelope is the outer table even where the
    // cut puts part of the outer surface into the inner arc (a sinus opened
    // by the defect, ProMED CT 0051 z = 56–57).
    let outer = [&ctx.tables.outer, &ctx.tables.inner];
    let template = cfg.templates.as_ref().and_then(|t| t.slices.get(&ctx.z));
    let surface = surfaces.and_then(|s| s.slices.get(&ctx.z));
    let input = WallInput {
        outer: &outer,
        is_bone: &is_bone,
        centre: ctx.centre,
        midline,
        a: ctx.ends.0,
        b: ctx.ends.1,
        template,
        surface,
        tissue: Some((&slice, cfg.threshold)),
    };
    f(&input)
}

/// Checks the slice list and that explicit templates cover every slice.
fn check_slices(cfg: &DefectConfig) -> Result<(), ImplantError> {
    if cfg.slices.is_empty() {
        return Err(ImplantError::TooFewSlices);
    }
    if cfg.slices.windows(2).any(|w| w[1].z <= w[0].z) {
        return Err(ImplantError::SlicesNotIncreasing);
    }
    if let Some(t) = &cfg.templates {
        if let Some(s) = cfg.slices.iter().find(|s| !t.slices.contains_key(&s.z)) {
            return Err(ImplantError::TemplateMissing {
                file: t.source.clone(),
                z: s.z,
            });
        }
    }
    Ok(())
}

/// The whole real-defect pipeline on a loaded volume with the curve fit:
/// [`reconstruct_defect_with`] and [`WallKind::CurveFit`].
pub fn reconstruct_defect<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    solver: &mut S,
) -> Result<Implant, ImplantError> {
    reconstruct_defect_with(volume, cfg, WallKind::CurveFit, solver)
}

/// The whole pipeline with walls of `kind`: the midline; per slice its
/// context ([`slice_context`]); then [`reconstruct_from`].
pub fn reconstruct_defect_with<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    kind: WallKind,
    solver: &mut S,
) -> Result<Implant, ImplantError> {
    check_slices(cfg)?;
    let (midline, midline_dice) = resolve_midline(volume, cfg)?;
    let contexts = cfg
        .slices
        .iter()
        .map(|s| slice_context(volume, cfg, s, midline))
        .collect::<Result<Vec<_>, _>>()?;
    reconstruct_from(
        volume,
        cfg,
        (midline, midline_dice),
        &contexts,
        kind,
        solver,
    )
}

/// The pipeline from the slice contexts on: the seats of A′ and B′
/// ([`choose_seats`]) and the outer designs (the solver is shared by the
/// slices in order, one random stream for a seeded metaheuristic); the
/// thickness and outer-wall smoothing across slices ([`super::smooth`]);
/// per slice the inner wall and the clipped section; the lofted mesh (a
/// one-slice study is a slab one slice thick), its voxels and each slice's
/// bone overlap and roughness.
pub fn reconstruct_from<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    (midline, midline_dice): (MidLine, Option<f64>),
    contexts: &[SliceContext],
    kind: WallKind,
    solver: &mut S,
) -> Result<Implant, ImplantError> {
    let zs: Vec<usize> = contexts.iter().map(|c| c.z).collect();
    let (designs, templates_3d) = design_walls(volume, cfg, midline, contexts, kind, solver)?;
    let checks = design_checks(&designs, &zs, (&cfg.wall, kind));
    let walls = finished_walls(volume, cfg, contexts, designs, &checks)?;
    let mut slices = Vec::with_capacity(contexts.len());
    for ((ctx, wall), (pre, _)) in contexts.iter().zip(walls).zip(&checks) {
        let (values, findings) = wall_checks((&wall, kind), &ctx.head, pre, &cfg.wall);
        let delivered = findings.is_empty().then(|| {
            let ring = delivered_ring(&wall, cfg.ring_points);
            measure_delivered(&ring, &wall.design)
        });
        slices.push(SliceResult {
            z: ctx.z,
            ends_mm: ctx.ends,
            outer: ctx.tables.outer.clone(),
            inner: ctx.tables.inner.clone(),
            midline,
            wall,
            implant_pixels: 0,
            bone_overlap_fraction: 0.0,
            roughness_mm: None,
            template_roughness_mm: None,
            delivered,
            checks: values,
            findings,
        });
    }
    let indices: Vec<usize> = contexts.iter().map(|c| c.k).collect();
    let sections: Vec<Polyline> = slices.iter().map(|s| s.wall.section.clone()).collect();
    let accepted: Vec<bool> = slices.iter().map(SliceResult::accepted).collect();
    let slab = slab_thickness(volume, cfg, &zs)?;
    let seats: Vec<Vec<Point>> = slices
        .iter()
        .map(|s| vec![s.wall.design.a, s.wall.design.b])
        .collect();
    let (mesh, mask) = accepted_mesh(
        volume,
        &indices,
        (&sections, &seats),
        &accepted,
        (cfg.ring_points, slab),
    )?;
    measure_slices(volume, cfg, &mask, &mut slices);
    Ok(Implant {
        slices,
        midline,
        midline_dice,
        mesh,
        mask,
        frame: volume.frame(),
        templates_3d,
    })
}

/// The finished walls of a stack: the designs that pass the design checks
/// (`checks`) smoothed across slices, their thickness limited between
/// slices, each finished and clipped; a refused design finished on its own
/// ([`finish_refused`]) without touching its neighbours.
fn finished_walls(
    volume: &Volume,
    cfg: &DefectConfig,
    contexts: &[SliceContext],
    designs: Vec<OuterDesign>,
    checks: &[(CheckValues, Vec<Finding>)],
) -> Result<Vec<Wall>, ImplantError> {
    let (good, refused): (Vec<_>, Vec<_>) = contexts
        .iter()
        .zip(designs)
        .zip(checks)
        .partition(|(_, c)| c.1.is_empty());
    let (ctxs, mut kept): (Vec<&SliceContext>, Vec<OuterDesign>) =
        good.into_iter().map(|(cd, _)| cd).unzip();
    let zs: Vec<usize> = ctxs.iter().map(|c| c.z).collect();
    smooth_outer_walls(&mut kept, &zs, cfg.smoothing.wall_half_width, &cfg.wall)?;
    let thickness = smoothed_thickness(&kept, &zs, cfg.smoothing.max_thickness_step_mm);
    let mut walls: Vec<(usize, Wall)> = Vec::with_capacity(contexts.len());
    for ((ctx, design), t) in ctxs.into_iter().zip(kept).zip(thickness) {
        let slice = volume.slice(ctx.k);
        let wall = finish_wall(design, t, Some((&slice, cfg.threshold)), &cfg.wall)
            .map_err(|source| ImplantError::on_slice(ctx.z, source))?;
        walls.push((ctx.z, wall));
    }
    for ((ctx, design), _) in refused {
        walls.push((ctx.z, finish_refused(design, &cfg.wall)));
    }
    walls.sort_by_key(|w| w.0);
    Ok(walls.into_iter().map(|w| w.1).collect())
}

/// The seats and the outer design of every slice, and the 3D templates
/// they were fitted to ([`surface_templates`]; `None` for the slice-wise
/// choices).
fn design_walls<S: SegmentSolver + ?Sized>(
    volume: &Volume,
    cfg: &DefectConfig,
    midline: MidLine,
    contexts: &[SliceContext],
    kind: WallKind,
    solver: &mut S,
) -> Result<(Vec<OuterDesign>, Option<SurfaceTemplates>), ImplantError> {
    let zs: Vec<usize> = contexts.iter().map(|c| c.z).collect();
    let slices: Vec<DefectSlice> = contexts.iter().map(SliceContext::defect_slice).collect();
    let options = (&cfg.wall, cfg.threshold, cfg.plane);
    let templates_3d = surface_templates(volume, options, &slices, &midline)?;
    let surfaces = templates_3d.as_ref();
    let at = |z: usize| move |source: SliceError| ImplantError::on_slice(z, source);
    let bends = contexts
        .iter()
        .map(|ctx| {
            with_input(volume, (cfg, surfaces), ctx, midline, |input| {
                seat_profiles(input, &cfg.wall)
            })
            .map_err(at(ctx.z))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let seats = choose_seats(
        &bends,
        &zs,
        &seat_rule(&cfg.wall, cfg.smoothing.seat_change_deg_per_mm),
    );
    contexts
        .iter()
        .zip(&seats)
        .map(|(ctx, &seat)| {
            with_input(volume, (cfg, surfaces), ctx, midline, |input| {
                design_outer(input, kind, &cfg.wall, Some(seat), solver)
            })
            .map_err(at(ctx.z))
        })
        .collect::<Result<Vec<_>, _>>()
        .map(|d| (d, templates_3d.clone()))
}

/// The thickness at A′ and B′ of every slice after the Lipschitz envelope.
fn smoothed_thickness(designs: &[OuterDesign], zs: &[usize], step: f64) -> Vec<(f64, f64)> {
    let ta: Vec<f64> = designs.iter().map(|d| d.bone_thickness.0).collect();
    let tb: Vec<f64> = designs.iter().map(|d| d.bone_thickness.1).collect();
    let (ta, tb) = (
        lipschitz_envelope(&ta, zs, step),
        lipschitz_envelope(&tb, zs, step),
    );
    ta.into_iter().zip(tb).collect()
}

/// Each slice's implant pixels, bone overlap and outer-wall roughness.
fn measure_slices(volume: &Volume, cfg: &DefectConfig, mask: &Mask3, slices: &mut [SliceResult]) {
    // Over the accepted slices: a refused wall is no part of the surface.
    let ok: Vec<&SliceResult> = slices.iter().filter(|s| s.accepted()).collect();
    let walls: Vec<&Polyline> = ok.iter().map(|s| &s.wall.design.outer).collect();
    let zs: Vec<usize> = ok.iter().map(|s| s.z).collect();
    let o = ok.iter().fold(Point::ZERO, |a, s| a + s.wall.design.centre) / ok.len().max(1) as f64;
    let templates: Vec<&Polyline> = ok.iter().map(|s| &s.wall.design.template).collect();
    let mut rough = roughness(&walls, &zs, o).into_iter();
    let mut bone = roughness(&templates, &zs, o).into_iter();
    let per_slice: Vec<(Option<f64>, Option<f64>)> = slices
        .iter()
        .map(|s| match s.accepted() {
            true => (rough.next().flatten(), bone.next().flatten()),
            false => (None, None),
        })
        .collect();
    for (s, (r, t)) in slices.iter_mut().zip(per_slice) {
        s.template_roughness_mm = t;
        let k = s.z - cfg.first_z;
        let sl = volume.slice(k);
        let m = mask.slice(k);
        let px = m.pixels();
        let bone = px
            .iter()
            .filter(|&&(r, c)| sl.get(r, c) >= cfg.threshold)
            .count();
        s.implant_pixels = px.len();
        s.bone_overlap_fraction = if px.is_empty() {
            0.0
        } else {
            bone as f64 / px.len() as f64
        };
        s.roughness_mm = r;
    }
}

/// The slab thickness of a one-slice design (`zs` the design's slices):
/// `[defect] thickness_mm` where given, else the study's slice spacing, or
/// [`ImplantError::NoSliceThickness`] when the study has none; the slice
/// spacing for a design of several slices (unused).
fn slab_thickness(volume: &Volume, cfg: &DefectConfig, zs: &[usize]) -> Result<f64, ImplantError> {
    match (zs, cfg.thickness_mm) {
        (_, Some(t)) => Ok(t),
        ([z], None) if !volume.z_spacing_known => Err(ImplantError::NoSliceThickness { z: *z }),
        _ => Ok(volume.spacing.z),
    }
}

/// Lofts the sections of the volume slices `indices` into a closed mesh
/// (`z = index·s_z`; one section becomes a slab one slice spacing thick)
/// and voxelises its rings on the volume grid ([`build_mesh_with`]).
pub fn build_mesh(
    volume: &Volume,
    indices: &[usize],
    sections: &[Polyline],
    ring_points: usize,
) -> Result<(Mesh, Mask3), ImplantError> {
    build_mesh_with(volume, indices, sections, ring_points, volume.spacing.z)
}

/// [`build_mesh`] with one section extruded into a slab `slab_mm` thick,
/// from `z − slab/2` to `z + slab/2`.
pub fn build_mesh_with(
    volume: &Volume,
    indices: &[usize],
    sections: &[Polyline],
    ring_points: usize,
    slab_mm: f64,
) -> Result<(Mesh, Mask3), ImplantError> {
    build_mesh_through(volume, indices, (sections, &[]), ring_points, slab_mm)
}

/// [`build_mesh_with`] with each ring resampled through its section's
/// `anchors` (the seats; [`crate::ct::resample_through`]).
pub fn build_mesh_through(
    volume: &Volume,
    indices: &[usize],
    (sections, anchors): (&[Polyline], &[Vec<Point>]),
    ring_points: usize,
    slab_mm: f64,
) -> Result<(Mesh, Mask3), ImplantError> {
    let sz = volume.spacing.z;
    let (secs, zs, anchors): (Vec<Polyline>, Vec<f64>, Vec<Vec<Point>>) = if sections.len() == 1 {
        let z = indices[0] as f64 * sz;
        let a = anchors.first().cloned().unwrap_or_default();
        (
            vec![sections[0].clone(), sections[0].clone()],
            vec![z - 0.5 * slab_mm, z + 0.5 * slab_mm],
            vec![a.clone(), a],
        )
    } else {
        (
            sections.to_vec(),
            indices.iter().map(|&k| k as f64 * sz).collect(),
            anchors.to_vec(),
        )
    };
    let rings = loft_rings_through(&secs, &anchors, &zs, ring_points)?;
    let mesh = crate::ct::mesh_of_rings(&rings, &zs);
    let vox: Vec<(usize, Polyline)> = if sections.len() == 1 {
        vec![(indices[0], rings[0].clone())]
    } else {
        indices.iter().copied().zip(rings).collect()
    };
    let mask = voxelise(&vox, volume.nx, volume.ny, volume.nz, volume.spacing);
    Ok((mesh, mask))
}

/// The mesh and voxels of the accepted slices (`indices`: volume indices
/// of the design's slices, `sections` their sections, each ring resampled
/// through its `seats`): each run lofted on
/// its own ([`build_mesh_with`]; a run of one slice is a slab `slab_mm`
/// thick), the meshes concatenated and the voxels united. Empty when no
/// slice is accepted.
pub fn accepted_mesh(
    volume: &Volume,
    indices: &[usize],
    (sections, seats): (&[Polyline], &[Vec<Point>]),
    accepted: &[bool],
    (ring_points, slab_mm): (usize, f64),
) -> Result<(Mesh, Mask3), ImplantError> {
    let mut mesh = Mesh {
        vertices: Vec::new(),
        triangles: Vec::new(),
    };
    let mut mask = Mask3::new(volume.nx, volume.ny, volume.nz, volume.spacing);
    for run in accepted_runs(accepted) {
        let ks: Vec<usize> = run.iter().map(|&i| indices[i]).collect();
        let secs: Vec<Polyline> = run.iter().map(|&i| sections[i].clone()).collect();
        let anchors: Vec<Vec<Point>> = run.iter().map(|&i| seats[i].clone()).collect();
        let (m, v) = build_mesh_through(volume, &ks, (&secs, &anchors), ring_points, slab_mm)?;
        let offset = mesh.vertices.len();
        mesh.vertices.extend(m.vertices);
        mesh.triangles.extend(
            m.triangles
                .iter()
                .map(|t| [t[0] + offset, t[1] + offset, t[2] + offset]),
        );
        for &k in &ks {
            for (r, c) in v.slice(k).pixels() {
                mask.set(k, r, c, true);
            }
        }
    }
    Ok((mesh, mask))
}
