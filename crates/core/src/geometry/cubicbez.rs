//! Cubic Bézier segments `P(t) = Σᵢ Cᵢ B_i^3(t)` (Farin 2002, §4.1).

use super::{Curve, Point};

/// A cubic Bézier segment with control points `C₀..C₃`; a small `Copy` type
/// for hot loops.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CubicBez {
    /// Start point `C₀`.
    pub p0: Point,
    /// First inner control point `C₁`.
    pub p1: Point,
    /// Second inner control point `C₂`.
    pub p2: Point,
    /// End point `C₃`.
    pub p3: Point,
}

impl CubicBez {
    /// The segment with control points `C₀, C₁, C₂, C₃`.
    #[inline]
    pub const fn new(p0: Point, p1: Point, p2: Point, p3: Point) -> CubicBez {
        CubicBez { p0, p1, p2, p3 }
    }

    /// The control points `[C₀, C₁, C₂, C₃]`.
    #[inline]
    pub fn points(&self) -> [Point; 4] {
        [self.p0, self.p1, self.p2, self.p3]
    }

    /// `P'(0) = 3(C₁ − C₀)`.
    #[inline]
    pub fn start_deriv(&self) -> Point {
        (self.p1 - self.p0) * 3.0
    }

    /// `P'(1) = 3(C₃ − C₂)`.
    #[inline]
    pub fn end_deriv(&self) -> Point {
        (self.p3 - self.p2) * 3.0
    }
}

impl Curve for CubicBez {
    /// `P(t) = (1−t)³C₀ + 3(1−t)²t C₁ + 3(1−t)t² C₂ + t³C₃` with the explicit
    /// Bernstein basis (Farin 2002, §4.1).
    #[inline]
    fn eval(&self, t: f64) -> Point {
        let mt = 1.0 - t;
        let mt2 = mt * mt;
        let t2 = t * t;
        self.p0 * (mt2 * mt)
            + self.p1 * (3.0 * mt2 * t)
            + self.p2 * (3.0 * mt * t2)
            + self.p3 * (t2 * t)
    }

    /// `P'(t) = 3[(1−t)²(C₁−C₀) + 2(1−t)t(C₂−C₁) + t²(C₃−C₂)]` (Farin 2002,
    /// eq. 5.18 with n = 3).
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        let mt = 1.0 - t;
        ((self.p1 - self.p0) * (mt * mt)
            + (self.p2 - self.p1) * (2.0 * mt * t)
            + (self.p3 - self.p2) * (t * t))
            * 3.0
    }

    /// `P''(t) = 6[(1−t)(C₂ − 2C₁ + C₀) + t(C₃ − 2C₂ + C₁)]` (Farin 2002,
    /// eq. 5.22 with n = 3).
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        let a = self.p2 - self.p1 * 2.0 + self.p0;
        let b = self.p3 - self.p2 * 2.0 + self.p1;
        (a * (1.0 - t) + b * t) * 6.0
    }

    /// `P(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.p0
    }

    /// `P(1) = C₃`.
    #[inline]
    fn end(&self) -> Point {
        self.p3
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::super::Bezier;
    use super::*;

    #[test]
    fn matches_general_bezier() {
        let mut rng = TestRng(20);
        for _ in 0..20 {
            let c = CubicBez::new(rng.point(), rng.point(), rng.point(), rng.point());
            let b = Bezier::from(c);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((c.eval(t) - b.eval(t)).hypot() < 1e-12);
                assert!((c.deriv(t) - b.deriv(t)).hypot() < 1e-11);
                assert!((c.deriv2(t) - b.deriv2(t)).hypot() < 1e-10);
            }
            assert!((c.start_deriv() - b.deriv(0.0)).hypot() < 1e-12);
            assert!((c.end_deriv() - b.deriv(1.0)).hypot() < 1e-12);
            assert_eq!(c.eval(0.0), c.p0);
            assert_eq!(c.eval(1.0), c.p3);
        }
    }

    #[test]
    fn eval_many_and_sse() {
        // The cubic with collinear, evenly spaced points is P(t) = (3t, 0).
        let c = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, 0.0),
        );
        let ts = [0.0, 0.5, 1.0];
        let mut out = [Point::ZERO; 3];
        c.eval_many(&ts, &mut out);
        assert_eq!(
            out,
            [Point::ZERO, Point::new(1.5, 0.0), Point::new(3.0, 0.0)]
        );
        let r = [
            Point::new(0.0, 1.0),
            Point::new(1.5, 0.0),
            Point::new(3.0, 2.0),
        ];
        assert_eq!(c.sse(&r, &ts), 5.0);
        assert!((c.arclen() - 3.0).abs() < 1e-13);
        assert!((c.deriv(0.3) - Point::new(3.0, 0.0)).hypot() < 1e-15);
    }
}
