//! A fitted segment: one of the four curve types behind one [`Curve`].

use super::FunctionType;
use crate::geometry::{
    CubicBez, Curve, Point, QuadBez, RationalCubicBez, RationalQuadBez, SegmentEnd,
};

/// The geometry of one fitted segment, of any [`FunctionType`]; implements
/// [`Curve`] and [`SegmentEnd`] by delegation (kurbo's `PathSeg` pattern).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A quadratic Bézier segment.
    Quadratic(QuadBez),
    /// A cubic Bézier segment.
    Cubic(CubicBez),
    /// A rational quadratic segment in standard form.
    RationalQuadratic(RationalQuadBez),
    /// A rational cubic segment in standard form.
    RationalCubic(RationalCubicBez),
}

impl Segment {
    /// The function type of this segment.
    pub fn function(&self) -> FunctionType {
        match self {
            Segment::Quadratic(_) => FunctionType::Quadratic,
            Segment::Cubic(_) => FunctionType::Cubic,
            Segment::RationalQuadratic(_) => FunctionType::RationalQuadratic,
            Segment::RationalCubic(_) => FunctionType::RationalCubic,
        }
    }

    /// The control points `C₀..C_m`.
    pub fn control_points(&self) -> Vec<Point> {
        match self {
            Segment::Quadratic(c) => c.points().to_vec(),
            Segment::Cubic(c) => c.points().to_vec(),
            Segment::RationalQuadratic(c) => c.points().to_vec(),
            Segment::RationalCubic(c) => c.points().to_vec(),
        }
    }

    /// The weights `w₀..w_m` (all 1 for polynomial segments).
    pub fn weights(&self) -> Vec<f64> {
        match self {
            Segment::Quadratic(_) => vec![1.0; 3],
            Segment::Cubic(_) => vec![1.0; 4],
            Segment::RationalQuadratic(c) => c.weights().to_vec(),
            Segment::RationalCubic(c) => c.weights().to_vec(),
        }
    }
}

impl Curve for Segment {
    /// `P(t)` of the wrapped curve.
    #[inline]
    fn eval(&self, t: f64) -> Point {
        match self {
            Segment::Quadratic(c) => c.eval(t),
            Segment::Cubic(c) => c.eval(t),
            Segment::RationalQuadratic(c) => c.eval(t),
            Segment::RationalCubic(c) => c.eval(t),
        }
    }

    /// `P'(t)` of the wrapped curve.
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        match self {
            Segment::Quadratic(c) => c.deriv(t),
            Segment::Cubic(c) => c.deriv(t),
            Segment::RationalQuadratic(c) => c.deriv(t),
            Segment::RationalCubic(c) => c.deriv(t),
        }
    }

    /// `P''(t)` of the wrapped curve.
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        match self {
            Segment::Quadratic(c) => c.deriv2(t),
            Segment::Cubic(c) => c.deriv2(t),
            Segment::RationalQuadratic(c) => c.deriv2(t),
            Segment::RationalCubic(c) => c.deriv2(t),
        }
    }

    /// `P(0) = C₀` of the wrapped curve.
    #[inline]
    fn start(&self) -> Point {
        match self {
            Segment::Quadratic(c) => c.start(),
            Segment::Cubic(c) => c.start(),
            Segment::RationalQuadratic(c) => c.start(),
            Segment::RationalCubic(c) => c.start(),
        }
    }

    /// `P(1) = C_m` of the wrapped curve.
    #[inline]
    fn end(&self) -> Point {
        match self {
            Segment::Quadratic(c) => c.end(),
            Segment::Cubic(c) => c.end(),
            Segment::RationalQuadratic(c) => c.end(),
            Segment::RationalCubic(c) => c.end(),
        }
    }
}

impl SegmentEnd for Segment {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        match self {
            Segment::Quadratic(c) => c.end_leg(),
            Segment::Cubic(c) => c.end_leg(),
            Segment::RationalQuadratic(c) => c.end_leg(),
            Segment::RationalCubic(c) => c.end_leg(),
        }
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        match self {
            Segment::Quadratic(c) => c.end_derivative(),
            Segment::Cubic(c) => c.end_derivative(),
            Segment::RationalQuadratic(c) => c.end_derivative(),
            Segment::RationalCubic(c) => c.end_derivative(),
        }
    }
}

impl From<QuadBez> for Segment {
    fn from(c: QuadBez) -> Segment {
        Segment::Quadratic(c)
    }
}

impl From<CubicBez> for Segment {
    fn from(c: CubicBez) -> Segment {
        Segment::Cubic(c)
    }
}

impl From<RationalQuadBez> for Segment {
    fn from(c: RationalQuadBez) -> Segment {
        Segment::RationalQuadratic(c)
    }
}

impl From<RationalCubicBez> for Segment {
    fn from(c: RationalCubicBez) -> Segment {
        Segment::RationalCubic(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delegates_to_the_curve() {
        let p = [
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        ];
        let rc = RationalCubicBez::new(p[0], p[1], p[2], p[3], 0.5, 2.0).unwrap();
        let s = Segment::from(rc);
        assert_eq!(s.function(), FunctionType::RationalCubic);
        assert_eq!(s.control_points(), p.to_vec());
        assert_eq!(s.weights(), vec![1.0, 0.5, 2.0, 1.0]);
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert_eq!(s.eval(t), rc.eval(t));
            assert_eq!(s.deriv(t), rc.deriv(t));
        }
        // The default sse over the dispatched eval is the curve's own, bit for bit.
        let ts = [0.0, 0.3, 0.7, 1.0];
        let r = [p[0], p[1], p[2], p[3]];
        assert_eq!(s.sse(&r, &ts).to_bits(), rc.sse(&r, &ts).to_bits());
        assert_eq!(s.end_derivative(), rc.end_deriv());
        assert_eq!(s.end_leg(), (p[2], p[3]));
        let q = Segment::from(QuadBez::new(p[0], p[1], p[2]));
        assert_eq!(q.weights(), vec![1.0; 3]);
        assert_eq!(q.end(), p[2]);
    }
}
