//! Voxelisation of a stack of cross-section polygons onto a CT grid: a voxel
//! is inside when its centre `(col·sx, row·sy)` is inside its slice's
//! polygon by the even-odd rule, evaluated per row by scanline crossings
//! (equivalent to the crossing-number point-in-polygon test per voxel).

use super::mask::Mask3;
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
        if *z >= nz || poly.points.len() < 3 {
            continue;
        }
        let n = poly.points.len();
        for row in 0..ny {
            let y = row as f64 * spacing.y;
            let mut xs: Vec<f64> = Vec::new();
            for i in 0..n {
                let (a, b) = (poly.points[i], poly.points[(i + 1) % n]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                // Columns whose centre x lies in [pair0, pair1).
                let c0 = (pair[0] / spacing.x).ceil().max(0.0) as usize;
                let c1 = ((pair[1] / spacing.x).ceil().max(0.0) as usize).min(nx);
                for col in c0..c1 {
                    m.set(*z, row, col, true);
                }
            }
        }
    }
    m
}
