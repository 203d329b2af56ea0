//! A run's controls from its caller: a start point every optimiser
//! evaluates first, a stop at the target, and an observer that may end the
//! run (`Evaluator::with_start`, `stop_at_target`, `with_observer`).

use std::sync::{Arc, Mutex};

use metabezier_core::optim::{Algorithm, EarlyEnd, Evaluator};
use metabezier_core::problem::{Bounds, Problem};
use metabezier_core::rng::run_rng;

/// `Σ (x_i − 0.3)²` in 3 variables, keeping the points it was given.
struct Recorded {
    bounds: Vec<Bounds>,
    points: Mutex<Vec<Vec<f64>>>,
}

impl Recorded {
    fn new() -> Self {
        Recorded {
            bounds: vec![Bounds::new(-2.0, 1.0); 3],
            points: Mutex::new(Vec::new()),
        }
    }
}

impl Problem for Recorded {
    fn dim(&self) -> usize {
        3
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn objective(&self, x: &[f64]) -> f64 {
        self.points.lock().unwrap().push(x.to_vec());
        x.iter().map(|v| (v - 0.3) * (v - 0.3)).sum()
    }
}

/// A run of `name` on a new [`Recorded`] with 3,000 evaluations, its
/// evaluator set up by `setup`: the problem, the evaluations used and why
/// the run ended early.
fn run(
    name: &str,
    setup: impl for<'a> FnOnce(Evaluator<'a, dyn Problem + 'a>) -> Evaluator<'a, dyn Problem + 'a>,
) -> (Recorded, u64, Option<EarlyEnd>) {
    let p = Recorded::new();
    let alg = Algorithm::default_for(name).unwrap();
    let (used, early) = {
        let mut eval = setup(Evaluator::new(&p as &dyn Problem, 3_000));
        alg.minimise(&mut eval, &mut run_rng(9));
        (eval.used(), eval.ended_early())
    };
    (p, used, early)
}

#[test]
fn every_optimiser_evaluates_the_start_point_first_and_draws_the_same_stream() {
    let x0 = vec![0.25, -1.5, 0.75];
    for name in Algorithm::names() {
        let (with, _, _) = run(name, |e| e.with_start(x0.clone()));
        let (without, _, _) = run(name, |e| e);
        let (a, b) = (
            with.points.into_inner().unwrap(),
            without.points.into_inner().unwrap(),
        );
        assert_eq!(a[0], x0, "{name} starts at x0");
        if name != "cmaes" {
            // The first point replaced, the rest of the initial population
            // (at least 5 points for every optimiser) as drawn.
            assert_eq!(a[1..5], b[1..5], "{name}");
        }
        assert_ne!(b[0], x0);
    }
}

#[test]
fn a_run_stops_at_its_target_and_when_its_observer_says() {
    for name in Algorithm::names() {
        let (_, used, early) = run(name, |e| e.with_target(0.5).stop_at_target());
        let reached = early == Some(EarlyEnd::Target);
        assert!(reached && used < 3_000, "{name}: {used} {early:?}");
        let seen = Arc::new(Mutex::new(Vec::new()));
        let log = Arc::clone(&seen);
        let (_, used, early) = run(name, move |e| {
            e.with_observer(Box::new(move |n, best, x| {
                log.lock().unwrap().push((n, best, x.to_vec()));
                n < 100
            }))
        });
        // A generation evaluated as one batch is counted whole.
        assert_eq!(early, Some(EarlyEnd::Observer), "{name}");
        assert!((100..100 + 64).contains(&used), "{name}: {used}");
        let seen = seen.lock().unwrap();
        assert_eq!(seen.last().unwrap().0, 100);
        assert!(seen.windows(2).all(|w| w[0].0 < w[1].0 && w[1].1 <= w[0].1));
    }
}
