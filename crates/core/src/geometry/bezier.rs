//! Polynomial Bézier curves of any degree, `P(t) = Σᵢ Cᵢ B_i^n(t)`
//! (Bézier 1966; Farin 2002, ch. 4–5).

use super::bernstein::bernstein;
use super::casteljau::jet;
use super::error::{check_points, GeometryError};
use super::{CubicBez, Curve, Point, QuadBez};

/// A polynomial Bézier curve of degree `n = len − 1 ≥ 0` on `t ∈ [0, 1]`,
/// `P(t) = Σᵢ Cᵢ B_i^n(t)` (Farin 2002, eq. 5.6).
///
/// Evaluation uses de Casteljau without allocation up to degree 31.
#[derive(Clone, Debug, PartialEq)]
pub struct Bezier {
    pts: Vec<Point>,
}

impl Bezier {
    /// A curve with control points `C₀..Cₙ`; fails if there are none or any
    /// coordinate is non-finite.
    pub fn new(points: Vec<Point>) -> Result<Bezier, GeometryError> {
        if points.is_empty() {
            return Err(GeometryError::Empty);
        }
        check_points(&points)?;
        Ok(Bezier { pts: points })
    }

    /// The control points `C₀..Cₙ`.
    #[inline]
    pub fn points(&self) -> &[Point] {
        &self.pts
    }

    /// The degree `n = number of control points − 1`.
    #[inline]
    pub fn degree(&self) -> usize {
        self.pts.len() - 1
    }

    /// `[P(t), P'(t), P''(t)]` in one de Casteljau pass.
    #[inline]
    pub fn jet(&self, t: f64) -> [Point; 3] {
        jet(self.pts.len(), |i| self.pts[i], t)
    }

    /// `P(t)` by the explicit Bernstein sum `Σᵢ Cᵢ B_i^n(t)`; a slower
    /// reference for [`Bezier::eval`].
    pub fn eval_bernstein(&self, t: f64) -> Point {
        let n = self.degree() as u32;
        self.pts
            .iter()
            .enumerate()
            .fold(Point::ZERO, |acc, (i, &c)| {
                acc + c * bernstein(n, i as u32, t)
            })
    }

    /// End derivative `P'(0) = n(C₁ − C₀)` (zero for degree 0).
    #[inline]
    pub fn start_deriv(&self) -> Point {
        match self.pts.as_slice() {
            [c0, c1, ..] => (*c1 - *c0) * self.degree() as f64,
            _ => Point::ZERO,
        }
    }

    /// End derivative `P'(1) = n(Cₙ − C_{n−1})` (zero for degree 0).
    #[inline]
    pub fn end_deriv(&self) -> Point {
        match self.pts.as_slice() {
            [.., a, b] => (*b - *a) * self.degree() as f64,
            _ => Point::ZERO,
        }
    }

    /// The hodograph: the degree `n−1` curve with points `n(C_{i+1} − Cᵢ)`
    /// whose value is `P'(t)` (Farin 2002, §5.3); a single zero point for degree 0.
    pub fn hodograph(&self) -> Bezier {
        let n = self.degree() as f64;
        let pts = if self.pts.len() == 1 {
            vec![Point::ZERO]
        } else {
            self.pts.windows(2).map(|w| (w[1] - w[0]) * n).collect()
        };
        Bezier { pts }
    }

    /// Degree elevation to `n+1`: `C'ᵢ = (i/(n+1)) C_{i−1} + (1 − i/(n+1)) Cᵢ`
    /// (Farin 2002, §6.1); the curve is unchanged.
    pub fn elevate(&self) -> Bezier {
        let n1 = self.pts.len() as f64; // n + 1
        let last = *self.pts.last().expect("non-empty by construction");
        let mut pts = Vec::with_capacity(self.pts.len() + 1);
        pts.push(self.pts[0]);
        for i in 1..self.pts.len() {
            let a = i as f64 / n1;
            pts.push(self.pts[i - 1] * a + self.pts[i] * (1.0 - a));
        }
        pts.push(last);
        Bezier { pts }
    }
}

impl Curve for Bezier {
    /// `P(t)` by the de Casteljau algorithm `C_i^r = (1−t)C_i^{r−1} + t C_{i+1}^{r−1}`
    /// (de Casteljau 1959; Farin 2002, §4.2), from [`Bezier::jet`].
    #[inline]
    fn eval(&self, t: f64) -> Point {
        self.jet(t)[0]
    }

    /// `P'(t) = n Σᵢ (C_{i+1} − Cᵢ) B_i^{n−1}(t)` (Farin 2002, eq. 5.18),
    /// read off the last de Casteljau level as `n(b₁ − b₀)`.
    #[inline]
    fn deriv(&self, t: f64) -> Point {
        self.jet(t)[1]
    }

    /// `P''(t) = n(n−1) Σᵢ Δ²Cᵢ B_i^{n−2}(t)` (Farin 2002, eq. 5.22), read off
    /// de Casteljau level `n−2` as `n(n−1)(c₂ − 2c₁ + c₀)`.
    #[inline]
    fn deriv2(&self, t: f64) -> Point {
        self.jet(t)[2]
    }

    /// `P(0) = C₀`.
    #[inline]
    fn start(&self) -> Point {
        self.pts[0]
    }

    /// `P(1) = Cₙ`.
    #[inline]
    fn end(&self) -> Point {
        self.pts[self.pts.len() - 1]
    }
}

impl From<QuadBez> for Bezier {
    fn from(q: QuadBez) -> Bezier {
        Bezier {
            pts: vec![q.p0, q.p1, q.p2],
        }
    }
}

impl From<CubicBez> for Bezier {
    fn from(c: CubicBez) -> Bezier {
        Bezier {
            pts: vec![c.p0, c.p1, c.p2, c.p3],
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A small deterministic generator (SplitMix64) for test data.
    pub(crate) struct TestRng(pub u64);

    impl TestRng {
        pub(crate) fn next_f64(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^= z >> 31;
            (z >> 11) as f64 / (1u64 << 53) as f64
        }
        pub(crate) fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * self.next_f64()
        }
        pub(crate) fn point(&mut self) -> Point {
            Point::new(self.range(-10.0, 10.0), self.range(-10.0, 10.0))
        }
    }

    #[test]
    fn rejects_bad_input() {
        assert_eq!(Bezier::new(vec![]), Err(GeometryError::Empty));
        assert_eq!(
            Bezier::new(vec![Point::ZERO, Point::new(f64::NAN, 0.0)]),
            Err(GeometryError::NonFinitePoint { index: 1 })
        );
    }

    #[test]
    fn de_casteljau_matches_bernstein_sum() {
        let mut rng = TestRng(1);
        for n in 1..=10 {
            let pts: Vec<Point> = (0..=n).map(|_| rng.point()).collect();
            let b = Bezier::new(pts.clone()).unwrap();
            assert_eq!(b.degree(), n);
            for k in 0..=50 {
                let t = k as f64 / 50.0;
                let d = (b.eval(t) - b.eval_bernstein(t)).hypot();
                assert!(d < 1e-12, "n={n} t={t} d={d}");
            }
            assert_eq!(b.eval(0.0), pts[0]);
            assert_eq!(b.eval(1.0), pts[n]);
        }
    }

    #[test]
    fn long_polygons_allocate_and_agree() {
        let mut rng = TestRng(2);
        let pts: Vec<Point> = (0..40).map(|_| rng.point()).collect();
        let b = Bezier::new(pts).unwrap();
        for k in 0..=10 {
            let t = k as f64 / 10.0;
            assert!((b.eval(t) - b.eval_bernstein(t)).hypot() < 1e-9);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let mut rng = TestRng(3);
        for n in 0..=8 {
            let b = Bezier::new((0..=n).map(|_| rng.point()).collect()).unwrap();
            let h = 1e-6;
            for k in 1..10 {
                let t = k as f64 / 10.0;
                let fd = (b.eval(t + h) - b.eval(t - h)) / (2.0 * h);
                assert!(
                    (b.deriv(t) - fd).hypot() < 1e-6 * (1.0 + fd.hypot()),
                    "n={n}"
                );
                let fd2 = (b.deriv(t + h) - b.deriv(t - h)) / (2.0 * h);
                assert!(
                    (b.deriv2(t) - fd2).hypot() < 1e-5 * (1.0 + fd2.hypot()),
                    "n={n}"
                );
                // The hodograph evaluates to the derivative.
                assert!((b.hodograph().eval(t) - b.deriv(t)).hypot() < 1e-10);
            }
            assert!((b.deriv(0.0) - b.start_deriv()).hypot() < 1e-10);
            assert!((b.deriv(1.0) - b.end_deriv()).hypot() < 1e-10);
        }
    }

    #[test]
    fn elevation_preserves_the_curve() {
        let mut rng = TestRng(4);
        for n in 0..=6 {
            let b = Bezier::new((0..=n).map(|_| rng.point()).collect()).unwrap();
            let e = b.elevate();
            assert_eq!(e.degree(), n + 1);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                assert!((b.eval(t) - e.eval(t)).hypot() < 1e-12);
            }
        }
    }

    #[test]
    fn tangent_normal_and_sse() {
        // The line from (0,0) to (3,0): tangent +x, normal (y', −x') = −y (right).
        let b = Bezier::new(vec![
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(3.0, 0.0),
        ])
        .unwrap();
        assert_eq!(b.unit_tangent(0.5), Some(Point::new(1.0, 0.0)));
        assert_eq!(b.unit_normal(0.5), Some(Point::new(0.0, -1.0)));
        let params = [0.0, 1.0];
        let pts = [Point::new(0.0, 1.0), Point::new(3.0, 2.0)];
        assert_eq!(b.sse(&pts, &params), 5.0);
        let mut out = [Point::ZERO; 2];
        b.eval_many(&params, &mut out);
        assert_eq!(out, [Point::ZERO, Point::new(3.0, 0.0)]);
        // A degenerate start (C0 = C1) has no tangent there.
        let d = Bezier::new(vec![Point::ZERO, Point::ZERO, Point::new(1.0, 1.0)]).unwrap();
        assert_eq!(d.unit_tangent(0.0), None);
        assert_eq!(Bezier::new(vec![Point::ZERO]).unwrap().arclen(), 0.0);
    }
}
