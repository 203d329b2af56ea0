//! A test problem the optimisers' unit tests share (test builds only).

use std::cell::Cell;

use super::Optimiser;
use crate::problem::{Bounds, Problem};
use crate::rng::run_rng;

/// `Σ (x_i − c_i)²` on asymmetric per-variable bounds, counting evaluations
/// outside the box and points with a coordinate in `(0, 2⁻⁵¹¹)` (whose
/// square is subnormal: `2⁻⁵¹¹ = √2⁻¹⁰²²`).
pub(crate) struct Bowl {
    pub(crate) bounds: Vec<Bounds>,
    pub(crate) centre: Vec<f64>,
    pub(crate) outside: Cell<u64>,
    pub(crate) tiny: Cell<u64>,
}

impl Bowl {
    pub(crate) fn sphere(dim: usize) -> Self {
        Self::new(vec![Bounds::new(-100.0, 100.0); dim], vec![0.0; dim])
    }

    pub(crate) fn new(bounds: Vec<Bounds>, centre: Vec<f64>) -> Self {
        Self {
            bounds,
            centre,
            outside: Cell::new(0),
            tiny: Cell::new(0),
        }
    }
}

impl Problem for Bowl {
    fn dim(&self) -> usize {
        self.bounds.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn objective(&self, x: &[f64]) -> f64 {
        if x.iter().zip(&self.bounds).any(|(v, b)| !b.contains(*v)) {
            self.outside.set(self.outside.get() + 1);
        }
        if x.iter()
            .any(|v| v.abs() > 0.0 && v.abs() < f64::MIN_POSITIVE.sqrt())
        {
            self.tiny.set(self.tiny.get() + 1);
        }
        x.iter()
            .zip(&self.centre)
            .map(|(v, c)| (v - c) * (v - c))
            .sum()
    }
}

/// Asserts that `algo` drives Sphere-10 on `[−100, 100]¹⁰` below `target`
/// within `budget` evaluations for each of the seeds 0 to 4, never
/// evaluating outside the box.
pub(crate) fn assert_solves_sphere_10(algo: &impl Optimiser, budget: u64, target: f64) {
    let p = Bowl::sphere(10);
    for seed in 0..5 {
        let out = algo.run(&p, budget, &mut run_rng(seed));
        assert!(
            out.best_value < target,
            "seed {seed}: best {}",
            out.best_value
        );
    }
    assert_eq!(p.outside.get(), 0);
}
