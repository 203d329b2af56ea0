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

/// Lofts closed cross-sections `sections[k]` at heights `zs[k]` (mm,
/// strictly increasing) into a closed triangle mesh: each section is
/// oriented counter-clockwise, resampled by arc length to `n` points, its
/// start rotated to best match the previous ring (least squares over the
/// `n` cyclic shifts, which avoids twisting), consecutive rings are joined by
/// two triangles per quad, and both ends are capped by ear clipping. The
/// result is watertight and outward oriented.
pub fn loft(sections: &[Polyline], zs: &[f64], n: usize) -> Result<Mesh, CtError> {
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
    let mut rings: Vec<Vec<Point>> = Vec::with_capacity(sections.len());
    for (k, s) in sections.iter().enumerate() {
        if s.points.len() < 3 || s.signed_area().abs() <= 0.0 {
            return Err(CtError::DegenerateSection { index: k });
        }
        let mut closed = positive(s);
        closed.closed = true;
        let r = closed.resample(n).points;
        let r = match rings.last() {
            None => r,
            Some(prev) => {
                let cost = |shift: usize| -> f64 {
                    (0..n)
                        .map(|i| r[(i + shift) % n].distance_squared(prev[i]))
                        .sum()
                };
                let best = (0..n)
                    .min_by(|&a, &b| cost(a).total_cmp(&cost(b)))
                    .unwrap_or(0);
                (0..n).map(|i| r[(i + best) % n]).collect()
            }
        };
        rings.push(r);
    }
    let mut mesh = Mesh::default();
    for (ring, &z) in rings.iter().zip(zs) {
        mesh.vertices.extend(ring.iter().map(|p| [p.x, p.y, z]));
    }
    let v = |k: usize, i: usize| k * n + i % n;
    for k in 0..rings.len() - 1 {
        for i in 0..n {
            mesh.triangles.push([v(k, i), v(k, i + 1), v(k + 1, i + 1)]);
            mesh.triangles.push([v(k, i), v(k + 1, i + 1), v(k + 1, i)]);
        }
    }
    let last = rings.len() - 1;
    for t in ear_clip(&rings[0]) {
        // Bottom cap faces −z: reverse the counter-clockwise triangles.
        mesh.triangles.push([v(0, t[0]), v(0, t[2]), v(0, t[1])]);
    }
    for t in ear_clip(&rings[last]) {
        mesh.triangles
            .push([v(last, t[0]), v(last, t[1]), v(last, t[2])]);
    }
    Ok(mesh)
}
