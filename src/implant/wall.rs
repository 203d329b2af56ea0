//! One slice's implant cross-section: the outer wall between the defect
//! ends (mirrored template, then the chapter-5 curve fit with both ends
//! fixed and joined G¹ or C¹ to the intact outer contour), the inner wall by
//! the offset `PO(u) = C(u) + Dis(u)·N(u)`, and the closed section between
//! them (thesis chapter 6).
//!
//! The function here works on contours only (mm, the slice frame of
//! [`crate::ct`]), so the real defect and the artificial defects of the
//! validation share it.

use crate::ct::{reflect, CtError, Polyline};
use crate::fit::{
    End, FitError, FunctionType, LmSolver, SearchSpaceOptions, Segment, SegmentProblem,
    SegmentSolver, Start,
};
use crate::geometry::{offset_linear, Continuity, Curve, LinearDistance, Parameterisation, Point};
use crate::problem::Problem;

/// How the outer wall across the defect is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum WallKind {
    /// The thesis: one (rational) Bézier segment from A to B fitted to the
    /// mirrored template, ends fixed, G¹/C¹ joins with the intact contour.
    CurveFit,
    /// Baseline: the mirrored template points themselves (ends replaced by A
    /// and B), joined by straight segments; no curve fit.
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
    /// The join with the intact outer contour at both ends: G¹ (default) or
    /// C¹ (C⁰ leaves the inner control points free).
    pub continuity: Continuity,
    /// Objective evaluations for the fit (default 10 000, the chapter-5
    /// budget per segment).
    pub budget: u64,
    /// Data points taken along the template (default 48).
    pub template_points: usize,
    /// Points on each wall of the section (default 64).
    pub wall_points: usize,
    /// How far (mm) C and D may lie from the mirrored outer envelope (default
    /// 15): a bound on the head's left–right asymmetry at the defect.
    pub mirror_tolerance_mm: f64,
    /// How far back from A and B (arc length, mm) the bone thickness is
    /// measured, clear of the bone end faces (default 4).
    pub thickness_setback_mm: f64,
    /// The search space of the fit.
    pub search: SearchSpaceOptions,
}

impl Default for WallOptions {
    fn default() -> Self {
        WallOptions {
            function: FunctionType::RationalCubic,
            continuity: Continuity::G1,
            budget: 10_000,
            template_points: 48,
            wall_points: 64,
            mirror_tolerance_mm: 15.0,
            thickness_setback_mm: 4.0,
            search: SearchSpaceOptions::default(),
        }
    }
}

/// The contours around one defect, in polar form about a centre on the
/// mid-sagittal line (so that the reflection `x ↦ 2M_x − x` maps the ray at
/// angle `θ` to the ray at `π − θ`).
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
    /// range are ever queried.
    pub outer: &'a [&'a Polyline],
    /// Whether a point (mm) is bone; used to measure the thickness.
    pub is_bone: &'a dyn Fn(Point) -> bool,
    /// The polar centre: `(M_x, y)` inside the head.
    pub centre: Point,
    /// The mid-sagittal line `x = M_x` in mm.
    pub midline_x: f64,
    /// The defect end A (mm): its polar angle starts the gap.
    pub a: Point,
    /// The defect end B (mm): its polar angle ends the gap.
    pub b: Point,
}

impl std::fmt::Debug for WallInput<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("WallInput")
            .field("centre", &self.centre)
            .field("midline_x", &self.midline_x)
            .field("a", &self.a)
            .field("b", &self.b)
            .finish_non_exhaustive()
    }
}

/// The farthest crossing (mm from `o`) of the ray from `o` at angle `theta`
/// with any of `polys`; `None` if the ray misses them all.
pub fn envelope_radius(polys: &[&Polyline], o: Point, theta: f64) -> Option<f64> {
    let d = Point::new(theta.cos(), theta.sin());
    let mut best: Option<f64> = None;
    for p in polys {
        for i in 0..p.segment_count() {
            let (u, v) = p.segment(i);
            let e = v - u;
            let den = d.cross(e);
            if den.abs() < 1e-15 {
                continue;
            }
            let w = u - o;
            let r = w.cross(e) / den;
            let t = w.cross(d) / den;
            if r > 0.0 && (0.0..=1.0).contains(&t) && best.is_none_or(|b| r > b) {
                best = Some(r);
            }
        }
    }
    best
}

/// One reconstructed cross-section.
#[derive(Clone, Debug, PartialEq)]
pub struct Wall {
    /// The wall's start, A on the contour.
    pub a: Point,
    /// The wall's end, B on the contour.
    pub b: Point,
    /// C = A reflected across `M_x`.
    pub c: Point,
    /// D = B reflected across `M_x`.
    pub d: Point,
    /// The mirrored template `R_i` (reflected back; from near A to near B).
    pub template: Polyline,
    /// The fitted segment ([`WallKind::CurveFit`] only).
    pub segment: Option<Segment>,
    /// The fit's `E = Σ|Rᵢ − P(sᵢ)|²` (mm², 0 for the baselines).
    pub fit_error: f64,
    /// Objective evaluations used by the fit.
    pub evaluations: u64,
    /// The outer wall from A to B.
    pub outer: Polyline,
    /// The inner wall from B' to A' (the offset, reversed).
    pub inner: Polyline,
    /// The closed section: outer A→B, then inner B'→A'.
    pub section: Polyline,
    /// Bone thickness measured at A and at B (mm).
    pub thickness: (f64, f64),
    /// The unit tangents of the intact contour at A and at B (direction of
    /// travel A→B).
    pub tangents: (Point, Point),
}

impl Wall {
    /// The angle (degrees) between the wall's tangent and the intact
    /// contour's at A and at B: 0 for an exact G¹ join.
    pub fn join_angles_deg(&self) -> (f64, f64) {
        let ang = |u: Point, v: Point| {
            let (u, v) = (u.normalize(), v.normalize());
            match (u, v) {
                (Some(u), Some(v)) => u.cross(v).atan2(u.dot(v)).abs().to_degrees(),
                _ => f64::NAN,
            }
        };
        match &self.segment {
            Some(s) => (
                ang(s.deriv(0.0), self.tangents.0),
                ang(s.deriv(1.0), self.tangents.1),
            ),
            None => {
                let p = &self.outer.points;
                let n = p.len();
                (
                    ang(p[1] - p[0], self.tangents.0),
                    ang(p[n - 1] - p[n - 2], self.tangents.1),
                )
            }
        }
    }
}

/// A cubic fitted by least squares (chord-length parameters) to `points`,
/// as the neighbouring segment of a chapter-5 piecewise fit would be; its
/// derivative at the last point (`at_end`) or the first.
fn neighbour_derivative(points: Vec<Point>, at_end: bool) -> Result<Point, FitError> {
    let p = SegmentProblem::with_parameterisation(
        FunctionType::Cubic,
        points,
        Parameterisation::ChordLength,
        Start::Free,
        &SearchSpaceOptions::default(),
    )?;
    let sol = LmSolver::default().solve(&p, 2_000);
    let seg = p.segment(&sol.x);
    Ok(if at_end {
        seg.deriv(1.0)
    } else {
        seg.deriv(0.0)
    })
}

/// The unit normal of a polyline at vertex `i` by central differences,
/// right of the direction of travel: `(y′, −x′)/|·|`, as
/// [`crate::geometry::Curve::unit_normal`].
fn polyline_normal(p: &[Point], i: usize) -> Point {
    let n = p.len();
    let d = p[(i + 1).min(n - 1)] - p[i.saturating_sub(1)];
    Point::new(d.y, -d.x).normalize().unwrap_or(Point::ZERO)
}

/// The bone thickness along the inward ray from the outer point `p`
/// towards `o`: the length of the first run of bone, stepping 0.1 mm and
/// ending at the first 0.5 mm without bone.
fn thickness_at(p: Point, o: Point, is_bone: &dyn Fn(Point) -> bool) -> f64 {
    let Some(dir) = (o - p).normalize() else {
        return 0.0;
    };
    let (step, max_gap) = (0.1, 0.5);
    let (mut last_bone, mut gap) = (0.0, 0.0);
    let mut s = 0.0;
    let limit = p.distance(o);
    // Start just inside the surface.
    while s < limit {
        s += step;
        if is_bone(p + dir * s) {
            last_bone = s;
            gap = 0.0;
        } else if last_bone > 0.0 || s > 2.0 {
            gap += step;
            if gap >= max_gap {
                break;
            }
        }
    }
    last_bone
}

/// The polar angle of `p` about `o`.
fn angle(p: Point, o: Point) -> f64 {
    (p.y - o.y).atan2(p.x - o.x)
}

/// `θ − θ₀` wrapped into `(−π, π]`.
fn wrap(d: f64) -> f64 {
    let t = std::f64::consts::TAU;
    let r = d.rem_euclid(t);
    if r > std::f64::consts::PI {
        r - t
    } else {
        r
    }
}

/// The defect in polar form about `input.centre`: the outer envelope
/// `E(θ)` and the gap's rays from A′ at `th_a` over the signed angular width
/// `span`, each end moved 0.5 mm (arc) into the intact bone so that the ray
/// meets the contour that the cut at A (B) ends.
struct Gap<'a> {
    input: WallInput<'a>,
    /// The polar angle of A′ (radians).
    th_a: f64,
    /// The signed angular width from A′ to B′ (radians).
    span: f64,
}

/// The wall's ends on the envelope and their reflections across `M_x`.
#[derive(Clone, Copy, Debug)]
struct WallEnds {
    /// A′ = E(θ_A).
    a: Point,
    /// B′ = E(θ_B).
    b: Point,
    /// C = A′ reflected.
    c: Point,
    /// D = B′ reflected.
    d: Point,
}

impl<'a> Gap<'a> {
    fn new(input: WallInput<'a>) -> Self {
        let o = input.centre;
        let th_a0 = angle(input.a, o);
        let span0 = wrap(angle(input.b, o) - th_a0);
        let nudge = |p: Point| 0.5 / p.distance(o).max(1e-9) * span0.signum();
        let th_a = th_a0 - nudge(input.a);
        let span = span0 + nudge(input.a) + nudge(input.b);
        Gap { input, th_a, span }
    }

    /// The envelope point `E(θ)`, or `None` where the ray misses.
    fn env(&self, theta: f64) -> Option<Point> {
        let o = self.input.centre;
        envelope_radius(self.input.outer, o, theta)
            .map(|r| o + Point::new(theta.cos(), theta.sin()) * r)
    }

    /// The mirrored envelope `R(θ) = reflect(E(π − θ))`.
    fn mirrored(&self, theta: f64) -> Option<Point> {
        self.env(std::f64::consts::PI - theta)
            .map(|p| reflect(p, self.input.midline_x))
    }

    /// A′, B′ on the envelope (A and B themselves may be the tips of the
    /// inner table; the caller checks that they lie on the bone contour),
    /// and C, D, each within `tol` of the envelope.
    fn ends(&self, tol: f64) -> Result<WallEnds, CtError> {
        let on = |what: &'static str, p: Option<Point>, target: Point| -> Result<Point, CtError> {
            match p {
                Some(q) if q.distance(target) <= tol => Ok(q),
                Some(q) => Err(CtError::NotOnContour {
                    what,
                    distance_mm: q.distance(target),
                    tolerance_mm: tol,
                }),
                None => Err(CtError::NotOnContour {
                    what,
                    distance_mm: f64::INFINITY,
                    tolerance_mm: tol,
                }),
            }
        };
        let (th_a, th_b) = (self.th_a, self.th_a + self.span);
        let a = on("A", self.env(th_a), self.env(th_a).unwrap_or(self.input.a))?;
        let b = on("B", self.env(th_b), self.env(th_b).unwrap_or(self.input.b))?;
        let mx = self.input.midline_x;
        let (c, d) = (reflect(a, mx), reflect(b, mx));
        on(
            "C (A mirrored)",
            self.mirrored(th_a).map(|p| reflect(p, mx)),
            c,
        )?;
        on(
            "D (B mirrored)",
            self.mirrored(th_b).map(|p| reflect(p, mx)),
            d,
        )?;
        Ok(WallEnds { a, b, c, d })
    }

    /// The template `R(θ)` on `template_points` rays from θ_A to θ_B, its
    /// ends replaced by A′ and B′.
    fn template(&self, ends: &WallEnds, options: &WallOptions) -> Result<Vec<Point>, CtError> {
        let n_t = options
            .template_points
            .max(options.function.min_points() + 2);
        let mut data = Vec::with_capacity(n_t);
        for k in 0..n_t {
            let theta = self.th_a + self.span * k as f64 / (n_t - 1) as f64;
            if let Some(p) = self.mirrored(theta) {
                data.push(p);
            }
        }
        if data.len() < options.function.min_points() {
            return Err(CtError::TemplateNotCovered {
                points: data.len(),
                needed: options.function.min_points(),
            });
        }
        let last = data.len() - 1;
        data[0] = ends.a;
        data[last] = ends.b;
        Ok(data)
    }

    /// The derivatives of the intact envelope at A′ and B′ (direction of
    /// travel), from neighbouring cubics over the same angular width
    /// (≤ 30°).
    fn neighbour_derivatives(&self) -> Result<(Point, Point), CtError> {
        let span = self.span;
        let w = span.abs().min(30f64.to_radians()) * span.signum();
        let side = |from: f64, dir: f64| -> Vec<Point> {
            (0..=24)
                .filter_map(|k| self.env(from + dir * w * k as f64 / 24.0))
                .collect()
        };
        let mut before = side(self.th_a, -1.0);
        before.reverse(); // ends at A′
        let after = side(self.th_a + span, 1.0); // starts at B′
        if before.len() < 6 || after.len() < 6 {
            return Err(CtError::TooLittleIntactContour {
                before: before.len(),
                after: after.len(),
            });
        }
        let d_a = neighbour_derivative(before, true).map_err(fit_err)?;
        let d_b = neighbour_derivative(after, false).map_err(fit_err)?;
        Ok((d_a, d_b))
    }

    /// The bone thickness next to A′ and B′, measured `setback_mm` (arc
    /// length) back into intact bone.
    fn thickness(&self, ends: &WallEnds, setback_mm: f64) -> Result<(f64, f64), CtError> {
        let (o, span) = (self.input.centre, self.span);
        let (a, b) = (ends.a, ends.b);
        let set = |p: Point| setback_mm / p.distance(o).max(1e-9);
        let pa = self.env(self.th_a - span.signum() * set(a)).unwrap_or(a);
        let pb = self
            .env(self.th_a + span + span.signum() * set(b))
            .unwrap_or(b);
        let t_a = thickness_at(pa, o, self.input.is_bone);
        let t_b = thickness_at(pb, o, self.input.is_bone);
        if t_a <= 0.0 || t_b <= 0.0 {
            return Err(CtError::NoBoneAtEnds {
                thickness_a: t_a,
                thickness_b: t_b,
            });
        }
        Ok((t_a, t_b))
    }
}

/// The outer wall from A′ to B′.
struct OuterWall {
    /// The fitted segment ([`WallKind::CurveFit`] only).
    segment: Option<Segment>,
    /// The fit's E (0 for the baselines).
    fit_error: f64,
    /// Objective evaluations of the fit.
    evaluations: u64,
    /// The wall's points.
    points: Vec<Point>,
}

impl OuterWall {
    /// A baseline wall: the points themselves, no fit.
    fn polyline(points: Vec<Point>) -> Self {
        OuterWall {
            segment: None,
            fit_error: 0.0,
            evaluations: 0,
            points,
        }
    }
}

/// The joins with the intact contour at A′ and B′.
#[derive(Clone, Copy, Debug)]
struct Joins {
    /// The envelope's derivatives (C¹ joins).
    derivatives: (Point, Point),
    /// The unit tangents (G¹ joins).
    tangents: (Point, Point),
}

/// The curve fit of the outer wall: one [`SegmentProblem`] on the template
/// `data` (chord-length parameters) with the ends fixed and the joins of
/// `options.continuity`, evaluated at `us`.
fn fit_outer_wall<S: SegmentSolver + ?Sized>(
    options: &WallOptions,
    data: &[Point],
    joins: &Joins,
    us: &[f64],
    solver: &mut S,
) -> Result<OuterWall, CtError> {
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
    let problem = SegmentProblem::with_parameterisation(
        options.function,
        data.to_vec(),
        Parameterisation::ChordLength,
        start,
        &options.search,
    )
    .and_then(|p| p.with_end(end))
    .map_err(fit_err)?;
    let sol = solver.solve(&problem, options.budget);
    let seg = problem.segment(&sol.x);
    let e = problem.objective(&sol.x);
    let points: Vec<Point> = us.iter().map(|&u| seg.eval(u)).collect();
    Ok(OuterWall {
        segment: Some(seg),
        fit_error: e,
        evaluations: sol.evaluations,
        points,
    })
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

/// The inner wall of a baseline polyline `p` (of length `length`): the same
/// offset with polyline normals and `u` the arc-length fraction.
fn offset_polyline(p: &[Point], length: f64, o: Point, (t_a, t_b): (f64, f64)) -> Vec<Point> {
    let mid = p.len() / 2;
    let sign = if polyline_normal(p, mid).dot(o - p[mid]) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    let total = length.max(f64::MIN_POSITIVE);
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

/// Reconstructs the implant cross-section across one defect with `kind`,
/// solving the curve fit with `solver`.
///
/// Steps (thesis chapter 6), all in polar form about `input.centre`
/// (`E(θ)` the outer envelope, see [`WallInput`]):
/// 1. The wall's ends are the envelope points A′ = E(θ_A), B′ = E(θ_B);
///    C, D are A′, B′ reflected across `M_x`, and must lie within
///    `mirror_tolerance_mm` of the envelope at the mirrored angles
///    ([`CtError::NotOnContour`] otherwise). The template is
///    `R(θ) = reflect(E(π − θ))` for `θ` from θ_A to θ_B
///    (`template_points` rays); its ends are replaced by A′ and B′.
/// 2. [`WallKind::CurveFit`]: one [`SegmentProblem`] of `options.function`
///    on the template (chord-length parameters), `C₀ = A′`, `C_m = B′`, with
///    [`Start::G1`]/[`End::G1`] (or C¹) joins whose tangent (derivative)
///    comes from a cubic fitted to the intact envelope next to A′ (B′) over
///    the same angular width as the defect (at most 30°). A quadratic can
///    only be joined at B (its one inner control point).
/// 3. Inner wall: `PO(u) = C(u) + Dis(u)·N(u)`, `N = (y′, −x′)/|C′|`,
///    `Dis(u) = ±((1 − u)·t_A + u·t_B)` with the sign that points into the
///    head and `t_A`, `t_B` the bone thickness (first bone run along the
///    inward ray) measured `thickness_setback_mm` back from A′ and B′ into
///    intact bone (**RECONSTRUCTION**: the thesis gives the offset formula
///    but not how Dis(u) is chosen). The baselines use the same offset with
///    polyline normals and `u` the arc-length fraction.
///
/// Errors: [`CtError::DefectCrossesMidline`], [`CtError::NotOnContour`]
/// (A, B, C or D not on the outer contour), [`CtError::TemplateNotCovered`],
/// [`CtError::TooLittleIntactContour`] and [`CtError::NoBoneAtEnds`] when
/// the contour around the defect is too short or holds no bone,
/// [`CtError::OuterWallFit`] for a failing fit.
pub fn reconstruct_wall<S: SegmentSolver + ?Sized>(
    input: &WallInput<'_>,
    kind: WallKind,
    options: &WallOptions,
    solver: &mut S,
) -> Result<Wall, CtError> {
    let (o, mx) = (input.centre, input.midline_x);
    if (input.a.x - mx) * (input.b.x - mx) <= 0.0 {
        return Err(CtError::DefectCrossesMidline {
            a_x: input.a.x,
            b_x: input.b.x,
            midline_x: mx,
        });
    }
    let gap = Gap::new(*input);
    let ends = gap.ends(options.mirror_tolerance_mm)?;
    let (a, b) = (ends.a, ends.b);

    // 1. The template R(θ), and the joins with the intact envelope.
    let data = gap.template(&ends, options)?;
    let template = Polyline::open(data.clone());
    let derivatives = gap.neighbour_derivatives()?;
    let joins = Joins {
        derivatives,
        tangents: (
            derivatives.0.normalize().unwrap_or(b - a),
            derivatives.1.normalize().unwrap_or(b - a),
        ),
    };

    // 2. The outer wall.
    let m = options.wall_points.max(4);
    let us: Vec<f64> = (0..m).map(|k| k as f64 / (m - 1) as f64).collect();
    let outer = match kind {
        WallKind::CurveFit => fit_outer_wall(options, &data, &joins, &us, solver)?,
        WallKind::Template => OuterWall::polyline(data),
        WallKind::Straight => OuterWall::polyline(us.iter().map(|&u| a.lerp(b, u)).collect()),
    };
    let outer_poly = Polyline::open(outer.points.clone());

    // 3. The inner wall.
    let thickness = gap.thickness(&ends, options.thickness_setback_mm)?;
    let inner_pts = match &outer.segment {
        Some(seg) => offset_segment(seg, &us, o, thickness),
        None => offset_polyline(&outer.points, outer_poly.length(), o, thickness),
    };
    let inner_rev: Vec<Point> = inner_pts.iter().rev().copied().collect();
    let mut section = outer.points;
    section.extend(inner_rev.iter().copied());
    Ok(Wall {
        a,
        b,
        c: ends.c,
        d: ends.d,
        template,
        segment: outer.segment,
        fit_error: outer.fit_error,
        evaluations: outer.evaluations,
        outer: outer_poly,
        inner: Polyline::open(inner_rev),
        section: Polyline::closed(section),
        thickness,
        tangents: joins.tangents,
    })
}

fn fit_err(source: FitError) -> CtError {
    CtError::OuterWallFit { source }
}
