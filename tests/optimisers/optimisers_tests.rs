//! Every optimiser, seeded, solves Sphere-10 to a stated target within a
//! stated budget (1e-6; 1e-2 for GHS, which has no fine-tuning bandwidth;
//! CMA-ES to 1e-10 in 10,000 evaluations; random search, the floor, is
//! instead required to lose to all of them), never evaluates outside the
//! bounds there and spends exactly its budget. Budgets of every size,
//! per-variable bounds under each bound policy, NaN regions, seeds and
//! SIMD levels are the conformance suite's
//! (`metabezier_core::optim::conformance`), which every registered
//! optimiser runs.

use std::cell::Cell;

use metabezier::functions::{BbobProblem, Function, TestProblem};
use metabezier::optim::{Algorithm, Evaluator, ParamSet};
use metabezier::problem::{Bounds, Problem};
use metabezier::rng::run_rng;

/// Wraps a problem and counts evaluations outside its bounds.
struct Guarded<P> {
    inner: P,
    outside: Cell<u64>,
    calls: Cell<u64>,
}

impl<P: Problem> Guarded<P> {
    fn new(inner: P) -> Self {
        Self {
            inner,
            outside: Cell::new(0),
            calls: Cell::new(0),
        }
    }
}

impl<P: Problem> Problem for Guarded<P> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn bounds(&self) -> &[Bounds] {
        self.inner.bounds()
    }
    fn objective(&self, x: &[f64]) -> f64 {
        self.calls.set(self.calls.get() + 1);
        if x.iter().zip(self.bounds()).any(|(v, b)| !b.contains(*v)) {
            self.outside.set(self.outside.get() + 1);
        }
        self.inner.objective(x)
    }
}

/// An algorithm with some parameters changed from their defaults.
fn configured(name: &str, changes: &[(&str, metabezier::optim::Raw)]) -> Algorithm {
    let mut p = ParamSet::defaults(Algorithm::params(name).unwrap());
    for (k, v) in changes {
        p.set(k, v).unwrap();
    }
    Algorithm::from_params(name, &p).unwrap()
}

use metabezier::optim::Raw;

/// The settings, budgets and targets under which each optimiser must solve
/// Sphere-10 (stated here, and in the README). GHS only ever samples values
/// already in memory, copies of the best harmony's coordinates or uniform
/// values, so its precision stalls near 1e-4 to 1e-8 (Omran & Mahdavi 2008,
/// Table 3, report a mean of 1e-5 on Sphere-30); its target is 1e-2, which
/// random search in [−100, 100]¹⁰ never reaches. Random search itself is
/// left out: it is the floor, which `random_search_is_the_floor` requires
/// every other optimiser to beat, and it cannot reach 1e-2 here (the
/// expected best of 200 000 uniform points is near 10³).
fn sphere_settings() -> Vec<(Algorithm, u64, f64)> {
    vec![
        (Algorithm::default_for("lshade").unwrap(), 200_000, 1e-6),
        (
            configured(
                "hs",
                &[
                    ("bw_decay", Raw::Text("exponential".into())),
                    ("bw", Raw::Float(0.01)),
                    ("bw_min", Raw::Float(1e-7)),
                ],
            ),
            200_000,
            1e-6,
        ),
        (Algorithm::default_for("ghs").unwrap(), 200_000, 1e-2),
        (Algorithm::default_for("ga").unwrap(), 200_000, 1e-6),
        (Algorithm::default_for("pso").unwrap(), 200_000, 1e-6),
        (
            configured(
                "mhs",
                &[
                    ("bw_decay", Raw::Text("exponential".into())),
                    ("bw_min", Raw::Float(1e-7)),
                ],
            ),
            200_000,
            1e-6,
        ),
        (
            configured(
                "mhs",
                &[
                    ("bw_decay", Raw::Text("exponential".into())),
                    ("bw_min", Raw::Float(1e-7)),
                    ("update", Raw::Text("each".into())),
                ],
            ),
            200_000,
            1e-6,
        ),
        (
            configured(
                "mhs",
                &[
                    ("bw_decay", Raw::Text("exponential".into())),
                    ("bw_min", Raw::Float(1e-7)),
                    ("scheme", Raw::Text("per-variable".into())),
                ],
            ),
            200_000,
            1e-6,
        ),
        (Algorithm::default_for("cmaes").unwrap(), 10_000, 1e-10),
        (
            configured("cmaes", &[("restarts", Raw::Text("bipop".into()))]),
            10_000,
            1e-10,
        ),
        (
            configured("cmaes", &[("bounds", Raw::Text("reflect".into()))]),
            10_000,
            1e-10,
        ),
    ]
}

#[test]
fn mhs_readings_stay_out_of_the_canonical_text_at_their_defaults() {
    let defaults = ParamSet::defaults(Algorithm::params("mhs").unwrap());
    // The text of every campaign recorded before the readings existed.
    assert_eq!(
        defaults.canonical(),
        "hms=10;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;l=3;operators=hs+ga+pso;pm=0.05;mutation=uniform;sigma=0.1;c=2;bounds=clip"
    );
    let mut p = defaults.clone();
    p.set("scheme", &Raw::Text("per-variable".into())).unwrap();
    p.set("p_ga", &Raw::Float(0.2)).unwrap();
    assert!(
        p.canonical().ends_with(";bounds=clip;scheme=per-variable"),
        "{}",
        p.canonical()
    );
    p.set("p_ga", &Raw::Float(0.6)).unwrap();
    p.set("p_pso", &Raw::Float(0.3)).unwrap();
    let e = Algorithm::from_params("mhs", &p).unwrap_err();
    assert_eq!(e.param, "p_pso");
    assert!(
        e.message.contains("par + p_ga + p_pso ≤ 1"),
        "{}",
        e.message
    );
}

#[test]
fn the_mhs_readings_differ() {
    let problem = TestProblem::new(Function::Rastrigin, 5).unwrap();
    let runs: Vec<f64> = [
        vec![],
        vec![("update", Raw::Text("each".into()))],
        vec![("scheme", Raw::Text("per-variable".into()))],
    ]
    .iter()
    .map(|changes| {
        configured("mhs", changes)
            .run(&problem, 3000, &mut run_rng(5))
            .best_value
    })
    .collect();
    assert!(
        runs[0] != runs[1] && runs[1] != runs[2] && runs[0] != runs[2],
        "{runs:?}"
    );
}

#[test]
fn every_optimiser_solves_sphere_10_within_its_budget_and_bounds() {
    for (algo, budget, target) in sphere_settings() {
        let problem = Guarded::new(TestProblem::new(Function::Sphere, 10).unwrap());
        let out = algo.run(&problem, budget, &mut run_rng(12345));
        assert!(
            out.best_value < target,
            "{} reached only {:e} in {budget} evaluations (target {target:e})",
            algo.name(),
            out.best_value
        );
        assert_eq!(
            out.evaluations,
            budget,
            "{} did not spend its budget",
            algo.name()
        );
        assert_eq!(
            problem.calls.get(),
            budget,
            "{} evaluated past its budget",
            algo.name()
        );
        assert_eq!(
            problem.outside.get(),
            0,
            "{} evaluated outside the bounds",
            algo.name()
        );
        assert_eq!(problem.objective(&out.best_x), out.best_value);
    }
}

/// The bits of everything a run reports, so that `-0.0` and `0.0` (or two
/// NaNs) are told apart.
fn outcome_bits(o: &metabezier::optim::Outcome) -> Vec<u64> {
    let mut bits: Vec<u64> = o.best_x.iter().map(|v| v.to_bits()).collect();
    bits.push(o.best_value.to_bits());
    bits.push(o.evaluations);
    for p in &o.trace {
        bits.push(p.evaluations);
        bits.push(p.best.to_bits());
    }
    bits
}

/// Settings beyond those the conformance suite generates (its defaults,
/// each choice, each count at its minimum), whose runs at every SIMD level
/// it compares too: harmony memories of twelve (three blocks of four),
/// CMA-ES with λ = 40, and an L-SHADE population that shrinks to N_min and
/// fills its archive within the 4000 evaluations.
#[test]
fn every_simd_level_gives_the_same_runs_beyond_the_suites_settings() {
    use metabezier::simd::{simd, with_level, Simd};
    let settings = [
        ("hs", vec![("hms", Raw::Int(12))]),
        ("ghs", vec![("hms", Raw::Int(12))]),
        ("cmaes", vec![("lambda", Raw::Int(40))]),
        (
            "lshade",
            vec![("r_n_init", Raw::Float(3.0)), ("arc_rate", Raw::Float(1.0))],
        ),
    ];
    let levels: Vec<Simd> = [Simd::Portable, Simd::Avx2, Simd::Avx512]
        .into_iter()
        .filter(|&l| l <= simd())
        .collect();
    // D = 7 and 33 leave a partial block of four; 33 also spans two blocks
    // of 32 variables.
    for (f, dim) in [(Function::Rastrigin, 7), (Function::Sphere, 33)] {
        let p = TestProblem::new(f, dim).unwrap();
        for (name, changes) in &settings {
            let algo = configured(name, changes);
            let runs: Vec<Vec<u64>> = levels
                .iter()
                .map(|&l| with_level(l, || outcome_bits(&algo.run(&p, 4000, &mut run_rng(9)))))
                .collect();
            for (l, run) in levels.iter().zip(&runs) {
                assert_eq!(
                    run, &runs[0],
                    "{name} {changes:?} on {f:?}-{dim}: {l:?} differs"
                );
            }
        }
    }
}

/// The first evaluation at which `algo` came within 1e-8 of COCO's `f*` on
/// bbob `function` at `dim`, `instance`, seeded by the instance.
fn evaluations_to_1e8(
    algo: &Algorithm,
    function: usize,
    dim: usize,
    instance: usize,
    budget: u64,
) -> Option<u64> {
    let p = BbobProblem::new(function, dim, instance).unwrap();
    let mut eval = Evaluator::new(&p as &dyn Problem, budget).with_targets(p.fopt(), vec![1e-8]);
    algo.minimise(&mut eval, &mut run_rng(instance as u64));
    let out = eval.finish();
    assert_eq!(out.evaluations, budget);
    out.hits.first().map(|h| h.evaluations)
}

/// Known answers: default L-SHADE (Tanabe & Fukunaga 2014) reaches
/// `f − f* ≤ 1e-8` on bbob f1 (sphere) and f2 (separable ellipsoid, condition
/// 10⁶) at D = 10, instances 1–3, one run each (seed = instance), within the
/// CEC 2014 budget of 10⁴·D = 100 000 evaluations. The evaluations it took,
/// when this test was written:
///
/// | function | instance 1 | instance 2 | instance 3 |
/// |---|---:|---:|---:|
/// | f1 | 24 568 | 24 787 | 26 155 |
/// | f2 | 34 662 | 34 833 | 34 941 |
#[test]
fn lshade_solves_bbob_sphere_and_ellipsoid_at_10d() {
    let algo = Algorithm::default_for("lshade").unwrap();
    for function in [1, 2] {
        for instance in 1..=3 {
            let hit = evaluations_to_1e8(&algo, function, 10, instance, 100_000);
            println!("lshade f{function} i{instance}: {hit:?}");
            assert!(
                hit.is_some(),
                "lshade missed 1e-8 on f{function} instance {instance}"
            );
        }
    }
}

/// The median of a sample (the mean of the middle two for an even size).
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        (v[n / 2 - 1] + v[n / 2]) / 2.0
    }
}

/// Random search is the floor: on bbob f1 at D = 10, over instances 1–11
/// (one run each, seed = instance, 10⁴·D evaluations), its median final
/// error `f − f*` is larger than every other optimiser's at its defaults.
/// Medians when this test was written: random 8.62; GHS 2.7e-3, HS 7.6e-7,
/// MHS 3.3e-7; GA, PSO and L-SHADE 0 (their best equals COCO's `f*` in
/// floating point).
#[test]
fn random_search_is_the_floor() {
    const BUDGET: u64 = 100_000;
    let median_error = |name: &str| {
        let algo = Algorithm::default_for(name).unwrap();
        let errors: Vec<f64> = (1..=11)
            .map(|instance| {
                let p = BbobProblem::new(1, 10, instance).unwrap();
                let out = algo.run(&p, BUDGET, &mut run_rng(instance as u64));
                assert_eq!(out.evaluations, BUDGET);
                out.best_value - p.fopt()
            })
            .collect();
        median(errors)
    };
    let floor = median_error("random");
    println!("random: {floor:e}");
    assert!(floor.is_finite() && floor > 0.0);
    for name in Algorithm::names().into_iter().filter(|n| *n != "random") {
        let m = median_error(name);
        println!("{name}: {m:e}");
        assert!(
            m < floor,
            "{name}'s median error {m:e} is not below random search's {floor:e}"
        );
    }
}

#[test]
fn every_optimiser_sizes_its_state_before_it_allocates() {
    // Issue 49: CMA-ES at D = 30,000 needs its 7.2 GB covariance twice
    // over; L-SHADE's population is r^N_init · D, so its state is
    // quadratic in D; HS at D = 10⁶ stays linear and small.
    use metabezier::optim::{Algorithm, MAX_STATE_BYTES};
    let cmaes = Algorithm::default_for("cmaes").unwrap();
    let d = 30_000u128;
    assert!(cmaes.state_bytes(30_000, 100_000) >= 2 * d * d * 8);
    assert!(cmaes.state_bytes(30_000, 100_000) > MAX_STATE_BYTES);
    // Restart growth raises the bound with the budget.
    assert!(cmaes.state_bytes(100, 10_000_000) > cmaes.state_bytes(100, 1_000));
    let lshade = Algorithm::default_for("lshade").unwrap();
    assert!(lshade.state_bytes(1000, 1000) > 4 * lshade.state_bytes(500, 1000) - 1_000_000);
    let hs = Algorithm::default_for("hs").unwrap();
    assert!(hs.state_bytes(1_000_000, 1000) < 100 << 20);
    for name in Algorithm::names() {
        let a = Algorithm::default_for(name).unwrap();
        let b = a.state_bytes(10, 1000);
        assert!(b > 0 && b < 1 << 30, "{name}: {b}");
    }
}
