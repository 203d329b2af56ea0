//! Uniform random search (Brooks 1958, "A discussion of random methods for
//! seeking maxima", Operations Research 6(2):244–251; Rastrigin 1963, "The
//! convergence of the random search method in the extremal control of a
//! many parameter system", Automation and Remote Control 24:1337–1342): the
//! floor every optimiser must beat, as Bergstra & Bengio (2012, "Random
//! search for hyper-parameter optimization", JMLR 13:281–305) use it as the
//! baseline of a search method. Implemented from its definition.

use super::params::{ParamDef, ParamSet};
use super::{clamp, Optimiser, ParamError};
use crate::optim::evaluator::Evaluator;
use crate::problem::{Bounds, Problem};
use crate::rng::Words;
use crate::simd::dispatch;

/// Points drawn and evaluated per block.
const BLOCK: usize = 64;

/// Pure random search: every evaluation is at a fresh point
/// `x_j = L_j + u_j (U_j − L_j)`, `u_j ~ U[0,1)` independently, clipped
/// against rounding onto the box; the [`Evaluator`] keeps the best. It has
/// no parameters, no memory and no notion of progress.
///
/// Points are drawn in blocks of up to 64 (`D` uniforms per point, point
/// after point, by [`Words::units`]) and each block is evaluated as one batch
/// ([`Problem::objective_batch`]); the last block is cut to the evaluations
/// left, so the run uses exactly its budget, and the random numbers are
/// those of drawing the points one at a time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RandomSearch;

/// The parameters of [`RandomSearch`]: none.
pub static PARAMS: [ParamDef; 0] = [];

impl RandomSearch {
    /// Random search; it takes no parameters.
    pub fn from_params(_: &ParamSet) -> Result<Self, ParamError> {
        Ok(Self)
    }
}

impl Optimiser for RandomSearch {
    /// A candidate and the best (2 × D).
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        super::vectors_bytes(2, dim)
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let bounds = eval.bounds();
        let dim = bounds.len();
        let rows = usize::try_from(eval.remaining()).map_or(BLOCK, |r| r.min(BLOCK));
        let mut xs = vec![0.0; rows * dim];
        let mut values = vec![0.0; rows];
        let lower: Vec<f64> = bounds.iter().map(|b| b.lower).collect();
        let upper: Vec<f64> = bounds.iter().map(|b| b.upper).collect();
        let width: Vec<f64> = bounds.iter().map(|b| b.width()).collect();
        dispatch(
            #[inline(always)]
            |_| {
                while eval.remaining() > 0 {
                    let m = usize::try_from(eval.remaining()).map_or(rows, |r| r.min(rows));
                    let block = &mut xs[..m * dim];
                    rng.units(block);
                    for row in block.chunks_exact_mut(dim.max(1)) {
                        let row = &mut row[..dim];
                        let (lower, upper, width) = (&lower[..dim], &upper[..dim], &width[..dim]);
                        for j in 0..dim {
                            let b = Bounds::new(lower[j], upper[j]);
                            row[j] = clamp(b, lower[j] + row[j] * width[j]);
                        }
                    }
                    eval.place_start(block);
                    eval.evaluate_batch(block, &mut values[..m]);
                }
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::optim::bowl::Bowl;

    use super::*;
    use crate::rng::{run_rng, Draw};

    /// (Budgets, bounds and seeds are the conformance suite's,
    /// [`crate::optim::conformance`].)
    #[test]
    fn the_best_is_the_best_of_the_points_drawn_one_by_one() {
        let bounds = vec![Bounds::new(-5.0, 5.0), Bounds::new(0.0, 2.0)];
        let p = Bowl::new(bounds.clone(), vec![0.0; 2]);
        let out = RandomSearch.run(&p, 200, &mut run_rng(4));
        let mut rng = run_rng(4);
        let mut best = (f64::INFINITY, vec![]);
        for _ in 0..200 {
            let x: Vec<f64> = bounds.iter().map(|b| b.lerp(rng.unit())).collect();
            let v = p.objective(&x);
            if v < best.0 {
                best = (v, x);
            }
        }
        assert_eq!((out.best_value, out.best_x), best);
    }
}
