//! What a wall reconstruction is given: the kind of wall
//! ([`WallKind`]), its options ([`WallOptions`]) and the contours around
//! one defect ([`WallInput`]). Both the polar reading of the gap
//! ([`super::polar`]) and the wall design ([`super::wall`]) take them, so
//! they sit below both.

use crate::ct::{MidLine, Polyline, Slice};
use crate::fit::{FunctionType, SearchSpaceOptions};
use crate::geometry::{Continuity, Point};

/// How the outer wall across the defect is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum WallKind {
    /// The thesis: one (rational) Bézier segment from A to B fitted to the
    /// template, ends fixed, G¹/C¹ joins with the intact contour.
    CurveFit,
    /// Baseline: the template points themselves (ends replaced by A and
    /// B), joined by straight segments; no curve fit.
    Template,
    /// Baseline: the straight line from A to B.
    Straight,
}

impl WallKind {
    /// All kinds, curve fit first.
    pub const ALL: [WallKind; 3] = [WallKind::CurveFit, WallKind::Template, WallKind::Straight];

    /// The name used in tables: `curve`, `template`, `straight`.
    pub fn name(self) -> &'static str {
        match self {
            WallKind::CurveFit => "curve",
            WallKind::Template => "template",
            WallKind::Straight => "straight",
        }
    }
}

/// Options of one wall reconstruction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WallOptions {
    /// The Bézier function of the outer wall (default rational cubic).
    pub function: FunctionType,
    /// The join with the intact outer table at both ends: G¹ (default) or
    /// C¹ (C⁰ leaves the inner control points free).
    pub continuity: Continuity,
    /// Objective evaluations for the fit (default 10 000, the chapter-5
    /// budget per segment).
    pub budget: u64,
    /// The RMS distance (mm) within which the outer wall should follow the
    /// template (default 0.75): a wall whose fit misses it is fitted again
    /// as a chain of more segments joined with `continuity`, up to
    /// `max_segments` (BEYOND the thesis, whose implant wall is one
    /// segment; the chain is chapter 5's).
    pub fit_tolerance_mm: f64,
    /// The most segments of the outer wall (default 4; 1: one segment as
    /// in the thesis).
    pub max_segments: usize,
    /// Data points taken along the template (default 48).
    pub template_points: usize,
    /// Points on each wall of the section (default 64).
    pub wall_points: usize,
    /// How far (mm) C and D may lie from the mirrored outer envelope, or an
    /// explicit template's ends from A′ and B′ (default 15): a bound on the
    /// head's left–right asymmetry at the defect.
    pub mirror_tolerance_mm: f64,
    /// How far back from A′ and B′ (arc length on the outer table, mm) the
    /// bone thickness is measured, clear of the bone end faces (default 4).
    pub thickness_setback_mm: f64,
    /// The arc length (mm) of outer table next to A′ and B′ whose fitted
    /// quadratic gives the end tangents of the joins (default 6).
    pub tangent_mm: f64,
    /// The largest implant thickness (mm, default 15): a cap on the bone
    /// thickness measured next to the ends.
    pub max_thickness_mm: f64,
    /// A′ and B′ are seated where the outer table turns by at most this
    /// angle between two consecutive 3 mm secants (degrees, default 3),
    /// behind the bevelled or rounded bone ends (RECONSTRUCTION).
    pub seat_bend_deg: f64,
    /// How far back from the tips (mm) a seat may lie (default 12; 0 keeps
    /// A′ and B′ at the tips). Each mm back costs
    /// [`WallOptions::seat_setback_deg_per_mm`].
    pub seat_max_mm: f64,
    /// The kink against the bone accepted at a seat (degrees, default 6):
    /// a seat where the join tangent, or the expected wall's last 1.5 mm
    /// and 3 mm secants, and the bone's iso-contour secants differ by more
    /// is avoided (see [`super::seats::SeatProfile`]); the margin below the
    /// 10° target of the measured 3 mm kink covers the fit's departure from
    /// the blended template near the seat (on the real defect up to ≈ 4°).
    pub seat_kink_deg: f64,
    /// The template–bone offset accepted at a seat (mm, default 1).
    pub seat_offset_tol_mm: f64,
    /// The cost of each mm of offset above it, in degrees of table bend
    /// (default 2): seats go where bone and template agree when that is
    /// near.
    pub seat_offset_deg_per_mm: f64,
    /// The cost of each mm a seat lies behind the bone tip, in degrees of
    /// table bend (default 1): seats stay near the tips unless the bone's
    /// shape or the template asks for more.
    pub seat_setback_deg_per_mm: f64,
    /// The template is blended onto the bone's tangent line at each seat
    /// over a length chosen so that the correction rises by at most this
    /// angle (degrees, default 15; see [`super::polar::blend_onto_bone`]).
    pub blend_slope_deg: f64,
    /// The shortest blend (mm of template arc, default 8).
    pub blend_min_mm: f64,
    /// Grid cells per pixel of the clipping field (default 4; 0 turns the
    /// clipping off).
    pub clip_subdivision: usize,
    /// The length (mm) of the outer wall's ends at A′ and B′ that clipping
    /// leaves as designed, in a band of [`super::wall::SEAT_KEEP_RADIUS_MM`]
    /// (default 1; 0 clips everything): the delivered part's outer surface
    /// then meets the bone at the designed seats, and its kink there is the
    /// design's ([`crate::ct::clip_to_tissue_keeping`]; issue 48).
    pub seat_keep_mm: f64,
    /// The search space of the fit.
    pub search: SearchSpaceOptions,
    /// Which template the wall is fitted to where no explicit one is given:
    /// the mirror (default, the thesis), the continuation of both sides, or
    /// the continuation only across the midline
    /// ([`super::continuation`], beyond the thesis).
    pub template: TemplateChoice,
    /// How the inner wall's offset `Dis(u)` varies between the thickness
    /// at A′ and at B′: linearly (default), or following the other side's
    /// bone thickness where the template is the mirror image
    /// ([`ThicknessProfile::Mirror`], beyond the thesis).
    pub thickness_profile: ThicknessProfile,
    /// Before clipping, extend the section into the bone beyond A′ and B′
    /// along the outer table by the end's thickness, so that the clipped
    /// implant fills up to the bone's cut face rather than stopping at the
    /// wall's normal through A′ and B′ (default `false`; beyond the
    /// thesis).
    pub fill_ends: bool,
    /// The plausibility limits a finished wall is checked against before
    /// it is accepted (`[checks]` in a spec; [`super::plausibility`]).
    pub checks: super::check_limits::PlausibilityLimits,
}

/// How the inner wall's offset `Dis(u)` runs from A′ to B′, as the spec
/// chooses it (`[implant] thickness_profile`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ThicknessProfile {
    /// `Dis(u) = (1 − u)·t_A + u·t_B` (RECONSTRUCTION: the thesis gives the
    /// offset `PO(u) = C(u) + Dis(u)·N(u)` but not `Dis`).
    #[default]
    Linear,
    /// The linear blend plus the other side's thickness profile less its
    /// own chord ([`super::polar::MirroredThickness::excess`]): the mirror
    /// technique applied to the inner table as well, so that the implant
    /// is as thick as the bone it replaces where the skull is thicker
    /// mid-gap than at its ends (e.g. a vault cut obliquely near the
    /// vertex). Where the template is not the mirror image (the
    /// continuation, an explicit file) the profile is linear. BEYOND the
    /// thesis.
    Mirror,
}

impl ThicknessProfile {
    /// The spec's names, in order: `linear`, `mirror`.
    pub const NAMES: [&'static str; 2] = ["linear", "mirror"];

    /// The profile of a spec name ([`ThicknessProfile::NAMES`]).
    pub fn from_name(name: &str) -> Option<ThicknessProfile> {
        match name {
            "linear" => Some(ThicknessProfile::Linear),
            "mirror" => Some(ThicknessProfile::Mirror),
            _ => None,
        }
    }

    /// The spec's name of the profile.
    pub fn name(self) -> &'static str {
        match self {
            ThicknessProfile::Linear => "linear",
            ThicknessProfile::Mirror => "mirror",
        }
    }
}

impl Default for WallOptions {
    fn default() -> Self {
        WallOptions {
            function: FunctionType::RationalCubic,
            continuity: Continuity::G1,
            budget: 10_000,
            fit_tolerance_mm: 0.75,
            max_segments: 4,
            template_points: 48,
            wall_points: 64,
            mirror_tolerance_mm: 15.0,
            thickness_setback_mm: 4.0,
            tangent_mm: 6.0,
            max_thickness_mm: 15.0,
            seat_bend_deg: 3.0,
            seat_max_mm: 12.0,
            seat_kink_deg: 6.0,
            seat_offset_tol_mm: 1.0,
            seat_offset_deg_per_mm: 2.0,
            seat_setback_deg_per_mm: 1.0,
            blend_slope_deg: 15.0,
            blend_min_mm: 8.0,
            clip_subdivision: 4,
            seat_keep_mm: 1.0,
            search: SearchSpaceOptions::default(),
            template: TemplateChoice::Mirror,
            thickness_profile: ThicknessProfile::Linear,
            fill_ends: false,
            checks: super::check_limits::PlausibilityLimits::default(),
        }
    }
}

/// The contours around one defect, read in polar form about a centre on
/// the mid-sagittal line (so that the reflection maps the ray at angle `θ`
/// to the ray at `2α − θ`, `α` the line's direction angle).
///
/// The outer table is read as its **envelope** `E(θ)`: the farthest
/// crossing of the ray at `θ` with the outer contour(s). This skips inner
/// surfaces that a cut ring exposes (such as a frontal sinus opened by the
/// defect, ProMED CT 0051 z = 56–66), which a nearest-point search would
/// otherwise take for the outer table (RECONSTRUCTION: the thesis only says
/// that C and D are the mirrored ends and the contour between them is the
/// template).
#[derive(Clone, Copy)]
pub struct WallInput<'a> {
    /// Outer contour(s) of the slice; only rays outside the defect's angular
    /// range are ever queried for the envelope, and the table next to the
    /// ends is walked along them.
    pub outer: &'a [&'a Polyline],
    /// Whether a point (mm) is bone; used to measure the thickness.
    pub is_bone: &'a dyn Fn(Point) -> bool,
    /// The polar centre, on the midline inside the head.
    pub centre: Point,
    /// The mid-sagittal line.
    pub midline: MidLine,
    /// The defect end A (mm): its polar angle starts the gap.
    pub a: Point,
    /// The defect end B (mm): its polar angle ends the gap.
    pub b: Point,
    /// An explicit template (from near A to near B; either order), used
    /// instead of the mirror image; the defect may then cross the midline.
    pub template: Option<&'a Polyline>,
    /// A 3D template sliced to this slice (`mirror3d`, `rim`), used
    /// instead of the slice-wise mirror image.
    pub surface: Option<&'a super::ray_template::RayTemplate>,
    /// The CT slice and bone threshold the section is clipped against
    /// (`None`: no clipping).
    pub tissue: Option<(&'a Slice<'a>, i16)>,
}

impl std::fmt::Debug for WallInput<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WallInput")
            .field("centre", &self.centre)
            .field("midline", &self.midline)
            .field("a", &self.a)
            .field("b", &self.b)
            .finish_non_exhaustive()
    }
}

/// Which template the outer wall is fitted to, as the spec chooses it
/// (`[implant] template_source`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TemplateChoice {
    /// The mirror technique where it applies, the continuation where it
    /// cannot serve: a defect across the mid-sagittal line, or one next to
    /// it whose mirrored end falls into the gap (`template_for` in [`super::continuation`]; the
    /// shipped chapter-6 spec asks for it).
    Auto,
    /// The mirror technique only (thesis chapter 6): a defect across the
    /// midline is refused ([`crate::ct::CtError::DefectCrossesMidline`]). The default,
    /// in [`WallOptions::default`] and in a spec, so that going beyond the
    /// thesis is asked for.
    #[default]
    Mirror,
    /// The continuation everywhere (`continuation_template`).
    Continuation,
    /// The outer table mirrored across the 3D mid-sagittal plane
    /// ([`super::surface_template`]); needs a volume of several slices.
    Mirror3d,
    /// The rim fill ([`super::rim_fill`]); needs a volume of several
    /// slices.
    Rim,
    /// Per slice, the 3D mirror where it serves, else the rim fill (the
    /// rule of [`super::surface_template`]); on one-slice data, as `Auto`.
    Auto3d,
}

impl TemplateChoice {
    /// The spec's names, in order: `auto`, `mirror`, `continuation`,
    /// `mirror3d`, `rim`, `auto3d`.
    pub const NAMES: [&'static str; 6] = [
        "auto",
        "mirror",
        "continuation",
        "mirror3d",
        "rim",
        "auto3d",
    ];

    /// The choice of a spec name ([`TemplateChoice::NAMES`]).
    pub fn from_name(name: &str) -> Option<TemplateChoice> {
        match name {
            "auto" => Some(TemplateChoice::Auto),
            "mirror" => Some(TemplateChoice::Mirror),
            "continuation" => Some(TemplateChoice::Continuation),
            "mirror3d" => Some(TemplateChoice::Mirror3d),
            "rim" => Some(TemplateChoice::Rim),
            "auto3d" => Some(TemplateChoice::Auto3d),
            _ => None,
        }
    }
}
