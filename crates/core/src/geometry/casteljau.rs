//! The de Casteljau algorithm (de Casteljau 1959; Farin 2002, §4.2), shared by
//! the polynomial and rational any-degree curves.

use std::ops::{Add, Mul, Sub};

use super::Point;

/// Largest control polygon evaluated in a stack buffer; longer ones allocate.
pub(crate) const STACK_LEN: usize = 32;

/// A value the de Casteljau algorithm can combine affinely.
pub(crate) trait Affine:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<f64, Output = Self>
{
    /// The additive identity.
    const ZERO: Self;

    /// `(1 − t)a + t b`.
    #[inline]
    fn mix(self, other: Self, t: f64) -> Self {
        self * (1.0 - t) + other * t
    }
}

impl Affine for Point {
    const ZERO: Point = Point::ZERO;
}

/// A homogeneous point `(w x, w y, w)` (Farin 2002, §13.1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hom {
    pub x: f64,
    pub y: f64,
    pub w: f64,
}

impl Hom {
    /// Lifts `p` with weight `w` to `(w p, w)`.
    #[inline]
    pub(crate) fn lift(p: Point, w: f64) -> Hom {
        Hom {
            x: w * p.x,
            y: w * p.y,
            w,
        }
    }

    /// The `(x, y)` part `A` of the homogeneous point, unprojected.
    #[inline]
    pub(crate) fn xy(self) -> Point {
        Point::new(self.x, self.y)
    }
}

impl Add for Hom {
    type Output = Hom;
    #[inline]
    fn add(self, o: Hom) -> Hom {
        Hom {
            x: self.x + o.x,
            y: self.y + o.y,
            w: self.w + o.w,
        }
    }
}

impl Sub for Hom {
    type Output = Hom;
    #[inline]
    fn sub(self, o: Hom) -> Hom {
        Hom {
            x: self.x - o.x,
            y: self.y - o.y,
            w: self.w - o.w,
        }
    }
}

impl Mul<f64> for Hom {
    type Output = Hom;
    #[inline]
    fn mul(self, s: f64) -> Hom {
        Hom {
            x: self.x * s,
            y: self.y * s,
            w: self.w * s,
        }
    }
}

impl Affine for Hom {
    const ZERO: Hom = Hom {
        x: 0.0,
        y: 0.0,
        w: 0.0,
    };
}

/// Value, first and second derivative `[P(t), P'(t), P''(t)]` of the Bézier
/// polynomial with `len` control values `get(0..len)`.
///
/// The last de Casteljau levels give the derivatives for free:
/// `P' = n(b₁ − b₀)` and `P'' = n(n−1)(c₂ − 2c₁ + c₀)` where `b`, `c` are the
/// points of levels `n−1`, `n−2` (Farin 2002, §5.3).
#[inline]
pub(crate) fn jet<T: Affine>(len: usize, get: impl Fn(usize) -> T, t: f64) -> [T; 3] {
    if len <= STACK_LEN {
        let mut buf = [T::ZERO; STACK_LEN];
        for (i, b) in buf[..len].iter_mut().enumerate() {
            *b = get(i);
        }
        jet_in_place(&mut buf[..len], t)
    } else {
        let mut buf: Vec<T> = (0..len).map(get).collect();
        jet_in_place(&mut buf, t)
    }
}

/// As [`jet`], overwriting `b` with intermediate de Casteljau points.
fn jet_in_place<T: Affine>(b: &mut [T], t: f64) -> [T; 3] {
    match *b {
        [] => [T::ZERO; 3],
        [b0] => [b0, T::ZERO, T::ZERO],
        [b0, b1] => [b0.mix(b1, t), b1 - b0, T::ZERO],
        _ => {
            let n = b.len() - 1;
            for level in 1..=n - 2 {
                for i in 0..=n - level {
                    b[i] = b[i].mix(b[i + 1], t);
                }
            }
            let (c0, c1, c2) = (b[0], b[1], b[2]);
            let nf = n as f64;
            let d2 = (c2 - c1 * 2.0 + c0) * (nf * (nf - 1.0));
            let b0 = c0.mix(c1, t);
            let b1 = c1.mix(c2, t);
            [b0.mix(b1, t), (b1 - b0) * nf, d2]
        }
    }
}

/// Projects a homogeneous jet `[H, H', H'']` with `H = (A, W)` to the rational
/// curve's `[Q, Q', Q'']` by the quotient rule:
/// `Q = A/W`, `Q' = (A' − W'Q)/W`, `Q'' = (A'' − 2W'Q' − W''Q)/W` (Farin 2002, §13.4).
#[inline]
pub(crate) fn project_jet([h, d1, d2]: [Hom; 3]) -> [Point; 3] {
    let inv = 1.0 / h.w;
    let q = h.xy() * inv;
    let q1 = (d1.xy() - q * d1.w) * inv;
    let q2 = (d2.xy() - q1 * (2.0 * d1.w) - q * d2.w) * inv;
    [q, q1, q2]
}
