//! Offset curves `PO(u) = C(u) + Dis(u)·N(u)` sampled at given parameters
//! (Tiller & Hanson 1984, "Offsets of two-dimensional profiles", *IEEE CG&A*
//! 4(9); Farin 2002, §11.9).
//!
//! Sign convention: `N = (y', −x')/|C'|` as in [`Curve::unit_normal`], which
//! points to the right of the direction of travel (y-up frame), so a positive
//! `Dis` offsets to the right — outward on a counter-clockwise circle (radius
//! `r + d`) and inward on a clockwise one (`r − d`).

use super::{Curve, Point};

/// A distance that varies linearly along the curve,
/// `Dis(u) = (1 − u) d₀ + u d₁`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearDistance {
    /// The distance `d₀` at `u = 0`.
    pub d0: f64,
    /// The distance `d₁` at `u = 1`.
    pub d1: f64,
}

impl LinearDistance {
    /// The distance ramp from `d₀` at `u = 0` to `d₁` at `u = 1`.
    #[inline]
    pub const fn new(d0: f64, d1: f64) -> LinearDistance {
        LinearDistance { d0, d1 }
    }

    /// A constant distance `Dis(u) = d`.
    #[inline]
    pub const fn constant(d: f64) -> LinearDistance {
        LinearDistance { d0: d, d1: d }
    }

    /// `Dis(u) = (1 − u) d₀ + u d₁`.
    #[inline]
    pub fn at(self, u: f64) -> f64 {
        (1.0 - u) * self.d0 + u * self.d1
    }
}

/// The unit normal at `u`; where `C'(u) = 0` it falls back to the normal a
/// hair (10⁻⁷) towards the interior, the limiting direction at a degenerate
/// end, and to `None` if that is also undefined.
#[inline]
fn normal_or_limit<C: Curve + ?Sized>(curve: &C, u: f64) -> Option<Point> {
    curve.unit_normal(u).or_else(|| {
        let h = if u < 0.5 { 1e-7 } else { -1e-7 };
        curve.unit_normal(u + h)
    })
}

/// One offset point `PO(u) = C(u) + d·N(u)` (Tiller & Hanson 1984); `C(u)`
/// itself where the normal is undefined (see the module docs for the sign).
#[inline]
pub fn offset_point<C: Curve + ?Sized>(curve: &C, u: f64, d: f64) -> Point {
    let c = curve.eval(u);
    match normal_or_limit(curve, u) {
        Some(n) => c + n * d,
        None => c,
    }
}

/// Writes `PO(uᵢ) = C(uᵢ) + Dis(uᵢ)·N(uᵢ)` into `out[i]` for the pairs of `us`
/// and `out` (the shorter decides), without allocation.
pub fn offset_into<C, D>(curve: &C, us: &[f64], dis: D, out: &mut [Point])
where
    C: Curve + ?Sized,
    D: Fn(f64) -> f64,
{
    for (o, &u) in out.iter_mut().zip(us) {
        *o = offset_point(curve, u, dis(u));
    }
}

/// `PO(uᵢ) = C(uᵢ) + Dis(uᵢ)·N(uᵢ)` for every `uᵢ` in `us`.
pub fn offset_points<C, D>(curve: &C, us: &[f64], dis: D) -> Vec<Point>
where
    C: Curve + ?Sized,
    D: Fn(f64) -> f64,
{
    let mut out = vec![Point::ZERO; us.len()];
    offset_into(curve, us, dis, &mut out);
    out
}

/// `PO(uᵢ)` with the linear distance `Dis(u) = (1 − u) d₀ + u d₁`.
pub fn offset_linear<C: Curve + ?Sized>(curve: &C, us: &[f64], dis: LinearDistance) -> Vec<Point> {
    offset_points(curve, us, |u| dis.at(u))
}

#[cfg(test)]
mod tests {
    use super::super::{CubicBez, QuadBez, RationalQuadBez};
    use super::*;

    fn us() -> Vec<f64> {
        (0..=50).map(|k| k as f64 / 50.0).collect()
    }

    #[test]
    fn circle_offsets_are_circles() {
        let centre = Point::new(1.0, -2.0);
        let r = 3.0;
        // Counter-clockwise arc: N points outward, radius r + d.
        let ccw = RationalQuadBez::circular_arc(centre, r, 0.3, 2.0).unwrap();
        for d in [0.5, -0.5, 1.25] {
            for p in offset_linear(&ccw, &us(), LinearDistance::constant(d)) {
                assert!((p.distance(centre) - (r + d)).abs() < 1e-12, "d={d}");
            }
        }
        // Clockwise arc: N points inward, radius r − d.
        let cw = RationalQuadBez::circular_arc(centre, r, 0.3, -2.0).unwrap();
        for p in offset_points(&cw, &us(), |_| 0.5) {
            assert!((p.distance(centre) - (r - 0.5)).abs() < 1e-12);
        }
    }

    #[test]
    fn linear_distance_ramps() {
        let d = LinearDistance::new(1.0, 3.0);
        assert_eq!(d.at(0.0), 1.0);
        assert_eq!(d.at(1.0), 3.0);
        assert_eq!(d.at(0.5), 2.0);
        let centre = Point::ZERO;
        let arc = RationalQuadBez::circular_arc(centre, 2.0, 0.0, 1.5).unwrap();
        let u = us();
        let pts = offset_linear(&arc, &u, d);
        for (&ui, p) in u.iter().zip(&pts) {
            assert!((p.distance(centre) - (2.0 + d.at(ui))).abs() < 1e-12);
        }
        let mut out = vec![Point::ZERO; 3];
        offset_into(&arc, &u[..3], |u| d.at(u), &mut out);
        assert_eq!(out[..], pts[..3]);
    }

    #[test]
    fn line_offset_is_to_the_right() {
        let line = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, 0.0),
        );
        let p = offset_point(&line, 0.5, 2.0);
        assert!((p - Point::new(1.5, -2.0)).hypot() < 1e-15);
    }

    #[test]
    fn degenerate_end_uses_limit_normal() {
        // C₀ = C₁: C'(0) = 0 but the curve leaves along +x.
        let q = QuadBez::new(Point::ZERO, Point::ZERO, Point::new(2.0, 0.0));
        let p = offset_point(&q, 0.0, 1.0);
        assert!((p - Point::new(0.0, -1.0)).hypot() < 1e-9);
        // A single repeated point has no normal: the offset is the point itself.
        let dot = QuadBez::new(Point::ZERO, Point::ZERO, Point::ZERO);
        assert_eq!(offset_point(&dot, 0.5, 1.0), Point::ZERO);
    }
}
