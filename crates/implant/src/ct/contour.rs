//! Bone contours by marching squares, the 2D case of marching cubes
//! (Lorensen & Cline, "Marching cubes: a high resolution 3D surface
//! construction algorithm", SIGGRAPH 1987), and the outer / inner table
//! contours of the skull ring.
//!
//! The field is sampled at pixel centres; a pixel is inside when its value
//! is ≥ the level, and crossings on cell edges are placed by linear
//! interpolation `t = (level − f_u)/(f_v − f_u)`, giving sub-pixel contours.
//! The image is padded with an outside border, so every contour is a closed
//! loop. Saddle cells always join the inside corners, so the loops follow
//! 8-connectivity of the inside, like [`super::bone::largest_component_2d`].
//! Loops are oriented with the inside on their left in the `(x, y)` frame
//! (`x = col·sx`, `y = row·sy`): outer boundaries have positive shoelace
//! area, holes negative.

use super::error::CtError;
use super::mask::Mask2;
use super::volume::Slice;
use crate::geometry::Point;
use crate::geometry::Polyline;

/// Closed iso-contours `f = level` of a row-major field of `ny × nx` samples
/// at pixel centres, in mm (`x = col·sx`, `y = row·sy`), inside (`f ≥ level`)
/// on the left. Loops shorter than 3 vertices are dropped.
pub fn marching_squares(
    field: &[f64],
    nx: usize,
    ny: usize,
    level: f64,
    sx: f64,
    sy: f64,
) -> Vec<Polyline> {
    assert_eq!(field.len(), nx * ny, "field size");
    let outside = level - 1.0;
    let value = |r: i64, c: i64| -> f64 {
        if r < 0 || c < 0 || r >= ny as i64 || c >= nx as i64 {
            outside
        } else {
            let v = field[r as usize * nx + c as usize];
            if v.is_nan() {
                outside
            } else {
                v
            }
        }
    };
    // Edge keys on the padded grid: rows and cols -1..=n map to 0..=n+1.
    let w = nx + 2;
    let key = |r: i64, c: i64, vertical: bool| -> usize {
        (((r + 1) as usize * w + (c + 1) as usize) << 1) | vertical as usize
    };
    let nkeys = (ny + 2) * w * 2;
    // next[k] = (end key, start point) of the segment starting at edge k.
    let mut next: Vec<Option<(usize, Point)>> = vec![None; nkeys];
    let mut starts = Vec::new();
    for r in -1..ny as i64 {
        for c in -1..nx as i64 {
            // Corners in positive cyclic order: (r,c) (r,c+1) (r+1,c+1) (r+1,c).
            let corners = [(r, c), (r, c + 1), (r + 1, c + 1), (r + 1, c)];
            let vals = corners.map(|(rr, cc)| value(rr, cc));
            let inside = vals.map(|v| v >= level);
            if inside.iter().all(|&b| b) || inside.iter().all(|&b| !b) {
                continue;
            }
            // Crossings on the four edges in cyclic order, as (key, point, exit?).
            let mut xs: Vec<(usize, Point, bool)> = Vec::with_capacity(4);
            for e in 0..4 {
                let (u, v) = (e, (e + 1) % 4);
                if inside[u] == inside[v] {
                    continue;
                }
                let t = (level - vals[u]) / (vals[v] - vals[u]);
                let (ru, cu) = corners[u];
                let (rv, cv) = corners[v];
                let row = ru as f64 + t * (rv - ru) as f64;
                let col = cu as f64 + t * (cv - cu) as f64;
                // The edge's key: named by its top/left corner.
                let k = match e {
                    0 => key(r, c, false),
                    1 => key(r, c + 1, true),
                    2 => key(r + 1, c, false),
                    _ => key(r, c, true),
                };
                xs.push((k, Point::new(col * sx, row * sy), inside[u]));
            }
            // Each exit joins the next entry in cyclic order.
            let m = xs.len();
            for i in 0..m {
                if !xs[i].2 {
                    continue;
                }
                let j = (1..m)
                    .map(|d| (i + d) % m)
                    .find(|&j| !xs[j].2)
                    .expect("an entry follows every exit");
                next[xs[i].0] = Some((xs[j].0, xs[i].1));
                starts.push(xs[i].0);
            }
        }
    }
    link_loops(&mut next, &starts)
}

/// Links the cell segments into closed loops: `next[k]` is the (end edge,
/// start point) of the segment starting at edge `k`, `starts` the edges
/// that start one. Repeated points are dropped, and loops shorter than 3
/// vertices.
fn link_loops(next: &mut [Option<(usize, Point)>], starts: &[usize]) -> Vec<Polyline> {
    let mut loops = Vec::new();
    for &s in starts {
        if next[s].is_none() {
            continue;
        }
        let mut pts = Vec::new();
        let mut k = s;
        while let Some((end, p)) = next[k].take() {
            if pts.last() != Some(&p) {
                pts.push(p);
            }
            k = end;
        }
        if pts.len() > 1 && pts.first() == pts.last() {
            pts.pop();
        }
        if pts.len() >= 3 {
            loops.push(Polyline::closed(pts));
        }
    }
    loops
}

/// The field for contouring a segmented bone mask at sub-pixel precision:
/// the HU value inside the mask, and `min(HU, threshold − 1)` outside it, so
/// that bone left out of the mask (other components) yields no contour.
pub fn masked_field(slice: &Slice, mask: &Mask2, threshold: i16) -> Vec<f64> {
    slice
        .data
        .iter()
        .zip(&mask.data)
        .map(|(&v, &m)| {
            if m {
                v as f64
            } else {
                (v as f64).min(threshold as f64 - 1.0)
            }
        })
        .collect()
}

/// The contour loops of the bone `mask` of `slice` at `threshold` HU
/// (marching squares on [`masked_field`]), sorted by decreasing |area|.
pub fn bone_loops(slice: &Slice, mask: &Mask2, threshold: i16) -> Vec<Polyline> {
    let f = masked_field(slice, mask, threshold);
    let mut loops = marching_squares(&f, slice.nx, slice.ny, threshold as f64, slice.sx, slice.sy);
    loops.sort_by(|a, b| b.signed_area().abs().total_cmp(&a.signed_area().abs()));
    loops
}

/// The outer and inner table contours of a skull slice, bone on the left.
#[derive(Clone, Debug, PartialEq)]
pub struct TableContours {
    /// The outer table: the outermost boundary around the head (closed when
    /// the ring is intact; an open arc between the defect ends when split).
    pub outer: Polyline,
    /// The inner table: the boundary of the cranial cavity (closed, negative
    /// area, when intact; the other open arc between the ends when split).
    pub inner: Polyline,
    /// Whether the bone ring is closed (no defect).
    pub intact: bool,
}

impl TableContours {
    /// Where the polar centre's height is read: the vertex mean of the
    /// outer table, or, for a ring broken twice (both tables whole closed
    /// loops of two pieces, [`table_contours`]), the mean of the two
    /// pieces' vertex means.
    pub fn vertex_mean(&self) -> Point {
        if !self.intact && self.outer.closed && self.inner.closed {
            (self.outer.vertex_mean() + self.inner.vertex_mean()) * 0.5
        } else {
            self.outer.vertex_mean()
        }
    }
}

/// Outer and inner table contours from the loops of [`bone_loops`].
///
/// - Intact ring (`ends = None`): the outer table is the loop of largest
///   positive area; the inner table is the hole (negative area) of largest
///   |area| inside it that contains the outer loop's vertex mean (the
///   cranial cavity, not a pore of the diploë). Error when there is no such
///   hole: the ring is open and the defect ends must be given.
/// - Interrupted ring (`ends = Some((a, b))`, points in mm at the two ends of
///   the bone gap, see [`super::defect`]): outer and inner tables are one
///   loop that turns around each bone end. It is cut at its points nearest
///   to `a` and `b` into two arcs; the outer table is the arc farther (mean
///   vertex distance) from the loop's vertex mean, the inner table the other
///   arc; both keep the loop's direction (bone on the left), so the outer
///   runs from one end to the other and the inner back. The bone end faces go to whichever arc the cut points leave them.
///   When `a` or `b` is more than 2 mm from that loop, the loops nearest
///   to them are used: one loop holding both is cut the same way; two
///   different loops (the ring broken twice, e.g. an artificial cut on a
///   slice with a real defect) are returned whole, the one holding `a` as
///   `outer`, the one holding `b` as `inner`, and the wall design reads
///   the envelope of both. Error [`CtError::NotOnContour`] when `a` or `b`
///   is more than 2 mm from every loop (the distance given is to the
///   largest loop).
pub fn table_contours(
    loops: &[Polyline],
    ends: Option<(Point, Point)>,
) -> Result<TableContours, CtError> {
    let outer = loops
        .iter()
        .filter(|l| l.signed_area() > 0.0)
        .max_by(|a, b| a.signed_area().total_cmp(&b.signed_area()))
        .ok_or(CtError::NoClosedContour)?;
    match ends {
        None => {
            let centre = outer.vertex_mean();
            let inner = loops
                .iter()
                .filter(|l| {
                    l.signed_area() < 0.0 && l.contains(centre) && outer.contains(l.points[0])
                })
                .min_by(|a, b| a.signed_area().total_cmp(&b.signed_area()))
                .ok_or(CtError::OpenRing)?;
            Ok(TableContours {
                outer: outer.clone(),
                inner: inner.clone(),
                intact: true,
            })
        }
        Some((a, b)) => {
            const TOL: f64 = 2.0;
            // The bone loop nearest to `p` (of positive area), within TOL.
            let holding = |what: &'static str, p: Point| -> Result<&Polyline, CtError> {
                let (loop_, d) = loops
                    .iter()
                    .filter(|l| l.signed_area() > 0.0)
                    .filter_map(|l| l.nearest(p).map(|n| (l, n.distance)))
                    .min_by(|x, y| x.1.total_cmp(&y.1))
                    .ok_or(CtError::NoClosedContour)?;
                if d > TOL {
                    let on_outer = outer.nearest(p).map_or(f64::INFINITY, |n| n.distance);
                    return Err(CtError::NotOnContour {
                        what,
                        distance_mm: on_outer,
                        tolerance_mm: TOL,
                    });
                }
                Ok(loop_)
            };
            let na = outer.nearest(a).expect("non-empty loop");
            let nb = outer.nearest(b).expect("non-empty loop");
            let ring = if na.distance <= TOL && nb.distance <= TOL {
                outer
            } else {
                let (la, lb) = (holding("A", a)?, holding("B", b)?);
                if !std::ptr::eq(la, lb) {
                    // The ring is broken twice (an artificial cut on a
                    // slice with a real defect): A and B end two pieces.
                    return Ok(two_pieces(la, lb));
                }
                la
            };
            let na = ring.nearest(a).expect("non-empty loop");
            let nb = ring.nearest(b).expect("non-empty loop");
            let centre = ring.vertex_mean();
            let arc1 = ring.sub_arc(&na, &nb);
            let arc2 = ring.sub_arc(&nb, &na);
            let mean_r = |p: &Polyline| {
                p.points.iter().map(|q| q.distance(centre)).sum::<f64>() / p.points.len() as f64
            };
            let (o, i) = if mean_r(&arc1) >= mean_r(&arc2) {
                (arc1, arc2)
            } else {
                (arc2, arc1)
            };
            Ok(TableContours {
                outer: o,
                inner: i,
                intact: false,
            })
        }
    }
}

/// The tables of a ring broken twice, A ending the piece `la` and B the
/// piece `lb`: each piece's whole loop, `la` as `outer` and `lb` as
/// `inner`. The design reads the outer table as the envelope of both
/// (the farthest crossing of a ray with either), which is the outer
/// surface of both pieces.
fn two_pieces(la: &Polyline, lb: &Polyline) -> TableContours {
    TableContours {
        outer: la.clone(),
        inner: lb.clone(),
        intact: false,
    }
}
