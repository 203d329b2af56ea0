//! The joint chain (`Chain::Joint`): every segment of a piecewise fit solved
//! at once with shared joins. On data no curve family holds (a wobbly
//! contour with deterministic noise) it never loses to the sequential chain
//! it starts from, keeps every join to rounding, closes a closed contour
//! smoothly, and refuses what it cannot impose.

use metabezier::fit::{
    fit_adaptive, fit_segment_count, Chain, Closing, ErrorMeasure, FitError, FitOptions,
    FunctionType, LmSolver, PiecewiseFit, SplitOptions,
};
use metabezier::geometry::{Continuity, Point};

/// A wobbly contour of `n` points with ±0.3 of deterministic noise: closed
/// all round, or open over 70 % of the turn.
fn blob(n: usize, closed: bool) -> Vec<Point> {
    let turn = if closed { std::f64::consts::TAU } else { 4.4 };
    (0..n)
        .map(|k| {
            let a = turn * k as f64 / n as f64;
            let r = 80.0 + 9.0 * (3.0 * a).sin() + 4.0 * (5.0 * a + 1.0).cos();
            let noise = 0.3 * ((k as f64 * 12.9898).sin() * 43_758.545).fract();
            Point::new((r + noise) * a.cos(), 0.6 * (r - noise) * a.sin())
        })
        .collect()
}

fn fit(points: &[Point], closed: bool, options: &FitOptions, chain: Chain) -> PiecewiseFit {
    let mut o = *options;
    o.chain = chain;
    fit_segment_count(points, closed, &[], 7, &o, &mut LmSolver::default()).unwrap()
}

#[test]
fn the_joint_chain_never_loses_and_keeps_every_join() {
    let cases = [
        (FunctionType::RationalCubic, Continuity::G1),
        (FunctionType::RationalCubic, Continuity::C1),
        (FunctionType::Cubic, Continuity::G1),
        (FunctionType::Cubic, Continuity::C1),
        (FunctionType::RationalQuadratic, Continuity::G1),
        (FunctionType::Quadratic, Continuity::G1),
    ];
    let mut gains = Vec::new();
    let mut rejected = Vec::new();
    for closed in [true, false] {
        let points = blob(240, closed);
        for (function, continuity) in cases {
            for error in [ErrorMeasure::Fixed, ErrorMeasure::Orthogonal] {
                let mut options = FitOptions::new(function, continuity);
                options.error = error;
                options.closing = Closing::Smooth;
                let label = format!("{function} {continuity:?} {error:?} closed {closed}");
                let seq = fit(&points, closed, &options, Chain::Sequential);
                let joint = fit(&points, closed, &options, Chain::Joint);
                assert_eq!(seq.chain, Chain::Sequential);
                if let Some(strayed) = joint.joint_rejected {
                    // The joint solve left the outline further than the
                    // sequential chain: the sequential chain is kept.
                    assert_eq!(joint.chain, Chain::Sequential, "{label}");
                    assert_eq!(joint.segments, seq.segments, "{label}");
                    assert!(strayed > seq.metrics.excess, "{label}: {strayed}");
                    rejected.push(label);
                    continue;
                }
                assert_eq!(joint.chain, Chain::Joint, "{label}");
                assert_eq!(joint.breaks(), seq.breaks(), "{label}");
                assert!(
                    joint.metrics.sse <= seq.metrics.sse * (1.0 + 1e-12),
                    "{label}: {} > {}",
                    joint.metrics.sse,
                    seq.metrics.sse
                );
                assert!(joint.joins_hold(1e-9), "{label}");
                assert!(joint.chain_evaluations > 0);
                assert_eq!(
                    joint.metrics.evaluations,
                    seq.metrics.evaluations + joint.chain_evaluations,
                    "{label}"
                );
                if let (Some(s), Some(j)) = (seq.closing, joint.closing) {
                    assert_eq!(s.imposed, j.imposed, "{label}");
                    if j.imposed == Continuity::G1 {
                        assert!(j.angle_degrees < 1e-6, "{label}: {j:?}");
                    }
                    if j.imposed == Continuity::C1 {
                        assert!(j.relative_derivative_gap < 1e-9, "{label}: {j:?}");
                    }
                }
                gains.push((label, joint.metrics.sse / seq.metrics.sse));
            }
        }
    }
    // The joint solve is kept almost everywhere.
    assert!(rejected.len() <= 2, "{rejected:?}");
    // Not a formality: solving the joins together lowers E, by at least 5 %
    // in most cases.
    let better = gains.iter().filter(|(_, g)| *g < 0.95).count();
    assert!(better * 4 >= gains.len() * 3, "{gains:?}");
}

#[test]
fn quadratics_joined_c1_are_refused_by_the_joint_chain() {
    let points = blob(120, true);
    let mut options = FitOptions::new(FunctionType::Quadratic, Continuity::C1);
    options.chain = Chain::Joint;
    let e =
        fit_segment_count(&points, true, &[], 5, &options, &mut LmSolver::default()).unwrap_err();
    assert_eq!(e, FitError::JointQuadraticC1);
    assert!(e.to_string().contains("chain \"sequential\""), "{e}");
}

#[test]
fn an_adaptive_fit_keeps_its_tolerance_with_the_joint_chain() {
    let points = blob(240, true);
    let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::G1);
    options.error = ErrorMeasure::Orthogonal;
    options.closing = Closing::Smooth;
    for tolerance in [0.5, 1.0, 2.0] {
        let split = SplitOptions::new(tolerance);
        let mut o = options;
        o.chain = Chain::Joint;
        let joint = fit_adaptive(&points, true, &[], &split, &o, &mut LmSolver::default()).unwrap();
        let seq = fit_adaptive(
            &points,
            true,
            &[],
            &split,
            &options,
            &mut LmSolver::default(),
        )
        .unwrap();
        assert_eq!(joint.breaks(), seq.breaks());
        if seq.metrics.max_distance <= tolerance {
            assert!(joint.metrics.max_distance <= tolerance, "{tolerance}");
        }
        assert!(joint.metrics.sse <= seq.metrics.sse * (1.0 + 1e-12));
    }
}
