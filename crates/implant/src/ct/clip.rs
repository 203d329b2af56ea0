//! Clipping an implant cross-section to the tissue that is not bone, so the
//! implant never occupies intact bone and its end faces follow the bone's
//! cut edge.
//!
//! The section `P` (a closed polygon in the slice's millimetre frame) and
//! the bone `{HU ≥ threshold}` are combined in one field sampled on a grid
//! `s` times finer than the pixels and aligned with the pixel centres:
//! `f(p) = min(K·d_P(p), threshold − HU(p))`, where `d_P` is the signed
//! distance to `P` (positive inside, exact within two grid cells of `P`'s
//! edges, ±∞ farther away), `HU(p)` is the bilinear interpolation of the
//! pixel centres and `K = 400 HU/mm` brings both terms to comparable
//! slopes. The clipped section is the largest loop of `f ≥ ½` by marching
//! squares ([`super::contour::marching_squares`], linear interpolation on
//! the cell edges). Every pixel centre is a grid node, so a bone pixel
//! (`HU ≥ threshold`, `f ≤ 0`) is never inside the result: the clipped
//! section voxelises onto no bone pixel. The even-odd sign of `d_P` also
//! resolves a self-intersecting section (an inner wall that folds over).

use super::contour::marching_squares;
use super::volume::Slice;
use crate::geometry::{segment_foot, Point, Polyline};

/// The slope factor `K` (HU per mm) of the distance term.
const K_HU_PER_MM: f64 = 400.0;

/// The result of [`clip_to_tissue`].
#[derive(Clone, Debug, PartialEq)]
pub struct Clipped {
    /// The largest loop of the section without bone (counter-clockwise).
    pub section: Polyline,
    /// The absolute shoelace area of the section before clipping (mm²).
    pub area_before: f64,
    /// The area of `section` (mm²).
    pub area_after: f64,
    /// Loops dropped besides the largest one (pieces cut off by bone).
    pub dropped_loops: usize,
}

/// The distance from `p` to segment `ab`.
fn segment_distance(p: Point, a: Point, b: Point) -> f64 {
    p.distance(segment_foot(p, a, b).1)
}

/// A grid of nodes `origin + (i·h.x, j·h.y)`, `nx × ny`, row-major.
struct Grid {
    origin: Point,
    h: Point,
    nx: usize,
    ny: usize,
}

impl Grid {
    fn node(&self, i: usize, j: usize) -> Point {
        self.origin + Point::new(i as f64 * self.h.x, j as f64 * self.h.y)
    }

    /// `K·d_P` at every node: the sign by scanline crossings (even-odd), the
    /// magnitude exact within two cells of an edge and `K·10⁶` elsewhere.
    fn signed_distance(&self, poly: &Polyline) -> Vec<f64> {
        let mut dist: Vec<f64> = vec![1e6; self.nx * self.ny];
        let n = poly.points.len();
        for k in 0..n {
            let (a, b) = (poly.points[k], poly.points[(k + 1) % n]);
            let lo = Point::new(a.x.min(b.x), a.y.min(b.y)) - self.origin;
            let hi = Point::new(a.x.max(b.x), a.y.max(b.y)) - self.origin;
            let i0 = ((lo.x / self.h.x).floor() - 2.0).max(0.0) as usize;
            let j0 = ((lo.y / self.h.y).floor() - 2.0).max(0.0) as usize;
            let i1 = (((hi.x / self.h.x).ceil() + 2.0).max(0.0) as usize).min(self.nx - 1);
            let j1 = (((hi.y / self.h.y).ceil() + 2.0).max(0.0) as usize).min(self.ny - 1);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    let d = segment_distance(self.node(i, j), a, b);
                    let slot = &mut dist[j * self.nx + i];
                    *slot = (*slot).min(d);
                }
            }
        }
        for j in 0..self.ny {
            let y = self.origin.y + j as f64 * self.h.y;
            let mut xs: Vec<f64> = Vec::new();
            for k in 0..n {
                let (a, b) = (poly.points[k], poly.points[(k + 1) % n]);
                if (a.y > y) != (b.y > y) {
                    xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
                }
            }
            xs.sort_by(f64::total_cmp);
            for i in 0..self.nx {
                let x = self.origin.x + i as f64 * self.h.x;
                let inside = xs.iter().filter(|&&c| c > x).count() % 2 == 1;
                let slot = &mut dist[j * self.nx + i];
                *slot = if inside { *slot } else { -*slot } * K_HU_PER_MM;
            }
        }
        dist
    }
}

/// Clips the closed polygon `section` (mm, the frame of `slice`) to the
/// tissue below `threshold` HU on a grid `subdivision` times finer than the
/// pixels (see the module documentation). `None` when nothing of the
/// section remains.
pub fn clip_to_tissue(
    section: &Polyline,
    slice: &Slice,
    threshold: i16,
    subdivision: usize,
) -> Option<Clipped> {
    clip_to_tissue_keeping(section, slice, threshold, subdivision, &[])
}

/// [`clip_to_tissue`], except within the capsules `keep` (the points within
/// a distance `r` of a segment `pq`, as `(p, q, r)` in mm), where the
/// section is kept as it is: the last millimetre of the implant's outer
/// wall at each seat, so that its outer surface meets the bone where it was
/// designed to rather than where its last fraction of a millimetre dips
/// below the threshold iso-contour (a feather edge whose direction is not
/// the wall's; issue 48).
pub fn clip_to_tissue_keeping(
    section: &Polyline,
    slice: &Slice,
    threshold: i16,
    subdivision: usize,
    keep: &[(Point, Point, f64)],
) -> Option<Clipped> {
    let (lo, hi) = section.bbox()?;
    let s = subdivision.max(1) as f64;
    let (sx, sy) = (slice.sx, slice.sy);
    // Pixel-aligned box around the section with a two-pixel margin, within
    // the image and its two-pixel margin: the grid's size is bounded by the
    // image's whatever the section (a wild wall may run metres away), and
    // what lies outside the image is cut off (the plausibility checks
    // measure the section before clipping).
    let (cmax, rmax) = (slice.nx as f64 + 1.0, slice.ny as f64 + 1.0);
    let c0 = ((lo.x / sx).floor() - 2.0).max(-2.0);
    let r0 = ((lo.y / sy).floor() - 2.0).max(-2.0);
    let c1 = ((hi.x / sx).ceil() + 2.0).min(cmax);
    let r1 = ((hi.y / sy).ceil() + 2.0).min(rmax);
    if c1 <= c0 || r1 <= r0 {
        return None;
    }
    let grid = Grid {
        origin: Point::new(c0 * sx, r0 * sy),
        h: Point::new(sx / s, sy / s),
        nx: ((c1 - c0) * s) as usize + 1,
        ny: ((r1 - r0) * s) as usize + 1,
    };
    let mut field = grid.signed_distance(section);
    for j in 0..grid.ny {
        for i in 0..grid.nx {
            let (row, col) = (r0 + j as f64 / s, c0 + i as f64 / s);
            let node = grid.node(i, j);
            if keep
                .iter()
                .any(|&(p, q, r)| segment_distance(node, p, q) <= r)
            {
                continue;
            }
            let hu = slice.bilinear(row, col, -1024.0);
            let f = &mut field[j * grid.nx + i];
            *f = f.min(threshold as f64 - hu);
        }
    }
    let loops = marching_squares(&field, grid.nx, grid.ny, 0.5, grid.h.x, grid.h.y);
    let count = loops.iter().filter(|l| l.signed_area() > 0.0).count();
    let best = loops
        .into_iter()
        .filter(|l| l.signed_area() > 0.0)
        .max_by(|a, b| a.signed_area().total_cmp(&b.signed_area()))?;
    let moved = Polyline::closed(best.points.iter().map(|&p| p + grid.origin).collect());
    Some(Clipped {
        area_after: moved.signed_area(),
        area_before: section.signed_area().abs(),
        section: moved,
        dropped_loops: count - 1,
    })
}
