//! The contours around one defect in polar form about a centre on the
//! mid-sagittal line, and what the wall design reads from them: the ends A′
//! and B′ on the outer envelope, the mirrored template, the local outer
//! table next to each end (its direction for the G¹ joins and the kink
//! metric) and the bone thickness along the table's normal.
//!
//! The reflection across the mid-sagittal line ([`crate::ct::MidLine`], tilted in
//! general) maps the ray at angle `θ` from its centre to the ray at
//! `2α − θ` (`α` the line's direction angle), so the mirrored envelope is
//! `R(θ) = reflect(E(2α − θ))`.

use super::wall_input::{WallInput, WallOptions};
use super::SliceError;
use crate::ct::{CtError, Polyline};
use crate::fit::{
    FitError, FunctionType, LmSolver, SearchSpaceOptions, SegmentProblem, SegmentSolver, Start,
};
use crate::geometry::{Curve, Nearest, Parameterisation, Point};
use crate::linalg::cholesky_solve;

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

/// The spacing of the candidate seats (mm of outer table).
pub const SEAT_STEP_MM: f64 = 0.25;

/// The polar angle of `p` about `o`.
pub(crate) fn angle(p: Point, o: Point) -> f64 {
    (p.y - o.y).atan2(p.x - o.x)
}

pub(crate) use super::ray_template::wrap;

/// The wall's ends on the envelope and their mirror images.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WallEnds {
    /// A′ = E(θ_A).
    pub a: Point,
    /// B′ = E(θ_B).
    pub b: Point,
    /// C: A′ reflected (or the explicit template's first point).
    pub c: Point,
    /// D: B′ reflected (or the explicit template's last point).
    pub d: Point,
}

/// Which end of the defect.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Side {
    /// A′, where the wall starts.
    A,
    /// B′, where the wall ends.
    B,
}

/// The defect in polar form about `input.centre`: the outer envelope
/// `E(θ)` and the gap's rays from A′ at `th_a` over the signed angular width
/// `span`, each end moved 0.5 mm (arc) into the intact bone so that the ray
/// meets the contour that the cut at A (B) ends.
pub(crate) struct Gap<'a> {
    pub input: WallInput<'a>,
    /// The polar angle of A′ (radians).
    pub th_a: f64,
    /// The signed angular width from A′ to B′ (radians).
    pub span: f64,
}

impl<'a> Gap<'a> {
    /// The gap between `input.a` and `input.b`, each end's ray moved into
    /// the bone: 0.5 mm of arc, then in 0.25 mm steps (up to 4 mm) until
    /// the envelope point lies within 2.5 mm of the end (a ray grazing a
    /// bone tip would otherwise meet the bone behind it).
    pub fn new(input: WallInput<'a>) -> Self {
        let o = input.centre;
        let th_a0 = angle(input.a, o);
        let span0 = wrap(angle(input.b, o) - th_a0);
        let mut gap = Gap {
            input,
            th_a: th_a0,
            span: span0,
        };
        let nudge = |gap: &Gap<'_>, p: Point, th: f64, dir: f64| {
            let per_mm = 1.0 / p.distance(o).max(1e-9);
            (0..=14)
                .map(|k| th + dir * (0.5 + 0.25 * k as f64) * per_mm)
                .find(|&t| gap.env(t).is_some_and(|q| q.distance(p) <= 2.5))
                .unwrap_or(th + dir * 0.5 * per_mm)
        };
        let sign = span0.signum();
        let th_a = nudge(&gap, input.a, th_a0, -sign);
        let th_b = nudge(&gap, input.b, th_a0 + span0, sign);
        gap.th_a = th_a;
        gap.span = th_b - th_a;
        gap
    }

    /// The envelope point `E(θ)`, or `None` where the ray misses.
    pub fn env(&self, theta: f64) -> Option<Point> {
        let o = self.input.centre;
        envelope_radius(self.input.outer, o, theta)
            .map(|r| o + Point::new(theta.cos(), theta.sin()) * r)
    }

    /// The mirrored envelope `R(θ) = reflect(E(2α − θ))`.
    /// With a 3D template ([`WallInput::surface`]), its point on the ray.
    pub fn mirrored(&self, theta: f64) -> Option<Point> {
        if let Some(s) = self.input.surface {
            return s.at(theta);
        }
        let line = self.input.midline;
        self.env(2.0 * line.angle() - theta)
            .map(|p| line.reflect(p))
    }

    /// A′, B′ on the envelope and C, D: the mirror images of A′, B′, each
    /// within `tol` of the envelope at the mirrored angle, or, with an
    /// explicit template, its first and last points, each within `tol` of
    /// A′ and B′.
    pub fn ends(&self, tol: f64) -> Result<WallEnds, CtError> {
        let on = |what: &'static str, p: Option<Point>, target: Point| -> Result<Point, CtError> {
            let d = p.map_or(f64::INFINITY, |q| q.distance(target));
            match p {
                Some(q) if d <= tol => Ok(q),
                _ => Err(CtError::NotOnContour {
                    what,
                    distance_mm: d,
                    tolerance_mm: tol,
                }),
            }
        };
        let (th_a, th_b) = (self.th_a, self.th_a + self.span);
        let a = on("A", self.env(th_a), self.env(th_a).unwrap_or(self.input.a))?;
        let b = on("B", self.env(th_b), self.env(th_b).unwrap_or(self.input.b))?;
        if let Some(t) = self.input.template {
            let (first, last) = template_ends(t, a);
            on("the template's start (A′)", Some(first), a)?;
            on("the template's end (B′)", Some(last), b)?;
            return Ok(WallEnds {
                a,
                b,
                c: first,
                d: last,
            });
        }
        if let Some(s) = self.input.surface {
            let (c, d) = (s.at(th_a), s.at(th_b));
            on("C (the 3D template at A′)", c, a)?;
            on("D (the 3D template at B′)", d, b)?;
            return Ok(WallEnds {
                a,
                b,
                c: c.unwrap_or(a),
                d: d.unwrap_or(b),
            });
        }
        let line = self.input.midline;
        let (c, d) = (line.reflect(a), line.reflect(b));
        on(
            "C (A mirrored)",
            self.mirrored(th_a).map(|p| line.reflect(p)),
            c,
        )?;
        on(
            "D (B mirrored)",
            self.mirrored(th_b).map(|p| line.reflect(p)),
            d,
        )?;
        Ok(WallEnds { a, b, c, d })
    }

    /// The fit data: the mirrored envelope `R(θ)` on `template_points` rays
    /// from θ_A to θ_B, or the explicit template resampled by arc length to
    /// as many points (its ends as they are: [`blend_onto_bone`] takes
    /// them to A′ and B′).
    pub fn template(
        &self,
        ends: &WallEnds,
        options: &WallOptions,
    ) -> Result<Vec<Point>, SliceError> {
        let needed = options.function.min_points();
        let n_t = options.template_points.max(needed + 2);
        let data: Vec<Point> = match self.input.template {
            Some(t) if t.points.len() >= 2 => {
                let (first, _) = template_ends(t, ends.a);
                let t = if first == t.points[0] {
                    t.clone()
                } else {
                    t.reversed()
                };
                t.resample(n_t).points
            }
            Some(t) => t.points.clone(),
            None => (0..n_t)
                .filter_map(|k| self.mirrored(self.th_a + self.span * k as f64 / (n_t - 1) as f64))
                .collect(),
        };
        if data.len() < needed {
            return Err(SliceError::TemplateNotCovered {
                points: data.len(),
                needed,
            });
        }
        Ok(data)
    }

    /// The same gap with its ends moved to the points `a` and `b` (the
    /// seats). Both angles are unwrapped next to the gap's own, so a seat
    /// moved across the ray at ±180° keeps the gap's side of the head
    /// (taking `angle(a)` as it is once made the template run the long
    /// way round the head there: issue 48).
    pub fn moved(&self, a: Point, b: Point) -> Gap<'a> {
        let o = self.input.centre;
        let t = angle(a, o);
        // Unwrapped only where the seat crossed the ray at ±180°, so every
        // other gap keeps its angle to the last bit.
        let th_a = if (t - self.th_a).abs() > std::f64::consts::PI {
            self.th_a + wrap(t - self.th_a)
        } else {
            t
        };
        let th_b = self.th_a + self.span + wrap(angle(b, o) - (self.th_a + self.span));
        Gap {
            input: self.input,
            th_a,
            span: th_b - th_a,
        }
    }

    /// The bend of the outer table at the candidate seats `s = 0, 0.25, …,
    /// max_mm` behind an end: the angle (degrees) between the 3 mm secant
    /// after `s` and the next 3 mm secant. Bone ends are bevelled or rounded
    /// over a few millimetres, and a wall joined tangentially to that bevel
    /// would meet the table proper at a kink.
    pub fn bends(walk: &TableWalk, max_mm: f64) -> Vec<f64> {
        let steps = (max_mm / SEAT_STEP_MM).floor().max(0.0) as usize;
        (0..=steps)
            .map(|k| {
                let s = k as f64 * SEAT_STEP_MM;
                let d1 = walk.at(s + 3.0) - walk.at(s);
                let d2 = walk.at(s + 6.0) - walk.at(s + 3.0);
                d1.cross(d2).atan2(d1.dot(d2)).abs().to_degrees()
            })
            .collect()
    }

    /// The polar angle of an end.
    fn theta(&self, side: Side) -> f64 {
        match side {
            Side::A => self.th_a,
            Side::B => self.th_a + self.span,
        }
    }

    /// The outer table next to an end: the envelope walked away from the
    /// gap over `length_mm` of arc (rays every ≈ 0.2 mm), starting at the
    /// end's ray. `None` when a ray misses the contour before.
    pub fn table(&self, side: Side, length_mm: f64) -> Option<TableWalk> {
        let o = self.input.centre;
        let dir = match side {
            Side::A => -self.span.signum(),
            Side::B => self.span.signum(),
        };
        let mut theta = self.theta(side);
        let mut pts = vec![self.env(theta)?];
        let mut cum = vec![0.0];
        while cum[cum.len() - 1] < length_mm {
            let last = pts[pts.len() - 1];
            theta += dir * 0.2 / last.distance(o).max(1.0);
            let p = self.env(theta)?;
            cum.push(cum[cum.len() - 1] + p.distance(last));
            pts.push(p);
        }
        Some(TableWalk { pts, cum })
    }

    /// The unit direction of travel (A → B) of the outer table at an end:
    /// the derivative at the end of a least-squares quadratic in arc length
    /// through 9 points of the table over `window_mm` next to it.
    pub fn local_tangent(&self, side: Side, walk: &TableWalk, window_mm: f64) -> Option<Point> {
        // σ: arc length in the direction of travel, 0 at the end.
        let sign = if side == Side::A { -1.0 } else { 1.0 };
        let samples: Vec<(f64, Point)> = (0..=8)
            .map(|k| {
                let s = window_mm * k as f64 / 8.0;
                (sign * s, walk.at(s))
            })
            .collect();
        quadratic_slope(&samples)?.normalize()
    }

    /// The bone thickness next to an end: the median of the first bone
    /// runs along the table's inward normal (from its secant over ±1 mm)
    /// at the points ½, ¾, 1, 1¼ and 1½ × `setback_mm` back from the end
    /// (runs of zero, where a ray misses the bone, are left out), capped at
    /// `max_mm`; 0 when every ray misses.
    pub fn thickness(&self, walk: &TableWalk, setback_mm: f64, max_mm: f64) -> f64 {
        let mut runs: Vec<f64> = [0.5, 0.75, 1.0, 1.25, 1.5]
            .iter()
            .map(|f| {
                let s = f * setback_mm;
                let p = walk.at(s);
                let t = walk.at(s + 1.0) - walk.at((s - 1.0).max(0.0));
                let Some(n) = t.perp().normalize() else {
                    return 0.0;
                };
                let inward = if n.dot(self.input.centre - p) >= 0.0 {
                    n
                } else {
                    -n
                };
                thickness_along(p, inward, self.input.is_bone)
            })
            .filter(|&t| t > 0.0)
            .collect();
        if runs.is_empty() {
            return 0.0;
        }
        runs.sort_by(f64::total_cmp);
        let n = runs.len();
        let m = if n % 2 == 1 {
            runs[n / 2]
        } else {
            0.5 * (runs[n / 2 - 1] + runs[n / 2])
        };
        m.min(max_mm)
    }

    /// The bone thickness of the other side of the head across the gap
    /// (the mirror technique applied to the inner table): on `n` rays from
    /// θ_A to θ_B, the mirrored ray `2α − θ` meets the intact outer table at
    /// `Q = E(2α − θ)`, and the thickness is the first bone run along the
    /// table's inward normal there (its secant over ±1 mm), capped at
    /// `max_mm`. Rays that miss the table or the bone are filled from
    /// their neighbours, and the profile is smoothed by a running median
    /// of five. `None` when fewer than half the rays measure.
    pub fn mirrored_thickness(&self, n: usize, max_mm: f64) -> Option<MirroredThickness> {
        let (o, line) = (self.input.centre, self.input.midline);
        let n = n.max(2);
        let raw: Vec<Option<f64>> = (0..n)
            .map(|k| {
                let th = 2.0 * line.angle() - (self.th_a + self.span * k as f64 / (n - 1) as f64);
                let q = self.env(th)?;
                let per_mm = 1.0 / q.distance(o).max(1e-9);
                let t = self.env(th + per_mm)? - self.env(th - per_mm)?;
                let nrm = t.perp().normalize()?;
                let inward = if nrm.dot(o - q) >= 0.0 { nrm } else { -nrm };
                let run = thickness_along(q, inward, self.input.is_bone);
                (run > 0.0).then(|| run.min(max_mm))
            })
            .collect();
        let known: Vec<(usize, f64)> = raw
            .iter()
            .enumerate()
            .filter_map(|(k, v)| v.map(|v| (k, v)))
            .collect();
        if 2 * known.len() < n {
            return None;
        }
        // Each missing ray takes the value of the nearest measured one.
        let filled: Vec<f64> = (0..n)
            .map(|k| {
                known
                    .iter()
                    .min_by_key(|(j, _)| j.abs_diff(k))
                    .map_or(0.0, |&(_, v)| v)
            })
            .collect();
        let values = (0..n)
            .map(|k| {
                let mut w: Vec<f64> = filled[k.saturating_sub(2)..(k + 3).min(n)].to_vec();
                w.sort_by(f64::total_cmp);
                w[w.len() / 2]
            })
            .collect();
        Some(MirroredThickness {
            th_a: self.th_a,
            span: self.span,
            values,
        })
    }

    /// The bone's iso-contour next to an end, as the bone sees it: the
    /// points `lengths_mm` of arc length from `p` along the threshold
    /// iso-contour of the slice (the marching-squares loops of
    /// `input.outer`, [`crate::ct::bone_loops`]), walked from the contour
    /// point nearest `p` in the direction that leaves the gap (the one
    /// whose end point lies farther from the gap in polar angle). Unlike
    /// the envelope walk ([`Gap::table`]), it follows a rounded bone tip
    /// round its turn. `None` without contour points.
    pub fn iso_points<const N: usize>(
        &self,
        side: Side,
        p: Point,
        lengths_mm: [f64; N],
    ) -> Option<[Point; N]> {
        let (poly, n) = self
            .input
            .outer
            .iter()
            .filter_map(|poly| poly.nearest(p).map(|n| (*poly, n)))
            .min_by(|x, y| x.1.distance.total_cmp(&y.1.distance))?;
        let o = self.input.centre;
        let away = match side {
            Side::A => -self.span.signum(),
            Side::B => self.span.signum(),
        };
        let th = angle(n.point, o);
        Some(lengths_mm.map(|l| {
            let (f, b) = (
                walk_along(poly, &n, l, true),
                walk_along(poly, &n, l, false),
            );
            let gain = |q: Point| away * wrap(angle(q, o) - th);
            if gain(f) >= gain(b) {
                f
            } else {
                b
            }
        }))
    }

    /// The template's offset from the bone at the point `p` (mm): on the
    /// ray through `p`, the mirrored envelope's distance from `p`, signed
    /// positive when it lies farther from the centre (as
    /// [`Blend::offset_mm`]); with an explicit template, its distance from
    /// `p`, signed the same way; 0 where the mirrored ray misses.
    pub fn template_offset(&self, p: Point) -> f64 {
        let o = self.input.centre;
        let q = match self.input.template {
            Some(t) => t.nearest(p).map(|n| n.point),
            None => self.mirrored(angle(p, o)),
        };
        q.map_or(0.0, |q| radial_offset(o, p, q))
    }

    /// Where the template blended onto the bone ([`blend_onto_bone`]) is
    /// expected `s` mm into the gap from a seat `p` whose join direction
    /// into the gap is `into`: the point `ℓ = p + s·into` on the bone's
    /// tangent line, moved along its ray by `S(s/L)·δ(ℓ)` (`δ(ℓ)` the
    /// template's offset there, [`Gap::template_offset`]; `S` the quintic
    /// smoothstep; `L` the blend length of the offset at the seat,
    /// [`blend_length`]). The wall fitted to the template turns as this
    /// point does over its last millimetres, which the join tangent alone
    /// does not show; the arc length along the template is taken as `s`
    /// and the other end's blend is ignored.
    pub fn blended_near_seat(
        &self,
        p: Point,
        into: Point,
        s: f64,
        slope_deg: f64,
        min_mm: f64,
    ) -> Point {
        let o = self.input.centre;
        let l = p + into * s;
        let length = blend_length(self.template_offset(p), slope_deg, min_mm);
        match (l - o).normalize() {
            Some(r) => l + r * (smootherstep(s / length) * self.template_offset(l)),
            None => l,
        }
    }

    /// The derivatives of the intact envelope at A′ and B′ (direction of
    /// travel), from neighbouring cubics over the same angular width as the
    /// gap (≤ 30°): the magnitudes of C¹ joins.
    pub fn neighbour_derivatives(&self) -> Result<(Point, Point), SliceError> {
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
            return Err(SliceError::TooLittleIntactContour {
                before: before.len(),
                after: after.len(),
            });
        }
        let d_a = neighbour_derivative(before, true).map_err(fit_err)?;
        let d_b = neighbour_derivative(after, false).map_err(fit_err)?;
        Ok((d_a, d_b))
    }
}

/// How the template was blended onto the bone at one end
/// ([`blend_onto_bone`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Blend {
    /// The template's offset from the seat before blending (mm): the
    /// distance from the seat to the template's end, positive when the
    /// template lies farther from the polar centre than the bone (the
    /// mirror image is fuller than the bone it replaces), negative when it
    /// lies inside.
    pub offset_mm: f64,
    /// The template arc length (mm) over which it was blended onto the
    /// bone's tangent line.
    pub length_mm: f64,
}

/// The other side's bone thickness across a gap, on evenly spaced polar
/// angles from θ_A to θ_B (measured by `Gap::mirrored_thickness`).
#[derive(Clone, Debug, PartialEq)]
pub struct MirroredThickness {
    /// The polar angle of A′ (radians).
    pub th_a: f64,
    /// The signed angular width from A′ to B′ (radians).
    pub span: f64,
    /// The thickness (mm) on the rays `θ_A + span·k/(n − 1)`.
    pub values: Vec<f64>,
}

impl MirroredThickness {
    /// The profile at polar angle `theta` (linear between rays, clamped to
    /// the ends) less its chord between the end values: how much thicker
    /// (or thinner) the other side is there than the straight blend of its
    /// ends. 0 at A′ and B′, so an inner wall `Dis = (1 − u)·t_A + u·t_B +
    /// excess` keeps the thickness measured at the seats.
    pub fn excess(&self, theta: f64) -> f64 {
        let n = self.values.len();
        if n < 2 || self.span == 0.0 {
            return 0.0;
        }
        let f = (wrap(theta - self.th_a) / self.span).clamp(0.0, 1.0);
        let x = f * (n - 1) as f64;
        let k = (x.floor() as usize).min(n - 2);
        let v = self.values[k] + (x - k as f64) * (self.values[k + 1] - self.values[k]);
        v - ((1.0 - f) * self.values[0] + f * self.values[n - 1])
    }
}

/// The quintic smoothstep `6x⁵ − 15x⁴ + 10x³` on `[0, 1]` (clamped): 0 and
/// 1 at the ends with vanishing first and second derivatives (Perlin,
/// "Improving noise", SIGGRAPH 2002), its largest slope 15/8.
pub fn smootherstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * x * (x * (6.0 * x - 15.0) + 10.0)
}

/// The point where the ray from `o` through `p` meets the line through
/// `q` with direction `t` (`None` when they are parallel or meet behind
/// `o`).
fn ray_line(o: Point, p: Point, q: Point, t: Point) -> Option<Point> {
    let d = p - o;
    let den = d.cross(t);
    if den.abs() < 1e-12 {
        return None;
    }
    let r = (q - o).cross(t) / den;
    (r > 0.0).then(|| o + d * r)
}

/// Blends a template `raw` (from near A′ to near B′) onto the bone at its
/// ends (**RECONSTRUCTION**, beyond the thesis): where the mirror image and
/// the bone disagree at a seat, the bone wins there, since the implant must
/// meet it flush and tangentially, and the template wins farther in.
///
/// In polar form about `o`: each template point `p` moves along its ray
/// towards the bone's tangent line at each end (the line through A′ with
/// the join direction `t_A`, and through B′ with `t_B`),
/// `p̃ = p + w_A(s)·(ℓ_A(p) − p) + w_B(s)·(ℓ_B(p) − p)`, `ℓ(p)` the ray's
/// crossing with the line, `w(s) = 1 − S(s/L)` of the arc length `s` from
/// the end and `S` the quintic smoothstep ([`smootherstep`]). The blended
/// template therefore starts at A′ along `t_A` and ends at B′ along `t_B`
/// with no jump in curvature, stays one radius per ray like the mirror
/// image, and equals the mirror image beyond `L`. The blend length is
/// `L = clamp(15/8·|δ| / tan(slope_deg), min_mm, S/2)` (`δ` the template
/// end's distance from the seat, `S` the template's arc length), so that
/// the correction rises by at most `slope_deg` where the defect is wide
/// enough. Returns the blended points (the ends exactly A′ and B′) and the
/// blend at each end (the offset signed positive when the template lies
/// farther than the seat from `o`).
pub fn blend_onto_bone(
    raw: &[Point],
    (a, b): (Point, Point),
    (t_a, t_b): (Point, Point),
    o: Point,
    slope_deg: f64,
    min_mm: f64,
) -> (Vec<Point>, (Blend, Blend)) {
    let n = raw.len();
    if n < 2 {
        return (raw.to_vec(), (Blend::default(), Blend::default()));
    }
    let mut cum = vec![0.0; n];
    for k in 1..n {
        cum[k] = cum[k - 1] + raw[k].distance(raw[k - 1]);
    }
    let total = cum[n - 1];
    let (d_a, d_b) = (radial_offset(o, a, raw[0]), radial_offset(o, b, raw[n - 1]));
    let length = |delta: f64| blend_length(delta, slope_deg, min_mm).min(0.5 * total);
    let (l_a, l_b) = (length(d_a), length(d_b));
    let mut out: Vec<Point> = raw
        .iter()
        .zip(&cum)
        .map(|(&p, &s)| {
            let mut q = p;
            for (end, t, l, s) in [(a, t_a, l_a, s), (b, t_b, l_b, total - s)] {
                let w = 1.0 - smootherstep(s / l.max(f64::MIN_POSITIVE));
                if let Some(on) = (w > 0.0).then(|| ray_line(o, p, end, t)).flatten() {
                    q += (on - p) * w;
                }
            }
            q
        })
        .collect();
    out[0] = a;
    out[n - 1] = b;
    let blend = |offset_mm, length_mm| Blend {
        offset_mm,
        length_mm,
    };
    (out, (blend(d_a, l_a), blend(d_b, l_b)))
}

/// The blend length of [`blend_onto_bone`] for a template lying `delta` mm
/// off the seat, before the cap at half the template:
/// `max(15/8·|δ| / tan(slope_deg), min_mm)` (15/8 the largest slope of
/// [`smootherstep`]).
pub fn blend_length(delta: f64, slope_deg: f64, min_mm: f64) -> f64 {
    let slope = slope_deg.to_radians().tan().max(1e-6);
    (1.875 * delta.abs() / slope).max(min_mm)
}

/// The distance from `seat` to `p`, signed positive when `p` lies farther
/// from `o` than the seat (the template fuller than the bone).
pub fn radial_offset(o: Point, seat: Point, p: Point) -> f64 {
    let d = p.distance(seat);
    if p.distance(o) >= seat.distance(o) {
        d
    } else {
        -d
    }
}

/// The explicit template's ends ordered so that the first is the one
/// nearer `a`.
fn template_ends(t: &Polyline, a: Point) -> (Point, Point) {
    let (p, q) = (t.points[0], t.points[t.points.len() - 1]);
    if p.distance(a) <= q.distance(a) {
        (p, q)
    } else {
        (q, p)
    }
}

/// The outer table walked from an end: envelope points by arc length.
pub(crate) struct TableWalk {
    /// The points, from the end outwards.
    pts: Vec<Point>,
    /// Their arc lengths from the end.
    cum: Vec<f64>,
}

impl TableWalk {
    /// The walk from the point `s` mm along it onwards.
    pub fn from(&self, s: f64) -> TableWalk {
        let mut pts = vec![self.at(s)];
        let mut cum = vec![0.0];
        for (p, c) in self.pts.iter().zip(&self.cum).filter(|(_, &c)| c > s) {
            pts.push(*p);
            cum.push(c - s);
        }
        TableWalk { pts, cum }
    }

    /// The point `s` mm (arc length) from the end (clamped to the walk).
    pub fn at(&self, s: f64) -> Point {
        let i = self.cum.partition_point(|&c| c < s);
        if i == 0 {
            return self.pts[0];
        }
        if i >= self.pts.len() {
            return self.pts[self.pts.len() - 1];
        }
        let (c0, c1) = (self.cum[i - 1], self.cum[i]);
        let t = if c1 > c0 { (s - c0) / (c1 - c0) } else { 0.0 };
        self.pts[i - 1].lerp(self.pts[i], t)
    }
}

/// The point `length` mm of arc length from the position `from` on `poly`,
/// walking with the vertex order (`forward`) or against it; a closed
/// polyline wraps round, an open one stops at its ends.
pub(crate) fn walk_along(poly: &Polyline, from: &Nearest, length: f64, forward: bool) -> Point {
    let pts = &poly.points;
    let n = pts.len();
    if n < 2 {
        return from.point;
    }
    let segs = poly.segment_count();
    let (mut seg, mut here) = (from.segment, from.point);
    let mut left = length;
    for _ in 0..=n {
        // The vertex ahead of `here` on the current segment.
        let (a, b) = poly.segment(seg);
        let next = if forward { b } else { a };
        let l = here.distance(next);
        if left <= l {
            return if l > 0.0 {
                here.lerp(next, left / l)
            } else {
                here
            };
        }
        left -= l;
        here = next;
        seg = match (forward, poly.closed) {
            (true, true) => (seg + 1) % segs,
            (false, true) => (seg + segs - 1) % segs,
            (true, false) if seg + 1 < segs => seg + 1,
            (false, false) if seg > 0 => seg - 1,
            _ => return here,
        };
    }
    here
}

/// The least-squares quadratic `v(σ) ≈ c₀ + c₁σ + c₂σ²` through
/// `(σ_k, v_k)` (normal equations, Cholesky): `[c₀, c₁, c₂]`, or `None` when
/// the samples do not determine it.
pub(crate) fn least_squares_quadratic(
    samples: impl Iterator<Item = (f64, f64)>,
) -> Option<[f64; 3]> {
    let mut m = [0.0; 9];
    let mut rhs = [0.0; 3];
    for (s, v) in samples {
        let f = [1.0, s, s * s];
        for i in 0..3 {
            for j in 0..3 {
                m[3 * i + j] += f[i] * f[j];
            }
            rhs[i] += f[i] * v;
        }
    }
    cholesky_solve(&mut m, &mut rhs, 3).then_some(rhs)
}

/// The slope `b` of the least-squares quadratic `p(σ) = a + bσ + cσ²`
/// through `(σ_k, p_k)`: the curve's derivative at σ = 0.
fn quadratic_slope(samples: &[(f64, Point)]) -> Option<Point> {
    let x = least_squares_quadratic(samples.iter().map(|&(s, p)| (s, p.x)))?;
    let y = least_squares_quadratic(samples.iter().map(|&(s, p)| (s, p.y)))?;
    Some(Point::new(x[1], y[1]))
}

/// The bone thickness along the ray from the outer point `p` in the unit
/// direction `dir`: the length of the first run of bone, stepping 0.1 mm,
/// ending at the first 0.5 mm without bone (the first 2 mm may be free of
/// bone: the contour lies half a pixel outside the bone's centres).
pub(crate) fn thickness_along(p: Point, dir: Point, is_bone: &dyn Fn(Point) -> bool) -> f64 {
    let (step, max_gap, limit) = (0.1, 0.5, 60.0);
    let (mut last_bone, mut gap) = (0.0, 0.0);
    let mut s = 0.0;
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

/// A fit error of the outer wall as the slice's error.
pub(crate) fn fit_err(source: FitError) -> SliceError {
    SliceError::OuterWallFit { source }
}

/// The angle in degrees between the directions `u` and `v` (NaN when one
/// is zero).
pub fn angle_deg(u: Point, v: Point) -> f64 {
    match (u.normalize(), v.normalize()) {
        (Some(u), Some(v)) => u.cross(v).atan2(u.dot(v)).abs().to_degrees(),
        _ => f64::NAN,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A contour with a 45° corner 1 mm from the seat at the origin: 1 mm
    /// along +x, then along (1, 1)/√2.
    fn corner() -> Polyline {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        Polyline::open(vec![
            Point::new(-5.0, 0.0),
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(1.0 + 10.0 * s, 10.0 * s),
        ])
    }

    #[test]
    fn the_iso_contour_secant_sees_a_corner_past_the_seat() {
        let c = corner();
        let n = c.nearest(Point::ZERO).unwrap();
        // A straight wall arriving along +x: its kink against the contour's
        // secant over L mm from the seat.
        let kink = |l: f64| angle_deg(Point::new(1.0, 0.0), walk_along(&c, &n, l, true));
        // 1.5 mm: 1 mm along x, 0.5 mm up the 45° leg.
        let expected_15 = (0.5 * 0.5f64.sqrt()).atan2(1.0 + 0.5 * 0.5f64.sqrt());
        assert!((kink(1.5) - expected_15.to_degrees()).abs() < 1e-9);
        let expected_3 = (2.0 * 0.5f64.sqrt()).atan2(1.0 + 2.0 * 0.5f64.sqrt());
        assert!((kink(3.0) - expected_3.to_degrees()).abs() < 1e-9);
        assert!(kink(3.0) > 25.0 && kink(0.5) < 1e-9);
        // Backwards, and clamped at the open end.
        assert_eq!(walk_along(&c, &n, 2.0, false), Point::new(-2.0, 0.0));
        assert_eq!(walk_along(&c, &n, 50.0, false), Point::new(-5.0, 0.0));
        // A closed loop wraps round.
        let sq = Polyline::closed(vec![
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(0.0, 1.0),
        ]);
        let n = sq.nearest(Point::new(0.5, 0.0)).unwrap();
        let p = walk_along(&sq, &n, 3.0, true);
        assert!(p.distance(Point::new(0.0, 0.5)) < 1e-12, "{p:?}");
        let p = walk_along(&sq, &n, 1.0, false);
        assert!(p.distance(Point::new(0.0, 0.5)) < 1e-12, "{p:?}");
    }

    #[test]
    fn the_blend_meets_the_seats_tangentially_and_keeps_the_template_farther_in() {
        // Centre at the origin; a template arc of radius 104 over 40°,
        // seats on radius 100 with tangents along the circle of radius 100:
        // the template lies 4 mm outside the bone at both ends.
        let o = Point::ZERO;
        let arc = |r: f64, t: f64| Point::new(r * t.cos(), r * t.sin());
        let (t0, t1) = (70f64.to_radians(), 110f64.to_radians());
        let raw: Vec<Point> = (0..=80)
            .map(|k| arc(104.0, t0 + (t1 - t0) * k as f64 / 80.0))
            .collect();
        let (a, b) = (arc(100.0, t0), arc(100.0, t1));
        let ta = Point::new(-t0.sin(), t0.cos());
        let tb = Point::new(-t1.sin(), t1.cos());
        let (out, (ba, bb)) = blend_onto_bone(&raw, (a, b), (ta, tb), o, 15.0, 8.0);
        assert_eq!((out[0], out[80]), (a, b));
        assert!((ba.offset_mm - 4.0).abs() < 1e-9 && (bb.offset_mm - 4.0).abs() < 1e-9);
        // L = 15/8 · 4 / tan 15° ≈ 28 mm, within half the arc (36 mm).
        let l = 1.875 * 4.0 / 15f64.to_radians().tan();
        assert!((ba.length_mm - l).abs() < 1e-9 && (bb.length_mm - l).abs() < 1e-9);
        // Tangent at the seats: the first leg along t_A within 1°.
        assert!(angle_deg(out[1] - out[0], ta) < 1.0);
        assert!(angle_deg(out[80] - out[79], tb) < 1.0);
        // The middle is the template itself (beyond L from both ends).
        assert_eq!(out[40], raw[40]);
        // One radius per ray, never below the bone nor above the template.
        for p in &out {
            let r = p.distance(o);
            assert!((99.9..=104.0 + 1e-9).contains(&r), "{r}");
        }
    }

    #[test]
    fn the_mirrored_excess_vanishes_at_the_ends_and_follows_the_profile() {
        // Thickness 4, 8, 6 mm on three rays over a gap of -0.5 rad from
        // theta_A = 3 (a gap walked clockwise, across the +-pi seam).
        let m = MirroredThickness {
            th_a: 3.0,
            span: -0.5,
            values: vec![4.0, 8.0, 6.0],
        };
        assert!(m.excess(3.0).abs() < 1e-12);
        assert!(m.excess(2.5).abs() < 1e-12);
        // Mid-gap: 8 against the chord's 5.
        assert!((m.excess(2.75) - 3.0).abs() < 1e-12);
        // A quarter in: 6 against 4.5.
        assert!((m.excess(2.875) - 1.5).abs() < 1e-12);
        // Outside the gap it is clamped to the ends.
        assert!(m.excess(3.2).abs() < 1e-12 && m.excess(2.0).abs() < 1e-12);
        let seam = MirroredThickness {
            th_a: 3.0,
            span: 0.5,
            values: vec![4.0, 8.0, 6.0],
        };
        // theta_A + span/2 = 3.25 is -3.033 after wrapping.
        assert!((seam.excess(3.25 - std::f64::consts::TAU) - 3.0).abs() < 1e-12);
    }
}
