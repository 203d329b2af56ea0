//! One evaluation of the segment objective `E = Σ|Rᵢ − P(sᵢ)|²` on a
//! 500-point segment, for each function type, against evaluating the bare
//! curve (`Curve::eval_many` on the geometry type) at the same 500 parameters.
//!
//! The goal is `E ≈ bare`: the objective builds the control points from the
//! decision vector on the stack and evaluates the fixed-degree Bernstein
//! form, with no allocation in the hot path. The table at the end prints
//! nanoseconds per point and the ratio.
//!
//! A second group times whole fits: the vendored horse outline (2,644
//! points) split recursively until every point is within 1 px, with LM and
//! with MHS (10,000 evaluations per segment, the `metabezier fit` default),
//! and cut into 101 segments (rational cubic, G1, LM); then the coin, which
//! has no corner, at 20 segments closed smoothly and closed C⁰ (what the
//! smooth closing costs), and the output stage alone: the horse's default
//! files, and with the PNG and the DXF. The last lines give the
//! 101-segment horse's orthogonal distances. Run with `cargo bench --bench fitting`.

mod common;

use common::mean_ns;
use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{Criterion, Throughput};
use metabezier::fit::{
    Chain, ErrorMeasure, FitOptions, FunctionType, SearchSpaceOptions, Segment, SegmentProblem,
    Start,
};
use metabezier::geometry::{Continuity, Curve, Parameterisation, Point};
use metabezier::problem::Problem;

const POINTS: usize = 500;

/// A wavy data segment with a little deterministic noise.
fn data() -> Vec<Point> {
    (0..POINTS)
        .map(|k| {
            let u = k as f64 / (POINTS - 1) as f64;
            let noise = if k == 0 || k == POINTS - 1 {
                0.0
            } else {
                1e-3 * ((k * 7919 % 101) as f64 / 101.0 - 0.5)
            };
            Point::new(10.0 * u, 3.0 * (3.0 * u).sin() + noise)
        })
        .collect()
}

/// The bare curve: `Curve::eval_many` on the geometry type at the parameters,
/// into a buffer (monomorphised per type, no reduction).
fn bare_eval(segment: &Segment, params: &[f64], out: &mut [Point]) {
    match segment {
        Segment::Quadratic(c) => c.eval_many(params, out),
        Segment::Cubic(c) => c.eval_many(params, out),
        Segment::RationalQuadratic(c) => c.eval_many(params, out),
        Segment::RationalCubic(c) => c.eval_many(params, out),
    }
}

fn bench(c: &mut Criterion) {
    let pts = data();
    for f in FunctionType::ALL {
        let problem = SegmentProblem::with_parameterisation(
            f,
            pts.clone(),
            Parameterisation::ChordLength,
            Start::Free,
            &SearchSpaceOptions::default(),
        )
        .expect("valid segment");
        let x: Vec<f64> = problem.guess().to_vec();
        let segment = problem.segment(&x);
        let params = problem.params().to_vec();
        let mut group = c.benchmark_group(format!("fit-{}", f.name()));
        group.throughput(Throughput::Elements(POINTS as u64));
        group.bench_function("objective", |b| b.iter(|| problem.objective(black_box(&x))));
        let mut r = vec![0.0; 2 * POINTS];
        group.bench_function("residuals", |b| {
            b.iter(|| {
                problem.residuals(black_box(&x), &mut r);
                r[POINTS]
            })
        });
        let mut out = vec![Point::ZERO; POINTS];
        group.bench_function("bare-curve", |b| {
            b.iter(|| {
                bare_eval(&segment, black_box(&params), &mut out);
                out[POINTS / 2]
            })
        });
        group.finish();
    }
}

/// The vendored horse, its one contour.
fn horse_source() -> metabezier::reconstruction::Source {
    use metabezier::reconstruction::{LoadOptions, Source};
    Source::load(
        "data/outlines/horse.png",
        Path::new(env!("CARGO_MANIFEST_DIR")),
        &LoadOptions::default(),
    )
    .expect("the vendored horse")
}

/// The horse at 101 segments, rational cubic, G1, with the error `error`
/// and the chain `chain`.
fn horse_101(
    source: &metabezier::reconstruction::Source,
    error: ErrorMeasure,
    chain: Chain,
) -> metabezier::reconstruction::Reconstruction<'_> {
    let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::G1);
    options.error = error;
    options.chain = chain;
    metabezier::reconstruction::Reconstruction {
        source,
        segmentation: metabezier::reconstruction::Segmentation::Count(101),
        corners: Some(metabezier::outline::CornerOptions::default()),
        options,
    }
}

/// Fitting the horse at 1 px tolerance, end to end after loading, and at
/// 101 segments with LM under the fixed and the orthogonal error.
fn horse(c: &mut Criterion) {
    use metabezier::fit::{FitOptions, FunctionType};
    use metabezier::geometry::Continuity;
    use metabezier::optim::Algorithm;
    use metabezier::outline::CornerOptions;
    use metabezier::reconstruction::{Method, Reconstruction, Segmentation};
    let source = horse_source();
    let r = Reconstruction {
        source: &source,
        segmentation: Segmentation::Tolerance(1.0),
        corners: Some(CornerOptions::default()),
        options: FitOptions::new(FunctionType::RationalCubic, Continuity::G1),
    };
    let mut group = c.benchmark_group("horse-1px");
    group.sample_size(10);
    for (name, method) in [
        ("lm", Method::Exact),
        (
            "mhs",
            Method::Metaheuristic(Algorithm::default_for("mhs").expect("mhs")),
        ),
    ] {
        group.bench_function(name, |b| {
            b.iter(|| r.fit(&method, 1).expect("a valid fit").metrics.segments)
        });
    }
    group.finish();
    let mut group = c.benchmark_group("horse-101");
    group.sample_size(20);
    for chain in [Chain::Sequential, Chain::Joint] {
        for error in [ErrorMeasure::Fixed, ErrorMeasure::Orthogonal] {
            let r = horse_101(&source, error, chain);
            let id = match chain {
                Chain::Sequential => format!("lm-{}", error.name()),
                Chain::Joint => format!("lm-{}-joint", error.name()),
            };
            group.bench_function(id, |b| {
                b.iter(|| {
                    r.fit(&Method::Exact, 1)
                        .expect("a valid fit")
                        .metrics
                        .segments
                })
            });
        }
    }
    // The command line's default end to end: the PNG loaded and traced,
    // then fitted (orthogonal error, joint chain).
    group.bench_function("end-to-end", |b| {
        b.iter(|| {
            let source = horse_source();
            horse_101(&source, ErrorMeasure::Orthogonal, Chain::Joint)
                .fit(&Method::Exact, 1)
                .expect("a valid fit")
                .metrics
                .segments
        })
    });
    group.bench_function("load-and-trace", |b| {
        b.iter(|| horse_source().points().len())
    });
    outputs(&mut group, &source);
    group.finish();
    closing(c);
    orthogonal_scaling(c);
}

/// The output stage alone, on the default fit of the horse at 101
/// segments: what `metabezier fit` writes by default (`fit.csv`,
/// `metrics.csv`, `timing.csv` and `fit.svg`), and with the raster and the
/// DXF too (`--outputs csv,svg,png,dxf`), into a scratch directory.
fn outputs(
    group: &mut criterion::BenchmarkGroup<'_, criterion::measurement::WallTime>,
    source: &metabezier::reconstruction::Source,
) {
    use metabezier::experiment::fit_files::write_fit_records;
    use metabezier::reconstruction::{save_shape_png, save_shape_svg, shape_dxf, Method};
    let fit = horse_101(source, ErrorMeasure::Orthogonal, Chain::Joint)
        .fit(&Method::Exact, 1)
        .expect("a valid fit");
    let data = source.points();
    let dir = std::env::temp_dir().join(format!("metabezier-bench-out-{}", std::process::id()));
    let case = [("input", "horse.png".to_owned())];
    let default = |dir: &Path| {
        write_fit_records(dir, &fit, &case, 0.0).expect("records written");
        save_shape_svg(&fit, &data, "horse", dir, "fit").expect("svg written");
    };
    group.bench_function("output-default", |b| b.iter(|| default(&dir)));
    group.bench_function("output-with-png-dxf", |b| {
        b.iter(|| {
            default(&dir);
            save_shape_png(&fit, &data, &dir, "fit").expect("png written");
            std::fs::write(dir.join("fit.dxf"), shape_dxf(&fit)).expect("dxf written");
        })
    });
    let _ = std::fs::remove_dir_all(&dir);
}

/// The orthogonal LM's cost against the number of points: a rotated ellipse
/// (semi-axes 140 and 55) sampled at 10³, 10⁴ and 10⁵ equal angles, four G1
/// rational cubics closed smoothly. One projection per point per
/// evaluation, so the cost should grow linearly.
fn orthogonal_scaling(c: &mut Criterion) {
    use metabezier::fit::{fit_piecewise, LmSolver};
    let mut group = c.benchmark_group("orthogonal-points");
    group.sample_size(10);
    for n in [1_000usize, 10_000, 100_000] {
        let (s, co) = 0.4f64.sin_cos();
        let pts: Vec<Point> = (0..n)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / n as f64;
                let (x, y) = (140.0 * phi.cos(), 55.0 * phi.sin());
                Point::new(co * x - s * y + 200.0, s * x + co * y + 150.0)
            })
            .collect();
        let breaks: Vec<usize> = (0..4).map(|k| k * n / 4).collect();
        let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::G1);
        options.error = ErrorMeasure::Orthogonal;
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(format!("{n}"), |b| {
            b.iter(|| {
                fit_piecewise(&pts, true, &breaks, &options, &mut LmSolver::default())
                    .expect("a valid fit")
                    .metrics
                    .max_distance
            })
        });
    }
    group.finish();
}

/// What the smooth closing costs: the coin (no corner, so its chain closes
/// with an end join) at 20 segments, rational cubic, G1, with LM and with
/// MHS (3,000 evaluations per segment), closed smoothly and closed C⁰.
fn closing(c: &mut Criterion) {
    use metabezier::fit::{Closing, FitOptions, FunctionType};
    use metabezier::geometry::Continuity;
    use metabezier::optim::Algorithm;
    use metabezier::outline::CornerOptions;
    use metabezier::reconstruction::{LoadOptions, Method, Reconstruction, Segmentation, Source};
    let source = Source::load(
        "data/outlines/coin.png",
        Path::new(env!("CARGO_MANIFEST_DIR")),
        &LoadOptions::default(),
    )
    .expect("the vendored coin");
    let mut group = c.benchmark_group("closing");
    group.sample_size(20);
    let mhs = Method::Metaheuristic(Algorithm::default_for("mhs").expect("mhs"));
    for (name, method) in [("lm", Method::Exact), ("mhs", mhs)] {
        for (closing, label) in [(Closing::Smooth, "smooth"), (Closing::C0, "c0")] {
            let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::G1);
            options.closing = closing;
            options.budget_per_segment = 3000;
            let r = Reconstruction {
                source: &source,
                segmentation: Segmentation::Count(20),
                corners: Some(CornerOptions::default()),
                options,
            };
            group.bench_function(format!("{name}-{label}"), |b| {
                b.iter(|| r.fit(&method, 1).expect("a valid fit").metrics.segments)
            });
        }
    }
    group.finish();
}

/// The horse at 101 segments (rational cubic, G1, LM) under each error: its
/// orthogonal maximum and RMS distance, by the fit's own measure (each point
/// to its segment) and as `metabezier score` measures them (to the whole
/// curve).
fn horse_accuracy() {
    use metabezier::outline::Segment;
    use metabezier::reconstruction::{cubic_pieces, score, Method};
    let source = horse_source();
    for (error, chain) in [
        (ErrorMeasure::Fixed, Chain::Sequential),
        (ErrorMeasure::Orthogonal, Chain::Sequential),
        (ErrorMeasure::Fixed, Chain::Joint),
        (ErrorMeasure::Orthogonal, Chain::Joint),
    ] {
        let fit = horse_101(&source, error, chain)
            .fit(&Method::Exact, 1)
            .expect("a valid fit");
        let curves: Vec<Vec<Segment>> = vec![fit
            .segments()
            .flat_map(|(_, s)| cubic_pieces(&s.segment, 1e-6))
            .map(Segment::Cubic)
            .collect()];
        let s = score(&source, &curves).expect("finite curves to score");
        println!(
            "\nThe horse at 101 segments (rational cubic, G1, LM, {} error, {} chain): max distance {:.3} px, RMS distance {:.3} px (each point to its segment); {:.3} px and {:.3} px to the whole curve",
            error.name(), chain.name(), fit.metrics.max_distance, fit.metrics.rms_distance, s.total.max_distance, s.total.rms_distance
        );
    }
}

fn main() {
    let mut c = Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    bench(&mut c);
    horse(&mut c);
    c.final_summary();
    println!("\nOne evaluation of E on a {POINTS}-point segment against the bare curve:");
    println!(
        "{:<20} {:>12} {:>12} {:>12} {:>8}",
        "function", "E ns/pt", "resid ns/pt", "bare ns/pt", "E/bare"
    );
    for f in FunctionType::NAMES {
        let g = format!("fit-{f}");
        let per = |id: &str| mean_ns(&g, id).map(|t| t / POINTS as f64);
        if let (Some(e), Some(r), Some(bare)) =
            (per("objective"), per("residuals"), per("bare-curve"))
        {
            println!("{f:<20} {e:>12.2} {r:>12.2} {bare:>12.2} {:>8.2}", e / bare);
        }
    }
    println!("\nThe horse (2,644 points) fitted with rational cubics, G1, at 1 px:");
    for m in ["lm", "mhs"] {
        if let Some(t) = mean_ns("horse-1px", m) {
            println!("{m:<6} {:>10.1} ms", t / 1e6);
        }
    }
    println!("\nThe horse at 101 segments, rational cubics, G1, LM:");
    for id in [
        "lm-fixed",
        "lm-orthogonal",
        "lm-fixed-joint",
        "lm-orthogonal-joint",
        "end-to-end",
        "load-and-trace",
        "output-default",
        "output-with-png-dxf",
    ] {
        if let Some(t) = mean_ns("horse-101", id) {
            println!("{id:<22} {:>8.2} ms", t / 1e6);
        }
    }
    println!("\nThe coin at 20 segments, rational cubics, G1, closed smoothly against C0:");
    for m in ["lm", "mhs"] {
        let smooth = mean_ns("closing", &format!("{m}-smooth"));
        let c0 = mean_ns("closing", &format!("{m}-c0"));
        if let (Some(a), Some(b)) = (smooth, c0) {
            println!(
                "{m:<6} {:>10.3} ms against {:>10.3} ms: {:+.1} %",
                a / 1e6,
                b / 1e6,
                100.0 * (a / b - 1.0)
            );
        }
    }
    horse_accuracy();
}
