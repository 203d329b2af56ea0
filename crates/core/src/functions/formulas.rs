//! The evaluations of the ten functions of Yao, Liu & Lin (1999). Each is
//! one left-to-right fold over the slice: no allocation, no indexing (hence
//! no bounds checks), no reassociation.
//!
//! # Gradual underflow
//!
//! The formulas keep IEEE gradual underflow: a square or a running product
//! that falls below 2⁻¹⁰²² is formed as a subnormal number, which costs x86
//! cores a microcode assist (Sphere-30 at points of magnitude 10⁻¹⁶⁰
//! evaluates about 4× slower than at magnitude 1). Flushing such terms in
//! the formulas was measured and rejected: a mask on every term of Sphere
//! cost about half again its time at ordinary points, and a flush in
//! Schwefel 2.22's product chain lengthens its loop-carried dependency
//! several-fold, to save time only where the values are below 10⁻²⁹².
//! Optimisers that converge onto 0 keep their points out of that range
//! instead (PSO's position floor).

use std::f64::consts::{E, TAU};

use super::SCHWEFEL_226_OFFSET;

#[inline]
pub(super) fn sphere(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |s, &v| s + v * v)
}

#[inline]
pub(super) fn schwefel_2_22(x: &[f64]) -> f64 {
    let (sum, prod) = x.iter().fold((0.0, 1.0), |(s, p), &v| {
        let a = v.abs();
        (s + a, p * a)
    });
    sum + prod
}

#[inline]
pub(super) fn rosenbrock(x: &[f64]) -> f64 {
    let Some((_, next)) = x.split_first() else {
        return 0.0;
    };
    x.iter().zip(next).fold(0.0, |s, (&a, &b)| {
        let t = b - a * a;
        let u = a - 1.0;
        s + (100.0 * t * t + u * u)
    })
}

/// `⌊x + ½⌋` without rounding the sum: `(x + 0.5).floor()` gives 1 at
/// `x = 0.49999999999999994` because `x + 0.5` rounds up to 1.0. Here
/// `x − ⌊x⌋` is exact for every finite `x`, so the comparison is exact.
#[inline]
pub(super) fn floor_half_up(x: f64) -> f64 {
    let r = x.floor();
    if x - r >= 0.5 {
        r + 1.0
    } else {
        r
    }
}

#[inline]
pub(super) fn step(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |s, &v| {
        let r = floor_half_up(v);
        s + r * r
    })
}

#[inline]
pub(super) fn schwefel_1_2(x: &[f64]) -> f64 {
    // The running prefix sum is bit-identical to recomputing Σ_{j≤i} x_j left
    // to right for each i, in O(D) instead of O(D²).
    let (sum, _) = x.iter().fold((0.0, 0.0), |(s, prefix), &v| {
        let p = prefix + v;
        (s + p * p, p)
    });
    sum
}

#[inline]
pub(super) fn schwefel_2_26(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |s, &v| {
        s + (SCHWEFEL_226_OFFSET - v * v.abs().sqrt().sin())
    })
}

#[inline]
pub(super) fn rastrigin(x: &[f64]) -> f64 {
    x.iter()
        .fold(0.0, |s, &v| s + (v * v + 10.0 * (1.0 - (TAU * v).cos())))
}

#[inline]
pub(super) fn ackley(x: &[f64]) -> f64 {
    let (sq, cs) = x.iter().fold((0.0, 0.0), |(sq, cs), &v| {
        (sq + v * v, cs + (TAU * v).cos())
    });
    let n = x.len() as f64;
    20.0 * (1.0 - (-0.2 * (sq / n).sqrt()).exp()) + (E - (cs / n).exp())
}

#[inline]
pub(super) fn griewank(x: &[f64]) -> f64 {
    let (sq, prod) = x.iter().enumerate().fold((0.0, 1.0), |(sq, p), (i, &v)| {
        (sq + v * v, p * (v / ((i + 1) as f64).sqrt()).cos())
    });
    sq / 4000.0 + (1.0 - prod)
}

#[inline]
pub(super) fn six_hump_camel(x: &[f64]) -> f64 {
    let &[a, b] = x else {
        panic!("six_hump_camel takes exactly 2 variables, got {}", x.len());
    };
    let a2 = a * a;
    let b2 = b * b;
    4.0 * a2 - 2.1 * a2 * a2 + a2 * a2 * a2 / 3.0 + a * b - 4.0 * b2 + 4.0 * b2 * b2
}
