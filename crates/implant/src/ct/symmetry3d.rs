//! The mid-sagittal **plane** in 3D (BEYOND THE THESIS, whose mirror is a
//! line per slice): the plane `n·p = d` (`|n| = 1`, `p` in voxel
//! millimetres `(col·sx, row·sy, slice·sz)`) whose reflection
//! `R(p) = p − 2(n·p − d)n` maps the skull's bone surface onto itself best.
//!
//! The registration of the skull to its own mirror image is the symmetry
//! plane search of Tuzikov, Colliot & Bloch ("Evaluation of the symmetry
//! plane in 3D MR brain images", Pattern Recognition Letters 24(14):
//! 2219–2233, 2003), here by the iterative closest point algorithm (Besl &
//! McKay, "A method for registration of 3-D shapes", IEEE TPAMI 14(2):
//! 239–256, 1992) on bone-surface voxels, trimmed (Chetverikov, Svirko,
//! Stepanov & Krsek, "The trimmed iterative closest point algorithm",
//! ICPR 2002) so that a defect, which has no mirror partner, does not pull
//! the plane: each iteration pairs every moving point `p_i` with the
//! surface point `q_i` nearest to `R(p_i)` and keeps the `keep` fraction
//! of pairs with the smallest `|R(p_i) − q_i|`.
//!
//! The first iteration moves the plane to the least-squares plane of the
//! kept pairs in closed form: with `v_i = p_i − q_i`, `m_i = (p_i + q_i)/2`
//! and `m̄` their mean, `|R(p_i) − q_i|² = |v_i|² − (n·v_i)² + 4(n·m_i − d)²`,
//! so the optimum is `d = n·m̄` and `n` the unit eigenvector of the largest
//! eigenvalue of `A = Σ v_i v_iᵀ − 4 Σ (m_i − m̄)(m_i − m̄)ᵀ`. Point-to-point
//! pairs slide along a smooth vault, so that a roll of the plane is
//! recovered only very slowly; every later iteration therefore takes the
//! Gauss–Newton step of the **point-to-plane** distance (Chen & Medioni,
//! "Object modelling by registration of multiple range images", Image and
//! Vision Computing 10(3):145–155, 1992),
//! `E(n, d) = Σ ((R(p_i) − q_i)·ν_i)²`, `ν_i` the unit bone-surface normal
//! at `q_i` (the HU gradient, 3 × 3 averaged central differences), with
//! `n ← normalise(n + a t₁ + b t₂)`, `t₁, t₂ ⊥ n`, and
//! `∂R/∂a = −2(t₁·p) n − 2(n·p − d) t₁`, `∂R/∂d = 2n`.
//!
//! The residual reported is the RMS of `|R(p_i) − q_i|` over the kept
//! pairs after the last iteration ([`SymmetryPlane::rms_mm`]).

use super::mask::Mask3;
use super::mirror::MidLine;
use super::volume::Volume;
use crate::geometry::Point;
use metabezier_core::linalg::symmetric_eigen;

/// A plane `n·p = d` in voxel millimetres, `n` a unit vector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane3 {
    /// The unit normal `n`.
    pub normal: [f64; 3],
    /// The offset `d` (mm).
    pub offset: f64,
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

impl Plane3 {
    /// The plane through `point` with normal `normal` (normalised here).
    pub fn through(point: [f64; 3], normal: [f64; 3]) -> Plane3 {
        let l = dot3(normal, normal).sqrt();
        let n = [normal[0] / l, normal[1] / l, normal[2] / l];
        Plane3 {
            normal: n,
            offset: dot3(n, point),
        }
    }

    /// The plane through an in-slice mid-sagittal line, parallel to the
    /// slice axis: normal `(cos t, −sin t, 0)` ([`MidLine::normal`]).
    pub fn from_midline(line: &MidLine) -> Plane3 {
        let n = line.normal();
        Plane3::through([line.point.x, line.point.y, 0.0], [n.x, n.y, 0.0])
    }

    /// The signed distance `n·p − d` (mm).
    pub fn side(&self, p: [f64; 3]) -> f64 {
        dot3(self.normal, p) - self.offset
    }

    /// The mirror image `R(p) = p − 2(n·p − d)n`.
    pub fn reflect(&self, p: [f64; 3]) -> [f64; 3] {
        let k = 2.0 * self.side(p);
        let n = self.normal;
        [p[0] - k * n[0], p[1] - k * n[1], p[2] - k * n[2]]
    }

    /// The angle (degrees, 0–90) between this plane and `other`:
    /// `acos |n₁·n₂|`.
    pub fn angle_deg(&self, other: &Plane3) -> f64 {
        dot3(self.normal, other.normal)
            .abs()
            .min(1.0)
            .acos()
            .to_degrees()
    }

    /// The plane's trace on the axial slice at height `z_mm`: the line
    /// `n_x x + n_y y = d − n_z z` in the slice's millimetre frame, as a
    /// [`MidLine`] through the point nearest `near`; `None` when the plane
    /// is (nearly) parallel to the slice (`|(n_x, n_y)| < 0.1`).
    pub fn trace(&self, z_mm: f64, near: Point) -> Option<MidLine> {
        let [nx, ny, nz] = self.normal;
        let l = (nx * nx + ny * ny).sqrt();
        if l < 0.1 {
            return None;
        }
        let (ux, uy) = (nx / l, ny / l);
        let c = (self.offset - nz * z_mm) / l;
        let s = ux * near.x + uy * near.y - c;
        let point = Point::new(near.x - s * ux, near.y - s * uy);
        // MidLine::normal = (cos t, −sin t) = (ux, uy) up to sign.
        let (ux, uy) = if ux < 0.0 { (-ux, -uy) } else { (ux, uy) };
        Some(MidLine {
            point,
            tilt: (-uy).atan2(ux),
        })
    }
}

/// The estimated mid-sagittal plane and its residual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SymmetryPlane {
    /// The plane.
    pub plane: Plane3,
    /// RMS of `|R(p_i) − q_i|` over the kept pairs (mm).
    pub rms_mm: f64,
    /// The kept pairs of the last iteration.
    pub pairs: usize,
    /// The iterations run.
    pub iterations: usize,
}

/// The options of [`estimate_symmetry_plane`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IcpOptions {
    /// The fraction of pairs kept per iteration (default 0.8).
    pub keep: f64,
    /// The largest pair distance searched (mm, default 8).
    pub search_mm: f64,
    /// The most iterations (default 60).
    pub max_iterations: usize,
    /// Every `stride`-th surface point moves (default 4).
    pub stride: usize,
}

impl Default for IcpOptions {
    fn default() -> Self {
        IcpOptions {
            keep: 0.8,
            search_mm: 8.0,
            max_iterations: 60,
            stride: 4,
        }
    }
}

/// Bone-surface points and their unit outward normals.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfacePoints {
    /// The points (voxel millimetres).
    pub points: Vec<[f64; 3]>,
    /// The unit normals, pointing out of the bone (down the HU gradient).
    pub normals: Vec<[f64; 3]>,
}

/// The HU gradient at voxel `(z, y, x)` (mm⁻¹ units of HU): central
/// differences averaged over the 3 × 3 neighbours across each axis
/// (Prewitt), clamped at the volume's faces.
fn gradient(volume: &Volume, z: usize, y: usize, x: usize) -> [f64; 3] {
    let (nx, ny, nz) = (volume.nx as i64, volume.ny as i64, volume.nz as i64);
    let sp = volume.spacing;
    let at = |z: i64, y: i64, x: i64| {
        f64::from(volume.get(
            z.clamp(0, nz - 1) as usize,
            y.clamp(0, ny - 1) as usize,
            x.clamp(0, nx - 1) as usize,
        ))
    };
    let (z, y, x) = (z as i64, y as i64, x as i64);
    let mut g = [0.0; 3];
    for a in -1..=1 {
        for b in -1..=1 {
            g[0] += at(z + a, y + b, x + 1) - at(z + a, y + b, x - 1);
            g[1] += at(z + a, y + 1, x + b) - at(z + a, y - 1, x + b);
            g[2] += at(z + 1, y + a, x + b) - at(z - 1, y + a, x + b);
        }
    }
    [
        g[0] / (18.0 * sp.x),
        g[1] / (18.0 * sp.y),
        g[2] / (18.0 * sp.z),
    ]
}

/// The bone-surface voxels of `volume` at `threshold` HU: bone voxels with
/// a 6-neighbour that is not bone (inside the volume), in voxel
/// millimetres, with their outward normals (`−∇HU/|∇HU|`; a voxel with no
/// gradient is left out). `skip` masks voxels to leave out (e.g. a known
/// defect).
pub fn bone_surface_points(volume: &Volume, threshold: i16, skip: Option<&Mask3>) -> SurfacePoints {
    let (nx, ny, nz) = (volume.nx, volume.ny, volume.nz);
    let sp = volume.spacing;
    let data = volume.data();
    let bone = |z: usize, y: usize, x: usize| data[(z * ny + y) * nx + x] >= threshold;
    let mut out = SurfacePoints::default();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if !bone(z, y, x) || skip.is_some_and(|m| m.data[(z * ny + y) * nx + x]) {
                    continue;
                }
                let open = (x > 0 && !bone(z, y, x - 1))
                    || (x + 1 < nx && !bone(z, y, x + 1))
                    || (y > 0 && !bone(z, y - 1, x))
                    || (y + 1 < ny && !bone(z, y + 1, x))
                    || (z > 0 && !bone(z - 1, y, x))
                    || (z + 1 < nz && !bone(z + 1, y, x));
                if !open {
                    continue;
                }
                let g = gradient(volume, z, y, x);
                let l = dot3(g, g).sqrt();
                if l > 0.0 {
                    out.points
                        .push([x as f64 * sp.x, y as f64 * sp.y, z as f64 * sp.z]);
                    out.normals.push(g.map(|v| -v / l));
                }
            }
        }
    }
    out
}

/// A uniform grid of points for nearest-neighbour queries.
struct Grid<'a> {
    points: &'a [[f64; 3]],
    cell: f64,
    lo: [f64; 3],
    dims: [usize; 3],
    start: Vec<usize>,
    order: Vec<usize>,
}

impl<'a> Grid<'a> {
    fn new(points: &'a [[f64; 3]], cell: f64) -> Grid<'a> {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in points {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
        }
        let dims = [0, 1, 2].map(|i| ((hi[i] - lo[i]) / cell).floor() as usize + 1);
        let key = |p: &[f64; 3]| {
            let c = [0, 1, 2].map(|i| ((p[i] - lo[i]) / cell).floor() as usize);
            (c[2] * dims[1] + c[1]) * dims[0] + c[0]
        };
        let mut count = vec![0usize; dims[0] * dims[1] * dims[2] + 1];
        for p in points {
            count[key(p) + 1] += 1;
        }
        for i in 1..count.len() {
            count[i] += count[i - 1];
        }
        let mut fill = count.clone();
        let mut order = vec![0; points.len()];
        for (i, p) in points.iter().enumerate() {
            let k = key(p);
            order[fill[k]] = i;
            fill[k] += 1;
        }
        Grid {
            points,
            cell,
            lo,
            dims,
            start: count,
            order,
        }
    }

    /// The point nearest `q` within `reach` cells, and its squared distance.
    fn nearest(&self, q: [f64; 3], reach: i64) -> Option<(usize, f64)> {
        let c = [0, 1, 2].map(|i| ((q[i] - self.lo[i]) / self.cell).floor() as i64);
        let mut best: Option<(usize, f64)> = None;
        for dz in -reach..=reach {
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let g = [c[0] + dx, c[1] + dy, c[2] + dz];
                    if (0..3).any(|i| g[i] < 0 || g[i] >= self.dims[i] as i64) {
                        continue;
                    }
                    let k = ((g[2] as usize * self.dims[1]) + g[1] as usize) * self.dims[0]
                        + g[0] as usize;
                    for &i in &self.order[self.start[k]..self.start[k + 1]] {
                        let p = self.points[i];
                        let d = (0..3).map(|j| (p[j] - q[j]).powi(2)).sum::<f64>();
                        if best.is_none_or(|b| d < b.1) {
                            best = Some((i, d));
                        }
                    }
                }
            }
        }
        best
    }
}

/// The least-squares plane of mirror pairs `(p_i, q_i)` (module
/// documentation): `n` the top eigenvector of
/// `Σ v vᵀ − 4 Σ (m − m̄)(m − m̄)ᵀ` (sign as `previous`), `d = n·m̄`.
fn pair_plane(pairs: &[([f64; 3], [f64; 3])], previous: &Plane3) -> Option<Plane3> {
    let n = pairs.len() as f64;
    let mut mbar = [0.0; 3];
    for (p, q) in pairs {
        for i in 0..3 {
            mbar[i] += 0.5 * (p[i] + q[i]) / n;
        }
    }
    let mut a = [0.0; 9];
    for (p, q) in pairs {
        let v = [0, 1, 2].map(|i| p[i] - q[i]);
        let m = [0, 1, 2].map(|i| 0.5 * (p[i] + q[i]) - mbar[i]);
        for r in 0..3 {
            for c in 0..3 {
                a[r * 3 + c] += v[r] * v[c] - 4.0 * m[r] * m[c];
            }
        }
    }
    let (mut values, mut e) = ([0.0; 3], [0.0; 3]);
    if !symmetric_eigen(&mut a, 3, &mut values, &mut e) {
        return None;
    }
    let mut normal = [a[6], a[7], a[8]];
    if dot3(normal, previous.normal) < 0.0 {
        normal = normal.map(|v| -v);
    }
    Some(Plane3 {
        normal,
        offset: dot3(normal, mbar),
    })
}

/// Two unit vectors completing `n` to an orthonormal frame.
fn tangents(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let a = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let cross = |u: [f64; 3], v: [f64; 3]| {
        [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ]
    };
    let t1 = cross(n, a);
    let l = dot3(t1, t1).sqrt();
    let t1 = t1.map(|v| v / l);
    (t1, cross(n, t1))
}

/// The Gauss–Newton step of the point-to-plane distance
/// `Σ ((R(p) − q)·ν)²` over the pairs `(p, q, ν)` (module documentation).
fn point_to_plane_step(pairs: &[([f64; 3], [f64; 3], [f64; 3])], plane: &Plane3) -> Option<Plane3> {
    let n = plane.normal;
    let (t1, t2) = tangents(n);
    let (mut jtj, mut jtr) = ([0.0; 9], [0.0; 3]);
    for (p, q, nu) in pairs {
        let r = plane.reflect(*p);
        let res = dot3([r[0] - q[0], r[1] - q[1], r[2] - q[2]], *nu);
        let s = plane.side(*p);
        let (nn, nt1, nt2) = (dot3(n, *nu), dot3(t1, *nu), dot3(t2, *nu));
        let j = [
            -2.0 * dot3(t1, *p) * nn - 2.0 * s * nt1,
            -2.0 * dot3(t2, *p) * nn - 2.0 * s * nt2,
            2.0 * nn,
        ];
        for a in 0..3 {
            jtr[a] += j[a] * res;
            for b in 0..3 {
                jtj[a * 3 + b] += j[a] * j[b];
            }
        }
    }
    let mut rhs = jtr.map(|v| -v);
    if !metabezier_core::linalg::cholesky_solve(&mut jtj, &mut rhs, 3) {
        return None;
    }
    let moved = [0, 1, 2].map(|i| n[i] + rhs[0] * t1[i] + rhs[1] * t2[i]);
    let l = dot3(moved, moved).sqrt();
    // d changes by Δd; keep the plane's point along n: d' = d + Δd in the
    // new normal's terms (small steps).
    Some(Plane3 {
        normal: moved.map(|v| v / l),
        offset: (plane.offset + rhs[2]) / l,
    })
}

/// Estimates the mid-sagittal plane of bone-surface points by trimmed ICP
/// of the points to their mirror image (module documentation), starting
/// from `initial`: the closed-form point-to-point plane first, then
/// point-to-plane Gauss–Newton steps until the plane moves by less than
/// 0.001° and 0.001 mm, or `max_iterations`. `None` when fewer than 20
/// pairs are found (the initial plane is too far off, or there are too
/// few points) or a step is singular.
pub fn estimate_symmetry_plane(
    surface: &SurfacePoints,
    initial: Plane3,
    options: &IcpOptions,
) -> Option<SymmetryPlane> {
    let cell = 2.0;
    let grid = Grid::new(&surface.points, cell);
    let reach = (options.search_mm / cell).ceil().max(1.0) as i64;
    let limit = options.search_mm * options.search_mm;
    let moving: Vec<[f64; 3]> = surface
        .points
        .iter()
        .step_by(options.stride.max(1))
        .copied()
        .collect();
    let mut plane = initial;
    let mut result = None;
    for it in 1..=options.max_iterations.max(1) {
        let mut pairs: Vec<(f64, [f64; 3], usize)> = moving
            .iter()
            .filter_map(|&p| {
                grid.nearest(plane.reflect(p), reach)
                    .filter(|(_, d)| *d <= limit)
                    .map(|(q, d)| (d, p, q))
            })
            .collect();
        if pairs.len() < 20 {
            return None;
        }
        pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
        pairs.truncate(((pairs.len() as f64) * options.keep.clamp(0.05, 1.0)).ceil() as usize);
        let rms = (pairs.iter().map(|p| p.0).sum::<f64>() / pairs.len() as f64).sqrt();
        let next = if it == 1 {
            let kept: Vec<_> = pairs.iter().map(|p| (p.1, surface.points[p.2])).collect();
            pair_plane(&kept, &plane)?
        } else {
            let kept: Vec<_> = pairs
                .iter()
                .map(|p| (p.1, surface.points[p.2], surface.normals[p.2]))
                .collect();
            point_to_plane_step(&kept, &plane)?
        };
        let moved = (next.angle_deg(&plane), (next.offset - plane.offset).abs());
        result = Some(SymmetryPlane {
            plane: next,
            rms_mm: rms,
            pairs: pairs.len(),
            iterations: it,
        });
        plane = next;
        if moved.0 < 1e-3 && moved.1 < 1e-3 {
            break;
        }
    }
    result
}

/// The mid-sagittal plane of a volume: [`estimate_symmetry_plane`] on its
/// bone surface at `threshold` from the plane of the in-slice midline
/// `initial` ([`Plane3::from_midline`]), run twice: with an 8 mm search,
/// then with a 3 mm search from the first result.
pub fn mid_sagittal_plane(
    volume: &Volume,
    threshold: i16,
    initial: &MidLine,
) -> Option<SymmetryPlane> {
    let surface = bone_surface_points(volume, threshold, None);
    let coarse = estimate_symmetry_plane(
        &surface,
        Plane3::from_midline(initial),
        &IcpOptions::default(),
    )?;
    let fine = IcpOptions {
        search_mm: 3.0,
        stride: 2,
        ..IcpOptions::default()
    };
    estimate_symmetry_plane(&surface, coarse.plane, &fine)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ct::Spacing;

    #[test]
    fn a_plane_reflects_points_across_itself() {
        let p = Plane3::through([10.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
        let r = p.reflect([13.0, 2.0, 5.0]);
        assert!((r[0] - 7.0).abs() < 1e-12 && r[1] == 2.0 && r[2] == 5.0);
        let line = p.trace(3.0, Point::new(0.0, 4.0)).unwrap();
        assert!((line.point.x - 10.0).abs() < 1e-12 && line.tilt.abs() < 1e-12);
    }

    #[test]
    fn the_trace_of_a_tilted_plane_is_the_midline_it_came_from() {
        let line = MidLine {
            point: Point::new(50.0, 60.0),
            tilt: 0.1,
        };
        let t = Plane3::from_midline(&line)
            .trace(7.0, Point::new(50.0, 60.0))
            .unwrap();
        assert!((t.tilt - 0.1).abs() < 1e-12);
        assert!(line.side(t.point).abs() < 1e-9);
    }

    #[test]
    fn pairs_of_an_exact_reflection_give_the_plane() {
        let truth = Plane3::through([1.0, 2.0, 3.0], [0.9, 0.3, 0.1]);
        let pairs: Vec<([f64; 3], [f64; 3])> = (0..50)
            .map(|i| {
                let p = [
                    (i as f64 * 1.3).sin() * 20.0,
                    (i as f64 * 0.7).cos() * 30.0,
                    i as f64,
                ];
                (p, truth.reflect(p))
            })
            .collect();
        let start = Plane3::through([0.0; 3], [1.0, 0.0, 0.0]);
        let got = pair_plane(&pairs, &start).unwrap();
        assert!(got.angle_deg(&truth) < 1e-9);
        assert!((got.offset - truth.offset).abs() < 1e-9);
    }

    #[test]
    fn the_surface_of_a_cube_is_its_faces() {
        let v = Volume::new(
            5,
            5,
            5,
            Spacing {
                x: 1.0,
                y: 1.0,
                z: 1.0,
            },
            [0.0; 3],
            (0..125)
                .map(|i| {
                    let (x, y, z) = (i % 5, (i / 5) % 5, i / 25);
                    if (1..4).contains(&x) && (1..4).contains(&y) && (1..4).contains(&z) {
                        1000
                    } else {
                        0
                    }
                })
                .collect(),
        )
        .unwrap();
        assert_eq!(bone_surface_points(&v, 300, None).points.len(), 26);
    }
}

#[cfg(test)]
mod synthetic {
    use super::*;
    use crate::ct::Spacing;

    /// An egg-shaped shell (bone 1000 HU, 5 mm thick) symmetric about
    /// `truth` only: in the frame of `truth`'s normal `e1`, and `e2`, `e3`,
    /// `f = |(x/a, y/b, z/c)| + 0.12·y/b` lies in `[0.9, 1]`.
    fn egg(truth: &Plane3, centre: [f64; 3], sp: Spacing, dims: [usize; 3]) -> Volume {
        let e1 = truth.normal;
        let t = [0.0, 0.0, 1.0];
        let mut e2 = [
            t[1] * e1[2] - t[2] * e1[1],
            t[2] * e1[0] - t[0] * e1[2],
            t[0] * e1[1] - t[1] * e1[0],
        ];
        let l = dot3(e2, e2).sqrt();
        e2 = e2.map(|v| v / l);
        let e3 = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        let [nx, ny, nz] = dims;
        let mut data = vec![-1000i16; nx * ny * nz];
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let p = [x as f64 * sp.x, y as f64 * sp.y, z as f64 * sp.z];
                    let d = [0, 1, 2].map(|i| p[i] - centre[i]);
                    let (u, v, w) = (dot3(d, e1), dot3(d, e2), dot3(d, e3));
                    let f = ((u / 55.0).powi(2) + (v / 70.0).powi(2) + (w / 60.0).powi(2)).sqrt()
                        + 0.12 * v / 70.0;
                    if (0.92..=1.0).contains(&f) {
                        data[(z * ny + y) * nx + x] = 1000;
                    }
                }
            }
        }
        Volume::new(nx, ny, nz, sp, [0.0; 3], data).unwrap()
    }

    #[test]
    fn the_plane_of_a_synthetic_skull_is_found_to_half_a_degree_and_half_a_millimetre() {
        let sp = Spacing {
            x: 1.0,
            y: 1.0,
            z: 2.0,
        };
        let centre = [80.0, 85.0, 40.0];
        // Yaw 7° and roll 4°: a plane no single slice's line can express.
        let (yaw, roll) = (7f64.to_radians(), 4f64.to_radians());
        let normal = [yaw.cos() * roll.cos(), -yaw.sin() * roll.cos(), roll.sin()];
        let truth = Plane3::through(centre, normal);
        let v = egg(&truth, centre, sp, [160, 170, 40]);
        // The in-slice start: 3° and 3 mm off, no roll.
        let start = MidLine {
            point: Point::new(centre[0] + 3.0, centre[1]),
            tilt: (7f64 - 3.0).to_radians(),
        };
        let got = mid_sagittal_plane(&v, 300, &start).unwrap();
        let angle = got.plane.angle_deg(&truth);
        let offset = got.plane.side(centre).abs();
        eprintln!(
            "plane: {angle:.3}°, {offset:.3} mm, residual {:.3} mm, {} iterations",
            got.rms_mm, got.iterations
        );
        assert!(angle < 0.5, "angle {angle}°");
        assert!(offset < 0.5, "offset {offset} mm");
        assert!(got.rms_mm < 1.0, "rms {}", got.rms_mm);
    }
}
