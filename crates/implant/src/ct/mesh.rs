//! Triangle meshes: lofting a stack of closed cross-sections into a closed
//! surface, with checks of watertightness and orientation.

use std::collections::HashMap;

use super::error::CtError;
use super::triangulate::ear_clip;
use crate::geometry::Point;
use crate::geometry::Polyline;

/// An indexed triangle mesh in mm.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions (x, y, z).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub triangles: Vec<[usize; 3]>,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

impl Mesh {
    /// Signed volume by the divergence theorem, `Σ v0·(v1 × v2) / 6` over the
    /// triangles; positive for a closed mesh with outward orientation.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i]);
                let k = cross(b, c);
                a[0] * k[0] + a[1] * k[1] + a[2] * k[2]
            })
            .sum::<f64>()
            / 6.0
    }

    /// Total surface area `Σ |(v1 − v0) × (v2 − v0)| / 2`.
    pub fn area(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i]);
                let k = cross(sub(b, a), sub(c, a));
                (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt() / 2.0
            })
            .sum()
    }

    /// The unit normal of triangle `t` by the right-hand rule (zero if
    /// degenerate).
    pub fn normal(&self, t: usize) -> [f64; 3] {
        let [a, b, c] = self.triangles[t].map(|i| self.vertices[i]);
        let k = cross(sub(b, a), sub(c, a));
        let l = (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
        if l > 0.0 {
            [k[0] / l, k[1] / l, k[2] / l]
        } else {
            [0.0; 3]
        }
    }

    /// Watertight: every undirected edge is shared by exactly two triangles
    /// (a closed 2-manifold boundary, no holes or T-junctions).
    pub fn is_watertight(&self) -> bool {
        let mut count: HashMap<(usize, usize), u32> = HashMap::new();
        for t in &self.triangles {
            for e in 0..3 {
                let (a, b) = (t[e], t[(e + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_default() += 1;
            }
        }
        !count.is_empty() && count.values().all(|&c| c == 2)
    }

    /// Consistently oriented outward: each directed edge appears exactly once
    /// (so neighbours traverse their shared edge in opposite directions), and
    /// the signed volume is positive.
    pub fn is_consistently_oriented(&self) -> bool {
        let mut count: HashMap<(usize, usize), u32> = HashMap::new();
        for t in &self.triangles {
            for e in 0..3 {
                *count.entry((t[e], t[(e + 1) % 3])).or_default() += 1;
            }
        }
        count.values().all(|&c| c == 1) && self.signed_volume() > 0.0
    }
}

/// The polygon oriented with positive area (counter-clockwise in (x, y)).
fn positive(p: &Polyline) -> Polyline {
    if p.signed_area() < 0.0 {
        p.reversed()
    } else {
        p.clone()
    }
}

/// `n` points of the closed polyline `ring` spaced evenly by arc length
/// between consecutive `anchors` (each anchor's nearest point on the ring
/// is a sample): a feature the resampling must keep (the seats, where the
/// implant meets the bone) is not cut off between two samples. Each arc
/// between anchors gets samples in proportion to its length, at least one;
/// without anchors (or with more anchors than `n`), [`Polyline::resample`].
pub fn resample_through(ring: &Polyline, anchors: &[Point], n: usize) -> Polyline {
    let cum = ring.cumulative_lengths();
    let total = cum.last().copied().unwrap_or(0.0);
    let mut at: Vec<f64> = anchors
        .iter()
        .filter_map(|&a| ring.nearest(a))
        .map(|m| {
            let (p, q) = ring.segment(m.segment);
            cum[m.segment] + m.t * p.distance(q)
        })
        .collect();
    at.sort_by(f64::total_cmp);
    at.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    if at.is_empty() || at.len() > n || total <= 0.0 {
        return ring.resample(n);
    }
    let m = at.len();
    let lens: Vec<f64> = (0..m)
        .map(|k| {
            if k + 1 < m {
                at[k + 1] - at[k]
            } else {
                at[0] + total - at[k]
            }
        })
        .collect();
    // Largest remainders, at least one sample an arc.
    let spare = (n - m) as f64;
    let mut counts: Vec<usize> = lens
        .iter()
        .map(|l| 1 + (spare * l / total).floor() as usize)
        .collect();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&i, &j| {
        let f = |k: usize| spare * lens[k] / total - (spare * lens[k] / total).floor();
        f(j).total_cmp(&f(i)).then(i.cmp(&j))
    });
    let mut left = n - counts.iter().sum::<usize>();
    for &k in order.iter().cycle().take(m * 2) {
        if left == 0 {
            break;
        }
        counts[k] += 1;
        left -= 1;
    }
    // Arc positions from at[0] on, increasing, within one lap.
    let mut targets = Vec::with_capacity(n);
    for k in 0..m {
        for i in 0..counts[k] {
            targets.push(at[k] + lens[k] * i as f64 / counts[k] as f64);
        }
    }
    Polyline::closed(points_at_increasing(ring, &cum, &targets))
}

/// The points of the closed polyline `ring` (cumulative lengths `cum`,
/// perimeter last) at the increasing arc positions `targets`, which span at
/// most one lap from a position in `[0, perimeter)`: one walk over at most
/// two laps of segments.
fn points_at_increasing(ring: &Polyline, cum: &[f64], targets: &[f64]) -> Vec<Point> {
    let n = ring.points.len();
    let total = cum[n];
    let mut out = Vec::with_capacity(targets.len());
    let mut i = 0; // segment of the doubled ring: i % n, starting at lap i / n
    for &t in targets {
        while i + 1 < 2 * n && (i / n) as f64 * total + cum[i % n + 1] < t {
            i += 1;
        }
        let (a, b) = (ring.points[i % n], ring.points[(i + 1) % n]);
        let start = (i / n) as f64 * total + cum[i % n];
        let l = a.distance(b);
        out.push(if l > 0.0 {
            a.lerp(b, ((t - start) / l).clamp(0.0, 1.0))
        } else {
            a
        });
    }
    out
}

/// The rings of a loft: each section oriented counter-clockwise,
/// resampled by arc length to `n` points, and its start rotated to best
/// match the previous ring (least squares over the `n` cyclic shifts, which
/// avoids twisting). Errors as [`loft`].
pub fn loft_rings(sections: &[Polyline], zs: &[f64], n: usize) -> Result<Vec<Polyline>, CtError> {
    loft_rings_through(sections, &[], zs, n)
}

/// [`loft_rings`] with each section's ring resampled through its
/// `anchors` ([`resample_through`]; none where `anchors` is shorter).
pub fn loft_rings_through(
    sections: &[Polyline],
    anchors: &[Vec<Point>],
    zs: &[f64],
    n: usize,
) -> Result<Vec<Polyline>, CtError> {
    if sections.len() < 2 || sections.len() != zs.len() {
        return Err(CtError::LoftSections {
            sections: sections.len(),
            heights: zs.len(),
        });
    }
    if n < 3 {
        return Err(CtError::LoftRingPoints { n });
    }
    if zs
        .windows(2)
        .any(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(CtError::LoftHeights);
    }
    let mut rings: Vec<Polyline> = Vec::with_capacity(sections.len());
    for (k, s) in sections.iter().enumerate() {
        if s.points.len() < 3 || s.signed_area().abs() <= 0.0 {
            return Err(CtError::DegenerateSection { index: k });
        }
        let mut closed = positive(s);
        closed.closed = true;
        let r = resample_through(&closed, anchors.get(k).map_or(&[][..], |a| &a[..]), n).points;
        let r = match rings.last() {
            None => r,
            Some(prev) => {
                let cost = |shift: usize| -> f64 {
                    (0..n)
                        .map(|i| r[(i + shift) % n].distance_squared(prev.points[i]))
                        .sum()
                };
                let best = (0..n)
                    .min_by(|&a, &b| cost(a).total_cmp(&cost(b)))
                    .unwrap_or(0);
                (0..n).map(|i| r[(i + best) % n]).collect()
            }
        };
        rings.push(Polyline::closed(r));
    }
    Ok(rings)
}

/// Lofts closed cross-sections `sections[k]` at heights `zs[k]` (mm,
/// strictly increasing) into a closed triangle mesh: the rings of
/// [`loft_rings`] joined by two triangles per quad, both ends capped by ear
/// clipping. The result is watertight and outward oriented.
pub fn loft(sections: &[Polyline], zs: &[f64], n: usize) -> Result<Mesh, CtError> {
    let rings = loft_rings(sections, zs, n)?;
    Ok(mesh_of_rings(&rings, zs))
}

/// The closed mesh through closed rings of equal length at heights `zs`
/// (as [`loft`] joins them: two triangles per quad, ear-clipped caps).
pub fn mesh_of_rings(rings: &[Polyline], zs: &[f64]) -> Mesh {
    let n = rings[0].points.len();
    let mut mesh = Mesh::default();
    for (ring, &z) in rings.iter().zip(zs) {
        mesh.vertices
            .extend(ring.points.iter().map(|p| [p.x, p.y, z]));
    }
    let v = |k: usize, i: usize| k * n + i % n;
    for k in 0..rings.len() - 1 {
        for i in 0..n {
            mesh.triangles.push([v(k, i), v(k, i + 1), v(k + 1, i + 1)]);
            mesh.triangles.push([v(k, i), v(k + 1, i + 1), v(k + 1, i)]);
        }
    }
    let last = rings.len() - 1;
    for t in ear_clip(&rings[0].points) {
        // Bottom cap faces −z: reverse the counter-clockwise triangles.
        mesh.triangles.push([v(0, t[0]), v(0, t[2]), v(0, t[1])]);
    }
    for t in ear_clip(&rings[last].points) {
        mesh.triangles
            .push([v(last, t[0]), v(last, t[1]), v(last, t[2])]);
    }
    mesh
}

/// The cross-section of a closed, outward-oriented mesh by the plane
/// `z = h`: closed loops, counter-clockwise around the solid (holes
/// clockwise). A vertex with `z ≥ h` counts as above the plane (simulation
/// of simplicity), so a plane through vertices gives no degenerate
/// crossings; crossings are keyed by their mesh edge, so a watertight mesh
/// gives closed loops.
pub fn slice_mesh(mesh: &Mesh, h: f64) -> Vec<Polyline> {
    let above = |i: usize| mesh.vertices[i][2] >= h;
    let cross = |i: usize, j: usize| {
        let (a, b) = (mesh.vertices[i], mesh.vertices[j]);
        let t = (h - a[2]) / (b[2] - a[2]);
        Point::new(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1]))
    };
    let key = |i: usize, j: usize| (i.min(j), i.max(j));
    // next[edge] = (next edge, the crossing point on this edge).
    let mut next: HashMap<(usize, usize), ((usize, usize), Point)> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let edges: Vec<(usize, usize)> = (0..3)
            .map(|e| (tri[e], tri[(e + 1) % 3]))
            .filter(|&(i, j)| above(i) != above(j))
            .collect();
        if edges.len() != 2 {
            continue;
        }
        let (p, q) = (cross(edges[0].0, edges[0].1), cross(edges[1].0, edges[1].1));
        let n = mesh.normal(t);
        // Interior on the left seen from +z: direction ẑ × n.
        let d = Point::new(-n[1], n[0]);
        let (e0, e1) = (key(edges[0].0, edges[0].1), key(edges[1].0, edges[1].1));
        if (q - p).dot(d) >= 0.0 {
            next.insert(e0, (e1, p));
        } else {
            next.insert(e1, (e0, q));
        }
    }
    let mut starts: Vec<(usize, usize)> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut loops = Vec::new();
    for s in starts {
        let mut pts = Vec::new();
        let mut k = s;
        while let Some((e, p)) = next.remove(&k) {
            pts.push(p);
            k = e;
        }
        if pts.len() >= 3 {
            loops.push(Polyline::closed(pts));
        }
    }
    loops
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ring_resampled_through_anchors_keeps_them_and_its_order() {
        let sq = Polyline::closed(vec![
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 2.0),
            Point::new(0.0, 2.0),
        ]);
        let anchors = [Point::new(4.0, 1.3), Point::new(0.0, 0.5)];
        let r = resample_through(&sq, &anchors, 24);
        assert_eq!(r.points.len(), 24);
        for a in anchors {
            assert!(r.points.iter().any(|p| p.distance(a) < 1e-12), "{a:?}");
        }
        // On the square, counter-clockwise like it, spaced at most the
        // perimeter over n − 2 apart.
        assert!(r.signed_area() > 7.9);
        let on = |p: &Point| {
            p.x.abs() < 1e-12
                || (p.x - 4.0).abs() < 1e-12
                || p.y.abs() < 1e-12
                || (p.y - 2.0).abs() < 1e-12
        };
        assert!(r.points.iter().all(on));
        let n = r.points.len();
        let gaps: Vec<f64> = (0..n)
            .map(|i| r.points[i].distance(r.points[(i + 1) % n]))
            .collect();
        assert!(
            gaps.iter().all(|&g| g > 0.0 && g <= 12.0 / 22.0 + 1e-9),
            "{gaps:?}"
        );
        // Without anchors: the plain resampling.
        assert_eq!(resample_through(&sq, &[], 10), sq.resample(10));
    }
}
