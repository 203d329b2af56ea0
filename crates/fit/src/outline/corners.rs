//! Corner detection of outlines by the k-turning angle
//! (the k-cosine of Rosenfeld & Johnston 1973, "Angle detection on digital
//! curves", IEEE Trans. Computers C-22(9):875–878), with non-maximum
//! suppression over the same neighbourhood.
//!
//! The angle at point `i` is the turn between the chords `a = pᵢ − pᵢ₋ₖ` and
//! `b = pᵢ₊ₖ − pᵢ`, `θᵢ = |atan2(a×b, a·b)|` ∈ [0, π]: 0 on a straight line,
//! π/2 at a square corner. Indices wrap around on a closed outline; on an open
//! one `θᵢ = 0` within `k` points of either end.

use super::Outline;

/// Parameters of the corner detector.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CornerOptions {
    /// The neighbourhood `k ≥ 1` (in points) of the turning angle and of the
    /// non-maximum suppression; larger `k` ignores pixel-scale noise.
    pub k: usize,
    /// A point is a corner candidate when `θᵢ` is at least this many degrees.
    pub angle_deg: f64,
}

impl Default for CornerOptions {
    /// `k = 5`, 60°: square and sharper corners of pixel outlines, not the
    /// 45° staircase steps of digitised curves or circles wider than ~10 px.
    fn default() -> Self {
        CornerOptions {
            k: 5,
            angle_deg: 60.0,
        }
    }
}

/// The turning angle `θᵢ` (radians) at every point, as in the module documentation.
pub fn turning_angles(outline: &Outline, k: usize) -> Vec<f64> {
    let p = &outline.points;
    let n = p.len();
    let k = k.max(1);
    let mut out = vec![0.0; n];
    if outline.closed {
        if n < 3 {
            return out;
        }
        for (i, o) in out.iter_mut().enumerate() {
            let a = p[i] - p[(i + n - k % n) % n];
            let b = p[(i + k) % n] - p[i];
            *o = a.cross(b).atan2(a.dot(b)).abs();
        }
    } else {
        for i in k..n.saturating_sub(k) {
            let a = p[i] - p[i - k];
            let b = p[i + k] - p[i];
            out[i] = a.cross(b).atan2(a.dot(b)).abs();
        }
    }
    out
}

/// The index distance between `i` and `j`, cyclic when `closed`.
fn index_distance(i: usize, j: usize, n: usize, closed: bool) -> usize {
    let d = i.abs_diff(j);
    if closed {
        d.min(n - d)
    } else {
        d
    }
}

/// The sorted indices of the corners: points whose turning angle reaches
/// `options.angle_deg` and is the largest within `±k` points (ties go to the
/// lower index), so that one corner gives one index.
pub fn find_corners(outline: &Outline, options: &CornerOptions) -> Vec<usize> {
    let n = outline.len();
    let k = options.k.max(1);
    let threshold = options.angle_deg.to_radians();
    let theta = turning_angles(outline, k);
    let mut candidates: Vec<usize> = (0..n).filter(|&i| theta[i] >= threshold).collect();
    candidates.sort_by(|&i, &j| theta[j].total_cmp(&theta[i]).then(i.cmp(&j)));
    let mut corners: Vec<usize> = Vec::new();
    for i in candidates {
        if corners
            .iter()
            .all(|&c| index_distance(i, c, n, outline.closed) > k)
        {
            corners.push(i);
        }
    }
    corners.sort_unstable();
    corners
}

/// The pieces of `outline` between consecutive `breaks` (indices; sorted,
/// deduplicated and those out of range dropped first), as
/// open outlines that share their end points; on a closed outline the last
/// piece wraps around to the first break (a single break gives the whole loop
/// with its first point repeated at the end).
pub fn split_at(outline: &Outline, breaks: &[usize]) -> Vec<Outline> {
    let p = &outline.points;
    let n = p.len();
    let mut b: Vec<usize> = breaks.iter().copied().filter(|&i| i < n).collect();
    b.sort_unstable();
    b.dedup();
    let mut out: Vec<Outline> = b
        .windows(2)
        .map(|w| Outline::new(p[w[0]..=w[1]].to_vec(), false))
        .collect();
    if outline.closed {
        if let (Some(&first), Some(&last)) = (b.first(), b.last()) {
            let mut piece = p[last..].to_vec();
            piece.extend_from_slice(&p[..=first]);
            out.push(Outline::new(piece, false));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use std::f64::consts::PI;

    /// A closed square of side 1 with `m` points per side, corners at 0, m, 2m, 3m.
    fn square(m: usize) -> Outline {
        let c = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)].map(Point::from);
        let mut pts = Vec::new();
        for s in 0..4 {
            for j in 0..m {
                pts.push(c[s].lerp(c[(s + 1) % 4], j as f64 / m as f64));
            }
        }
        Outline::new(pts, true)
    }

    #[test]
    fn a_square_has_four_corners() {
        let s = square(25);
        assert_eq!(
            find_corners(&s, &CornerOptions::default()),
            vec![0, 25, 50, 75]
        );
        let theta = turning_angles(&s, 5);
        assert!((theta[25] - PI / 2.0).abs() < 1e-12);
        assert_eq!(theta[10], 0.0);
        // Rotated start: the corners move with the indices.
        let mut r = s.clone();
        r.points.rotate_left(7);
        assert_eq!(
            find_corners(&r, &CornerOptions::default()),
            vec![18, 43, 68, 93]
        );
        assert_eq!(split_at(&s, &[0, 25, 50, 75]).len(), 4);
        assert_eq!(split_at(&s, &[0, 25, 50, 75])[3].points.len(), 26);
        assert_eq!(
            split_at(&s, &[50, 0, 400, 25, 75, 25]),
            split_at(&s, &[0, 25, 50, 75])
        );
    }
}
