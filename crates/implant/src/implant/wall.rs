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
pub use super::polar::Blend;
use super::polar::SEAT_STEP_MM;
use super::polar::{
    angle, blend_onto_bone, fit_err, walk_along, Gap, MirroredThickness, Side, TableWalk,
};
use super::seats::{choose_seats, SeatProfile, SeatRule};
use super::SliceError;
use crate::ct::{clip_to_tissue_keeping, CtError, Polyline, Slice};
use crate::fit::{
    equal_arc_breaks, fit_between, ChainEnds, End, ErrorMeasure, FitOptions, Segment,
    SegmentSolver, Start,
};
use crate::geometry::{Continuity, Curve, Parameterisation, Point};

pub use super::polar::{angle_deg, envelope_radius};
use super::wall_input::ThicknessProfile;
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
    /// The template `R_i` the wall is fitted to (from A′ to B′): the mirror
    /// image (or explicit template) blended onto the bone at its ends
    /// ([`blend_onto_bone`]).
    pub template: Polyline,
    /// The mirror image (or explicit template) as it is, before the blend:
    /// its ends are where the other side of the head puts them.
    pub mirror: Polyline,
    /// How the template was blended onto the bone at A′ and at B′: its
    /// offset from the seat and the blend length.
    pub blends: (Blend, Blend),
    /// The fitted segments from A′ to B′, joined with the wall's continuity
    /// ([`WallKind::CurveFit`] only; more than one where one segment cannot
    /// follow the template within [`WallOptions::fit_tolerance_mm`]).
    pub segments: Vec<Segment>,
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
    /// The bone's direction of travel at A′ and B′ as the bone sees it:
    /// the secants of the threshold iso-contour from each seat over
    /// [`ISO_SECANTS_MM`] (1.5 mm, then 3 mm) of arc length
    /// (`Gap::iso_points` in [`super::polar`]).
    pub iso_dirs: [(Point, Point); 2],
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
    /// The other side's bone thickness across the gap, which the inner
    /// wall follows ([`WallOptions::thickness_profile`] `Mirror` with a
    /// mirrored template; `None`: `Dis(u)` linear).
    pub mirror_thickness: Option<MirroredThickness>,
    /// The outer table beyond A′ and beyond B′, walked away from the gap
    /// (a point every [`BEYOND_STEP_MM`], up to
    /// [`WallOptions::max_thickness_mm`]): where the section is extended
    /// into the bone before clipping ([`WallOptions::fill_ends`]).
    pub beyond: [Vec<Point>; 2],
}

/// The spacing (mm of outer table) of [`OuterDesign::beyond`].
pub const BEYOND_STEP_MM: f64 = 0.5;

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

/// The arc lengths (mm) of the iso-contour secants of the kink measure
/// ([`OuterDesign::iso_kinks_deg`]).
pub const ISO_SECANTS_MM: [f64; 2] = [1.5, 3.0];

impl OuterDesign {
    /// The wall's end directions at A′ and B′ (direction of travel): the
    /// segment's derivatives, or the polyline's first and last legs.
    pub fn end_directions(&self) -> (Point, Point) {
        match (self.segments.first(), self.segments.last()) {
            (Some(f), Some(l)) => (f.deriv(0.0), l.deriv(1.0)),
            _ => {
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

    /// The kinks against the bone at A′ and B′ over 3 mm (degrees): the
    /// second pair of [`OuterDesign::iso_kinks_deg`].
    pub fn kinks_deg(&self) -> (f64, f64) {
        self.iso_kinks_deg()[1]
    }

    /// The kinks as the bone sees them (degrees), at A′ and B′ for each
    /// arc length `L` of [`ISO_SECANTS_MM`] (1.5 mm, then 3 mm): the angle
    /// between the wall's secant over its last `L` mm of arc length at
    /// the seat and the secant over `L` mm of the bone's threshold
    /// iso-contour from the seat ([`OuterDesign::iso_dirs`]), i.e. the
    /// turn at the seat seen at the scale `L` from both sides. A wall
    /// whose end derivative is tangent to the bone but that turns within
    /// its last millimetres (a G¹ leg shrunk to nothing) shows here as the
    /// corner it is.
    pub fn iso_kinks_deg(&self) -> [(f64, f64); 2] {
        let w = &self.outer;
        let r = w.reversed();
        let (Some(na), Some(nb)) = (w.nearest(self.a), r.nearest(self.b)) else {
            return [(f64::NAN, f64::NAN); 2];
        };
        [0, 1].map(|k| {
            let l = ISO_SECANTS_MM[k];
            let qa = walk_along(w, &na, l, true);
            let qb = walk_along(&r, &nb, l, true);
            let (ta, tb) = self.iso_dirs[k];
            (angle_deg(qa - self.a, ta), angle_deg(self.b - qb, tb))
        })
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
    segments: Vec<Segment>,
    fit_error: f64,
    evaluations: u64,
    points: Vec<Point>,
}

/// The joins of the outer wall's chain to the bone at A′ and B′, with
/// `options.continuity` (C⁰: free). A quadratic has one inner control
/// point: it is joined at B′ only.
fn chain_ends(options: &WallOptions, joins: &Joins) -> ChainEnds {
    let (d_a, d_b) = joins.derivatives;
    let start = match options.continuity {
        _ if options.function.degree() == 2 => Start::Free,
        Continuity::C0 => Start::Free,
        Continuity::C1 => Start::C1 { derivative: d_a },
        Continuity::G1 => Start::G1 {
            leg: joins.tangents.0,
        },
    };
    let end = match options.continuity {
        Continuity::C0 => End::Free,
        Continuity::C1 => End::C1 { derivative: d_b },
        Continuity::G1 => End::G1 {
            dir: joins.tangents.1,
        },
    };
    ChainEnds { start, end }
}

/// The fit options of the outer wall's chain: `options.function` and
/// `options.continuity` on the template's chord-length parameters (the
/// thesis's fixed-parameter `E`), `options.search`, `budget` evaluations
/// per piece.
fn chain_options(options: &WallOptions, budget: u64) -> FitOptions {
    FitOptions {
        search: options.search,
        budget_per_segment: budget,
        parameterisation: Parameterisation::ChordLength,
        error: ErrorMeasure::Fixed,
        ..FitOptions::new(options.function, options.continuity)
    }
}

/// The break indices of a chain of `count` pieces on `data`: equal arc
/// length ([`crate::fit::equal_arc_breaks`]), the last point appended.
fn chain_breaks(data: &[Point], count: usize) -> Result<Vec<usize>, SliceError> {
    let (mut breaks, _) = equal_arc_breaks(data, false, &[], count).map_err(fit_err)?;
    breaks.push(data.len() - 1);
    Ok(breaks)
}

/// `E = Σᵢ |Rᵢ − P(sᵢ)|²` of a chain of `segments` on `data` split at the
/// chain's breaks, with chord-length parameters on each piece (the fit's
/// objective, summed).
fn chain_error(segments: &[Segment], data: &[Point]) -> Result<f64, SliceError> {
    let breaks = chain_breaks(data, segments.len())?;
    Ok(segments
        .iter()
        .zip(breaks.windows(2))
        .map(|(seg, w)| {
            let piece = &data[w[0]..=w[1]];
            seg.sse(piece, &Parameterisation::ChordLength.params(piece))
        })
        .sum())
}

/// The chain of `count` segments fitted to `data` in sequence (the
/// chapter-5 sequential chain, [`crate::fit::fit_between`], with the
/// bone's joins at both ends), each piece solved by `solver` with
/// `budget` evaluations.
fn fit_chain<S: SegmentSolver + ?Sized>(
    options: &WallOptions,
    data: &[Point],
    joins: &Joins,
    count: usize,
    budget: u64,
    solver: &mut S,
) -> Result<(Vec<Segment>, u64), SliceError> {
    let breaks = chain_breaks(data, count)?;
    let ends = chain_ends(options, joins);
    let fit = fit_between(data, &breaks, ends, &chain_options(options, budget), solver)
        .map_err(fit_err)?;
    let evaluations = fit.metrics.evaluations;
    Ok((
        fit.segments.into_iter().map(|s| s.segment).collect(),
        evaluations,
    ))
}

/// The points of a chain at `m` parameters: `u = (k + v)/count` on its
/// `k`-th segment at local `v` (the wall's global parameter).
fn chain_points(segments: &[Segment], us: &[f64]) -> Vec<Point> {
    us.iter().map(|&u| chain_eval(segments, u).0).collect()
}

/// The segment and local parameter of the global parameter `u` of a chain,
/// and the point there.
fn chain_eval(segments: &[Segment], u: f64) -> (Point, usize, f64) {
    let n = segments.len();
    let x = (u.clamp(0.0, 1.0) * n as f64).min(n as f64);
    let k = (x.floor() as usize).min(n - 1);
    let v = x - k as f64;
    (segments[k].eval(v), k, v)
}

/// The curve fit of the outer wall: one segment, then chains of 2, 3, …
/// up to [`WallOptions::max_segments`] while the fit's RMS to the template
/// `√(E/n)` exceeds [`WallOptions::fit_tolerance_mm`] (the chain with the
/// smallest RMS is kept), each piece with the full budget; evaluated at
/// `us`.
fn fit_outer_wall<S: SegmentSolver + ?Sized>(
    options: &WallOptions,
    data: &[Point],
    joins: &Joins,
    us: &[f64],
    solver: &mut S,
) -> Result<OuterWall, SliceError> {
    let mut best: Option<(Vec<Segment>, f64)> = None;
    let mut evaluations = 0;
    // A quadratic has one inner control point: it can be joined to the bone
    // at one end only, and in a chain it could not be joined to both its
    // neighbour and the bone at B′; it stays one segment.
    let most = if options.function.degree() == 2 {
        1
    } else {
        options.max_segments.max(1)
    };
    for count in 1..=most {
        if count > 1 && data.len() < count * (options.function.min_points() + 1) {
            break;
        }
        let (segments, used) = fit_chain(options, data, joins, count, options.budget, solver)?;
        evaluations += used;
        let e = chain_error(&segments, data)?;
        if best.as_ref().is_none_or(|b| e < b.1) {
            best = Some((segments, e));
        }
        let rms = (e / data.len() as f64).sqrt();
        if rms <= options.fit_tolerance_mm {
            break;
        }
    }
    let (segments, fit_error) = best.ok_or(SliceError::OuterWallFit {
        source: crate::fit::FitError::TooFewSegments {
            requested: 0,
            minimum: 1,
        },
    })?;
    Ok(OuterWall {
        fit_error,
        evaluations,
        points: chain_points(&segments, us),
        segments,
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
) -> Result<Joins, SliceError> {
    let chord = ends.1 - ends.0;
    let ta = gap
        .local_tangent(Side::A, walks.0, options.tangent_mm)
        .ok_or(SliceError::TooLittleIntactContour {
            before: 0,
            after: 1,
        })?;
    let tb = gap
        .local_tangent(Side::B, walks.1, options.tangent_mm)
        .ok_or(SliceError::TooLittleIntactContour {
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

/// The gap at the tips of a wall input and the outer table walked from
/// each tip (far enough for the seat search, the tangents and the
/// thickness). Checks first that the defect does not cross the midline
/// when the mirror is to serve it.
fn tip_walks<'a>(
    input: &WallInput<'a>,
    options: &WallOptions,
) -> Result<(Gap<'a>, TableWalk, TableWalk), SliceError> {
    let line = input.midline;
    if template_source(input, options) == TemplateSource::Mirror
        && crosses_midline(input.a, input.b, &line)
    {
        return Err(CtError::DefectCrossesMidline {
            a_x: input.a.x,
            b_x: input.b.x,
            midline_x: line.x_at(0.5 * (input.a.y + input.b.y)),
        }
        .into());
    }
    let tips = Gap::new(*input);
    let reach = options.seat_max_mm
        + options
            .tangent_mm
            .max(1.5 * options.thickness_setback_mm + 1.0)
            .max(6.0);
    let walk = |side: Side| {
        tips.table(side, reach)
            .ok_or(SliceError::TooLittleIntactContour {
                before: 0,
                after: 0,
            })
    };
    let (a, b) = (walk(Side::A)?, walk(Side::B)?);
    Ok((tips, a, b))
}

/// What the candidate seats behind A and behind B offer on one slice
/// (index `k` is `k·0.25` mm behind the tip, up to `seat_max_mm`): the
/// table's bend (`Gap::bends` in [`super::polar`]), the kink a wall joined
/// there would make against the bone's iso-contour (the angle between the
/// join tangent of [`WallOptions::tangent_mm`] and the iso-contour secants
/// over [`ISO_SECANTS_MM`], the larger) and the template's offset from the
/// bone on the seat's ray (the mirror image; an explicit template's
/// distance).
pub fn seat_profiles(
    input: &WallInput<'_>,
    options: &WallOptions,
) -> Result<(SeatProfile, SeatProfile), SliceError> {
    let (tips, tip_a, tip_b) = tip_walks(input, options)?;
    let side = |walk: &TableWalk, side: Side| {
        let steps = (options.seat_max_mm / SEAT_STEP_MM).floor().max(0.0) as usize;
        let (mut kink_deg, mut offset_mm) = (Vec::new(), Vec::new());
        for k in 0..=steps {
            let from = walk.from(k as f64 * SEAT_STEP_MM);
            let p = from.at(0.0);
            let t = tips.local_tangent(side, &from, options.tangent_mm);
            let iso = tips.iso_points(side, p, ISO_SECANTS_MM);
            let kink = match (t, iso) {
                (Some(t), Some(qs)) => qs
                    .iter()
                    .zip(ISO_SECANTS_MM)
                    .flat_map(|(&q, l)| {
                        // The join tangent, and the secant of the wall's
                        // expected last `l` mm (the blended template's
                        // turn), against the bone's `l` mm secant.
                        let (into, bone) = match side {
                            Side::A => (t, p - q),
                            Side::B => (-t, q - p),
                        };
                        let w = tips.blended_near_seat(
                            p,
                            into,
                            l,
                            options.blend_slope_deg,
                            options.blend_min_mm,
                        );
                        let wall = if side == Side::A { w - p } else { p - w };
                        [angle_deg(t, bone), angle_deg(wall, bone)]
                    })
                    .filter(|k| k.is_finite())
                    .fold(0.0, f64::max),
                _ => 0.0,
            };
            kink_deg.push(kink);
            offset_mm.push(tips.template_offset(p));
        }
        SeatProfile {
            bend_deg: Gap::bends(walk, options.seat_max_mm),
            kink_deg,
            offset_mm,
        }
    };
    Ok((side(&tip_a, Side::A), side(&tip_b, Side::B)))
}

/// The seat rule of `options` with `change_deg_per_mm` between slices.
pub fn seat_rule(options: &WallOptions, change_deg_per_mm: f64) -> SeatRule {
    SeatRule {
        bend_deg: options.seat_bend_deg,
        kink_deg: options.seat_kink_deg,
        offset_tol_mm: options.seat_offset_tol_mm,
        offset_deg_per_mm: options.seat_offset_deg_per_mm,
        setback_deg_per_mm: options.seat_setback_deg_per_mm,
        change_deg_per_mm,
    }
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
) -> Result<OuterDesign, SliceError> {
    let (tips, tip_a, tip_b) = tip_walks(input, options)?;
    let seats = match seats {
        Some(s) => s,
        None => {
            let profiles = seat_profiles(input, options)?;
            choose_seats(&[profiles], &[0], &seat_rule(options, 0.0))[0]
        }
    };
    let (walk_a, walk_b) = (tip_a.from(seats.0), tip_b.from(seats.1));
    let gap = tips.moved(walk_a.at(0.0), walk_b.at(0.0));
    let (ends, raw, source) = template_for(&gap, input, options)?;
    let (a, b) = (ends.a, ends.b);
    let joins = joins(&gap, (a, b), (&walk_a, &walk_b), options)?;
    let (data, blends) = blend_onto_bone(
        &raw,
        (a, b),
        joins.tangents,
        input.centre,
        options.blend_slope_deg,
        options.blend_min_mm,
    );
    let mut bare = raw.clone();
    let last = bare.len() - 1;
    (bare[0], bare[last]) = (a, b);
    let us = unit_params(options.wall_points);
    let outer = match kind {
        WallKind::CurveFit => fit_outer_wall(options, &data, &joins, &us, solver)?,
        WallKind::Template => OuterWall {
            segments: Vec::new(),
            fit_error: 0.0,
            evaluations: 0,
            points: bare,
        },
        WallKind::Straight => OuterWall {
            segments: Vec::new(),
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
        return Err(SliceError::NoBoneAtEnds {
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
        mirror: Polyline::open(raw),
        blends,
        segments: outer.segments,
        fit_error: outer.fit_error,
        evaluations: outer.evaluations,
        outer: Polyline::open(outer.points),
        tangents: joins.tangents,
        derivatives: joins.derivatives,
        smoothing_shift_mm: 0.0,
        iso_dirs: {
            let qa = gap.iso_points(Side::A, a, ISO_SECANTS_MM);
            let qb = gap.iso_points(Side::B, b, ISO_SECANTS_MM);
            [0, 1].map(|k| {
                let qa = qa.map_or(a, |q| q[k]);
                let qb = qb.map_or(b, |q| q[k]);
                (a - qa, qb - b)
            })
        },
        seats,
        bone_thickness,
        centre: input.centre,
        template_source: source,
        mirror_thickness: match (options.thickness_profile, source) {
            (ThicknessProfile::Mirror, TemplateSource::Mirror) => {
                gap.mirrored_thickness(options.template_points, cap)
            }
            _ => None,
        },
        beyond: [&walk_a, &walk_b].map(|w| {
            let n = (options.max_thickness_mm / BEYOND_STEP_MM).ceil().max(0.0) as usize;
            (1..=n).map(|k| w.at(BEYOND_STEP_MM * k as f64)).collect()
        }),
    })
}

/// Refits a fitted outer wall to `points` (from A′ to B′, e.g. the wall
/// smoothed across slices) by Levenberg–Marquardt with the same function,
/// ends, joins and number of segments, and records how far it moved and
/// its `E` against the template. A baseline design (no segment) is left
/// unchanged.
pub fn refit_outer(
    design: &mut OuterDesign,
    points: Vec<Point>,
    options: &WallOptions,
) -> Result<(), SliceError> {
    if design.segments.is_empty() {
        return Ok(());
    }
    let joins = Joins {
        derivatives: design.derivatives,
        tangents: design.tangents,
    };
    let count = design.segments.len();
    let (segments, _) = fit_chain(
        options,
        &points,
        &joins,
        count,
        2_000,
        &mut crate::fit::LmSolver::default(),
    )?;
    let us = unit_params(options.wall_points);
    let outer = chain_points(&segments, &us);
    let shift = outer
        .iter()
        .map(|&p| design.outer.distance_to(p))
        .fold(0.0, f64::max);
    design.fit_error = chain_error(&segments, &design.template.points)?;
    design.smoothing_shift_mm = shift;
    design.outer = Polyline::open(outer);
    design.segments = segments;
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

/// The inner wall of a fitted chain: `PO(u) = C(u) + Dis(u)·N(u)` at the
/// global parameters `us` ([`chain_eval`]), `Dis = dis(u, C(u))` with the
/// sign that points towards `o`.
fn offset_chain(
    segments: &[Segment],
    us: &[f64],
    o: Point,
    dis: &dyn Fn(f64, Point) -> f64,
) -> Vec<Point> {
    let (mid, k, v) = chain_eval(segments, 0.5);
    let n_mid = crate::geometry::offset_point(&segments[k], v, 1.0) - mid;
    let sign = if n_mid.dot(o - mid) >= 0.0 { 1.0 } else { -1.0 };
    us.iter()
        .map(|&u| {
            let (c, k, v) = chain_eval(segments, u);
            crate::geometry::offset_point(&segments[k], v, sign * dis(u, c))
        })
        .collect()
}

/// The inner wall of a baseline polyline `p`: the same offset with
/// polyline normals and `u` the arc-length fraction.
fn offset_polyline(p: &[Point], o: Point, dis: &dyn Fn(f64, Point) -> f64) -> Vec<Point> {
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
            p[i] + polyline_normal(p, i) * (sign * dis(s / total, p[i]))
        })
        .collect()
}

/// The section extended into the bone at both ends before clipping: the
/// outer wall continued along the outer table beyond A′ and B′ by the
/// end's thickness ([`OuterDesign::beyond`]), offset inwards by that
/// thickness, then the inner wall `inner` (A″ → B″) between. Clipping
/// removes the extension where it is bone and keeps it where the bone
/// was cut away behind the wall's end face, so the implant reaches the
/// bone's cut face whatever its angle to the wall's normal.
fn filled_section(design: &OuterDesign, inner: &[Point], (t_a, t_b): (f64, f64)) -> Polyline {
    let take = |k: usize, t: f64| {
        let n = ((t / BEYOND_STEP_MM).ceil() as usize).min(design.beyond[k].len());
        design.beyond[k][..n].to_vec()
    };
    let (ext_a, ext_b) = (take(0, t_a), take(1, t_b));
    let mut outer: Vec<Point> = ext_a.iter().rev().copied().collect();
    let first = outer.len();
    outer.extend(design.outer.points.iter().copied());
    let last = outer.len();
    outer.extend(ext_b.iter().copied());
    let o = design.centre;
    let offset = |i: usize, t: f64| {
        let n = polyline_normal(&outer, i);
        let n = if n.dot(o - outer[i]) >= 0.0 { n } else { -n };
        outer[i] + n * t
    };
    let mut inner_all: Vec<Point> = (0..first).map(|i| offset(i, t_a)).collect();
    inner_all.extend(inner.iter().copied());
    inner_all.extend((last..outer.len()).map(|i| offset(i, t_b)));
    let mut pts = outer;
    pts.extend(inner_all.iter().rev().copied());
    Polyline::closed(pts)
}

/// The radius (mm) of the capsules kept from clipping along the wall's
/// last millimetres at each seat (`seat_capsules`): a grid cell and a
/// half of the clipping field (4 cells per 0.96 mm pixel).
pub const SEAT_KEEP_RADIUS_MM: f64 = 0.35;

/// The capsules about the outer wall's first and last `length` mm (from
/// A′ and from B′), radius [`SEAT_KEEP_RADIUS_MM`], that clipping leaves
/// as designed ([`crate::ct::clip_to_tissue_keeping`]); none for
/// `length ≤ 0`.
fn seat_capsules(design: &OuterDesign, length: f64) -> Vec<(Point, Point, f64)> {
    if length <= 0.0 {
        return Vec::new();
    }
    let w = &design.outer;
    let r = w.reversed();
    let mut keep = Vec::new();
    for (poly, seat) in [(w, design.a), (&r, design.b)] {
        if let Some(n) = poly.nearest(seat) {
            let q = walk_along(poly, &n, length, true);
            keep.push((seat, q, SEAT_KEEP_RADIUS_MM));
        }
    }
    keep
}

/// The second step: the inner wall at `thickness` (mm at A′ and B′), the
/// section, and its clipping against `tissue` (the CT slice and bone
/// threshold; `None` or `options.clip_subdivision = 0`: no clipping).
/// Error [`SliceError::ClippedAway`] when no tissue is left in the section.
pub fn finish_wall(
    design: OuterDesign,
    thickness: (f64, f64),
    tissue: Option<(&Slice<'_>, i16)>,
    options: &WallOptions,
) -> Result<Wall, SliceError> {
    let us = unit_params(options.wall_points);
    let o = design.centre;
    let (t_a, t_b) = thickness;
    // Dis(u): linear from t_A to t_B, plus the other side's excess
    // thickness at the point's polar angle where the profile follows the
    // mirror; never below a fifth of the thinner end.
    let floor = 0.2 * t_a.min(t_b);
    let dis = |u: f64, c: Point| -> f64 {
        let excess = design
            .mirror_thickness
            .as_ref()
            .map_or(0.0, |m| m.excess(angle(c, o)));
        ((1.0 - u) * t_a + u * t_b + excess).max(floor)
    };
    let inner_pts = if design.segments.is_empty() {
        offset_polyline(&design.outer.points, o, &dis)
    } else {
        offset_chain(&design.segments, &us, o, &dis)
    };
    let inner_rev: Vec<Point> = inner_pts.iter().rev().copied().collect();
    let mut pts = design.outer.points.clone();
    pts.extend(inner_rev.iter().copied());
    let raw_section = Polyline::closed(pts);
    let (section, clipped_fraction) = match tissue {
        Some((slice, threshold)) if options.clip_subdivision > 0 => {
            let to_clip = if options.fill_ends {
                filled_section(&design, &inner_pts, thickness)
            } else {
                raw_section.clone()
            };
            let keep = seat_capsules(&design, options.seat_keep_mm);
            let c =
                clip_to_tissue_keeping(&to_clip, slice, threshold, options.clip_subdivision, &keep)
                    .ok_or(SliceError::ClippedAway)?;
            let before = raw_section.area().abs().max(f64::MIN_POSITIVE);
            (c.section, (1.0 - c.area_after / before).max(0.0))
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
/// 2. [`WallKind::CurveFit`]: one [`crate::fit::SegmentProblem`] of `options.function`
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
///    formula but not how Dis(u) is chosen). With
///    [`ThicknessProfile::Mirror`] the other side's thickness profile less
///    its chord is added ([`MirroredThickness::excess`], beyond the
///    thesis). The baselines use the same offset with polyline normals and
///    `u` the arc-length fraction.
/// 4. The section (outer A′→B′, inner back; with
///    [`WallOptions::fill_ends`] extended into the bone along the outer
///    table beyond both ends) is clipped to the tissue below the bone
///    threshold ([`crate::ct::clip_to_tissue`]), so it never occupies
///    intact bone, and its end faces follow the bone's cut edge where it
///    reaches into bone (with `fill_ends`, wherever the cut face lies).
///
/// Errors: [`CtError::DefectCrossesMidline`] (the mirror across the
/// midline: no explicit template, [`WallOptions::template`] not
/// continuing),
/// [`CtError::NotOnContour`] (A, B, C or D not on the outer contour),
/// [`SliceError::TemplateNotCovered`], [`SliceError::TooLittleIntactContour`] and
/// [`SliceError::NoBoneAtEnds`] when the contour around the defect is too
/// short or holds no bone, [`SliceError::OuterWallFit`] for a failing fit,
/// [`SliceError::ClippedAway`].
pub fn reconstruct_wall<S: SegmentSolver + ?Sized>(
    input: &WallInput<'_>,
    kind: WallKind,
    options: &WallOptions,
    solver: &mut S,
) -> Result<Wall, SliceError> {
    let design = design_outer(input, kind, options, None, solver)?;
    let t = design.bone_thickness;
    finish_wall(design, t, input.tissue, options)
}
