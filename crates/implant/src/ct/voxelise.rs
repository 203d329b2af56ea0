//! Voxelisation of a stack of cross-section polygons onto a CT grid: a voxel
//! is inside when its centre `(col·sx, row·sy)` is inside its slice's
//! polygon by the even-odd rule, evaluated per row by scanline crossings
//! (equivalent to the crossing-number point-in-polygon test per voxel).

use super::mask::Mask3;
use super::mesh::{slice_mesh, Mesh};
use super::volume::Spacing;
use crate::geometry::Polyline;

/// A mask on the `nx × ny × nz` grid with `spacing`, true inside
/// `sections[k].1` on slice `sections[k].0` (several polygons on one slice
/// are united); slices out of range are ignored.
pub fn voxelise(
    sections: &[(usize, Polyline)],
    nx: usize,
    ny: usize,
    nz: usize,
    spacing: Spacing,
) -> Mask3 {
    let mut m = Mask3::new(nx, ny, nz, spacing);
    for (z, poly) in sections {
        if *z < nz && poly.points.len() >= 3 {
            fill_even_odd(&mut m, *z, std::slice::from_ref(poly));
        }
    }
    m
}

/// A closed, outward-oriented mesh in voxel millimetres voxelised on the
/// `nx × ny × nz` grid with `spacing`: slice `k` is the mesh's
/// cross-section ([`slice_mesh`]) at `z = k·sz` moved by `10⁻³·sz` into the
/// mesh's z range (so a section lofted exactly at a slice height is cut
/// just inside it, even after the single-precision round trip of an STL in
/// a rotated patient frame, about 10⁻⁵ mm), filled by the even-odd rule
/// over all its loops (holes stay empty). Slices outside the mesh's z range
/// stay empty.
pub fn voxelise_mesh(mesh: &Mesh, nx: usize, ny: usize, nz: usize, spacing: Spacing) -> Mask3 {
    let mut m = Mask3::new(nx, ny, nz, spacing);
    let (lo, hi) = mesh
        .vertices
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v[2]), hi.max(v[2]))
        });
    let eps = 1e-3 * spacing.z;
    for k in 0..nz {
        let z = k as f64 * spacing.z;
        if z < lo - eps || z > hi + eps {
            continue;
        }
        let h = if z - eps >= lo { z - eps } else { z + eps };
        let loops = slice_mesh(mesh, h);
        fill_even_odd(&mut m, k, &loops);
    }
    m
}

/// Sets the voxels of slice `k` whose centres lie inside `loops` by the
/// even-odd rule (scanline crossings of all loops together).
fn fill_even_odd(m: &mut Mask3, k: usize, loops: &[Polyline]) {
    let sp = m.spacing;
    for row in 0..m.ny {
        let y = row as f64 * sp.y;
        let mut xs: Vec<f64> = Vec::new();
        for poly in loops {
            let n = poly.points.len();
            for i in 0..n {
                let (a, b) = (poly.points[i], poly.points[(i + 1) % n]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            let c0 = (pair[0] / sp.x).ceil().max(0.0) as usize;
            let c1 = ((pair[1] / sp.x).ceil().max(0.0) as usize).min(m.nx);
            for col in c0..c1 {
                m.set(k, row, col, true);
            }
        }
    }
}
