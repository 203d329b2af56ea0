//! The benchmark functions' values, optima, domains and errors.

use super::formulas::floor_half_up;
use super::*;
use crate::problem::Problem;
use std::f64::consts::{PI, SQRT_2};

/// `|actual − expected| ≤ rel·max(1, |expected|)`.
fn assert_close(actual: f64, expected: f64, rel: f64, what: &str) {
    let tol = rel * expected.abs().max(1.0);
    assert!(
        (actual - expected).abs() <= tol,
        "{what}: got {actual:e}, expected {expected:e} (tolerance {tol:e})"
    );
}

/// The documented tolerance of `f(x*)` around `f*`.
fn optimum_tolerance(f: Function, dim: usize) -> f64 {
    match f {
        Function::Schwefel226 => 2.5e-13 * dim as f64,
        Function::Ackley => 4.5e-16,
        Function::SixHumpCamel => 2e-15,
        _ => 0.0,
    }
}

#[test]
fn every_instance_keeps_f_star_at_its_shift() {
    for f in Function::ALL.into_iter().filter(|f| f.is_transformable()) {
        for d in [2, 10, 30] {
            for t in [Transform::Shift, Transform::ShiftRotate] {
                for k in 1..=5 {
                    let p = TestProblem::instance(f, d, t, k).unwrap();
                    let o = p.transformed().unwrap().shift().to_vec();
                    assert!(o.iter().zip(p.bounds()).all(|(x, b)| b.contains(*x)));
                    let v = p.objective(&o);
                    let tol = optimum_tolerance(f, d);
                    assert!(
                        (v - f.optimum_value()).abs() <= tol,
                        "{f}-{d} {t} #{k}: F(o) = {v:e}"
                    );
                    // Away from o_k the value is worse.
                    let mut x = o.clone();
                    x[0] = p.bounds()[0].clip(x[0] + 0.3 * p.bounds()[0].width());
                    assert!(p.objective(&x) > f.optimum_value() + tol, "{f}-{d} {t}");
                }
            }
        }
    }
    let big = TestProblem::instance(Function::Sphere, 200, Transform::ShiftRotate, 1).unwrap();
    let o = big.transformed().unwrap().shift().to_vec();
    assert_eq!(big.objective(&o), 0.0);
}

#[test]
fn untransformable_functions_and_huge_rotations_are_refused() {
    for f in [Function::Schwefel226, Function::SixHumpCamel] {
        let e = TestProblem::instance(f, 2, Transform::Shift, 1).unwrap_err();
        assert!(e.to_string().contains("has no \"shift\" instances"), "{e}");
        assert!(TestProblem::instance(f, 2, Transform::None, 1).is_ok());
    }
    let e = TestProblem::instance(Function::Sphere, 1001, Transform::ShiftRotate, 1);
    assert_eq!(e, Err(FunctionError::RotationTooLarge { requested: 1001 }));
    let plain = TestProblem::instance(Function::Sphere, 3, Transform::None, 7).unwrap();
    assert_eq!(plain, TestProblem::new(Function::Sphere, 3).unwrap());
}

#[test]
fn optimum_value_at_optimum_location() {
    for f in Function::ALL {
        let dims: &[usize] = if f.is_scalable() { &[2, 10, 30] } else { &[2] };
        for &d in dims {
            let x = f.optimum_location(d);
            assert_eq!(x.len(), d, "{f}");
            let v = f.eval(&x);
            let tol = optimum_tolerance(f, d);
            assert!(
                (v - f.optimum_value()).abs() <= tol,
                "{f}-{d}: f(x*) = {v:e}, f* = {:e}, tolerance {tol:e}",
                f.optimum_value()
            );
        }
    }
}

#[test]
fn camel_back_mirror_minimiser() {
    let [a, b] = CAMEL_X;
    let v = Function::SixHumpCamel.eval(&[-a, -b]);
    assert!((v - CAMEL_MIN).abs() <= 2e-15, "{v:e}");
    // The often-quoted (0.08984201368301331, −0.7126564032704135) is ~6e-10
    // off the true root but agrees in value.
    let quoted = Function::SixHumpCamel.eval(&[0.089_842_013_683_013_31, -0.712_656_403_270_413_5]);
    assert!((quoted - CAMEL_MIN).abs() <= 2e-15, "{quoted:e}");
}

#[test]
fn optimum_is_a_local_minimum() {
    // Moving any one coordinate of x* by ±h must not go below f* (beyond the
    // documented tolerance); catches a wrong optimum location.
    for f in Function::ALL {
        let d = f.fixed_dim().unwrap_or(5);
        let x = f.optimum_location(d);
        let fstar = f.optimum_value();
        for i in 0..d {
            for h in [1e-3, -1e-3, 1e-6, -1e-6] {
                let mut y = x.clone();
                y[i] += h;
                let v = f.eval(&y);
                assert!(
                    v >= fstar - optimum_tolerance(f, d),
                    "{f}: f(x* + {h}e_{i}) = {v:e} < f* = {fstar:e}"
                );
                if f != Function::Step {
                    assert!(v > fstar, "{f}: x* + {h}e_{i} is not strictly worse");
                }
            }
        }
    }
}

#[test]
fn optimum_locations_are_stationary_points() {
    // Values are flat at a minimum, so check the gradient instead: it pins
    // the minimiser to ~1e-12, where f(x*) could not tell a 1e-8 error.
    // Schwefel 2.26: d/dx (x sin √x) = sin u + (u/2) cos u with u = √x.
    let u = SCHWEFEL_226_X.sqrt();
    let g1 = u.sin() + 0.5 * u * u.cos();
    assert!(g1.abs() < 1e-12, "Schwefel 2.26 slope at x*: {g1:e}");
    // Camel-back: ∂f/∂x = 8x − 8.4x³ + 2x⁵ + y, ∂f/∂y = x − 8y + 16y³.
    let [x, y] = CAMEL_X;
    let gx = 8.0 * x - 8.4 * x.powi(3) + 2.0 * x.powi(5) + y;
    let gy = x - 8.0 * y + 16.0 * y.powi(3);
    assert!(
        gx.abs() < 1e-12 && gy.abs() < 1e-12,
        "camel gradient ({gx:e}, {gy:e})"
    );
}

#[test]
fn optimum_location_is_inside_the_domain() {
    for f in Function::ALL {
        let b = f.domain();
        assert!(b.lower < b.upper, "{f}");
        for v in f.optimum_location(f.fixed_dim().unwrap_or(3)) {
            assert!(b.contains(v), "{f}: {v} outside [{}, {}]", b.lower, b.upper);
        }
    }
}

#[test]
fn domains_match_yao_et_al() {
    let expected = [
        (Function::Sphere, 100.0),
        (Function::Schwefel222, 10.0),
        (Function::Rosenbrock, 30.0),
        (Function::Step, 100.0),
        (Function::Schwefel12, 100.0),
        (Function::Schwefel226, 500.0),
        (Function::Rastrigin, 5.12),
        (Function::Ackley, 32.0),
        (Function::Griewank, 600.0),
        (Function::SixHumpCamel, 5.0),
    ];
    for (f, r) in expected {
        assert_eq!(f.domain(), Bounds::new(-r, r), "{f}");
    }
}

#[test]
fn sphere_values() {
    assert_eq!(Function::Sphere.eval(&[1.0, 2.0, 3.0]), 14.0);
    assert_eq!(Function::Sphere.eval(&[-0.5]), 0.25);
    assert_eq!(Function::Sphere.eval(&[100.0; 30]), 300_000.0);
}

#[test]
fn schwefel_2_22_values() {
    // Σ|x| = 6, Π|x| = 6.
    assert_eq!(Function::Schwefel222.eval(&[1.0, -2.0, 3.0]), 12.0);
    // Σ|x| = 1.25, Π|x| = 0.
    assert_eq!(Function::Schwefel222.eval(&[0.0, -0.25, 1.0]), 1.25);
    // D = 30 at the corner: 300 + 10³⁰.
    assert_close(
        Function::Schwefel222.eval(&[-10.0; 30]),
        1e30 + 300.0,
        1e-15,
        "corner",
    );
}

#[test]
fn rosenbrock_values() {
    assert_eq!(Function::Rosenbrock.eval(&[0.0, 0.0]), 1.0);
    // 100(2 − 1)² + (−2)² = 104; 100(0.5 − 4)² + 1² = 1226.
    assert_eq!(Function::Rosenbrock.eval(&[-1.0, 2.0, 0.5]), 1330.0);
    // Only the last pair contributes: 100(2 − 1)².
    assert_eq!(Function::Rosenbrock.eval(&[1.0, 1.0, 1.0, 2.0]), 100.0);
    // D = 1 has no pair: constant 0.
    assert_eq!(Function::Rosenbrock.eval(&[7.0]), 0.0);
}

#[test]
fn step_values() {
    // ⌊0.9⌋ = 0, ⌊−0.1⌋ = −1, ⌊2.0⌋ = 2.
    assert_eq!(Function::Step.eval(&[0.4, -0.6, 1.5]), 5.0);
    // The whole plateau [−½, ½)^D is optimal, including its exact edges.
    // (`f64::next_down` needs Rust 1.86; the crate's MSRV is 1.85.)
    let below_half = f64::from_bits(0.5f64.to_bits() - 1);
    assert_eq!(below_half, 0.499_999_999_999_999_94);
    assert_eq!(Function::Step.eval(&[-0.5, below_half, 0.0, -0.0]), 0.0);
    // ... and ½ itself is not.
    assert_eq!(Function::Step.eval(&[0.5]), 1.0);
    assert_eq!(
        Function::Step.eval(&[f64::from_bits((-0.5f64).to_bits() + 1)]),
        1.0
    );
    // ⌊−99.7 + ½⌋ = −100 → 10⁴.
    assert_eq!(Function::Step.eval(&[-99.7, 2.49]), 10_004.0);
}

#[test]
fn floor_half_up_matches_exact_rounding() {
    for (x, r) in [
        (0.0, 0.0),
        (0.5, 1.0),
        (-0.5, 0.0),
        (0.499_999_999_999_999_94, 0.0),
        (1.499_999_999_999_999_8, 1.0),
        (-1.5, -1.0),
        (-1.500_000_000_000_000_2, -2.0),
        (2.5, 3.0),
        (-2.5, -2.0),
        (-1e-300, 0.0),
        (4_503_599_627_370_495.5, 4_503_599_627_370_496.0),
        (-4_503_599_627_370_495.5, -4_503_599_627_370_495.0),
        (4_503_599_627_370_497.0, 4_503_599_627_370_497.0),
        (-1e300, -1e300),
        (f64::INFINITY, f64::INFINITY),
        (f64::NEG_INFINITY, f64::NEG_INFINITY),
        (-3.0, -3.0),
        (-2.7, -3.0),
        (-2.2, -2.0),
        (99.5, 100.0),
    ] {
        assert_eq!(floor_half_up(x), r, "⌊{x} + ½⌋");
    }
    assert!(floor_half_up(f64::NAN).is_nan());
    // Agrees with the libm-based definition away from the rounding edge.
    for k in -4000..4000 {
        let x = k as f64 * 0.0137 + 0.001;
        assert_eq!(floor_half_up(x), (x + 0.5).floor(), "x = {x}");
    }
}

#[test]
fn schwefel_1_2_values() {
    // Prefix sums 1, 3, 6: 1 + 9 + 36.
    assert_eq!(Function::Schwefel12.eval(&[1.0, 2.0, 3.0]), 46.0);
    // Prefix sums 1, 0, 2, −2: 1 + 0 + 4 + 4.
    assert_eq!(Function::Schwefel12.eval(&[1.0, -1.0, 2.0, -4.0]), 9.0);
}

#[test]
fn schwefel_1_2_equals_the_quadratic_definition() {
    // The O(D) prefix sum is bit-identical to the O(D²) double sum.
    let x: Vec<f64> = (0..30)
        .map(|i| ((i * 37 % 23) as f64 - 11.3) * 7.77)
        .collect();
    let naive: f64 = (0..x.len()).fold(0.0, |s, i| {
        let inner = x[..=i].iter().fold(0.0, |t, &v| t + v);
        s + inner * inner
    });
    assert_eq!(Function::Schwefel12.eval(&x).to_bits(), naive.to_bits());
}

#[test]
fn schwefel_2_26_values() {
    let c = SCHWEFEL_226_OFFSET;
    // sin √0 = 0: each variable contributes the offset.
    assert_eq!(Function::Schwefel226.eval(&[0.0, 0.0]), 2.0 * c);
    // 418.9828872724337 − 100 sin 10 (mpmath, 40 digits: 473.38499836137066746155…).
    assert_close(
        Function::Schwefel226.eval(&[100.0]),
        473.384_998_361_370_67,
        1e-15,
        "x = 100",
    );
    // The mirror of the minimiser is near the maximum: c + x* sin √x* + c
    // (mpmath: 1256.9486618173010785…).
    assert_close(
        Function::Schwefel226.eval(&[-SCHWEFEL_226_X, 0.0]),
        1_256.948_661_817_301_1,
        1e-15,
        "(−x*, 0)",
    );
    // 3c − sin 1 − 4 sin 2 + 9 sin 3 (mpmath: 1253.7400811977292400…).
    assert_close(
        Function::Schwefel226.eval(&[1.0, 4.0, -9.0]),
        1_253.740_081_197_729_2,
        1e-15,
        "(1, 4, −9)",
    );
}

#[test]
fn schwefel_2_26_constants() {
    // The offset is x* sin √x* in f64, so each summand vanishes at x*.
    let g = SCHWEFEL_226_X * SCHWEFEL_226_X.sqrt().sin();
    assert!((g - SCHWEFEL_226_OFFSET).abs() <= 2.5e-13, "{g:e}");
    // The often-published 418.9828872724339 (two ulps too high) in the
    // literal form `c·D − Σ x sin √|x|` leaves ~5.5e-12 at D = 30; the
    // summand-wise form with the nearest-f64 offset does better.
    let published_form = 418.982_887_272_433_9 * 30.0 - (0..30).fold(0.0, |s, _| s + g);
    let ours = Function::Schwefel226.eval(&[SCHWEFEL_226_X; 30]);
    assert!(published_form.abs() > 1e-12, "{published_form:e}");
    assert!(
        ours.abs() <= 2.5e-13 * 30.0 && ours.abs() < published_form.abs(),
        "{ours:e}"
    );
    // Around x*, no f64 is worse than the documented lower bound per variable.
    let bits = SCHWEFEL_226_X.to_bits();
    for y in (bits - 1000..=bits + 1000).map(f64::from_bits) {
        let v = Function::Schwefel226.eval(&[y]);
        assert!((-2.5e-13..=1e-9).contains(&v), "f({y}) = {v:e}");
    }
}

#[test]
fn rastrigin_values() {
    assert_eq!(Function::Rastrigin.eval(&[1.0, 1.0]), 2.0);
    // (0.25 + 20) + (2.25 + 20) + (4 + 0).
    assert_eq!(Function::Rastrigin.eval(&[0.5, -1.5, 2.0]), 46.5);
    // 0.0625 + 10(1 − cos(π/2)) = 10.0625.
    assert_close(
        Function::Rastrigin.eval(&[0.25]),
        10.0625,
        1e-15,
        "x = 0.25",
    );
}

#[test]
fn ackley_values() {
    // f(0) is exactly 0 with the grouping used (documented bound: one ulp of e).
    for d in [1, 2, 30] {
        assert!(Function::Ackley.eval(&vec![0.0; d]).abs() <= 4.5e-16);
    }
    // Σx²/D = 1, Σcos/D = 1: 20(1 − e^−0.2) (mpmath: 3.6253849384403630083…).
    assert_close(
        Function::Ackley.eval(&[1.0, 1.0]),
        3.625_384_938_440_363,
        1e-15,
        "(1, 1)",
    );
    // √(Σx²/D) = ½, Σcos/D = −1: 20(1 − e^−0.1) + e − e^−1 (mpmath: 4.2536540265684115509…).
    assert_close(
        Function::Ackley.eval(&[0.5, 0.5]),
        4.253_654_026_568_411_6,
        1e-15,
        "(½, ½)",
    );
    // mpmath: 5.4221317177995082164…
    assert_close(
        Function::Ackley.eval(&[1.0, 2.0]),
        5.422_131_717_799_508,
        1e-15,
        "(1, 2)",
    );
    // mpmath: 8.9892644965369578022…
    assert_close(
        Function::Ackley.eval(&[-3.0, 0.25, 2.5]),
        8.989_264_496_536_958,
        1e-15,
        "(−3, ¼, 2.5)",
    );
    // The corner (mpmath: 19.966768854536521321…).
    assert_close(
        Function::Ackley.eval(&[32.0, 32.0]),
        19.966_768_854_536_52,
        1e-15,
        "(32, 32)",
    );
}

#[test]
fn griewank_values() {
    // x_i/√i = π for both: Π cos = 1, so f = 3π²/4000 (mpmath: 0.0074022033008170189641…).
    assert_close(
        Function::Griewank.eval(&[PI, PI * SQRT_2]),
        0.007_402_203_300_817_019,
        1e-15,
        "(π, π√2)",
    );
    // 1 + 14/4000 − cos 1 cos(2/√2) cos(3/√3) (mpmath: 1.0170279701835734335…).
    assert_close(
        Function::Griewank.eval(&[1.0, 2.0, 3.0]),
        1.017_027_970_183_573_4,
        1e-15,
        "(1, 2, 3)",
    );
    // 1 + 12500/4000 − cos 100 cos(−50/√2) (mpmath: 4.7271305211515814565…).
    assert_close(
        Function::Griewank.eval(&[100.0, -50.0]),
        4.727_130_521_151_581,
        1e-15,
        "(100, −50)",
    );
}

#[test]
fn six_hump_camel_values() {
    assert_eq!(Function::SixHumpCamel.eval(&[0.0, 0.0]), 0.0);
    // 4 − 2.1 + 1/3 + 1 − 4 + 4 = 97/30.
    assert_close(
        Function::SixHumpCamel.eval(&[1.0, 1.0]),
        97.0 / 30.0,
        1e-15,
        "(1, 1)",
    );
    // 4 − 2.1 + 1/3 − 2 − 16 + 64 = 48.2333…
    assert_close(
        Function::SixHumpCamel.eval(&[-1.0, 2.0]),
        48.233_333_333_333_333,
        1e-15,
        "(−1, 2)",
    );
    // 1 − 0.13125 + 0.015625/3 − 0.125 − 0.25 + 0.015625 = 0.5145833…
    assert_close(
        Function::SixHumpCamel.eval(&[0.5, -0.25]),
        0.514_583_333_333_333_3,
        1e-15,
        "(½, −¼)",
    );
}

#[test]
#[should_panic(expected = "six_hump_camel takes exactly 2 variables, got 3")]
fn six_hump_camel_rejects_other_lengths() {
    Function::SixHumpCamel.eval(&[0.0, 0.0, 0.0]);
}

#[test]
fn names_round_trip_and_are_distinct() {
    for f in Function::ALL {
        assert_eq!(Function::from_name(f.name()), Some(f));
        assert_eq!(f.to_string(), f.name());
        assert!(!f.title().is_empty());
    }
    let mut names: Vec<&str> = Function::ALL.iter().map(|f| f.name()).collect();
    let mut titles: Vec<&str> = Function::ALL.iter().map(|f| f.title()).collect();
    names.sort_unstable();
    names.dedup();
    titles.sort_unstable();
    titles.dedup();
    assert_eq!(names.len(), 10);
    assert_eq!(titles.len(), 10);
    assert_eq!(Function::Schwefel222.title(), "Schwefel 2.22");
    assert_eq!(Function::Schwefel12.name(), "schwefel_1_2");
}

#[test]
fn unknown_names_are_rejected() {
    for name in [
        "",
        "Sphere",
        "SPHERE",
        "sphere ",
        "schwefel",
        "schwefel_2_21",
        "six-hump-camel",
        "camel",
    ] {
        assert_eq!(Function::from_name(name), None, "{name:?}");
    }
}

#[test]
fn scalability() {
    for f in Function::ALL {
        assert_eq!(f.is_scalable(), f != Function::SixHumpCamel, "{f}");
        assert_eq!(f.fixed_dim().is_none(), f.is_scalable(), "{f}");
    }
    assert_eq!(Function::SixHumpCamel.fixed_dim(), Some(2));
    assert_eq!(Function::SixHumpCamel.optimum_location(30).len(), 2);
}

#[test]
fn test_problem_errors_have_exact_messages() {
    let e = TestProblem::new(Function::SixHumpCamel, 30).unwrap_err();
    assert_eq!(
        e,
        FunctionError::WrongDimension {
            function: Function::SixHumpCamel,
            required: 2,
            requested: 30
        }
    );
    assert_eq!(
        e.to_string(),
        "six_hump_camel is defined only for dimension 2, not 30"
    );
    assert_eq!(
        TestProblem::new(Function::SixHumpCamel, 0)
            .unwrap_err()
            .to_string(),
        "six_hump_camel is defined only for dimension 2, not 0"
    );
    let e = TestProblem::new(Function::Sphere, 0).unwrap_err();
    assert_eq!(
        e,
        FunctionError::ZeroDimension {
            function: Function::Sphere
        }
    );
    assert_eq!(
        e.to_string(),
        "sphere is defined only for dimension 1 or more, not 0"
    );
    assert_eq!(
        TestProblem::new(Function::Schwefel226, 0)
            .unwrap_err()
            .to_string(),
        "schwefel_2_26 is defined only for dimension 1 or more, not 0"
    );
    // Usable as a boxed std error.
    let boxed: Box<dyn std::error::Error> = Box::new(e);
    assert!(boxed.to_string().starts_with("sphere "));
}

#[test]
fn test_problem_implements_problem() {
    for f in Function::ALL {
        let d = f.fixed_dim().unwrap_or(30);
        let p = TestProblem::new(f, d).unwrap();
        assert_eq!(p.function(), f);
        assert_eq!(p.dim(), d);
        assert_eq!(p.key(), format!("{}-{d}", f.name()));
        assert_eq!(p.bounds().len(), d);
        assert!(p.bounds().iter().all(|&b| b == f.domain()));
        let x: Vec<f64> = p
            .bounds()
            .iter()
            .enumerate()
            .map(|(i, b)| b.lerp((i as f64 * 0.618).fract()))
            .collect();
        assert_eq!(p.objective(&x).to_bits(), f.eval(&x).to_bits(), "{f}");
    }
    assert_eq!(
        TestProblem::new(Function::Sphere, 30).unwrap().key(),
        "sphere-30"
    );
    assert_eq!(
        TestProblem::new(Function::SixHumpCamel, 2).unwrap().key(),
        "six_hump_camel-2"
    );
    assert!(TestProblem::new(Function::Rosenbrock, 1).is_ok());
}
