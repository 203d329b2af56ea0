//! Objective evaluations per second of each optimiser on Sphere (D = 2, 10,
//! 30 and 100) and Rastrigin-30, against the bare cost of the function alone.
//!
//! Every benchmark reports its throughput in evaluations (criterion's
//! "elements"), so the optimiser's overhead ratio is
//! `time per evaluation inside the optimiser / time per bare evaluation`,
//! both measured in the same bench run. The target is a ratio ≤ 3 on
//! Sphere-30 for every optimiser, with ≤ 2 as the stretch (the optimiser's
//! own work per evaluation costs at most one Sphere-30 evaluation).
//! `make bench` prints the ratio table at the end. These ratios are
//! wall-clock means of two separate benchmarks; `make overhead`
//! (`benches/overhead.rs`) measures the same ratio in thread CPU time
//! against a bare loop timed next to each run, which the README quotes.
//! Every algorithm of
//! `Algorithm::names()` is benched, L-SHADE and random search included
//! (random search's ratio is the floor: drawing uniform points and the
//! evaluator's bookkeeping).
//!
//! Two parts of that overhead are also measured alone, so that the floor
//! of the ratio can be read off: `generator/words-60` (the 60 random words
//! one HS improvisation of 30 variables reads) and `improvise/hs-30` (HS
//! improvisations of 30 variables from a memory of 5, words included,
//! compiled for the CPU as in a run); their throughputs are per word and
//! per variable.
//!
//! Two more give the floor itself. `generator/ideal-16-lanes-512` steps
//! sixteen independent Xoshiro256++ lanes held in registers with no buffer,
//! the fastest this generator ran on the CPU measured (it is not the run's
//! stream, only its speed).
//! `improvise/hs-30-words-given` is `improvise/hs-30` with the words
//! already in place, so it times the improvisation's own arithmetic.
//!
//! The `overhead-sphere-<D>` groups (D = 10, 30, 100) time a run of
//! [`OVERHEAD_EVALS`] evaluations of HS, CMA-ES (also with `eigen_gap =
//! 4`) and L-SHADE, and as many bare
//! evaluations of Sphere-D; the summary prints each optimiser's overhead
//! per evaluation, `(run time − bare time)/evaluations`. CMA-ES's covers
//! its sampling (`O(D²)` a point), its updates (`O(μD²)` a generation) and
//! the eigendecomposition (`O(D³)` every `⌊1/(10D(c_1 + c_μ))⌋ + 1`
//! generations, as the tutorial amortises it: every generation at
//! D = 10 and 30, every second at D = 100).

mod common;

use common::{mean_ns, uniform_points};
use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput};
use metabezier::functions::{Function, TestProblem};
use metabezier::linalg::symmetric_eigen;
use metabezier::optim::harmony::{BoundColumns, HarmonyMemory, Improvisation};
use metabezier::optim::params::{ParamSet, Raw};
use metabezier::optim::Algorithm;
use metabezier::optim::Evaluator;
use metabezier::problem::{BoundPolicy, Problem};
use metabezier::rng::{lane_steps, run_rng, Draw, Words};
use metabezier::simd::dispatch;
use rand::RngCore;

const BUDGET: u64 = 20_000;
/// The evaluations of each run (and bare loop) of the `overhead` groups.
const OVERHEAD_EVALS: u64 = 20_000;
/// An entry of [`OVERHEAD_ALGOS`].
type OverheadAlgo = (&'static str, &'static str, Option<(&'static str, f64)>);

/// The optimisers of the `overhead` groups: (bench name, algorithm, a
/// parameter set away from its default). `cmaes-gap4` decomposes `C` four
/// times less often than the tutorial (`eigen_gap = 4`).
const OVERHEAD_ALGOS: [OverheadAlgo; 4] = [
    ("hs", "hs", None),
    ("cmaes", "cmaes", None),
    ("cmaes-gap4", "cmaes", Some(("eigen_gap", 4.0))),
    ("lshade", "lshade", None),
];

/// The algorithm of an [`OVERHEAD_ALGOS`] entry.
fn overhead_algo(name: &str, setting: Option<(&str, f64)>) -> Algorithm {
    let mut p = ParamSet::defaults(Algorithm::params(name).unwrap());
    if let Some((param, value)) = setting {
        p.set(param, &Raw::Float(value)).unwrap();
    }
    Algorithm::from_params(name, &p).unwrap()
}
const POINTS: usize = 1024;
/// HS improvisations per iteration of the `improvise` benchmarks.
const REPEAT: usize = 100;
/// The dimension of the `generator` and `improvise` benchmarks.
const DIM: usize = 30;

fn bench_function(c: &mut Criterion, f: Function, dim: usize) {
    let problem = TestProblem::new(f, dim).unwrap();
    let points = uniform_points(&problem, POINTS);
    let mut group = c.benchmark_group(format!("{}-{dim}", f.name()));
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("bare", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for x in &points {
                s += problem.objective(black_box(x));
            }
            s
        })
    });
    group.throughput(Throughput::Elements(BUDGET));
    for name in Algorithm::names() {
        let algo = Algorithm::default_for(name).unwrap();
        group.bench_with_input(BenchmarkId::from_parameter(name), &algo, |b, algo| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                algo.run(&problem, BUDGET, &mut run_rng(seed)).best_value
            })
        });
    }
    group.finish();
}

/// A run of [`OVERHEAD_EVALS`] evaluations of each of [`OVERHEAD_ALGOS`]
/// on Sphere-`dim`, and as many bare evaluations of it (cycling through
/// [`POINTS`] uniform points).
fn bench_overhead(c: &mut Criterion, dim: usize) {
    let problem = TestProblem::new(Function::Sphere, dim).unwrap();
    let points = uniform_points(&problem, POINTS);
    let mut group = c.benchmark_group(format!("overhead-sphere-{dim}"));
    group.throughput(Throughput::Elements(OVERHEAD_EVALS));
    group.bench_function("bare", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for x in points.iter().cycle().take(OVERHEAD_EVALS as usize) {
                s += problem.objective(black_box(x));
            }
            s
        })
    });
    for (name, kind, setting) in OVERHEAD_ALGOS {
        let algo = overhead_algo(kind, setting);
        group.bench_with_input(BenchmarkId::from_parameter(name), &algo, |b, algo| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                algo.run(&problem, OVERHEAD_EVALS, &mut run_rng(seed))
                    .best_value
            })
        });
    }
    group.finish();
}

/// The cost of the registry, side by side in one process: a run of
/// [`OVERHEAD_EVALS`] evaluations of HS and of PSO on Sphere-`dim`, called
/// as its own type (`direct`), through the registry's [`Algorithm`] on the
/// built-in function (`registry`, the runner's path for the thesis's
/// functions) and through `dyn Problem` (`registry-dyn`, the path of bbob,
/// fitting and registered problems).
fn bench_registry(c: &mut Criterion, dim: usize) {
    use metabezier::optim::{HarmonySearch, Optimiser, ParticleSwarm};
    let problem = TestProblem::new(Function::Sphere, dim).unwrap();
    let mut group = c.benchmark_group(format!("registry-sphere-{dim}"));
    group.throughput(Throughput::Elements(OVERHEAD_EVALS));
    fn direct<O: Optimiser>(
        group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
        name: &str,
        o: &O,
        p: &TestProblem,
    ) {
        group.bench_function(format!("{name}-direct"), |b| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                o.run(p, OVERHEAD_EVALS, &mut run_rng(seed)).best_value
            })
        });
    }
    direct(&mut group, "hs", &HarmonySearch::default(), &problem);
    direct(&mut group, "pso", &ParticleSwarm::default(), &problem);
    for name in ["hs", "pso"] {
        let algo = Algorithm::default_for(name).unwrap();
        group.bench_function(format!("{name}-registry"), |b| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                algo.run(&problem, OVERHEAD_EVALS, &mut run_rng(seed))
                    .best_value
            })
        });
        group.bench_function(format!("{name}-registry-dyn"), |b| {
            let mut seed = 0;
            b.iter(|| {
                seed += 1;
                let mut eval = Evaluator::new(&problem as &dyn Problem, OVERHEAD_EVALS);
                algo.minimise(&mut eval, &mut run_rng(seed));
                eval.finish().best_value
            })
        });
    }
    group.finish();
}

/// [`symmetric_eigen`] of a covariance matrix as CMA-ES meets one (a
/// rotated spectrum `10^{6k/(D−1)}`, compiled for the CPU as in a run) at
/// D = 10, 30 and 100: the `O(D³)` part of CMA-ES's overhead.
fn bench_eigen(c: &mut Criterion) {
    let mut group = c.benchmark_group("eigen");
    for dim in [10, 30, 100] {
        let mut rng = run_rng(7);
        // A random orthonormal basis (Gram–Schmidt) and the spectrum.
        let mut q: Vec<f64> = (0..dim * dim).map(|_| rng.gaussian()).collect();
        for i in 0..dim {
            for j in 0..i {
                let d: f64 = (0..dim).map(|k| q[i * dim + k] * q[j * dim + k]).sum();
                for k in 0..dim {
                    q[i * dim + k] -= d * q[j * dim + k];
                }
            }
            let norm = (0..dim).map(|k| q[i * dim + k].powi(2)).sum::<f64>().sqrt();
            for k in 0..dim {
                q[i * dim + k] /= norm;
            }
        }
        let a: Vec<f64> = (0..dim * dim)
            .map(|ij| {
                let (i, j) = (ij / dim, ij % dim);
                (0..dim)
                    .map(|k| {
                        let e = 10f64.powf(6.0 * k as f64 / (dim - 1) as f64);
                        q[k * dim + i] * e * q[k * dim + j]
                    })
                    .sum()
            })
            .collect();
        let (mut w, mut values, mut e) = (a.clone(), vec![0.0; dim], vec![0.0; dim]);
        group.bench_function(BenchmarkId::from_parameter(dim), |b| {
            b.iter(|| {
                w.copy_from_slice(&a);
                dispatch(
                    #[inline(always)]
                    |_| symmetric_eigen(&mut w, dim, &mut values, &mut e),
                );
                values[0]
            })
        });
    }
    group.finish();
}

/// The parts of an HS evaluation's overhead at D = 30: the random words and
/// the whole improvisation.
fn bench_parts(c: &mut Criterion) {
    let mut group = c.benchmark_group("generator");
    group.throughput(Throughput::Elements(2 * DIM as u64));
    let mut rng = run_rng(1);
    let mut words = [0u64; 2 * DIM];
    group.bench_function("words-60", |b| {
        b.iter(|| {
            rng.words(&mut words);
            black_box(words[0])
        })
    });
    // Sixteen independent lanes (four AVX-512 registers per state word):
    // only their throughput counts, not their stream.
    let mut lanes = [[0u64; 16]; 4];
    for (i, s) in lanes.iter_mut().flatten().enumerate() {
        *s = rng.next_u64() | i as u64;
    }
    let mut ideal = [0u64; 512];
    group.throughput(Throughput::Elements(512));
    group.bench_function("ideal-16-lanes-512", |b| {
        b.iter(|| {
            dispatch(
                #[inline(always)]
                |_| lane_steps(&mut lanes, &mut ideal),
            );
            black_box(ideal[0])
        })
    });
    group.finish();
    let problem = TestProblem::new(Function::Sphere, DIM).unwrap();
    let mut eval = Evaluator::new(&problem, 5);
    let hm = HarmonyMemory::random(5, &mut eval, &mut rng);
    let cols = BoundColumns::new(problem.bounds());
    let bw: Vec<f64> = problem.bounds().iter().map(|b| 0.01 * b.width()).collect();
    let imp = Improvisation {
        hmcr: 0.9,
        par: 0.3,
        policy: BoundPolicy::Clip,
    };
    let mut group = c.benchmark_group("improvise");
    group.throughput(Throughput::Elements((REPEAT * DIM) as u64));
    // `hs-30` draws its words as a run does; `hs-30-words-given` finds them
    // already in the scratch buffer.
    let parts = (&imp, &hm, &cols, &bw[..]);
    let (mut x, mut scratch) = ([0.0; DIM], [0u64; 64]);
    group.bench_function("hs-30", |b| {
        b.iter(|| improvise_repeatedly(parts, &mut rng, &mut scratch, &mut x))
    });
    rng.words(&mut scratch);
    group.bench_function("hs-30-words-given", |b| {
        b.iter(|| improvise_repeatedly(parts, &mut Given, &mut scratch, &mut x))
    });
    group.finish();
}

/// [`REPEAT`] HS improvisations of `x` inside one dispatch, as in a run, with
/// words from `words`; returns the last harmony's first value. (`x` is an
/// array, as in the first version of this benchmark; with a slice, as in a
/// run, the improvisation measured about 6 ns slower.)
fn improvise_repeatedly<R: Words>(
    (imp, hm, cols, bw): (&Improvisation, &HarmonyMemory, &BoundColumns, &[f64]),
    words: &mut R,
    scratch: &mut [u64; 64],
    x: &mut [f64; DIM],
) -> f64 {
    dispatch(
        #[inline(always)]
        |simd| {
            for _ in 0..REPEAT {
                imp.improvise(hm, cols, bw, words, scratch, x, simd);
                black_box(&mut *x);
            }
        },
    );
    x[0]
}

/// A word source that leaves the caller's words as they are, so that a
/// benchmark times only what is done with them.
struct Given;

impl RngCore for Given {
    fn next_u32(&mut self) -> u32 {
        0
    }
    fn next_u64(&mut self) -> u64 {
        0
    }
    fn fill_bytes(&mut self, _: &mut [u8]) {}
}

impl Words for Given {
    #[inline(always)]
    fn words(&mut self, _: &mut [u64]) {}
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bench_parts(&mut c);
    for dim in [30, 2, 10, 100] {
        bench_function(&mut c, Function::Sphere, dim);
    }
    bench_function(&mut c, Function::Rastrigin, 30);
    bench_eigen(&mut c);
    for dim in [10, 30, 100] {
        bench_overhead(&mut c, dim);
    }
    for dim in [2, 30] {
        bench_registry(&mut c, dim);
    }
    c.final_summary();
    println!("\nTime per evaluation inside each optimiser against the bare function:");
    println!("ratio = ns/eval ÷ bare ns; overhead = (ns/eval − bare ns) in units of one bare Sphere-30 evaluation");
    println!("(wall clock, separate benchmarks; `make overhead` gives the ratios in CPU time against a bare loop in the same process)");
    println!(
        "{:<14} {:>6} {:>10} {:>10} {:>8} {:>9}",
        "function", "algo", "ns/eval", "bare ns", "ratio", "overhead"
    );
    let sphere_bare = mean_ns("sphere-30", "bare").map(|t| t / POINTS as f64);
    for f in [
        "sphere-2",
        "sphere-10",
        "sphere-30",
        "sphere-100",
        "rastrigin-30",
    ] {
        let bare = mean_ns(f, "bare").map(|t| t / POINTS as f64);
        for name in Algorithm::names() {
            if let (Some(run), Some(bare), Some(sphere)) = (mean_ns(f, name), bare, sphere_bare) {
                let per_eval = run / BUDGET as f64;
                let ratio = per_eval / bare;
                let overhead = (per_eval - bare) / sphere;
                println!(
                    "{f:<14} {name:>6} {per_eval:>10.1} {bare:>10.1} {ratio:>8.2} {overhead:>9.2}"
                );
            }
        }
    }
    println!("\nOverhead per evaluation, (run − bare)/evaluations, runs of {OVERHEAD_EVALS} evaluations:");
    println!(
        "{:<12} {:>8} {:>10} {:>12} {:>10}",
        "function", "algo", "ns/eval", "overhead ns", "evals/s"
    );
    for dim in [10, 30, 100] {
        let group = format!("overhead-sphere-{dim}");
        let Some(bare) = mean_ns(&group, "bare").map(|t| t / OVERHEAD_EVALS as f64) else {
            continue;
        };
        println!(
            "{:<12} {:>8} {bare:>10.1} {:>12} {:>10}",
            format!("sphere-{dim}"),
            "bare",
            "",
            ""
        );
        for (name, _, _) in OVERHEAD_ALGOS {
            if let Some(run) = mean_ns(&group, name) {
                let per_eval = run / OVERHEAD_EVALS as f64;
                let overhead = per_eval - bare;
                println!(
                    "{:<12} {name:>8} {per_eval:>10.1} {overhead:>12.1} {:>10.3e}",
                    format!("sphere-{dim}"),
                    1e9 / overhead
                );
            }
        }
    }
}
