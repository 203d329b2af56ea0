//! Validation in 3D (AutoImplant protocol, Li & Egger et al., IEEE TMI
//! 40(9), 2021): a patch of bone spanning several slices is cut out of the
//! intact vault, the whole pipeline reconstructs it (seats, fits,
//! smoothing across slices, clipping, loft, voxels), and the implant's
//! voxels are scored against the removed bone in 3D: Dice, boundary Dice
//! within 10 mm of the defective skull, and HD95 in mm on the voxel
//! surfaces with the volume's anisotropic spacing.
//!
//! A case is a slice range `z₀..=z₁` (closed bone rings), a position `θ_c`
//! (degrees about each slice's polar centre, as in [`super::validation`])
//! and a width `w` (mm). The patch is elliptical in (arc length, z): on a
//! slice at `Δz` from the range's middle its width is
//! `w·√(1 − (Δz/b)²)`, `b` half the range's height plus half a slice, so
//! every slice of the range is cut. The removed bone (the slice's bone mask
//! in the wedge) is set to [`super::validation::CUT_HU`] in a copy of the
//! volume, and the pipeline runs on that copy with A and B given at the
//! cut's outer corners.

use super::continuation::TemplateSource;
use super::pipeline::{
    index_of, reconstruct_from, slice_context, DefectConfig, Ends, Implant, ImplantError,
    SliceContext, SliceSpec,
};
use super::plausibility::describe;
use super::regions::Region;
use super::validation::{in_wedge, outer_loop, CUT_HU};
use super::wall::{envelope_radius, WallKind};
use super::SliceError;
use crate::ct::{boundary_dice, dice, hd95, CtError, Mask3, MidLine, Volume};
use crate::fit::SegmentSolver;
use crate::geometry::Point;

/// One 3D artificial-defect case.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Case3d {
    /// First and last slice (original numbering).
    pub range: (usize, usize),
    /// Position: polar angle of the patch centre in degrees.
    pub position_deg: f64,
    /// Width at the middle slice (mm).
    pub width_mm: f64,
}

/// A prepared 3D case: the cut volume, the removed bone and the slice
/// contexts the pipeline starts from.
#[derive(Clone, Debug)]
pub struct Prepared3d {
    /// The case.
    pub case: Case3d,
    /// The volume with the patch's bone set to soft tissue.
    pub cut: Volume,
    /// The removed bone on the volume grid.
    pub truth: Mask3,
    /// The slice contexts of the cut volume (A and B at the cut's outer
    /// corners).
    pub contexts: Vec<SliceContext>,
    /// The midline the cases are placed about.
    pub midline: MidLine,
    /// The pipeline configuration (the range's slices, the midline given).
    pub config: DefectConfig,
    /// The half-width (degrees about the polar centre) of the widest cut
    /// slice's wedge: the patch covers `position ± half_width_deg`.
    pub half_width_deg: f64,
}

/// The patch's width on a slice at `dz` slices from the range's middle.
fn patch_width(case: &Case3d, dz: f64) -> f64 {
    let b = 0.5 * (case.range.1 - case.range.0 + 1) as f64;
    case.width_mm * (1.0 - (dz / b).powi(2)).max(0.0).sqrt()
}

/// Cuts slice `k` of `data` (the volume's samples) for the case: returns
/// the ends A, B (mm) and the wedge's half-width (radians); marks the
/// removed voxels in `truth`.
fn cut_slice(
    volume: &Volume,
    data: &mut [i16],
    truth: &mut Mask3,
    k: usize,
    (theta, width): (f64, f64),
    midline: &MidLine,
    threshold: i16,
) -> Result<(Point, Point, f64), SliceError> {
    let slice = volume.slice(k);
    let (sx, sy, nx) = (slice.sx, slice.sy, slice.nx);
    let (mask, outer, centre) = outer_loop(&slice, threshold, midline)?;
    let polys = [&outer];
    let pt = |t: f64| {
        envelope_radius(&polys, centre, t)
            .map(|r| centre + Point::new(t.cos(), t.sin()) * r)
            .ok_or(SliceError::DefectLeavesContour)
    };
    let rc = pt(theta)?.distance(centre);
    let half = 0.5 * width / rc;
    let (t1, t2) = (theta - half, theta + half);
    let mut removed = 0;
    for (r, c) in mask.pixels() {
        let p = Point::new(c as f64 * sx, r as f64 * sy);
        let th = (p.y - centre.y).atan2(p.x - centre.x);
        if in_wedge(th, t1, t2 - t1) {
            truth.set(k, r, c, true);
            data[(k * slice.ny + r) * nx + c] = CUT_HU;
            removed += 1;
        }
    }
    if removed == 0 {
        return Err(SliceError::CutRemovedNoBone);
    }
    Ok((pt(t1)?, pt(t2)?, half))
}

/// Cuts the case's patch out of `volume` and prepares the slice contexts
/// of the cut volume (`cfg` gives `first_z`, the threshold and the wall
/// options; its slices and midline are replaced).
pub fn prepare_case_3d(
    volume: &Volume,
    cfg: &DefectConfig,
    case: Case3d,
    midline: MidLine,
) -> Result<Prepared3d, ImplantError> {
    let mut data = volume.data().to_vec();
    let mut truth = Mask3::new(volume.nx, volume.ny, volume.nz, volume.spacing);
    let mid = 0.5 * (case.range.0 + case.range.1) as f64;
    let theta = case.position_deg.to_radians();
    let mut slices = Vec::new();
    let mut widest = 0.0f64;
    for z in case.range.0..=case.range.1 {
        let k = index_of(cfg, volume, z)?;
        let w = patch_width(&case, z as f64 - mid);
        let (a, b, half) = cut_slice(
            volume,
            &mut data,
            &mut truth,
            k,
            (theta, w),
            &midline,
            cfg.threshold,
        )
        .map_err(|source| ImplantError::on_slice(z, source))?;
        widest = widest.max(half);
        slices.push(SliceSpec {
            z,
            ends: Ends::Mm { a, b },
        });
    }
    let cut = volume.with_data(data);
    let config = DefectConfig {
        slices,
        midline: super::pipeline::MidlineSpec::Given(midline),
        templates: None,
        plane: None,
        ..cfg.clone()
    };
    let contexts = config
        .slices
        .iter()
        .map(|s| slice_context(&cut, &config, s, midline))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Prepared3d {
        case,
        cut,
        truth,
        contexts,
        midline,
        config,
        half_width_deg: widest.to_degrees(),
    })
}

/// The 3D metrics of one reconstruction, as in the AutoImplant challenge
/// (Li & Egger et al., IEEE TMI 40(9), 2021).
#[derive(Clone, Debug, PartialEq)]
pub struct Metrics3d {
    /// Dice of the implant's voxels `R` and the removed bone `T`:
    /// `DSC = 2|R ∩ T| / (|R| + |T|)` (Dice 1945).
    pub dice: f64,
    /// Boundary Dice (bDSC): the Dice restricted to the voxels within the
    /// margin (10 mm) of the defective skull ([`crate::ct::boundary_dice`]).
    pub boundary_dice: f64,
    /// HD95 in mm: the 95th percentile of the symmetric surface distances
    /// of `R` and `T` in 3D, with the volume's anisotropic spacing
    /// ([`crate::ct::hd95`]; infinite when `R` is empty).
    pub hd95: f64,
    /// Voxels of the removed bone.
    pub truth_voxels: usize,
    /// Voxels of the implant.
    pub implant_voxels: usize,
    /// How many of the implant's slices were fitted to each template
    /// source, in the order of [`TemplateSource::ALL`] (the mirrored
    /// template, the continuation, an explicit file, the 3D mirror, the rim
    /// fill; [`super::wall::OuterDesign::template_source`]).
    pub template_sources: [usize; 5],
    /// The slices the design refused (a plausibility check failed: no
    /// piece of the implant there, [`super::plausibility`]), each with the
    /// failed checks; the row is then `implausible`.
    pub refused: Vec<(usize, String)>,
}

impl Metrics3d {
    /// The template sources used, by name, joined by `+` when the slices
    /// differ: `mirror`, `continuation`, `mirror+continuation`.
    pub fn template_source_name(&self) -> String {
        TemplateSource::ALL
            .iter()
            .zip(self.template_sources)
            .filter(|(_, n)| *n > 0)
            .map(|(s, _)| s.name())
            .collect::<Vec<_>>()
            .join("+")
    }
}

/// The box (inclusive voxel ranges z, y, x) around the voxels of `a` and
/// `b`, grown by `margin_mm` plus two voxels on every side and clipped to
/// the grid; `None` when both are empty.
fn crop_box(a: &Mask3, b: &Mask3, margin_mm: f64) -> Option<[(usize, usize); 3]> {
    let (mut lo, mut hi) = ([usize::MAX; 3], [0usize; 3]);
    for m in [a, b] {
        for z in 0..m.nz {
            for y in 0..m.ny {
                for x in 0..m.nx {
                    if m.get(z, y, x) {
                        for (i, v) in [z, y, x].into_iter().enumerate() {
                            lo[i] = lo[i].min(v);
                            hi[i] = hi[i].max(v);
                        }
                    }
                }
            }
        }
    }
    if lo[0] > hi[0] {
        return None;
    }
    let sp = [a.spacing.z, a.spacing.y, a.spacing.x];
    let n = [a.nz, a.ny, a.nx];
    Some(std::array::from_fn(|i| {
        let g = (margin_mm / sp[i]).ceil() as usize + 2;
        (lo[i].saturating_sub(g), (hi[i] + g).min(n[i] - 1))
    }))
}

/// `m` restricted to the box.
fn crop(m: &Mask3, b: &[(usize, usize); 3]) -> Mask3 {
    let [(z0, z1), (y0, y1), (x0, x1)] = *b;
    Mask3::from_fn(
        x1 - x0 + 1,
        y1 - y0 + 1,
        z1 - z0 + 1,
        m.spacing,
        |z, y, x| m.get(z + z0, y + y0, x + x0),
    )
}

/// Scores an implant against the case's removed bone on a box around both
/// (the metrics are those of the whole grid: the box holds both masks and
/// every skull voxel within the margin of them).
pub fn score_3d(p: &Prepared3d, implant: &Implant, margin_mm: f64) -> Result<Metrics3d, CtError> {
    let b = crop_box(&implant.mask, &p.truth, margin_mm).ok_or(CtError::EmptyMask)?;
    let (recon, truth) = (crop(&implant.mask, &b), crop(&p.truth, &b));
    let threshold = p.config.threshold;
    let [(z0, _), (y0, _), (x0, _)] = b;
    let skull = Mask3::from_fn(truth.nx, truth.ny, truth.nz, truth.spacing, |z, y, x| {
        p.cut.get(z + z0, y + y0, x + x0) >= threshold
    });
    let hd = if recon.count() == 0 {
        f64::INFINITY
    } else {
        hd95(&recon, &truth)?
    };
    Ok(Metrics3d {
        dice: dice(&recon, &truth)?,
        boundary_dice: boundary_dice(&recon, &truth, &skull, margin_mm)?,
        hd95: hd,
        truth_voxels: truth.count(),
        implant_voxels: recon.count(),
        template_sources: source_counts(implant),
        refused: implant
            .refused()
            .map(|s| (s.z, describe(&s.findings)))
            .collect(),
    })
}

/// How many slices of `implant` used each template source, in the order
/// of [`TemplateSource::ALL`].
fn source_counts(implant: &Implant) -> [usize; 5] {
    let mut n = [0; 5];
    for s in &implant.slices {
        let source = s.wall.design.template_source;
        if let Some(i) = TemplateSource::ALL.iter().position(|&t| t == source) {
            n[i] += 1;
        }
    }
    n
}

/// One row of `validation_3d.csv`: a case × method × run.
#[derive(Debug)]
pub struct Row3d {
    /// The case.
    pub case: Case3d,
    /// `curve:<method>`, `template` or `straight`.
    pub method: String,
    /// Run index (0 for deterministic methods).
    pub run: usize,
    /// The seed (0 for deterministic methods).
    pub seed: u64,
    /// The metrics, or why the reconstruction failed.
    pub metrics: Result<Metrics3d, ImplantError>,
    /// The template sources of the implant's slices
    /// ([`Metrics3d::template_source_name`]; empty when it failed).
    pub template_source: String,
    /// The patch's half-width in degrees ([`Prepared3d::half_width_deg`];
    /// NaN when the patch was not built).
    pub half_width_deg: f64,
    /// The region of the head the patch lies in (its middle slice;
    /// [`super::regions`]).
    pub region: Region,
}

/// Reconstructs a prepared case with walls of `kind` by the whole pipeline
/// and scores it.
pub fn evaluate_3d<S: SegmentSolver + ?Sized>(
    p: &Prepared3d,
    kind: WallKind,
    margin_mm: f64,
    solver: &mut S,
) -> Result<Metrics3d, ImplantError> {
    let implant = reconstruct_from(
        &p.cut,
        &p.config,
        (p.midline, None),
        &p.contexts,
        kind,
        solver,
    )?;
    Ok(score_3d(p, &implant, margin_mm)?)
}
