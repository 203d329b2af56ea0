//! The [`Outline`] type: an ordered list of boundary points, open or closed.

use crate::geometry::Point;

/// The turning sense of a closed outline in a y-up frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Orientation {
    /// Positive signed area: the interior is on the left of the direction of
    /// travel (outer boundaries, by this module's convention).
    CounterClockwise,
    /// Negative signed area: the interior is on the right (holes).
    Clockwise,
    /// Zero signed area (fewer than three points, or all collinear).
    Degenerate,
}

/// An ordered list of points along a curve, in a y-up frame.
///
/// For a closed outline the last point connects back to the first, and the
/// first point is *not* repeated at the end. Outer boundaries produced by this
/// module run counter-clockwise (positive [`signed_area`](Outline::signed_area)),
/// holes clockwise, so the enclosed shape is always on the left.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Outline {
    /// The points in order.
    pub points: Vec<Point>,
    /// Whether the last point connects back to the first.
    pub closed: bool,
}

impl Outline {
    /// An outline through `points`, closed or open.
    pub fn new(points: Vec<Point>, closed: bool) -> Outline {
        Outline { points, closed }
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the outline has no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The signed area by the shoelace formula `A = ½ Σ (xᵢ yᵢ₊₁ − xᵢ₊₁ yᵢ)`,
    /// indices modulo n (an open outline is closed by its chord); positive for
    /// counter-clockwise order in a y-up frame.
    pub fn signed_area(&self) -> f64 {
        let n = self.points.len();
        if n < 3 {
            return 0.0;
        }
        // Relative to the first point, to limit cancellation far from the origin.
        let o = self.points[0];
        let mut twice = 0.0;
        for i in 1..n - 1 {
            twice += (self.points[i] - o).cross(self.points[i + 1] - o);
        }
        0.5 * twice
    }

    /// The enclosed area `|A|` (see [`signed_area`](Outline::signed_area)).
    pub fn area(&self) -> f64 {
        self.signed_area().abs()
    }

    /// The orientation from the sign of the shoelace area.
    pub fn orientation(&self) -> Orientation {
        let a = self.signed_area();
        if a > 0.0 {
            Orientation::CounterClockwise
        } else if a < 0.0 {
            Orientation::Clockwise
        } else {
            Orientation::Degenerate
        }
    }

    /// Reverses the order of the points in place (a closed outline keeps its
    /// first point, so that indices of break points stay meaningful as `n − i`).
    pub fn reverse(&mut self) {
        if self.closed && self.points.len() > 1 {
            self.points[1..].reverse();
        } else {
            self.points.reverse();
        }
    }

    /// The outline with the order of its points reversed (see [`reverse`](Outline::reverse)).
    pub fn reversed(&self) -> Outline {
        let mut o = self.clone();
        o.reverse();
        o
    }

    /// Reverses the outline if needed so that it has `orientation`; a
    /// degenerate outline is left as is. Returns whether it was reversed.
    pub fn orient(&mut self, orientation: Orientation) -> bool {
        let current = self.orientation();
        if current != Orientation::Degenerate
            && orientation != Orientation::Degenerate
            && current != orientation
        {
            self.reverse();
            true
        } else {
            false
        }
    }

    /// The polyline length `Σ |pᵢ₊₁ − pᵢ|`, with the closing edge when closed.
    pub fn perimeter(&self) -> f64 {
        let n = self.points.len();
        let open: f64 = self.points.windows(2).map(|w| w[0].distance(w[1])).sum();
        if self.closed && n > 1 {
            open + self.points[n - 1].distance(self.points[0])
        } else {
            open
        }
    }

    /// Cumulative chord lengths `L₀ = 0, Lᵢ = Σ_{j<i} |pⱼ₊₁ − pⱼ|`, one per
    /// point; for a closed outline a last entry with the full perimeter is
    /// appended (the return to the first point).
    pub fn cumulative_lengths(&self) -> Vec<f64> {
        let mut out = Vec::with_capacity(self.points.len() + 1);
        let mut s = 0.0;
        if let Some(&first) = self.points.first() {
            out.push(0.0);
            let mut prev = first;
            for &p in &self.points[1..] {
                s += prev.distance(p);
                out.push(s);
                prev = p;
            }
            if self.closed {
                out.push(s + prev.distance(first));
            }
        }
        out
    }

    /// The axis-aligned bounding box `(min, max)`, or `None` when empty.
    pub fn bbox(&self) -> Option<(Point, Point)> {
        let first = *self.points.first()?;
        Some(self.points.iter().fold((first, first), |(lo, hi), p| {
            (
                Point::new(lo.x.min(p.x), lo.y.min(p.y)),
                Point::new(hi.x.max(p.x), hi.y.max(p.y)),
            )
        }))
    }

    /// Removes consecutive duplicate points (and, when closed, a last point
    /// equal to the first).
    pub fn dedup(&mut self) {
        self.points.dedup();
        if self.closed && self.points.len() > 1 && self.points.first() == self.points.last() {
            self.points.pop();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Outline {
        let p = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        Outline::new(p.iter().map(|&q| q.into()).collect(), true)
    }

    #[test]
    fn shoelace_area_and_orientation() {
        let s = square();
        assert_eq!(s.signed_area(), 4.0);
        assert_eq!(s.orientation(), Orientation::CounterClockwise);
        let r = s.reversed();
        assert_eq!(r.signed_area(), -4.0);
        assert_eq!(r.orientation(), Orientation::Clockwise);
        assert_eq!(r.points[0], s.points[0]);
        assert_eq!(r.points[1], Point::new(0.0, 2.0));
        let mut t = r.clone();
        assert!(t.orient(Orientation::CounterClockwise));
        assert_eq!(t, s);
        assert!(!t.orient(Orientation::CounterClockwise));
        let line = Outline::new(vec![Point::ZERO, Point::new(1.0, 1.0)], false);
        assert_eq!(line.orientation(), Orientation::Degenerate);
    }

    #[test]
    fn perimeter_and_lengths() {
        let s = square();
        assert_eq!(s.perimeter(), 8.0);
        assert_eq!(s.cumulative_lengths(), vec![0.0, 2.0, 4.0, 6.0, 8.0]);
        let open = Outline::new(s.points.clone(), false);
        assert_eq!(open.perimeter(), 6.0);
        assert_eq!(open.cumulative_lengths(), vec![0.0, 2.0, 4.0, 6.0]);
        assert_eq!(s.bbox(), Some((Point::ZERO, Point::new(2.0, 2.0))));
        assert_eq!(Outline::default().bbox(), None);
    }

    #[test]
    fn dedup_removes_repeats_and_closing_duplicate() {
        let p = Point::new(1.0, 1.0);
        let mut o = Outline::new(vec![Point::ZERO, Point::ZERO, p, p, Point::ZERO], true);
        o.dedup();
        assert_eq!(o.points, vec![Point::ZERO, p]);
        let mut open = Outline::new(vec![Point::ZERO, p, Point::ZERO], false);
        open.dedup();
        assert_eq!(open.len(), 3);
    }
}
