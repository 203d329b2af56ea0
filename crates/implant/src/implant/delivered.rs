//! The part as delivered, measured like the design (issue 48): each
//! slice's ring of the STL — the clipped section oriented
//! counter-clockwise and resampled by arc length to the loft's ring points,
//! as [`crate::ct::loft_rings`] makes it — gives the kinks at the seats
//! against the bone's threshold iso-contour (1.5 mm and 3 mm secants, as
//! [`super::wall::OuterDesign::iso_kinks_deg`] on the design) and the
//! thickness at A′ and B′.
//!
//! On the ring, the seat is the ring's point nearest to A′ (B′); its
//! outer surface runs along the ring in the direction whose point 3 mm on
//! lies nearer the designed outer wall; the kink is the angle between the
//! ring's secant over `L` mm from the seat and the bone's secant over `L`
//! mm of iso-contour from the seat; the thickness is the length of the
//! ring's chord along the inward normal of the outer surface 3 mm from the
//! seat (at the seat itself the part thins to a feather edge on the bone).

use super::polar::{angle_deg, walk_along};
use super::wall::{OuterDesign, Wall, ISO_SECANTS_MM};
use crate::ct::resample_through;
use crate::geometry::{Nearest, Point, Polyline};

/// The delivered ring's measures of one slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Delivered {
    /// The kinks at A′ and B′ (degrees) over each secant of
    /// [`ISO_SECANTS_MM`] (1.5 mm, then 3 mm); `NaN` where the ring has no
    /// outer surface at the seat.
    pub kinks_deg: [(f64, f64); 2],
    /// The ring's thickness 3 mm into the implant from A′ and from B′ along
    /// its outer surface (mm; `NaN` when not measured).
    pub thickness: (f64, f64),
}

impl Delivered {
    /// The larger 3 mm kink of the two seats (`NaN` only where both are).
    pub fn max_kink_3mm(&self) -> f64 {
        self.kinks_deg[1].0.max(self.kinks_deg[1].1)
    }
}

/// The ring the loft makes of a wall's section: counter-clockwise, closed,
/// resampled by arc length to `n` points through the seats A′ and B′
/// ([`resample_through`]).
pub fn delivered_ring(wall: &Wall, n: usize) -> Polyline {
    let section = &wall.section;
    let mut ring = if section.signed_area() < 0.0 {
        section.reversed()
    } else {
        section.clone()
    };
    ring.closed = true;
    resample_through(&ring, &[wall.design.a, wall.design.b], n)
}

/// The delivered measures of `ring` against its slice's `design`.
pub fn measure_delivered(ring: &Polyline, design: &OuterDesign) -> Delivered {
    let at = |seat: Point, end: usize| -> ([f64; 2], f64) {
        let Some(n) = ring.nearest(seat) else {
            return ([f64::NAN; 2], f64::NAN);
        };
        let forward = outer_direction(ring, &n, design);
        let kinks = [0, 1].map(|k| {
            let l = ISO_SECANTS_MM[k];
            let q = walk_along(ring, &n, l, forward);
            let bone = if end == 0 {
                design.iso_dirs[k].0
            } else {
                design.iso_dirs[k].1
            };
            // Direction of travel: from A′ into the wall, into B′ from it.
            let d = if end == 0 { q - n.point } else { n.point - q };
            angle_deg(d, bone)
        });
        // The thickness 3 mm into the implant: at the seat itself the part
        // thins to its feather edge on the bone.
        let q = walk_along(ring, &n, ISO_SECANTS_MM[1], forward);
        let q2 = walk_along(ring, &n, ISO_SECANTS_MM[1] + 0.5, forward);
        (kinks, chord_inwards(ring, q, q2 - q, design.centre))
    };
    let (ka, ta) = at(design.a, 0);
    let (kb, tb) = at(design.b, 1);
    Delivered {
        kinks_deg: [(ka[0], kb[0]), (ka[1], kb[1])],
        thickness: (ta, tb),
    }
}

/// Whether the ring's outer surface runs forward (increasing index) from
/// `n`: the walk whose point 3 mm on lies nearer the designed outer wall.
fn outer_direction(ring: &Polyline, n: &Nearest, design: &OuterDesign) -> bool {
    let l = ISO_SECANTS_MM[1];
    let dist = |q: Point| {
        design
            .outer
            .nearest(q)
            .map_or(f64::INFINITY, |m| m.point.distance(q))
    };
    dist(walk_along(ring, n, l, true)) <= dist(walk_along(ring, n, l, false))
}

/// The length of the ring's chord from `p` along the normal of `dir`
/// pointing towards `centre`: the nearest crossing of that ray with the
/// ring beyond 0.05 mm (`NaN` when none).
fn chord_inwards(ring: &Polyline, p: Point, dir: Point, centre: Point) -> f64 {
    let Some(d) = dir.normalize() else {
        return f64::NAN;
    };
    let mut nrm = Point::new(-d.y, d.x);
    if nrm.dot(centre - p) < 0.0 {
        nrm = -nrm;
    }
    (0..ring.segment_count())
        .filter_map(|i| {
            let (a, b) = ring.segment(i);
            ray_segment(p, nrm, a, b)
        })
        .filter(|&t| t > 0.05)
        .fold(f64::NAN, f64::min)
}

/// The parameter `t ≥ 0` where the ray `p + t·u` crosses segment `ab`.
fn ray_segment(p: Point, u: Point, a: Point, b: Point) -> Option<f64> {
    let e = b - a;
    let den = u.cross(e);
    if den.abs() < 1e-12 {
        return None;
    }
    let w = a - p;
    let t = w.cross(e) / den;
    let s = w.cross(u) / den;
    (t >= 0.0 && (0.0..=1.0).contains(&s)).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ray_meets_a_square_at_its_far_side() {
        let sq = Polyline::closed(vec![
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(4.0, 2.0),
            Point::new(0.0, 2.0),
        ]);
        // From the bottom edge, inwards (towards a centre above it).
        let t = chord_inwards(
            &sq,
            Point::new(1.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(2.0, 5.0),
        );
        assert!((t - 2.0).abs() < 1e-12, "{t}");
        let ring = resample_through(&sq.reversed(), &[Point::new(4.0, 1.3)], 24);
        assert!(ring.points.len() == 24);
        assert!(ring
            .points
            .iter()
            .any(|p| p.distance(Point::new(4.0, 1.3)) < 1e-12));
    }
}
