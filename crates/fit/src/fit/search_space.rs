//! The search space: first guesses of the inner control points and the box
//! around them (thesis chapter 5, the "search-space technique").
//!
//! **This is a reconstruction.** The thesis names the symbols (`A₁′, A₂′`
//! first guesses of `C₁, C₂`; `α_size` the size of the search space;
//! `R_Q1, R_mid, R_Q3` the last point of the first quarter, the middle point
//! and the last point of the third quarter of the segment's data; `pt ∈ [0, 1]`
//! projecting `A₁′, A₂′`), but its formulas are lost. Our construction:
//!
//! * **Guesses, cubic.** With the ends fixed, the cubic passes through `R_Q1`
//!   at `s = 1/4` and `R_Q3` at `s = 3/4`. Since
//!   `64 P(1/4) = 27C₀ + 27C₁ + 9C₂ + C₃` and `64 P(3/4) = C₀ + 9C₁ + 27C₂ + 27C₃`,
//!   with `a = 64R_Q1 − 27C₀ − C₃` and `b = 64R_Q3 − C₀ − 27C₃` the 2×2 system
//!   `27A₁′ + 9A₂′ = a`, `9A₁′ + 27A₂′ = b` gives
//!   `A₁′ = (3a − b)/72`, `A₂′ = (3b − a)/72` ([`cubic_guess`]).
//!   [`GuessRule::ActualParams`] uses the data's own `s_Q1, s_Q3` instead
//!   ([`cubic_guess_at`]).
//! * **Guesses, quadratic.** The quadratic passes through `R_mid` at
//!   `s = 1/2`: `C₁ = 2R_mid − (C₀ + C₂)/2` ([`quadratic_guess`]).
//! * **Rational functions** use the same guesses (the polynomial curve is
//!   the rational one with unit weights).
//! * **Projection by `pt`.** Each guess moves to `(1 − pt)·A + pt·A*`, where
//!   for a cubic `A*` is the orthogonal projection of `A₁′` (`A₂′`) on the
//!   tangent line at the start (end), and for a quadratic it is the
//!   intersection of the two tangent lines (when they meet in front of both
//!   ends; otherwise `A` stays). A tangent is the chord from the end point to
//!   its `k`-th neighbour (`k =` [`SearchSpaceOptions::tangent_points`]), or
//!   for a joined segment the known start tangent of the join.
//! * **Box.** Each free control point coordinate lies in
//!   `A ± α_size·|C_m − C₀|` (if the ends coincide, `|C_m − C₀|` is replaced by
//!   the diagonal of the data's bounding box). A G¹ ratio lies in
//!   `[T_min, T_max]`, a weight in `[w_min, w_max]`.
//!
//! [`SearchSpace::BoundingBox`] is the naive alternative the technique is
//! compared with: each coordinate may lie anywhere in the data's bounding box
//! enlarged by `margin` times its larger side on every side.

use super::options::{GuessRule, SearchSpace, SearchSpaceOptions};
use super::FunctionType;
use crate::geometry::{bounding_box, Point};

/// The indices `(q1, mid, q3)` of `R_Q1, R_mid, R_Q3` among `len` points:
/// with `n = len − 1` intervals, the points nearest to `n/4`, `n/2`, `3n/4`
/// (exactly those when `4 | n`; ties round down).
pub fn quarter_indices(len: usize) -> (usize, usize, usize) {
    let n = len.saturating_sub(1);
    let near = |num: usize| (2 * num * n + 3) / 8; // round(num·n/4), ties down
    (near(1), near(2), near(3))
}

/// `A₁′ = (3a − b)/72`, `A₂′ = (3b − a)/72` with `a = 64R_Q1 − 27C₀ − C₃`,
/// `b = 64R_Q3 − C₀ − 27C₃`: the inner control points of the cubic with ends
/// `C₀, C₃` through `R_Q1` at `s = 1/4` and `R_Q3` at `s = 3/4`.
pub fn cubic_guess(c0: Point, rq1: Point, rq3: Point, c3: Point) -> (Point, Point) {
    let a = rq1 * 64.0 - c0 * 27.0 - c3;
    let b = rq3 * 64.0 - c0 - c3 * 27.0;
    ((a * 3.0 - b) / 72.0, (b * 3.0 - a) / 72.0)
}

/// The inner control points of the cubic with ends `C₀, C₃` through `Ra` at
/// `s = sa` and `Rb` at `s = sb`, by Cramer's rule on
/// `B₁(s)C₁ + B₂(s)C₂ = R − B₀(s)C₀ − B₃(s)C₃`; `None` if the system is
/// singular (e.g. `sa = sb` or a parameter at an end).
pub fn cubic_guess_at(
    c0: Point,
    ra: Point,
    sa: f64,
    rb: Point,
    sb: f64,
    c3: Point,
) -> Option<(Point, Point)> {
    let basis = |s: f64| {
        let m = 1.0 - s;
        [m * m * m, 3.0 * m * m * s, 3.0 * m * s * s, s * s * s]
    };
    let (ba, bb) = (basis(sa), basis(sb));
    let ya = ra - c0 * ba[0] - c3 * ba[3];
    let yb = rb - c0 * bb[0] - c3 * bb[3];
    let det = ba[1] * bb[2] - ba[2] * bb[1];
    if det.abs() < 1e-12 {
        return None;
    }
    let c1 = (ya * bb[2] - yb * ba[2]) / det;
    let c2 = (yb * ba[1] - ya * bb[1]) / det;
    Some((c1, c2))
}

/// `C₁ = 2R_mid − (C₀ + C₂)/2`: the quadratic with ends `C₀, C₂` through
/// `R_mid` at `s = 1/2`.
pub fn quadratic_guess(c0: Point, rmid: Point, c2: Point) -> Point {
    rmid * 2.0 - (c0 + c2) * 0.5
}

/// `C₁ = (R − (1−s)²C₀ − s²C₂)/(2(1−s)s)`: the quadratic through `R` at `s`;
/// `None` unless `0 < s < 1`.
pub fn quadratic_guess_at(c0: Point, r: Point, s: f64, c2: Point) -> Option<Point> {
    let m = 1.0 - s;
    let d = 2.0 * m * s;
    if d.abs() < 1e-12 || !d.is_finite() {
        return None;
    }
    Some((r - c0 * (m * m) - c2 * (s * s)) / d)
}

/// The unit tangents estimated at both ends of the data, each pointing into
/// the segment: `(R_k − R₀)/|·|` and `(R_{n−k} − R_n)/|·|`, with `k` capped
/// at `n`; `None` for a degenerate chord.
pub fn end_tangents(points: &[Point], k: usize) -> (Option<Point>, Option<Point>) {
    let n = points.len().saturating_sub(1);
    if n == 0 {
        return (None, None);
    }
    let k = k.clamp(1, n);
    (
        (points[k] - points[0]).normalize(),
        (points[n - k] - points[n]).normalize(),
    )
}

/// The orthogonal projection of `a` on the line through `origin` along `dir`.
pub fn project_on_line(a: Point, origin: Point, dir: Point) -> Point {
    match dir.normalize() {
        Some(u) => origin + u * (a - origin).dot(u),
        None => a,
    }
}

/// The first guesses `A₁′` and (cubic) `A₂′` of a segment, after the `pt`
/// projection; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Guesses {
    /// `A₁′`, the guess of `C₁`.
    pub a1: Point,
    /// `A₂′`, the guess of `C₂` (cubics only).
    pub a2: Option<Point>,
}

/// The guesses for `function` on the segment data `points` (ends fixed at
/// the first and last point) with local parameters `params`. `start_tangent`
/// overrides the tangent estimated at the start (a joined segment knows it).
pub fn guesses(
    function: FunctionType,
    points: &[Point],
    params: &[f64],
    start_tangent: Option<Point>,
    options: &SearchSpaceOptions,
) -> Guesses {
    let n = points.len() - 1;
    let (c0, cn) = (points[0], points[n]);
    let (q1, mid, q3) = quarter_indices(points.len());
    let (t0, t1) = end_tangents(points, options.tangent_points);
    let t0 = start_tangent.and_then(Point::normalize).or(t0);
    let pt = options.pt;
    if function.degree() == 2 {
        let raw = match options.guess {
            GuessRule::QuarterPoints => None,
            GuessRule::ActualParams => quadratic_guess_at(c0, points[mid], params[mid], cn),
        }
        .unwrap_or_else(|| quadratic_guess(c0, points[mid], cn));
        let target = match (t0, t1) {
            (Some(u), Some(v)) => {
                // C₀ + λu = C₂ + μv with λ, μ > 0.
                let det = u.cross(v);
                let d = cn - c0;
                if det.abs() > 1e-12 {
                    let lambda = d.cross(v) / det;
                    let mu = d.cross(u) / det;
                    if lambda > 0.0 && mu > 0.0 {
                        c0 + u * lambda
                    } else {
                        raw
                    }
                } else {
                    raw
                }
            }
            _ => raw,
        };
        Guesses {
            a1: raw.lerp(target, pt),
            a2: None,
        }
    } else {
        let raw = match options.guess {
            GuessRule::QuarterPoints => None,
            GuessRule::ActualParams => {
                cubic_guess_at(c0, points[q1], params[q1], points[q3], params[q3], cn)
            }
        }
        .unwrap_or_else(|| cubic_guess(c0, points[q1], points[q3], cn));
        let p1 = t0.map_or(raw.0, |u| project_on_line(raw.0, c0, u));
        let p2 = t1.map_or(raw.1, |v| project_on_line(raw.1, cn, v));
        Guesses {
            a1: raw.0.lerp(p1, pt),
            a2: Some(raw.1.lerp(p2, pt)),
        }
    }
}

/// An axis-aligned box `[lower, upper]` for one control point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointBox {
    /// The lower corner.
    pub lower: Point,
    /// The upper corner.
    pub upper: Point,
}

impl PointBox {
    /// Whether `p` lies in the box.
    pub fn contains(&self, p: Point) -> bool {
        (self.lower.x..=self.upper.x).contains(&p.x) && (self.lower.y..=self.upper.y).contains(&p.y)
    }
}

/// The box of a control point guessed at `centre` on segment data `points`:
/// `centre ± α_size·|C_m − C₀|` for the technique, the enlarged bounding box
/// for [`SearchSpace::BoundingBox`] (see the module docs).
pub fn point_box(centre: Point, points: &[Point], options: &SearchSpaceOptions) -> PointBox {
    let (lo, hi) = bounding_box(points).expect("segment data are never empty");
    let size = hi - lo;
    let diag = size.hypot();
    match options.kind {
        SearchSpace::Technique => {
            let chord = points[0].distance(points[points.len() - 1]);
            let scale = if chord > 1e-9 * diag {
                chord
            } else if diag > 0.0 {
                diag
            } else {
                1.0
            };
            let h = options.alpha_size * scale;
            PointBox {
                lower: centre - Point::new(h, h),
                upper: centre + Point::new(h, h),
            }
        }
        SearchSpace::BoundingBox => {
            let side = size.x.max(size.y);
            let m = options.margin * if side > 0.0 { side } else { 1.0 };
            PointBox {
                lower: lo - Point::new(m, m),
                upper: hi + Point::new(m, m),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{CubicBez, Curve, QuadBez};

    #[test]
    fn quarter_indices_are_exact_for_multiples_of_four() {
        assert_eq!(quarter_indices(9), (2, 4, 6));
        assert_eq!(quarter_indices(201), (50, 100, 150));
        assert_eq!(quarter_indices(5), (1, 2, 3));
        // n = 6: 1.5 → 1, 3, 4.5 → 4.
        assert_eq!(quarter_indices(7), (1, 3, 4));
    }

    #[test]
    fn guesses_recover_exact_polynomials() {
        let c = CubicBez::new(
            Point::new(0.0, 0.0),
            Point::new(1.0, 3.0),
            Point::new(4.0, -1.0),
            Point::new(5.0, 2.0),
        );
        let (a1, a2) = cubic_guess(c.p0, c.eval(0.25), c.eval(0.75), c.p3);
        assert!((a1 - c.p1).hypot() < 1e-12 && (a2 - c.p2).hypot() < 1e-12);
        let (b1, b2) = cubic_guess_at(c.p0, c.eval(0.1), 0.1, c.eval(0.6), 0.6, c.p3).unwrap();
        assert!((b1 - c.p1).hypot() < 1e-10 && (b2 - c.p2).hypot() < 1e-10);
        assert!(cubic_guess_at(c.p0, c.p0, 0.3, c.p3, 0.3, c.p3).is_none());
        let q = QuadBez::new(Point::ZERO, Point::new(2.0, 4.0), Point::new(3.0, 0.0));
        assert!((quadratic_guess(q.p0, q.eval(0.5), q.p2) - q.p1).hypot() < 1e-12);
        let g = quadratic_guess_at(q.p0, q.eval(0.3), 0.3, q.p2).unwrap();
        assert!((g - q.p1).hypot() < 1e-12);
        assert!(quadratic_guess_at(q.p0, q.p0, 0.0, q.p2).is_none());
    }

    #[test]
    fn pt_projects_onto_tangents() {
        // A quarter circle: the tangent lines meet at (1, 1).
        let pts: Vec<Point> = (0..=40)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64 / 40.0;
                Point::new(a.cos(), a.sin())
            })
            .collect();
        let params: Vec<f64> = (0..=40).map(|k| k as f64 / 40.0).collect();
        let mut o = SearchSpaceOptions {
            pt: 1.0,
            tangent_points: 1,
            ..Default::default()
        };
        let g = guesses(FunctionType::Quadratic, &pts, &params, None, &o);
        // The chords to the first neighbours are nearly the tangents.
        assert!((g.a1 - Point::new(1.0, 1.0)).hypot() < 0.05, "{g:?}");
        o.pt = 0.0;
        let g0 = guesses(FunctionType::Quadratic, &pts, &params, None, &o);
        assert!((g0.a1 - quadratic_guess(pts[0], pts[20], pts[40])).hypot() < 1e-15);
        // Cubic: with pt = 1 the guesses lie on the tangent lines.
        o.pt = 1.0;
        let g = guesses(
            FunctionType::Cubic,
            &pts,
            &params,
            Some(Point::new(0.0, 1.0)),
            &o,
        );
        assert!((g.a1.x - 1.0).abs() < 1e-12, "{g:?}");
        let (_, t1) = end_tangents(&pts, 1);
        let a2 = g.a2.unwrap();
        assert!((a2 - pts[40]).cross(t1.unwrap()).abs() < 1e-12);
    }

    #[test]
    fn boxes() {
        let pts = [Point::ZERO, Point::new(2.0, 1.0), Point::new(4.0, 0.0)];
        let o = SearchSpaceOptions::default();
        let b = point_box(Point::new(2.0, 2.0), &pts, &o);
        assert_eq!(b.lower, Point::new(0.0, 0.0));
        assert_eq!(b.upper, Point::new(4.0, 4.0));
        let o = SearchSpaceOptions {
            kind: SearchSpace::BoundingBox,
            margin: 0.25,
            ..Default::default()
        };
        let b = point_box(Point::new(99.0, 99.0), &pts, &o);
        assert_eq!(b.lower, Point::new(-1.0, -1.0));
        assert_eq!(b.upper, Point::new(5.0, 2.0));
        assert!(b.contains(Point::new(0.0, 1.5)));
        // Coincident ends (a closed loop) fall back to the diagonal.
        let loop_pts = [Point::ZERO, Point::new(3.0, 4.0), Point::ZERO];
        let o = SearchSpaceOptions::default();
        let b = point_box(Point::ZERO, &loop_pts, &o);
        assert_eq!(b.upper, Point::new(2.5, 2.5));
    }
}
