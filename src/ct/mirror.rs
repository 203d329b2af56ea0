//! The mirror technique (thesis chapter 6): the defect ends A and B are
//! reflected across the mid-sagittal line `x = M_x` to C and D on the intact
//! side, and the intact outer contour between C and D, reflected back,
//! serves as the template of the missing contour.
//!
//! `M_x` is given or estimated by maximising the reflection symmetry of the
//! bone mask: the Dice coefficient (Dice 1945) of the mask and its mirror
//! image over candidate lines, `D(m) = 2|M ∩ R_m M| / (|M| + |R_m M|)` with
//! `R_m(col) = 2m − col`, evaluated on half-pixel steps (exact pixel maps)
//! and refined to sub-pixel precision by a parabola through the best
//! candidate and its two neighbours.

use super::error::CtError;
use super::mask::Mask2;
use crate::geometry::Point;
use crate::geometry::Polyline;

/// The reflection of `p` across the vertical line `x = midline_x`:
/// `(2·M_x − x, y)`.
#[inline]
pub fn reflect(p: Point, midline_x: f64) -> Point {
    Point::new(2.0 * midline_x - p.x, p.y)
}

/// An estimated mid-sagittal line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Midline {
    /// The line's column (fractional pixel index).
    pub col: f64,
    /// The line's x in mm (`col·sx`).
    pub x: f64,
    /// The reflection Dice at the best half-pixel candidate.
    pub dice: f64,
}

/// The reflection Dice of a stack of slice masks across the column line
/// `col = k/2` (`k` = twice the column, so the pixel map is exact).
pub fn reflection_dice(masks: &[Mask2], k: i64) -> f64 {
    let (mut inter, mut total) = (0usize, 0usize);
    for m in masks {
        for (r, c) in m.pixels() {
            total += 1;
            let cc = k - c as i64;
            if cc >= 0 && (cc as usize) < m.nx {
                total += 1; // the mirrored pixel is in the image
                if m.get(r, cc as usize) {
                    inter += 1;
                }
            }
        }
    }
    if total == 0 {
        0.0
    } else {
        2.0 * inter as f64 / total as f64
    }
}

/// Estimates `M_x` from one or more slice masks (pooled counts) with column
/// spacing `sx`: candidates on half-pixel steps within the middle half of
/// the masks' column extent, then parabolic sub-pixel refinement. `None`
/// when the masks are empty.
pub fn estimate_midline(masks: &[Mask2], sx: f64) -> Option<Midline> {
    let (mut cmin, mut cmax) = (usize::MAX, 0usize);
    for m in masks {
        for (_, c) in m.pixels() {
            cmin = cmin.min(c);
            cmax = cmax.max(c);
        }
    }
    if cmin > cmax {
        return None;
    }
    let width = (cmax - cmin) as i64;
    let mid2 = (cmin + cmax) as i64; // twice the centre column
    let lo = (mid2 - width / 2).max(0);
    let hi = mid2 + width / 2;
    let mut best = (lo, f64::MIN);
    let scores: Vec<(i64, f64)> = (lo..=hi).map(|k| (k, reflection_dice(masks, k))).collect();
    for &(k, d) in &scores {
        if d > best.1 {
            best = (k, d);
        }
    }
    let at = |k: i64| {
        scores
            .iter()
            .find(|(kk, _)| *kk == k)
            .map(|&(_, d)| d)
            .unwrap_or_else(|| reflection_dice(masks, k))
    };
    let (k, d0) = best;
    let (dm, dp) = (at(k - 1), at(k + 1));
    let denom = dm - 2.0 * d0 + dp;
    let delta = if denom < 0.0 {
        (0.5 * (dm - dp) / denom).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    let col = (k as f64 + delta) / 2.0;
    Some(Midline {
        col,
        x: col * sx,
        dice: d0,
    })
}

/// The mirror template of a defect.
#[derive(Clone, Debug, PartialEq)]
pub struct MirrorTemplate {
    /// C: A reflected across `M_x`.
    pub c: Point,
    /// D: B reflected across `M_x`.
    pub d: Point,
    /// The intact outer contour from (the point nearest) C to (the point
    /// nearest) D, on the intact side.
    pub intact_arc: Polyline,
    /// `intact_arc` reflected back across `M_x`: the template of the missing
    /// contour, running from near A to near B.
    pub template: Polyline,
}

/// Builds the mirror template for the defect with ends `a`, `b` (mm) on the
/// outer table `outer` (an open arc from [`super::contour::table_contours`]
/// or a closed loop; for a loop the shorter arc between C and D is used).
///
/// Errors: [`CtError::DefectCrossesMidline`] when A and B lie on opposite
/// sides of (or on) `x = midline_x` — mirroring cannot serve, an explicit
/// template is needed; [`CtError::NotOnContour`] when C or D is farther than
/// `tolerance_mm` from `outer` (the head is too asymmetric there).
pub fn mirror_template(
    outer: &Polyline,
    a: Point,
    b: Point,
    midline_x: f64,
    tolerance_mm: f64,
) -> Result<MirrorTemplate, CtError> {
    if (a.x - midline_x) * (b.x - midline_x) <= 0.0 {
        return Err(CtError::DefectCrossesMidline {
            a_x: a.x,
            b_x: b.x,
            midline_x,
        });
    }
    if outer.points.len() < 2 {
        return Err(CtError::EmptyContour);
    }
    let c = reflect(a, midline_x);
    let d = reflect(b, midline_x);
    let nc = outer.nearest(c).expect("non-empty");
    let nd = outer.nearest(d).expect("non-empty");
    for (what, n) in [("C (A mirrored)", &nc), ("D (B mirrored)", &nd)] {
        if n.distance > tolerance_mm {
            return Err(CtError::NotOnContour {
                what,
                distance_mm: n.distance,
                tolerance_mm,
            });
        }
    }
    let intact_arc = if outer.closed {
        let fwd = outer.sub_arc(&nc, &nd);
        let back = outer.sub_arc(&nd, &nc).reversed();
        if fwd.length() <= back.length() {
            fwd
        } else {
            back
        }
    } else {
        outer.sub_arc(&nc, &nd)
    };
    let template = Polyline::open(
        intact_arc
            .points
            .iter()
            .map(|&p| reflect(p, midline_x))
            .collect(),
    );
    Ok(MirrorTemplate {
        c,
        d,
        intact_arc,
        template,
    })
}
