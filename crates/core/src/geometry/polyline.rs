//! The [`Polyline`]: an ordered list of points, open or closed, as the
//! outline of an image or a glyph, a bone contour, or a cross-section of the
//! implant. When closed, the last point joins back to the first, and the
//! first point is not repeated at the end.

use super::Point;

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

/// An ordered list of points along a curve, open or closed, in a y-up frame.
///
/// For a closed polyline the last point connects back to the first, and the
/// first point is *not* repeated at the end.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Polyline {
    /// The points in order.
    pub points: Vec<Point>,
    /// Whether the last point connects back to the first.
    pub closed: bool,
}

/// The nearest point of a polyline to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Nearest {
    /// Index of the segment's first vertex (segment `i` joins `i` and `i+1`,
    /// or the last and the first vertex when closed).
    pub segment: usize,
    /// Position on the segment, in \[0, 1\].
    pub t: f64,
    /// The nearest point.
    pub point: Point,
    /// Its distance to the query.
    pub distance: f64,
}

/// The axis-aligned bounding box `(min, max)` of `points`, or `None` when
/// there are none.
pub fn bounding_box(points: &[Point]) -> Option<(Point, Point)> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(lo, hi), p| {
        (
            Point::new(lo.x.min(p.x), lo.y.min(p.y)),
            Point::new(hi.x.max(p.x), hi.y.max(p.y)),
        )
    }))
}

/// The foot of the perpendicular from `p` on segment `ab`: its parameter
/// `t = clamp((p − a)·(b − a) / |b − a|², 0, 1)` and the point `a + t(b − a)`
/// (`t = 0` for a degenerate segment).
pub fn segment_foot(p: Point, a: Point, b: Point) -> (f64, Point) {
    let d = b - a;
    let l2 = d.hypot2();
    let t = if l2 > 0.0 {
        ((p - a).dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (t, a + d * t)
}

impl Polyline {
    /// An polyline through `points`, closed or open.
    pub fn new(points: Vec<Point>, closed: bool) -> Polyline {
        Polyline { points, closed }
    }

    /// The number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Whether the polyline has no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// The enclosed area `|A|` (see [`signed_area`](Polyline::signed_area)).
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

    /// Reverses the direction of travel in place; a closed polyline keeps its
    /// first point (so that indices of break points stay meaningful as
    /// `n − i`), an open one swaps its ends.
    pub fn reverse_keeping_start(&mut self) {
        if self.closed && self.points.len() > 1 {
            self.points[1..].reverse();
        } else {
            self.points.reverse();
        }
    }

    /// Reverses the polyline if needed so that it has `orientation`; a
    /// degenerate polyline is left as is. Returns whether it was reversed.
    pub fn orient(&mut self, orientation: Orientation) -> bool {
        let current = self.orientation();
        if current != Orientation::Degenerate
            && orientation != Orientation::Degenerate
            && current != orientation
        {
            self.reverse_keeping_start();
            true
        } else {
            false
        }
    }

    /// Cumulative chord lengths `L₀ = 0, Lᵢ = Σ_{j<i} |pⱼ₊₁ − pⱼ|`, one per
    /// point; for a closed polyline a last entry with the full perimeter is
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
        bounding_box(&self.points)
    }

    /// Removes consecutive duplicate points (and, when closed, a last point
    /// equal to the first).
    pub fn dedup(&mut self) {
        self.points.dedup();
        if self.closed && self.points.len() > 1 && self.points.first() == self.points.last() {
            self.points.pop();
        }
    }

    /// A closed polyline.
    pub fn closed(points: Vec<Point>) -> Polyline {
        Polyline {
            points,
            closed: true,
        }
    }

    /// An open polyline.
    pub fn open(points: Vec<Point>) -> Polyline {
        Polyline {
            points,
            closed: false,
        }
    }

    /// Number of segments: `n` when closed, `n − 1` when open.
    pub fn segment_count(&self) -> usize {
        let n = self.points.len();
        if n < 2 {
            0
        } else if self.closed {
            n
        } else {
            n - 1
        }
    }

    /// Segment `i` as its end points.
    pub fn segment(&self, i: usize) -> (Point, Point) {
        let n = self.points.len();
        (self.points[i], self.points[(i + 1) % n])
    }

    /// Signed area by the shoelace formula `½ Σ (x_i y_{i+1} − x_{i+1} y_i)`,
    /// indices modulo n, over the closed loop (an open polyline is closed by
    /// its chord); positive for counter-clockwise order in a y-up frame.
    /// Outer boundaries (of images, glyphs and bone contours) are positive,
    /// holes negative, so the enclosed shape is always on the left.
    pub fn signed_area(&self) -> f64 {
        let n = self.points.len();
        if n < 3 {
            return 0.0;
        }
        let mut s = 0.0;
        for i in 0..n {
            let (a, b) = (self.points[i], self.points[(i + 1) % n]);
            s += a.cross(b);
        }
        s / 2.0
    }

    /// The length `Σ |pᵢ₊₁ − pᵢ|`, with the closing edge when closed.
    pub fn length(&self) -> f64 {
        (0..self.segment_count())
            .map(|i| {
                let (a, b) = self.segment(i);
                a.distance(b)
            })
            .sum()
    }

    /// The same curve traversed the other way: the points in reverse order
    /// (the first becomes the last; compare
    /// [`reverse_keeping_start`](Polyline::reverse_keeping_start)).
    pub fn reversed(&self) -> Polyline {
        let mut points = self.points.clone();
        points.reverse();
        Polyline {
            points,
            closed: self.closed,
        }
    }

    /// The mean of the vertices.
    pub fn vertex_mean(&self) -> Point {
        let n = self.points.len().max(1) as f64;
        self.points.iter().fold(Point::ZERO, |s, &p| s + p) / n
    }

    /// The nearest point to `p` (None for an empty polyline).
    pub fn nearest(&self, p: Point) -> Option<Nearest> {
        if self.points.len() == 1 {
            let q = self.points[0];
            return Some(Nearest {
                segment: 0,
                t: 0.0,
                point: q,
                distance: p.distance(q),
            });
        }
        let mut best: Option<Nearest> = None;
        for i in 0..self.segment_count() {
            let (a, b) = self.segment(i);
            let (t, q) = segment_foot(p, a, b);
            let d = p.distance(q);
            if best.is_none_or(|n| d < n.distance) {
                best = Some(Nearest {
                    segment: i,
                    t,
                    point: q,
                    distance: d,
                });
            }
        }
        best
    }

    /// The distance from `p` to the polyline (∞ when empty).
    pub fn distance_to(&self, p: Point) -> f64 {
        self.nearest(p).map_or(f64::INFINITY, |n| n.distance)
    }

    /// Even-odd point-in-polygon test (Jordan curve theorem, crossing number;
    /// Haines 1994); the polyline is treated as closed.
    pub fn contains(&self, p: Point) -> bool {
        let n = self.points.len();
        let mut inside = false;
        let mut j = n.wrapping_sub(1);
        for i in 0..n {
            let (a, b) = (self.points[i], self.points[j]);
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if p.x < x {
                    inside = !inside;
                }
            }
            j = i;
        }
        inside
    }

    /// The point at arc length `s` (clamped to \[0, length\]).
    pub fn point_at(&self, s: f64) -> Point {
        let mut left = s.max(0.0);
        for i in 0..self.segment_count() {
            let (a, b) = self.segment(i);
            let l = a.distance(b);
            if left <= l && l > 0.0 {
                return a.lerp(b, left / l);
            }
            left -= l;
        }
        if self.closed {
            self.points[0]
        } else {
            *self.points.last().expect("non-empty polyline")
        }
    }

    /// `n` points equally spaced by arc length. A closed polyline gives `n`
    /// points starting at its first vertex (spacing `L/n`); an open one gives
    /// `n ≥ 2` points from its first to its last vertex (spacing `L/(n−1)`).
    pub fn resample(&self, n: usize) -> Polyline {
        assert!(!self.points.is_empty(), "empty polyline");
        let len = self.length();
        let step = if self.closed {
            len / n as f64
        } else {
            len / (n.max(2) - 1) as f64
        };
        // Walk once over the segments (linear time).
        let mut out = Vec::with_capacity(n);
        let mut seg = 0;
        let mut seg_start = 0.0;
        let segs = self.segment_count();
        for k in 0..n {
            let s = k as f64 * step;
            while seg < segs {
                let (a, b) = self.segment(seg);
                let l = a.distance(b);
                if s <= seg_start + l || seg + 1 == segs {
                    break;
                }
                seg_start += l;
                seg += 1;
            }
            if segs == 0 {
                out.push(self.points[0]);
                continue;
            }
            let (a, b) = self.segment(seg);
            let l = a.distance(b);
            let t = if l > 0.0 {
                ((s - seg_start) / l).clamp(0.0, 1.0)
            } else {
                0.0
            };
            out.push(a.lerp(b, t));
        }
        if !self.closed && n >= 2 {
            out[n - 1] = *self.points.last().expect("non-empty");
        }
        Polyline {
            points: out,
            closed: self.closed,
        }
    }

    /// The sub-arc from `from` to `to` (positions on the polyline as given by
    /// [`Polyline::nearest`]), following the vertex order; for a closed
    /// polyline it wraps around. The result is open and starts and ends at
    /// the exact positions.
    pub fn sub_arc(&self, from: &Nearest, to: &Nearest) -> Polyline {
        let n = self.points.len();
        let mut pts = vec![from.point];
        let forward = (from.segment, from.t) <= (to.segment, to.t);
        if !self.closed && !forward {
            // Open polyline walked backwards: reverse the result of the
            // forward walk.
            return self.sub_arc(to, from).reversed();
        }
        let mut i = from.segment;
        if self.closed && !forward {
            // Wrap: from `from` to the end, then from 0 to `to`.
            loop {
                i = (i + 1) % n;
                pts.push(self.points[i]);
                if i == to.segment {
                    break;
                }
            }
        } else {
            while i < to.segment {
                i += 1;
                pts.push(self.points[i]);
            }
        }
        if pts.last() != Some(&to.point) {
            pts.push(to.point);
        }
        Polyline::open(pts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Polyline {
        let p = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)];
        Polyline::new(p.iter().map(|&q| q.into()).collect(), true)
    }

    #[test]
    fn shoelace_area_and_orientation() {
        let s = square();
        assert_eq!(s.signed_area(), 4.0);
        assert_eq!(s.orientation(), Orientation::CounterClockwise);
        let mut r = s.clone();
        r.reverse_keeping_start();
        assert_eq!(r.signed_area(), -4.0);
        assert_eq!(r.orientation(), Orientation::Clockwise);
        assert_eq!(r.points[0], s.points[0]);
        assert_eq!(r.points[1], Point::new(0.0, 2.0));
        let full = s.reversed();
        assert_eq!(full.points[0], Point::new(0.0, 2.0));
        assert_eq!(full.points[3], s.points[0]);
        assert_eq!(full.signed_area(), -4.0);
        let mut t = r.clone();
        assert!(t.orient(Orientation::CounterClockwise));
        assert_eq!(t, s);
        assert!(!t.orient(Orientation::CounterClockwise));
        let line = Polyline::new(vec![Point::ZERO, Point::new(1.0, 1.0)], false);
        assert_eq!(line.orientation(), Orientation::Degenerate);
    }

    #[test]
    fn perimeter_and_lengths() {
        let s = square();
        assert_eq!(s.length(), 8.0);
        assert_eq!(s.cumulative_lengths(), vec![0.0, 2.0, 4.0, 6.0, 8.0]);
        let open = Polyline::new(s.points.clone(), false);
        assert_eq!(open.length(), 6.0);
        assert_eq!(open.cumulative_lengths(), vec![0.0, 2.0, 4.0, 6.0]);
        assert_eq!(s.bbox(), Some((Point::ZERO, Point::new(2.0, 2.0))));
        assert_eq!(Polyline::default().bbox(), None);
    }

    #[test]
    fn dedup_removes_repeats_and_closing_duplicate() {
        let p = Point::new(1.0, 1.0);
        let mut o = Polyline::new(vec![Point::ZERO, Point::ZERO, p, p, Point::ZERO], true);
        o.dedup();
        assert_eq!(o.points, vec![Point::ZERO, p]);
        let mut open = Polyline::new(vec![Point::ZERO, p, Point::ZERO], false);
        open.dedup();
        assert_eq!(open.len(), 3);
    }
}
