//! [`TestProblem`]: a benchmark function fixed at a dimension, optionally
//! shifted and rotated, as the [`Problem`] the optimisers minimise.

use std::sync::Arc;

use super::{Function, FunctionError, Instance, Transform, MAX_ROTATION_DIM};
use crate::problem::{objective_rows, Bounds, Problem};

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
