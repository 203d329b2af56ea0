//! Quadratic Bézier segments `P(t) = (1−t)²C₀ + 2(1−t)t C₁ + t²C₂` (Farin 2002, §4.1).

use super::{CubicBez, Curve, Point};

/// A quadratic Bézier segment with control points `C₀, C₁, C₂`; a small `Copy`
/// type for hot loops.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct QuadBez {
    /// Start point `C₀`.
    pub p0: Point,
    /// Middle control point `C₁`.
    pub p1: Point,
    /// End point `C₂`.
    pub p2: Point,
}

impl QuadBez {
    /// The segment with control points `C₀, C₁, C₂`.
    #[inline]
    pub const fn new(p0: Point, p1: Point, p2: Point) -> QuadBez {
        QuadBez { p0, p1, p2 }
    }

    /// The control points `[C₀, C₁, C₂]`.
    #[inline]
    pub fn points(&self) -> [Point; 3] {
        [self.p0, self.p1, self.p2]
    }

    /// `P'(0) = 2(C₁ − C₀)`.
    #[inline]
    pub fn start_deriv(&self) -> Point {
        (self.p1 - self.p0) * 2.0
    }

    /// `P'(1) = 2(C₂ − C₁)`.
    #[inline]
    pub fn end_deriv(&self) -> Point {
        (self.p2 - self.p1) * 2.0
    }

    /// The same curve as a cubic by degree elevation:
    /// `(C₀, C₀ + ⅔(C₁−C₀), C₂ + ⅔(C₁−C₂), C₂)` (Farin 2002, §6.1).
    #[inline]
    pub fn raise(&self) -> CubicBez {
        CubicBez::new(
            self.p0,
            self.p0 + (self.p1 - self.p0) * (2.0 / 3.0),
            self.p2 + (self.p1 - self.p2) * (2.0 / 3.0),
            self.p2,
        )
    }
}

impl Curve for QuadBez {
    /// `P(t) = (1−t)²C₀ + 2(1−t)t C₁ + t²C₂` with the explicit Bernstein basis
    /// (Farin 2002, §4.1).
    #[inline]
    fn eval(&self, t: f64) -> Point {
        let mt = 1.0 - t;
        self.p0 * (mt * mt) + self.p1 * (2.0 * mt * t) + self.p2 * (t * t)
    }

    /// `P'(t) = 2[(1−t)(C₁ − C₀) + t(C₂ − C₁)]` (Farin 2002, eq. 5.18 with n = 2).
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        ((self.p1 - self.p0) * (1.0 - t) + (self.p2 - self.p1) * t) * 2.0
    }

    /// `P''(t) = 2(C₂ − 2C₁ + C₀)`, constant (Farin 2002, eq. 5.22 with n = 2).
    #[inline]
    fn deriv2(&self, _t: f64) -> Point {
        (self.p2 - self.p1 * 2.0 + self.p0) * 2.0
    }

    /// `P(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.p0
    }

    /// `P(1) = C₂`.
    #[inline]
    fn end(&self) -> Point {
        self.p2
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::super::Bezier;
    use super::*;

    #[test]
    fn matches_general_bezier() {
        let mut rng = TestRng(10);
        for _ in 0..20 {
            let q = QuadBez::new(rng.point(), rng.point(), rng.point());
            let b = Bezier::from(q);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((q.eval(t) - b.eval(t)).hypot() < 1e-12);
                assert!((q.deriv(t) - b.deriv(t)).hypot() < 1e-12);
                assert!((q.deriv2(t) - b.deriv2(t)).hypot() < 1e-12);
            }
            assert!((q.start_deriv() - b.deriv(0.0)).hypot() < 1e-12);
            assert!((q.end_deriv() - b.deriv(1.0)).hypot() < 1e-12);
            assert_eq!(q.eval(0.0), q.p0);
            assert_eq!(q.eval(1.0), q.p2);
            let c = q.raise();
            assert_eq!(c.p0, q.p0);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((q.eval(t) - c.eval(t)).hypot() < 1e-12);
            }
        }
    }

    #[test]
    fn eval_many_and_sse() {
        let q = QuadBez::new(Point::ZERO, Point::new(1.0, 2.0), Point::new(2.0, 0.0));
        let ts = [0.0, 0.5, 1.0];
        let mut out = [Point::ZERO; 3];
        q.eval_many(&ts, &mut out);
        assert_eq!(
            out,
            [Point::ZERO, Point::new(1.0, 1.0), Point::new(2.0, 0.0)]
        );
        let r = [
            Point::new(0.0, 1.0),
            Point::new(1.0, 1.0),
            Point::new(2.0, -2.0),
        ];
        assert_eq!(q.sse(&r, &ts), 1.0 + 0.0 + 4.0);
        // Arc length of the straight segment (0,0)-(1,0)-(2,0) is 2.
        let line = QuadBez::new(Point::ZERO, Point::new(1.0, 0.0), Point::new(2.0, 0.0));
        assert!((line.arclen() - 2.0).abs() < 1e-13);
    }
}
