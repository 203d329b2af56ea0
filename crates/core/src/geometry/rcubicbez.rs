//! Rational cubic Bézier segments in standard form `w₀ = w₃ = 1`
//! (Farin 2002, §13.1–13.3).

use super::casteljau::{project_jet, Hom};
use super::error::{check_points, check_weight, GeometryError};
use super::{Curve, Point};

/// A rational cubic segment `Q(t) = Σ wᵢ Cᵢ B_i^3(t) / Σ wᵢ B_i^3(t)` with
/// weights `(1, w₁, w₂, 1)`, `w₁, w₂ > 0` (Farin 2002, eq. 13.2 in standard form).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RationalCubicBez {
    p0: Point,
    p1: Point,
    p2: Point,
    p3: Point,
    w1: f64,
    w2: f64,
}

impl RationalCubicBez {
    /// The segment with control points `C₀..C₃` and inner weights `w₁, w₂`;
    /// fails unless both weights are finite and `> 0` and every point is finite.
    pub fn new(
        p0: Point,
        p1: Point,
        p2: Point,
        p3: Point,
        w1: f64,
        w2: f64,
    ) -> Result<RationalCubicBez, GeometryError> {
        check_points(&[p0, p1, p2, p3])?;
        check_weight(1, w1)?;
        check_weight(2, w2)?;
        Ok(RationalCubicBez {
            p0,
            p1,
            p2,
            p3,
            w1,
            w2,
        })
    }

    /// The segment with arbitrary positive weights `w₀..w₃`, converted to
    /// standard form by `wᵢ ← wᵢ cⁱ / w₀`, `c = (w₀/w₃)^{1/3}` (Farin 2002, §13.3);
    /// the curve is reparametrised, its trace unchanged.
    pub fn from_weights(
        points: [Point; 4],
        weights: [f64; 4],
    ) -> Result<RationalCubicBez, GeometryError> {
        for (i, &w) in weights.iter().enumerate() {
            check_weight(i, w)?;
        }
        let [w0, w1, w2, w3] = weights;
        let c = (w0 / w3).cbrt();
        let [p0, p1, p2, p3] = points;
        RationalCubicBez::new(p0, p1, p2, p3, w1 * c / w0, w2 * c * c / w0)
    }

    /// The control points `[C₀, C₁, C₂, C₃]`.
    #[inline]
    pub fn points(&self) -> [Point; 4] {
        [self.p0, self.p1, self.p2, self.p3]
    }

    /// The inner weight `w₁`.
    #[inline]
    pub fn w1(&self) -> f64 {
        self.w1
    }

    /// The inner weight `w₂`.
    #[inline]
    pub fn w2(&self) -> f64 {
        self.w2
    }

    /// All weights in standard form, `[1, w₁, w₂, 1]`.
    #[inline]
    pub fn weights(&self) -> [f64; 4] {
        [1.0, self.w1, self.w2, 1.0]
    }

    /// `[Q, Q', Q'']` from the homogeneous cubic `H = (A, W)` with points
    /// `(wᵢCᵢ, wᵢ)` and the quotient rule `Q' = (A' − W'Q)/W`,
    /// `Q'' = (A'' − 2W'Q' − W''Q)/W` (Farin 2002, §13.4).
    #[inline]
    pub fn jet(&self, t: f64) -> [Point; 3] {
        let h0 = Hom::lift(self.p0, 1.0);
        let h1 = Hom::lift(self.p1, self.w1);
        let h2 = Hom::lift(self.p2, self.w2);
        let h3 = Hom::lift(self.p3, 1.0);
        let mt = 1.0 - t;
        let (d0, d1, d2) = (h1 - h0, h2 - h1, h3 - h2);
        let h = h0 * (mt * mt * mt)
            + h1 * (3.0 * mt * mt * t)
            + h2 * (3.0 * mt * t * t)
            + h3 * (t * t * t);
        let dh = (d0 * (mt * mt) + d1 * (2.0 * mt * t) + d2 * (t * t)) * 3.0;
        let ddh = ((d1 - d0) * mt + (d2 - d1) * t) * 6.0;
        project_jet([h, dh, ddh])
    }

    /// `Q'(0) = 3(w₁/w₀)(C₁ − C₀) = 3w₁(C₁ − C₀)` (Farin 2002, eq. 13.10).
    #[inline]
    pub fn start_deriv(&self) -> Point {
        (self.p1 - self.p0) * (3.0 * self.w1)
    }

    /// `Q'(1) = 3(w₂/w₃)(C₃ − C₂) = 3w₂(C₃ − C₂)` (Farin 2002, eq. 13.10).
    #[inline]
    pub fn end_deriv(&self) -> Point {
        (self.p3 - self.p2) * (3.0 * self.w2)
    }
}

impl Curve for RationalCubicBez {
    /// `Q(t) = A(t)/W(t)` with the explicit cubic Bernstein basis
    /// `A = Σ wᵢ Cᵢ B_i^3(t)`, `W = Σ wᵢ B_i^3(t)` (Farin 2002, eq. 13.2).
    #[inline]
    fn eval(&self, t: f64) -> Point {
        let mt = 1.0 - t;
        let mt2 = mt * mt;
        let t2 = t * t;
        let b0 = mt2 * mt;
        let b1 = 3.0 * self.w1 * mt2 * t;
        let b2 = 3.0 * self.w2 * mt * t2;
        let b3 = t2 * t;
        (self.p0 * b0 + self.p1 * b1 + self.p2 * b2 + self.p3 * b3) / (b0 + b1 + b2 + b3)
    }

    /// `Q'(t) = (A' − W'Q)/W` with
    /// `A' = 3[(1−t)²(w₁C₁ − C₀) + 2(1−t)t(w₂C₂ − w₁C₁) + t²(C₃ − w₂C₂)]`
    /// and `W'` the same with the weights (quotient rule; Farin 2002, §13.4),
    /// from [`RationalCubicBez::jet`].
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        self.jet(t)[1]
    }

    /// `Q''(t) = (A'' − 2W'Q' − W''Q)/W` with
    /// `A'' = 6[(1−t)(w₂C₂ − 2w₁C₁ + C₀) + t(C₃ − 2w₂C₂ + w₁C₁)]` and `W''` the
    /// same with the weights (Farin 2002, §13.4), from [`RationalCubicBez::jet`].
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        self.jet(t)[2]
    }

    /// `Q(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.p0
    }

    /// `Q(1) = C₃`.
    #[inline]
    fn end(&self) -> Point {
        self.p3
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::super::{CubicBez, RationalBezier};
    use super::*;

    fn random(rng: &mut TestRng) -> RationalCubicBez {
        RationalCubicBez::new(
            rng.point(),
            rng.point(),
            rng.point(),
            rng.point(),
            rng.range(0.1, 6.0),
            rng.range(0.1, 6.0),
        )
        .unwrap()
    }

    #[test]
    fn rejects_bad_weights() {
        let p = Point::ZERO;
        assert!(matches!(
            RationalCubicBez::new(p, p, p, p, 0.0, 1.0),
            Err(GeometryError::InvalidWeight { index: 1, .. })
        ));
        assert!(matches!(
            RationalCubicBez::new(p, p, p, p, 1.0, -2.0),
            Err(GeometryError::InvalidWeight { index: 2, .. })
        ));
        assert!(RationalCubicBez::new(p, p, p, p, f64::NAN, 1.0).is_err());
        assert!(RationalCubicBez::new(p, p, p, p, 1.0, f64::INFINITY).is_err());
        assert!(RationalCubicBez::new(p, p, Point::new(0.0, f64::NAN), p, 1.0, 1.0).is_err());
        assert!(RationalCubicBez::from_weights([p; 4], [1.0, 1.0, 1.0, 0.0]).is_err());
        assert!(RationalCubicBez::new(p, p, p, p, 1e-3, 1e3).is_ok());
    }

    #[test]
    fn unit_weights_give_the_polynomial() {
        let mut rng = TestRng(50);
        for _ in 0..10 {
            let [a, b, c, d] = [rng.point(), rng.point(), rng.point(), rng.point()];
            let r = RationalCubicBez::new(a, b, c, d, 1.0, 1.0).unwrap();
            let p = CubicBez::new(a, b, c, d);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((r.eval(t) - p.eval(t)).hypot() < 1e-13);
                assert!((r.deriv(t) - p.deriv(t)).hypot() < 1e-11);
                assert!((r.deriv2(t) - p.deriv2(t)).hypot() < 1e-10);
            }
        }
    }

    #[test]
    fn matches_general_rational() {
        let mut rng = TestRng(51);
        for _ in 0..20 {
            let r = random(&mut rng);
            let g = RationalBezier::from(r);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let [q, d1, d2] = g.jet(t);
                assert!((r.eval(t) - q).hypot() < 1e-12);
                assert!((r.deriv(t) - d1).hypot() < 1e-10 * (1.0 + d1.hypot()));
                assert!((r.deriv2(t) - d2).hypot() < 1e-10 * (1.0 + d2.hypot()));
                assert!((r.eval(t) - g.eval_bernstein(t)).hypot() < 1e-11);
            }
        }
    }

    #[test]
    fn end_derivatives_match_finite_differences() {
        let mut rng = TestRng(52);
        let h = 1e-6;
        for _ in 0..20 {
            let r = random(&mut rng);
            let fd0 = (r.eval(0.0) * -3.0 + r.eval(h) * 4.0 - r.eval(2.0 * h)) / (2.0 * h);
            let fd1 =
                (r.eval(1.0) * 3.0 - r.eval(1.0 - h) * 4.0 + r.eval(1.0 - 2.0 * h)) / (2.0 * h);
            assert!((r.start_deriv() - fd0).hypot() < 1e-5 * (1.0 + fd0.hypot()));
            assert!((r.end_deriv() - fd1).hypot() < 1e-5 * (1.0 + fd1.hypot()));
            let s = r.start_deriv();
            let e = r.end_deriv();
            assert!((s - r.deriv(0.0)).hypot() < 1e-10 * (1.0 + s.hypot()));
            assert!((e - r.deriv(1.0)).hypot() < 1e-10 * (1.0 + e.hypot()));
            for k in 1..10 {
                let t = k as f64 / 10.0;
                let fd = (r.eval(t + h) - r.eval(t - h)) / (2.0 * h);
                assert!((r.deriv(t) - fd).hypot() < 1e-6 * (1.0 + fd.hypot()));
            }
        }
    }

    #[test]
    fn from_weights_keeps_the_trace() {
        let pts = [
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.5),
            Point::new(4.0, 0.0),
        ];
        let w = [3.0, 0.5, 2.0, 0.25];
        let s = RationalCubicBez::from_weights(pts, w).unwrap();
        let g = RationalBezier::new(pts.to_vec(), w.to_vec()).unwrap();
        let c = (w[0] / w[3]).cbrt();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            let u = c * t / ((1.0 - t) + c * t);
            assert!((s.eval(t) - g.eval(u)).hypot() < 1e-12);
        }
        let std = g.to_standard_form();
        assert!((std.weights()[1] - s.w1()).abs() < 1e-14);
        assert!((std.weights()[2] - s.w2()).abs() < 1e-14);
        let ts = [0.0, 1.0];
        let mut out = [Point::ZERO; 2];
        s.eval_many(&ts, &mut out);
        assert_eq!(out, [pts[0], pts[3]]);
        assert_eq!(s.sse(&[pts[0], Point::new(4.0, 2.0)], &ts), 4.0);
    }
}
