//! How a segment joins its neighbours: its start after the previous
//! segment ([`Start`]), its end before a known curve ([`End`]), and where
//! the two tangent lines of a quadratic joined G¹ at both ends meet
//! ([`tangent_meet`]) (Farin 2002, §10.2 and eq. 13.10).

use crate::geometry::{Continuity, Point, SegmentEnd};

/// How a segment starts: its start point `C′₀` is always the first data
/// point; the join with the previous segment decides `C′₁`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// The first segment of an open outline, or a C⁰ join: `C′₁` is free.
    Free,
    /// A C¹ join after a segment with end derivative `D = Q′(1)`:
    /// `C′₁ = C′₀ + D/(m w′₁)` (`w′₁ = 1` for polynomial segments), i.e.
    /// `C′₁ = C₃ + (w₂w′₀)/(w₃w′₁)(C₃ − C₂)` for rational cubics and
    /// `C′₁ = C₂ + (h₁/h′₁)(C₂ − C₁)` for rational quadratics in standard
    /// form (Farin 2002, eq. 13.10).
    C1 {
        /// The previous segment's end derivative `Q′(1)`.
        derivative: Point,
    },
    /// A G¹ join after a segment whose last control leg is
    /// `L = C_m − C_{m−1}`: `C′₁ = C′₀ + T·L` with a free `T > 0`
    /// (Farin 2002, §10.2; the thesis's "T: parameter to locate new
    /// position of CP1").
    G1 {
        /// The previous segment's last leg `C_m − C_{m−1}`.
        leg: Point,
    },
}

impl Start {
    /// The start of a segment that follows `previous` with `continuity`.
    pub fn after<L: SegmentEnd + ?Sized>(previous: &L, continuity: Continuity) -> Start {
        match continuity {
            Continuity::C0 => Start::Free,
            Continuity::C1 => Start::C1 {
                derivative: previous.end_derivative(),
            },
            Continuity::G1 => {
                let (a, b) = previous.end_leg();
                Start::G1 { leg: b - a }
            }
        }
    }

    /// The start tangent direction this join imposes, if any.
    pub fn tangent(self) -> Option<Point> {
        match self {
            Start::Free => None,
            Start::C1 { derivative } => Some(derivative),
            Start::G1 { leg } => Some(leg),
        }
    }
}

/// How a segment ends: its end point `C_m` is always the last data point;
/// an optional join with a known curve *after* it decides `C_{m−1}`.
///
/// Used when a segment must fit between two fixed neighbours, as the
/// cranial-implant outer wall does between the intact contour at A and at B
/// (thesis chapter 6). The formulas mirror [`Start`] (Farin 2002, §10.2 and
/// eq. 13.10, read from the end): the end derivative of a (rational) Bézier
/// segment of degree `m` in standard form is `Q′(1) = m (w_{m−1}/w_m)(C_m − C_{m−1})`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum End {
    /// No constraint: `C_{m−1}` is free (or set by [`Start`] for a quadratic).
    #[default]
    Free,
    /// A C¹ join before a curve with start derivative `D`:
    /// `C_{m−1} = C_m − D/(m w_{m−1})` (`w_{m−1} = 1` for polynomial segments).
    C1 {
        /// The next curve's start derivative `Q′(0)`.
        derivative: Point,
    },
    /// A G¹ join before a curve whose start tangent (direction of travel) is
    /// `dir`: `C_{m−1} = C_m − T_end·dir` with a free `T_end > 0`.
    G1 {
        /// The next curve's start tangent direction (need not be unit).
        dir: Point,
    },
}

impl End {
    /// The end tangent direction (direction of travel) this join imposes.
    pub fn tangent(self) -> Option<Point> {
        match self {
            End::Free => None,
            End::C1 { derivative } => Some(derivative),
            End::G1 { dir } => Some(dir),
        }
    }
}

/// Where the start tangent line `C₀ + t·leg` meets the end tangent line
/// `C_m − u·dir`, if it does so in front of both ends (`t, u > 0`): the
/// inner control point of a quadratic joined G¹ at both ends (Farin 2002,
/// §10.2). `None` for (nearly) parallel lines.
pub fn tangent_meet(c0: Point, leg: Point, cn: Point, dir: Point) -> Option<Point> {
    let det = leg.cross(dir);
    let d = cn - c0;
    if det.abs() <= 1e-12 * leg.hypot() * dir.hypot() || !det.is_finite() {
        return None;
    }
    let t = d.cross(dir) / det;
    let u = leg.cross(d) / det;
    (t > 0.0 && u > 0.0).then(|| c0 + leg * t)
}
