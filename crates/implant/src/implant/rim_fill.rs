//! A smooth surface through the bone around a defect, in 3D (BEYOND THE
//! THESIS): the **rim fill**, for defects the mirror cannot serve (across
//! the mid-sagittal plane, an abnormal mirror side, the vertex, where an
//! axial slice is nearly tangent to the vault).
//!
//! The outer table around the defect (the rim points `p_i`) is described
//! as a radius function about a centre `c`: a best-fit sphere as the
//! trend, and a thin-plate spline of the residual.
//!
//! 1. The sphere `|p − c| = ρ` by the algebraic least-squares fit
//!    `|p|² = 2c·p + k`, `ρ² = k + |c|²` (Kåsa, "A circle fitting procedure
//!    and its error analysis", IEEE Trans. Instrum. Meas. 25(1):8–14,
//!    1976, in 3D), fitted again without the points farther from it than
//!    `1 mm + 3σ̂` (`σ̂ = 1.4826·MAD` of `|p − c| − ρ`, the robust scale of
//!    Hampel 1974): other bone met by a rim ray does not pull the sphere.
//! 2. A chart of directions about `c`: the stereographic projection from
//!    `−e₀`, `e₀` the mean direction of the rim from `c`: a unit direction
//!    `u` maps to `2ρ·(u·e₁, u·e₂)/(1 + u·e₀)` (mm), `e₁, e₂ ⊥ e₀`
//!    (conformal, and defined for a rim spanning more than a hemisphere).
//! 3. The residual `δ_i = |p_i − c| − ρ` at the chart points `x_i` is
//!    interpolated by the smoothing thin-plate spline (Duchon, "Splines
//!    minimizing rotation-invariant semi-norms in Sobolev spaces", LNM 571,
//!    1977; Bookstein, "Principal warps: thin-plate splines and the
//!    decomposition of deformations", IEEE TPAMI 11(6):567–585, 1989)
//!    `δ(x) = a₀ + a₁x + a₂y + Σ w_i U(|x − x_i|)`, `U(r) = r² ln r`, with
//!    `(K + λI)w + Pa = δ`, `Pᵀw = 0` (`K_ij = U(|x_i − x_j|)`, `P` the rows
//!    `(1, x_i, y_i)`; λ the smoothing of Wahba, *Spline Models for
//!    Observational Data*, SIAM 1990, §2.4), the surface of least bending
//!    energy through the rim.
//!
//! The filled surface is `p(u) = c + (ρ + δ(chart(u)))·u`. A sphere cap is
//! reproduced exactly (δ ≡ 0); a smooth vault is followed to within the
//! spline's error.

use crate::geometry::Point;

/// Why a rim surface could not be fitted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RimError {
    /// Too few rim points.
    #[error("the rim fill needs at least {needed} rim points around the defect; found {found}")]
    TooFewPoints {
        /// Points found.
        found: usize,
        /// Points needed.
        needed: usize,
    },
    /// The points do not determine a sphere or a spline (collinear or
    /// coplanar rim, or a singular system).
    #[error("the rim points around the defect do not determine a surface ({what})")]
    Degenerate {
        /// Which system was singular.
        what: &'static str,
    },
}

/// A fitted rim surface (module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct RimSurface {
    /// The sphere's centre `c` (mm).
    pub centre: [f64; 3],
    /// The sphere's radius `ρ` (mm).
    pub radius: f64,
    /// The chart's axes `e₀` (towards the rim), `e₁`, `e₂`.
    pub axes: [[f64; 3]; 3],
    /// The spline's nodes `x_i` (chart mm).
    pub nodes: Vec<Point>,
    /// The spline's weights `w_i`.
    pub weights: Vec<f64>,
    /// The spline's affine part `(a₀, a₁, a₂)`.
    pub affine: [f64; 3],
    /// RMS of the surface's radial distance from the rim points (mm).
    pub rim_rms_mm: f64,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = dot(a, a).sqrt();
    a.map(|v| v / l)
}

fn cross(u: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ]
}

/// The thin-plate kernel `U(r) = r² ln r` (0 at `r = 0`), of `r²`.
fn kernel(r2: f64) -> f64 {
    if r2 <= 0.0 {
        0.0
    } else {
        0.5 * r2 * r2.ln()
    }
}

/// Solves the dense system `A x = b` (`n × n`, row-major) by Gaussian
/// elimination with partial pivoting; `None` when singular.
fn solve(mut a: Vec<f64>, mut b: Vec<f64>, n: usize) -> Option<Vec<f64>> {
    for k in 0..n {
        let p = (k..n).max_by(|&i, &j| a[i * n + k].abs().total_cmp(&a[j * n + k].abs()))?;
        if a[p * n + k].abs() < 1e-12 {
            return None;
        }
        if p != k {
            for c in 0..n {
                a.swap(k * n + c, p * n + c);
            }
            b.swap(k, p);
        }
        for i in k + 1..n {
            let f = a[i * n + k] / a[k * n + k];
            if f != 0.0 {
                for c in k..n {
                    a[i * n + c] -= f * a[k * n + c];
                }
                b[i] -= f * b[k];
            }
        }
    }
    let mut x = vec![0.0; n];
    for k in (0..n).rev() {
        let s: f64 = (k + 1..n).map(|c| a[k * n + c] * x[c]).sum();
        x[k] = (b[k] - s) / a[k * n + k];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The algebraic least-squares sphere `(c, ρ)` of `points` (Kåsa 1976).
pub fn fit_sphere(points: &[[f64; 3]]) -> Option<([f64; 3], f64)> {
    // Normal equations of [2x 2y 2z 1]·(c, k) = |p|², centred for
    // conditioning.
    let n = points.len() as f64;
    let m = points.iter().fold([0.0; 3], |s, p| {
        [s[0] + p[0] / n, s[1] + p[1] / n, s[2] + p[2] / n]
    });
    let mut ata = vec![0.0; 16];
    let mut atb = vec![0.0; 4];
    for p in points {
        let q = sub(*p, m);
        let row = [2.0 * q[0], 2.0 * q[1], 2.0 * q[2], 1.0];
        let rhs = dot(q, q);
        for i in 0..4 {
            atb[i] += row[i] * rhs;
            for j in 0..4 {
                ata[i * 4 + j] += row[i] * row[j];
            }
        }
    }
    let x = solve(ata, atb, 4)?;
    let c = [x[0], x[1], x[2]];
    let r2 = x[3] + dot(c, c);
    (r2 > 0.0).then(|| ([c[0] + m[0], c[1] + m[1], c[2] + m[2]], r2.sqrt()))
}

/// The distance `1 mm + 3·1.4826·MAD` beyond which a point is an outlier
/// of the sphere `(c, ρ)`.
fn outlier_cut(points: &[[f64; 3]], c: [f64; 3], rho: f64) -> f64 {
    let mut r: Vec<f64> = points
        .iter()
        .map(|p| (dot(sub(*p, c), sub(*p, c)).sqrt() - rho).abs())
        .collect();
    r.sort_by(f64::total_cmp);
    1.0 + 3.0 * 1.4826 * r[r.len() / 2]
}

/// [`fit_sphere`] of `points`, then again of the points within
/// the distance `1 mm + 3·1.4826·MAD` of it (module documentation).
pub fn robust_sphere(points: &[[f64; 3]]) -> Option<([f64; 3], f64)> {
    let (c, rho) = fit_sphere(points)?;
    let cut = outlier_cut(points, c, rho);
    let kept: Vec<[f64; 3]> = points
        .iter()
        .filter(|p| (dot(sub(**p, c), sub(**p, c)).sqrt() - rho).abs() <= cut)
        .copied()
        .collect();
    if kept.len() < 10 {
        return Some((c, rho));
    }
    fit_sphere(&kept)
}

impl RimSurface {
    /// Fits the rim surface to `points` with smoothing `lambda` (mm²;
    /// 0 interpolates). Needs at least 10 points; the points should be
    /// at most a few hundred (the system is dense, `O(n³)`).
    pub fn fit(points: &[[f64; 3]], lambda: f64) -> Result<RimSurface, RimError> {
        if points.len() < 10 {
            return Err(RimError::TooFewPoints {
                found: points.len(),
                needed: 10,
            });
        }
        let (centre, radius) =
            robust_sphere(points).ok_or(RimError::Degenerate { what: "sphere" })?;
        let points: Vec<[f64; 3]> = {
            let cut = outlier_cut(points, centre, radius);
            points
                .iter()
                .filter(|p| (dot(sub(**p, centre), sub(**p, centre)).sqrt() - radius).abs() <= cut)
                .copied()
                .collect()
        };
        let points = &points[..];
        if points.len() < 10 {
            return Err(RimError::TooFewPoints {
                found: points.len(),
                needed: 10,
            });
        }
        let mean = points.iter().fold([0.0; 3], |s, p| {
            let u = unit(sub(*p, centre));
            [s[0] + u[0], s[1] + u[1], s[2] + u[2]]
        });
        let e0 = unit(mean);
        let helper = if e0[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let e1 = unit(cross(e0, helper));
        let e2 = cross(e0, e1);
        let mut surface = RimSurface {
            centre,
            radius,
            axes: [e0, e1, e2],
            nodes: Vec::new(),
            weights: Vec::new(),
            affine: [0.0; 3],
            rim_rms_mm: 0.0,
        };
        let mut nodes = Vec::with_capacity(points.len());
        let mut values = Vec::with_capacity(points.len());
        for p in points {
            let d = sub(*p, centre);
            let x = surface
                .chart(unit(d))
                .ok_or(RimError::Degenerate { what: "chart" })?;
            nodes.push(x);
            values.push(dot(d, d).sqrt() - radius);
        }
        let n = nodes.len();
        let m = n + 3;
        let mut a = vec![0.0; m * m];
        let mut b = vec![0.0; m];
        for i in 0..n {
            for j in 0..n {
                a[i * m + j] = kernel(nodes[i].distance_squared(nodes[j]));
            }
            a[i * m + i] += lambda;
            let row = [1.0, nodes[i].x, nodes[i].y];
            for k in 0..3 {
                a[i * m + n + k] = row[k];
                a[(n + k) * m + i] = row[k];
            }
            b[i] = values[i];
        }
        let x = solve(a, b, m).ok_or(RimError::Degenerate {
            what: "thin-plate spline",
        })?;
        surface.weights = x[..n].to_vec();
        surface.affine = [x[n], x[n + 1], x[n + 2]];
        surface.nodes = nodes;
        let sq: f64 = points
            .iter()
            .map(|p| surface.signed_distance(*p).unwrap_or(f64::INFINITY).powi(2))
            .sum();
        surface.rim_rms_mm = (sq / n as f64).sqrt();
        Ok(surface)
    }

    /// The chart point `2ρ·(u·e₁, u·e₂)/(1 + u·e₀)` of a unit direction
    /// `u`; `None` within 25° of `−e₀`.
    pub fn chart(&self, u: [f64; 3]) -> Option<Point> {
        let [e0, e1, e2] = self.axes;
        let c0 = dot(u, e0);
        (c0 > -0.9).then(|| Point::new(dot(u, e1), dot(u, e2)) * (2.0 * self.radius / (1.0 + c0)))
    }

    /// The spline residual `δ(x)` at a chart point.
    pub fn residual(&self, x: Point) -> f64 {
        let [a0, a1, a2] = self.affine;
        a0 + a1 * x.x
            + a2 * x.y
            + self
                .nodes
                .iter()
                .zip(&self.weights)
                .map(|(n, w)| w * kernel(x.distance_squared(*n)))
                .sum::<f64>()
    }

    /// `|p − c| − (ρ + δ(chart(p)))`: positive outside the surface (mm,
    /// along the ray from `c`); `None` outside the chart.
    pub fn signed_distance(&self, p: [f64; 3]) -> Option<f64> {
        let d = sub(p, self.centre);
        let l = dot(d, d).sqrt();
        let x = self.chart(d.map(|v| v / l))?;
        Some(l - self.radius - self.residual(x))
    }

    /// Where the ray `origin + t·dir` last crosses the surface outwards
    /// for `t` in `[t_lo, t_hi]`: walking in from `t_hi` (which must be
    /// outside) in 0.5 mm steps to the first sample inside, then bisection
    /// to 1 µm. `None` when there is no such crossing or the ray leaves the
    /// chart first.
    pub fn ray_hit(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        (t_lo, t_hi): (f64, f64),
    ) -> Option<f64> {
        let at = |t: f64| {
            self.signed_distance([
                origin[0] + t * dir[0],
                origin[1] + t * dir[1],
                origin[2] + t * dir[2],
            ])
        };
        if at(t_hi)? <= 0.0 {
            return None;
        }
        let steps = ((t_hi - t_lo) / 0.5).ceil().max(1.0) as usize;
        let inside = (1..=steps)
            .map(|k| t_hi - (t_hi - t_lo) * k as f64 / steps as f64)
            .find(|&t| at(t).is_none_or(|v| v < 0.0))?;
        at(inside)?;
        let (mut lo, mut hi) = (inside, inside + (t_hi - t_lo) / steps as f64);
        while hi - lo > 1e-3 {
            let mid = 0.5 * (lo + hi);
            if at(mid)? < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points of the surface `r(u) = f(u)` about `c` on a ring of angular
    /// radii `[inner, outer]` (radians) about the direction `axis`.
    fn ring(
        c: [f64; 3],
        axis: [f64; 3],
        (inner, outer): (f64, f64),
        f: impl Fn([f64; 3]) -> f64,
    ) -> Vec<[f64; 3]> {
        let e0 = unit(axis);
        let e1 = unit(cross(e0, [0.3, 1.0, 0.2]));
        let e2 = cross(e0, e1);
        let mut out = Vec::new();
        for i in 0..6 {
            let a = inner + (outer - inner) * i as f64 / 5.0;
            for k in 0..48 {
                let phi = std::f64::consts::TAU * k as f64 / 48.0;
                let u = [0, 1, 2]
                    .map(|j| a.cos() * e0[j] + a.sin() * (phi.cos() * e1[j] + phi.sin() * e2[j]));
                let r = f(u);
                out.push([c[0] + r * u[0], c[1] + r * u[1], c[2] + r * u[2]]);
            }
        }
        out
    }

    #[test]
    fn the_rim_fill_reproduces_a_sphere_cap_to_a_tenth_of_a_millimetre() {
        let c = [100.0, 120.0, 40.0];
        // A 70 mm skull, a hole of 25° angular radius (≈ 30 mm) on the
        // side, the rim 25°–37°.
        let rim = ring(c, [0.8, -0.2, 0.5], (0.44, 0.65), |_| 70.0);
        let s = RimSurface::fit(&rim, 0.0).unwrap();
        for i in 0..20 {
            let a = 0.44 * i as f64 / 19.0;
            let u = unit([0.8 + a * 0.3, -0.2 + a, 0.5 - a * 0.2]);
            let t = s.ray_hit(c, u, (10.0, 150.0)).unwrap();
            assert!((t - 70.0).abs() < 0.1, "r = {t}");
        }
        assert!(s.rim_rms_mm < 1e-6);
    }

    #[test]
    fn the_rim_fill_follows_an_ellipsoidal_vault_to_a_tenth_of_a_millimetre() {
        // An ellipsoid 75 × 90 × 65 mm: not a sphere, so the spline works.
        let c = [0.0; 3];
        let r = |u: [f64; 3]| {
            1.0 / ((u[0] / 75.0).powi(2) + (u[1] / 90.0).powi(2) + (u[2] / 65.0).powi(2)).sqrt()
        };
        let axis = [0.5, 0.3, 0.8];
        let rim = ring(c, axis, (0.35, 0.6), r);
        let s = RimSurface::fit(&rim, 0.0).unwrap();
        let mut worst = 0.0f64;
        for i in 0..=10 {
            for k in 0..12 {
                let a = 0.35 * i as f64 / 10.0;
                let phi = std::f64::consts::TAU * k as f64 / 12.0;
                let e0 = unit(axis);
                let e1 = unit(cross(e0, [0.3, 1.0, 0.2]));
                let e2 = cross(e0, e1);
                let u = [0, 1, 2]
                    .map(|j| a.cos() * e0[j] + a.sin() * (phi.cos() * e1[j] + phi.sin() * e2[j]));
                let t = s.ray_hit(c, u, (10.0, 200.0)).unwrap();
                worst = worst.max((t - r(u)).abs());
            }
        }
        assert!(worst < 0.1, "worst {worst} mm");
    }

    #[test]
    fn too_few_rim_points_are_refused() {
        assert!(matches!(
            RimSurface::fit(&[[0.0; 3]; 4], 0.0),
            Err(RimError::TooFewPoints { found: 4, .. })
        ));
    }
}
