//! The Bayesian signed-rank test with a region of practical equivalence
//! (rope) of Benavoli, Corani, Demšar & Zaffalon (2017), as implemented by
//! the Python package `baycomp` 1.0.3 (`SignedRankTest`), sampled with the
//! project's own generator so that results are bit-reproducible.

use super::error::{check_no_nan, check_non_empty, StatsError};
use crate::rng::{run_rng, Draw};

/// Posterior probabilities that the differences d tend to lie below −rope
/// (`left`), within [−rope, rope] (`rope`) or above +rope (`right`): the
/// fractions of posterior samples in which θ_left, θ_rope or θ_right is the
/// largest (Benavoli, Corani, Demšar & Zaffalon 2017, "Time for a change: a
/// tutorial for comparing multiple classifiers through Bayesian analysis",
/// JMLR 18(77):1–36, §5).
///
/// Sign convention: `left` is about d itself ("d tends to be below −rope").
/// `baycomp` works on the difference y − x of its arguments, so
/// `baycomp.SignedRankTest(x, y, rope).probs()` returns
/// `(p_left, p_rope, p_right)` = (`left`, `rope`, `right`) of
/// [`bayesian_signed_rank`] on d = y − x; for instance
/// `SignedRankTest(np.zeros(n), d, rope)` with the same d. With rope 0,
/// `rope` is 0 and `baycomp` returns only `(p_left, p_right)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RopePosterior {
    /// P(θ_left is the largest): d tends to be below −rope.
    pub left: f64,
    /// P(θ_rope is the largest): d tends to be within [−rope, rope].
    pub rope: f64,
    /// P(θ_right is the largest): d tends to be above +rope.
    pub right: f64,
}

/// The parameters of [`bayesian_signed_rank`] (Benavoli, Corani, Demšar &
/// Zaffalon 2017, "Time for a change: a tutorial for comparing multiple
/// classifiers through Bayesian analysis", JMLR 18(77):1–36):
/// a Dirichlet process prior DP(s, δ₀) with strength s = `prior` and its
/// pseudo-observation at 0, `samples` Monte Carlo samples of the posterior
/// drawn from [`crate::rng::run_rng`]`(seed)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BayesSignedRank {
    /// Half-width r ≥ 0 of the region of practical equivalence [−r, r].
    pub rope: f64,
    /// Strength s > 0 of the prior's pseudo-observation z₀ = 0.
    pub prior: f64,
    /// Number of posterior samples (at least 1); the Monte Carlo standard
    /// error of a probability is at most 0.5/√samples.
    pub samples: usize,
    /// Seed of the generator ([`crate::rng::run_rng`]).
    pub seed: u64,
}

impl BayesSignedRank {
    /// `baycomp`'s default prior strength (`SignedRankTest.sample(...,
    /// prior=0.5)`), the weight of the pseudo-observation at 0.
    pub const BAYCOMP_PRIOR: f64 = 0.5;
    /// `baycomp`'s default number of samples (`nsamples=50000`).
    pub const BAYCOMP_SAMPLES: usize = 50_000;

    /// `baycomp`'s defaults (prior strength 0.5 at a pseudo-observation 0,
    /// 50,000 samples) with rope half-width `rope` and seed 0 (`baycomp`'s
    /// `random_state=None` draws a fresh seed; here a run is reproducible).
    pub fn with_rope(rope: f64) -> Self {
        Self {
            rope,
            ..Self::default()
        }
    }
}

impl Default for BayesSignedRank {
    /// `baycomp` 1.0.3's `SignedRankTest` defaults: rope 0, prior 0.5,
    /// 50,000 samples; seed 0.
    fn default() -> Self {
        Self {
            rope: 0.0,
            prior: Self::BAYCOMP_PRIOR,
            samples: Self::BAYCOMP_SAMPLES,
            seed: 0,
        }
    }
}

/// The Bayesian signed-rank test of the differences `d` (Benavoli, Corani,
/// Demšar & Zaffalon 2017, "Time for a change: a tutorial for comparing
/// multiple classifiers through Bayesian analysis", JMLR 18(77):1–36, §5;
/// the test itself: Benavoli, Mangili, Corani, Zaffalon & Ruggeri 2014, "A
/// Bayesian Wilcoxon signed-rank test based on the Dirichlet process",
/// ICML, PMLR 32(2):1026–1034), following `baycomp` 1.0.3's
/// `SignedRankTest` exactly except for the random numbers.
///
/// With z = (z₀ = 0, d₁, …, dₙ), each sample draws weights
/// w ~ Dirichlet(s, 1, …, 1) (normalised Gamma(s), Gamma(1), … variates)
/// and, with t = 2r and H(a, t) = 1 if a > t, ½ if a = t, 0 otherwise
/// (baycomp's `heaviside`), over all ordered pairs i, j including i = j:
///
/// θ_right = Σᵢⱼ wᵢwⱼ·H(zᵢ + zⱼ, t),  θ_left = Σᵢⱼ wᵢwⱼ·H(−(zᵢ + zⱼ), t),
/// θ_rope = 1 − θ_left − θ_right.
///
/// With r = 0, as in baycomp, only θ_right is summed, θ_left = 1 − θ_right
/// and θ_rope = 0. The result is the fraction of samples in which each θ is
/// the largest, ties going to the first of (left, rope, right) (NumPy's
/// `argmax`). The comparisons are made on the floating sums `zᵢ + zⱼ`
/// themselves, as baycomp's, but in O(n) per sample instead of O(n²): with
/// z sorted, the j with zᵢ + zⱼ > t (or ≥ t, < −t, ≤ −t) form a suffix (a
/// prefix) whose end moves monotonically with i; those ends are found once
/// with two pointers, and per sample prefix sums of w give their weight.
/// The weights are drawn in the order of the sorted d (the
/// pseudo-observation's first), so the result does not depend on the order
/// of `d`. Gamma variates: Gamma(1) = −ln(1 − U); other shapes by Marsaglia
/// & Tsang (2000, "A simple method for generating gamma variables", ACM
/// TOMS 26(3):363–372), with Gamma(a) = Gamma(a + 1)·U^{1/a} for a < 1.
///
/// Errors: empty `d`, a NaN ([`StatsError::NotANumber`]), an infinite
/// difference (refused: ∞ − ∞ pair sums would be NaN), a rope that is
/// negative or not finite, a prior that is not finite and positive, or
/// zero samples ([`StatsError::InvalidParameter`]).
///
/// ```
/// use metabezier_core::stats::{bayesian_signed_rank, BayesSignedRank};
///
/// // Every difference lies well inside the rope ±0.3.
/// let d = [0.01, -0.015, 0.002, 0.018, -0.007, 0.0, 0.011, -0.019];
/// let p = bayesian_signed_rank(&d, &BayesSignedRank::with_rope(0.3)).unwrap();
/// assert_eq!((p.left, p.rope, p.right), (0.0, 1.0, 0.0));
/// ```
pub fn bayesian_signed_rank(
    d: &[f64],
    test: &BayesSignedRank,
) -> Result<RopePosterior, StatsError> {
    check_inputs(d, test)?;
    let (z, pseudo) = support(d);
    let cuts = Cuts::new(&z, 2.0 * test.rope);
    let mut rng = run_rng(test.seed);
    let mut w = vec![0.0; z.len()];
    let mut cum = vec![0.0; z.len() + 1];
    let mut wins = [0usize; 3];
    for _ in 0..test.samples {
        draw_weights(&mut rng, test.prior, pseudo, &mut w, &mut cum);
        let theta = thetas(&cuts, &w, &cum, test.rope > 0.0);
        wins[winner(theta)] += 1;
    }
    let total = test.samples as f64;
    Ok(RopePosterior {
        left: wins[0] as f64 / total,
        rope: wins[1] as f64 / total,
        right: wins[2] as f64 / total,
    })
}

/// Refuses empty, NaN or infinite `d` and parameters outside their domain.
fn check_inputs(d: &[f64], test: &BayesSignedRank) -> Result<(), StatsError> {
    check_non_empty(d, "differences")?;
    check_no_nan(d, "differences")?;
    let invalid = |name, reason| Err(StatsError::InvalidParameter { name, reason });
    if d.iter().any(|v| v.is_infinite()) {
        return invalid(
            "differences",
            "the Bayesian signed-rank test needs finite differences",
        );
    }
    if !(test.rope >= 0.0 && test.rope.is_finite()) {
        return invalid("rope", "the rope half-width must be finite and >= 0");
    }
    if !(test.prior > 0.0 && test.prior.is_finite()) {
        return invalid("prior", "the prior strength must be finite and > 0");
    }
    if test.samples == 0 {
        return invalid("samples", "at least one posterior sample is needed");
    }
    Ok(())
}

/// z = d with the pseudo-observation 0 inserted, sorted ascending, and the
/// position of the pseudo-observation (before any zero of d).
fn support(d: &[f64]) -> (Vec<f64>, usize) {
    let mut z = d.to_vec();
    z.sort_unstable_by(f64::total_cmp);
    let pseudo = z.partition_point(|&v| v < 0.0);
    z.insert(pseudo, 0.0);
    (z, pseudo)
}

/// Fills `w` with unnormalised Dirichlet(s, 1, …, 1) weights (Gamma(s) at
/// `pseudo`, drawn first; Gamma(1) elsewhere, in order) and `cum` with their
/// prefix sums, `cum[p]` = Σ_{j<p} wⱼ. A draw whose weights are all 0
/// (probability below 2⁻⁵³ per weight) is redrawn.
fn draw_weights(rng: &mut impl Draw, prior: f64, pseudo: usize, w: &mut [f64], cum: &mut [f64]) {
    loop {
        w[pseudo] = gamma(rng, prior);
        for (j, v) in w.iter_mut().enumerate() {
            if j != pseudo {
                *v = -(1.0 - rng.unit()).ln();
            }
        }
        let mut acc = 0.0;
        cum[0] = 0.0;
        for (c, &v) in cum[1..].iter_mut().zip(w.iter()) {
            acc += v;
            *c = acc;
        }
        if acc > 0.0 {
            return;
        }
    }
}

/// Where the partners of each zᵢ of the ascending support z start and end
/// for the threshold t: the j with zᵢ + zⱼ > t are the suffix from
/// `gt[i]`, those with ≥ t the suffix from `ge[i]`; the j with zᵢ + zⱼ < −t
/// (that is, −fl(zᵢ + zⱼ) > t, negation being exact) are the prefix before
/// `lt[i]`, those with ≤ −t the prefix before `le[i]`. They depend on z and
/// t only, so they are found once, not per sample.
struct Cuts {
    gt: Vec<usize>,
    ge: Vec<usize>,
    lt: Vec<usize>,
    le: Vec<usize>,
}

impl Cuts {
    /// The cuts of ascending `z` for `t`, in O(n): fl(a + b) is monotone in
    /// b, so each set is a suffix (a prefix), and its start (end) only moves
    /// left as zᵢ grows; the comparisons are those of baycomp on the same
    /// floating sums.
    fn new(z: &[f64], t: f64) -> Cuts {
        let m = z.len();
        let mut c = Cuts {
            gt: Vec::with_capacity(m),
            ge: Vec::with_capacity(m),
            lt: Vec::with_capacity(m),
            le: Vec::with_capacity(m),
        };
        let (mut gt, mut ge, mut lt, mut le) = (m, m, m, m);
        for &zi in z {
            while gt > 0 && zi + z[gt - 1] > t {
                gt -= 1;
            }
            while ge > 0 && zi + z[ge - 1] >= t {
                ge -= 1;
            }
            while lt > 0 && zi + z[lt - 1] >= -t {
                lt -= 1;
            }
            while le > 0 && zi + z[le - 1] > -t {
                le -= 1;
            }
            c.gt.push(gt);
            c.ge.push(ge);
            c.lt.push(lt);
            c.le.push(le);
        }
        c
    }
}

/// (θ_left, θ_rope, θ_right) of one sample from the cuts of the support,
/// the unnormalised weights `w` and their prefix sums `cum` (`cum[p]` =
/// Σ_{j<p} wⱼ, the last entry normalising), as baycomp computes them with
/// or without a rope: θ_right·W² = Σᵢ wᵢ·[(W − cum[gtᵢ]) + ½(cum[gtᵢ] −
/// cum[geᵢ])] and θ_left·W² = Σᵢ wᵢ·[cum[ltᵢ] + ½(cum[leᵢ] − cum[ltᵢ])].
fn thetas(cuts: &Cuts, w: &[f64], cum: &[f64], with_rope: bool) -> [f64; 3] {
    let total = cum[cum.len() - 1];
    let scale = total * total;
    let mut above = 0.0;
    for ((&wi, &gt), &ge) in w.iter().zip(&cuts.gt).zip(&cuts.ge) {
        above += wi * ((total - cum[gt]) + 0.5 * (cum[gt] - cum[ge]));
    }
    let right = above / scale;
    if !with_rope {
        return [-right + 1.0, 0.0, right];
    }
    let mut below = 0.0;
    for ((&wi, &lt), &le) in w.iter().zip(&cuts.lt).zip(&cuts.le) {
        below += wi * (cum[lt] + 0.5 * (cum[le] - cum[lt]));
    }
    let left = below / scale;
    [left, -left - right + 1.0, right]
}

/// The index of the largest of (θ_left, θ_rope, θ_right), the first on a
/// tie, as NumPy's `argmax`.
fn winner(theta: [f64; 3]) -> usize {
    let mut best = 0;
    for k in 1..3 {
        if theta[k] > theta[best] {
            best = k;
        }
    }
    best
}

/// A Gamma(a, 1) variate: −ln(1 − U) for a = 1; Marsaglia & Tsang (2000,
/// "A simple method for generating gamma variables", ACM TOMS
/// 26(3):363–372) for a > 1, and Gamma(a + 1)·U^{1/a} for a < 1 (their §6).
fn gamma(rng: &mut impl Draw, a: f64) -> f64 {
    if a == 1.0 {
        -(1.0 - rng.unit()).ln()
    } else if a < 1.0 {
        let g = marsaglia_tsang(rng, a + 1.0);
        g * rng.unit().powf(1.0 / a)
    } else {
        marsaglia_tsang(rng, a)
    }
}

/// Marsaglia & Tsang's (2000, ACM TOMS 26(3):363–372) rejection sampler for
/// Gamma(a, 1), a ≥ 1: with d = a − ⅓, c = 1/√(9d), x ~ N(0, 1),
/// v = (1 + cx)³ > 0 and u ~ U[0, 1), accept d·v if u < 1 − 0.0331x⁴ or
/// ln u < x²/2 + d(1 − v + ln v). The acceptance rate exceeds 0.95.
fn marsaglia_tsang(rng: &mut impl Draw, a: f64) -> f64 {
    let d = a - 1.0 / 3.0;
    let c = 1.0 / (9.0 * d).sqrt();
    loop {
        let x = rng.gaussian();
        let v = 1.0 + c * x;
        if v <= 0.0 {
            continue;
        }
        let v = v * v * v;
        let u = rng.unit();
        let x2 = x * x;
        if u < 1.0 - 0.0331 * x2 * x2 || u.ln() < 0.5 * x2 + d * (1.0 - v + v.ln()) {
            return d * v;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// baycomp's O(n²) double sum: (θ_left, θ_right) with normalised weights.
    fn naive(z: &[f64], w: &[f64], t: f64) -> (f64, f64) {
        let total: f64 = w.iter().sum();
        let h = |a: f64| {
            if a > t {
                1.0
            } else if a == t {
                0.5
            } else {
                0.0
            }
        };
        let (mut left, mut right) = (0.0, 0.0);
        for (&zi, &wi) in z.iter().zip(w) {
            for (&zj, &wj) in z.iter().zip(w) {
                let s = zi + zj;
                let p = (wi / total) * (wj / total);
                left += p * h(-s);
                right += p * h(s);
            }
        }
        (left, right)
    }

    #[test]
    fn pointer_sums_equal_the_double_loop() {
        let mut rng = run_rng(3);
        for case in 0..200 {
            let n = 1 + rng.index(40);
            // Quarter steps: many ties, zeros and sums exactly at ±2r.
            let d: Vec<f64> = if case % 2 == 0 {
                (0..n).map(|_| rng.index(13) as f64 / 4.0 - 1.5).collect()
            } else {
                (0..n).map(|_| 0.3 * rng.gaussian()).collect()
            };
            let (z, pseudo) = support(&d);
            let mut w = vec![0.0; z.len()];
            let mut cum = vec![0.0; z.len() + 1];
            for rope in [0.0, 0.125, 0.25, 0.5, 0.1] {
                draw_weights(&mut rng, 0.5, pseudo, &mut w, &mut cum);
                let [left, _, right] = thetas(&Cuts::new(&z, 2.0 * rope), &w, &cum, true);
                let (l, r) = naive(&z, &w, 2.0 * rope);
                assert!((left - l).abs() < 1e-12, "case {case}, rope {rope}");
                assert!((right - r).abs() < 1e-12, "case {case}, rope {rope}");
            }
        }
    }

    #[track_caller]
    fn near(p: RopePosterior, want: [f64; 3]) {
        let got = [p.left, p.rope, p.right];
        for (g, w) in got.iter().zip(want) {
            assert!((g - w).abs() <= 0.01, "got {got:?}, baycomp {want:?}");
        }
    }

    #[test]
    fn agrees_with_baycomp() {
        // baycomp 1.0.3 (NumPy 2.4.6, Python 3.11.7), with x = zeros and
        // y = d, so that its y − x is d and its (p_left, p_rope, p_right)
        // are (left, rope, right): SignedRankTest(np.zeros(n), d, rope,
        // random_state=s).probs(with_rope=True), mean over s = 0..9 (50,000
        // samples each); ci/stats-reference/bayes_and_hl.py. The range over
        // the ten seeds is in the comments.
        let test = |rope| BayesSignedRank::with_rope(rope);
        // 24 uniforms on ±0.02 (numpy default_rng(1)), rope 0.3 -> [0, 1, 0].
        let equivalent = [
            0.0005, 0.018, -0.0142, 0.0179, -0.0075, -0.0031, 0.0131, -0.0036, 0.002, -0.0189,
            0.0101, 0.0015, -0.0068, 0.0115, -0.0079, -0.0019, -0.0146, -0.0039, -0.0119, -0.0095,
            0.01, -0.0088, -0.0006, 0.0192,
        ];
        let p = bayesian_signed_rank(&equivalent, &test(0.3)).unwrap();
        assert_eq!((p.left, p.rope, p.right), (0.0, 1.0, 0.0));
        // rope 0.1 -> [0, 0, 1] on every seed.
        let one_sided = [
            0.8, 1.2, 0.5, 2.1, 0.9, 1.7, -0.2, 1.1, 0.6, 1.4, 0.95, 1.3, 0.7, 1.05, 0.4,
        ];
        let p = bayesian_signed_rank(&one_sided, &test(0.1)).unwrap();
        assert_eq!((p.left, p.rope, p.right), (0.0, 0.0, 1.0));
        // rope 0.1 -> mean [0.02698, 0.56523, 0.40779]; seed 0 [0.02688,
        // 0.5633, 0.40982]; seeds 0..9 span rope 0.5625..0.56908. (With
        // 2,000,000 samples this function gives [0.02749, 0.56430, 0.40821],
        // baycomp over random_state 10..39 [0.02737, 0.56441, 0.40822].)
        let undecided = [-0.3, 0.25, 0.1, -0.05, 0.4, -0.2, 0.15, 0.05, -0.1, 0.35];
        near(
            bayesian_signed_rank(&undecided, &test(0.1)).unwrap(),
            [0.02698, 0.56523, 0.40779],
        );
        // Ties, zeros and pair sums exactly at ±2r = ±1.
        let ties = [
            0.0, 0.0, 0.5, 0.5, -0.5, -1.0, -1.0, 0.25, -1.5, 0.5, 0.0, -2.0,
        ];
        // rope 0.5 -> mean [0.22625, 0.77375, 0.0]; seed 0 [0.22498, 0.77502, 0.0].
        near(
            bayesian_signed_rank(&ties, &test(0.5)).unwrap(),
            [0.22625, 0.77375, 0.0],
        );
        // rope 0 (baycomp's path without rope) -> mean [0.84378, 0.0, 0.15622];
        // seed 0 [0.84028, 0.0, 0.15972].
        near(
            bayesian_signed_rank(&ties, &test(0.0)).unwrap(),
            [0.84378, 0.0, 0.15622],
        );
    }

    #[test]
    fn a_seed_reproduces_its_result_and_the_order_of_d_does_not_matter() {
        let d = [-0.3, 0.25, 0.1, -0.05, 0.4, -0.2, 0.15, 0.05, -0.1, 0.35];
        let mut test = BayesSignedRank {
            rope: 0.1,
            samples: 5_000,
            seed: 42,
            ..BayesSignedRank::default()
        };
        let a = bayesian_signed_rank(&d, &test).unwrap();
        assert_eq!(a, bayesian_signed_rank(&d, &test).unwrap());
        let mut reversed = d;
        reversed.reverse();
        assert_eq!(a, bayesian_signed_rank(&reversed, &test).unwrap());
        test.seed = 43;
        assert_ne!(a, bayesian_signed_rank(&d, &test).unwrap());
        assert_eq!(a.left + a.rope + a.right, 1.0);
    }

    #[test]
    fn gamma_variates_have_the_right_moments() {
        let mut rng = run_rng(9);
        for a in [0.1, 0.5, 1.0, 2.5, 30.0] {
            let k = 200_000;
            let g: Vec<f64> = (0..k).map(|_| gamma(&mut rng, a)).collect();
            let mean = g.iter().sum::<f64>() / k as f64;
            let var = g.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / k as f64;
            // Mean and variance a; five standard errors.
            assert!(
                (mean - a).abs() < 5.0 * (a / k as f64).sqrt(),
                "a {a}: mean {mean}"
            );
            assert!((var - a).abs() < 0.05 * a.max(0.5), "a {a}: var {var}");
            assert!(g.iter().all(|&v| v >= 0.0 && v.is_finite()));
        }
    }

    #[test]
    fn bad_inputs_are_errors() {
        let ok = BayesSignedRank::with_rope(0.1);
        assert!(matches!(
            bayesian_signed_rank(&[], &ok),
            Err(StatsError::EmptyInput { .. })
        ));
        assert!(matches!(
            bayesian_signed_rank(&[0.1, f64::NAN], &ok),
            Err(StatsError::NotANumber { index: 1, .. })
        ));
        assert!(bayesian_signed_rank(&[0.1, f64::NEG_INFINITY], &ok).is_err());
        let bad = [
            BayesSignedRank { rope: -0.1, ..ok },
            BayesSignedRank {
                rope: f64::NAN,
                ..ok
            },
            BayesSignedRank {
                rope: f64::INFINITY,
                ..ok
            },
            BayesSignedRank { prior: 0.0, ..ok },
            BayesSignedRank { prior: -1.0, ..ok },
            BayesSignedRank {
                prior: f64::NAN,
                ..ok
            },
            BayesSignedRank { samples: 0, ..ok },
        ];
        for test in bad {
            assert!(
                matches!(
                    bayesian_signed_rank(&[0.1, 0.2], &test),
                    Err(StatsError::InvalidParameter { .. })
                ),
                "{test:?}"
            );
        }
    }

    /// Run with `cargo test --release -p metabezier-core bayes_signed_rank::tests::timing
    /// -- --ignored --nocapture`; prints, asserts nothing about time.
    #[test]
    #[ignore]
    fn timing() {
        let mut rng = run_rng(1);
        for n in [24, 300] {
            let d: Vec<f64> = (0..n).map(|_| 0.01 + 0.05 * rng.gaussian()).collect();
            let test = BayesSignedRank::with_rope(0.01);
            let start = std::time::Instant::now();
            let p = bayesian_signed_rank(&d, &test).unwrap();
            println!(
                "n = {n}, {} samples: {:?} ({p:?})",
                test.samples,
                start.elapsed()
            );
        }
    }
}
