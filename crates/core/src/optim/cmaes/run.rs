//! One run of CMA-ES: the state and buffers of a call, and a generation
//! cut into sample, select, adapt and stop (Hansen 2016, "The CMA
//! evolution strategy: a tutorial", arXiv:1604.00772, Appendix A and B.3;
//! the module docs of `cmaes` give every formula).

use super::strategy::{Covariance, Stop, Strategy};
use super::{InitialMean, STAGNATION_MAX, TOL_CONDITION, TOL_FUN, TOL_UP_SIGMA, TOL_X};
use crate::linalg::{dot, symmetric_eigen};
use crate::optim::clamp;
use crate::optim::evaluator::Evaluator;
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::{Draw, Words};

/// One run's request: population, step size, evaluation limit.
#[derive(Clone, Copy)]
pub(super) struct Setup {
    pub(super) lambda: usize,
    pub(super) sigma0: f64,
    pub(super) limit: u64,
    /// The multiple of the tutorial's eigendecomposition gap.
    pub(super) eigen_gap: f64,
    /// Active or positive-only covariance update.
    pub(super) covariance: Covariance,
    /// Where a run's mean is drawn.
    pub(super) x0: InitialMean,
}

/// The strategy and the evolving scalars of one run.
pub(super) struct RunState {
    s: Strategy,
    sigma: f64,
    sigma0: f64,
    limit: u64,
    /// Evaluations between eigendecompositions.
    eigen_gap: f64,
    /// `(1.4 + 2/(n + 1)) E‖N(0,I)‖`, the bound of `h_σ`.
    hsig_bound: f64,
    /// `√(c_σ(2 − c_σ)μ_eff)`.
    cs_mass: f64,
    /// `√(c_c(2 − c_c)μ_eff)`.
    cc_mass: f64,
    /// The rank `⌈0.7λ⌉ − 1` (from 0) of the flat fitness test.
    flat: usize,
    /// The least window of the `stagnation` criterion.
    stagnation_min: usize,
    /// `(1 − c_σ)^{2g}`.
    ps_decay: f64,
    generations: u64,
    evals: u64,
    /// `evals` at the last eigendecomposition.
    eigen_evals: u64,
    /// The largest of `D`.
    d_max: f64,
}

/// What the ranking of a generation tells the update and the stop.
pub(super) struct Ranked {
    best: f64,
    worst: f64,
    median: f64,
    /// Whether the `⌈0.7λ⌉`-th value equals the best.
    flat: bool,
}

/// A fixed-capacity history of the last values pushed.
struct Ring {
    buf: Vec<f64>,
    len: usize,
    head: usize,
}

impl Ring {
    fn with_capacity(cap: usize) -> Self {
        Self {
            buf: Vec::with_capacity(cap),
            len: 0,
            head: 0,
        }
    }

    /// Empties the history and sets its capacity to `cap ≥ 1` (the memory
    /// is reused, not cleared).
    fn reset(&mut self, cap: usize) {
        let cap = cap.max(1);
        if self.buf.len() != cap {
            self.buf.clear();
            self.buf.resize(cap, 0.0);
        }
        self.len = 0;
        self.head = 0;
    }

    fn push(&mut self, v: f64) {
        let cap = self.buf.len();
        self.buf[self.head] = v;
        self.head = (self.head + 1) % cap;
        self.len = (self.len + 1).min(cap);
    }

    fn is_full(&self) -> bool {
        self.len == self.buf.len()
    }

    /// The `i`-th oldest value, `i < len`.
    fn get(&self, i: usize) -> f64 {
        let cap = self.buf.len();
        self.buf[(self.head + cap - self.len + i) % cap]
    }

    /// The smallest and largest values.
    fn range(&self) -> (f64, f64) {
        self.buf[..self.len]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }
}

/// The state and buffers of a [`super::CmaEs`] call, reused by its runs.
pub(super) struct Work {
    n: usize,
    mean: Vec<f64>,
    ps: Vec<f64>,
    pc: Vec<f64>,
    /// `C`, row-major; only the upper triangle is kept.
    c: Vec<f64>,
    /// The eigenvectors of `C` as rows (`Bᵀ`, row-major).
    b: Vec<f64>,
    /// The square roots of the eigenvalues of `C`.
    d: Vec<f64>,
    scratch_n: Vec<f64>,
    ybar: Vec<f64>,
    t: Vec<f64>,
    z: Vec<f64>,
    /// The steps `y_k` of a generation, one row per sample.
    ys: Vec<f64>,
    /// The evaluated points, one row per sample.
    xs: Vec<f64>,
    f: Vec<f64>,
    order: Vec<usize>,
    /// `‖C^{-1/2} y_k‖²` of each sample, for the active update's weights;
    /// infinite for a repaired sample, whose negative weight is then 0.
    mahalanobis2: Vec<f64>,
    /// `(c_μ w°_i, k)` of the rank-μ update, by rank.
    coef: Vec<(f64, usize)>,
    fun_hist: Ring,
    best_hist: Ring,
    median_hist: Ring,
    select: Vec<f64>,
    /// The second normal of the last polar pair, not yet used.
    spare: Option<f64>,
}

/// The next standard normal of the stream (Marsaglia's polar method; see
/// the module docs).
#[inline(always)]
fn normal<R: Words + ?Sized>(rng: &mut R, spare: &mut Option<f64>) -> f64 {
    if let Some(z) = spare.take() {
        return z;
    }
    loop {
        let v1 = 2.0 * rng.unit() - 1.0;
        let v2 = 2.0 * rng.unit() - 1.0;
        let s = v1 * v1 + v2 * v2;
        if s < 1.0 && s > 0.0 {
            let f = (-2.0 * s.ln() / s).sqrt();
            *spare = Some(v2 * f);
            return v1 * f;
        }
    }
}

/// `y ← y + a·x`.
#[inline(always)]
fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    for (yi, &xi) in y.iter_mut().zip(x) {
        *yi += a * xi;
    }
}

/// The median of `values` (the upper one of an even count), through the
/// scratch `buf`.
fn median_of(values: impl Iterator<Item = f64>, buf: &mut Vec<f64>) -> f64 {
    buf.clear();
    buf.extend(values);
    let k = buf.len() / 2;
    *buf.select_nth_unstable_by(k, f64::total_cmp).1
}

const UNIT: Bounds = Bounds::new(0.0, 1.0);

impl Work {
    pub(super) fn new(n: usize) -> Self {
        Self {
            n,
            mean: vec![0.0; n],
            ps: vec![0.0; n],
            pc: vec![0.0; n],
            c: vec![0.0; n * n],
            b: vec![0.0; n * n],
            d: vec![1.0; n],
            scratch_n: vec![0.0; n],
            ybar: vec![0.0; n],
            t: vec![0.0; n],
            z: vec![0.0; n],
            ys: Vec::new(),
            xs: Vec::new(),
            f: Vec::new(),
            order: Vec::new(),
            mahalanobis2: Vec::new(),
            coef: Vec::new(),
            fun_hist: Ring::with_capacity(16),
            best_hist: Ring::with_capacity(STAGNATION_MAX),
            median_hist: Ring::with_capacity(STAGNATION_MAX),
            select: Vec::with_capacity(STAGNATION_MAX),
            spare: None,
        }
    }

    /// Resets the distribution to `N(m, σ₀² I)` and sizes the buffers for
    /// `rows` samples.
    fn reset(&mut self, rows: usize) {
        let n = self.n;
        self.ps.fill(0.0);
        self.pc.fill(0.0);
        self.c.fill(0.0);
        self.b.fill(0.0);
        for i in 0..n {
            self.c[i * n + i] = 1.0;
            self.b[i * n + i] = 1.0;
        }
        self.d.fill(1.0);
        self.ys.resize(rows * n, 0.0);
        self.xs.resize(rows * n, 0.0);
        self.f.resize(rows, 0.0);
        self.order.resize(rows, 0);
        self.mahalanobis2.resize(rows, 0.0);
    }

    /// Samples `r` points around the mean into `xs` (repaired, in the
    /// problem's coordinates), their steps into `ys` and the squared
    /// Mahalanobis lengths `‖D⁻¹Bᵀy_k‖²` of the steps into `mahalanobis2`
    /// (`‖z_k‖²` for a step that was not repaired).
    #[inline(always)]
    fn sample<R: Words + ?Sized>(
        &mut self,
        rng: &mut R,
        bounds: &[Bounds],
        r: usize,
        sigma: f64,
        policy: BoundPolicy,
    ) {
        let n = self.n;
        let cy = (n as f64).sqrt() + 2.0 * n as f64 / (n as f64 + 2.0);
        for k in 0..r {
            for zj in self.z.iter_mut() {
                *zj = normal(rng, &mut self.spare);
            }
            let y = &mut self.ys[k * n..(k + 1) * n];
            y.fill(0.0);
            for ((bi, &di), &zi) in self.b.chunks_exact(n).zip(&self.d).zip(&self.z) {
                axpy(y, di * zi, bi);
            }
            self.mahalanobis2[k] = dot(&self.z, &self.z);
            let x = &mut self.xs[k * n..(k + 1) * n];
            let mut repaired = false;
            for (((yj, xj), &mj), b) in y.iter_mut().zip(x.iter_mut()).zip(&self.mean).zip(bounds) {
                let u = mj + sigma * *yj;
                let v = match policy {
                    BoundPolicy::Clip => clamp(UNIT, u),
                    BoundPolicy::Reflect => UNIT.reflect(u),
                };
                if v != u {
                    repaired = true;
                    *yj = (v - mj) / sigma;
                }
                *xj = b.lerp(v);
            }
            if repaired {
                // The Mahalanobis length ‖D⁻¹Bᵀy‖ of the repaired step.
                let mut len2 = 0.0;
                for (bi, &di) in self.b.chunks_exact(n).zip(&self.d) {
                    let t = dot(bi, y) / di;
                    len2 += t * t;
                }
                let len = len2.sqrt();
                if len > cy {
                    let shrink = cy / len;
                    for yj in y.iter_mut() {
                        *yj *= shrink;
                    }
                }
                // A repaired point was not drawn from the distribution:
                // like pycma (`CMA_active_injected = 0`), the active update
                // gives it no negative weight.
                self.mahalanobis2[k] = f64::INFINITY;
            }
        }
    }

    /// The mean of a new run, uniform in the unit box, or in its central
    /// 80 % for [`InitialMean::Central`]; a start point
    /// ([`Evaluator::with_start`]) is the first run's mean (pycma's `x0`)
    /// and, so that the best is never worse than it, its first evaluation.
    fn draw_mean<P: Problem + ?Sized, R: Words + ?Sized>(
        &mut self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        x0: InitialMean,
    ) {
        for m in self.mean.iter_mut() {
            *m = match x0 {
                InitialMean::Uniform => rng.unit(),
                InitialMean::Central => 0.1 + 0.8 * rng.unit(),
            };
        }
        if let Some(x0) = eval.start().map(<[f64]>::to_vec) {
            for ((m, &x), b) in self.mean.iter_mut().zip(&x0).zip(eval.bounds()) {
                *m = b.normalise(x);
            }
            eval.evaluate(&x0);
        }
    }

    /// The start of a run: its mean, `N(m, σ₀² I)`,
    /// the strategy parameters and the termination windows.
    fn start<P: Problem + ?Sized, R: Words + ?Sized>(
        &mut self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        setup: Setup,
    ) -> RunState {
        let nf = self.n as f64;
        let lambda = setup.lambda;
        self.draw_mean(eval, rng, setup.x0);
        let rows = lambda.min(usize::try_from(eval.remaining()).unwrap_or(usize::MAX));
        self.reset(rows);
        let s = Strategy::new(self.n, lambda, setup.covariance);
        let fun_window = 10 + (30.0 * nf / lambda as f64).ceil() as usize;
        self.fun_hist.reset(fun_window);
        self.best_hist.reset(STAGNATION_MAX);
        self.median_hist.reset(STAGNATION_MAX);
        RunState {
            // Multiplying by 1 is exact: the tutorial's schedule.
            eigen_gap: s.eigen_gap * setup.eigen_gap,
            hsig_bound: (1.4 + 2.0 / (nf + 1.0)) * s.chi_n,
            cs_mass: (s.cs * (2.0 - s.cs) * s.mueff).sqrt(),
            cc_mass: (s.cc * (2.0 - s.cc) * s.mueff).sqrt(),
            flat: ((0.7 * lambda as f64).ceil() as usize).clamp(1, lambda) - 1,
            stagnation_min: 120 + (30.0 * nf / lambda as f64).ceil() as usize,
            s,
            sigma: setup.sigma0,
            sigma0: setup.sigma0,
            limit: setup.limit,
            ps_decay: 1.0,
            generations: 0,
            evals: 0,
            eigen_evals: 0,
            d_max: 1.0,
        }
    }

    /// One run until a termination criterion fires or the budget is spent:
    /// sample, select, adapt, stop, generation after generation.
    #[inline(always)]
    pub(super) fn run<P: Problem + ?Sized, R: Words + ?Sized>(
        &mut self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        setup: Setup,
        policy: BoundPolicy,
    ) -> (u64, Stop) {
        let n = self.n;
        let bounds = eval.bounds();
        let lambda = setup.lambda;
        let mut st = self.start(eval, rng, setup);
        loop {
            let r = lambda.min(usize::try_from(eval.remaining()).unwrap_or(usize::MAX));
            if r == 0 {
                return (st.generations, Stop::Budget);
            }
            self.sample(rng, bounds, r, st.sigma, policy);
            eval.evaluate_batch(&self.xs[..r * n], &mut self.f[..r]);
            st.evals += r as u64;
            st.generations += 1;
            if r < lambda || eval.remaining() == 0 {
                return (st.generations, Stop::Budget);
            }
            let ranked = self.select(lambda, st.flat);
            if ranked.best.is_nan() || ranked.best == f64::INFINITY {
                return (st.generations, Stop::NoFiniteValue);
            }
            let stop = self
                .adapt(&mut st, &ranked)
                .or_else(|| self.stop(&st, &ranked));
            if let Some(stop) = stop {
                return (st.generations, stop);
            }
        }
    }

    /// Ranks the generation by value, ties by sample index, into `order`;
    /// `flat` is the rank `⌈0.7λ⌉` compared with the best for the flat
    /// fitness escape.
    fn select(&mut self, lambda: usize, flat: usize) -> Ranked {
        let f = &self.f[..lambda];
        let order = &mut self.order[..lambda];
        for (i, o) in order.iter_mut().enumerate() {
            *o = i;
        }
        order.sort_unstable_by(|&a, &b| f[a].total_cmp(&f[b]).then(a.cmp(&b)));
        Ranked {
            best: f[order[0]],
            worst: f[order[lambda - 1]],
            median: f[order[lambda / 2]],
            flat: f[order[flat]] == f[order[0]],
        }
    }

    /// The update of one generation (see the module docs): the mean, the
    /// paths, `C` (rank one, rank μ, and the active update's negative
    /// weights), `σ`, and the lazy eigendecomposition; `Some` when `C` is
    /// no longer positive definite or too ill-conditioned.
    #[inline(always)]
    fn adapt(&mut self, st: &mut RunState, ranked: &Ranked) -> Option<Stop> {
        let n = self.n;
        let s = &st.s;
        let order = &self.order[..s.lambda];

        // Recombination: ⟨y⟩_w and the new mean.
        self.ybar.fill(0.0);
        for (&w, &k) in s.weights.iter().zip(order) {
            axpy(&mut self.ybar, w, &self.ys[k * n..(k + 1) * n]);
        }
        for (m, &yb) in self.mean.iter_mut().zip(&self.ybar) {
            *m += st.sigma * yb;
        }

        // CSA: p_σ with C^{-1/2}⟨y⟩_w = B D⁻¹ Bᵀ ⟨y⟩_w.
        for ((ti, bi), &di) in self.t.iter_mut().zip(self.b.chunks_exact(n)).zip(&self.d) {
            *ti = dot(bi, &self.ybar) / di;
        }
        self.scratch_n.fill(0.0);
        for (bi, &ti) in self.b.chunks_exact(n).zip(&self.t) {
            axpy(&mut self.scratch_n, ti, bi);
        }
        for (p, &v) in self.ps.iter_mut().zip(&self.scratch_n) {
            *p = (1.0 - s.cs) * *p + st.cs_mass * v;
        }
        let norm_ps = dot(&self.ps, &self.ps).sqrt();
        st.ps_decay *= (1.0 - s.cs) * (1.0 - s.cs);
        let hsig = norm_ps / (1.0 - st.ps_decay).sqrt() < st.hsig_bound;

        // p_c, then the rank-one and rank-μ update of C's upper triangle;
        // a negative weight w_i becomes w_i·n/‖C^{-1/2}y_{i:λ}‖² (Hansen
        // 2016, eq. (46)), so that its step has the length of a typical one,
        // and 0 for a repaired step (infinite length, see `sample`).
        let h = if hsig { st.cc_mass } else { 0.0 };
        for (p, &yb) in self.pc.iter_mut().zip(&self.ybar) {
            *p = (1.0 - s.cc) * *p + h * yb;
        }
        let delta = if hsig {
            0.0
        } else {
            s.c1 * s.cc * (2.0 - s.cc)
        };
        // Σw = 1 without the active update: the factor of the tutorial's code.
        let keep = if s.cov_weights.len() == s.mu {
            1.0 + delta - s.c1 - s.cmu
        } else {
            1.0 + delta - s.c1 - s.cmu * s.cov_weight_sum
        };
        self.coef.clear();
        for (&w, &k) in s.cov_weights.iter().zip(order) {
            let w = if w < 0.0 {
                w * n as f64 / self.mahalanobis2[k]
            } else {
                w
            };
            self.coef.push((s.cmu * w, k));
        }
        for j in 0..n {
            let row = &mut self.c[j * n + j..(j + 1) * n];
            let a = s.c1 * self.pc[j];
            for (cjk, &pk) in row.iter_mut().zip(&self.pc[j..]) {
                *cjk = keep * *cjk + a * pk;
            }
            for &(cw, k) in &self.coef {
                if cw != 0.0 {
                    let yk = &self.ys[k * n + j..(k + 1) * n];
                    axpy(row, cw * yk[0], yk);
                }
            }
        }

        // Step size.
        st.sigma *= ((s.cs / s.ds) * (norm_ps / s.chi_n - 1.0)).exp();
        if ranked.flat {
            st.sigma *= (0.2 + s.cs / s.ds).exp();
        }

        // The lazy eigendecomposition C = B D² Bᵀ.
        if (st.evals - st.eigen_evals) as f64 > st.eigen_gap {
            st.eigen_evals = st.evals;
            self.b.copy_from_slice(&self.c);
            if !symmetric_eigen(&mut self.b, n, &mut self.d, &mut self.t) || self.d[0] <= 0.0 {
                return Some(Stop::Numerics);
            }
            if self.d[n - 1] > TOL_CONDITION * self.d[0] {
                return Some(Stop::ConditionCov);
            }
            for di in self.d.iter_mut() {
                *di = di.sqrt();
            }
            st.d_max = self.d[n - 1];
        }
        if !st.sigma.is_finite() || !norm_ps.is_finite() {
            return Some(Stop::Numerics);
        }
        None
    }

    /// The tutorial's termination criteria after a generation (see the
    /// module docs), `None` when the run goes on.
    fn stop(&mut self, st: &RunState, ranked: &Ranked) -> Option<Stop> {
        let n = self.n;
        let sigma = st.sigma;
        self.fun_hist.push(ranked.best);
        if self.fun_hist.is_full() {
            let (lo, hi) = self.fun_hist.range();
            if hi.max(ranked.worst) - lo < TOL_FUN {
                return Some(Stop::TolFun);
            }
            if hi == lo {
                return Some(Stop::EqualFunValues);
            }
        }
        let diag = |j: usize| self.c[j * n + j];
        if (0..n).all(|j| sigma * self.pc[j].abs().max(diag(j).sqrt()) < TOL_X * st.sigma0) {
            return Some(Stop::TolX);
        }
        let axis = (st.generations % n as u64) as usize;
        let step = 0.1 * sigma * self.d[axis];
        let bi = &self.b[axis * n..(axis + 1) * n];
        if self
            .mean
            .iter()
            .zip(bi)
            .all(|(&m, &bij)| m + step * bij == m)
        {
            return Some(Stop::NoEffectAxis);
        }
        if (0..n).any(|j| self.mean[j] + 0.2 * sigma * diag(j).sqrt() == self.mean[j]) {
            return Some(Stop::NoEffectCoord);
        }
        if sigma * st.d_max > TOL_UP_SIGMA * st.sigma0 {
            return Some(Stop::TolUpSigma);
        }
        self.best_hist.push(ranked.best);
        self.median_hist.push(ranked.median);
        if self.stagnates(st.generations, st.stagnation_min) {
            return Some(Stop::Stagnation);
        }
        if st.evals >= st.limit {
            return Some(Stop::RunBudget);
        }
        None
    }

    /// The `stagnation` criterion after `g` generations (see the module
    /// docs).
    fn stagnates(&mut self, g: u64, least: usize) -> bool {
        let g = usize::try_from(g).unwrap_or(usize::MAX);
        let window = g.div_ceil(5).max(least).min(STAGNATION_MAX);
        if g < window || g % window.div_ceil(40) != 0 {
            return false;
        }
        let k = (3 * window).div_ceil(10);
        let len = self.best_hist.len;
        let start = len - window;
        let mut worse = true;
        for hist in [&self.best_hist, &self.median_hist] {
            let first = median_of((start..start + k).map(|i| hist.get(i)), &mut self.select);
            let last = median_of((len - k..len).map(|i| hist.get(i)), &mut self.select);
            worse &= last >= first;
        }
        worse
    }
}
