//! The segment problem's tests: dimensions, objective, Jacobian, joins.

use super::*;
use crate::geometry::{Continuity, CubicBez, QuadBez, RationalCubicBez};
use crate::optim::lm::LeastSquares;

fn sample<C: Curve>(c: &C, n: usize) -> (Vec<Point>, Vec<f64>) {
    let params: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
    (params.iter().map(|&s| c.eval(s)).collect(), params)
}

fn starts() -> [Start; 3] {
    [
        Start::Free,
        Start::C1 {
            derivative: Point::new(3.0, 1.0),
        },
        Start::G1 {
            leg: Point::new(1.0, 0.5),
        },
    ]
}

#[test]
fn dimensions_follow_the_joins() {
    let c = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (pts, ps) = sample(&c, 20);
    let o = SearchSpaceOptions::default();
    let expect = [[2, 0, 1], [4, 2, 3], [3, 1, 2], [6, 4, 5]];
    for (f, dims) in FunctionType::ALL.iter().zip(expect) {
        let continuities = [Continuity::C0, Continuity::C1, Continuity::G1];
        for ((start, d), continuity) in starts().into_iter().zip(dims).zip(continuities) {
            let p = SegmentProblem::new(*f, pts.clone(), ps.clone(), start, &o).unwrap();
            assert_eq!(p.dim(), d, "{f} {start:?}");
            // What a segment adds to a chain is the dimension of a
            // segment whose start is joined.
            assert_eq!(f.chain_dim(continuity), d, "{f} {continuity:?}");
            assert_eq!(p.bounds().len(), d);
            assert_eq!(p.variable_names().len(), d);
            assert!(p.variable_names().iter().all(|n| !n.is_empty()));
            assert!(p
                .guess()
                .iter()
                .zip(p.bounds())
                .all(|(&g, b)| b.contains(g)));
        }
    }
}

#[test]
fn objective_matches_the_geometry_and_residuals() {
    let c = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (mut pts, ps) = sample(&c, 30);
    for (i, p) in pts.iter_mut().enumerate().skip(1) {
        p.y += 0.01 * ((i * 7 % 5) as f64 - 2.0);
    }
    let o = SearchSpaceOptions::default();
    for f in FunctionType::ALL {
        for start in starts() {
            let p = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o).unwrap();
            let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.37)).collect();
            let seg = p.segment(&x);
            let e = p.objective(&x);
            let e_geom = seg.sse(&pts, &ps);
            assert!(
                (e - e_geom).abs() <= 1e-12 * e_geom.max(1.0),
                "{f} {start:?}"
            );
            let mut r = vec![0.0; p.residual_count()];
            p.residuals(&x, &mut r);
            let e_r: f64 = r.iter().map(|v| v * v).sum();
            assert!((e - e_r).abs() <= 1e-12 * e.max(1.0));
            assert_eq!(seg.start(), pts[0]);
            assert_eq!(seg.end(), pts[30]);
        }
    }
}

/// Checks the analytic Jacobian of `p` against central differences
/// (step 10⁻⁶) at a point inside its box; `what` names the case.
fn assert_jacobian(p: &SegmentProblem, what: &str) {
    let (d, m) = (p.dim(), p.residual_count());
    let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.41)).collect();
    let mut jac = vec![0.0; m * d];
    p.jacobian(&x, &mut jac);
    let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
    let h = 1e-6;
    for j in 0..d {
        let mut xp = x.clone();
        xp[j] += h;
        p.residuals(&xp, &mut rp);
        xp[j] -= 2.0 * h;
        p.residuals(&xp, &mut rm);
        for k in 0..m {
            let fd = (rp[k] - rm[k]) / (2.0 * h);
            let an = jac[k * d + j];
            assert!(
                (fd - an).abs() < 1e-6 * (1.0 + fd.abs()),
                "{what} var {j} row {k}: fd {fd} an {an}"
            );
        }
    }
}

#[test]
fn analytic_jacobian_matches_finite_differences() {
    let c = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (pts, ps) = sample(&c, 12);
    let o = SearchSpaceOptions::default();
    for f in FunctionType::ALL {
        for start in starts() {
            let p = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o).unwrap();
            assert_jacobian(&p, &format!("{f} {start:?}"));
        }
    }
}

#[test]
fn joins_are_built_in() {
    let prev = RationalCubicBez::new(
        Point::new(-4.0, 1.0),
        Point::new(-3.0, 2.0),
        Point::new(-1.0, -1.0),
        Point::ZERO,
        0.7,
        1.8,
    )
    .unwrap();
    let next = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (pts, ps) = sample(&next, 20);
    let o = SearchSpaceOptions::default();
    for f in FunctionType::ALL {
        for cont in [Continuity::C1, Continuity::G1] {
            let p = SegmentProblem::new(f, pts.clone(), ps.clone(), Start::after(&prev, cont), &o)
                .unwrap();
            let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.8)).collect();
            let seg = p.segment(&x);
            assert!(
                crate::geometry::check_join(&prev, &seg, cont, 1e-12),
                "{f} {cont:?}"
            );
        }
    }
}

#[test]
fn errors_are_explained() {
    let o = SearchSpaceOptions::default();
    let pts = vec![
        Point::ZERO,
        Point::new(1.0, 1.0),
        Point::new(2.0, 0.0),
        Point::new(3.0, 0.0),
    ];
    let e = SegmentProblem::with_parameterisation(
        FunctionType::RationalCubic,
        pts.clone(),
        Parameterisation::ChordLength,
        Start::Free,
        &o,
    )
    .unwrap_err();
    assert!(matches!(
        e,
        FitError::TooFewPoints {
            found: 4,
            needed: 5,
            ..
        }
    ));
    let msg = e.to_string();
    assert!(
        msg.contains("4 data point") && msg.contains("at least 5"),
        "{msg}"
    );
    let bad = SearchSpaceOptions {
        weight_range: (-1.0, 1.0),
        ..o
    };
    let e = SegmentProblem::with_parameterisation(
        FunctionType::Cubic,
        pts,
        Parameterisation::ChordLength,
        Start::Free,
        &bad,
    )
    .unwrap_err();
    assert!(e.to_string().contains("strictly positive"), "{e}");
}

/// Every function with a start join and an end join (where allowed):
/// the joins hold to 1e-9 at both ends for arbitrary decision vectors,
/// the analytic Jacobian matches finite differences, and LM recovers a
/// curve that satisfies both joins exactly.
#[test]
fn end_joins_are_built_in() {
    let prev = RationalCubicBez::new(
        Point::new(-4.0, 1.0),
        Point::new(-3.0, 2.0),
        Point::new(-1.0, -1.0),
        Point::ZERO,
        0.7,
        1.8,
    )
    .unwrap();
    let next = RationalCubicBez::new(
        Point::new(4.0, 0.0),
        Point::new(5.0, -2.0),
        Point::new(7.0, 1.0),
        Point::new(9.0, 0.5),
        1.3,
        0.6,
    )
    .unwrap();
    let mid = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (pts, ps) = sample(&mid, 20);
    let o = SearchSpaceOptions::default();
    let ends = [
        (
            Continuity::C1,
            End::C1 {
                derivative: next.deriv(0.0),
            },
        ),
        (
            Continuity::G1,
            End::G1 {
                dir: next.deriv(0.0) * 0.1,
            },
        ),
    ];
    for f in FunctionType::ALL {
        for start_cont in [Continuity::C0, Continuity::C1, Continuity::G1] {
            for (end_cont, end) in ends {
                let start = Start::after(&prev, start_cont);
                let built = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o)
                    .unwrap()
                    .with_end(end);
                let both_g1 = start_cont == Continuity::G1 && end_cont == Continuity::G1;
                if f.degree() == 2 && start != Start::Free && !both_g1 {
                    let e = built.unwrap_err();
                    assert!(e.to_string().contains("free start"), "{e}");
                    continue;
                }
                let p = match built {
                    Ok(p) => p,
                    Err(e) => {
                        // G¹ at both ends of a quadratic: only when the
                        // tangent lines meet in front of both ends.
                        assert!(f.degree() == 2 && both_g1, "{f}: {e}");
                        assert!(e.to_string().contains("meet in front"), "{e}");
                        continue;
                    }
                };
                assert_eq!(p.end(), end);
                assert_eq!(p.variable_names().len(), p.dim());
                assert!(p.variable_names().iter().all(|n| !n.is_empty()));
                for frac in [0.2, 0.8] {
                    let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(frac)).collect();
                    let seg = p.segment(&x);
                    assert_eq!(seg.start(), pts[0]);
                    assert_eq!(seg.end(), pts[20]);
                    assert!(
                        crate::geometry::check_join(&seg, &next, end_cont, 1e-9),
                        "end {f} {start_cont:?} {end_cont:?}: {:?} vs {:?}",
                        seg.deriv(1.0),
                        next.deriv(0.0)
                    );
                    if start_cont != Continuity::C0 {
                        assert!(
                            crate::geometry::check_join(&prev, &seg, start_cont, 1e-9),
                            "start {f} {start_cont:?} {end_cont:?}"
                        );
                    }
                }
                // Jacobian against central differences.
                assert_jacobian(&p, &format!("{f} {start_cont:?} {end_cont:?}"));
            }
        }
    }
}

#[test]
fn a_quadratic_joined_g1_at_both_ends_meets_its_tangent_lines() {
    // The quadratic (0,0)-(1,1)-(2,0): start tangent (1,1), end tangent (1,−1).
    let q = QuadBez::new(Point::ZERO, Point::new(1.0, 1.0), Point::new(2.0, 0.0));
    let (pts, ps) = sample(&q, 10);
    assert_eq!(
        tangent_meet(
            Point::ZERO,
            Point::new(0.5, 0.5),
            Point::new(2.0, 0.0),
            Point::new(3.0, -3.0)
        ),
        Some(Point::new(1.0, 1.0))
    );
    // Behind an end, or parallel: no meeting point.
    assert_eq!(
        tangent_meet(
            Point::ZERO,
            Point::new(-1.0, -1.0),
            Point::new(2.0, 0.0),
            Point::new(1.0, -1.0)
        ),
        None
    );
    assert_eq!(
        tangent_meet(
            Point::ZERO,
            Point::new(1.0, 0.0),
            Point::new(2.0, 1.0),
            Point::new(1.0, 0.0)
        ),
        None
    );
    let o = SearchSpaceOptions::default();
    for (f, dim) in [
        (FunctionType::Quadratic, 0),
        (FunctionType::RationalQuadratic, 1),
    ] {
        let p = SegmentProblem::new(
            f,
            pts.clone(),
            ps.clone(),
            Start::G1 {
                leg: Point::new(2.0, 2.0),
            },
            &o,
        )
        .unwrap()
        .with_end(End::G1 {
            dir: Point::new(1.0, -1.0),
        })
        .unwrap();
        assert_eq!(p.dim(), dim, "{f}");
        let x = vec![1.0; dim];
        assert!(p.objective(&x) < 1e-24, "{f}");
    }
}

#[test]
fn end_g1_dimensions_and_exact_recovery() {
    // A cubic whose end leg points along (1, −2): with End::G1 along that
    // direction (C₂ = C₃ − T·dir, T = 1) LM recovers it exactly.
    let c = CubicBez::new(
        Point::ZERO,
        Point::new(1.0, 2.0),
        Point::new(3.0, 2.0),
        Point::new(4.0, 0.0),
    );
    let (pts, ps) = sample(&c, 30);
    let o = SearchSpaceOptions::default();
    let expect = [1, 3, 2, 5];
    for (f, dim) in FunctionType::ALL.into_iter().zip(expect) {
        let p = SegmentProblem::new(f, pts.clone(), ps.clone(), Start::Free, &o)
            .unwrap()
            .with_end(End::G1 {
                dir: Point::new(1.0, -2.0),
            })
            .unwrap();
        assert_eq!(p.dim(), dim, "{f}");
    }
    let p = SegmentProblem::new(FunctionType::Cubic, pts, ps, Start::Free, &o)
        .unwrap()
        .with_end(End::G1 {
            dir: Point::new(1.0, -2.0),
        })
        .unwrap();
    let x = crate::fit::linear_fit(&p);
    assert!(p.objective(&x) < 1e-20, "{x:?}");
    let seg = p.segment(&x);
    assert!((seg.control_points()[2] - Point::new(3.0, 2.0)).hypot() < 1e-9);
    let e = SegmentProblem::new(
        FunctionType::Cubic,
        p.points().to_vec(),
        p.params().to_vec(),
        Start::Free,
        &o,
    )
    .unwrap()
    .with_end(End::G1 { dir: Point::ZERO })
    .unwrap_err();
    assert!(e.to_string().contains("non-zero end tangent"), "{e}");
}
