//! The optimisation problem: a box-bounded objective to minimise.
//!
//! This is the "cost function" side of the problem/solver/executor split used
//! by argmin: a [`Problem`] knows its dimension, the per-variable [`Bounds`]
//! (the thesis's `Lx_i`, `Ux_i`) and how to evaluate the objective. It knows
//! nothing of the algorithm that solves it.

/// Closed bounds `[lower, upper]` on one decision variable `x_i`
/// (the thesis's `Lx_i ≤ x_i ≤ Ux_i`).
///
/// ```
/// use metabezier_core::problem::{BoundPolicy, Bounds};
///
/// let b = Bounds::new(-1.0, 3.0);
/// assert_eq!(b.width(), 4.0);
/// assert_eq!(b.repair(5.0, BoundPolicy::Clip), 3.0);
/// assert_eq!(b.repair(3.5, BoundPolicy::Reflect), 2.5);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Lower bound `Lx_i`.
    pub lower: f64,
    /// Upper bound `Ux_i`.
    pub upper: f64,
}

/// How an optimiser brings a trial value that left its [`Bounds`] back inside.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BoundPolicy {
    /// Project onto the nearest bound: `min(max(x, L), U)`.
    #[default]
    Clip,
    /// Mirror at the violated bound, `L + (L − x)` or `U − (x − U)`, repeated
    /// until the value is inside (clipped if the box has zero width).
    Reflect,
}

impl BoundPolicy {
    /// The names accepted in experiment specs, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["clip", "reflect"];

    /// Parses a spec name (`"clip"` or `"reflect"`).
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "clip" => Some(Self::Clip),
            "reflect" => Some(Self::Reflect),
            _ => None,
        }
    }

    /// The spec name of this policy.
    pub fn name(self) -> &'static str {
        match self {
            Self::Clip => "clip",
            Self::Reflect => "reflect",
        }
    }
}

impl Bounds {
    /// Bounds `[lower, upper]`; the caller guarantees `lower ≤ upper`.
    pub const fn new(lower: f64, upper: f64) -> Self {
        Self { lower, upper }
    }

    /// The range `U − L`.
    #[inline]
    pub fn width(self) -> f64 {
        self.upper - self.lower
    }

    /// Whether `L ≤ x ≤ U`.
    #[inline]
    pub fn contains(self, x: f64) -> bool {
        x >= self.lower && x <= self.upper
    }

    /// The point `L + u·(U − L)` for `u ∈ [0, 1]`, clipped so rounding
    /// cannot leave the box.
    #[inline]
    pub fn lerp(self, u: f64) -> f64 {
        self.clip(self.lower + u * self.width())
    }

    /// The normalised coordinate `(x − L)/(U − L)`, or 0 for a zero-width box.
    #[inline]
    pub fn normalise(self, x: f64) -> f64 {
        let w = self.width();
        if w > 0.0 {
            (x - self.lower) / w
        } else {
            0.0
        }
    }

    /// `min(max(x, L), U)`; a NaN becomes `L` so that no NaN is ever evaluated.
    #[inline]
    pub fn clip(self, x: f64) -> f64 {
        if x >= self.lower {
            if x <= self.upper {
                x
            } else {
                self.upper
            }
        } else {
            self.lower
        }
    }

    /// Reflects `x` at the bounds until it lies inside (see [`BoundPolicy::Reflect`]).
    #[inline]
    pub fn reflect(self, x: f64) -> f64 {
        let w = self.width();
        if self.contains(x) {
            return x;
        }
        if w.is_nan() || w <= 0.0 || !x.is_finite() {
            return self.clip(x);
        }
        // Reflection with period 2w: fold the distance from L into [0, 2w).
        let d = (x - self.lower).rem_euclid(2.0 * w);
        let y = if d <= w {
            self.lower + d
        } else {
            self.upper - (d - w)
        };
        self.clip(y)
    }

    /// Brings `x` inside the bounds with the given policy.
    #[inline]
    pub fn repair(self, x: f64, policy: BoundPolicy) -> f64 {
        match policy {
            BoundPolicy::Clip => self.clip(x),
            BoundPolicy::Reflect => self.reflect(x),
        }
    }
}

/// A box-bounded minimisation problem: minimise `f(x)` for `x ∈ Π [Lx_i, Ux_i]`.
///
/// Implementations must return the same value for the same `x` (they are
/// pure functions of `x`); a NaN or infinite value is allowed and is ranked
/// worse than every finite value by the optimisers.
///
/// ```
/// use metabezier_core::problem::{Bounds, Problem};
///
/// /// f(x) = Σ |x_i| on [−1, 1]^D.
/// struct Abs(Vec<Bounds>);
/// impl Problem for Abs {
///     fn dim(&self) -> usize { self.0.len() }
///     fn bounds(&self) -> &[Bounds] { &self.0 }
///     fn objective(&self, x: &[f64]) -> f64 { x.iter().map(|v| v.abs()).sum() }
/// }
///
/// let p = Abs(vec![Bounds::new(-1.0, 1.0); 3]);
/// let mut out = [0.0; 2];
/// // The default batch evaluation is the objective row by row.
/// p.objective_batch(&[0.5, -0.5, 0.0, 1.0, 1.0, 1.0], &mut out);
/// assert_eq!(out, [1.0, 3.0]);
/// ```
pub trait Problem {
    /// The number of decision variables `N_DV`.
    fn dim(&self) -> usize;

    /// The bounds of each decision variable; its length is [`Problem::dim`].
    fn bounds(&self) -> &[Bounds];

    /// The objective value `f(x)`; `x.len() == self.dim()`.
    fn objective(&self, x: &[f64]) -> f64;

    /// The objective values of `out.len()` points stored row-major in `xs`
    /// (`xs.len() == out.len() · dim`): `out[i] = f(xs[i·D..(i+1)·D])`.
    ///
    /// The default calls [`Problem::objective`] row by row; a problem may
    /// override it to share work across the rows, but must return exactly the
    /// values `objective` would.
    fn objective_batch(&self, xs: &[f64], out: &mut [f64]) {
        objective_rows(self, xs, out)
    }
}

/// [`Problem::objective`] of each row of the row-major `xs` into `out`: the
/// default [`Problem::objective_batch`], for overrides that fall back to it.
pub fn objective_rows<P: Problem + ?Sized>(problem: &P, xs: &[f64], out: &mut [f64]) {
    let dim = problem.dim();
    debug_assert_eq!(xs.len(), out.len() * dim);
    for (i, o) in out.iter_mut().enumerate() {
        *o = problem.objective(&xs[i * dim..(i + 1) * dim]);
    }
}

impl<P: Problem + ?Sized> Problem for &P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn bounds(&self) -> &[Bounds] {
        (**self).bounds()
    }
    fn objective(&self, x: &[f64]) -> f64 {
        (**self).objective(x)
    }
    fn objective_batch(&self, xs: &[f64], out: &mut [f64]) {
        (**self).objective_batch(xs, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clip_and_reflect_stay_inside() {
        let b = Bounds::new(-1.0, 3.0);
        assert_eq!(b.clip(5.0), 3.0);
        assert_eq!(b.clip(-7.0), -1.0);
        assert_eq!(b.clip(f64::NAN), -1.0);
        assert_eq!(b.reflect(3.5), 2.5);
        assert_eq!(b.reflect(-1.5), -0.5);
        // Two widths away folds back twice.
        assert_eq!(b.reflect(3.0 + 4.0 + 1.0), 0.0);
        for k in -50..50 {
            let x = k as f64 * 0.37;
            assert!(b.contains(b.reflect(x)), "reflect({x})");
            assert!(b.contains(b.repair(x, BoundPolicy::Clip)));
        }
    }

    #[test]
    fn normalise_inverts_lerp() {
        let b = Bounds::new(-600.0, 600.0);
        for u in [0.0, 0.25, 0.5, 1.0] {
            assert!((b.normalise(b.lerp(u)) - u).abs() < 1e-15);
        }
        assert_eq!(Bounds::new(2.0, 2.0).normalise(2.0), 0.0);
    }
}
