//! Smoothness across slices (RECONSTRUCTION: the thesis designs each slice
//! on its own). Two smoothers run between the per-slice design of the
//! outer walls and the inner walls:
//!
//! - **Thickness**: the per-slice bone thickness next to A′ (and next to
//!   B′) is replaced by its lower Lipschitz envelope
//!   `t̃(z) = min_k (t(k) + L·|z − k|)`, the largest profile that never
//!   exceeds the measured bone and changes by at most `L` mm per slice
//!   ([`lipschitz_envelope`]). The implant therefore never gets thicker than
//!   the bone next to it, and a step in the bone (the thin wall over the
//!   frontal sinus next to full-thickness frontal bone) becomes a ramp.
//! - **Outer wall**: each fitted wall is read in polar form `r_z(θ)` about
//!   a centre common to the stack (the mean of the slices' polar centres);
//!   at the wall's own rays the radius is averaged over the neighbouring
//!   slices whose walls the ray meets, with binomial weights (half-width
//!   `h`: `[1, 2, 1]/4` for 1, `[1, 4, 6, 4, 1]/16` for 2, renormalised over
//!   the walls present; faded out over the quarter of the rays next to
//!   each end by a quintic smoothstep, [`END_TAPER`], so that near A′ and
//!   B′ each wall keeps the shape that meets its own seat, which moves
//!   between slices), and the wall is refitted to these points by
//!   Levenberg–Marquardt with the same ends and joins
//!   ([`super::wall::refit_outer`]), so A′, B′ and the G¹ joins stay exact
//!   while the surface varies smoothly in z ([`roughness`] measures it).

use super::polar::{angle, envelope_radius, smootherstep, wrap};
use super::wall::{refit_outer, OuterDesign, WallOptions};
use super::SliceError;
use crate::geometry::{Point, Polyline};

/// The lower Lipschitz envelope `t̃_i = min_j (t_j + step·|z_i − z_j|)` of
/// `values` at the slice numbers `zs`.
pub fn lipschitz_envelope(values: &[f64], zs: &[usize], step: f64) -> Vec<f64> {
    values
        .iter()
        .zip(zs)
        .map(|(_, &zi)| {
            values
                .iter()
                .zip(zs)
                .map(|(&t, &zj)| t + step * zi.abs_diff(zj) as f64)
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

/// The fraction of a wall's rays at each end over which the smoothing
/// across slices fades out ([`smooth_outer_walls`]).
pub const END_TAPER: f64 = 0.25;

/// Binomial weights `C(2h, h + k)` for `k = −h..=h`.
fn binomial(h: usize) -> Vec<f64> {
    let n = 2 * h;
    let mut w = vec![1.0; n + 1];
    for k in 1..n {
        w[k] = w[k - 1] * (n + 1 - k) as f64 / k as f64;
    }
    w
}

/// The rays of a wall: `m` polar angles about `o` from its first to its
/// last point.
fn rays(wall: &Polyline, o: Point, m: usize) -> Vec<f64> {
    let (a, b) = (wall.points[0], wall.points[wall.points.len() - 1]);
    let ta = angle(a, o);
    let span = wrap(angle(b, o) - ta);
    (0..m)
        .map(|j| ta + span * j as f64 / (m - 1) as f64)
        .collect()
}

/// The radius of `wall` along the ray from `o` at `theta` (`None` where
/// the ray misses it).
fn radius(wall: &Polyline, o: Point, theta: f64) -> Option<f64> {
    envelope_radius(&[wall], o, theta)
}

/// The common polar centre of a stack of designs: the mean of theirs.
fn common_centre(designs: &[&OuterDesign]) -> Point {
    designs.iter().fold(Point::ZERO, |s, d| s + d.centre) / designs.len().max(1) as f64
}

/// Smooths the fitted outer walls of consecutive slices (`zs`) across z
/// with binomial half-width `half_width` (0: unchanged) and refits them
/// (see the module documentation). Baseline designs are left unchanged.
pub fn smooth_outer_walls(
    designs: &mut [OuterDesign],
    zs: &[usize],
    half_width: usize,
    options: &WallOptions,
) -> Result<(), SliceError> {
    if half_width == 0 || designs.len() < 2 || designs.iter().any(|d| d.segments.is_empty()) {
        return Ok(());
    }
    let o = common_centre(&designs.iter().collect::<Vec<_>>());
    let m = options.wall_points.max(8);
    let walls: Vec<Polyline> = designs.iter().map(|d| d.outer.clone()).collect();
    let w = binomial(half_width);
    for (i, design) in designs.iter_mut().enumerate() {
        let thetas = rays(&walls[i], o, m);
        let mut points = Vec::with_capacity(m);
        for (j, &t) in thetas.iter().enumerate() {
            if j == 0 || j + 1 == m {
                points.push(if j == 0 { design.a } else { design.b });
                continue;
            }
            let (mut acc, mut total) = (0.0, 0.0);
            for (k, &wk) in w.iter().enumerate() {
                let n = i as i64 + k as i64 - half_width as i64;
                if n < 0 || n as usize >= walls.len() || zs[i].abs_diff(zs[n as usize]) > half_width
                {
                    continue;
                }
                if let Some(r) = radius(&walls[n as usize], o, t) {
                    acc += wk * r;
                    total += wk;
                }
            }
            let own = radius(&walls[i], o, t);
            let averaged = (total > 0.0).then(|| acc / total);
            // Tapered towards the ends, where the wall meets its own bone.
            let u = j as f64 / (m - 1) as f64;
            let taper = smootherstep(u.min(1.0 - u) / END_TAPER);
            let r = match (averaged, own) {
                (Some(s), Some(w)) => Some(taper * s + (1.0 - taper) * w),
                (s, w) => w.or(s),
            };
            if let Some(r) = r {
                points.push(o + Point::new(t.cos(), t.sin()) * r);
            }
        }
        refit_outer(design, points, options)?;
    }
    Ok(())
}

/// The radial roughness of a stack of outer walls across z: per slice with
/// both neighbours (consecutive in `zs`), the mean over 24 rays from the
/// common centre `o` (those that meet all three walls) of the second
/// difference of the radius, `|r(z−1) − 2r(z) + r(z+1)|` (mm); `None` at
/// the ends of the stack, next to a gap in `zs`, or with no common ray. A
/// surface that is smooth in z gives a few hundredths of a millimetre;
/// walls designed slice by slice give steps.
pub fn roughness(walls: &[&Polyline], zs: &[usize], o: Point) -> Vec<Option<f64>> {
    (0..walls.len())
        .map(|i| {
            if i == 0 || i + 1 >= walls.len() || zs[i + 1] - zs[i] != 1 || zs[i] - zs[i - 1] != 1 {
                return None;
            }
            let d: Vec<f64> = rays(walls[i], o, 24)
                .into_iter()
                .filter_map(|t| {
                    let r = |k: usize| radius(walls[k], o, t);
                    Some((r(i - 1)? - 2.0 * r(i)? + r(i + 1)?).abs())
                })
                .collect();
            (!d.is_empty()).then(|| d.iter().sum::<f64>() / d.len() as f64)
        })
        .collect()
}
