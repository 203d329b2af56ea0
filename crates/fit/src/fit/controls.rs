//! A segment's control points and weights as the fitting problem evaluates
//! them: the explicit Bernstein forms of degree 2 and 3, their first two
//! derivatives, and the foot-point projection of a data point.

use super::{FunctionType, Segment};
use crate::geometry::{CubicBez, GeometryError, Point, QuadBez, RationalCubicBez, RationalQuadBez};

/// The control points (`c[0..=m]`, unused slots zero) and inner weights of a
/// decision vector; polynomial segments have `w₁ = w₂ = 1`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Controls {
    pub(super) c: [Point; 4],
    pub(super) w1: f64,
    pub(super) w2: f64,
}

/// `P(s)` of the quadratic: `(1−s)²C₀ + 2(1−s)s C₁ + s²C₂`.
#[inline(always)]
pub(super) fn quad(k: &Controls, s: f64) -> Point {
    let t = 1.0 - s;
    let (b0, b1, b2) = (t * t, 2.0 * t * s, s * s);
    Point::new(
        b0 * k.c[0].x + b1 * k.c[1].x + b2 * k.c[2].x,
        b0 * k.c[0].y + b1 * k.c[1].y + b2 * k.c[2].y,
    )
}

/// `P(s)` of the cubic in the explicit Bernstein form.
#[inline(always)]
pub(super) fn cubic(k: &Controls, s: f64) -> Point {
    let t = 1.0 - s;
    let (tt, ss) = (t * t, s * s);
    let (b0, b1, b2, b3) = (tt * t, 3.0 * tt * s, 3.0 * t * ss, ss * s);
    Point::new(
        b0 * k.c[0].x + b1 * k.c[1].x + b2 * k.c[2].x + b3 * k.c[3].x,
        b0 * k.c[0].y + b1 * k.c[1].y + b2 * k.c[2].y + b3 * k.c[3].y,
    )
}

/// `Q(s)` of the rational quadratic `(b₀C₀ + h₁b₁C₁ + b₂C₂)/(b₀ + h₁b₁ + b₂)`.
#[inline(always)]
pub(super) fn rquad(k: &Controls, s: f64) -> Point {
    let t = 1.0 - s;
    let (b0, b1, b2) = (t * t, 2.0 * k.w1 * t * s, s * s);
    let inv = 1.0 / (b0 + b1 + b2);
    Point::new(
        (b0 * k.c[0].x + b1 * k.c[1].x + b2 * k.c[2].x) * inv,
        (b0 * k.c[0].y + b1 * k.c[1].y + b2 * k.c[2].y) * inv,
    )
}

/// `Q(s)` of the rational cubic `Σ w_k b_k C_k / Σ w_k b_k`.
#[inline(always)]
pub(super) fn rcubic(k: &Controls, s: f64) -> Point {
    let t = 1.0 - s;
    let (tt, ss) = (t * t, s * s);
    let (b0, b1, b2, b3) = (tt * t, 3.0 * k.w1 * tt * s, 3.0 * k.w2 * t * ss, ss * s);
    let inv = 1.0 / (b0 + b1 + b2 + b3);
    Point::new(
        (b0 * k.c[0].x + b1 * k.c[1].x + b2 * k.c[2].x + b3 * k.c[3].x) * inv,
        (b0 * k.c[0].y + b1 * k.c[1].y + b2 * k.c[2].y + b3 * k.c[3].y) * inv,
    )
}

/// `Σᵢ |Rᵢ − f(sᵢ)|²`, accumulated in four interleaved partial sums
/// (points `4k + j` into sum `j`, added as `(a₀ + a₁) + (a₂ + a₃)` at the
/// end) so that consecutive points do not wait on one addition chain; the
/// order is fixed, so the value is deterministic.
#[inline(always)]
pub(super) fn sum_sq<F: Fn(f64) -> Point>(points: &[Point], params: &[f64], f: F) -> f64 {
    let n = points.len().min(params.len());
    let (points, params) = (&points[..n], &params[..n]);
    let sq = |r: Point, s: f64| {
        let p = f(s);
        let (dx, dy) = (r.x - p.x, r.y - p.y);
        dx * dx + dy * dy
    };
    let mut acc = [0.0; 4];
    let mut pc = points.chunks_exact(4);
    let mut sc = params.chunks_exact(4);
    for (r, s) in (&mut pc).zip(&mut sc) {
        acc[0] += sq(r[0], s[0]);
        acc[1] += sq(r[1], s[1]);
        acc[2] += sq(r[2], s[2]);
        acc[3] += sq(r[3], s[3]);
    }
    for (j, (&r, &s)) in pc.remainder().iter().zip(sc.remainder()).enumerate() {
        acc[j] += sq(r, s);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
}

impl Controls {
    /// The homogeneous control points `(w_k C_k, w_k)`, `k = 0..=m`, with
    /// `w₀ = w_m = 1` (unused slots zero).
    #[inline(always)]
    fn homogeneous(&self, m: usize) -> [[f64; 3]; 4] {
        let w = [1.0, self.w1, if m == 3 { self.w2 } else { 1.0 }, 1.0];
        let mut h = [[0.0; 3]; 4];
        for (k, hk) in h.iter_mut().enumerate().take(m + 1) {
            let wk = if k == m { 1.0 } else { w[k] };
            *hk = [wk * self.c[k].x, wk * self.c[k].y, wk];
        }
        h
    }

    /// `P(s)`, `P′(s)` and `P″(s)` of the degree-`m` curve (rational or
    /// not: polynomial segments have unit weights), from the homogeneous
    /// form `N(s)/W(s)`: `N′ = m Σ B^{m−1}_k Δh_k`, `N″ = m(m−1) Σ B^{m−2}_k Δ²h_k`,
    /// `P′ = (N′ − P W′)/W`, `P″ = (N″ − 2P′W′ − P W″)/W` (Farin 2002, §13.2).
    #[inline]
    pub(super) fn eval_d2(&self, m: usize, s: f64) -> (Point, Point, Point) {
        let h = self.homogeneous(m);
        let t = 1.0 - s;
        let bern = |d: usize| -> [f64; 4] {
            match d {
                0 => [1.0, 0.0, 0.0, 0.0],
                1 => [t, s, 0.0, 0.0],
                2 => [t * t, 2.0 * t * s, s * s, 0.0],
                _ => [t * t * t, 3.0 * t * t * s, 3.0 * t * s * s, s * s * s],
            }
        };
        let combine = |b: [f64; 4], rows: &[[f64; 3]]| -> [f64; 3] {
            let mut out = [0.0; 3];
            for (bk, row) in b.iter().zip(rows) {
                for c in 0..3 {
                    out[c] += bk * row[c];
                }
            }
            out
        };
        let mut d1 = [[0.0; 3]; 3];
        let mut d2 = [[0.0; 3]; 2];
        for k in 0..m {
            for c in 0..3 {
                d1[k][c] = h[k + 1][c] - h[k][c];
            }
        }
        for k in 0..m.saturating_sub(1) {
            for c in 0..3 {
                d2[k][c] = d1[k + 1][c] - d1[k][c];
            }
        }
        let mf = m as f64;
        let n0 = combine(bern(m), &h[..=m]);
        let n1 = combine(bern(m - 1), &d1[..m]).map(|v| v * mf);
        let n2 = combine(bern(m - 2), &d2[..m - 1]).map(|v| v * mf * (mf - 1.0));
        let (w, w1, w2) = (n0[2], n1[2], n2[2]);
        let p = Point::new(n0[0], n0[1]) / w;
        let p1 = (Point::new(n1[0], n1[1]) - p * w1) / w;
        let p2 = (Point::new(n2[0], n2[1]) - p1 * (2.0 * w1) - p * w2) / w;
        (p, p1, p2)
    }

    /// The segment of `function` with these control points (`c[0..=m]`)
    /// and inner weights; fails where a weight is not positive or a point
    /// is not finite.
    pub(super) fn segment(&self, function: FunctionType) -> Result<Segment, GeometryError> {
        let [c0, c1, c2, c3] = self.c;
        Ok(match function {
            FunctionType::Quadratic => Segment::Quadratic(QuadBez::new(c0, c1, c2)),
            FunctionType::Cubic => Segment::Cubic(CubicBez::new(c0, c1, c2, c3)),
            FunctionType::RationalQuadratic => {
                Segment::RationalQuadratic(RationalQuadBez::new(c0, c1, c2, self.w1)?)
            }
            FunctionType::RationalCubic => {
                Segment::RationalCubic(RationalCubicBez::new(c0, c1, c2, c3, self.w1, self.w2)?)
            }
        })
    }

    /// The partial derivatives of `P(s)` of the degree-`m` curve with
    /// respect to the inner control points and weights: with
    /// `P = Σ w_k B_k C_k / W`, `W = Σ w_k B_k`, `∂P/∂C_k = (w_k B_k / W) I`
    /// and `∂P/∂w_k = B_k (C_k − P) / W` (Piegl & Tiller, *The NURBS Book*,
    /// §4.2). For `m = 2` the `C₂`, `w₂` parts are zero.
    #[inline(always)]
    pub(super) fn partials(&self, m: usize, s: f64) -> Partials {
        let w = [1.0, self.w1, if m == 3 { self.w2 } else { 1.0 }, 1.0];
        let t = 1.0 - s;
        let b: [f64; 4] = if m == 3 {
            [t * t * t, 3.0 * t * t * s, 3.0 * t * s * s, s * s * s]
        } else {
            [t * t, 2.0 * t * s, s * s, 0.0]
        };
        let mut wsum = 0.0;
        let mut num = Point::ZERO;
        for j in 0..=m {
            wsum += w[j] * b[j];
            num += self.c[j] * (w[j] * b[j]);
        }
        let p = num / wsum;
        let inner2 = m == 3;
        Partials {
            c1: w[1] * b[1] / wsum,
            c2: if inner2 { w[2] * b[2] / wsum } else { 0.0 },
            w1: (self.c[1] - p) * (b[1] / wsum),
            w2: if inner2 {
                (self.c[2] - p) * (b[2] / wsum)
            } else {
                Point::ZERO
            },
        }
    }

    /// The foot parameter of `r` on the degree-`m` curve near `s0`: Newton's
    /// method on `g(s) = (P(s) − r)·P′(s)` with `g′ = |P′|² + (P − r)·P″`
    /// (Piegl & Tiller, *The NURBS Book*, §6.1), the Gauss–Newton `g′ = |P′|²`
    /// where the curvature term makes `g′ ≤ 0`, clamped to `[0, 1]`, each
    /// step halved until the distance does not grow beyond its rounding; at most
    /// [`FOOT_ITERATIONS`] steps, stopping when a step moves `s` by at most
    /// `10⁻¹²`. Deterministic; returns `(s, P(s), P′(s))`.
    #[inline]
    pub(super) fn foot(&self, m: usize, r: Point, s0: f64) -> (f64, Point, Point) {
        let mut s = s0.clamp(0.0, 1.0);
        let (mut p, mut d1, mut d2) = self.eval_d2(m, s);
        let mut dist = p.distance_squared(r);
        for _ in 0..FOOT_ITERATIONS {
            let e = p - r;
            let g = e.dot(d1);
            let curved = d1.hypot2() + e.dot(d2);
            let gp = if curved > 0.0 { curved } else { d1.hypot2() };
            if !(gp > 0.0 && gp.is_finite() && g.is_finite()) || g == 0.0 {
                break;
            }
            let mut step = -g / gp;
            let mut moved = 0.0;
            // The rounding of |P − r|² near the foot: without this slack a
            // Newton step that removes a tangential error below
            // √(|P − r|·ε|P|) looks like no gain and the projection stalls.
            let slack = 8.0 * f64::EPSILON * dist.sqrt() * (p.hypot() + r.hypot());
            for _ in 0..40 {
                let next = (s + step).clamp(0.0, 1.0);
                if next == s {
                    break;
                }
                let (pn, d1n, d2n) = self.eval_d2(m, next);
                let dn = pn.distance_squared(r);
                if dn <= dist + slack {
                    moved = (next - s).abs();
                    (s, p, d1, d2, dist) = (next, pn, d1n, d2n, dn);
                    break;
                }
                step *= 0.5;
            }
            if moved <= FOOT_STOP {
                break;
            }
        }
        (s, p, d1)
    }
}

/// The first-order sensitivities of `P(s)` ([`Controls::partials`]).
#[derive(Clone, Copy, Debug)]
pub(super) struct Partials {
    /// `∂P/∂C₁ = c1 · I`.
    pub(super) c1: f64,
    /// `∂P/∂C₂ = c2 · I` (0 for quadratics).
    pub(super) c2: f64,
    /// `∂P/∂w₁`.
    pub(super) w1: Point,
    /// `∂P/∂w₂` (zero for quadratics).
    pub(super) w2: Point,
}

/// The most Newton steps of one foot-point projection ([`Controls::foot`]).
pub(super) const FOOT_ITERATIONS: usize = 30;

/// A projection stops after a step that moves `s` by at most this: Newton
/// converges quadratically there, so what remains is below rounding (on
/// the horse at 101 segments this saves a quarter of the steps of a `4ε`
/// test, and the exactness tests still recover conics to 10⁻¹²).
const FOOT_STOP: f64 = 1e-12;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{CubicBez, Curve, QuadBez, RationalCubicBez, RationalQuadBez};

    fn controls() -> Controls {
        Controls {
            c: [
                Point::new(0.0, 0.0),
                Point::new(1.0, 3.0),
                Point::new(4.0, 2.5),
                Point::new(5.0, -1.0),
            ],
            w1: 0.7,
            w2: 1.9,
        }
    }

    #[test]
    fn derivatives_match_the_curves() {
        let k = controls();
        let [c0, c1, c2, c3] = k.c;
        let unit = Controls {
            w1: 1.0,
            w2: 1.0,
            ..k
        };
        let curves: [(&dyn Curve, Controls, usize); 4] = [
            (&QuadBez::new(c0, c1, c2), unit, 2),
            (&CubicBez::new(c0, c1, c2, c3), unit, 3),
            (&RationalQuadBez::new(c0, c1, c2, k.w1).unwrap(), k, 2),
            (
                &RationalCubicBez::new(c0, c1, c2, c3, k.w1, k.w2).unwrap(),
                k,
                3,
            ),
        ];
        for (curve, k, m) in curves {
            for j in 0..=10 {
                let s = j as f64 / 10.0;
                let (p, d1, d2) = k.eval_d2(m, s);
                let close = |a: Point, b: Point| a.distance(b) <= 1e-12 * (1.0 + b.hypot());
                assert!(close(p, curve.eval(s)), "m {m} s {s}");
                assert!(
                    close(d1, curve.deriv(s)),
                    "m {m} s {s}: {d1:?} {:?}",
                    curve.deriv(s)
                );
                assert!(
                    close(d2, curve.deriv2(s)),
                    "m {m} s {s}: {d2:?} {:?}",
                    curve.deriv2(s)
                );
            }
        }
    }

    #[test]
    fn the_foot_point_is_where_the_residual_is_normal() {
        let k = controls();
        for (m, r) in [(3, Point::new(2.5, 3.0)), (2, Point::new(1.0, 0.2))] {
            let (s, p, d1) = k.foot(m, r, 0.5);
            assert!((0.0..=1.0).contains(&s));
            assert!((p - r).dot(d1).abs() < 1e-12 * d1.hypot() * (p - r).hypot().max(1.0));
            // No sampled parameter is closer.
            for j in 0..=1000 {
                let q = k.eval_d2(m, j as f64 / 1000.0).0;
                assert!(q.distance(r) >= p.distance(r) - 1e-12);
            }
        }
    }
}
