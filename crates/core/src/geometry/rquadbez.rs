//! Rational quadratic Bézier segments (conic sections) in standard form
//! `w₀ = w₂ = 1` (Farin 2002, ch. 12; Piegl & Tiller, *The NURBS Book*, §7.2).

use super::casteljau::{project_jet, Hom};
use super::error::{check_points, check_weight, GeometryError};
use super::{Curve, Point};

/// A rational quadratic segment `Q(t) = ((1−t)²C₀ + 2h₁(1−t)t C₁ + t²C₂) /
/// ((1−t)² + 2h₁(1−t)t + t²)` with middle weight `h₁ > 0` (Farin 2002, eq. 12.2).
///
/// `h₁ < 1` gives an ellipse arc, `h₁ = 1` a parabola, `h₁ > 1` a hyperbola.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RationalQuadBez {
    p0: Point,
    p1: Point,
    p2: Point,
    h1: f64,
}

impl RationalQuadBez {
    /// The segment with control points `C₀, C₁, C₂` and middle weight `h₁`;
    /// fails unless `h₁` is finite and `> 0` and every point is finite.
    pub fn new(p0: Point, p1: Point, p2: Point, h1: f64) -> Result<RationalQuadBez, GeometryError> {
        check_points(&[p0, p1, p2])?;
        check_weight(1, h1)?;
        Ok(RationalQuadBez { p0, p1, p2, h1 })
    }

    /// The segment with arbitrary positive weights `w₀, w₁, w₂`, converted to
    /// standard form by `h₁ = w₁/√(w₀w₂)` (Farin 2002, §12.3, the conic shape
    /// factor); the curve is reparametrised, its trace unchanged.
    pub fn from_weights(
        points: [Point; 3],
        weights: [f64; 3],
    ) -> Result<RationalQuadBez, GeometryError> {
        for (i, &w) in weights.iter().enumerate() {
            check_weight(i, w)?;
        }
        let [w0, w1, w2] = weights;
        let [p0, p1, p2] = points;
        RationalQuadBez::new(p0, p1, p2, w1 / (w0 * w2).sqrt())
    }

    /// The circular arc of radius `r` about `center` from angle `start` turning
    /// by `sweep` (radians, `0 < |sweep| < π`; negative is clockwise):
    /// `C₁` is the tangent intersection at distance `r / cos(sweep/2)` and
    /// `h₁ = cos(sweep/2)` (Farin 2002, §12.5; Piegl & Tiller §7.3).
    pub fn circular_arc(
        center: Point,
        r: f64,
        start: f64,
        sweep: f64,
    ) -> Result<RationalQuadBez, GeometryError> {
        if !(r.is_finite() && r > 0.0) {
            return Err(GeometryError::InvalidParameter {
                name: "r",
                value: r,
            });
        }
        if !(sweep.is_finite() && sweep != 0.0 && sweep.abs() < std::f64::consts::PI) {
            return Err(GeometryError::InvalidParameter {
                name: "sweep",
                value: sweep,
            });
        }
        if !start.is_finite() {
            return Err(GeometryError::InvalidParameter {
                name: "start",
                value: start,
            });
        }
        let half = 0.5 * sweep;
        let h1 = half.cos();
        let at = |a: f64, rad: f64| center + Point::new(a.cos(), a.sin()) * rad;
        RationalQuadBez::new(
            at(start, r),
            at(start + half, r / h1),
            at(start + sweep, r),
            h1,
        )
    }

    /// The control points `[C₀, C₁, C₂]`.
    #[inline]
    pub fn points(&self) -> [Point; 3] {
        [self.p0, self.p1, self.p2]
    }

    /// The middle weight `h₁`.
    #[inline]
    pub fn h1(&self) -> f64 {
        self.h1
    }

    /// All weights in standard form, `[1, h₁, 1]`.
    #[inline]
    pub fn weights(&self) -> [f64; 3] {
        [1.0, self.h1, 1.0]
    }

    /// `[Q, Q', Q'']` from the homogeneous polynomial `H = (A, W)` and the
    /// quotient rule `Q' = (A' − W'Q)/W`, `Q'' = (A'' − 2W'Q' − W''Q)/W`.
    #[inline]
    pub fn jet(&self, t: f64) -> [Point; 3] {
        let h0 = Hom::lift(self.p0, 1.0);
        let h1 = Hom::lift(self.p1, self.h1);
        let h2 = Hom::lift(self.p2, 1.0);
        let mt = 1.0 - t;
        let d0 = h1 - h0;
        let d1 = h2 - h1;
        let h = h0 * (mt * mt) + h1 * (2.0 * mt * t) + h2 * (t * t);
        let dh = (d0 * mt + d1 * t) * 2.0;
        let ddh = (d1 - d0) * 2.0;
        project_jet([h, dh, ddh])
    }

    /// `Q'(0) = 2(w₁/w₀)(C₁ − C₀) = 2h₁(C₁ − C₀)` (Farin 2002, eq. 13.10).
    #[inline]
    pub fn start_deriv(&self) -> Point {
        (self.p1 - self.p0) * (2.0 * self.h1)
    }

    /// `Q'(1) = 2(w₁/w₂)(C₂ − C₁) = 2h₁(C₂ − C₁)` (Farin 2002, eq. 13.10).
    #[inline]
    pub fn end_deriv(&self) -> Point {
        (self.p2 - self.p1) * (2.0 * self.h1)
    }
}

impl Curve for RationalQuadBez {
    /// `Q(t) = A(t)/W(t)` with the explicit basis
    /// `A = (1−t)²C₀ + 2h₁(1−t)t C₁ + t²C₂`, `W = (1−t)² + 2h₁(1−t)t + t²`
    /// (Farin 2002, eq. 12.2).
    #[inline]
    fn eval(&self, t: f64) -> Point {
        let mt = 1.0 - t;
        let b0 = mt * mt;
        let b1 = 2.0 * self.h1 * mt * t;
        let b2 = t * t;
        (self.p0 * b0 + self.p1 * b1 + self.p2 * b2) / (b0 + b1 + b2)
    }

    /// `Q'(t) = (A' − W'Q)/W` with `A' = 2[(1−t)(h₁C₁ − C₀) + t(C₂ − h₁C₁)]` and
    /// `W' = 2(h₁ − 1)(1 − 2t)` (quotient rule; Farin 2002, §13.4), from
    /// [`RationalQuadBez::jet`].
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        self.jet(t)[1]
    }

    /// `Q''(t) = (A'' − 2W'Q' − W''Q)/W` with `A'' = 2(C₂ − 2h₁C₁ + C₀)` and
    /// `W'' = 4(1 − h₁)` (Farin 2002, §13.4), from [`RationalQuadBez::jet`].
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        self.jet(t)[2]
    }

    /// `Q(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.p0
    }

    /// `Q(1) = C₂`.
    #[inline]
    fn end(&self) -> Point {
        self.p2
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::super::{QuadBez, RationalBezier};
    use super::*;

    #[test]
    fn rejects_bad_weights() {
        let (a, b, c) = (Point::ZERO, Point::new(1.0, 1.0), Point::new(2.0, 0.0));
        for bad in [0.0, -0.5, f64::NAN, f64::INFINITY] {
            assert!(matches!(
                RationalQuadBez::new(a, b, c, bad),
                Err(GeometryError::InvalidWeight { index: 1, .. })
            ));
        }
        assert!(RationalQuadBez::new(a, Point::new(f64::NAN, 0.0), c, 1.0).is_err());
        assert!(RationalQuadBez::from_weights([a, b, c], [1.0, 1.0, 0.0]).is_err());
        assert!(RationalQuadBez::circular_arc(a, 1.0, 0.0, std::f64::consts::PI).is_err());
        assert!(RationalQuadBez::circular_arc(a, -1.0, 0.0, 1.0).is_err());
        assert!(RationalQuadBez::circular_arc(a, 1.0, 0.0, 0.0).is_err());
    }

    #[test]
    fn unit_weight_is_the_polynomial() {
        let mut rng = TestRng(40);
        for _ in 0..10 {
            let (a, b, c) = (rng.point(), rng.point(), rng.point());
            let r = RationalQuadBez::new(a, b, c, 1.0).unwrap();
            let q = QuadBez::new(a, b, c);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((r.eval(t) - q.eval(t)).hypot() < 1e-13);
                assert!((r.deriv(t) - q.deriv(t)).hypot() < 1e-12);
                assert!((r.deriv2(t) - q.deriv2(t)).hypot() < 1e-11);
            }
        }
    }

    #[test]
    fn matches_general_rational() {
        let mut rng = TestRng(41);
        for _ in 0..20 {
            let r =
                RationalQuadBez::new(rng.point(), rng.point(), rng.point(), rng.range(0.1, 6.0))
                    .unwrap();
            let g = RationalBezier::from(r);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let [q, d1, d2] = g.jet(t);
                assert!((r.eval(t) - q).hypot() < 1e-12);
                assert!((r.deriv(t) - d1).hypot() < 1e-10 * (1.0 + d1.hypot()));
                assert!((r.deriv2(t) - d2).hypot() < 1e-10 * (1.0 + d2.hypot()));
            }
            assert!(
                (r.start_deriv() - r.deriv(0.0)).hypot() < 1e-10 * (1.0 + r.start_deriv().hypot())
            );
            assert!((r.end_deriv() - r.deriv(1.0)).hypot() < 1e-10 * (1.0 + r.end_deriv().hypot()));
        }
    }

    #[test]
    fn end_derivatives_match_finite_differences() {
        let mut rng = TestRng(42);
        let h = 1e-6;
        for _ in 0..20 {
            let r =
                RationalQuadBez::new(rng.point(), rng.point(), rng.point(), rng.range(0.1, 6.0))
                    .unwrap();
            let fd0 = (r.eval(0.0) * -3.0 + r.eval(h) * 4.0 - r.eval(2.0 * h)) / (2.0 * h);
            let fd1 =
                (r.eval(1.0) * 3.0 - r.eval(1.0 - h) * 4.0 + r.eval(1.0 - 2.0 * h)) / (2.0 * h);
            assert!((r.start_deriv() - fd0).hypot() < 1e-5 * (1.0 + fd0.hypot()));
            assert!((r.end_deriv() - fd1).hypot() < 1e-5 * (1.0 + fd1.hypot()));
        }
    }

    /// Farin's conic test: with `C₀, C₂` the ends of a circular arc of angle 2θ,
    /// `C₁` the intersection of the end tangents and `h₁ = cos θ`, every point of
    /// the curve lies on the circle.
    #[test]
    fn cos_theta_weight_gives_an_exact_circle() {
        for &theta in &[0.1, 0.5, std::f64::consts::FRAC_PI_4, 1.0, 1.4, 1.55] {
            let r: f64 = 2.5;
            let c0 = Point::new(r * theta.cos(), -r * theta.sin());
            let c2 = Point::new(r * theta.cos(), r * theta.sin());
            let c1 = Point::new(r / theta.cos(), 0.0);
            let q = RationalQuadBez::new(c0, c1, c2, theta.cos()).unwrap();
            for k in 0..=200 {
                let t = k as f64 / 200.0;
                let d = q.eval(t).hypot();
                assert!((d - r).abs() < 1e-12, "theta={theta} t={t} err={}", d - r);
            }
            // Arc length 2θr.
            let len = q.arclen();
            assert!((len - 2.0 * theta * r).abs() < 1e-9 * r, "theta={theta}");
        }
        // The helper constructor, off-centre and clockwise.
        let centre = Point::new(3.0, -1.0);
        let q = RationalQuadBez::circular_arc(centre, 0.75, 2.0, -2.5).unwrap();
        for k in 0..=100 {
            let t = k as f64 / 100.0;
            assert!((q.eval(t).distance(centre) - 0.75).abs() < 1e-12);
        }
        // A non-circular weight leaves the circle.
        let [a, b, c] = q.points();
        let e = RationalQuadBez::new(a, b, c, 0.9 * q.h1()).unwrap();
        assert!((e.eval(0.5).distance(centre) - 0.75).abs() > 1e-3);
    }

    #[test]
    fn from_weights_keeps_the_trace() {
        let pts = [Point::ZERO, Point::new(1.0, 2.0), Point::new(3.0, 0.5)];
        let w = [2.0, 1.5, 0.5];
        let s = RationalQuadBez::from_weights(pts, w).unwrap();
        assert!((s.h1() - 1.5).abs() < 1e-15); // 1.5 / √(2·0.5)
        let g = RationalBezier::new(pts.to_vec(), w.to_vec()).unwrap();
        let c = (w[0] / w[2]).sqrt();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let u = c * t / ((1.0 - t) + c * t);
            assert!((s.eval(t) - g.eval(u)).hypot() < 1e-12);
        }
        let ts = [0.0, 1.0];
        let mut out = [Point::ZERO; 2];
        s.eval_many(&ts, &mut out);
        assert_eq!(out, [pts[0], pts[2]]);
        assert_eq!(s.sse(&[pts[0], Point::new(3.0, 1.5)], &ts), 1.0);
    }
}
