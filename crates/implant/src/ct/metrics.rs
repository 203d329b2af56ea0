//! Implant metrics of the AutoImplant challenge (Li, Egger et al.,
//! "AutoImplant 2020 — first MICCAI challenge on automatic cranial implant
//! design", IEEE TMI 40(9), 2021; and "Towards clinical applicability and
//! computational efficiency in automatic cranial implant design: an overview
//! of the AutoImplant 2021 cranial implant design challenge", MedIA 88, 2023):
//! Dice, boundary Dice and HD95, plus contour deviations between polylines.

use super::edt::edt_squared;
use super::error::CtError;
use super::mask::Mask3;
use crate::geometry::Polyline;

fn check(a: &Mask3, b: &Mask3) -> Result<(), CtError> {
    if a.same_grid(b) {
        Ok(())
    } else {
        Err(CtError::GridMismatch {
            a: [a.nx, a.ny, a.nz],
            b: [b.nx, b.ny, b.nz],
        })
    }
}

/// The Dice coefficient (Dice 1945) `2|A ∩ B| / (|A| + |B|)`; 1 when both
/// masks are empty.
pub fn dice(a: &Mask3, b: &Mask3) -> Result<f64, CtError> {
    check(a, b)?;
    let inter = a
        .data
        .iter()
        .zip(&b.data)
        .filter(|(x, y)| **x && **y)
        .count();
    let total = a.count() + b.count();
    Ok(if total == 0 {
        1.0
    } else {
        2.0 * inter as f64 / total as f64
    })
}

/// Boundary Dice (AutoImplant 2021's bDSC): the Dice of `a` and `b`
/// restricted to the voxels within `margin_mm` (Euclidean, in mm) of the
/// defective skull `skull`; 10 mm in the challenge.
pub fn boundary_dice(a: &Mask3, b: &Mask3, skull: &Mask3, margin_mm: f64) -> Result<f64, CtError> {
    check(a, b)?;
    check(a, skull)?;
    let d2 = edt_squared(skull);
    let m2 = margin_mm * margin_mm;
    let (mut inter, mut total) = (0usize, 0usize);
    for ((&x, &y), &d) in a.data.iter().zip(&b.data).zip(&d2) {
        if d <= m2 {
            inter += (x && y) as usize;
            total += x as usize + y as usize;
        }
    }
    Ok(if total == 0 {
        1.0
    } else {
        2.0 * inter as f64 / total as f64
    })
}

/// The surface of a mask: its voxels with a face neighbour (6-connectivity)
/// outside the mask or outside the grid (as `A ⊕ erosion(A)` in medpy,
/// used by the AutoImplant evaluation). An axis of size 1 has no
/// neighbours, so a one-slice mask gets its 2D boundary (4-connectivity).
pub fn surface(m: &Mask3) -> Mask3 {
    let (nx, ny, nz) = (m.nx, m.ny, m.nz);
    let mut s = Mask3::new(nx, ny, nz, m.spacing);
    // Whether the neighbour at offset `d` along an axis of size `n` is
    // outside the mask (outside the grid counts as outside).
    let out = |i: usize, n: usize, d: i64, f: &dyn Fn(usize) -> bool| -> bool {
        if n == 1 {
            return false;
        }
        let j = i as i64 + d;
        j < 0 || j >= n as i64 || !f(j as usize)
    };
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if !m.get(z, y, x) {
                    continue;
                }
                let open = [-1, 1].iter().any(|&d| {
                    out(x, nx, d, &|j| m.get(z, y, j))
                        || out(y, ny, d, &|j| m.get(z, j, x))
                        || out(z, nz, d, &|j| m.get(j, y, x))
                });
                if open {
                    s.set(z, y, x, true);
                }
            }
        }
    }
    s
}

/// Distances (mm) from each surface voxel of `a` to the nearest surface
/// voxel of `b`.
pub fn surface_distances(a: &Mask3, b: &Mask3) -> Result<Vec<f64>, CtError> {
    check(a, b)?;
    let sa = surface(a);
    let d2 = edt_squared(&surface(b));
    Ok(sa
        .data
        .iter()
        .zip(d2)
        .filter(|(s, _)| **s)
        .map(|(_, d)| d.sqrt())
        .collect())
}

/// The `p`-th percentile (0..=100) with linear interpolation between order
/// statistics (numpy's default): rank `p/100·(n − 1)`.
pub fn percentile(values: &[f64], p: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let rank = (p / 100.0).clamp(0.0, 1.0) * (v.len() - 1) as f64;
    let lo = rank.floor() as usize;
    let hi = rank.ceil() as usize;
    Some(v[lo] + (rank - lo as f64) * (v[hi] - v[lo]))
}

/// HD95 in mm: the 95th percentile of the symmetric surface distance, i.e.
/// of the distances from `a`'s surface voxels to `b`'s surface and from
/// `b`'s to `a`'s, pooled (Huttenlocher et al., "Comparing images using the
/// Hausdorff distance", IEEE TPAMI 1993, for the Hausdorff distance; the
/// 95th-percentile variant as in medpy's `hd95` used by AutoImplant).
/// Distances use the anisotropic spacing via the exact EDT. Error when a
/// mask is empty.
pub fn hd95(a: &Mask3, b: &Mask3) -> Result<f64, CtError> {
    if a.count() == 0 || b.count() == 0 {
        return Err(CtError::EmptyMask);
    }
    let mut d = surface_distances(a, b)?;
    d.extend(surface_distances(b, a)?);
    Ok(percentile(&d, 95.0).expect("non-empty surfaces"))
}

/// Mean and maximum deviation between two contours.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContourDeviation {
    /// Mean distance in mm.
    pub mean: f64,
    /// Maximum distance in mm (the symmetric Hausdorff distance of the
    /// sampled curves).
    pub max: f64,
}

/// Symmetric contour deviation between polylines `a` and `b`: both are
/// sampled by arc length at spacing ≤ `step_mm` (plus their vertices, so
/// the max is exact at corners), each sample's distance to
/// the other polyline is taken, and the mean and max over all samples of
/// both are returned.
pub fn contour_deviation(
    a: &Polyline,
    b: &Polyline,
    step_mm: f64,
) -> Result<ContourDeviation, CtError> {
    if a.points.is_empty() || b.points.is_empty() || step_mm.is_nan() || step_mm <= 0.0 {
        return Err(CtError::BadDeviationInput);
    }
    let mut d = Vec::new();
    for (p, q) in [(a, b), (b, a)] {
        let n = ((p.length() / step_mm).ceil() as usize).max(1) + usize::from(!p.closed);
        for s in p.resample(n).points.iter().chain(&p.points) {
            d.push(q.distance_to(*s));
        }
    }
    let mean = d.iter().sum::<f64>() / d.len() as f64;
    let max = d.iter().copied().fold(0.0, f64::max);
    Ok(ContourDeviation { mean, max })
}
