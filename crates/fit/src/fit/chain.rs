//! The joint chain: every segment of a piecewise fit solved in one
//! least-squares problem, its C¹ or G¹ joins imposed by construction, so
//! that no segment inherits its predecessor's error.
//!
//! The sequential chain ([`Chain::Sequential`], the thesis's method) fits
//! segment `k` with its start tangent taken from segment `k − 1`: an error
//! in one tangent is passed down the chain. The joint chain
//! ([`Chain::Joint`]) makes the joins shared variables (the G¹ spline
//! parameterisation of Farin 2002, *Curves and Surfaces for CAGD*, 5th ed.,
//! §8.1, and the joint tangent fitting of Plass & Stone 1983, "Curve-fitting
//! with piecewise parametric cubics", SIGGRAPH):
//!
//! * the join points stay at the data break points (interpolated, as in the
//!   thesis and the sequential chain), so the two chains differ only in how
//!   the joins' tangents are chosen;
//! * at a G¹ joint, one unit tangent `u(θ) = (cos θ, sin θ)` shared by both
//!   sides and one free length on each side: `C₁ = J + a·u(θ)` after it,
//!   `C₂ = J − b·u(θ)` before it (cubic functions); a quadratic's one inner
//!   point lies where the tangent lines of its two ends meet;
//! * at a C¹ joint, one shared derivative `d`: `C₁ = J + d/(m w₁)`,
//!   `C₂ = J − d/(m w₂)` (`w₁ = w₂ = 1` for polynomials); quadratics with C¹
//!   joins are determined by their first segment and are refused
//!   ([`FitError::JointQuadraticC1`]);
//! * at a corner, an open end, or a closing joint the sequential chain had
//!   to leave C⁰, each side's control point is free.
//!
//! A closed chain whose closing joint is smooth is cyclic: its first joint's
//! variables are ordered last, so `JᵀJ` is banded with a small border
//! ([`BandedArrow`]), and Levenberg–Marquardt solves each step in
//! `O(n b²)` ([`LeastSquares::normal_structure`]). The solve starts from
//! the sequential chain's curves (the same curves, rewritten in the joint
//! variables), so its `E` is never larger; under the orthogonal error each
//! data point's parameter is its foot point, projected from the sequential
//! chain's.
//!
//! Beyond the thesis: its chains are sequential.

use super::controls::Controls;
use super::metrics::segment_metrics;
use super::span::Outline;
#[cfg(doc)]
use super::Chain;
use super::{End, ErrorMeasure, FitError, FitOptions, FittedSegment, FunctionType};
use crate::geometry::{bounding_box, Continuity, Curve, Point};
use crate::linalg::BandedArrow;
use crate::optim::lm::{LeastSquares, LevenbergMarquardt};
use crate::problem::{Bounds, Problem};
use std::cell::RefCell;

/// The variables of one joint.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Joint {
    /// No shared variable (a corner, an open end, a C⁰ closing).
    Corner,
    /// The tangent angle `θ` at this index.
    G1(usize),
    /// The derivative `(d_x, d_y)` at this index and the next.
    C1(usize),
}

/// How one side of a segment's inner control points is set.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    /// A free point `(x, y)` at this index.
    Free(usize),
    /// A free length along the joint's tangent, at this index.
    Length(usize),
    /// The joint's derivative over `m w` (C¹).
    Derivative,
    /// A quadratic's inner point where both ends' tangent lines meet.
    Meet,
}

/// One segment of the chain: its ends, interior data and variables.
#[derive(Clone, Debug)]
struct Link {
    /// Its start and end joint (indices into `JointChain::joints`).
    joints: (usize, usize),
    /// The end control points (the data break points).
    ends: (Point, Point),
    /// The interior data points and their (stored) parameters.
    points: Vec<Point>,
    params: Vec<f64>,
    /// How `C₁` and `C₂` are set (quadratics: `start` sets `C₁`, `end` is
    /// unused).
    start: Side,
    end: Side,
    /// The inner weights' indices (rational functions).
    w1: Option<usize>,
    w2: Option<usize>,
    /// The first residual (pair) of its points.
    offset: usize,
}

/// The first-order change of a segment's inner control points and weights
/// with one variable.
#[derive(Clone, Copy, Debug, Default)]
struct Sensitivity {
    var: usize,
    c1: Point,
    c2: Point,
    w1: f64,
    w2: f64,
}

/// At most this many variables touch one segment (two joints' derivatives,
/// two free points, two weights).
const MAX_LOCAL: usize = 10;

/// The joint chain as a least-squares problem.
struct JointChain {
    function: FunctionType,
    error: ErrorMeasure,
    kinds: Vec<Joint>,
    links: Vec<Link>,
    bounds: Vec<Bounds>,
    residuals: usize,
    width: usize,
    border: usize,
    /// The point of the last residual evaluation and, under the orthogonal
    /// error, the foot parameters found there (one per residual pair), so
    /// that the normal equations at that point do not project again.
    feet: RefCell<(Vec<f64>, Vec<f64>)>,
}

/// `(cos θ, sin θ)`.
#[inline]
fn unit(theta: f64) -> Point {
    Point::new(theta.cos(), theta.sin())
}

/// `u` turned by +90°.
#[inline]
fn perp(u: Point) -> Point {
    Point::new(-u.y, u.x)
}

impl JointChain {
    /// The controls of link `k` at `x`, and their sensitivities; `None`
    /// when a quadratic's tangent lines do not meet in front of both ends.
    fn controls(&self, k: usize, x: &[f64]) -> Option<(Controls, [Sensitivity; MAX_LOCAL], usize)> {
        let link = &self.links[k];
        let m = self.function.degree();
        let (j0, j1) = link.ends;
        let w1 = link.w1.map_or(1.0, |i| x[i]);
        let w2 = link.w2.map_or(1.0, |i| x[i]);
        let mut sens = [Sensitivity::default(); MAX_LOCAL];
        let mut n = 0;
        let mut push = |s: Sensitivity| {
            sens[n] = s;
            n += 1;
        };
        let free = |i: usize| Point::new(x[i], x[i + 1]);
        let (ka, kb) = (self.kinds[link.joints.0], self.kinds[link.joints.1]);
        let mut c = [j0, Point::ZERO, Point::ZERO, Point::ZERO];
        let mf = m as f64;
        if m == 2 {
            c[2] = j1;
            c[1] = match (link.start, ka, kb) {
                (Side::Meet, Joint::G1(t0), Joint::G1(t1)) => {
                    let (u0, u1) = (unit(x[t0]), unit(x[t1]));
                    let d = j1 - j0;
                    let den = u0.cross(u1);
                    let t = d.cross(u1) / den;
                    let s = u0.cross(d) / den;
                    if !(t > 0.0 && s > 0.0 && t.is_finite() && s.is_finite()) {
                        return None;
                    }
                    let dt0 = -t * perp(u0).cross(u1) / den;
                    let dt1 = (d.cross(perp(u1)) - t * u0.cross(perp(u1))) / den;
                    push(sens_c1(t0, perp(u0) * t + u0 * dt0));
                    push(sens_c1(t1, u0 * dt1));
                    j0 + u0 * t
                }
                // A leg along the start's tangent, else the end's.
                (Side::Length(_), Joint::G1(_), _) | (Side::Free(_), _, _) => {
                    let (p, d) = leg(link.start, ka, j0, 1.0, 1.0, x);
                    for (v, d) in d {
                        push(sens_c1(v, d));
                    }
                    p
                }
                (side, _, _) => {
                    let (p, d) = leg(side, kb, j1, -1.0, 1.0, x);
                    for (v, d) in d {
                        push(sens_c1(v, d));
                    }
                    p
                }
            };
        } else {
            c[3] = j1;
            let (p, d) = leg(link.start, ka, j0, 1.0, mf * w1, x);
            for (v, d) in d {
                push(sens_c1(v, d));
            }
            c[1] = p;
            let (p, d) = leg(link.end, kb, j1, -1.0, mf * w2, x);
            for (v, d) in d {
                push(sens_c2(v, d));
            }
            c[2] = p;
        }
        if let Some(i) = link.w1 {
            let mut s = Sensitivity {
                var: i,
                w1: 1.0,
                ..Sensitivity::default()
            };
            if let (Side::Derivative, Joint::C1(d)) = (link.start, ka) {
                s.c1 = free(d) * (-1.0 / (mf * w1 * w1));
            }
            push(s);
        }
        if let Some(i) = link.w2 {
            let mut s = Sensitivity {
                var: i,
                w2: 1.0,
                ..Sensitivity::default()
            };
            if let (Side::Derivative, Joint::C1(d)) = (link.end, kb) {
                s.c2 = free(d) * (1.0 / (mf * w2 * w2));
            }
            push(s);
        }
        Some((Controls { c, w1, w2 }, sens, n))
    }

    /// `(sᵢ, P(sᵢ), P′(sᵢ))` of interior point `i` of link `k`: the stored
    /// parameter, or its foot point.
    #[inline]
    fn measured(&self, k: &Controls, link: &Link, i: usize) -> (f64, Point, Point) {
        let m = self.function.degree();
        let s = link.params[i];
        match self.error {
            ErrorMeasure::Fixed => {
                let (p, d1, _) = k.eval_d2(m, s);
                (s, p, d1)
            }
            ErrorMeasure::Orthogonal => k.foot(m, link.points[i], s),
        }
    }
}

/// An inner control point set by one side of a segment, at joint `j`
/// (variables `joint`), leaving it in the direction `sign` (+1 from the
/// start, −1 from the end), and its sensitivities to its two variables:
/// a free point; `J + sign·a·u(θ)` (G¹); `J + sign·d/scale` with `scale =
/// m w` (C¹).
fn leg(
    side: Side,
    joint: Joint,
    j: Point,
    sign: f64,
    scale: f64,
    x: &[f64],
) -> (Point, [(usize, Point); 2]) {
    match (side, joint) {
        (Side::Free(i), _) => (
            Point::new(x[i], x[i + 1]),
            [(i, Point::new(1.0, 0.0)), (i + 1, Point::new(0.0, 1.0))],
        ),
        (Side::Length(i), Joint::G1(t)) => {
            let u = unit(x[t]);
            (
                j + u * (sign * x[i]),
                [(i, u * sign), (t, perp(u) * (sign * x[i]))],
            )
        }
        (Side::Derivative, Joint::C1(i)) => {
            let f = sign / scale;
            (
                j + Point::new(x[i], x[i + 1]) * f,
                [(i, Point::new(f, 0.0)), (i + 1, Point::new(0.0, f))],
            )
        }
        _ => unreachable!("a side is built with its joint"),
    }
}

/// A sensitivity of `C₁` only.
fn sens_c1(var: usize, c1: Point) -> Sensitivity {
    Sensitivity {
        var,
        c1,
        ..Sensitivity::default()
    }
}

/// A sensitivity of `C₂` only.
fn sens_c2(var: usize, c2: Point) -> Sensitivity {
    Sensitivity {
        var,
        c2,
        ..Sensitivity::default()
    }
}

impl Problem for JointChain {
    fn dim(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        let mut r = vec![0.0; self.residuals];
        self.residuals(x, &mut r);
        r.iter().map(|v| v * v).sum()
    }
}

impl LeastSquares for JointChain {
    fn residual_count(&self) -> usize {
        self.residuals
    }

    /// `Rᵢ − P(sᵢ)` for the interior points of every link (the ends are
    /// interpolated); infinite where a quadratic's tangent lines do not meet.
    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        let mut feet = self.feet.borrow_mut();
        let (at, params) = &mut *feet;
        at.clear();
        params.clear();
        let keep = self.error == ErrorMeasure::Orthogonal;
        if keep {
            params.resize(self.residuals / 2, f64::NAN);
        }
        for (k, link) in self.links.iter().enumerate() {
            let rows = &mut out[2 * link.offset..2 * (link.offset + link.points.len())];
            let Some((c, _, _)) = self.controls(k, x) else {
                rows.fill(f64::INFINITY);
                continue;
            };
            for (i, o) in rows.chunks_exact_mut(2).enumerate() {
                let (s, p, _) = self.measured(&c, link, i);
                if keep {
                    params[link.offset + i] = s;
                }
                let r = link.points[i];
                o[0] = r.x - p.x;
                o[1] = r.y - p.y;
            }
        }
        if keep {
            at.extend_from_slice(x);
        }
    }

    fn normal_structure(&self) -> Option<(usize, usize)> {
        Some((self.width, self.border))
    }

    /// `JᵀJ` and `Jᵀr` link by link: each residual pair's row is
    /// `−∂P/∂v = −Σ (∂P/∂C, ∂P/∂w)·(∂C/∂v, ∂w/∂v)` over the link's
    /// variables, projected onto the normal under the orthogonal error
    /// (as [`crate::fit::SegmentProblem::jacobian`]).
    fn normal_equations(&self, x: &[f64], r: &[f64], a: &mut BandedArrow, g: &mut [f64]) {
        let m = self.function.degree();
        let feet = self.feet.borrow();
        let cached = (feet.0.as_slice() == x).then_some(feet.1.as_slice());
        for (k, link) in self.links.iter().enumerate() {
            let Some((c, sens, n)) = self.controls(k, x) else {
                continue;
            };
            let sens = &sens[..n];
            let mut row = [Point::ZERO; MAX_LOCAL];
            for i in 0..link.points.len() {
                let (s, d1) = match cached {
                    Some(params) => {
                        let s = params[link.offset + i];
                        (s, c.eval_d2(m, s).1)
                    }
                    None => {
                        let (s, _, d1) = self.measured(&c, link, i);
                        (s, d1)
                    }
                };
                let q = c.partials(m, s);
                for (o, v) in row.iter_mut().zip(sens) {
                    *o = -(v.c1 * q.c1 + v.c2 * q.c2 + q.w1 * v.w1 + q.w2 * v.w2);
                }
                if self.error == ErrorMeasure::Orthogonal {
                    let len = d1.hypot();
                    if len > 0.0 && len.is_finite() {
                        let t = d1 / len;
                        for o in row.iter_mut().take(n) {
                            *o -= t * o.dot(t);
                        }
                    }
                }
                let ri = Point::new(r[2 * (link.offset + i)], r[2 * (link.offset + i) + 1]);
                for p in 0..n {
                    g[sens[p].var] += row[p].dot(ri);
                    for q2 in 0..=p {
                        a.add(sens[p].var, sens[q2].var, row[p].dot(row[q2]));
                    }
                }
            }
        }
    }
}

/// The chain's variables as they are laid out: each one's box and start.
#[derive(Default)]
struct Vars {
    bounds: Vec<Bounds>,
    x0: Vec<f64>,
}

impl Vars {
    /// A new variable starting at `start` in `[lo, hi]` widened to contain
    /// it (the sequential curve is always a feasible start); its index.
    fn add(&mut self, start: f64, lo: f64, hi: f64) -> usize {
        self.bounds.push(Bounds::new(lo.min(start), hi.max(start)));
        self.x0.push(start);
        self.bounds.len() - 1
    }
}

/// One segment of the sequential fit and its span on the outline.
pub(super) struct Fitted<'a> {
    pub(super) segment: &'a FittedSegment,
    pub(super) span: (usize, usize),
}

/// The joint chain of a sequential fit's segments: variables, their start
/// values (the sequential curves) and bounds; `None` when a quadratic's
/// end tangents are parallel (a straight quadratic, whose inner point the
/// meet of its tangent lines cannot place). Fails for quadratics with C¹
/// joins.
fn build(
    outline: &Outline<'_>,
    fitted: &[Fitted<'_>],
    options: &FitOptions,
) -> Result<Option<(JointChain, Vec<f64>)>, FitError> {
    let function = options.function;
    let m = function.degree();
    let n = fitted.len();
    let closed = outline.closed;
    // Joint k is segment k's start; an open chain has one more at its end.
    let count = if closed { n } else { n + 1 };
    let continuity = joint_continuities(fitted, closed, m)?;
    let (lo, hi) = bounding_box(outline.points).expect("an outline has points");
    let centre = lo.lerp(hi, 0.5);
    let reach = 1e3 * (hi - lo).hypot().max(1.0);
    let mut vars = Vars::default();
    // Joint variables, the closing joint's last (the border).
    let mut kinds = vec![Joint::Corner; count];
    let joint_vars = |k: usize, vars: &mut Vars| {
        joint_variables(fitted, continuity[k], k, reach * m as f64, vars)
    };
    let mut links: Vec<Link> = Vec::with_capacity(n);
    let mut offset = 0;
    let (wmin, wmax) = options.search.weight_range;
    let (tmin, tmax) = options.search.t_range;
    for (k, f) in fitted.iter().enumerate() {
        if k > 0 || !closed {
            kinds[k] = joint_vars(k, &mut vars);
        }
        let seg = &f.segment.segment;
        let cp = seg.control_points();
        let weights = seg.weights();
        let (j0, j1) = (cp[0], cp[m]);
        let chord = j0.distance(j1).max(f64::MIN_POSITIVE);
        let legs = (tmin * chord / m as f64, tmax * chord / m as f64);
        let end_joint = if closed { (k + 1) % n } else { k + 1 };
        let (ka, kb) = (continuity[k], continuity[end_joint]);
        let box_ = PointBox { centre, reach };
        let (start, end) = link_sides(m, (ka, kb), &cp, legs, box_, &mut vars);
        let (w1, w2) = match function {
            FunctionType::RationalQuadratic => (Some(vars.add(weights[1], wmin, wmax)), None),
            FunctionType::RationalCubic => (
                Some(vars.add(weights[1], wmin, wmax)),
                Some(vars.add(weights[2], wmin, wmax)),
            ),
            _ => (None, None),
        };
        let all = outline.gather(f.span.0, f.span.1);
        let inner = all.len().saturating_sub(2);
        let params = f.segment.params[1..1 + inner].to_vec();
        links.push(Link {
            joints: (k, end_joint),
            ends: (j0, j1),
            points: all[1..1 + inner].to_vec(),
            params,
            start,
            end,
            w1,
            w2,
            offset,
        });
        offset += inner;
    }
    let lead = vars.bounds.len();
    if closed {
        kinds[0] = joint_vars(0, &mut vars);
    } else {
        kinds[n] = joint_vars(n, &mut vars);
    }
    let border = vars.bounds.len() - lead;
    let Vars { bounds, x0 } = vars;
    let mut chain = JointChain {
        function,
        error: options.error,
        kinds,
        links,
        bounds,
        residuals: 2 * offset,
        width: 0,
        border,
        feet: RefCell::new((Vec::new(), Vec::new())),
    };
    // Tangent lines of a straight quadratic are parallel: no meet.
    let Some(width) = half_bandwidth(&chain, &x0, lead) else {
        return Ok(None);
    };
    chain.width = width;
    Ok(Some((chain, x0)))
}

/// The box of a free control point: `centre ± reach` on both axes.
#[derive(Clone, Copy, Debug)]
struct PointBox {
    centre: Point,
    reach: f64,
}

/// How the inner control points `cp[1]` (and `cp[2]`) of a link of degree
/// `m` between joints of continuity `ka` and `kb` are set, their variables
/// added to `vars` (started at the sequential curve): a free point in
/// `free` (C⁰), a length along the joint's tangent within `legs` (G¹), the
/// joint's derivative (C¹); a quadratic's one point where both tangent
/// lines meet when both joints are G¹.
fn link_sides(
    m: usize,
    (ka, kb): (Continuity, Continuity),
    cp: &[Point],
    legs: (f64, f64),
    free: PointBox,
    vars: &mut Vars,
) -> (Side, Side) {
    let (j0, j1) = (cp[0], cp[m]);
    let (centre, reach) = (free.centre, free.reach);
    let free_point = |p: Point, vars: &mut Vars| {
        let i = vars.add(p.x, centre.x - reach, centre.x + reach);
        vars.add(p.y, centre.y - reach, centre.y + reach);
        Side::Free(i)
    };
    if m == 2 {
        let side = match (ka, kb) {
            (Continuity::G1, Continuity::G1) => Side::Meet,
            (Continuity::G1, _) => {
                let a = cp[1].distance(j0);
                Side::Length(vars.add(a, legs.0, legs.1))
            }
            (_, Continuity::G1) => {
                let b = j1.distance(cp[1]);
                Side::Length(vars.add(b, legs.0, legs.1))
            }
            _ => free_point(cp[1], vars),
        };
        (side, Side::Free(usize::MAX))
    } else {
        let start = match ka {
            Continuity::G1 => Side::Length(vars.add(cp[1].distance(j0), legs.0, legs.1)),
            Continuity::C1 => Side::Derivative,
            Continuity::C0 => free_point(cp[1], vars),
        };
        let end = match kb {
            Continuity::G1 => Side::Length(vars.add(j1.distance(cp[2]), legs.0, legs.1)),
            Continuity::C1 => Side::Derivative,
            Continuity::C0 => free_point(cp[2], vars),
        };
        (start, end)
    }
}

/// The continuity at each joint of the chain of `fitted` (joint `k` is
/// segment `k`'s start; an open chain has one more at its end, C⁰): the
/// sequential chain's joins, the first joint the closing one, smooth when
/// the sequential chain closed smoothly (the last segment joined the
/// first). Fails for a quadratic (degree `m` 2) with a C¹ joint.
fn joint_continuities(
    fitted: &[Fitted<'_>],
    closed: bool,
    m: usize,
) -> Result<Vec<Continuity>, FitError> {
    let mut continuity: Vec<Continuity> = fitted.iter().map(|f| f.segment.join).collect();
    continuity[0] = match fitted.last().map(|f| f.segment.end) {
        Some(End::G1 { .. }) if closed => Continuity::G1,
        Some(End::C1 { .. }) if closed => Continuity::C1,
        _ => Continuity::C0,
    };
    if !closed {
        continuity.push(Continuity::C0);
    }
    if m == 2 && continuity.contains(&Continuity::C1) {
        return Err(FitError::JointQuadraticC1);
    }
    Ok(continuity)
}

/// The variables of joint `k` of `continuity`, added to `vars`, started at
/// the sequential chain's derivative there (segment `k`'s start, or the
/// last segment's end for the open end): none at a corner, the tangent
/// angle `θ` within ±2 turns (G¹), the derivative within ±`reach` (C¹).
fn joint_variables(
    fitted: &[Fitted<'_>],
    continuity: Continuity,
    k: usize,
    reach: f64,
    vars: &mut Vars,
) -> Joint {
    let n = fitted.len();
    let seg = &fitted[k % n].segment.segment;
    let d = if k < n {
        seg.deriv(0.0)
    } else {
        fitted[n - 1].segment.segment.deriv(1.0)
    };
    match continuity {
        Continuity::C0 => Joint::Corner,
        Continuity::G1 => {
            let theta = d.y.atan2(d.x);
            Joint::G1(vars.add(
                theta,
                theta - 2.0 * std::f64::consts::TAU,
                theta + 2.0 * std::f64::consts::TAU,
            ))
        }
        Continuity::C1 => {
            let i = vars.add(d.x, -reach, reach);
            vars.add(d.y, -reach, reach);
            Joint::C1(i)
        }
    }
}

/// The half-bandwidth of `chain` at `x0`: the widest spread of one link's
/// variables below `lead` (the border's are after it); `None` when a
/// link's controls cannot be built (a straight quadratic).
fn half_bandwidth(chain: &JointChain, x0: &[f64], lead: usize) -> Option<usize> {
    let mut width = 0;
    for k in 0..chain.links.len() {
        let (_, sens, used) = chain.controls(k, x0)?;
        let idx = sens[..used].iter().map(|s| s.var).filter(|&v| v < lead);
        let (a, b) = idx.fold((usize::MAX, 0), |(a, b), v| (a.min(v), b.max(v)));
        if a <= b {
            width = width.max(b - a);
        }
    }
    Some(width)
}

/// Solves the chain of a sequential fit's segments jointly with `lm` within
/// `budget` evaluations, and returns the refitted segments (same spans,
/// joins and order) with the evaluations used; `None` where the joint
/// variables cannot describe the sequential chain (see [`build`]).
pub(super) fn solve_joint(
    outline: &Outline<'_>,
    fitted: &[Fitted<'_>],
    options: &FitOptions,
    lm: &LevenbergMarquardt,
    budget: u64,
) -> Result<Option<(Vec<FittedSegment>, u64)>, FitError> {
    let Some((chain, x0)) = build(outline, fitted, options)? else {
        return Ok(None);
    };
    let outcome = lm.minimise(&chain, &x0, budget);
    let x = outcome.x;
    let mut out = Vec::with_capacity(fitted.len());
    for (k, f) in fitted.iter().enumerate() {
        let link = &chain.links[k];
        // LM only accepts steps of finite E, so every link is valid at x.
        let Some(c) = chain.controls(k, &x) else {
            return Ok(None);
        };
        let Ok(segment) = c.0.segment(options.function) else {
            return Ok(None);
        };
        let mut params = Vec::with_capacity(link.points.len() + 2);
        params.push(0.0);
        params.extend((0..link.points.len()).map(|i| chain.measured(&c.0, link, i).0));
        params.push(1.0);
        let points = outline.gather(f.span.0, f.span.1);
        let metrics = segment_metrics(&segment, &points, &params, f.segment.metrics.evaluations);
        let mut refit = f.segment.clone();
        refit.x = c.1[..c.2].iter().map(|s| x[s.var]).collect();
        refit.segment = segment;
        refit.params = params;
        refit.metrics = metrics;
        refit.inserted = 0;
        out.push(refit);
    }
    // The closing join's direction or derivative now comes from the new
    // first segment.
    if let (Some(first), Some(last)) = (out.first().map(|s| s.segment), out.last_mut()) {
        let d = first.deriv(0.0);
        last.end = match last.end {
            End::G1 { .. } => End::G1 { dir: d },
            End::C1 { .. } => End::C1 { derivative: d },
            End::Free => End::Free,
        };
    }
    Ok(Some((out, outcome.evaluations)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::{fit_piecewise, Closing, LmSolver};

    /// A wobbly closed contour (not any curve family's), 120 points.
    fn blob() -> Vec<Point> {
        (0..120)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 120.0;
                let r = 50.0 + 6.0 * (3.0 * a).sin() + 2.0 * (7.0 * a).cos();
                Point::new(r * a.cos() + 3.0, 0.6 * r * a.sin() - 2.0)
            })
            .collect()
    }

    /// `JᵀJ` and `Jᵀr` by central differences of the residuals.
    fn numeric(chain: &JointChain, x: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let (n, m) = (chain.dim(), chain.residual_count());
        let mut r = vec![0.0; m];
        chain.residuals(x, &mut r);
        let mut jac = vec![0.0; m * n];
        let (mut up, mut down) = (vec![0.0; m], vec![0.0; m]);
        for j in 0..n {
            let h = 1e-6 * x[j].abs().max(1.0);
            let mut xp = x.to_vec();
            xp[j] += h;
            chain.residuals(&xp, &mut up);
            xp[j] -= 2.0 * h;
            chain.residuals(&xp, &mut down);
            for k in 0..m {
                jac[k * n + j] = (up[k] - down[k]) / (2.0 * h);
            }
        }
        let mut a = vec![0.0; n * n];
        let mut g = vec![0.0; n];
        for k in 0..m {
            for i in 0..n {
                g[i] += jac[k * n + i] * r[k];
                for j in 0..n {
                    a[i * n + j] += jac[k * n + i] * jac[k * n + j];
                }
            }
        }
        (a, g)
    }

    #[test]
    fn the_banded_normal_equations_are_the_jacobians() {
        let pts = blob();
        for (function, continuity, closing) in [
            (FunctionType::RationalCubic, Continuity::G1, Closing::Smooth),
            (FunctionType::Cubic, Continuity::C1, Closing::Smooth),
            (FunctionType::RationalCubic, Continuity::C1, Closing::C0),
            (
                FunctionType::RationalQuadratic,
                Continuity::G1,
                Closing::Smooth,
            ),
            (FunctionType::Quadratic, Continuity::G1, Closing::Smooth),
        ] {
            let mut options = FitOptions::new(function, continuity);
            options.closing = closing;
            options.error = ErrorMeasure::Fixed;
            let fit = fit_piecewise(
                &pts,
                true,
                &[0, 30, 55, 90],
                &options,
                &mut LmSolver::default(),
            )
            .unwrap();
            let outline = Outline {
                points: &pts,
                closed: true,
            };
            let fitted: Vec<Fitted<'_>> = fit
                .segments
                .iter()
                .map(|s| Fitted {
                    segment: s,
                    span: (
                        s.first,
                        if s.last <= s.first {
                            s.last + 120
                        } else {
                            s.last
                        },
                    ),
                })
                .collect();
            let (chain, x0) = build(&outline, &fitted, &options).unwrap().unwrap();
            // The start is the sequential chain.
            let e: f64 = fit.segments.iter().map(|s| s.metrics.sse).sum();
            assert!(
                (chain.objective(&x0) - e).abs() <= 1e-9 * e,
                "{function} {continuity:?}"
            );
            let n = chain.dim();
            let mut a = BandedArrow::new(n, chain.width, chain.border);
            let mut g = vec![0.0; n];
            let mut r = vec![0.0; chain.residual_count()];
            chain.residuals(&x0, &mut r);
            chain.normal_equations(&x0, &r, &mut a, &mut g);
            let (na, ng) = numeric(&chain, &x0);
            let scale = na.iter().fold(0.0f64, |s, v| s.max(v.abs()));
            for i in 0..n {
                assert!(
                    (g[i] - ng[i]).abs() <= 1e-5 * (1.0 + ng[i].abs()) * scale.sqrt(),
                    "{function} {continuity:?} g[{i}] {} vs {}",
                    g[i],
                    ng[i]
                );
                for j in 0..n {
                    assert!(
                        (a.get(i, j) - na[i * n + j]).abs() <= 1e-6 * scale,
                        "{function} {continuity:?} A[{i}][{j}] {} vs {}",
                        a.get(i, j),
                        na[i * n + j]
                    );
                }
            }
        }
    }
}
