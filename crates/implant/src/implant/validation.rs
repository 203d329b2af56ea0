//! Validation on "perfect data" (thesis chapter 6; protocol of the
//! AutoImplant challenge, Li & Egger et al., IEEE TMI 40(9), 2021):
//! artificial defects are cut out of intact bone, reconstructed, and
//! compared with the bone that was removed.
//!
//! A case is one slice `z`, a position (polar angle `θ_c` in degrees about
//! the polar centre on the midline at the outer contour's mean height,
//! image frame: 0° = +x, 90° = +y = the face in CT 0051) and
//! a width `w` (mm, arc length on the outer envelope). The cut is the
//! wedge of rays `θ_c ± w/(2 r_c)`, `r_c = E(θ_c)`: every bone pixel whose
//! centre lies in it is removed (the ground truth), so the bone ends are
//! radial. The removed pixels are set to 40 HU (soft tissue) in the slice
//! the section is clipped against. The reconstruction only reads the
//! contour at rays outside the wedge (see [`super::wall::reconstruct_wall`]),
//! the defective bone mask and the defective slice.
//!
//! Metrics (one-slice masks, so surfaces are the 2D boundaries):
//! [`dice`], [`boundary_dice`] within `margin_mm` of the defective skull,
//! [`hd95`] (mm), and the mean / max [`contour_deviation`] (mm) of the
//! reconstructed outer wall from the removed outer envelope.

use super::continuation::{source_for, TemplateSource};
use super::plausibility::{head_hull, measure_wall, CheckValues, Finding};
use super::regions::Region;
use super::wall::{envelope_radius, reconstruct_wall, Wall, WallInput, WallKind, WallOptions};
use super::SliceError;
use crate::ct::{
    bone_loops, bone_mask_slice, boundary_dice, contour_deviation, dice, hd95, voxelise,
    ConvexHull, CtError, Mask2, Mask3, MidLine, Polyline, Slice, Spacing, Volume,
};

/// The HU value given to the bone removed by an artificial cut (soft
/// tissue).
pub const CUT_HU: i16 = 40;
use crate::fit::SegmentSolver;
use crate::geometry::Point;

/// One artificial-defect case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case {
    /// The slice (volume index).
    pub index: usize,
    /// Position: polar angle of the defect centre in degrees.
    pub position_deg: f64,
    /// Width in mm (arc length on the outer envelope).
    pub width_mm: f64,
}

/// The prepared case: the defective slice and its ground truth.
#[derive(Clone, Debug)]
pub struct PreparedCase {
    /// The case.
    pub case: Case,
    /// The slice's outer contour (largest outer loop, uncut).
    pub outer: Polyline,
    /// The polar centre: the midline at the outer contour's mean height.
    pub centre: Point,
    /// The mid-sagittal line.
    pub midline: MidLine,
    /// A = E(θ₁) and B = E(θ₂), the cut's outer corners.
    pub a: Point,
    /// B.
    pub b: Point,
    /// The removed bone (ground truth).
    pub truth: Mask2,
    /// The bone left after the cut.
    pub defective: Mask2,
    /// The slice's HU with the removed bone set to [`CUT_HU`] (row-major).
    pub defective_hu: Vec<i16>,
    /// The removed outer envelope between A and B (reference contour).
    pub true_outer: Polyline,
    /// Pixel spacing (x, y) in mm.
    pub spacing: (f64, f64),
    /// The bone threshold (HU).
    pub threshold: i16,
    /// The head's hull on the slice (the defective bone and its mirror
    /// image), the plausibility checks' outline
    /// ([`super::plausibility::head_hull`]).
    pub head: ConvexHull,
    /// The cut's half-width (degrees about the polar centre): the wedge is
    /// `position ± half_width_deg` (what decides whether two positions cut
    /// the same bone, [`super::units::position_units`]).
    pub half_width_deg: f64,
}

/// Metrics of one reconstruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaseMetrics {
    /// Dice of the implant and the removed bone.
    pub dice: f64,
    /// Boundary Dice within the margin of the defective skull.
    pub boundary_dice: f64,
    /// 95th-percentile symmetric surface distance (mm).
    pub hd95: f64,
    /// Mean outer-contour deviation (mm).
    pub dev_mean: f64,
    /// Max outer-contour deviation (mm).
    pub dev_max: f64,
}

/// Whether the polar angle `theta` lies in the wedge `[lo, lo + width]`
/// (radians, modulo 2π).
pub(crate) fn in_wedge(theta: f64, lo: f64, width: f64) -> bool {
    (theta - lo).rem_euclid(std::f64::consts::TAU) <= width
}

/// An intact slice's bone mask, its outer bone loop (the largest
/// counter-clockwise loop) and the polar centre on `midline` at the loop's
/// mean height.
pub(crate) fn outer_loop(
    slice: &Slice<'_>,
    threshold: i16,
    midline: &MidLine,
) -> Result<(Mask2, Polyline, Point), CtError> {
    let mask = bone_mask_slice(slice, threshold)?;
    let loops = bone_loops(slice, &mask, threshold);
    let outer = loops
        .into_iter()
        .filter(|l| l.signed_area() > 0.0)
        .max_by(|a, b| a.signed_area().total_cmp(&b.signed_area()))
        .ok_or(CtError::NoClosedContour)?;
    let centre = midline.at_y(outer.vertex_mean().y);
    Ok((mask, outer, centre))
}

/// Cuts the case's defect out of slice `case.index` of `volume`.
pub fn prepare_case(
    volume: &Volume,
    case: Case,
    midline: MidLine,
    threshold: i16,
) -> Result<PreparedCase, SliceError> {
    let slice = volume.slice(case.index);
    let (sx, sy) = (slice.sx, slice.sy);
    let (mask, outer, centre) = outer_loop(&slice, threshold, &midline)?;
    let polys = [&outer];
    let tc = case.position_deg.to_radians();
    let rc = envelope_radius(&polys, centre, tc).ok_or(SliceError::NoContourAt {
        position_deg: case.position_deg,
    })?;
    let half = 0.5 * case.width_mm / rc;
    let (t1, t2) = (tc - half, tc + half);
    let pt = |t: f64| -> Result<Point, SliceError> {
        envelope_radius(&polys, centre, t)
            .map(|r| centre + Point::new(t.cos(), t.sin()) * r)
            .ok_or(SliceError::DefectLeavesContour)
    };
    let (a, b) = (pt(t1)?, pt(t2)?);
    let true_outer = Polyline::open(
        (0..=64)
            .map(|k| pt(t1 + (t2 - t1) * k as f64 / 64.0))
            .collect::<Result<Vec<_>, _>>()?,
    );
    let mut truth = Mask2::new(mask.nx, mask.ny);
    let mut defective = mask.clone();
    let mut defective_hu = slice.data.to_vec();
    for (r, c) in mask.pixels() {
        let p = Point::new(c as f64 * sx, r as f64 * sy);
        let th = (p.y - centre.y).atan2(p.x - centre.x);
        if in_wedge(th, t1, t2 - t1) {
            truth.set(r, c, true);
            defective.set(r, c, false);
            defective_hu[r * mask.nx + c] = CUT_HU;
        }
    }
    if truth.count() == 0 {
        return Err(SliceError::CutRemovedNoBone);
    }
    let head = head_hull(&defective, (sx, sy), &midline);
    Ok(PreparedCase {
        head,
        half_width_deg: half.to_degrees(),
        case,
        outer,
        centre,
        midline,
        a,
        b,
        truth,
        defective,
        defective_hu,
        true_outer,
        spacing: (sx, sy),
        threshold,
    })
}

/// Reconstructs a prepared case with `kind` (the solver is used by
/// [`WallKind::CurveFit`] only).
pub fn reconstruct_case<S: SegmentSolver + ?Sized>(
    p: &PreparedCase,
    kind: WallKind,
    options: &WallOptions,
    solver: &mut S,
) -> Result<Wall, SliceError> {
    reconstruct_case_with(p, None, kind, options, solver)
}

/// [`reconstruct_case`] with an explicit template in place of the mirror
/// image (`None`: the mirror or the continuation, as `options` choose).
pub fn reconstruct_case_with<S: SegmentSolver + ?Sized>(
    p: &PreparedCase,
    template: Option<&Polyline>,
    kind: WallKind,
    options: &WallOptions,
    solver: &mut S,
) -> Result<Wall, SliceError> {
    let (sx, sy) = p.spacing;
    let is_bone = |q: Point| {
        let (r, c) = ((q.y / sy).round(), (q.x / sx).round());
        r >= 0.0 && c >= 0.0 && p.defective.get_or_false(r as i64, c as i64)
    };
    let outer = [&p.outer];
    let slice = Slice {
        z: p.case.index,
        nx: p.truth.nx,
        ny: p.truth.ny,
        sx,
        sy,
        data: &p.defective_hu,
    };
    let input = WallInput {
        outer: &outer,
        is_bone: &is_bone,
        centre: p.centre,
        midline: p.midline,
        a: p.a,
        b: p.b,
        template,
        surface: None,
        tissue: Some((&slice, p.threshold)),
    };
    reconstruct_wall(&input, kind, options, solver)
}

/// The metrics of `wall` against the case's ground truth.
pub fn case_metrics(p: &PreparedCase, wall: &Wall, margin_mm: f64) -> Result<CaseMetrics, CtError> {
    let (nx, ny) = (p.truth.nx, p.truth.ny);
    let spacing = Spacing {
        x: p.spacing.0,
        y: p.spacing.1,
        z: 1.0,
    };
    let recon = voxelise(&[(0, wall.section.clone())], nx, ny, 1, spacing);
    let truth = Mask3::from_slices(std::slice::from_ref(&p.truth), spacing);
    let skull = Mask3::from_slices(std::slice::from_ref(&p.defective), spacing);
    let hd = if recon.count() == 0 {
        f64::INFINITY
    } else {
        hd95(&recon, &truth)?
    };
    let dev = contour_deviation(&wall.design.outer, &p.true_outer, 0.25)?;
    Ok(CaseMetrics {
        dice: dice(&recon, &truth)?,
        boundary_dice: boundary_dice(&recon, &truth, &skull, margin_mm)?,
        hd95: hd,
        dev_mean: dev.mean,
        dev_max: dev.max,
    })
}

/// Why one reconstruction of a validation case has no metrics (the text
/// of `validation.csv`'s `error` column).
#[derive(Debug, thiserror::Error)]
pub enum CaseError {
    /// The wall could not be reconstructed (see [`reconstruct_case`]).
    #[error("case not built: {0}")]
    Reconstruct(SliceError),
    /// The wall was reconstructed but could not be measured (see
    /// [`case_metrics`]).
    #[error(transparent)]
    Measure(CtError),
    /// The case could not be cut out of its slice ([`prepare_case`]): every
    /// method's row of the case carries this reason.
    #[error("case not built: {0}")]
    NotBuilt(std::sync::Arc<SliceError>),
}

/// Validation result row: one case × method × run.
#[derive(Debug)]
pub struct ValidationRow {
    /// The case.
    pub case: Case,
    /// Original slice number.
    pub z: usize,
    /// `curve:<method>`, `template` or `straight`.
    pub method: String,
    /// Run index (0 for deterministic methods).
    pub run: usize,
    /// The seed of the run (0 for deterministic methods).
    pub seed: u64,
    /// The metrics, or why the case failed.
    pub metrics: Result<CaseMetrics, CaseError>,
    /// The fit's E (mm²; 0 for baselines).
    pub fit_error: f64,
    /// Join angles at A and B (degrees).
    pub join_deg: (f64, f64),
    /// The template the case's walls are fitted to (`None`: the case was
    /// not built), see [`case_template_source`].
    pub template_source: Option<TemplateSource>,
    /// The plausibility checks' values.
    pub checks: CheckValues,
    /// The checks that failed (`status = implausible`).
    pub findings: Vec<Finding>,
    /// The cut's half-width in degrees ([`PreparedCase::half_width_deg`];
    /// NaN when the case was not built).
    pub half_width_deg: f64,
    /// The region of the head the case lies in ([`super::regions`]).
    pub region: Region,
}

impl ValidationRow {
    /// `ok`, `implausible` (built and measured, but a plausibility check
    /// failed: [`ValidationRow::findings`]) or `error` (not built).
    pub fn status(&self) -> &'static str {
        match (&self.metrics, self.findings.is_empty()) {
            (Err(_), _) => "error",
            (Ok(_), true) => "ok",
            (Ok(_), false) => "implausible",
        }
    }
}

/// The template the walls of a prepared case are fitted to under
/// `options.template`: the mirror, or the continuation of both sides
/// ([`super::continuation`]) where it is forced or the mirror cannot serve
/// the cut. Read off the case's bare-template design (no fit, a few
/// milliseconds); where even that fails, what could be told beforehand
/// ([`source_for`]).
pub fn case_template_source(p: &PreparedCase, options: &WallOptions) -> TemplateSource {
    match reconstruct_case(
        p,
        WallKind::Template,
        options,
        &mut crate::fit::LmSolver::default(),
    ) {
        Ok(w) => w.design.template_source,
        Err(_) => source_for(p.a, p.b, &p.midline, false, options),
    }
}

/// What [`evaluate`] gives for one method on one case.
#[derive(Debug)]
pub struct Evaluation {
    /// The metrics, or why the case was not built or measured.
    pub metrics: Result<CaseMetrics, CaseError>,
    /// The fit's `E` (mm²; NaN when not built).
    pub fit_error: f64,
    /// The join angles at A and B (degrees; NaN when not built).
    pub join_deg: (f64, f64),
    /// The plausibility checks' values ([`super::plausibility`]; the width
    /// jump is not measured on one slice).
    pub checks: CheckValues,
    /// The checks that failed: the row is `implausible`.
    pub findings: Vec<Finding>,
}

/// Runs `kind` on a prepared case, checks its plausibility and measures
/// it; a failure becomes the row's error message.
pub fn evaluate<S: SegmentSolver + ?Sized>(
    p: &PreparedCase,
    kind: WallKind,
    options: &WallOptions,
    margin_mm: f64,
    solver: &mut S,
) -> Evaluation {
    match reconstruct_case(p, kind, options, solver) {
        Ok(w) => {
            let checks = measure_wall(&w, &p.head, kind);
            Evaluation {
                metrics: case_metrics(p, &w, margin_mm).map_err(CaseError::Measure),
                fit_error: w.design.fit_error,
                join_deg: w.join_angles_deg(),
                findings: checks.findings(&options.checks),
                checks,
            }
        }
        Err(e) => Evaluation {
            metrics: Err(CaseError::Reconstruct(e)),
            fit_error: f64::NAN,
            join_deg: (f64::NAN, f64::NAN),
            checks: CheckValues::default(),
            findings: Vec::new(),
        },
    }
}
