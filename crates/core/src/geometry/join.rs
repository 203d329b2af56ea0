//! Joining two segments with C⁰, C¹ or G¹ continuity at the common point
//! (Farin 2002, §13.6 for rational, §10.2 for polynomial curves).
//!
//! Segment 1 (the *left*, `C₀..C_m`, weights `w₀..w_m`) ends where segment 2
//! (the *right*, `C'₀..C'_{m'}`, weights `w'₀..w'_{m'}`) starts; both run on
//! `t ∈ [0, 1]`. The join fixes `C'₀` and, for C¹ and G¹, `C'₁`.

use super::error::{check_weight, GeometryError};
use super::{
    Bezier, CubicBez, Curve, Point, QuadBez, RationalBezier, RationalCubicBez, RationalQuadBez,
};

/// The continuity required where two segments meet.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Continuity {
    /// Positional continuity: `C'₀ = C_m`; `C'₁` stays free.
    C0,
    /// Parametric first-derivative continuity `Q₁'(1) = Q₂'(0)`, which fixes
    /// `C'₁ = C_m + (m w_{m−1} w'₀)/(m' w_m w'₁)(C_m − C_{m−1})` (Farin 2002, eq. 13.10).
    C1,
    /// Geometric (tangent-direction) continuity: `C'₁ = C_m + T(C_m − C_{m−1})`
    /// with a free `T > 0` (Farin 2002, §10.2 and §13.6).
    G1,
}

impl Continuity {
    /// The names accepted in experiment specs, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["c0", "c1", "g1"];

    /// Parses a spec name (`"c0"`, `"c1"` or `"g1"`, case-insensitive).
    pub fn from_name(name: &str) -> Option<Continuity> {
        match name.to_ascii_lowercase().as_str() {
            "c0" => Some(Continuity::C0),
            "c1" => Some(Continuity::C1),
            "g1" => Some(Continuity::G1),
            _ => None,
        }
    }

    /// The spec name of this continuity.
    pub fn name(self) -> &'static str {
        match self {
            Continuity::C0 => "c0",
            Continuity::C1 => "c1",
            Continuity::G1 => "g1",
        }
    }

    /// How many free scalars [`join_start`] takes: 2 for C⁰ (the coordinates
    /// of `C'₁`), 0 for C¹, 1 for G¹ (the ratio `T`).
    pub const fn free_params(self) -> usize {
        match self {
            Continuity::C0 => 2,
            Continuity::C1 => 0,
            Continuity::G1 => 1,
        }
    }
}

/// The end of a left segment, as far as a join needs it.
pub trait SegmentEnd {
    /// The last leg `(C_{m−1}, C_m)` of the control polygon (`(C₀, C₀)` for degree 0).
    fn end_leg(&self) -> (Point, Point);

    /// The end derivative `Q'(1) = m (w_{m−1}/w_m)(C_m − C_{m−1})` (Farin 2002,
    /// eq. 13.10; all `w = 1` for polynomial curves).
    fn end_derivative(&self) -> Point;
}

/// The degree and first two weights of the right segment, which the C¹
/// condition needs: `Q₂'(0) = m'(w'₁/w'₀)(C'₁ − C'₀)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RightStart {
    degree: usize,
    w0: f64,
    w1: f64,
}

impl RightStart {
    /// A right segment of degree `m' ≥ 1` with weights `w'₀, w'₁` (finite, `> 0`).
    pub fn new(degree: usize, w0: f64, w1: f64) -> Result<RightStart, GeometryError> {
        if degree == 0 {
            return Err(GeometryError::InvalidParameter {
                name: "degree",
                value: 0.0,
            });
        }
        check_weight(0, w0)?;
        check_weight(1, w1)?;
        Ok(RightStart { degree, w0, w1 })
    }

    /// A polynomial right segment of degree `m' ≥ 1` (`w'₀ = w'₁ = 1`).
    pub fn polynomial(degree: usize) -> Result<RightStart, GeometryError> {
        RightStart::new(degree, 1.0, 1.0)
    }

    /// A standard-form rational quadratic right segment with middle weight `h'₁`.
    pub fn rational_quad(h1: f64) -> Result<RightStart, GeometryError> {
        RightStart::new(2, 1.0, h1)
    }

    /// A standard-form rational cubic right segment with first inner weight `w'₁`.
    pub fn rational_cubic(w1: f64) -> Result<RightStart, GeometryError> {
        RightStart::new(3, 1.0, w1)
    }

    /// The factor `m' w'₁ / w'₀` in `Q₂'(0) = (m' w'₁/w'₀)(C'₁ − C'₀)`.
    #[inline]
    pub fn scale(self) -> f64 {
        self.degree as f64 * self.w1 / self.w0
    }
}

/// C⁰ join: `C'₀ = C_m`.
#[inline]
pub fn c0_start<L: SegmentEnd + ?Sized>(left: &L) -> Point {
    left.end_leg().1
}

/// C¹ join: `(C'₀, C'₁)` with `C'₀ = C_m` and `C'₁ = C'₀ + Q₁'(1) w'₀/(m' w'₁)`,
/// i.e. `C'₁ = C₃ + (w₂w'₀)/(w₃w'₁)(C₃ − C₂)` for two cubics (Farin 2002,
/// eq. 13.10), `2C₃ − C₂` for polynomial cubics, and
/// `C₂ + (h₁h'₀)/(h₂h'₁)(C₂ − C₁)` for two rational quadratics.
#[inline]
pub fn c1_start<L: SegmentEnd + ?Sized>(left: &L, right: RightStart) -> (Point, Point) {
    let c0 = c0_start(left);
    (c0, c0 + left.end_derivative() / right.scale())
}

/// G¹ join: `(C'₀, C'₁)` with `C'₀ = C_m` and `C'₁ = C_m + T(C_m − C_{m−1})`;
/// fails unless `T` is finite and `> 0`. A degenerate last leg gives `C'₁ = C'₀`.
pub fn g1_start<L: SegmentEnd + ?Sized>(left: &L, t: f64) -> Result<(Point, Point), GeometryError> {
    if !(t.is_finite() && t > 0.0) {
        return Err(GeometryError::InvalidParameter {
            name: "T",
            value: t,
        });
    }
    let (a, b) = left.end_leg();
    Ok((b, b + (b - a) * t))
}

/// `(C'₀, C'₁)` for the given continuity from its [`Continuity::free_params`]
/// free scalars: `[x, y]` of `C'₁` for C⁰, none for C¹, `[T]` for G¹
/// (`right` is only used by C¹). Fails on a wrong count or an invalid value.
pub fn join_start<L: SegmentEnd + ?Sized>(
    left: &L,
    continuity: Continuity,
    right: RightStart,
    free: &[f64],
) -> Result<(Point, Point), GeometryError> {
    if free.len() != continuity.free_params() {
        return Err(GeometryError::FreeParamCount {
            expected: continuity.free_params(),
            found: free.len(),
        });
    }
    match continuity {
        Continuity::C0 => {
            let p = Point::new(free[0], free[1]);
            if !p.is_finite() {
                return Err(GeometryError::NonFinitePoint { index: 1 });
            }
            Ok((c0_start(left), p))
        }
        Continuity::C1 => Ok(c1_start(left, right)),
        Continuity::G1 => g1_start(left, free[0]),
    }
}

/// Whether `left` and `right` meet with the given continuity, to relative
/// tolerance `tol`: `|Q₁(1) − Q₂(0)|`, `|Q₁'(1) − Q₂'(0)|` (C¹) or the sine of
/// the angle between the end tangents (G¹, which also needs a positive dot
/// product) must be at most `tol` times the larger magnitude (or 1).
pub fn check_join<L: Curve + ?Sized, R: Curve + ?Sized>(
    left: &L,
    right: &R,
    continuity: Continuity,
    tol: f64,
) -> bool {
    let (a, b) = (left.end(), right.start());
    if a.distance(b) > tol * a.hypot().max(b.hypot()).max(1.0) {
        return false;
    }
    let (d1, d2) = (left.deriv(1.0), right.deriv(0.0));
    match continuity {
        Continuity::C0 => true,
        Continuity::C1 => (d1 - d2).hypot() <= tol * d1.hypot().max(d2.hypot()).max(1.0),
        Continuity::G1 => {
            let (l1, l2) = (d1.hypot(), d2.hypot());
            l1 > 0.0 && l2 > 0.0 && d1.dot(d2) > 0.0 && d1.cross(d2).abs() <= tol * l1 * l2
        }
    }
}

impl SegmentEnd for QuadBez {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        (self.p1, self.p2)
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

impl SegmentEnd for CubicBez {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        (self.p2, self.p3)
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

impl SegmentEnd for RationalQuadBez {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        let [_, p1, p2] = self.points();
        (p1, p2)
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

impl SegmentEnd for RationalCubicBez {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        let [_, _, p2, p3] = self.points();
        (p2, p3)
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

impl SegmentEnd for Bezier {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        match self.points() {
            [.., a, b] => (*a, *b),
            [a] => (*a, *a),
            [] => (Point::ZERO, Point::ZERO),
        }
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

impl SegmentEnd for RationalBezier {
    #[inline]
    fn end_leg(&self) -> (Point, Point) {
        match self.points() {
            [.., a, b] => (*a, *b),
            [a] => (*a, *a),
            [] => (Point::ZERO, Point::ZERO),
        }
    }
    #[inline]
    fn end_derivative(&self) -> Point {
        self.end_deriv()
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::*;

    fn rel_close(a: Point, b: Point, tol: f64) -> bool {
        (a - b).hypot() <= tol * a.hypot().max(b.hypot())
    }

    /// Asserts C¹ numerically: equal points and equal derivatives to 1e-9 relative.
    fn assert_c1<L: Curve, R: Curve>(l: &L, r: &R) {
        assert!(rel_close(l.end(), r.start(), 1e-12));
        let (a, b) = (l.deriv(1.0), r.deriv(0.0));
        assert!(rel_close(a, b, 1e-9), "left {a:?} right {b:?}");
        assert!(check_join(l, r, Continuity::C1, 1e-9));
    }

    /// Asserts G¹ numerically: parallel, same-direction end tangents.
    fn assert_g1<L: Curve, R: Curve>(l: &L, r: &R) {
        assert!(rel_close(l.end(), r.start(), 1e-12));
        let (a, b) = (l.deriv(1.0), r.deriv(0.0));
        assert!(
            a.cross(b).abs() <= 1e-9 * a.hypot() * b.hypot(),
            "left {a:?} right {b:?}"
        );
        assert!(a.dot(b) > 0.0);
        assert!(check_join(l, r, Continuity::G1, 1e-9));
    }

    #[test]
    fn names_and_counts() {
        for (i, n) in Continuity::NAMES.iter().enumerate() {
            let c = Continuity::from_name(n).unwrap();
            assert_eq!(c.name(), *n);
            assert_eq!(c.free_params(), [2, 0, 1][i]);
        }
        assert_eq!(Continuity::from_name("G1"), Some(Continuity::G1));
        assert_eq!(Continuity::from_name("c2"), None);
    }

    #[test]
    fn rejects_bad_free_parameters() {
        let l = CubicBez::new(
            Point::ZERO,
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
        );
        let r = RightStart::polynomial(3).unwrap();
        assert!(RightStart::polynomial(0).is_err());
        assert!(RightStart::rational_cubic(0.0).is_err());
        assert!(RightStart::new(3, f64::NAN, 1.0).is_err());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(g1_start(&l, bad).is_err());
            assert!(join_start(&l, Continuity::G1, r, &[bad]).is_err());
        }
        assert_eq!(
            join_start(&l, Continuity::C1, r, &[1.0]),
            Err(GeometryError::FreeParamCount {
                expected: 0,
                found: 1
            })
        );
        assert!(join_start(&l, Continuity::C0, r, &[1.0]).is_err());
        assert!(join_start(&l, Continuity::C0, r, &[1.0, f64::NAN]).is_err());
        let (a, b) = join_start(&l, Continuity::C0, r, &[5.0, 6.0]).unwrap();
        assert_eq!((a, b), (Point::new(2.0, 0.0), Point::new(5.0, 6.0)));
    }

    #[test]
    fn closed_forms() {
        let mut rng = TestRng(60);
        // Polynomial cubic: C'₁ = 2C₃ − C₂.
        let l = CubicBez::new(rng.point(), rng.point(), rng.point(), rng.point());
        let (c0, c1) = c1_start(&l, RightStart::polynomial(3).unwrap());
        assert_eq!(c0, l.p3);
        assert!((c1 - (l.p3 * 2.0 - l.p2)).hypot() < 1e-12);
        // General rational cubics: C'₁ = C₃ + (w₂w'₀)/(w₃w'₁)(C₃ − C₂).
        let w: Vec<f64> = (0..4).map(|_| rng.range(0.2, 4.0)).collect();
        let pts: Vec<Point> = (0..4).map(|_| rng.point()).collect();
        let l = RationalBezier::new(pts.clone(), w.clone()).unwrap();
        let (rw0, rw1) = (rng.range(0.2, 4.0), rng.range(0.2, 4.0));
        let (_, c1) = c1_start(&l, RightStart::new(3, rw0, rw1).unwrap());
        let expect = pts[3] + (pts[3] - pts[2]) * (w[2] * rw0 / (w[3] * rw1));
        assert!((c1 - expect).hypot() < 1e-12 * (1.0 + expect.hypot()));
        // Rational quadratics in standard form: C'₁ = C₂ + (h₁h'₀)/(h₂h'₁)(C₂ − C₁).
        let q = RationalQuadBez::new(rng.point(), rng.point(), rng.point(), 0.7).unwrap();
        let [_, q1, q2] = q.points();
        let (_, c1) = c1_start(&q, RightStart::rational_quad(1.4).unwrap());
        let expect = q2 + (q2 - q1) * (0.7 / 1.4);
        assert!((c1 - expect).hypot() < 1e-12 * (1.0 + expect.hypot()));
        // G¹: C'₁ = C₃ + T(C₃ − C₂).
        let l = CubicBez::new(rng.point(), rng.point(), rng.point(), rng.point());
        let (_, g) = g1_start(&l, 0.3).unwrap();
        assert!((g - (l.p3 + (l.p3 - l.p2) * 0.3)).hypot() < 1e-12);
    }

    #[test]
    fn c1_and_g1_for_all_curve_types() {
        let mut rng = TestRng(61);
        for _ in 0..50 {
            let t = rng.range(0.05, 5.0);

            // Polynomial quadratic.
            let l = QuadBez::new(rng.point(), rng.point(), rng.point());
            let (a, b) = c1_start(&l, RightStart::polynomial(2).unwrap());
            assert_c1(&l, &QuadBez::new(a, b, rng.point()));
            let (a, b) = g1_start(&l, t).unwrap();
            assert_g1(&l, &QuadBez::new(a, b, rng.point()));

            // Polynomial cubic.
            let l = CubicBez::new(rng.point(), rng.point(), rng.point(), rng.point());
            let (a, b) = c1_start(&l, RightStart::polynomial(3).unwrap());
            assert_c1(&l, &CubicBez::new(a, b, rng.point(), rng.point()));
            let (a, b) = g1_start(&l, t).unwrap();
            assert_g1(&l, &CubicBez::new(a, b, rng.point(), rng.point()));

            // Rational quadratic with random weights.
            let l =
                RationalQuadBez::new(rng.point(), rng.point(), rng.point(), rng.range(0.1, 5.0))
                    .unwrap();
            let h = rng.range(0.1, 5.0);
            let (a, b) = c1_start(&l, RightStart::rational_quad(h).unwrap());
            assert_c1(&l, &RationalQuadBez::new(a, b, rng.point(), h).unwrap());
            let (a, b) = g1_start(&l, t).unwrap();
            assert_g1(&l, &RationalQuadBez::new(a, b, rng.point(), h).unwrap());

            // Rational cubic with random weights.
            let l = RationalCubicBez::new(
                rng.point(),
                rng.point(),
                rng.point(),
                rng.point(),
                rng.range(0.1, 5.0),
                rng.range(0.1, 5.0),
            )
            .unwrap();
            let (w1, w2) = (rng.range(0.1, 5.0), rng.range(0.1, 5.0));
            let (a, b) = c1_start(&l, RightStart::rational_cubic(w1).unwrap());
            assert_c1(
                &l,
                &RationalCubicBez::new(a, b, rng.point(), rng.point(), w1, w2).unwrap(),
            );
            let (a, b) = g1_start(&l, t).unwrap();
            assert_g1(
                &l,
                &RationalCubicBez::new(a, b, rng.point(), rng.point(), w1, w2).unwrap(),
            );

            // General rationals, non-standard weights, mixed degrees (4 then 2).
            let lw: Vec<f64> = (0..5).map(|_| rng.range(0.1, 5.0)).collect();
            let l = RationalBezier::new((0..5).map(|_| rng.point()).collect(), lw).unwrap();
            let rw = vec![
                rng.range(0.1, 5.0),
                rng.range(0.1, 5.0),
                rng.range(0.1, 5.0),
            ];
            let (a, b) = c1_start(&l, RightStart::new(2, rw[0], rw[1]).unwrap());
            assert_c1(
                &l,
                &RationalBezier::new(vec![a, b, rng.point()], rw.clone()).unwrap(),
            );
            let (a, b) = g1_start(&l, t).unwrap();
            assert_g1(
                &l,
                &RationalBezier::new(vec![a, b, rng.point()], rw).unwrap(),
            );

            // General polynomial of degree 5 into a cubic, through join_start.
            let l = Bezier::new((0..6).map(|_| rng.point()).collect()).unwrap();
            let (a, b) =
                join_start(&l, Continuity::C1, RightStart::polynomial(3).unwrap(), &[]).unwrap();
            assert_c1(&l, &CubicBez::new(a, b, rng.point(), rng.point()));
        }
    }

    #[test]
    fn c0_only_is_not_c1() {
        let l = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 1.0),
            Point::new(2.0, 1.0),
            Point::new(3.0, 0.0),
        );
        let r = CubicBez::new(
            l.p3,
            Point::new(3.0, 5.0),
            Point::new(4.0, 1.0),
            Point::new(5.0, 0.0),
        );
        assert!(check_join(&l, &r, Continuity::C0, 1e-12));
        assert!(!check_join(&l, &r, Continuity::C1, 1e-6));
        assert!(!check_join(&l, &r, Continuity::G1, 1e-6));
        // Opposite tangents are parallel but not G¹.
        let (a, b) = (l.p3, l.p3 - (l.p3 - l.p2));
        let back = CubicBez::new(a, b, Point::new(0.0, 3.0), Point::new(0.0, 4.0));
        assert!(!check_join(&l, &back, Continuity::G1, 1e-6));
    }
}
