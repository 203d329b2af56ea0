//! Automatic detection of a cranial defect in one slice: the two ends A and
//! B of the gap in the bone ring.
//!
//! Method (angular coverage from the head centre, the polar "ray casting"
//! used for skull outlines): the centre `O` is the centroid of the bone
//! pixels; each bone pixel covers the interval of polar angles (about `O`)
//! spanned by its four corners, so no ray from `O` can slip between
//! 8-connected pixels; angles are binned (`bins` per turn) and the longest
//! circular run of uncovered bins is the gap. A gap narrower than
//! `min_gap_deg` is no defect, and a slice whose ring covers every angle is
//! intact. The ends are then the mutually closest pair of bone pixels (one
//! on each side) among the pixels whose centre angle lies within
//! `side_window_deg` beyond each edge of the gap: the narrowest chord across
//! the gap, i.e. the tips of the two bone ends.

use super::mask::Mask2;
use crate::geometry::Point;

/// Parameters of [`detect_defect`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefectParams {
    /// Angular bins per full turn.
    pub bins: usize,
    /// Smallest gap (degrees) reported as a defect.
    pub min_gap_deg: f64,
    /// Angular window (degrees) beyond each gap edge searched for the ends.
    pub side_window_deg: f64,
}

impl Default for DefectParams {
    fn default() -> Self {
        DefectParams {
            bins: 1440,
            min_gap_deg: 2.0,
            side_window_deg: 20.0,
        }
    }
}

/// A detected defect in one slice.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Defect {
    /// End A as (row, col): the bone pixel at the gap's start (increasing
    /// polar angle `atan2(y, x)` about the centre, y = row·sy down).
    pub a: (usize, usize),
    /// End B as (row, col), at the gap's end.
    pub b: (usize, usize),
    /// A in mm (`x = col·sx`, `y = row·sy`).
    pub a_mm: Point,
    /// B in mm.
    pub b_mm: Point,
    /// The centre of the angular scan (bone centroid) in mm.
    pub centre: Point,
    /// Polar angle (degrees, in \[0, 360)) where the gap starts.
    pub gap_start_deg: f64,
    /// Angular width of the gap in degrees.
    pub gap_width_deg: f64,
}

impl Defect {
    /// The gap width |AB| in mm.
    pub fn width_mm(&self) -> f64 {
        self.a_mm.distance(self.b_mm)
    }
}

fn angle01(p: Point, o: Point) -> f64 {
    let a = (p.y - o.y).atan2(p.x - o.x) / std::f64::consts::TAU;
    if a < 0.0 {
        a + 1.0
    } else {
        a
    }
}

/// Which of `nb` equal angular bins about `centre` (turns from +x) the
/// pixels cover; a pixel covers every bin its square overlaps, and one
/// holding the centre covers them all. `mm` maps (row, col) to mm.
fn angular_coverage(
    pixels: &[(usize, usize)],
    mm: impl Fn(f64, f64) -> Point,
    centre: Point,
    nb: usize,
) -> Vec<bool> {
    let mut covered = vec![false; nb];
    for &(r, c) in pixels {
        let (r, c) = (r as f64, c as f64);
        let corners = [
            mm(r - 0.5, c - 0.5),
            mm(r - 0.5, c + 0.5),
            mm(r + 0.5, c + 0.5),
            mm(r + 0.5, c - 0.5),
        ];
        if corners.iter().all(|&q| q == centre) {
            continue;
        }
        // Angular extent relative to the pixel centre's angle (no wrap issue).
        let a0 = angle01(mm(r, c), centre);
        let mut lo: f64 = 0.0;
        let mut hi: f64 = 0.0;
        for q in corners {
            let mut d = angle01(q, centre) - a0;
            if d > 0.5 {
                d -= 1.0;
            } else if d < -0.5 {
                d += 1.0;
            }
            lo = lo.min(d);
            hi = hi.max(d);
        }
        if hi - lo >= 0.5 {
            // The pixel contains the centre: it covers every direction.
            covered.iter_mut().for_each(|b| *b = true);
            continue;
        }
        let b0 = ((a0 + lo) * nb as f64).floor() as i64;
        let b1 = ((a0 + hi) * nb as f64).floor() as i64;
        for b in b0..=b1 {
            covered[b.rem_euclid(nb as i64) as usize] = true;
        }
    }
    covered
}

/// The longest circular run of uncovered bins as (start bin, length);
/// `None` when no bin is covered, length 0 when every bin is.
fn longest_gap(covered: &[bool]) -> Option<(usize, usize)> {
    let nb = covered.len();
    let first_covered = covered.iter().position(|&b| b)?;
    let mut best = (0usize, 0usize); // (start bin, length)
    let mut run_start = None;
    for k in 1..=nb {
        let i = (first_covered + k) % nb;
        if !covered[i] {
            if run_start.is_none() {
                run_start = Some((i, k));
            }
        } else if let Some((s, k0)) = run_start.take() {
            let len = k - k0;
            if len > best.1 {
                best = (s, len);
            }
        }
    }
    Some(best)
}

/// A bone pixel (row, col) and its centre in mm.
type Px = (usize, usize, Point);

/// The closest pair of a pixel of `side_a` and one of `side_b` (the first
/// found among equals).
fn closest_pair(side_a: &[Px], side_b: &[Px]) -> Option<(Px, Px)> {
    let mut best_pair: Option<(f64, Px, Px)> = None;
    for &pa in side_a {
        for &pb in side_b {
            let d = pa.2.distance_squared(pb.2);
            if best_pair.is_none_or(|(bd, _, _)| d < bd) {
                best_pair = Some((d, pa, pb));
            }
        }
    }
    best_pair.map(|(_, pa, pb)| (pa, pb))
}

/// Finds the gap in the bone ring of `mask` (one slice, typically the
/// largest component), with pixel spacing `sx`, `sy` in mm; `None` when the
/// ring covers every direction from its centre or the widest gap is below
/// `min_gap_deg`.
pub fn detect_defect(mask: &Mask2, sx: f64, sy: f64, params: &DefectParams) -> Option<Defect> {
    let pixels = mask.pixels();
    if pixels.is_empty() {
        return None;
    }
    let mm = |r: f64, c: f64| Point::new(c * sx, r * sy);
    let centre = pixels
        .iter()
        .fold(Point::ZERO, |s, &(r, c)| s + mm(r as f64, c as f64))
        / pixels.len() as f64;
    let nb = params.bins.max(8);
    let covered = angular_coverage(&pixels, mm, centre, nb);
    let best = longest_gap(&covered)?;
    let width_deg = best.1 as f64 * 360.0 / nb as f64;
    if best.1 == 0 || width_deg < params.min_gap_deg {
        return None;
    }
    let start = best.0 as f64 / nb as f64; // gap start, turns
    let width = best.1 as f64 / nb as f64;
    let win = params.side_window_deg / 360.0;
    // Side A: angles in [start − win, start]; side B: [start + width, + win].
    let mut side_a = Vec::new();
    let mut side_b = Vec::new();
    for &(r, c) in &pixels {
        let p = mm(r as f64, c as f64);
        let a = angle01(p, centre);
        let da = (start - a).rem_euclid(1.0);
        let db = (a - (start + width)).rem_euclid(1.0);
        if da <= win {
            side_a.push((r, c, p));
        }
        if db <= win {
            side_b.push((r, c, p));
        }
    }
    let (pa, pb) = closest_pair(&side_a, &side_b)?;
    Some(Defect {
        a: (pa.0, pa.1),
        b: (pb.0, pb.1),
        a_mm: pa.2,
        b_mm: pb.2,
        centre,
        gap_start_deg: start * 360.0,
        gap_width_deg: width_deg,
    })
}
