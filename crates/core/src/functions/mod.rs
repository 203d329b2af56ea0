//! The ten classic benchmark functions of Yao, Liu & Lin (1999), "Evolutionary
//! programming made faster", IEEE TEC 3(2):82–102, in the selection used by
//! Omran & Mahdavi (2008), "Global-best harmony search", Appl. Math. Comput.
//! 198(2):643–656.
//!
//! [`Function`] names a benchmark and evaluates it on a slice; [`TestProblem`]
//! fixes a function at a dimension and implements
//! [`Problem`](crate::problem::Problem) for the optimisers. Every function is
//! minimised.
//!
//! # Numerical conventions
//!
//! * Sums run strictly left to right over the variables (no pairwise or
//!   vectorised reassociation), so a value is bit-reproducible on any CPU with
//!   the same `libm`. Each summand is formed completely before it is added.
//! * Where the published formula adds and subtracts constants (Schwefel 2.26,
//!   Rastrigin, Ackley, Griewank), the constants are grouped with the term they
//!   cancel, e.g. Rastrigin as `Σ (x² + 10(1 − cos 2πx))` instead of
//!   `10D + Σ (x² − 10 cos 2πx)`. This is the same function, but the value at
//!   the optimum is exactly 0 and values near the optimum keep their
//!   precision instead of being the difference of two large numbers.
//! * [`Function::eval`] expects a non-empty slice (`x.len() == 2` for the
//!   camel-back, which panics otherwise); [`TestProblem`] guarantees both.

mod error;
mod formulas;
mod instance;
mod panels;
mod test_problem;

use std::fmt;

use crate::problem::Bounds;
use formulas::{
    ackley, griewank, rastrigin, rosenbrock, schwefel_1_2, schwefel_2_22, schwefel_2_26,
    six_hump_camel, sphere, step,
};

pub use error::FunctionError;
pub use instance::{instance_seed, Instance, Transform, MAX_ROTATION_DIM};
pub use test_problem::TestProblem;

/// The minimiser of Schwefel 2.26 in each coordinate, `x* = u²` with
/// `tan u = −u/2`, i.e. 420.968746359982027311844… rounded to the nearest f64.
const SCHWEFEL_226_X: f64 = 420.968_746_359_982_03;

/// The per-variable offset of Schwefel 2.26: `max x·sin √x` on `[0, 500]` is
/// 418.982887272433706274786… and this is the nearest f64 to it. It is also
/// bit-for-bit `x*·sin √x*` evaluated in f64 at [`SCHWEFEL_226_X`] (with a
/// correctly rounded `sin`, as in glibc), so each summand vanishes exactly there.
const SCHWEFEL_226_OFFSET: f64 = 418.982_887_272_433_7;

/// One global minimiser of the six-hump camel-back (the other is its mirror
/// `−x*`), to the nearest f64 of the exact root of the gradient,
/// (0.0898420131003180624…, −0.7126564030207396333…).
const CAMEL_X: [f64; 2] = [0.089_842_013_100_318_06, -0.712_656_403_020_739_6];

/// The minimum of the six-hump camel-back, −1.03162845348987735041… rounded to
/// the nearest f64.
const CAMEL_MIN: f64 = -1.031_628_453_489_877_4;

/// One of the ten benchmark functions of Yao, Liu & Lin (1999) used by
/// Omran & Mahdavi (2008); the Yao et al. number is given with each variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Function {
    /// Sphere (Yao f1): `Σ x_i²` on `[−100, 100]^D`, minimum 0 at `x = 0`.
    Sphere,
    /// Schwefel 2.22 (Yao f2): `Σ |x_i| + Π |x_i|` on `[−10, 10]^D`, minimum 0 at `x = 0`.
    Schwefel222,
    /// Generalised Rosenbrock (Yao f5): `Σ_{i<D} 100(x_{i+1} − x_i²)² + (x_i − 1)²`
    /// on `[−30, 30]^D`, minimum 0 at `x = (1, …, 1)` (constant 0 when `D = 1`).
    Rosenbrock,
    /// Step (Yao f6): `Σ ⌊x_i + ½⌋²` on `[−100, 100]^D`, minimum 0 on the whole
    /// plateau `[−½, ½)^D`; `⌊x + ½⌋` is computed exactly, with no rounding at `x → ½⁻`.
    Step,
    /// Schwefel 1.2, the rotated hyper-ellipsoid (Yao f3): `Σ_i (Σ_{j≤i} x_j)²`
    /// on `[−100, 100]^D`, minimum 0 at `x = 0`; evaluated in O(D) with a running prefix sum.
    Schwefel12,
    /// Generalised Schwefel 2.26 (Yao f8), shifted so the minimum is 0:
    /// `418.9828872724337·D − Σ x_i sin √|x_i|` on `[−500, 500]^D`, minimum at
    /// `x_i = 420.96874635998203`.
    Schwefel226,
    /// Generalised Rastrigin (Yao f9): `10D + Σ (x_i² − 10 cos 2πx_i)` on
    /// `[−5.12, 5.12]^D`, minimum 0 at `x = 0`.
    Rastrigin,
    /// Ackley (Yao f10): `−20 exp(−0.2 √(Σx_i²/D)) − exp(Σ cos(2πx_i)/D) + 20 + e`
    /// on `[−32, 32]^D`, minimum 0 at `x = 0`.
    Ackley,
    /// Generalised Griewank (Yao f11): `1 + Σ x_i²/4000 − Π cos(x_i/√i)` (i from 1)
    /// on `[−600, 600]^D`, minimum 0 at `x = 0`.
    Griewank,
    /// Six-hump camel-back (Yao f16): `4x² − 2.1x⁴ + x⁶/3 + xy − 4y² + 4y⁴` on
    /// `[−5, 5]²`, minimum −1.0316284534898774 at ±(0.08984201310031806, −0.7126564030207396).
    SixHumpCamel,
}

/// Evaluates `$body` with `$f` bound to the formula (a function item, so
/// calls stay direct) of the benchmark function `$function`: the one place a
/// [`Function`] is mapped to its evaluation.
macro_rules! with_formula {
    ($function:expr, $f:ident => $body:expr) => {
        with_formula!(@each $function, $f, $body;
            Sphere => sphere, Schwefel222 => schwefel_2_22, Rosenbrock => rosenbrock,
            Step => step, Schwefel12 => schwefel_1_2, Schwefel226 => schwefel_2_26,
            Rastrigin => rastrigin, Ackley => ackley, Griewank => griewank,
            SixHumpCamel => six_hump_camel)
    };
    (@each $function:expr, $f:ident, $body:expr; $($variant:ident => $formula:ident),+) => {
        match $function {
            $(Function::$variant => {
                let $f = $formula;
                $body
            })+
        }
    };
}

impl Function {
    /// All ten functions, in the order of Omran & Mahdavi (2008, Table 1).
    pub const ALL: [Function; 10] = [
        Function::Sphere,
        Function::Schwefel222,
        Function::Rosenbrock,
        Function::Step,
        Function::Schwefel12,
        Function::Schwefel226,
        Function::Rastrigin,
        Function::Ackley,
        Function::Griewank,
        Function::SixHumpCamel,
    ];

    /// The snake_case name used in experiment specs, e.g. `"schwefel_2_22"`.
    pub fn name(self) -> &'static str {
        match self {
            Function::Sphere => "sphere",
            Function::Schwefel222 => "schwefel_2_22",
            Function::Rosenbrock => "rosenbrock",
            Function::Step => "step",
            Function::Schwefel12 => "schwefel_1_2",
            Function::Schwefel226 => "schwefel_2_26",
            Function::Rastrigin => "rastrigin",
            Function::Ackley => "ackley",
            Function::Griewank => "griewank",
            Function::SixHumpCamel => "six_hump_camel",
        }
    }

    /// The function with this spec name (exact, case-sensitive match of
    /// [`Function::name`]), or `None`.
    pub fn from_name(name: &str) -> Option<Function> {
        Function::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The human-readable name, e.g. `"Schwefel 2.22"`, as in Yao et al. (1999).
    pub fn title(self) -> &'static str {
        match self {
            Function::Sphere => "Sphere",
            Function::Schwefel222 => "Schwefel 2.22",
            Function::Rosenbrock => "Rosenbrock",
            Function::Step => "Step",
            Function::Schwefel12 => "Schwefel 1.2",
            Function::Schwefel226 => "Schwefel 2.26",
            Function::Rastrigin => "Rastrigin",
            Function::Ackley => "Ackley",
            Function::Griewank => "Griewank",
            Function::SixHumpCamel => "Six-hump camel-back",
        }
    }

    /// The search interval of every variable, `[L, U]` as in Yao et al. (1999, Tables I–III).
    pub fn domain(self) -> Bounds {
        match self {
            Function::Sphere | Function::Step | Function::Schwefel12 => Bounds::new(-100.0, 100.0),
            Function::Schwefel222 => Bounds::new(-10.0, 10.0),
            Function::Rosenbrock => Bounds::new(-30.0, 30.0),
            Function::Schwefel226 => Bounds::new(-500.0, 500.0),
            Function::Rastrigin => Bounds::new(-5.12, 5.12),
            Function::Ackley => Bounds::new(-32.0, 32.0),
            Function::Griewank => Bounds::new(-600.0, 600.0),
            Function::SixHumpCamel => Bounds::new(-5.0, 5.0),
        }
    }

    /// The only dimension the function is defined for (`Some(2)` for the
    /// six-hump camel-back), or `None` if it is scalable to any `D ≥ 1`.
    pub fn fixed_dim(self) -> Option<usize> {
        match self {
            Function::SixHumpCamel => Some(2),
            _ => None,
        }
    }

    /// Whether the function is defined for every dimension `D ≥ 1`
    /// (all but the six-hump camel-back).
    pub fn is_scalable(self) -> bool {
        self.fixed_dim().is_none()
    }

    /// The global minimum value `f*`: 0 for all but the six-hump camel-back
    /// (−1.0316284534898774, the nearest f64 to −1.03162845348987735…).
    ///
    /// [`Function::eval`] at [`Function::optimum_location`] returns exactly 0
    /// for Sphere, Schwefel 2.22, Rosenbrock, Step, Schwefel 1.2, Rastrigin and
    /// Griewank. The residuals of the others are:
    /// * Schwefel 2.26: exactly 0 with a correctly rounded `sin` (glibc);
    ///   in general `|f(x*)| ≤ 2.5·10⁻¹³·D` (a few ulps of 418.98 per variable).
    ///   Neighbouring f64 points may evaluate down to about `−1.2·10⁻¹³·D`,
    ///   because `x sin √x` rounds up to the offset's ulp there.
    /// * Ackley: exactly 0 when `exp(1)` is correctly rounded (glibc);
    ///   in general `|f(0)| ≤ 4.5·10⁻¹⁶` (one ulp of e).
    /// * Six-hump camel-back: within `2·10⁻¹⁵` of `f*` at both minimisers.
    pub fn optimum_value(self) -> f64 {
        match self {
            Function::SixHumpCamel => CAMEL_MIN,
            _ => 0.0,
        }
    }

    /// A global minimiser of dimension `dim` (for the camel-back, whose
    /// dimension is fixed, `dim` is ignored and the 2-vector is returned):
    /// zeros, ones for Rosenbrock, `420.96874635998203` per variable for Schwefel 2.26.
    pub fn optimum_location(self, dim: usize) -> Vec<f64> {
        match self {
            Function::Rosenbrock => vec![1.0; dim],
            Function::Schwefel226 => vec![SCHWEFEL_226_X; dim],
            Function::SixHumpCamel => CAMEL_X.to_vec(),
            _ => vec![0.0; dim],
        }
    }

    /// Whether shifted and rotated instances ([`Transform`]) are defined: for
    /// the eight functions with one minimiser whose value does not depend on
    /// the box. Schwefel 2.26 is excluded because its minimiser sits near
    /// the corner of the box and a deceptive second-best lies at the far
    /// corner: shifting it moves the global minimum out of the box or turns
    /// it into a different function; the six-hump camel-back has two
    /// global minimisers and a fixed dimension.
    pub fn is_transformable(self) -> bool {
        !matches!(self, Function::Schwefel226 | Function::SixHumpCamel)
    }

    /// Evaluates the function at `x` (non-empty; exactly 2 variables for the
    /// camel-back, which panics otherwise), with the formulas of Yao et al. (1999).
    #[inline]
    pub fn eval(self, x: &[f64]) -> f64 {
        with_formula!(self, f => f(x))
    }

    /// `f` at each row of the row-major `xs` (rows of length `dim ≥ 1`),
    /// into `out`: the values of [`Function::eval`], with the function
    /// chosen once for the whole batch instead of once per row.
    pub fn eval_rows(self, xs: &[f64], dim: usize, out: &mut [f64]) {
        #[inline(always)]
        fn each(xs: &[f64], dim: usize, out: &mut [f64], f: impl Fn(&[f64]) -> f64) {
            for (o, x) in out.iter_mut().zip(xs.chunks_exact(dim)) {
                *o = f(x);
            }
        }
        with_formula!(self, f => each(xs, dim, out, f))
    }
}

impl fmt::Display for Function {
    /// Writes the spec name ([`Function::name`]).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests;
