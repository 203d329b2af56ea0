//! A host's interrupt ends every run at once and is lowered with the last
//! watch (`optim::interrupt`). Its own test binary: the flag is the
//! process's, so no other test may run beside it.

use std::sync::atomic::{AtomicU64, Ordering};

use metabezier_core::optim::lm::Termination;
use metabezier_core::optim::{interrupt, CmaEs, Evaluator, HarmonySearch, LeastSquares};
use metabezier_core::optim::{LevenbergMarquardt, Optimiser};
use metabezier_core::problem::{Bounds, Problem};
use metabezier_core::rng::run_rng;

/// `Σ (x_i − 0.3)²` in 4 variables; asks for an interrupt at call `at`.
struct Tripwire {
    at: u64,
    calls: AtomicU64,
}

impl Tripwire {
    fn new(at: u64) -> Self {
        Tripwire {
            at,
            calls: AtomicU64::new(0),
        }
    }
    fn trip(&self) {
        if self.calls.fetch_add(1, Ordering::Relaxed) + 1 == self.at {
            interrupt::request();
        }
    }
}

impl Problem for Tripwire {
    fn dim(&self) -> usize {
        4
    }
    fn bounds(&self) -> &[Bounds] {
        const B: [Bounds; 4] = [Bounds::new(-1.0, 1.0); 4];
        &B
    }
    fn objective(&self, x: &[f64]) -> f64 {
        self.trip();
        x.iter().map(|v| (v - 0.3) * (v - 0.3)).sum()
    }
}

impl LeastSquares for Tripwire {
    fn residual_count(&self) -> usize {
        4
    }
    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        self.trip();
        for (o, v) in out.iter_mut().zip(x) {
            *o = v - 0.3;
        }
    }
}

/// Evaluations of a run of `opt` on a problem that asks for an interrupt at
/// call `at`, within `budget`, and whether the run says it was cut; in a
/// watch of its own, as a host's call.
fn cut_at<O: Optimiser>(opt: &O, at: u64, budget: u64) -> (u64, bool) {
    let _watch = interrupt::Watch::begin();
    let p = Tripwire::new(at);
    let mut eval = Evaluator::new(&p, budget);
    opt.minimise(&mut eval, &mut run_rng(3));
    let cut = eval.interrupted();
    (eval.finish().evaluations, cut)
}

#[test]
fn an_interrupt_ends_every_run_within_a_poll_and_is_lowered_with_the_last_watch() {
    let poll = interrupt::POLL_EVALUATIONS;
    for at in [1_000, 70_001] {
        // One evaluation at a time, then a generation at a time.
        let (n, cut) = cut_at(&HarmonySearch::default(), at, 1_000_000_000);
        assert!(cut && (at..at + poll).contains(&n), "HS stopped at {n}");
        // CMA-ES evaluates a generation as one batch: the poll is seen
        // within it, and the generation of its run's λ completes.
        let watch = interrupt::Watch::begin();
        let p = Tripwire::new(at);
        let mut eval = Evaluator::new(&p, 1_000_000_000);
        let runs = CmaEs::default().minimise_recorded(&mut eval, &mut run_rng(3));
        let (cut, n) = (eval.interrupted(), eval.finish().evaluations);
        let lambda = runs.last().map_or(0, |r| r.lambda) as u64;
        assert!(
            cut && (at..at + poll + lambda).contains(&n),
            "CMA-ES at {n}, λ = {lambda}"
        );
        drop(watch);
    }
    let outer = interrupt::Watch::begin();
    // Levenberg–Marquardt stops before its first iteration.
    let out = LevenbergMarquardt::default().minimise(&Tripwire::new(1), &[0.9; 4], 1_000_000);
    assert_eq!((out.termination, out.iterations), (Termination::Budget, 0));
    // An inner watch closing leaves the request raised for the outer one.
    drop(interrupt::Watch::begin());
    assert!(interrupt::requested());
    drop(outer);
    assert!(!interrupt::requested(), "lowered with the last watch");
    assert_eq!(
        cut_at(&HarmonySearch::default(), u64::MAX, 5_000),
        (5_000, false)
    );
    // Without any watch, a request raised before a watch opens is stale.
    interrupt::request();
    let w = interrupt::Watch::begin();
    assert!(
        !interrupt::requested(),
        "the first watch lowers a stale one"
    );
    drop(w);
}
