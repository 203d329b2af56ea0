//! One slice's implant cross-section: the outer wall between the defect
//! ends (mirrored or explicit template, then the chapter-5 curve fit with
//! both ends fixed and joined G¹ or C¹ to the local outer table), the inner
//! wall by the offset `PO(u) = C(u) + Dis(u)·N(u)`, and the closed section
//! between them, clipped to the tissue that is not bone (thesis chapter 6).
//!
//! The design has two steps so that a pipeline can smooth across slices in
//! between: [`design_outer`] (ends, template, joins, the outer wall, the
//! bone thickness next to the ends) and [`finish_wall`] (inner wall with a
//! given thickness, the section, its clipping, the kink metric).
//! [`reconstruct_wall`] runs both on one slice. Everything works on
//! contours in the slice's millimetre frame of [`crate::ct`], so the real
//! defect and the artificial defects of the validation share it.

use super::continuation::{crosses_midline, template_for, template_source, TemplateSource};
use super::polar::{fit_err, Gap, Side, TableWalk};
use super::seats::choose_seats;
use crate::ct::{clip_to_tissue, CtError, Polyline, Slice};
use crate::fit::{End, Segment, SegmentProblem, SegmentSolver, Start};
use crate::geometry::{offset_linear, Continuity, Curve, LinearDistance, Parameterisation, Point};
use crate::problem::Problem;

pub use super::polar::envelope_radius;
pub use super::wall_input::{WallInput, WallKind, WallOptions};

/// The first step of a wall: everything that does not depend on the
/// thickness.
#[derive(Clone, Debug, PartialEq)]
pub struct OuterDesign {
    /// The wall's start A′ on the outer envelope.
    pub a: Point,
    /// The wall's end B′.
    pub b: Point,
    /// C = A′ mirrored (or the explicit template's start).
    pub c: Point,
    /// D = B′ mirrored (or the explicit template's end).
    pub d: Point,
    /// The template `R_i` the wall is fitted to (from A′ to B′).
    pub template: Polyline,
    /// The fitted segment ([`WallKind::CurveFit`] only).
    pub segment: Option<Segment>,
    /// The fit's `E = Σ|Rᵢ − P(sᵢ)|²` (mm², 0 for the baselines).
    pub fit_error: f64,
    /// Objective evaluations used by the fit.
    pub evaluations: u64,
    /// The outer wall from A′ to B′.
    pub outer: Polyline,
    /// The unit tangents of the joins at A′ and B′ (direction of travel),
    /// from the local outer table ([`WallOptions::tangent_mm`]).
    pub tangents: (Point, Point),
    /// The end derivatives of C¹ joins (the tangents times a speed).
    pub derivatives: (Point, Point),
    /// The largest distance (mm) the cross-slice smoothing moved the wall
    /// (0 when not smoothed).
    pub smoothing_shift_mm: f64,
    /// The outer table's direction of travel at A′ and B′ measured as the
    /// secant over the 3 mm of table next to each end (the kink metric's
    /// reference).
    pub table_dirs: (Point, Point),
    /// The bone thickness measured next to A′ and B′ along the table's
    /// normal, capped at [`WallOptions::max_thickness_mm`] (mm).
    pub bone_thickness: (f64, f64),
    /// The polar centre.
    pub centre: Point,
    /// How far (arc length on the outer table, mm) A′ and B′ were seated
    /// back from the defect's tips (see [`WallOptions::seat_bend_deg`]).
    pub seats: (f64, f64),
    /// Where the template came from ([`super::continuation`]).
    pub template_source: TemplateSource,
}

/// One reconstructed cross-section.
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// The outer design it was finished from.
    pub design: OuterDesign,
    /// The inner wall from B″ to A″ (the offset, reversed).
    pub inner: Polyline,
    /// The section before clipping: outer A′→B′, then inner B″→A″.
    pub raw_section: Polyline,
    /// The section clipped to the tissue that is not bone (the raw section
    /// when clipping is off).
    pub section: Polyline,
    /// The thickness used at A′ and B′ (mm; `Dis(0)`, `Dis(1)`).
    pub thickness: (f64, f64),
    /// The fraction of the raw section's area removed by clipping.
    pub clipped_fraction: f64,
}

/// The angle in degrees between the directions `u` and `v` (NaN when one
/// is zero).
pub fn angle_deg(u: Point, v: Point) -> f64 {
    match (u.normalize(), v.normalize()) {
        (Some(u), Some(v)) => u.cross(v).atan2(u.dot(v)).abs().to_degrees(),
        _ => f64::NAN,
    }
}

impl OuterDesign {
    /// The wall's end directions at A′ and B′ (direction of travel): the
    /// segment's derivatives, or the polyline's first and last legs.
    pub fn end_directions(&self) -> (Point, Point) {
        match &self.segment {
            Some(s) => (s.deriv(0.0), s.deriv(1.0)),
            None => {
                let p = &self.outer.points;
                let n = p.len();
                (p[1] - p[0], p[n - 1] - p[n - 2])
            }
        }
    }

    /// The angle (degrees) between the wall's end direction and the join
    /// tangent at A′ and B′: 0 for an exact G¹ join.
    pub fn join_angles_deg(&self) -> (f64, f64) {
        let (da, db) = self.end_directions();
        (
            angle_deg(da, self.tangents.0),
            angle_deg(db, self.tangents.1),
        )
    }

    /// The kinks against the real bone (degrees): the angle between the
    /// wall's end direction and the outer table's secant over the 3 mm next
    /// to A′ and B′.
    pub fn kinks_deg(&self) -> (f64, f64) {
        let (da, db) = self.end_directions();
        (
            angle_deg(da, self.table_dirs.0),
            angle_deg(db, self.table_dirs.1),
        )
    }

    /// The defect width |A′B′| (mm).
    pub fn width(&self) -> f64 {
        self.a.distance(self.b)
    }
}

impl Wall {
    /// See [`OuterDesign::join_angles_deg`].
    pub fn join_angles_deg(&self) -> (f64, f64) {
        self.design.join_angles_deg()
    }

    /// See [`OuterDesign::kinks_deg`].
    pub fn kinks_deg(&self) -> (f64, f64) {
        self.design.kinks_deg()
    }
}

/// The joins with the intact contour at A′ and B′.
#[derive(Clone, Copy, Debug)]
struct Joins {
    /// Derivatives for C¹ joins (local tangent × the neighbouring cubic's
    /// speed).
    derivatives: (Point, Point),
    /// The unit tangents (G¹ joins).
    tangents: (Point, Point),
}

/// The outer wall from A′ to B′.
struct OuterWall {
    segment: Option<Segment>,
    fit_error: f64,
    evaluations: u64,
    points: Vec<Point>,
}

/// The fitting problem of the outer wall: `options.function` on `data`
/// (chord-length parameters), the ends fixed and the joins of
/// `options.continuity`.
fn wall_problem(
    options: &WallOptions,
    data: &[Point],
    joins: &Joins,
) -> Result<SegmentProblem, CtError> {
    let (d_a, d_b) = joins.derivatives;
    let (start, end) = match options.continuity {
        Continuity::C0 => (Start::Free, End::Free),
        Continuity::C1 => (Start::C1 { derivative: d_a }, End::C1 { derivative: d_b }),
        Continuity::G1 => (
            Start::G1 {
                leg: joins.tangents.0,
            },
            End::G1 {
                dir: joins.tangents.1,
            },
        ),
    };
    let start = if options.function.degree() == 2 {
        Start::Free
    } else {
        start
    };
    SegmentProblem::with_parameterisation(
        options.function,
        data.to_vec(),
        Parameterisation::ChordLength,
        start,
        &options.search,
    )
    .and_then(|p| p.with_end(end))
    .map_err(fit_err)
}

/// The curve fit of the outer wall ([`wall_problem`]), evaluated at `us`.
fn fit_outer_wall<S: SegmentSolver + ?Sized>(
    options: &WallOptions,
    data: &[Point],
    joins: &Joins,
    us: &[f64],
    solver: &mut S,
) -> Result<OuterWall, CtError> {
    let problem = wall_problem(options, data, joins)?;
    let sol = solver.solve(&problem, options.budget);
    let seg = problem.segment(&sol.x);
    Ok(OuterWall {
        fit_error: problem.objective(&sol.x),
        evaluations: sol.evaluations,
        points: us.iter().map(|&u| seg.eval(u)).collect(),
        segment: Some(seg),
    })
}

/// `m` parameters equally spaced in [0, 1].
pub(crate) fn unit_params(m: usize) -> Vec<f64> {
    let m = m.max(4);
    (0..m).map(|k| k as f64 / (m - 1) as f64).collect()
}

/// The joins at A′ and B′: the local outer table's tangents, and for C¹ the
/// neighbouring cubic's speed along them.
fn joins(
    gap: &Gap<'_>,
    ends: (Point, Point),
    walks: (&TableWalk, &TableWalk),
    options: &WallOptions,
) -> Result<Joins, CtError> {
    let chord = ends.1 - ends.0;
    let ta = gap
        .local_tangent(Side::A, walks.0, options.tangent_mm)
        .ok_or(CtError::TooLittleIntactContour {
            before: 0,
            after: 1,
        })?;
    let tb = gap
        .local_tangent(Side::B, walks.1, options.tangent_mm)
        .ok_or(CtError::TooLittleIntactContour {
            before: 1,
            after: 0,
        })?;
    let derivatives = if options.continuity == Continuity::C1 {
        let (da, db) = gap.neighbour_derivatives()?;
        (ta * da.hypot(), tb * db.hypot())
    } else {
        (ta * chord.hypot(), tb * chord.hypot())
    };
    Ok(Joins {
        derivatives,
        tangents: (ta, tb),
    })
}

/// The outer table's direction of travel at an end: the secant over the
/// 3 mm of table next to it.
fn table_dir(walk: &TableWalk, side: Side) -> Point {
    match side {
        Side::A => walk.at(0.0) - walk.at(3.0),
        Side::B => walk.at(3.0) - walk.at(0.0),
    }
}

/// The gap at the tips of a wall input and the outer table walked from
/// each tip (far enough for the seat search, the tangents and the
/// thickness). Checks first that the defect does not cross the midline
/// when the mirror is to serve it.
fn tip_walks<'a>(
    input: &WallInput<'a>,
    options: &WallOptions,
) -> Result<(Gap<'a>, TableWalk, TableWalk), CtError> {
    let line = input.midline;
    if template_source(input, options) == TemplateSource::Mirror
        && crosses_midline(input.a, input.b, &line)
    {
        return Err(CtError::DefectCrossesMidline {
            a_x: input.a.x,
            b_x: input.b.x,
            midline_x: line.x_at(0.5 * (input.a.y + input.b.y)),
        });
    }
    let tips = Gap::new(*input);
    let reach = options.seat_max_mm
        + options
            .tangent_mm
            .max(1.5 * options.thickness_setback_mm + 1.0)
            .max(6.0);
    let walk = |side: Side| {
        tips.table(side, reach)
            .ok_or(CtError::TooLittleIntactContour {
                before: 0,
                after: 0,
            })
    };
    let (a, b) = (walk(Side::A)?, walk(Side::B)?);
    Ok((tips, a, b))
}

/// The bend of the outer table at the candidate seats behind A and behind
/// B on one slice (`Gap::bends` in [`super::polar`]: index `k` is `k·0.25` mm behind the tip).
pub fn seat_bends(
    input: &WallInput<'_>,
    options: &WallOptions,
) -> Result<(Vec<f64>, Vec<f64>), CtError> {
    let (_, tip_a, tip_b) = tip_walks(input, options)?;
    Ok((
        Gap::bends(&tip_a, options.seat_max_mm),
        Gap::bends(&tip_b, options.seat_max_mm),
    ))
}

/// The first step of the wall across one defect with `kind` (see
/// [`reconstruct_wall`] for the steps), with A′ and B′ seated `seats` mm
/// back from the tips (`None`: this slice's own seats,
/// [`super::seats::choose_seats`] on this slice alone); the curve fit is
/// solved by `solver`.
pub fn design_outer<S: SegmentSolver + ?Sized>(
    input: &WallInput<'_>,
    kind: WallKind,
    options: &WallOptions,
    seats: Option<(f64, f64)>,
    solver: &mut S,
) -> Result<OuterDesign, CtError> {
    let (tips, tip_a, tip_b) = tip_walks(input, options)?;
    let seats = match seats {
        Some(s) => s,
        None => {
            let bends = (
                Gap::bends(&tip_a, options.seat_max_mm),
                Gap::bends(&tip_b, options.seat_max_mm),
            );
            choose_seats(&[bends], &[0], options.seat_bend_deg, 0.0)[0]
        }
    };
    let (walk_a, walk_b) = (tip_a.from(seats.0), tip_b.from(seats.1));
    let gap = tips.moved(walk_a.at(0.0), walk_b.at(0.0));
    let (ends, data, source) = template_for(&gap, input, options)?;
    let (a, b) = (ends.a, ends.b);
    let joins = joins(&gap, (a, b), (&walk_a, &walk_b), options)?;
    let us = unit_params(options.wall_points);
    let outer = match kind {
        WallKind::CurveFit => fit_outer_wall(options, &data, &joins, &us, solver)?,
        WallKind::Template => OuterWall {
            segment: None,
            fit_error: 0.0,
            evaluations: 0,
            points: data.clone(),
        },
        WallKind::Straight => OuterWall {
            segment: None,
            fit_error: 0.0,
            evaluations: 0,
            points: us.iter().map(|&u| a.lerp(b, u)).collect(),
        },
    };
    let (set, cap) = (options.thickness_setback_mm, options.max_thickness_mm);
    let bone_thickness = (
        gap.thickness(&walk_a, set, cap),
        gap.thickness(&walk_b, set, cap),
    );
    if bone_thickness.0 <= 0.0 || bone_thickness.1 <= 0.0 {
        return Err(CtError::NoBoneAtEnds {
            thickness_a: bone_thickness.0,
            thickness_b: bone_thickness.1,
        });
    }
    Ok(OuterDesign {
        a,
        b,
        c: ends.c,
        d: ends.d,
        template: Polyline::open(data),
        segment: outer.segment,
        fit_error: outer.fit_error,
        evaluations: outer.evaluations,
        outer: Polyline::open(outer.points),
        tangents: joins.tangents,
        derivatives: joins.derivatives,
        smoothing_shift_mm: 0.0,
        table_dirs: (table_dir(&walk_a, Side::A), table_dir(&walk_b, Side::B)),
        seats,
        bone_thickness,
        centre: input.centre,
        template_source: source,
    })
}

/// Refits a fitted outer wall to `points` (from A′ to B′, e.g. the wall
/// smoothed across slices) by Levenberg–Marquardt with the same function,
/// ends and joins, and records how far it moved and its `E` against the
/// template. A baseline design (no segment) is left unchanged.
pub fn refit_outer(
    design: &mut OuterDesign,
    points: Vec<Point>,
    options: &WallOptions,
) -> Result<(), CtError> {
    if design.segment.is_none() {
        return Ok(());
    }
    let joins = Joins {
        derivatives: design.derivatives,
        tangents: design.tangents,
    };
    let problem = wall_problem(options, &points, &joins)?;
    let sol = crate::fit::LmSolver::default().solve(&problem, 2_000);
    let seg = problem.segment(&sol.x);
    let us = unit_params(options.wall_points);
    let outer: Vec<Point> = us.iter().map(|&u| seg.eval(u)).collect();
    let shift = outer
        .iter()
        .map(|&p| design.outer.distance_to(p))
        .fold(0.0, f64::max);
    let template = wall_problem(options, &design.template.points, &joins)?;
    design.fit_error = template.objective(&sol.x);
    design.smoothing_shift_mm = shift;
    design.outer = Polyline::open(outer);
    design.segment = Some(seg);
    Ok(())
}

/// The unit normal of a polyline at vertex `i` by central differences,
/// right of the direction of travel: `(y′, −x′)/|·|`, as
/// [`crate::geometry::Curve::unit_normal`].
fn polyline_normal(p: &[Point], i: usize) -> Point {
    let n = p.len();
    let d = p[(i + 1).min(n - 1)] - p[i.saturating_sub(1)];
    Point::new(d.y, -d.x).normalize().unwrap_or(Point::ZERO)
}

/// The inner wall of a fitted segment: `PO(u) = C(u) + Dis(u)·N(u)` at
/// `us`, `Dis` linear from `t_A` to `t_B` with the sign that points
/// towards `o`.
fn offset_segment(seg: &Segment, us: &[f64], o: Point, (t_a, t_b): (f64, f64)) -> Vec<Point> {
    let mid = seg.eval(0.5);
    let n_mid = crate::geometry::offset_point(seg, 0.5, 1.0) - mid;
    let sign = if n_mid.dot(o - mid) >= 0.0 { 1.0 } else { -1.0 };
    offset_linear(
        seg,
        us,
        LinearDistance {
            d0: sign * t_a,
            d1: sign * t_b,
        },
    )
}

/// The inner wall of a baseline polyline `p`: the same offset with
/// polyline normals and `u` the arc-length fraction.
fn offset_polyline(p: &[Point], o: Point, (t_a, t_b): (f64, f64)) -> Vec<Point> {
    let mid = p.len() / 2;
    let sign = if polyline_normal(p, mid).dot(o - p[mid]) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let total = Polyline::open(p.to_vec()).length().max(f64::MIN_POSITIVE);
    let mut s = 0.0;
    (0..p.len())
        .map(|i| {
            if i > 0 {
                s += p[i].distance(p[i - 1]);
            }
            let u = s / total;
            p[i] + polyline_normal(p, i) * (sign * ((1.0 - u) * t_a + u * t_b))
        })
        .collect()
}

/// The second step: the inner wall at `thickness` (mm at A′ and B′), the
/// section, and its clipping against `tissue` (the CT slice and bone
/// threshold; `None` or `options.clip_subdivision = 0`: no clipping).
/// Error [`CtError::ClippedAway`] when no tissue is left in the section.
pub fn finish_wall(
    design: OuterDesign,
    thickness: (f64, f64),
    tissue: Option<(&Slice<'_>, i16)>,
    options: &WallOptions,
) -> Result<Wall, CtError> {
    let us = unit_params(options.wall_points);
    let o = design.centre;
    let inner_pts = match &design.segment {
        Some(seg) => offset_segment(seg, &us, o, thickness),
        None => offset_polyline(&design.outer.points, o, thickness),
    };
    let inner_rev: Vec<Point> = inner_pts.iter().rev().copied().collect();
    let mut pts = design.outer.points.clone();
    pts.extend(inner_rev.iter().copied());
    let raw_section = Polyline::closed(pts);
    let (section, clipped_fraction) = match tissue {
        Some((slice, threshold)) if options.clip_subdivision > 0 => {
            let c = clip_to_tissue(&raw_section, slice, threshold, options.clip_subdivision)
                .ok_or(CtError::ClippedAway)?;
            let f = 1.0 - c.area_after / c.area_before.max(f64::MIN_POSITIVE);
            (c.section, f.max(0.0))
        }
        _ => (raw_section.clone(), 0.0),
    };
    Ok(Wall {
        design,
        inner: Polyline::open(inner_rev),
        raw_section,
        section,
        thickness,
        clipped_fraction,
    })
}

/// Reconstructs the implant cross-section across one defect with `kind`,
/// solving the curve fit with `solver`.
///
/// Steps (thesis chapter 6), all in polar form about `input.centre`
/// (`E(θ)` the outer envelope, see [`WallInput`]):
/// 1. The wall's ends are the envelope points A′ = E(θ_A), B′ = E(θ_B);
///    C, D are A′, B′ mirrored across the midline, and must lie within
///    `mirror_tolerance_mm` of the envelope at the mirrored angles
///    ([`CtError::NotOnContour`] otherwise). The template is
///    `R(θ) = reflect(E(2α − θ))` for `θ` from θ_A to θ_B
///    (`template_points` rays), or the explicit template; its ends are
///    replaced by A′ and B′.
/// 2. [`WallKind::CurveFit`]: one [`SegmentProblem`] of `options.function`
///    on the template (chord-length parameters), `C₀ = A′`, `C_m = B′`, with
///    [`Start::G1`]/[`End::G1`] (or C¹) joins whose tangent is the slope at
///    A′ (B′) of a least-squares quadratic through the outer table over
///    `tangent_mm` next to the end (**RECONSTRUCTION**; C¹ takes its speed
///    from a cubic over the same angular width as the defect). A quadratic
///    can only be joined at B (its one inner control point).
/// 3. Inner wall: `PO(u) = C(u) + Dis(u)·N(u)`, `N = (y′, −x′)/|C′|`,
///    `Dis(u) = ±((1 − u)·t_A + u·t_B)` with the sign that points into the
///    head and `t_A`, `t_B` the bone thickness along the outer table's
///    normal `thickness_setback_mm` back from A′ and B′, capped at
///    `max_thickness_mm` (**RECONSTRUCTION**: the thesis gives the offset
///    formula but not how Dis(u) is chosen). The baselines use the same
///    offset with polyline normals and `u` the arc-length fraction.
/// 4. The section (outer A′→B′, inner back) is clipped to the tissue below
///    the bone threshold ([`crate::ct::clip_to_tissue`]), so its end faces
///    follow the bone's cut edge and it never occupies intact bone.
///
/// Errors: [`CtError::DefectCrossesMidline`] (the mirror across the
/// midline: no explicit template, [`WallOptions::template`] not
/// continuing),
/// [`CtError::NotOnContour`] (A, B, C or D not on the outer contour),
/// [`CtError::TemplateNotCovered`], [`CtError::TooLittleIntactContour`] and
/// [`CtError::NoBoneAtEnds`] when the contour around the defect is too
/// short or holds no bone, [`CtError::OuterWallFit`] for a failing fit,
/// [`CtError::ClippedAway`].
pub fn reconstruct_wall<S: SegmentSolver + ?Sized>(
    input: &WallInput<'_>,
    kind: WallKind,
    options: &WallOptions,
    solver: &mut S,
) -> Result<Wall, CtError> {
    let design = design_outer(input, kind, options, None, solver)?;
    let t = design.bone_thickness;
    finish_wall(design, t, input.tissue, options)
}
