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
//! candidate and its two neighbours ([`estimate_midline`], a vertical line).
//!
//! A head is rarely scanned perfectly straight, so the mid-sagittal line is
//! in general a tilted line ([`MidLine`]): [`estimate_tilted_midline`]
//! maximises the same Dice over the line's tilt and position (the
//! reflection of a pixel centre looked up at its nearest pixel), by a coarse
//! grid and three finer local grids. One line serves every slice: the
//! mid-sagittal plane is taken parallel to the slice axis (a yaw of the head
//! is modelled, a roll is not).

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

/// A mid-sagittal line in a slice's millimetre frame: through `point`,
/// with direction `(sin t, cos t)`, `t` the tilt from the image's y axis
/// (0 = the vertical line `x = point.x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MidLine {
    /// A point of the line (mm).
    pub point: Point,
    /// The tilt `t` from the y axis, radians (positive turns the line's
    /// +y end towards +x).
    pub tilt: f64,
}

impl MidLine {
    /// The vertical line `x = x_mm`.
    pub fn vertical(x_mm: f64) -> MidLine {
        MidLine {
            point: Point::new(x_mm, 0.0),
            tilt: 0.0,
        }
    }

    /// The unit direction `(sin t, cos t)`.
    pub fn direction(&self) -> Point {
        Point::new(self.tilt.sin(), self.tilt.cos())
    }

    /// The unit normal `(cos t, −sin t)` (towards +x).
    pub fn normal(&self) -> Point {
        Point::new(self.tilt.cos(), -self.tilt.sin())
    }

    /// The signed distance of `p` from the line, positive on the +x side.
    pub fn side(&self, p: Point) -> f64 {
        (p - self.point).dot(self.normal())
    }

    /// The mirror image of `p`: `p − 2·side(p)·n`.
    pub fn reflect(&self, p: Point) -> Point {
        p - self.normal() * (2.0 * self.side(p))
    }

    /// The line's x at height `y`.
    pub fn x_at(&self, y: f64) -> f64 {
        self.point.x + (y - self.point.y) * self.tilt.tan()
    }

    /// The line's point at height `y`.
    pub fn at_y(&self, y: f64) -> Point {
        Point::new(self.x_at(y), y)
    }

    /// The polar angle `α = π/2 − t` of the direction; the reflection maps
    /// the ray at angle `θ` from a point of the line to the ray at `2α − θ`.
    pub fn angle(&self) -> f64 {
        std::f64::consts::FRAC_PI_2 - self.tilt
    }

    /// The tilt in degrees.
    pub fn tilt_deg(&self) -> f64 {
        self.tilt.to_degrees()
    }
}

/// An estimated tilted mid-sagittal line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltedMidline {
    /// The line; its point lies at the bone's mean height.
    pub line: MidLine,
    /// The reflection Dice of the best candidate.
    pub dice: f64,
}

/// The bone pixel centres (mm) of every mask, with the masks.
struct Pooled<'a> {
    masks: &'a [Mask2],
    pixels: Vec<Vec<Point>>,
    sx: f64,
    sy: f64,
}

impl Pooled<'_> {
    /// The reflection Dice across `line`, using every `stride`-th pixel.
    fn dice(&self, line: &MidLine, stride: usize) -> f64 {
        let (mut inter, mut total) = (0usize, 0usize);
        // q = p − 2((p − o)·n)n, in pixel units.
        let (n, o) = (line.normal(), line.point);
        for (m, px) in self.masks.iter().zip(&self.pixels) {
            for p in px.iter().step_by(stride) {
                total += 1;
                let k = 2.0 * ((p.x - o.x) * n.x + (p.y - o.y) * n.y);
                let (r, c) = (
                    ((p.y - k * n.y) / self.sy).round(),
                    ((p.x - k * n.x) / self.sx).round(),
                );
                if r >= 0.0 && c >= 0.0 && (r as usize) < m.ny && (c as usize) < m.nx {
                    total += 1;
                    inter += usize::from(m.data[r as usize * m.nx + c as usize]);
                }
            }
        }
        if total == 0 {
            0.0
        } else {
            2.0 * inter as f64 / total as f64
        }
    }

    /// The best `(tilt, x, Dice)` of a grid of `2k.0 + 1` tilts by
    /// `2k.1 + 1` offsets around `centre` with `steps`, every `stride`-th
    /// pixel.
    fn grid(
        &self,
        centre: (f64, f64),
        y: f64,
        steps: (f64, f64),
        k: (i64, i64),
        stride: usize,
    ) -> (f64, f64, f64) {
        let mut best = (centre.0, centre.1, f64::MIN);
        for i in -k.0..=k.0 {
            for j in -k.1..=k.1 {
                let (t, x) = (centre.0 + i as f64 * steps.0, centre.1 + j as f64 * steps.1);
                let line = MidLine {
                    point: Point::new(x, y),
                    tilt: t,
                };
                let d = self.dice(&line, stride);
                if d > best.2 {
                    best = (t, x, d);
                }
            }
        }
        best
    }
}

/// Estimates a tilted mid-sagittal line from slice masks (pooled counts)
/// with pixel spacing `sx`, `sy`: the tilt within ±`max_tilt_deg` and the
/// line's x at the bone's mean height within the middle half of the bone's
/// x extent, on a coarse grid (2°, 2 pixels, every 16th pixel), then four
/// local 5 × 5 grids with steps 1°/1 px (every 4th pixel), 0.5°/0.5 px
/// (every 2nd), 0.2°/0.2 px and 0.05°/0.05 px (every pixel). `None` when the masks are empty.
pub fn estimate_tilted_midline(
    masks: &[Mask2],
    sx: f64,
    sy: f64,
    max_tilt_deg: f64,
) -> Option<TiltedMidline> {
    let pixels: Vec<Vec<Point>> = masks
        .iter()
        .map(|m| {
            m.pixels()
                .into_iter()
                .map(|(r, c)| Point::new(c as f64 * sx, r as f64 * sy))
                .collect()
        })
        .collect();
    let all: Vec<Point> = pixels.iter().flatten().copied().collect();
    if all.is_empty() {
        return None;
    }
    let y = all.iter().map(|p| p.y).sum::<f64>() / all.len() as f64;
    let (lo, hi) = all
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
            (l.min(p.x), h.max(p.x))
        });
    let pooled = Pooled {
        masks,
        pixels,
        sx,
        sy,
    };
    let mid = 0.5 * (lo + hi);
    let kx = ((hi - lo) / 4.0 / (2.0 * sx)).ceil() as i64;
    let kt = (max_tilt_deg / 2.0).ceil() as i64;
    let mut best = (0.0, mid, f64::MIN);
    for i in -kt..=kt {
        let t = (i as f64 * 2.0)
            .clamp(-max_tilt_deg, max_tilt_deg)
            .to_radians();
        let g = pooled.grid((t, mid), y, (0.0, 2.0 * sx), (0, kx), 16);
        if g.2 > best.2 {
            best = g;
        }
    }
    for (dt, dx, stride) in [(1.0, 1.0, 4), (0.5, 0.5, 2), (0.2, 0.2, 1), (0.05, 0.05, 1)] {
        best = pooled.grid(
            (best.0, best.1),
            y,
            (f64::to_radians(dt), dx * sx),
            (2, 2),
            stride,
        );
    }
    Some(TiltedMidline {
        line: MidLine {
            point: Point::new(best.1, y),
            tilt: best.0,
        },
        dice: best.2,
    })
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
