//! The convex hull of a point set and how far a point lies outside it: the
//! head's outer outline a design can know on one slice (the bone and its
//! mirror image across the mid-sagittal line), against which an implant
//! section is checked ([`crate::implant::plausibility`]).
//!
//! Hull by Andrew's monotone chain (A. M. Andrew, "Another efficient
//! algorithm for convex hulls in two dimensions", Information Processing
//! Letters 9(5), 1979): the points sorted by (x, y), the lower and upper
//! chains built keeping left turns only; `O(n log n)`.

use crate::geometry::Point;

/// A convex polygon, counter-clockwise, without repeated or collinear
/// vertices (empty, one point or two for degenerate input).
#[derive(Clone, Debug, PartialEq)]
pub struct ConvexHull {
    /// The vertices, counter-clockwise (y up; clockwise on an image whose
    /// rows grow downwards, which does not change the distances).
    pub vertices: Vec<Point>,
}

/// The z component of `(b − a) × (c − a)`: positive for a left turn.
fn turn(a: Point, b: Point, c: Point) -> f64 {
    (b - a).cross(c - a)
}

impl ConvexHull {
    /// The convex hull of `points` (Andrew's monotone chain); non-finite
    /// points are ignored.
    pub fn of(points: &[Point]) -> ConvexHull {
        let mut p: Vec<Point> = points
            .iter()
            .copied()
            .filter(|q| q.x.is_finite() && q.y.is_finite())
            .collect();
        p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
        p.dedup();
        if p.len() < 3 {
            return ConvexHull { vertices: p };
        }
        let mut hull: Vec<Point> = Vec::with_capacity(2 * p.len());
        for pass in 0..2 {
            let start = hull.len();
            let chain: Box<dyn Iterator<Item = &Point>> = if pass == 0 {
                Box::new(p.iter())
            } else {
                Box::new(p.iter().rev())
            };
            for &q in chain {
                while hull.len() >= start + 2
                    && turn(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
                {
                    hull.pop();
                }
                hull.push(q);
            }
            hull.pop(); // the last point starts the other chain
        }
        ConvexHull { vertices: hull }
    }

    /// How far `p` lies outside the hull (mm; 0 inside or on it): the
    /// largest signed distance of `p` from the hull's edge lines, which is
    /// the exact distance where the nearest point of the hull is on an
    /// edge and a lower bound near a vertex; infinite for an empty hull.
    pub fn outside_distance(&self, p: Point) -> f64 {
        let v = &self.vertices;
        match v.len() {
            0 => f64::INFINITY,
            1 => p.distance(v[0]),
            2 => crate::geometry::segment_foot(p, v[0], v[1]).1.distance(p),
            n => (0..n)
                .map(|i| {
                    let (a, b) = (v[i], v[(i + 1) % n]);
                    let e = b - a;
                    // Counter-clockwise: the outside is to the right of e.
                    -e.cross(p - a) / e.hypot()
                })
                .fold(0.0, f64::max),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hull_of_a_square_with_inner_points_is_its_corners() {
        let mut pts = vec![
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0),
            Point::new(2.0, 2.0),
            Point::new(0.0, 2.0),
            Point::new(1.0, 0.0), // collinear on an edge
        ];
        pts.extend((0..10).map(|k| Point::new(0.1 + 0.15 * k as f64, 1.0)));
        let h = ConvexHull::of(&pts);
        assert_eq!(h.vertices.len(), 4, "{h:?}");
        assert_eq!(h.outside_distance(Point::new(1.0, 1.0)), 0.0);
        assert!((h.outside_distance(Point::new(3.5, 1.0)) - 1.5).abs() < 1e-12);
        assert!((h.outside_distance(Point::new(1.0, -0.25)) - 0.25).abs() < 1e-12);
    }

    #[test]
    fn degenerate_hulls_measure_to_their_points() {
        assert!(ConvexHull::of(&[])
            .outside_distance(Point::ZERO)
            .is_infinite());
        let one = ConvexHull::of(&[Point::new(1.0, 1.0), Point::new(1.0, 1.0)]);
        assert!((one.outside_distance(Point::new(4.0, 5.0)) - 5.0).abs() < 1e-12);
    }
}
