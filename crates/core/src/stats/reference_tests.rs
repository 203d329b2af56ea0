//! Reference values computed with SciPy 1.17.1 and statsmodels 0.15.0 (NumPy
//! 2.4.6, Python 3.11). Each expected number is a literal copied from the call
//! named in the comment above it. Tolerances: statistics and exact p-values
//! 1e-9, normal-approximation and chi-square p-values 1e-6 (most agree to ~1e-15).

use super::*;

const EXACT: f64 = 1e-9;
const APPROX: f64 = 1e-6;

#[track_caller]
fn close(actual: f64, expected: f64, tol: f64) {
    assert!(
        (actual - expected).abs() <= tol,
        "actual {actual:e} vs expected {expected:e} (tol {tol:e})"
    );
}

const TS: Alternative = Alternative::TwoSided;
const LESS: Alternative = Alternative::Less;
const GREATER: Alternative = Alternative::Greater;

// ---------------------------------------------------------------- Wilcoxon

const W1X: [f64; 9] = [1.83, 0.50, 1.62, 2.48, 1.68, 1.88, 1.55, 3.06, 1.30];
#[allow(clippy::approx_constant)] // 3.14 is a data value, not π
const W1Y: [f64; 9] = [0.878, 0.647, 0.598, 2.05, 1.06, 1.29, 1.06, 3.14, 1.29];

#[test]
fn wilcoxon_small_exact_all_alternatives() {
    // scipy 1.17.1: scipy.stats.wilcoxon(W1X, W1Y) -> statistic=5.0, pvalue=0.0390625
    let r = wilcoxon(&W1X, &W1Y, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Exact);
    assert_eq!((r.n, r.n_zero), (9, 0));
    close(r.statistic, 5.0, EXACT);
    close(r.p_value, 0.0390625, EXACT);
    close(r.r_plus, 40.0, EXACT);
    close(r.r_minus, 5.0, EXACT);
    assert_eq!(r.z, None);
    // scipy 1.17.1: scipy.stats.wilcoxon(W1X, W1Y, alternative="less")
    //   -> statistic=40.0, pvalue=0.986328125
    let r = wilcoxon(&W1X, &W1Y, LESS).unwrap();
    close(r.statistic, 40.0, EXACT);
    close(r.p_value, 0.986328125, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon(W1X, W1Y, alternative="greater")
    //   -> statistic=40.0, pvalue=0.01953125
    let r = wilcoxon(&W1X, &W1Y, GREATER).unwrap();
    close(r.statistic, 40.0, EXACT);
    close(r.p_value, 0.01953125, EXACT);
}

#[test]
fn wilcoxon_ties_small_sample_uses_permutation() {
    let d = [1.5, -2.0, 2.0, 3.5, -1.5, 4.0, 4.0, 5.0, -0.5, 6.0];
    // scipy 1.17.1: scipy.stats.wilcoxon(d) -> statistic=8.0, pvalue=0.046875
    let r = wilcoxon_signed_rank(&d, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Permutation);
    close(r.statistic, 8.0, EXACT);
    close(r.p_value, 0.046875, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon(d, alternative="less") -> statistic=47.0, pvalue=0.98046875
    let r = wilcoxon_signed_rank(&d, LESS).unwrap();
    close(r.statistic, 47.0, EXACT);
    close(r.p_value, 0.98046875, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon(d, alternative="greater") -> statistic=47.0, pvalue=0.0234375
    let r = wilcoxon_signed_rank(&d, GREATER).unwrap();
    close(r.statistic, 47.0, EXACT);
    close(r.p_value, 0.0234375, EXACT);
}

#[test]
fn wilcoxon_zero_differences_are_dropped() {
    let d = [0.0, 1.2, -0.4, 2.3, 0.0, 3.1, 1.7, -0.9, 2.8];
    // scipy 1.17.1: scipy.stats.wilcoxon(d) -> statistic=3.0, pvalue=0.078125
    let r = wilcoxon_signed_rank(&d, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Permutation);
    assert_eq!((r.n, r.n_zero), (7, 2));
    close(r.statistic, 3.0, EXACT);
    close(r.p_value, 0.078125, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon(d, alternative="less") -> statistic=25.0, pvalue=0.9765625
    let r = wilcoxon_signed_rank(&d, LESS).unwrap();
    close(r.statistic, 25.0, EXACT);
    close(r.p_value, 0.9765625, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon(d, alternative="greater") -> statistic=25.0, pvalue=0.0390625
    let r = wilcoxon_signed_rank(&d, GREATER).unwrap();
    close(r.statistic, 25.0, EXACT);
    close(r.p_value, 0.0390625, EXACT);
}

/// d_i = ((i·7) mod 11) − 3 for i = 1..=n: ties and zeros.
fn tied_with_zeros(n: usize) -> Vec<f64> {
    (1..=n).map(|i| ((i * 7) % 11) as f64 - 3.0).collect()
}

#[test]
fn wilcoxon_ties_boundary_13_permutation_14_asymptotic() {
    let d13 = tied_with_zeros(13);
    assert_eq!(d13, [4., 0., 7., 3., -1., 6., 2., -2., 5., 1., -3., 4., 0.]);
    // scipy 1.17.1: scipy.stats.wilcoxon([4,0,7,3,-1,6,2,-2,5,1,-3,4,0])
    //   -> statistic=10.5, pvalue=0.046875
    let r = wilcoxon_signed_rank(&d13, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Permutation);
    close(r.statistic, 10.5, EXACT);
    close(r.p_value, 0.046875, EXACT);
    // scipy 1.17.1: same, alternative="greater" -> statistic=55.5, pvalue=0.0234375
    let r = wilcoxon_signed_rank(&d13, GREATER).unwrap();
    close(r.statistic, 55.5, EXACT);
    close(r.p_value, 0.0234375, EXACT);

    let d14 = tied_with_zeros(14);
    assert_eq!(d14[13], 7.0);
    // scipy 1.17.1: scipy.stats.wilcoxon([4,0,7,3,-1,6,2,-2,5,1,-3,4,0,7])
    //   -> statistic=10.5, pvalue=0.02508859544148754
    let r = wilcoxon_signed_rank(&d14, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Asymptotic);
    close(r.statistic, 10.5, EXACT);
    close(r.p_value, 0.02508859544148754, APPROX);
    // scipy 1.17.1: same, alternative="greater" -> statistic=67.5, pvalue=0.01254429772074377
    let r = wilcoxon_signed_rank(&d14, GREATER).unwrap();
    close(r.statistic, 67.5, EXACT);
    close(r.p_value, 0.01254429772074377, APPROX);
}

/// d_i = ±(i+1), negative when i mod 3 = 0, i = 0..n: no ties, no zeros.
fn untied(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| (i + 1) as f64 * if i % 3 == 0 { -1.0 } else { 1.0 })
        .collect()
}

#[test]
fn wilcoxon_no_ties_boundary_50_exact_51_asymptotic() {
    let d50 = untied(50);
    // scipy 1.17.1: scipy.stats.wilcoxon(d50) -> statistic=425.0, pvalue=0.03996834652842374
    // (method="asymptotic" would give 0.0402356268160887 instead)
    let r = wilcoxon_signed_rank(&d50, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Exact);
    close(r.statistic, 425.0, EXACT);
    close(r.p_value, 0.03996834652842374, EXACT);
    // scipy 1.17.1: alternative="less" -> statistic=850.0, pvalue=0.9804922372390692
    let r = wilcoxon_signed_rank(&d50, LESS).unwrap();
    close(r.statistic, 850.0, EXACT);
    close(r.p_value, 0.9804922372390692, EXACT);
    // scipy 1.17.1: alternative="greater" -> statistic=850.0, pvalue=0.01998417326421187
    let r = wilcoxon_signed_rank(&d50, GREATER).unwrap();
    close(r.p_value, 0.01998417326421187, EXACT);

    let d51 = untied(51);
    // scipy 1.17.1: scipy.stats.wilcoxon(d51) -> statistic=425.0, pvalue=0.02568873999366418
    let r = wilcoxon_signed_rank(&d51, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Asymptotic);
    close(r.statistic, 425.0, EXACT);
    close(r.p_value, 0.02568873999366418, APPROX);
    // scipy 1.17.1: alternative="less" -> statistic=901.0, pvalue=0.9871556300031679
    let r = wilcoxon_signed_rank(&d51, LESS).unwrap();
    close(r.statistic, 901.0, EXACT);
    close(r.p_value, 0.9871556300031679, APPROX);
    // scipy 1.17.1: alternative="greater" -> statistic=901.0, pvalue=0.01284436999683209
    let r = wilcoxon_signed_rank(&d51, GREATER).unwrap();
    close(r.p_value, 0.01284436999683209, APPROX);
}

#[test]
fn wilcoxon_asymptotic_with_zeros_and_ties_and_continuity() {
    let d = tied_with_zeros(20);
    // scipy 1.17.1: scipy.stats.wilcoxon(d20) -> statistic=24.0, pvalue=0.0072451916673987905
    let r = wilcoxon_signed_rank(&d, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Asymptotic);
    close(r.statistic, 24.0, EXACT);
    close(r.p_value, 0.0072451916673987905, APPROX);
    // scipy 1.17.1: scipy.stats.wilcoxon(d20, correction=True)
    //   -> statistic=24.0, pvalue=0.0077326227001271435
    let r = wilcoxon_signed_rank_with(&d, TS, true).unwrap();
    close(r.statistic, 24.0, EXACT);
    close(r.p_value, 0.0077326227001271435, APPROX);
    // scipy 1.17.1: scipy.stats.wilcoxon(d20, correction=True, alternative="greater")
    //   -> statistic=147.0, pvalue=0.0038663113500635718
    let r = wilcoxon_signed_rank_with(&d, GREATER, true).unwrap();
    close(r.statistic, 147.0, EXACT);
    close(r.p_value, 0.0038663113500635718, APPROX);
}

#[test]
fn wilcoxon_large_sample_one_sided() {
    // d_i = ((i·13) mod 17) − 6 for i = 1..=60 (4 zeros, many ties)
    let d: Vec<f64> = (1..=60).map(|i| ((i * 13) % 17) as f64 - 6.0).collect();
    let cases = [
        // scipy 1.17.1: scipy.stats.wilcoxon(d60, alternative=alt[, correction=True])
        (TS, false, 440.0, 0.003449334024204751),
        (TS, true, 440.0, 0.00349487487653006),
        (LESS, false, 1156.0, 0.9982753329878976),
        (LESS, true, 1156.0, 0.9982978330244843),
        (GREATER, false, 1156.0, 0.0017246670121023756),
        (GREATER, true, 1156.0, 0.00174743743826503),
    ];
    for (alt, corr, stat, p) in cases {
        let r = wilcoxon_signed_rank_with(&d, alt, corr).unwrap();
        assert_eq!(r.method, PValueMethod::Asymptotic);
        assert_eq!((r.n, r.n_zero), (56, 4));
        close(r.statistic, stat, EXACT);
        close(r.p_value, p, APPROX);
    }
}

#[test]
fn wilcoxon_degenerate_inputs() {
    // scipy 1.17.1: scipy.stats.wilcoxon([2.5]) -> statistic=0.0, pvalue=1.0
    let r = wilcoxon_signed_rank(&[2.5], TS).unwrap();
    close(r.statistic, 0.0, EXACT);
    close(r.p_value, 1.0, EXACT);
    // scipy 1.17.1: scipy.stats.wilcoxon([0.0, 0.0, 0.0]) -> statistic=0.0, pvalue=1.0
    let r = wilcoxon_signed_rank(&[0.0, 0.0, 0.0], TS).unwrap();
    close(r.statistic, 0.0, EXACT);
    close(r.p_value, 1.0, EXACT);
    assert_eq!((r.n, r.n_zero), (0, 3));
    // scipy 1.17.1: scipy.stats.wilcoxon([1,2,3,4,5], [1,2,3,4,5]) -> statistic=0.0, pvalue=1.0
    let x = [1.0, 2.0, 3.0, 4.0, 5.0];
    let r = wilcoxon(&x, &x, TS).unwrap();
    close(r.p_value, 1.0, EXACT);
    // Beyond SciPy's range (it returns NaN for > 13 all-zero differences): p = 1.
    let r = wilcoxon_signed_rank(&[0.0; 40], LESS).unwrap();
    close(r.p_value, 1.0, EXACT);
    // Errors instead of NaN or panics.
    assert!(matches!(
        wilcoxon_signed_rank(&[], TS),
        Err(StatsError::EmptyInput { .. })
    ));
    assert!(matches!(
        wilcoxon_signed_rank(&[1.0, f64::NAN], TS),
        Err(StatsError::NotANumber { index: 1, .. })
    ));
    assert!(matches!(
        wilcoxon(&[1.0, 2.0], &[1.0], TS),
        Err(StatsError::LengthMismatch { .. })
    ));
    assert!(matches!(
        wilcoxon(&[f64::INFINITY], &[f64::INFINITY], TS),
        Err(StatsError::NotANumber { .. })
    ));
    // Infinite differences are ranked like any other value.
    let r = wilcoxon_signed_rank(&[f64::INFINITY, 1.0, 2.0, -0.5], TS).unwrap();
    close(r.r_plus, 9.0, EXACT);
}

// ------------------------------------------------------------ Mann–Whitney

#[test]
fn mann_whitney_exact_small() {
    let males = [19.0, 22.0, 16.0, 29.0, 24.0];
    let females = [20.0, 11.0, 17.0, 12.0];
    // scipy 1.17.1: scipy.stats.mannwhitneyu(males, females)
    //   -> statistic=17.0, pvalue=0.1111111111111111
    let r = mann_whitney_u(&males, &females, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Exact);
    close(r.statistic, 17.0, EXACT);
    close(r.u2(), 3.0, EXACT);
    close(r.p_value, 0.1111111111111111, EXACT);
    // scipy 1.17.1: scipy.stats.mannwhitneyu(females, males, alternative="less")
    //   -> statistic=3.0, pvalue=0.05555555555555555
    let r = mann_whitney_u(&females, &males, LESS).unwrap();
    close(r.statistic, 3.0, EXACT);
    close(r.p_value, 0.05555555555555555, EXACT);
    // scipy 1.17.1: scipy.stats.mannwhitneyu([1,4,5], [2,3,6]) -> statistic=4.0, pvalue=1.0
    let r = mann_whitney_u(&[1.0, 4.0, 5.0], &[2.0, 3.0, 6.0], TS).unwrap();
    close(r.statistic, 4.0, EXACT);
    close(r.p_value, 1.0, EXACT);
}

const M2X: [f64; 8] = [1.1, 2.3, 0.7, 4.5, 3.3, 2.9, 5.1, 0.2];
const M2Y: [f64; 9] = [3.9, 6.2, 4.8, 5.5, 7.1, 2.5, 6.6, 5.9, 4.1];

#[test]
fn mann_whitney_boundary_8_exact_9_asymptotic() {
    // n1 = 8, n2 = 9, no ties: exact.
    let cases = [
        // scipy 1.17.1: scipy.stats.mannwhitneyu(M2X, M2Y, alternative=alt)
        (TS, 0.007897984368572603),
        (LESS, 0.003948992184286302),
        (GREATER, 0.9972439325380501),
    ];
    for (alt, p) in cases {
        let r = mann_whitney_u(&M2X, &M2Y, alt).unwrap();
        assert_eq!(r.method, PValueMethod::Exact);
        close(r.statistic, 9.0, EXACT);
        close(r.p_value, p, EXACT);
    }
    // n1 = 9 (M2X + [1.9]), n2 = 9, no ties: asymptotic
    // (method="exact" would give 0.0039901275195392836 two-sided).
    let mut m3x = M2X.to_vec();
    m3x.push(1.9);
    let cases = [
        // scipy 1.17.1: scipy.stats.mannwhitneyu(M2X + [1.9], M2Y, alternative=alt)
        (TS, 0.006193318174044277),
        (LESS, 0.0030966590870221385),
        (GREATER, 0.9976409006359425),
    ];
    for (alt, p) in cases {
        let r = mann_whitney_u(&m3x, &M2Y, alt).unwrap();
        assert_eq!(r.method, PValueMethod::Asymptotic);
        close(r.statistic, 9.0, EXACT);
        close(r.p_value, p, APPROX);
    }
}

#[test]
fn mann_whitney_exact_unbalanced() {
    // x = [0.5, 10.25, 20.75], y = [i + 0.1 for i in range(40)]: exact (n1 = 3 ≤ 8).
    let x = [0.5, 10.25, 20.75];
    let y: Vec<f64> = (0..40).map(|i| i as f64 + 0.1).collect();
    let cases = [
        // scipy 1.17.1: scipy.stats.mannwhitneyu(x, y, alternative=alt) -> statistic=33.0
        (TS, 0.2182967344623612),
        (LESS, 0.1091483672311806),
        (GREATER, 0.8996029495178673),
    ];
    for (alt, p) in cases {
        let r = mann_whitney_u(&x, &y, alt).unwrap();
        assert_eq!(r.method, PValueMethod::Exact);
        close(r.statistic, 33.0, EXACT);
        close(r.p_value, p, EXACT);
    }
}

#[test]
fn mann_whitney_ties_asymptotic() {
    let x = [1.0, 2.0, 2.0, 3.0, 4.0];
    let y = [2.0, 3.0, 3.0, 5.0, 6.0, 6.0];
    // scipy 1.17.1: scipy.stats.mannwhitneyu([1,2,2,3,4], [2,3,3,5,6,6])
    //   -> statistic=6.0, pvalue=0.1130499788563229
    let r = mann_whitney_u(&x, &y, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Asymptotic);
    close(r.statistic, 6.0, EXACT);
    close(r.p_value, 0.1130499788563229, APPROX);
    // scipy 1.17.1: same, alternative="greater" -> statistic=6.0, pvalue=0.9617245753150733
    let r = mann_whitney_u(&x, &y, GREATER).unwrap();
    close(r.p_value, 0.9617245753150733, APPROX);

    // x = [i % 7 for i in range(25)], y = [i % 5 + 1 for i in range(30)]
    let x: Vec<f64> = (0..25).map(|i| (i % 7) as f64).collect();
    let y: Vec<f64> = (0..30).map(|i| (i % 5 + 1) as f64).collect();
    let cases = [
        // scipy 1.17.1: scipy.stats.mannwhitneyu(x, y, alternative=alt) -> statistic=342.0
        (TS, 0.577578047541083),
        (LESS, 0.2887890237705415),
        (GREATER, 0.7170371095593819),
    ];
    for (alt, p) in cases {
        let r = mann_whitney_u(&x, &y, alt).unwrap();
        assert_eq!(r.method, PValueMethod::Asymptotic);
        close(r.statistic, 342.0, EXACT);
        close(r.p_value, p, APPROX);
    }
}

#[test]
fn mann_whitney_degenerate_inputs() {
    // scipy 1.17.1: scipy.stats.mannwhitneyu([1.0,1.0,1.0], [1.0,1.0]) -> statistic=3.0, pvalue=1.0
    let r = mann_whitney_u(&[1.0; 3], &[1.0; 2], TS).unwrap();
    close(r.statistic, 3.0, EXACT);
    close(r.p_value, 1.0, EXACT);
    // scipy 1.17.1: scipy.stats.mannwhitneyu([1.0], [2.0]) -> statistic=0.0, pvalue=1.0
    let r = mann_whitney_u(&[1.0], &[2.0], TS).unwrap();
    close(r.statistic, 0.0, EXACT);
    close(r.p_value, 1.0, EXACT);
    assert!(matches!(
        mann_whitney_u(&[], &[1.0], TS),
        Err(StatsError::EmptyInput { .. })
    ));
    assert!(matches!(
        mann_whitney_u(&[1.0], &[f64::NAN], TS),
        Err(StatsError::NotANumber { .. })
    ));
    // A sample far too large for integer counts still gives a valid p-value.
    let big: Vec<f64> = (0..300_000).map(|i| i as f64 + 0.5).collect();
    let r = mann_whitney_u(&[-1.0, 1e9], &big, TS).unwrap();
    assert_eq!(r.method, PValueMethod::Exact);
    close(r.p_value, 1.0, EXACT);
}

// ---------------------------------------------------------------- Friedman

#[test]
fn friedman_without_ties() {
    let rows = [
        [1.2, 2.3, 3.1],
        [0.9, 2.8, 2.2],
        [1.5, 1.1, 3.9],
        [0.7, 2.0, 2.6],
        [1.8, 2.4, 3.3],
        [2.1, 1.7, 3.0],
    ];
    // scipy 1.17.1: scipy.stats.friedmanchisquare(*zip(*rows))
    //   -> statistic=7.0, pvalue=0.0301973834223185;
    // numpy.mean([scipy.stats.rankdata(r) for r in rows], axis=0)
    //   -> [1.3333333333333333, 1.8333333333333333, 2.8333333333333335]
    let r = friedman(&rows).unwrap();
    close(r.statistic, 7.0, EXACT);
    close(r.p_value, 0.0301973834223185, APPROX);
    assert_eq!((r.n_blocks, r.n_treatments, r.df), (6, 3, 2));
    for (a, e) in
        r.average_ranks
            .iter()
            .zip([1.3333333333333333, 1.8333333333333333, 2.8333333333333335])
    {
        close(*a, e, EXACT);
    }
}

#[test]
fn friedman_with_ties() {
    let rows: Vec<Vec<f64>> = vec![
        vec![1., 2., 2., 4.],
        vec![3., 1., 2., 4.],
        vec![1., 1., 1., 2.],
        vec![2., 3., 1., 4.],
        vec![1., 2., 3., 3.],
        vec![4., 2., 2., 1.],
        vec![1., 3., 2., 4.],
        vec![2., 2., 3., 1.],
    ];
    // scipy 1.17.1: scipy.stats.friedmanchisquare(*zip(*rows))
    //   -> statistic=3.75, pvalue=0.28975578119338535; mean ranks [2.0625, 2.3125, 2.4375, 3.1875]
    let r = friedman(&rows).unwrap();
    close(r.statistic, 3.75, EXACT);
    close(r.p_value, 0.28975578119338535, APPROX);
    for (a, e) in r.average_ranks.iter().zip([2.0625, 2.3125, 2.4375, 3.1875]) {
        close(*a, e, EXACT);
    }

    // k = 5, N = 10: rows[i][j] = ((i·j·7 + i + 3j) mod 9) / 2, one row fully tied.
    let rows: Vec<Vec<f64>> = (0..10)
        .map(|i| {
            (0..5)
                .map(|j| ((i * j * 7 + i + 3 * j) % 9) as f64 * 0.5)
                .collect()
        })
        .collect();
    assert_eq!(rows[6], vec![3.0; 5]);
    // scipy 1.17.1: scipy.stats.friedmanchisquare(*zip(*rows))
    //   -> statistic=0.41379310344829157, pvalue=0.981332123919527;
    //   mean ranks [2.95, 3.15, 2.8, 2.95, 3.15]
    let r = friedman(&rows).unwrap();
    close(r.statistic, 0.41379310344829157, EXACT);
    close(r.p_value, 0.981332123919527, APPROX);
    for (a, e) in r.average_ranks.iter().zip([2.95, 3.15, 2.8, 2.95, 3.15]) {
        close(*a, e, EXACT);
    }
}

#[test]
fn friedman_degenerate_inputs() {
    // scipy 1.17.1: scipy.stats.friedmanchisquare([3.0], [1.0], [2.0])
    //   -> statistic=2.0, pvalue=0.36787944117144245
    let r = friedman(&[[3.0, 1.0, 2.0]]).unwrap();
    close(r.statistic, 2.0, EXACT);
    close(r.p_value, 0.36787944117144245, APPROX);
    assert_eq!(r.average_ranks, vec![3.0, 1.0, 2.0]);
    // All rows tied: SciPy returns NaN; we report no evidence.
    let r = friedman(&[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]).unwrap();
    assert_eq!((r.statistic, r.p_value), (0.0, 1.0));
    assert_eq!(r.average_ranks, vec![2.0; 3]);
    let empty: [[f64; 3]; 0] = [];
    assert!(matches!(
        friedman(&empty),
        Err(StatsError::EmptyInput { .. })
    ));
    assert!(matches!(
        friedman(&[[1.0], [2.0]]),
        Err(StatsError::InvalidParameter { .. })
    ));
    let ragged = vec![vec![1.0, 2.0, 3.0], vec![1.0, 2.0]];
    assert!(matches!(
        friedman(&ragged),
        Err(StatsError::LengthMismatch { .. })
    ));
    assert!(matches!(
        friedman(&[[1.0, 2.0, 3.0], [1.0, f64::NAN, 3.0]]),
        Err(StatsError::NotANumber { index: 4, .. })
    ));
}

// -------------------------------------------------------------------- Holm

#[test]
fn holm_matches_statsmodels() {
    let cases: [(&[f64], &[f64]); 4] = [
        // statsmodels 0.15.0: multipletests([0.01, 0.04, 0.03, 0.005, 0.2], method='holm')[1]
        (
            &[0.01, 0.04, 0.03, 0.005, 0.2],
            &[0.04, 0.09, 0.09, 0.025, 0.2],
        ),
        // statsmodels 0.15.0: multipletests([0.5, 0.01, 0.01, 0.9, 0.04, 0.3], method='holm')[1]
        (
            &[0.5, 0.01, 0.01, 0.9, 0.04, 0.3],
            &[1.0, 0.06, 0.06, 1.0, 0.16, 0.8999999999999999],
        ),
        // statsmodels 0.15.0: multipletests([0.02], method='holm')[1]
        (&[0.02], &[0.02]),
        // statsmodels 0.15.0: multipletests([0.0, 1.0, 0.3], method='holm')[1]
        (&[0.0, 1.0, 0.3], &[0.0, 1.0, 0.6]),
    ];
    for (p, expected) in cases {
        let adj = holm_bonferroni(p).unwrap();
        assert_eq!(adj.len(), expected.len());
        for (a, e) in adj.iter().zip(expected) {
            close(*a, *e, EXACT);
        }
    }
    assert_eq!(holm_bonferroni(&[]).unwrap(), Vec::<f64>::new());
    assert!(holm_bonferroni(&[0.1, f64::NAN]).is_err());
    assert!(holm_bonferroni(&[1.5]).is_err());
    assert!(holm_bonferroni(&[-0.1]).is_err());
}

// ------------------------------------------------------------ Effect sizes

#[test]
fn vargha_delaney_a12_is_u_over_n1_n2() {
    let x = [0.12, 0.5, 0.5, 0.9, 1.3, 2.0, 2.0, 3.1, 4.4, 0.05];
    let y = [0.3, 0.5, 1.1, 1.3, 1.7, 2.0, 2.6, 3.3, 5.0, 6.2, 7.0, 0.5];
    // scipy 1.17.1: mannwhitneyu(x, y).statistic / (10 * 12) -> 0.3458333333333333
    close(
        vargha_delaney_a12(&x, &y).unwrap(),
        0.3458333333333333,
        EXACT,
    );
    // scipy 1.17.1: mannwhitneyu(y, x).statistic / (10 * 12) -> 0.6541666666666667
    close(
        vargha_delaney_a12(&y, &x).unwrap(),
        0.6541666666666667,
        EXACT,
    );
    assert_eq!(vargha_delaney_a12(&[1.0, 2.0], &[1.0, 2.0]).unwrap(), 0.5);
    assert_eq!(vargha_delaney_a12(&[0.0], &[1.0]).unwrap(), 0.0);
}

/// A seeded uniform index in 0..n for the bootstrap tests (SplitMix64;
/// the modulo bias is below 2⁻⁶⁰ for these n).
fn splitmix_index(state: &mut u64) -> impl FnMut(usize) -> usize + '_ {
    move |n| {
        *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = *state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) % n as u64) as usize
    }
}

#[test]
fn bootstrap_interval_of_a_ratio_of_medians_matches_scipy_and_the_exact_distribution() {
    let ratio = |a: &mut [f64], b: &mut [f64]| ratio_of_medians(a, b, 0.0);
    // Independent samples of 7: the median of a resample is a sample value,
    // so the bootstrap distribution of the ratio is discrete. Its exact
    // distribution (the binomial law of a resample's median) puts the 2.5 %
    // and 97.5 % quantiles at 0.28125 and 1.2952380952380953, each at least
    // 0.0109 in probability from the next atom (over 10 Monte Carlo standard
    // errors at 20,000 resamples).
    // scipy 1.17.1: bootstrap((a, b), median(a)/median(b), method="percentile",
    //   n_resamples=200000) -> (0.28125, 1.2952380952380953)
    let a = [1.85, 0.72, 0.65, 1.7, 0.67, 1.13, 1.36];
    let b = [2.56, 1.88, 3.29, 1.05, 2.07, 0.93, 1.55];
    let mut s = 1u64;
    let ci = bootstrap_interval(
        &a,
        &b,
        Resampling::Independent,
        20_000,
        0.95,
        ratio,
        splitmix_index(&mut s),
    )
    .unwrap();
    close(ci.low, 0.28125, EXACT);
    close(ci.high, 1.2952380952380953, EXACT);
    // Paired samples: all 7⁷ resamples enumerated put the quantiles at the
    // smallest and largest ratio, 0.5408163265306123 (mass 0.082) and
    // 1.2264150943396226 (mass 0.063).
    // scipy 1.17.1: bootstrap(..., paired=True, method="percentile",
    //   n_resamples=200000) -> (0.5408163265306123, 1.2264150943396226)
    let a = [1.73, 0.53, 0.72, 0.66, 0.42, 1.07, 1.3];
    let b = [1.69, 0.98, 1.13, 0.97, 0.58, 1.74, 1.06];
    let mut s = 2u64;
    let ci = bootstrap_interval(
        &a,
        &b,
        Resampling::Paired,
        20_000,
        0.95,
        ratio,
        splitmix_index(&mut s),
    )
    .unwrap();
    close(ci.low, 0.5408163265306123, EXACT);
    close(ci.high, 1.2264150943396226, EXACT);
}

// ------------------------------------------------- Post-hoc after Friedman

#[test]
fn friedman_control_posthoc_matches_scikit_posthocs_and_finner() {
    let blocks: [[f64; 4]; 9] = [
        [1.0, 2.0, 3.0, 4.0],
        [2.0, 1.0, 3.5, 4.0],
        [1.5, 2.5, 2.5, 4.5],
        [0.5, 3.0, 1.0, 2.0],
        [1.0, 1.5, 2.0, 2.5],
        [3.0, 1.0, 4.0, 5.0],
        [1.2, 2.2, 3.2, 0.2],
        [0.9, 1.9, 2.9, 3.9],
        [2.0, 2.0, 1.0, 3.0],
    ];
    let f = friedman(&blocks).unwrap();
    // scipy 1.17.1: friedmanchisquare(*columns) -> 12.374999999999995, p 0.006202992067298099
    close(f.statistic, 12.374999999999995, EXACT);
    // The control is treatment 3 (average rank 3.5556).
    let post = friedman_control_posthoc(&f.average_ranks, 9, 3).unwrap();
    let raw: Vec<f64> = post.iter().map(|c| c.p_value).collect();
    // scikit-posthocs 0.17.1: posthoc_siegel_friedman(data) column 3 ->
    //   0.0007311539508918686, 0.028459736916310627, 0.1709035202307977
    for (p, e) in raw.iter().zip([
        0.0007311539508918686,
        0.028459736916310627,
        0.1709035202307977,
    ]) {
        close(*p, e, APPROX);
    }
    assert!(
        post.iter().all(|c| c.z > 0.0),
        "every treatment ranks better than the control"
    );
    // statsmodels 0.15.0: multipletests(raw, method="holm")[1] ->
    //   0.0021934618526756058, 0.056919473832621255, 0.1709035202307977
    let holm = holm_bonferroni(&raw).unwrap();
    for (p, e) in holm.iter().zip([
        0.0021934618526756058,
        0.056919473832621255,
        0.1709035202307977,
    ]) {
        close(*p, e, APPROX);
    }
    // Finner's formula 1 − (1 − p₍ⱼ₎)^(m/j) with the running maximum, in NumPy ->
    //   0.0021918584852406164, 0.0423844153447408, 0.1709035202307977
    let fin = finner(&raw).unwrap();
    for (p, e) in fin.iter().zip([
        0.0021918584852406164,
        0.0423844153447408,
        0.1709035202307977,
    ]) {
        close(*p, e, APPROX);
    }
    // The same formula on [0.001, 0.01, 0.02, 0.04, 0.3].
    let fin = finner(&[0.001, 0.01, 0.02, 0.04, 0.3]).unwrap();
    for (p, e) in fin.iter().zip([
        0.004990009995000988,
        0.024812812891801816,
        0.03311061396069681,
        0.04974745526276503,
        0.30000000000000004,
    ]) {
        close(*p, e, EXACT);
    }
    // scipy 1.17.1: 2 * norm.sf(3 / sqrt(4 * 5 / (6 * 9))) -> 8.243906238216859e-07
    close(
        smallest_friedman_control_p(4, 9),
        8.243906238216859e-07,
        1e-15,
    );
}
