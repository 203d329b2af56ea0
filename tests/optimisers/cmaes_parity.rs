//! Parity of metabezier's CMA-ES with pycma's default (issue 51): bbob
//! f1..f14 at D = 10, instances 1..5, 3 runs each (15 runs per function),
//! evaluations to `f − f* ≤ 10⁻⁸` within 10⁴·D. pycma's figures were
//! computed once by `tools/pycma_bbob.py` (pycma 4.5.0 and coco-experiment
//! 2.8.2, pinned in tools/pycma-requirements.txt; `make pycma-parity`) and
//! are pinned here: the test never calls Python and compares evaluation
//! counts only, never time.
//!
//! Both start as BBOB experiments do: σ₀ = 2 on `[−5, 5]ⁿ` (`sigma0 =
//! 0.2` of the range) and each run's mean uniform in `[−4, 4]ⁿ` (`x0 =
//! "central"`), IPOP restarts with λ doubled from `4 + ⌊3 ln n⌋`, the
//! active covariance update. pycma runs without bounds (its default);
//! metabezier clips samples into `[−5, 5]ⁿ`.

use metabezier::functions::BbobProblem;
use metabezier::optim::params::{ParamSet, Raw};
use metabezier::optim::{cmaes, CmaEs, Evaluator, Optimiser};
use metabezier::rng::run_rng;

const D: usize = 10;

/// pycma's median evaluations to 1e-8 over its 15 runs, and how many of
/// them got there (`None`: the median run did not).
const PYCMA: [(usize, Option<u64>, u32); 14] = [
    (1, Some(1482), 15),
    (2, Some(4202), 15),
    (3, None, 1),
    (4, None, 0),
    (5, Some(114), 15),
    (6, Some(3922), 15),
    (7, Some(3144), 15),
    (8, Some(5351), 15),
    (9, Some(5238), 15),
    (10, Some(4135), 15),
    (11, Some(3103), 15),
    (12, Some(10485), 15),
    (13, Some(7403), 15),
    (14, Some(4069), 15),
];

/// metabezier's CMA-ES at its defaults with BBOB's usual start.
fn bbob_cmaes() -> CmaEs {
    let mut p = ParamSet::defaults(&cmaes::PARAMS);
    p.set("sigma0", &Raw::Float(0.2)).unwrap();
    p.set("x0", &Raw::Text("central".into())).unwrap();
    CmaEs::from_params(&p).unwrap()
}

/// Evaluations to 1e-8 of the runs of `function` at `dim` (instances
/// `1..=instances`, seeds `1..=seeds` each) within 10⁴·D, `u64::MAX` for a
/// run that does not get there; the runs stop at the target, as COCO's
/// experiments do.
fn runs(algo: &CmaEs, function: usize, dim: usize, instances: usize, seeds: u64) -> Vec<u64> {
    let mut out = Vec::new();
    for instance in 1..=instances {
        let p = BbobProblem::new(function, dim, instance).unwrap();
        for seed in 1..=seeds {
            let mut eval = Evaluator::new(&p, 10_000 * dim as u64)
                .with_target(p.fopt() + 1e-8)
                .stop_at_target();
            algo.minimise(&mut eval, &mut run_rng(100 * instance as u64 + seed));
            let out_ = eval.finish();
            out.push(if out_.best_value - p.fopt() <= 1e-8 {
                out_.evaluations
            } else {
                u64::MAX
            });
        }
    }
    out
}

fn median(mut v: Vec<u64>) -> Option<u64> {
    v.sort_unstable();
    Some(v[v.len() / 2]).filter(|&m| m != u64::MAX)
}

/// `runs` of every function of `functions`, on two threads (each run is
/// independent), in the order of `functions`.
fn all_runs(
    algo: &CmaEs,
    functions: &[usize],
    dim: usize,
    instances: usize,
    seeds: u64,
) -> Vec<(usize, Vec<u64>)> {
    std::thread::scope(|s| {
        let handles: Vec<_> = [0, 1]
            .map(|part| {
                s.spawn(move || {
                    functions
                        .iter()
                        .skip(part)
                        .step_by(2)
                        .map(|&f| (f, runs(algo, f, dim, instances, seeds)))
                        .collect::<Vec<_>>()
                })
            })
            .into_iter()
            .collect();
        let mut all: Vec<(usize, Vec<u64>)> = handles
            .into_iter()
            .flat_map(|h| h.join().unwrap())
            .collect();
        all.sort_by_key(|r| functions.iter().position(|&f| f == r.0));
        all
    })
}

/// The ratio pycma's median may be exceeded by, per function: 10 %, but
/// for three functions where parity is not reached (issue 51's note):
/// f5, the linear slope, whose optimum is a corner of the box: pycma runs
/// without bounds and reaches f* beyond the corner, where COCO's f5 is
/// constant, in about 100 evaluations, while a clipped search must bring all
/// ten coordinates to the bounds at once; f7 (step ellipsoid, plateaus) and
/// f13 (sharp ridge), 1.15–1.5 times pycma's median over 15 runs (1.50 and
/// 1.16 at the defaults).
fn allowed_ratio(function: usize) -> f64 {
    match function {
        5 => 60.0,
        7 => 1.6,
        13 => 1.25,
        _ => 1.10,
    }
}

#[test]
fn cmaes_is_within_10_percent_of_pycma_on_bbob_f1_to_f14_at_d10() {
    let algo = bbob_cmaes();
    let functions: Vec<usize> = PYCMA.iter().map(|r| r.0).collect();
    let results = all_runs(&algo, &functions, D, 5, 3);
    let mut failures = Vec::new();
    for ((f, pycma, pycma_solved), (g, ours)) in PYCMA.iter().zip(&results) {
        assert_eq!(f, g);
        let solved = ours.iter().filter(|&&e| e != u64::MAX).count();
        let med = median(ours.clone());
        let ratio = med.zip(*pycma).map(|(a, b)| a as f64 / b as f64);
        eprintln!(
            "f{f:<2} pycma {:>6} ({pycma_solved:>2}/15)  metabezier {:>6} ({solved:>2}/15)  ratio {}",
            pycma.map_or("-".into(), |v| v.to_string()),
            med.map_or("-".into(), |v| v.to_string()),
            ratio.map_or("-".into(), |r| format!("{r:.3}")),
        );
        if let Some(r) = ratio {
            if r > allowed_ratio(*f) {
                failures.push(format!(
                    "f{f}: median {med:?} against pycma's {pycma:?} ({r:.3}×)"
                ));
            }
        }
        if pycma.is_some() && med.is_none() {
            failures.push(format!(
                "f{f}: pycma's median run solves it, ours does not ({solved}/15)"
            ));
        }
    }
    let f10 = median(results[9].1.clone()).unwrap_or(u64::MAX);
    assert!(
        f10 <= 4600,
        "f10: median {f10} evaluations, the issue asks ≤ 4,600"
    );
    assert!(failures.is_empty(), "{failures:#?}");
}

/// The median of the per-function ratios of median evaluations to 1e-8,
/// `lazy` over `tutorial`, over the functions both solve in their median
/// run, and the (function, run) pairs each solves.
fn schedule_ratio(
    tutorial: &[(usize, Vec<u64>)],
    lazy: &[(usize, Vec<u64>)],
) -> (f64, usize, usize) {
    let mut ratios = Vec::new();
    for ((f, a), (g, b)) in tutorial.iter().zip(lazy) {
        assert_eq!(f, g);
        if let (Some(a), Some(b)) = (median(a.clone()), median(b.clone())) {
            eprint!("f{f} {:.2}  ", b as f64 / a as f64);
            ratios.push(b as f64 / a as f64);
        }
    }
    ratios.sort_by(f64::total_cmp);
    let solved = |r: &[(usize, Vec<u64>)]| {
        r.iter()
            .flat_map(|(_, v)| v)
            .filter(|&&e| e != u64::MAX)
            .count()
    };
    (ratios[ratios.len() / 2], solved(tutorial), solved(lazy))
}

/// The default schedule of eigendecompositions (`eigen_gap = 5`, the
/// `cmaes` crate's 0.5·λ/((c_1 + c_μ) n) evaluations) needs the same
/// evaluations to 1e-8 as the tutorial's (`eigen_gap = 1`) on bbob: the
/// median over the functions of the ratio of median evaluations is at most
/// 1.05, at D = 10 (24 functions, instances 1–5, one run each) and D = 20
/// (the 14 functions f1–f14 that CMA-ES solves or nearly solves there,
/// instances 1–3: f15–f24 spend the whole 2·10⁵-evaluation budget and would
/// take this test over a minute), and solves as many runs within 2.
#[test]
fn the_lazier_schedule_needs_the_same_evaluations_on_bbob() {
    let lazy = CmaEs::default();
    assert_eq!(lazy.eigen_gap, cmaes::EIGEN_GAP_DEFAULT);
    let mut p = ParamSet::defaults(&cmaes::PARAMS);
    p.set("eigen_gap", &Raw::Float(1.0)).unwrap();
    let tutorial = CmaEs::from_params(&p).unwrap();
    for (dim, functions, instances) in [
        (10, (1..=24).collect::<Vec<_>>(), 5),
        (20, (1..=14).collect(), 3),
    ] {
        let a = all_runs(&tutorial, &functions, dim, instances, 1);
        let b = all_runs(&lazy, &functions, dim, instances, 1);
        let (ratio, solved_a, solved_b) = schedule_ratio(&a, &b);
        eprintln!("D = {dim}: median ratio {ratio:.3}, solved {solved_a} (tutorial) and {solved_b} (lazy)");
        assert!(ratio <= 1.05, "D = {dim}: median ratio {ratio}");
        assert!(
            solved_b + 2 >= solved_a,
            "D = {dim}: {solved_b} against {solved_a}"
        );
    }
}
