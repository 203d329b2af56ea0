//! The orthogonal (closest-point) distance from a point to a curve segment,
//! found where `g(t) = (Q(t) − p)·Q'(t) = 0` or at an endpoint (Piegl &
//! Tiller, *The NURBS Book*, §6.1 "point inversion").

use super::{Curve, Point};

/// Samples used by [`nearest`] to bracket the roots of `g(t)`.
pub const DEFAULT_SAMPLES: usize = 64;

/// The closest point of `curve` to `p`, as `(t, distance)`; see [`nearest_with`].
#[inline]
pub fn nearest<C: Curve + ?Sized>(curve: &C, p: Point) -> (f64, f64) {
    nearest_with(curve, p, DEFAULT_SAMPLES)
}

/// The closest point of `curve` to `p` on `t ∈ [0, 1]`, as `(t, |Q(t) − p|)`.
///
/// Samples `g(t) = (Q(t) − p)·Q'(t)`, half the derivative of `|Q − p|²`, at
/// `samples + 1` equally spaced `t` (at least 2 intervals), refines every
/// bracket where `g` changes sign from − to + (a local minimum of the distance)
/// by Newton's method `t ← t − g/g'` with `g' = |Q'|² + (Q − p)·Q''`, safeguarded
/// by bisection, polishes the best sample the same way, and returns the best of
/// these candidates and the endpoints `t = 0`, `t = 1` (Piegl & Tiller §6.1).
pub fn nearest_with<C: Curve + ?Sized>(curve: &C, p: Point, samples: usize) -> (f64, f64) {
    let n = samples.max(2);
    // (t, squared distance) of the best candidate so far.
    let mut best = (0.0, f64::INFINITY);
    let consider = |best: &mut (f64, f64), t: f64| -> bool {
        let d2 = curve.eval(t).distance_squared(p);
        let better = d2 < best.1;
        if better {
            *best = (t, d2);
        }
        better
    };
    let g = |t: f64| (curve.eval(t) - p).dot(curve.deriv(t));
    consider(&mut best, 0.0);
    let (mut prev_t, mut prev_g) = (0.0, g(0.0));
    let mut best_k = 0;
    for k in 1..=n {
        let t = k as f64 / n as f64;
        let gk = g(t);
        if consider(&mut best, t) {
            best_k = k;
        }
        if prev_g < 0.0 && gk > 0.0 {
            consider(&mut best, refine(curve, p, prev_t, t));
        }
        prev_t = t;
        prev_g = gk;
    }
    // Polish the best sample in case a root pair hides between two samples.
    let lo = best_k.saturating_sub(1) as f64 / n as f64;
    let hi = (best_k + 1).min(n) as f64 / n as f64;
    let start = best_k as f64 / n as f64;
    consider(&mut best, newton_from(curve, p, start, lo, hi));
    (best.0, best.1.sqrt())
}

/// A root of `g` in `[a, b]` with `g(a) < 0 < g(b)`, by Newton steps that fall
/// back to bisection whenever they leave the shrinking bracket.
fn refine<C: Curve + ?Sized>(curve: &C, p: Point, mut a: f64, mut b: f64) -> f64 {
    let mut t = 0.5 * (a + b);
    for _ in 0..100 {
        let q = curve.eval(t);
        let d1 = curve.deriv(t);
        let gt = (q - p).dot(d1);
        if gt == 0.0 {
            return t;
        }
        if gt < 0.0 {
            a = t;
        } else {
            b = t;
        }
        let gp = d1.hypot2() + (q - p).dot(curve.deriv2(t));
        let newton = t - gt / gp;
        let next = if gp > 0.0 && newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        if (next - t).abs() <= 1e-15 || b - a <= 1e-15 {
            return next;
        }
        t = next;
    }
    t
}

/// Undamped Newton on `g` from `t`, kept inside `[lo, hi]`; returns `t` itself
/// if the iteration does not settle.
fn newton_from<C: Curve + ?Sized>(curve: &C, p: Point, t0: f64, lo: f64, hi: f64) -> f64 {
    let mut t = t0;
    for _ in 0..30 {
        let q = curve.eval(t);
        let d1 = curve.deriv(t);
        let gp = d1.hypot2() + (q - p).dot(curve.deriv2(t));
        if gp.is_nan() || gp <= 0.0 {
            return t0;
        }
        let next = (t - (q - p).dot(d1) / gp).clamp(lo, hi);
        if (next - t).abs() <= 1e-15 {
            return next;
        }
        t = next;
    }
    t
}

#[cfg(test)]
mod tests {
    use super::super::bezier::tests::TestRng;
    use super::super::{
        Bezier, CubicBez, QuadBez, RationalBezier, RationalCubicBez, RationalQuadBez,
    };
    use super::*;

    /// Dense sampling: 20 001 samples, then 2 001 more across the two
    /// intervals around the best one.
    fn brute<C: Curve>(c: &C, p: Point) -> (f64, f64) {
        let scan = |lo: f64, hi: f64, n: usize| {
            (0..=n)
                .map(|k| {
                    let t = lo + (hi - lo) * k as f64 / n as f64;
                    (t, c.eval(t).distance(p))
                })
                .fold((0.0, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a })
        };
        let h = 1.0 / 20_000.0;
        let (t, _) = scan(0.0, 1.0, 20_000);
        scan((t - h).max(0.0), (t + h).min(1.0), 2_000)
    }

    fn check<C: Curve>(c: &C, p: Point) {
        let (t, d) = nearest(c, p);
        let (bt, bd) = brute(c, p);
        assert!((0.0..=1.0).contains(&t));
        assert!((c.eval(t).distance(p) - d).abs() < 1e-12);
        assert!(
            d <= bd + 1e-12,
            "missed: ours {d} at {t}, brute {bd} at {bt}"
        );
        assert!(bd - d < 1e-6, "ours {d} at {t}, brute {bd} at {bt}");
    }

    #[test]
    fn agrees_with_brute_force() {
        let mut rng = TestRng(70);
        for _ in 0..8 {
            let q = QuadBez::new(rng.point(), rng.point(), rng.point());
            let c = CubicBez::new(rng.point(), rng.point(), rng.point(), rng.point());
            let rq =
                RationalQuadBez::new(rng.point(), rng.point(), rng.point(), rng.range(0.1, 8.0))
                    .unwrap();
            let rc = RationalCubicBez::new(
                rng.point(),
                rng.point(),
                rng.point(),
                rng.point(),
                rng.range(0.1, 8.0),
                rng.range(0.1, 8.0),
            )
            .unwrap();
            let b = Bezier::new((0..7).map(|_| rng.point()).collect()).unwrap();
            let rb = RationalBezier::new(
                (0..6).map(|_| rng.point()).collect(),
                (0..6).map(|_| rng.range(0.1, 8.0)).collect(),
            )
            .unwrap();
            for _ in 0..4 {
                let p = rng.point();
                check(&q, p);
                check(&c, p);
                check(&rq, p);
                check(&rc, p);
                check(&b, p);
                check(&rb, p);
            }
        }
    }

    #[test]
    fn interior_foot_is_orthogonal_and_endpoints_are_checked() {
        // Unit quarter circle: the foot from (2, 2) is at 45°, distance 2√2 − 1.
        let arc = RationalQuadBez::circular_arc(Point::ZERO, 1.0, 0.0, std::f64::consts::FRAC_PI_2)
            .unwrap();
        let (t, d) = nearest(&arc, Point::new(2.0, 2.0));
        assert!((d - (2.0 * 2f64.sqrt() - 1.0)).abs() < 1e-14);
        assert!((t - 0.5).abs() < 1e-12);
        let foot = arc.eval(t);
        assert!((foot - Point::new(2.0, 2.0)).dot(arc.deriv(t)).abs() < 1e-12);
        // A point beyond the start projects onto the endpoint t = 0.
        let (t, d) = nearest(&arc, Point::new(2.0, -3.0));
        assert_eq!(t, 0.0);
        assert!((d - Point::new(1.0, 3.0).hypot()).abs() < 1e-15);
        // A point on the curve has distance ~0.
        let (_, d) = nearest(&arc, arc.eval(0.3));
        assert!(d < 1e-14);
        // The centre is equidistant: any t, distance 1.
        let (_, d) = nearest(&arc, Point::ZERO);
        assert!((d - 1.0).abs() < 1e-14);
    }
}
