//! A 2D point, also used as a displacement vector.

use std::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A point or vector `(x, y)` in the plane, in a y-up frame.
///
/// One `Copy` type serves as both point and vector (affine combinations are
/// the caller's responsibility), as in Farin (2002), ch. 2.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Point {
    /// The x coordinate.
    pub x: f64,
    /// The y coordinate.
    pub y: f64,
}

impl Point {
    /// The origin / zero vector `(0, 0)`.
    pub const ZERO: Point = Point::new(0.0, 0.0);

    /// The point `(x, y)`.
    #[inline]
    pub const fn new(x: f64, y: f64) -> Point {
        Point { x, y }
    }

    /// Dot product `a·b = a_x b_x + a_y b_y`.
    #[inline]
    pub fn dot(self, other: Point) -> f64 {
        self.x * other.x + self.y * other.y
    }

    /// 2D cross product (z of the 3D cross) `a×b = a_x b_y − a_y b_x`;
    /// positive when `b` is counter-clockwise from `a`.
    #[inline]
    pub fn cross(self, other: Point) -> f64 {
        self.x * other.y - self.y * other.x
    }

    /// Euclidean length `|v| = √(x² + y²)` (computed with `hypot`, no overflow).
    #[inline]
    pub fn hypot(self) -> f64 {
        self.x.hypot(self.y)
    }

    /// Squared length `|v|² = x² + y²`.
    #[inline]
    pub fn hypot2(self) -> f64 {
        self.dot(self)
    }

    /// Euclidean distance `|a − b|`.
    #[inline]
    pub fn distance(self, other: Point) -> f64 {
        (self - other).hypot()
    }

    /// Squared distance `|a − b|²`.
    #[inline]
    pub fn distance_squared(self, other: Point) -> f64 {
        (self - other).hypot2()
    }

    /// Linear interpolation `(1 − t)a + t b` (the de Casteljau step; exact at
    /// `t = 0` and `t = 1`).
    #[inline]
    pub fn lerp(self, other: Point, t: f64) -> Point {
        self * (1.0 - t) + other * t
    }

    /// The vector rotated by +90°, `(−y, x)`.
    #[inline]
    pub fn perp(self) -> Point {
        Point::new(-self.y, self.x)
    }

    /// The unit vector `v/|v|`, or `None` if `|v|` is zero or not finite.
    #[inline]
    pub fn normalize(self) -> Option<Point> {
        let len = self.hypot();
        if len > 0.0 && len.is_finite() {
            Some(self / len)
        } else {
            None
        }
    }

    /// Whether both coordinates are finite (neither NaN nor infinite).
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl From<(f64, f64)> for Point {
    #[inline]
    fn from((x, y): (f64, f64)) -> Point {
        Point::new(x, y)
    }
}

impl From<[f64; 2]> for Point {
    #[inline]
    fn from([x, y]: [f64; 2]) -> Point {
        Point::new(x, y)
    }
}

impl Add for Point {
    type Output = Point;
    #[inline]
    fn add(self, o: Point) -> Point {
        Point::new(self.x + o.x, self.y + o.y)
    }
}

impl Sub for Point {
    type Output = Point;
    #[inline]
    fn sub(self, o: Point) -> Point {
        Point::new(self.x - o.x, self.y - o.y)
    }
}

impl Neg for Point {
    type Output = Point;
    #[inline]
    fn neg(self) -> Point {
        Point::new(-self.x, -self.y)
    }
}

impl Mul<f64> for Point {
    type Output = Point;
    #[inline]
    fn mul(self, s: f64) -> Point {
        Point::new(self.x * s, self.y * s)
    }
}

impl Mul<Point> for f64 {
    type Output = Point;
    #[inline]
    fn mul(self, p: Point) -> Point {
        p * self
    }
}

impl Div<f64> for Point {
    type Output = Point;
    #[inline]
    fn div(self, s: f64) -> Point {
        Point::new(self.x / s, self.y / s)
    }
}

impl AddAssign for Point {
    #[inline]
    fn add_assign(&mut self, o: Point) {
        *self = *self + o;
    }
}

impl SubAssign for Point {
    #[inline]
    fn sub_assign(&mut self, o: Point) {
        *self = *self - o;
    }
}

impl MulAssign<f64> for Point {
    #[inline]
    fn mul_assign(&mut self, s: f64) {
        *self = *self * s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arithmetic() {
        let a = Point::new(1.0, 2.0);
        let b = Point::new(3.0, -1.0);
        assert_eq!(a + b, Point::new(4.0, 1.0));
        assert_eq!(a - b, Point::new(-2.0, 3.0));
        assert_eq!(-a, Point::new(-1.0, -2.0));
        assert_eq!(a * 2.0, Point::new(2.0, 4.0));
        assert_eq!(2.0 * a, a * 2.0);
        assert_eq!(b / 2.0, Point::new(1.5, -0.5));
        let mut c = a;
        c += b;
        c -= a;
        c *= 3.0;
        assert_eq!(c, Point::new(9.0, -3.0));
        assert_eq!(Point::from((1.0, 2.0)), a);
        assert_eq!(Point::from([1.0, 2.0]), a);
    }

    #[test]
    fn products_and_lengths() {
        let a = Point::new(3.0, 4.0);
        let b = Point::new(-4.0, 3.0);
        assert_eq!(a.dot(b), 0.0);
        assert_eq!(a.cross(b), 25.0);
        assert_eq!(b.cross(a), -25.0);
        assert_eq!(a.hypot(), 5.0);
        assert_eq!(a.hypot2(), 25.0);
        assert_eq!(a.distance(Point::ZERO), 5.0);
        assert_eq!(a.distance_squared(b), 49.0 + 1.0);
        assert_eq!(a.perp(), b);
        assert_eq!(a.normalize(), Some(Point::new(0.6, 0.8)));
        assert_eq!(Point::ZERO.normalize(), None);
        assert_eq!(Point::new(f64::NAN, 0.0).normalize(), None);
        assert!(!Point::new(f64::INFINITY, 0.0).is_finite());
    }

    #[test]
    fn lerp_is_exact_at_ends() {
        let a = Point::new(0.1, 0.7);
        let b = Point::new(0.3, -0.2);
        assert_eq!(a.lerp(b, 0.0), a);
        assert_eq!(a.lerp(b, 1.0), b);
        let m = a.lerp(b, 0.5);
        assert!((m - Point::new(0.2, 0.25)).hypot() < 1e-15);
    }
}
