//! How noisy an outline's points are: the scale below which a fit to a
//! tolerance follows the noise rather than the shape.

use crate::geometry::Point;

/// A robust estimate of the points' noise `σ` (per coordinate), from the
/// fourth differences along the outline:
///
/// `eᵢ = −½Rᵢ₋₂ + 2Rᵢ₋₁ − 3Rᵢ + 2Rᵢ₊₁ − ½Rᵢ₊₂`
///
/// (the second difference at `i` less the mean of its neighbours'). A smooth
/// curve sampled evenly contributes `O(h⁴)` to `eᵢ`, so `eᵢ` is noise; for
/// independent noise of variance `σ²` per coordinate each coordinate of
/// `eᵢ` has variance `17.5σ²` (the sum of the coefficients' squares), `|eᵢ|`
/// is Rayleigh distributed with median `σ·√17.5·√(2 ln 2)`, and so
///
/// `σ̂ = median |eᵢ| / (√17.5 · √(2 ln 2)) ≈ median |eᵢ| / 4.925`.
///
/// The median ignores corners (a few large `eᵢ`). Pixel outlines get the
/// staircase's amplitude, a fraction of a pixel. Returns 0 for fewer than 5
/// points. Closed outlines wrap; open ones use the interior points.
/// (Noise estimation by differencing: Rice 1984, "Bandwidth choice for
/// nonparametric regression", *Ann. Statist.* 12; Gasser, Sroka &
/// Jennen-Steinmetz 1986, *Biometrika* 73.)
pub fn noise_level(points: &[Point], closed: bool) -> f64 {
    let n = points.len();
    if n < 5 {
        return 0.0;
    }
    let at = |i: isize| points[i.rem_euclid(n as isize) as usize];
    let range = if closed { 0..n } else { 2..n - 2 };
    let mut e: Vec<f64> = range
        .map(|i| {
            let i = i as isize;
            let v = at(i - 2) * -0.5 + at(i - 1) * 2.0 - at(i) * 3.0 + at(i + 1) * 2.0
                - at(i + 2) * 0.5;
            v.hypot()
        })
        .collect();
    if e.is_empty() {
        return 0.0;
    }
    let mid = e.len() / 2;
    let (_, median, _) = e.select_nth_unstable_by(mid, f64::total_cmp);
    *median / (17.5f64.sqrt() * (2.0 * std::f64::consts::LN_2).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_smooth_circle_has_almost_none_and_gaussian_noise_is_found() {
        let circle: Vec<Point> = (0..400)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / 400.0;
                Point::new(100.0 * a.cos(), 100.0 * a.sin())
            })
            .collect();
        assert!(noise_level(&circle, true) < 1e-6);
        // Deterministic normal draws (Box–Muller on a fixed LCG).
        let mut state = 12345u64;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let noisy: Vec<Point> = circle
            .iter()
            .map(|&p| {
                let (u, v) = (uniform(), uniform());
                let r = (-2.0 * u.ln()).sqrt() * 0.3;
                let a = std::f64::consts::TAU * v;
                p + Point::new(r * a.cos(), r * a.sin())
            })
            .collect();
        let s = noise_level(&noisy, true);
        assert!((s - 0.3).abs() < 0.05, "{s}");
        assert_eq!(noise_level(&circle[..4], false), 0.0);
    }
}
