//! Triangulation of a simple polygon by ear clipping (Meisters, "Polygons
//! have ears", Amer. Math. Monthly 1975; O(n²) per ear search, O(n³) worst
//! case, ample for cross-section caps of a few hundred vertices).

use crate::geometry::Point;

fn cross3(a: Point, b: Point, c: Point) -> f64 {
    (b - a).cross(c - a)
}

/// Whether `p` is inside the counter-clockwise triangle `abc`: strictly,
/// or (`inclusive`) also on its edges, unless `p` coincides with a corner.
fn in_triangle(p: Point, a: Point, b: Point, c: Point, inclusive: bool) -> bool {
    let d1 = cross3(a, b, p);
    let d2 = cross3(b, c, p);
    let d3 = cross3(c, a, p);
    if inclusive {
        p != a && p != b && p != c && d1 >= 0.0 && d2 >= 0.0 && d3 >= 0.0
    } else {
        d1 > 0.0 && d2 > 0.0 && d3 > 0.0
    }
}

/// Triangles `[i, j, k]` (indices into `poly`) covering the simple polygon
/// `poly`, each with the polygon's orientation (positive area for a
/// positively oriented polygon). `n − 2` triangles for `n ≥ 3` vertices.
/// Degenerate (collinear) vertices are clipped as flat ears when no proper
/// ear remains, so the result always uses every polygon edge once.
pub fn ear_clip(poly: &[Point]) -> Vec<[usize; 3]> {
    let n = poly.len();
    if n < 3 {
        return Vec::new();
    }
    let area: f64 = (0..n).map(|i| poly[i].cross(poly[(i + 1) % n])).sum();
    let sign = if area >= 0.0 { 1.0 } else { -1.0 };
    let mut idx: Vec<usize> = (0..n).collect();
    let mut out = Vec::with_capacity(n - 2);
    while idx.len() > 3 {
        let m = idx.len();
        let mut clipped = None;
        // Pass 1: a strictly convex ear with no other vertex inside or on its
        // edges; pass 2: a flat or convex vertex with no vertex strictly
        // inside (degenerate input).
        for strict in [true, false] {
            for i in 0..m {
                let (ia, ib, ic) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
                let (a, b, c) = (poly[ia], poly[ib], poly[ic]);
                let turn = sign * cross3(a, b, c);
                if (strict && turn <= 0.0) || (!strict && turn < 0.0) {
                    continue;
                }
                let blocked = idx.iter().any(|&j| {
                    j != ia && j != ib && j != ic && {
                        let p = poly[j];
                        if sign > 0.0 {
                            in_triangle(p, a, b, c, strict)
                        } else {
                            in_triangle(p, a, c, b, strict)
                        }
                    }
                });
                if !blocked {
                    clipped = Some(i);
                    break;
                }
            }
            if clipped.is_some() {
                break;
            }
        }
        // A non-simple polygon may have no ear at all: clip any vertex so the
        // result stays a fan over the boundary edges.
        let i = clipped.unwrap_or(0);
        let m = idx.len();
        out.push([idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]]);
        idx.remove(i);
    }
    out.push([idx[0], idx[1], idx[2]]);
    out
}
