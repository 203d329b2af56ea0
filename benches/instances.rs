//! The cost of a transformed benchmark instance against the bare function
//! at D = 30: a shift should cost at most 1.5× the bare evaluation, a
//! rotation at most the bare evaluation plus one D × D matrix-vector
//! product (measured here on its own). Also one evaluation of COCO's bbob
//! f1 through COCO's C code against our Sphere at D = 10. `make bench`
//! prints the ratios.

mod common;

use common::{mean_ns, uniform_points};
use std::hint::black_box;

use criterion::{Criterion, Throughput};
use metabezier::functions::{BbobProblem, Function, TestProblem, Transform};
use metabezier::problem::Problem;
use metabezier::rng::{run_rng, Draw};

const POINTS: usize = 1024;
const D: usize = 30;

fn bench(c: &mut Criterion, f: Function) {
    let mut group = c.benchmark_group(format!("{}-{D}-instance", f.name()));
    group.throughput(Throughput::Elements(POINTS as u64));
    for t in [Transform::None, Transform::Shift, Transform::ShiftRotate] {
        let problem = TestProblem::instance(f, D, t, 1).unwrap();
        let xs = uniform_points(&problem, POINTS);
        group.bench_function(t.name(), |b| {
            b.iter(|| {
                let mut s = 0.0;
                for x in &xs {
                    s += problem.objective(black_box(x));
                }
                s
            })
        });
    }
    // One D × D matrix-vector product, summed left to right as the rotation is.
    let m: Vec<f64> = {
        let mut rng = run_rng(2);
        (0..D * D).map(|_| rng.gaussian()).collect()
    };
    let xs = uniform_points(&TestProblem::new(f, D).unwrap(), POINTS);
    group.bench_function("matvec", |b| {
        let mut y = [0.0; D];
        b.iter(|| {
            let mut s = 0.0;
            for x in &xs {
                for (yi, row) in y.iter_mut().zip(m.chunks_exact(D)) {
                    let mut acc = 0.0;
                    for (a, v) in row.iter().zip(black_box(x)) {
                        acc += a * v;
                    }
                    *yi = acc;
                }
                s += y[0];
            }
            s
        })
    });
    group.finish();
}

/// One evaluation of COCO's bbob f1 (sphere) through COCO's C code against
/// our own Sphere, at D = 10.
fn bench_coco(c: &mut Criterion) {
    let ours = TestProblem::new(Function::Sphere, 10).unwrap();
    let coco = BbobProblem::new(1, 10, 1).unwrap();
    let xs = uniform_points(&ours, POINTS);
    let mut group = c.benchmark_group("sphere-10-coco");
    group.throughput(Throughput::Elements(POINTS as u64));
    group.bench_function("ours", |b| {
        b.iter(|| xs.iter().map(|x| ours.objective(black_box(x))).sum::<f64>())
    });
    group.bench_function("coco-f1", |b| {
        b.iter(|| xs.iter().map(|x| coco.objective(black_box(x))).sum::<f64>())
    });
    group.finish();
}

fn main() {
    let mut c = Criterion::default().configure_from_args();
    bench(&mut c, Function::Sphere);
    bench(&mut c, Function::Rastrigin);
    bench_coco(&mut c);
    c.final_summary();
    let per = |g: &str, id: &str| mean_ns(g, id).map(|t| t / POINTS as f64);
    if let (Some(ours), Some(coco)) = (
        per("sphere-10-coco", "ours"),
        per("sphere-10-coco", "coco-f1"),
    ) {
        println!(
            "\nD = 10, ns per evaluation: our Sphere {ours:.1}, COCO's bbob f1 {coco:.1} ({:.1}×)",
            coco / ours
        );
    }
    println!("\nTransformed instances at D = {D}, ns per evaluation:");
    println!(
        "{:<22} {:>8} {:>8} {:>13} {:>8} {:>16}",
        "function", "bare", "shift", "shift÷bare", "rotate", "rotate÷(bare+mv)"
    );
    for f in ["sphere", "rastrigin"] {
        let group = format!("{f}-{D}-instance");
        let per = |id: &str| mean_ns(&group, id).map(|t| t / POINTS as f64);
        if let (Some(bare), Some(shift), Some(rot), Some(mv)) = (
            per("none"),
            per("shift"),
            per("shift-rotate"),
            per("matvec"),
        ) {
            println!(
                "{group:<22} {bare:>8.1} {shift:>8.1} {:>13.2} {rot:>8.1} {:>16.2}",
                shift / bare,
                rot / (bare + mv)
            );
        }
    }
}
