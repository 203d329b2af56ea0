//! The ten classic benchmark functions of Yao, Liu & Lin (1999), "Evolutionary
//! programming made faster", IEEE TEC 3(2):82–102, in the selection used by
//! Omran & Mahdavi (2008), "Global-best harmony search", Appl. Math. Comput.
//! 198(2):643–656.
//!
//! [`Function`] names a benchmark and evaluates it on a slice; [`TestProblem`]
//! fixes a function at a dimension and implements [`Problem`] for the
//! optimisers. Every function is minimised.
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

mod formulas;
mod instance;
mod panels;

use std::fmt;
use std::sync::Arc;

use crate::problem::{objective_rows, Bounds, Problem};
use formulas::{
    ackley, griewank, rastrigin, rosenbrock, schwefel_1_2, schwefel_2_22, schwefel_2_26,
    six_hump_camel, sphere, step,
};

pub use instance::{instance_seed, Instance, Transform, MAX_ROTATION_DIM};

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

// ---------------------------------------------------------------------------

/// Why a [`TestProblem`] could not be built: the requested dimension is not one
/// the benchmark function of Yao et al. (1999) is defined for.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FunctionError {
    /// Dimension 0 was requested for a scalable function (which needs `D ≥ 1`).
    ZeroDimension {
        /// The function requested.
        function: Function,
    },
    /// A fixed-dimension function (the camel-back, `D = 2`) was requested at another dimension.
    WrongDimension {
        /// The function requested.
        function: Function,
        /// The only dimension it is defined for.
        required: usize,
        /// The dimension that was asked for.
        requested: usize,
    },
    /// A transform was asked for a function that does not admit one
    /// ([`Function::is_transformable`]).
    NotTransformable {
        /// The function requested.
        function: Function,
        /// The transform requested.
        transform: Transform,
    },
    /// A rotation was asked above [`MAX_ROTATION_DIM`].
    RotationTooLarge {
        /// The dimension that was asked for.
        requested: usize,
    },
}

impl fmt::Display for FunctionError {
    /// A sentence naming the function and the valid dimension(s).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FunctionError::ZeroDimension { function } => write!(
                f,
                "{function} is defined only for dimension 1 or more, not 0"
            ),
            FunctionError::WrongDimension {
                function,
                required,
                requested,
            } => write!(
                f,
                "{function} is defined only for dimension {required}, not {requested}"
            ),
            FunctionError::NotTransformable {
                function,
                transform,
            } => write!(
                f,
                "{function} has no \"{transform}\" instances: only sphere, schwefel_2_22, rosenbrock, step, schwefel_1_2, rastrigin, ackley and griewank are shifted or rotated ({})",
                match function {
                    Function::SixHumpCamel => "the camel-back has two global minimisers and a fixed dimension",
                    _ => "Schwefel 2.26's minimiser lies near a corner of the box, so a shift would move it out",
                }
            ),
            FunctionError::RotationTooLarge { requested } => write!(
                f,
                "a rotation needs D ≤ {MAX_ROTATION_DIM} (it has D² entries and costs O(D³) to draw), not {requested}; use \"shift\""
            ),
        }
    }
}

impl std::error::Error for FunctionError {}

/// A benchmark [`Function`] at a fixed dimension `D`, on the box `domain()^D`:
/// the [`Problem`] the optimisers of Omran & Mahdavi (2008) are compared on.
///
/// ```
/// use metabezier_core::functions::{Function, TestProblem, Transform};
/// use metabezier_core::problem::Problem;
///
/// let rastrigin = TestProblem::new(Function::Rastrigin, 10).unwrap();
/// assert_eq!(rastrigin.objective(&[0.0; 10]), 0.0);
/// // A shifted and rotated instance k moves the optimum, not its value.
/// let moved = TestProblem::instance(Function::Rastrigin, 10, Transform::ShiftRotate, 3).unwrap();
/// assert_eq!(moved.dim(), 10);
/// // The camel-back function exists at D = 2 only.
/// assert!(TestProblem::new(Function::SixHumpCamel, 3).is_err());
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TestProblem {
    function: Function,
    dim: usize,
    bounds: Vec<Bounds>,
    instance: Option<Arc<Instance>>,
}

/// Dimensions up to this evaluate a transformed instance without allocating.
const STACK_DIM: usize = 128;

/// The smaller stack buffer, for the thesis's dimensions up to 32.
const SMALL_STACK_DIM: usize = 32;

impl TestProblem {
    /// The function at dimension `dim`; fails if `dim == 0`, or if the
    /// function has a fixed dimension (camel-back: 2) and `dim` differs.
    pub fn new(function: Function, dim: usize) -> Result<TestProblem, FunctionError> {
        if let Some(required) = function.fixed_dim() {
            if dim != required {
                return Err(FunctionError::WrongDimension {
                    function,
                    required,
                    requested: dim,
                });
            }
        }
        if dim == 0 {
            return Err(FunctionError::ZeroDimension { function });
        }
        Ok(TestProblem {
            function,
            dim,
            bounds: vec![function.domain(); dim],
            instance: None,
        })
    }

    /// Instance `k` of the function at `dim` under `transform` (see
    /// [`Instance`]); `Transform::None` is the plain function. Fails as
    /// [`TestProblem::new`] does, for a function that admits no transform,
    /// and for a rotation above [`MAX_ROTATION_DIM`].
    pub fn instance(
        function: Function,
        dim: usize,
        transform: Transform,
        k: u32,
    ) -> Result<TestProblem, FunctionError> {
        Self::check_instance(function, dim, transform)?;
        let plain = Self::new(function, dim)?;
        Ok(match transform {
            Transform::None => plain,
            _ => plain.with_instance(Arc::new(Instance::new(function, dim, transform, k))),
        })
    }

    /// Whether `transform` can be applied to `function` at `dim`.
    pub fn check_instance(
        function: Function,
        dim: usize,
        transform: Transform,
    ) -> Result<(), FunctionError> {
        if transform != Transform::None && !function.is_transformable() {
            return Err(FunctionError::NotTransformable {
                function,
                transform,
            });
        }
        if transform == Transform::ShiftRotate && dim > MAX_ROTATION_DIM {
            return Err(FunctionError::RotationTooLarge { requested: dim });
        }
        Ok(())
    }

    /// The function at `inst`'s map of `x`, through stack buffers of `N ≥ D`.
    #[inline]
    fn eval_mapped<const N: usize>(&self, inst: &Instance, x: &[f64]) -> f64 {
        let mut y = [0.0; N];
        if inst.rotation().is_some() {
            let mut scratch = [0.0; N];
            inst.map_into(x, &mut scratch, &mut y[..self.dim]);
        } else {
            inst.map_into(x, &mut [], &mut y[..self.dim]);
        }
        self.function.eval(&y[..self.dim])
    }

    /// This problem on an already drawn instance of its function and
    /// dimension (instances are shared between runs).
    pub fn with_instance(mut self, instance: Arc<Instance>) -> TestProblem {
        debug_assert_eq!(instance.shift().len(), self.dim);
        self.instance = Some(instance);
        self
    }

    /// The instance, if the function is transformed.
    pub fn transformed(&self) -> Option<&Instance> {
        self.instance.as_deref()
    }

    /// The benchmark function.
    pub fn function(&self) -> Function {
        self.function
    }

    /// The stable text key `name-dim`, e.g. `sphere-30` or `six_hump_camel-2`.
    pub fn key(&self) -> String {
        format!("{}-{}", self.function.name(), self.dim)
    }
}

impl Problem for TestProblem {
    #[inline]
    fn dim(&self) -> usize {
        self.dim
    }

    #[inline]
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    #[inline]
    fn objective(&self, x: &[f64]) -> f64 {
        debug_assert_eq!(
            x.len(),
            self.dim,
            "{}: wrong number of variables",
            self.key()
        );
        match &self.instance {
            None => self.function.eval(x),
            // Two stack sizes, so that a small D does not pay for zeroing
            // 128 entries per evaluation (the values are the same).
            Some(inst) if self.dim <= SMALL_STACK_DIM => {
                self.eval_mapped::<SMALL_STACK_DIM>(inst, x)
            }
            Some(inst) if self.dim <= STACK_DIM => self.eval_mapped::<STACK_DIM>(inst, x),
            Some(inst) => {
                let (mut scratch, mut y) = (vec![0.0; self.dim], vec![0.0; self.dim]);
                inst.map_into(x, &mut scratch, &mut y);
                self.function.eval(&y)
            }
        }
    }

    /// Untransformed rows are evaluated with the function chosen once per
    /// batch; transformed rows go through [`Problem::objective`]. The values
    /// are those of `objective`, row by row.
    fn objective_batch(&self, xs: &[f64], out: &mut [f64]) {
        debug_assert_eq!(xs.len(), out.len() * self.dim);
        if self.instance.is_some() || self.dim == 0 {
            return objective_rows(self, xs, out);
        }
        self.function.eval_rows(xs, self.dim, out);
    }
}

#[cfg(test)]
mod tests {
    use super::formulas::floor_half_up;
    use super::*;
    use std::f64::consts::{PI, SQRT_2};

    /// `|actual − expected| ≤ rel·max(1, |expected|)`.
    fn assert_close(actual: f64, expected: f64, rel: f64, what: &str) {
        let tol = rel * expected.abs().max(1.0);
        assert!(
            (actual - expected).abs() <= tol,
            "{what}: got {actual:e}, expected {expected:e} (tolerance {tol:e})"
        );
    }

    /// The documented tolerance of `f(x*)` around `f*`.
    fn optimum_tolerance(f: Function, dim: usize) -> f64 {
        match f {
            Function::Schwefel226 => 2.5e-13 * dim as f64,
            Function::Ackley => 4.5e-16,
            Function::SixHumpCamel => 2e-15,
            _ => 0.0,
        }
    }

    #[test]
    fn every_instance_keeps_f_star_at_its_shift() {
        for f in Function::ALL.into_iter().filter(|f| f.is_transformable()) {
            for d in [2, 10, 30] {
                for t in [Transform::Shift, Transform::ShiftRotate] {
                    for k in 1..=5 {
                        let p = TestProblem::instance(f, d, t, k).unwrap();
                        let o = p.transformed().unwrap().shift().to_vec();
                        assert!(o.iter().zip(p.bounds()).all(|(x, b)| b.contains(*x)));
                        let v = p.objective(&o);
                        let tol = optimum_tolerance(f, d);
                        assert!(
                            (v - f.optimum_value()).abs() <= tol,
                            "{f}-{d} {t} #{k}: F(o) = {v:e}"
                        );
                        // Away from o_k the value is worse.
                        let mut x = o.clone();
                        x[0] = p.bounds()[0].clip(x[0] + 0.3 * p.bounds()[0].width());
                        assert!(p.objective(&x) > f.optimum_value() + tol, "{f}-{d} {t}");
                    }
                }
            }
        }
        let big = TestProblem::instance(Function::Sphere, 200, Transform::ShiftRotate, 1).unwrap();
        let o = big.transformed().unwrap().shift().to_vec();
        assert_eq!(big.objective(&o), 0.0);
    }

    #[test]
    fn untransformable_functions_and_huge_rotations_are_refused() {
        for f in [Function::Schwefel226, Function::SixHumpCamel] {
            let e = TestProblem::instance(f, 2, Transform::Shift, 1).unwrap_err();
            assert!(e.to_string().contains("has no \"shift\" instances"), "{e}");
            assert!(TestProblem::instance(f, 2, Transform::None, 1).is_ok());
        }
        let e = TestProblem::instance(Function::Sphere, 1001, Transform::ShiftRotate, 1);
        assert_eq!(e, Err(FunctionError::RotationTooLarge { requested: 1001 }));
        let plain = TestProblem::instance(Function::Sphere, 3, Transform::None, 7).unwrap();
        assert_eq!(plain, TestProblem::new(Function::Sphere, 3).unwrap());
    }

    #[test]
    fn optimum_value_at_optimum_location() {
        for f in Function::ALL {
            let dims: &[usize] = if f.is_scalable() { &[2, 10, 30] } else { &[2] };
            for &d in dims {
                let x = f.optimum_location(d);
                assert_eq!(x.len(), d, "{f}");
                let v = f.eval(&x);
                let tol = optimum_tolerance(f, d);
                assert!(
                    (v - f.optimum_value()).abs() <= tol,
                    "{f}-{d}: f(x*) = {v:e}, f* = {:e}, tolerance {tol:e}",
                    f.optimum_value()
                );
            }
        }
    }

    #[test]
    fn camel_back_mirror_minimiser() {
        let [a, b] = CAMEL_X;
        let v = Function::SixHumpCamel.eval(&[-a, -b]);
        assert!((v - CAMEL_MIN).abs() <= 2e-15, "{v:e}");
        // The often-quoted (0.08984201368301331, −0.7126564032704135) is ~6e-10
        // off the true root but agrees in value.
        let quoted =
            Function::SixHumpCamel.eval(&[0.089_842_013_683_013_31, -0.712_656_403_270_413_5]);
        assert!((quoted - CAMEL_MIN).abs() <= 2e-15, "{quoted:e}");
    }

    #[test]
    fn optimum_is_a_local_minimum() {
        // Moving any one coordinate of x* by ±h must not go below f* (beyond the
        // documented tolerance); catches a wrong optimum location.
        for f in Function::ALL {
            let d = f.fixed_dim().unwrap_or(5);
            let x = f.optimum_location(d);
            let fstar = f.optimum_value();
            for i in 0..d {
                for h in [1e-3, -1e-3, 1e-6, -1e-6] {
                    let mut y = x.clone();
                    y[i] += h;
                    let v = f.eval(&y);
                    assert!(
                        v >= fstar - optimum_tolerance(f, d),
                        "{f}: f(x* + {h}e_{i}) = {v:e} < f* = {fstar:e}"
                    );
                    if f != Function::Step {
                        assert!(v > fstar, "{f}: x* + {h}e_{i} is not strictly worse");
                    }
                }
            }
        }
    }

    #[test]
    fn optimum_locations_are_stationary_points() {
        // Values are flat at a minimum, so check the gradient instead: it pins
        // the minimiser to ~1e-12, where f(x*) could not tell a 1e-8 error.
        // Schwefel 2.26: d/dx (x sin √x) = sin u + (u/2) cos u with u = √x.
        let u = SCHWEFEL_226_X.sqrt();
        let g1 = u.sin() + 0.5 * u * u.cos();
        assert!(g1.abs() < 1e-12, "Schwefel 2.26 slope at x*: {g1:e}");
        // Camel-back: ∂f/∂x = 8x − 8.4x³ + 2x⁵ + y, ∂f/∂y = x − 8y + 16y³.
        let [x, y] = CAMEL_X;
        let gx = 8.0 * x - 8.4 * x.powi(3) + 2.0 * x.powi(5) + y;
        let gy = x - 8.0 * y + 16.0 * y.powi(3);
        assert!(
            gx.abs() < 1e-12 && gy.abs() < 1e-12,
            "camel gradient ({gx:e}, {gy:e})"
        );
    }

    #[test]
    fn optimum_location_is_inside_the_domain() {
        for f in Function::ALL {
            let b = f.domain();
            assert!(b.lower < b.upper, "{f}");
            for v in f.optimum_location(f.fixed_dim().unwrap_or(3)) {
                assert!(b.contains(v), "{f}: {v} outside [{}, {}]", b.lower, b.upper);
            }
        }
    }

    #[test]
    fn domains_match_yao_et_al() {
        let expected = [
            (Function::Sphere, 100.0),
            (Function::Schwefel222, 10.0),
            (Function::Rosenbrock, 30.0),
            (Function::Step, 100.0),
            (Function::Schwefel12, 100.0),
            (Function::Schwefel226, 500.0),
            (Function::Rastrigin, 5.12),
            (Function::Ackley, 32.0),
            (Function::Griewank, 600.0),
            (Function::SixHumpCamel, 5.0),
        ];
        for (f, r) in expected {
            assert_eq!(f.domain(), Bounds::new(-r, r), "{f}");
        }
    }

    #[test]
    fn sphere_values() {
        assert_eq!(Function::Sphere.eval(&[1.0, 2.0, 3.0]), 14.0);
        assert_eq!(Function::Sphere.eval(&[-0.5]), 0.25);
        assert_eq!(Function::Sphere.eval(&[100.0; 30]), 300_000.0);
    }

    #[test]
    fn schwefel_2_22_values() {
        // Σ|x| = 6, Π|x| = 6.
        assert_eq!(Function::Schwefel222.eval(&[1.0, -2.0, 3.0]), 12.0);
        // Σ|x| = 1.25, Π|x| = 0.
        assert_eq!(Function::Schwefel222.eval(&[0.0, -0.25, 1.0]), 1.25);
        // D = 30 at the corner: 300 + 10³⁰.
        assert_close(
            Function::Schwefel222.eval(&[-10.0; 30]),
            1e30 + 300.0,
            1e-15,
            "corner",
        );
    }

    #[test]
    fn rosenbrock_values() {
        assert_eq!(Function::Rosenbrock.eval(&[0.0, 0.0]), 1.0);
        // 100(2 − 1)² + (−2)² = 104; 100(0.5 − 4)² + 1² = 1226.
        assert_eq!(Function::Rosenbrock.eval(&[-1.0, 2.0, 0.5]), 1330.0);
        // Only the last pair contributes: 100(2 − 1)².
        assert_eq!(Function::Rosenbrock.eval(&[1.0, 1.0, 1.0, 2.0]), 100.0);
        // D = 1 has no pair: constant 0.
        assert_eq!(Function::Rosenbrock.eval(&[7.0]), 0.0);
    }

    #[test]
    fn step_values() {
        // ⌊0.9⌋ = 0, ⌊−0.1⌋ = −1, ⌊2.0⌋ = 2.
        assert_eq!(Function::Step.eval(&[0.4, -0.6, 1.5]), 5.0);
        // The whole plateau [−½, ½)^D is optimal, including its exact edges.
        // (`f64::next_down` needs Rust 1.86; the crate's MSRV is 1.85.)
        let below_half = f64::from_bits(0.5f64.to_bits() - 1);
        assert_eq!(below_half, 0.499_999_999_999_999_94);
        assert_eq!(Function::Step.eval(&[-0.5, below_half, 0.0, -0.0]), 0.0);
        // ... and ½ itself is not.
        assert_eq!(Function::Step.eval(&[0.5]), 1.0);
        assert_eq!(
            Function::Step.eval(&[f64::from_bits((-0.5f64).to_bits() + 1)]),
            1.0
        );
        // ⌊−99.7 + ½⌋ = −100 → 10⁴.
        assert_eq!(Function::Step.eval(&[-99.7, 2.49]), 10_004.0);
    }

    #[test]
    fn floor_half_up_matches_exact_rounding() {
        for (x, r) in [
            (0.0, 0.0),
            (0.5, 1.0),
            (-0.5, 0.0),
            (0.499_999_999_999_999_94, 0.0),
            (1.499_999_999_999_999_8, 1.0),
            (-1.5, -1.0),
            (-1.500_000_000_000_000_2, -2.0),
            (2.5, 3.0),
            (-2.5, -2.0),
            (-1e-300, 0.0),
            (4_503_599_627_370_495.5, 4_503_599_627_370_496.0),
            (-4_503_599_627_370_495.5, -4_503_599_627_370_495.0),
            (4_503_599_627_370_497.0, 4_503_599_627_370_497.0),
            (-1e300, -1e300),
            (f64::INFINITY, f64::INFINITY),
            (f64::NEG_INFINITY, f64::NEG_INFINITY),
            (-3.0, -3.0),
            (-2.7, -3.0),
            (-2.2, -2.0),
            (99.5, 100.0),
        ] {
            assert_eq!(floor_half_up(x), r, "⌊{x} + ½⌋");
        }
        assert!(floor_half_up(f64::NAN).is_nan());
        // Agrees with the libm-based definition away from the rounding edge.
        for k in -4000..4000 {
            let x = k as f64 * 0.0137 + 0.001;
            assert_eq!(floor_half_up(x), (x + 0.5).floor(), "x = {x}");
        }
    }

    #[test]
    fn schwefel_1_2_values() {
        // Prefix sums 1, 3, 6: 1 + 9 + 36.
        assert_eq!(Function::Schwefel12.eval(&[1.0, 2.0, 3.0]), 46.0);
        // Prefix sums 1, 0, 2, −2: 1 + 0 + 4 + 4.
        assert_eq!(Function::Schwefel12.eval(&[1.0, -1.0, 2.0, -4.0]), 9.0);
    }

    #[test]
    fn schwefel_1_2_equals_the_quadratic_definition() {
        // The O(D) prefix sum is bit-identical to the O(D²) double sum.
        let x: Vec<f64> = (0..30)
            .map(|i| ((i * 37 % 23) as f64 - 11.3) * 7.77)
            .collect();
        let naive: f64 = (0..x.len()).fold(0.0, |s, i| {
            let inner = x[..=i].iter().fold(0.0, |t, &v| t + v);
            s + inner * inner
        });
        assert_eq!(Function::Schwefel12.eval(&x).to_bits(), naive.to_bits());
    }

    #[test]
    fn schwefel_2_26_values() {
        let c = SCHWEFEL_226_OFFSET;
        // sin √0 = 0: each variable contributes the offset.
        assert_eq!(Function::Schwefel226.eval(&[0.0, 0.0]), 2.0 * c);
        // 418.9828872724337 − 100 sin 10 (mpmath, 40 digits: 473.38499836137066746155…).
        assert_close(
            Function::Schwefel226.eval(&[100.0]),
            473.384_998_361_370_67,
            1e-15,
            "x = 100",
        );
        // The mirror of the minimiser is near the maximum: c + x* sin √x* + c
        // (mpmath: 1256.9486618173010785…).
        assert_close(
            Function::Schwefel226.eval(&[-SCHWEFEL_226_X, 0.0]),
            1_256.948_661_817_301_1,
            1e-15,
            "(−x*, 0)",
        );
        // 3c − sin 1 − 4 sin 2 + 9 sin 3 (mpmath: 1253.7400811977292400…).
        assert_close(
            Function::Schwefel226.eval(&[1.0, 4.0, -9.0]),
            1_253.740_081_197_729_2,
            1e-15,
            "(1, 4, −9)",
        );
    }

    #[test]
    fn schwefel_2_26_constants() {
        // The offset is x* sin √x* in f64, so each summand vanishes at x*.
        let g = SCHWEFEL_226_X * SCHWEFEL_226_X.sqrt().sin();
        assert!((g - SCHWEFEL_226_OFFSET).abs() <= 2.5e-13, "{g:e}");
        // The often-published 418.9828872724339 (two ulps too high) in the
        // literal form `c·D − Σ x sin √|x|` leaves ~5.5e-12 at D = 30; the
        // summand-wise form with the nearest-f64 offset does better.
        let published_form = 418.982_887_272_433_9 * 30.0 - (0..30).fold(0.0, |s, _| s + g);
        let ours = Function::Schwefel226.eval(&[SCHWEFEL_226_X; 30]);
        assert!(published_form.abs() > 1e-12, "{published_form:e}");
        assert!(
            ours.abs() <= 2.5e-13 * 30.0 && ours.abs() < published_form.abs(),
            "{ours:e}"
        );
        // Around x*, no f64 is worse than the documented lower bound per variable.
        let bits = SCHWEFEL_226_X.to_bits();
        for y in (bits - 1000..=bits + 1000).map(f64::from_bits) {
            let v = Function::Schwefel226.eval(&[y]);
            assert!((-2.5e-13..=1e-9).contains(&v), "f({y}) = {v:e}");
        }
    }

    #[test]
    fn rastrigin_values() {
        assert_eq!(Function::Rastrigin.eval(&[1.0, 1.0]), 2.0);
        // (0.25 + 20) + (2.25 + 20) + (4 + 0).
        assert_eq!(Function::Rastrigin.eval(&[0.5, -1.5, 2.0]), 46.5);
        // 0.0625 + 10(1 − cos(π/2)) = 10.0625.
        assert_close(
            Function::Rastrigin.eval(&[0.25]),
            10.0625,
            1e-15,
            "x = 0.25",
        );
    }

    #[test]
    fn ackley_values() {
        // f(0) is exactly 0 with the grouping used (documented bound: one ulp of e).
        for d in [1, 2, 30] {
            assert!(Function::Ackley.eval(&vec![0.0; d]).abs() <= 4.5e-16);
        }
        // Σx²/D = 1, Σcos/D = 1: 20(1 − e^−0.2) (mpmath: 3.6253849384403630083…).
        assert_close(
            Function::Ackley.eval(&[1.0, 1.0]),
            3.625_384_938_440_363,
            1e-15,
            "(1, 1)",
        );
        // √(Σx²/D) = ½, Σcos/D = −1: 20(1 − e^−0.1) + e − e^−1 (mpmath: 4.2536540265684115509…).
        assert_close(
            Function::Ackley.eval(&[0.5, 0.5]),
            4.253_654_026_568_411_6,
            1e-15,
            "(½, ½)",
        );
        // mpmath: 5.4221317177995082164…
        assert_close(
            Function::Ackley.eval(&[1.0, 2.0]),
            5.422_131_717_799_508,
            1e-15,
            "(1, 2)",
        );
        // mpmath: 8.9892644965369578022…
        assert_close(
            Function::Ackley.eval(&[-3.0, 0.25, 2.5]),
            8.989_264_496_536_958,
            1e-15,
            "(−3, ¼, 2.5)",
        );
        // The corner (mpmath: 19.966768854536521321…).
        assert_close(
            Function::Ackley.eval(&[32.0, 32.0]),
            19.966_768_854_536_52,
            1e-15,
            "(32, 32)",
        );
    }

    #[test]
    fn griewank_values() {
        // x_i/√i = π for both: Π cos = 1, so f = 3π²/4000 (mpmath: 0.0074022033008170189641…).
        assert_close(
            Function::Griewank.eval(&[PI, PI * SQRT_2]),
            0.007_402_203_300_817_019,
            1e-15,
            "(π, π√2)",
        );
        // 1 + 14/4000 − cos 1 cos(2/√2) cos(3/√3) (mpmath: 1.0170279701835734335…).
        assert_close(
            Function::Griewank.eval(&[1.0, 2.0, 3.0]),
            1.017_027_970_183_573_4,
            1e-15,
            "(1, 2, 3)",
        );
        // 1 + 12500/4000 − cos 100 cos(−50/√2) (mpmath: 4.7271305211515814565…).
        assert_close(
            Function::Griewank.eval(&[100.0, -50.0]),
            4.727_130_521_151_581,
            1e-15,
            "(100, −50)",
        );
    }

    #[test]
    fn six_hump_camel_values() {
        assert_eq!(Function::SixHumpCamel.eval(&[0.0, 0.0]), 0.0);
        // 4 − 2.1 + 1/3 + 1 − 4 + 4 = 97/30.
        assert_close(
            Function::SixHumpCamel.eval(&[1.0, 1.0]),
            97.0 / 30.0,
            1e-15,
            "(1, 1)",
        );
        // 4 − 2.1 + 1/3 − 2 − 16 + 64 = 48.2333…
        assert_close(
            Function::SixHumpCamel.eval(&[-1.0, 2.0]),
            48.233_333_333_333_333,
            1e-15,
            "(−1, 2)",
        );
        // 1 − 0.13125 + 0.015625/3 − 0.125 − 0.25 + 0.015625 = 0.5145833…
        assert_close(
            Function::SixHumpCamel.eval(&[0.5, -0.25]),
            0.514_583_333_333_333_3,
            1e-15,
            "(½, −¼)",
        );
    }

    #[test]
    #[should_panic(expected = "six_hump_camel takes exactly 2 variables, got 3")]
    fn six_hump_camel_rejects_other_lengths() {
        Function::SixHumpCamel.eval(&[0.0, 0.0, 0.0]);
    }

    #[test]
    fn names_round_trip_and_are_distinct() {
        for f in Function::ALL {
            assert_eq!(Function::from_name(f.name()), Some(f));
            assert_eq!(f.to_string(), f.name());
            assert!(!f.title().is_empty());
        }
        let mut names: Vec<&str> = Function::ALL.iter().map(|f| f.name()).collect();
        let mut titles: Vec<&str> = Function::ALL.iter().map(|f| f.title()).collect();
        names.sort_unstable();
        names.dedup();
        titles.sort_unstable();
        titles.dedup();
        assert_eq!(names.len(), 10);
        assert_eq!(titles.len(), 10);
        assert_eq!(Function::Schwefel222.title(), "Schwefel 2.22");
        assert_eq!(Function::Schwefel12.name(), "schwefel_1_2");
    }

    #[test]
    fn unknown_names_are_rejected() {
        for name in [
            "",
            "Sphere",
            "SPHERE",
            "sphere ",
            "schwefel",
            "schwefel_2_21",
            "six-hump-camel",
            "camel",
        ] {
            assert_eq!(Function::from_name(name), None, "{name:?}");
        }
    }

    #[test]
    fn scalability() {
        for f in Function::ALL {
            assert_eq!(f.is_scalable(), f != Function::SixHumpCamel, "{f}");
            assert_eq!(f.fixed_dim().is_none(), f.is_scalable(), "{f}");
        }
        assert_eq!(Function::SixHumpCamel.fixed_dim(), Some(2));
        assert_eq!(Function::SixHumpCamel.optimum_location(30).len(), 2);
    }

    #[test]
    fn test_problem_errors_have_exact_messages() {
        let e = TestProblem::new(Function::SixHumpCamel, 30).unwrap_err();
        assert_eq!(
            e,
            FunctionError::WrongDimension {
                function: Function::SixHumpCamel,
                required: 2,
                requested: 30
            }
        );
        assert_eq!(
            e.to_string(),
            "six_hump_camel is defined only for dimension 2, not 30"
        );
        assert_eq!(
            TestProblem::new(Function::SixHumpCamel, 0)
                .unwrap_err()
                .to_string(),
            "six_hump_camel is defined only for dimension 2, not 0"
        );
        let e = TestProblem::new(Function::Sphere, 0).unwrap_err();
        assert_eq!(
            e,
            FunctionError::ZeroDimension {
                function: Function::Sphere
            }
        );
        assert_eq!(
            e.to_string(),
            "sphere is defined only for dimension 1 or more, not 0"
        );
        assert_eq!(
            TestProblem::new(Function::Schwefel226, 0)
                .unwrap_err()
                .to_string(),
            "schwefel_2_26 is defined only for dimension 1 or more, not 0"
        );
        // Usable as a boxed std error.
        let boxed: Box<dyn std::error::Error> = Box::new(e);
        assert!(boxed.to_string().starts_with("sphere "));
    }

    #[test]
    fn test_problem_implements_problem() {
        for f in Function::ALL {
            let d = f.fixed_dim().unwrap_or(30);
            let p = TestProblem::new(f, d).unwrap();
            assert_eq!(p.function(), f);
            assert_eq!(p.dim(), d);
            assert_eq!(p.key(), format!("{}-{d}", f.name()));
            assert_eq!(p.bounds().len(), d);
            assert!(p.bounds().iter().all(|&b| b == f.domain()));
            let x: Vec<f64> = p
                .bounds()
                .iter()
                .enumerate()
                .map(|(i, b)| b.lerp((i as f64 * 0.618).fract()))
                .collect();
            assert_eq!(p.objective(&x).to_bits(), f.eval(&x).to_bits(), "{f}");
        }
        assert_eq!(
            TestProblem::new(Function::Sphere, 30).unwrap().key(),
            "sphere-30"
        );
        assert_eq!(
            TestProblem::new(Function::SixHumpCamel, 2).unwrap().key(),
            "six_hump_camel-2"
        );
        assert!(TestProblem::new(Function::Rosenbrock, 1).is_ok());
    }
}
