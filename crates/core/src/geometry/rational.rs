//! Rational Bézier curves of any degree,
//! `Q(t) = Σᵢ wᵢ Cᵢ B_i^m(t) / Σᵢ wᵢ B_i^m(t)` (Farin 2002, §13.1).

use super::bernstein::bernstein;
use super::casteljau::{jet, project_jet, Hom};
use super::error::{check_points, check_weight, GeometryError};
use super::{Bezier, Curve, Point, RationalCubicBez, RationalQuadBez};

/// A rational Bézier curve of degree `m = len − 1` with control points `Cᵢ`
/// and weights `wᵢ > 0`: `Q(t) = Σ wᵢ Cᵢ B_i^m(t) / Σ wᵢ B_i^m(t)` (Farin 2002, eq. 13.2).
///
/// Evaluated by de Casteljau on the homogeneous points `(wᵢCᵢ, wᵢ)` followed by
/// projection, without allocation up to degree 31.
#[derive(Clone, Debug, PartialEq)]
pub struct RationalBezier {
    pts: Vec<Point>,
    weights: Vec<f64>,
}

impl RationalBezier {
    /// A curve with control points `C₀..C_m` and weights `w₀..w_m`; fails if
    /// there are no points, the lengths differ, a point is non-finite, or a
    /// weight is not finite and `> 0`.
    pub fn new(points: Vec<Point>, weights: Vec<f64>) -> Result<RationalBezier, GeometryError> {
        if points.is_empty() {
            return Err(GeometryError::Empty);
        }
        if points.len() != weights.len() {
            return Err(GeometryError::LengthMismatch {
                points: points.len(),
                weights: weights.len(),
            });
        }
        check_points(&points)?;
        for (i, &w) in weights.iter().enumerate() {
            check_weight(i, w)?;
        }
        Ok(RationalBezier {
            pts: points,
            weights,
        })
    }

    /// The polynomial curve `P` as a rational one with all weights 1.
    pub fn from_polynomial(curve: &Bezier) -> RationalBezier {
        RationalBezier {
            pts: curve.points().to_vec(),
            weights: vec![1.0; curve.points().len()],
        }
    }

    /// The control points `C₀..C_m`.
    #[inline]
    pub fn points(&self) -> &[Point] {
        &self.pts
    }

    /// The weights `w₀..w_m`.
    #[inline]
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The degree `m = number of control points − 1`.
    #[inline]
    pub fn degree(&self) -> usize {
        self.pts.len() - 1
    }

    /// `[Q(t), Q'(t), Q''(t)]`: de Casteljau on `(wᵢCᵢ, wᵢ)` then the quotient
    /// rule `Q' = (A' − W'Q)/W`, `Q'' = (A'' − 2W'Q' − W''Q)/W` (Farin 2002, §13.4).
    #[inline]
    pub fn jet(&self, t: f64) -> [Point; 3] {
        project_jet(jet(
            self.pts.len(),
            |i| Hom::lift(self.pts[i], self.weights[i]),
            t,
        ))
    }

    /// `Q(t)` by the explicit sums `Σ wᵢCᵢB_i^m(t) / Σ wᵢB_i^m(t)`; a slower
    /// reference for [`RationalBezier::eval`].
    pub fn eval_bernstein(&self, t: f64) -> Point {
        let m = self.degree() as u32;
        let (mut a, mut w) = (Point::ZERO, 0.0);
        for (i, (&c, &wi)) in self.pts.iter().zip(&self.weights).enumerate() {
            let b = wi * bernstein(m, i as u32, t);
            a += c * b;
            w += b;
        }
        a / w
    }

    /// End derivative `Q'(0) = m (w₁/w₀)(C₁ − C₀)` (Farin 2002, eq. 13.10);
    /// zero for degree 0.
    #[inline]
    pub fn start_deriv(&self) -> Point {
        match (self.pts.as_slice(), self.weights.as_slice()) {
            ([c0, c1, ..], [w0, w1, ..]) => (*c1 - *c0) * (self.degree() as f64 * w1 / w0),
            _ => Point::ZERO,
        }
    }

    /// End derivative `Q'(1) = m (w_{m−1}/w_m)(C_m − C_{m−1})` (Farin 2002,
    /// eq. 13.10); zero for degree 0.
    #[inline]
    pub fn end_deriv(&self) -> Point {
        match (self.pts.as_slice(), self.weights.as_slice()) {
            ([.., a, b], [.., wa, wb]) => (*b - *a) * (self.degree() as f64 * wa / wb),
            _ => Point::ZERO,
        }
    }

    /// The same curve in standard form (`w₀ = w_m = 1`) by the rational linear
    /// reparametrisation `wᵢ ← wᵢ cⁱ / w₀` with `c = (w₀/w_m)^{1/m}` (Farin 2002,
    /// §13.3); the new curve at `t` equals the old one at `ct / ((1−t) + ct)`.
    pub fn to_standard_form(&self) -> RationalBezier {
        let m = self.degree();
        if m == 0 {
            return RationalBezier {
                pts: self.pts.clone(),
                weights: vec![1.0],
            };
        }
        let w0 = self.weights[0];
        let c = (w0 / self.weights[m]).powf(1.0 / m as f64);
        let mut weights: Vec<f64> = self
            .weights
            .iter()
            .enumerate()
            .map(|(i, &w)| w * c.powi(i as i32) / w0)
            .collect();
        weights[0] = 1.0;
        weights[m] = 1.0;
        RationalBezier {
            pts: self.pts.clone(),
            weights,
        }
    }
}

impl Curve for RationalBezier {
    /// `Q(t) = A(t)/W(t)` by the rational de Casteljau algorithm on the
    /// homogeneous points `(wᵢCᵢ, wᵢ)` (Farin 2002, §13.2), from
    /// [`RationalBezier::jet`].
    #[inline]
    fn eval(&self, t: f64) -> Point {
        self.jet(t)[0]
    }

    /// `Q'(t) = (A'(t) − W'(t) Q(t)) / W(t)` with `A = Σ wᵢCᵢBᵢ`, `W = Σ wᵢBᵢ`
    /// (quotient rule; Farin 2002, §13.4), from [`RationalBezier::jet`].
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        self.jet(t)[1]
    }

    /// `Q''(t) = (A'' − 2W'Q' − W''Q) / W` (Farin 2002, §13.4), from
    /// [`RationalBezier::jet`].
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        self.jet(t)[2]
    }

    /// `Q(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.pts[0]
    }

    /// `Q(1) = C_m`.
    #[inline]
    fn end(&self) -> Point {
        self.pts[self.pts.len() - 1]
    }
}

impl From<&Bezier> for RationalBezier {
    fn from(b: &Bezier) -> RationalBezier {
        RationalBezier::from_polynomial(b)
    }
}

impl From<RationalQuadBez> for RationalBezier {
    fn from(q: RationalQuadBez) -> RationalBezier {
        RationalBezier {
            pts: q.points().to_vec(),
            weights: q.weights().to_vec(),
        }
    }
}

impl From<RationalCubicBez> for RationalBezier {
    fn from(c: RationalCubicBez) -> RationalBezier {
        RationalBezier {
            pts: c.points().to_vec(),
            weights: c.weights().to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::*;

    fn random(rng: &mut TestRng, m: usize) -> RationalBezier {
        let pts = (0..=m).map(|_| rng.point()).collect();
        let w = (0..=m).map(|_| rng.range(0.2, 5.0)).collect();
        RationalBezier::new(pts, w).unwrap()
    }

    #[test]
    fn rejects_bad_input() {
        let p = vec![Point::ZERO, Point::new(1.0, 0.0)];
        assert_eq!(
            RationalBezier::new(vec![], vec![]),
            Err(GeometryError::Empty)
        );
        assert_eq!(
            RationalBezier::new(p.clone(), vec![1.0]),
            Err(GeometryError::LengthMismatch {
                points: 2,
                weights: 1
            })
        );
        assert_eq!(
            RationalBezier::new(p.clone(), vec![1.0, 0.0]),
            Err(GeometryError::InvalidWeight {
                index: 1,
                value: 0.0
            })
        );
        assert!(RationalBezier::new(p.clone(), vec![-1.0, 1.0]).is_err());
        assert!(RationalBezier::new(p.clone(), vec![1.0, f64::NAN]).is_err());
        assert!(RationalBezier::new(p.clone(), vec![f64::INFINITY, 1.0]).is_err());
        let bad = vec![Point::ZERO, Point::new(0.0, f64::INFINITY)];
        assert_eq!(
            RationalBezier::new(bad, vec![1.0, 1.0]),
            Err(GeometryError::NonFinitePoint { index: 1 })
        );
        assert!(RationalBezier::new(p, vec![1.0, 2.0]).is_ok());
    }

    #[test]
    fn unit_weights_give_the_polynomial() {
        let mut rng = TestRng(30);
        for n in 0..=10 {
            let b = Bezier::new((0..=n).map(|_| rng.point()).collect()).unwrap();
            let r = RationalBezier::from(&b);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((r.eval(t) - b.eval(t)).hypot() < 1e-12, "n={n}");
                assert!((r.deriv(t) - b.deriv(t)).hypot() < 1e-10, "n={n}");
                assert!((r.deriv2(t) - b.deriv2(t)).hypot() < 1e-8, "n={n}");
            }
        }
    }

    #[test]
    fn de_casteljau_matches_explicit_sum() {
        let mut rng = TestRng(31);
        for m in 1..=10 {
            let r = random(&mut rng, m);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((r.eval(t) - r.eval_bernstein(t)).hypot() < 1e-11, "m={m}");
            }
            assert!((r.eval(0.0) - r.points()[0]).hypot() < 1e-13);
            assert!((r.eval(1.0) - r.points()[m]).hypot() < 1e-13);
            assert_eq!(r.start(), r.points()[0]);
            assert_eq!(r.end(), r.points()[m]);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let mut rng = TestRng(32);
        let h = 1e-6;
        for m in 1..=7 {
            let r = random(&mut rng, m);
            for k in 1..10 {
                let t = k as f64 / 10.0;
                let fd = (r.eval(t + h) - r.eval(t - h)) / (2.0 * h);
                assert!(
                    (r.deriv(t) - fd).hypot() < 1e-6 * (1.0 + fd.hypot()),
                    "m={m}"
                );
                let fd2 = (r.deriv(t + h) - r.deriv(t - h)) / (2.0 * h);
                assert!(
                    (r.deriv2(t) - fd2).hypot() < 1e-5 * (1.0 + fd2.hypot()),
                    "m={m}"
                );
            }
            // One-sided second-order differences at the ends.
            let fd0 = (r.eval(0.0) * -3.0 + r.eval(h) * 4.0 - r.eval(2.0 * h)) / (2.0 * h);
            let fd1 =
                (r.eval(1.0) * 3.0 - r.eval(1.0 - h) * 4.0 + r.eval(1.0 - 2.0 * h)) / (2.0 * h);
            let s = r.start_deriv();
            let e = r.end_deriv();
            assert!((s - fd0).hypot() < 1e-5 * (1.0 + s.hypot()), "m={m}");
            assert!((e - fd1).hypot() < 1e-5 * (1.0 + e.hypot()), "m={m}");
            assert!((s - r.deriv(0.0)).hypot() < 1e-10 * (1.0 + s.hypot()));
            assert!((e - r.deriv(1.0)).hypot() < 1e-10 * (1.0 + e.hypot()));
        }
    }

    #[test]
    fn standard_form_is_a_reparametrisation() {
        let mut rng = TestRng(33);
        for m in 1..=6 {
            let r = random(&mut rng, m);
            let s = r.to_standard_form();
            assert_eq!(s.weights()[0], 1.0);
            assert_eq!(s.weights()[m], 1.0);
            let w = r.weights();
            let c = (w[0] / w[m]).powf(1.0 / m as f64);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let u = c * t / ((1.0 - t) + c * t);
                assert!((s.eval(t) - r.eval(u)).hypot() < 1e-11, "m={m} t={t}");
            }
        }
    }
}
