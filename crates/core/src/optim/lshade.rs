//! L-SHADE: success-history based adaptive differential evolution with
//! linear population size reduction (Tanabe & Fukunaga 2014, "Improving the
//! search performance of SHADE using linear population size reduction",
//! Proc. IEEE CEC 2014, 1658–1665), the winner of the CEC 2014 competition
//! on real-parameter single-objective optimisation. It extends SHADE
//! (Tanabe & Fukunaga 2013, "Success-history based parameter adaptation for
//! differential evolution", Proc. IEEE CEC 2013, 71–78), itself built on the
//! current-to-pbest/1 mutation and external archive of JADE (Zhang &
//! Sanderson 2009, "JADE: adaptive differential evolution with optional
//! external archive", IEEE TEC 13(5):945–958).
//!
//! Implemented from the two papers; where they leave a detail open, the
//! choice of the authors' published L-SHADE code is followed and said so
//! below.

use crate::optim::params::Param;
use std::cmp::Ordering;
use std::f64::consts::PI;

use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{clamp, select, Optimiser, ParamError};
use crate::optim::evaluator::Evaluator;
use crate::problem::{Bounds, Problem};
use crate::rng::{Draw, Words};
use crate::simd::dispatch;

/// The final population size `N_min` of the linear reduction: the smallest
/// population for which current-to-pbest/1 can draw `r1 ≠ i` and
/// `r2 ∉ {i, r1}` (Tanabe & Fukunaga 2014).
pub const N_MIN: usize = 4;

/// The spread of the parameter sampling: `CR_i ~ N(M_CR, 0.1)` and
/// `F_i ~ Cauchy(M_F, 0.1)` (Tanabe & Fukunaga 2013).
pub const SPREAD: f64 = 0.1;

/// The initial value of every memory cell `M_CR,k` and `M_F,k`.
pub const MEMORY_INIT: f64 = 0.5;

/// How a trial coordinate that left the box is brought back.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Repair {
    /// The midpoint between the parent's coordinate and the violated bound,
    /// `(L_j + x_i,j)/2` or `(U_j + x_i,j)/2`: the rule of the authors'
    /// L-SHADE code (after JADE, Zhang & Sanderson 2009), and the default.
    Midpoint,
    /// Projection onto the violated bound, as [`crate::problem::BoundPolicy::Clip`].
    Clip,
    /// Mirroring at the bounds, as [`crate::problem::BoundPolicy::Reflect`].
    Reflect,
}

impl Repair {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["midpoint", "clip", "reflect"];

    fn from_name(name: &str) -> Self {
        match name {
            "clip" => Self::Clip,
            "reflect" => Self::Reflect,
            _ => Self::Midpoint,
        }
    }
}

/// L-SHADE with the parameters of Tanabe & Fukunaga (2014).
///
/// **Population.** `N_init = max(N_min, round(r^N_init · D))` vectors are
/// drawn uniformly in the box and evaluated (all `N_init` evaluations come
/// before the first generation; a smaller budget ends the run there).
/// The paper's `N_init = round(18·D)` is below `N_min = 4` only for a small
/// `r^N_init` or `D`; the population then starts, and stays, at 4.
///
/// **One generation.** With `N = N_G`, the `p·N` best vectors (at least two,
/// ties by index) sorted by value, and for each `i = 0, …, N − 1` in turn:
/// * a memory cell `r ~ U{0, …, H − 1}`;
/// * `CR_i = 0` if `M_CR,r = ⊥` (the "terminal value" of the 2014 paper),
///   else `CR_i = clip(M_CR,r + 0.1·N(0,1), 0, 1)`;
/// * `F_i = M_F,r + 0.1·tan(π(u − 0.5))`, `u ~ U[0,1)` (a Cauchy variate),
///   drawn again while `F_i ≤ 0` and set to 1 if `F_i > 1`;
/// * current-to-pbest/1 with the archive `A`:
///   `v_i = x_i + F_i(x_pbest − x_i) + F_i(x_r1 − x̃_r2)`, `x_pbest` uniform
///   among the `p·N` best, `r1 ~ U{0..N} ∖ {i}`, `r2 ~ U{0..N+|A|} ∖ {i, r1}`
///   (indices `N` and up are archive members), each drawn again until it
///   differs;
/// * binomial crossover: `u_i,j = v_i,j` if `u_j < CR_i` or `j = j_rand`
///   (`j_rand ~ U{0..D}`, `u_j ~ U[0,1)`), else `x_i,j`;
/// * a mutant coordinate outside `[L_j, U_j]` is repaired by [`Repair`]
///   (by default the midpoint between `x_i,j` and the violated bound, as in
///   the authors' code; crossed-over parent coordinates are already inside).
///
/// All `N` trials are made from generation `G` and then evaluated as one
/// batch ([`Problem::objective_batch`]); the run ends exactly at the budget,
/// inside a generation if need be (only the trials the budget still allows
/// are made and evaluated). Then, for each `i` in order, `u_i` replaces `x_i`
/// if `f(u_i) ≤ f(x_i)` (ties accepted, as in the papers' selection rule);
/// on a strict improvement `x_i` goes into the archive, and `CR_i`, `F_i` and
/// `Δf_i = |f(u_i) − f(x_i)|` are recorded in `S_CR`, `S_F`.
///
/// **Memory update.** If `S_F` is not empty, cell `k` (which cycles
/// `0, 1, …, H − 1, 0, …`, one step per generation with a success) becomes
/// `M_F,k = mean_WL(S_F)` and `M_CR,k = mean_WL(S_CR)`, the weighted Lehmer
/// mean `Σ w_s s² / Σ w_s s` with `w_s ∝ Δf_s` (the 2014 paper uses it for
/// `CR` too, where SHADE 2013 had the weighted arithmetic mean); `M_CR,k`
/// becomes `⊥` instead if it is `⊥` already or `max(S_CR) = 0`, and keeps it
/// for the rest of the run. An infinite `Δf` (a trial that turned `+∞` or
/// NaN, which the evaluator maps to `+∞`, into a finite value) carries all
/// the weight, shared equally with the other infinite ones.
///
/// **Archive.** Its capacity is `round(r^arc · N_G)`. A parent entering a
/// full archive overwrites a uniformly chosen member (the authors' code: a
/// random member is deleted to make room); `r^arc = 0` disables it.
///
/// **Linear population size reduction.** After each generation,
/// `N_{G+1} = round((N_min − N_init)/max_nfe · nfe + N_init)` with `nfe` the
/// evaluations used so far and `max_nfe` the evaluator's budget; if it is
/// below `N_G`, the `N_G − N_{G+1}` worst vectors (ties: the higher index
/// goes first) are removed, the others keep their order, and the archive is
/// cut to its new capacity by deleting uniformly chosen members one at a
/// time.
///
/// **Random numbers**, in this order: the initial population, `N_init · D`
/// uniforms row by row ([`Words::units`]); per trial, `r`, the two uniforms
/// of the Gaussian (none when `M_CR,r = ⊥`), the Cauchy uniforms, the p-best
/// rank, `r1`, `r2`, `j_rand` (each index by [`Draw::index`], repeated while
/// rejected), then `D` crossover uniforms ([`Words::units`]); after the
/// batch, one index per parent entering a full archive, in the order of
/// `i`; after the reduction, one index per deleted archive member.
#[derive(Clone, Debug, PartialEq)]
pub struct Lshade {
    /// `r^N_init`: the initial population size per variable.
    pub r_n_init: f64,
    /// The size `H` of the success-history memories `M_CR` and `M_F`.
    pub memory: usize,
    /// `r^arc`: the archive capacity per population member.
    pub arc_rate: f64,
    /// `p`: the fraction of the population the p-best vector is drawn from.
    pub p_best: f64,
    /// Bound handling of mutant coordinates.
    pub repair: Repair,
}

/// The key of the `r_n_init` parameter.
pub const R_N_INIT_KEY: Param<f64> = Param::new("r_n_init");
/// The key of the `memory` parameter.
pub const MEMORY_KEY: Param<u64> = Param::new("memory");
/// The key of the `arc_rate` parameter.
pub const ARC_RATE_KEY: Param<f64> = Param::new("arc_rate");
/// The key of the `p_best` parameter.
pub const P_BEST_KEY: Param<f64> = Param::new("p_best");
/// The key of the `bounds` parameter.
pub const BOUNDS_KEY: Param<&'static str> = Param::new("bounds");

/// The parameters of [`Lshade`], with the published defaults of Tanabe &
/// Fukunaga (2014): `r^N_init = 18`, `H = 6`, `r^arc = 2.6`, `p = 0.11`.
pub static PARAMS: [ParamDef; 5] = [
    ParamDef {
        name: R_N_INIT_KEY.name,
        doc: "initial population per variable r^N_init: N_init = max(4, round(r_n_init·D))",
        kind: Kind::Real {
            min: 0.0,
            max: 1000.0,
            open_min: true,
        },
        default: Setting::Real(18.0),
        omit_at_default: false,
    },
    ParamDef {
        name: MEMORY_KEY.name,
        doc: "size H of the success-history memories M_CR and M_F",
        kind: Kind::Count { min: 1, max: 1000 },
        default: Setting::Count(6),
        omit_at_default: false,
    },
    ParamDef {
        name: ARC_RATE_KEY.name,
        doc: "archive capacity per population member r^arc: |A| = round(arc_rate·N)",
        kind: Kind::Real {
            min: 0.0,
            max: 100.0,
            open_min: false,
        },
        default: Setting::Real(2.6),
        omit_at_default: false,
    },
    ParamDef {
        name: P_BEST_KEY.name,
        doc: "p of current-to-pbest/1: pbest among the max(2, round(p·N)) best",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.11),
        omit_at_default: false,
    },
    ParamDef {
        name: BOUNDS_KEY.name,
        doc: "bound handling of mutant coordinates: \"midpoint\" (between the parent and the violated bound, the L-SHADE code), \"clip\" or \"reflect\"",
        kind: Kind::Choice(&Repair::NAMES),
        default: Setting::Choice("midpoint"),
        omit_at_default: false,
    },
];

impl Default for Lshade {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl Lshade {
    /// Builds L-SHADE from validated parameters. Each parameter's range is
    /// checked on its own (by [`PARAMS`]); no combination is invalid.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        Ok(Self {
            r_n_init: p.get(R_N_INIT_KEY),
            memory: p.get(MEMORY_KEY) as usize,
            arc_rate: p.get(ARC_RATE_KEY),
            p_best: p.get(P_BEST_KEY),
            repair: Repair::from_name(p.get(BOUNDS_KEY)),
        })
    }

    /// `N_init = max(N_min, round(r^N_init · D))`.
    pub fn initial_population(&self, dim: usize) -> usize {
        // A saturating cast: a population beyond usize is never reached, the
        // budget ends the run first.
        ((self.r_n_init * dim as f64).round() as usize).max(N_MIN)
    }

    /// The archive capacity `round(r^arc · N)` for a population of `n`.
    pub fn archive_capacity(&self, n: usize) -> usize {
        (self.arc_rate * n as f64).round() as usize
    }

    /// The size `max(2, round(p · N))` (at most `N`) of the set the p-best
    /// vector is drawn from.
    pub fn p_best_count(&self, n: usize) -> usize {
        ((self.p_best * n as f64).round() as usize).max(2).min(n)
    }
}

/// The planned population size after `nfe` of `max_nfe` evaluations,
/// `round((N_min − N_init)/max_nfe · nfe + N_init)`, at least [`N_MIN`].
pub fn planned_population(n_init: usize, nfe: u64, max_nfe: u64) -> usize {
    if max_nfe == 0 {
        return n_init.max(N_MIN);
    }
    let (lo, hi) = (N_MIN as f64, n_init as f64);
    let n = ((lo - hi) / max_nfe as f64 * nfe as f64 + hi).round();
    (n.max(0.0) as usize).max(N_MIN)
}

/// The weighted Lehmer mean `Σ w_k s_k² / Σ w_k s_k` with `w_k ∝ Δ_k`
/// (Tanabe & Fukunaga 2014), or `None` if the denominator is not positive.
///
/// The weights are `Δ_k / max Δ`, which leaves the mean unchanged and keeps
/// the sums finite; when some `Δ_k` are infinite they share the weight
/// equally and the finite ones get none (the limit of the finite case).
pub fn weighted_lehmer_mean(s: &[f64], delta: &[f64]) -> Option<f64> {
    debug_assert_eq!(s.len(), delta.len());
    let max = delta.iter().copied().fold(0.0, f64::max);
    // `f64::max` ignores NaN, so `max` is a number ≥ 0.
    if max <= 0.0 {
        return None;
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (&v, &d) in s.iter().zip(delta) {
        let w = if max.is_infinite() {
            if d.is_infinite() {
                1.0
            } else {
                0.0
            }
        } else {
            d / max
        };
        num += w * v * v;
        den += w * v;
    }
    (den > 0.0).then(|| num / den)
}

/// The success-history memories `M_CR` (`None` is the terminal value `⊥`)
/// and `M_F`, and the cell `k` the next update writes.
#[derive(Clone, Debug, PartialEq)]
pub struct Memory {
    /// `M_CR,0..H`; `None` is `⊥`.
    pub cr: Vec<Option<f64>>,
    /// `M_F,0..H`.
    pub f: Vec<f64>,
    /// The cell the next update writes.
    pub k: usize,
}

impl Memory {
    /// `H` cells of 0.5 each, writing cell 0 first.
    pub fn new(h: usize) -> Self {
        let h = h.max(1);
        Self {
            cr: vec![Some(MEMORY_INIT); h],
            f: vec![MEMORY_INIT; h],
            k: 0,
        }
    }

    /// The update after a generation with the successful `S_CR`, `S_F` and
    /// their improvements `Δf`; nothing happens without a success.
    pub fn update(&mut self, s_cr: &[f64], s_f: &[f64], delta: &[f64]) {
        if s_f.is_empty() {
            return;
        }
        let k = self.k;
        if let Some(m) = weighted_lehmer_mean(s_f, delta) {
            self.f[k] = m;
        }
        let all_zero = s_cr.iter().all(|&c| c == 0.0);
        self.cr[k] = match self.cr[k] {
            None => None,
            Some(_) if all_zero => None,
            // A zero denominator needs every weighted CR to vanish, which
            // only underflowing weights allow: keep the cell then.
            Some(old) => Some(weighted_lehmer_mean(s_cr, delta).unwrap_or(old)),
        };
        self.k = (k + 1) % self.f.len();
    }
}

/// Orders population indices by value, then by index.
#[inline]
fn by_value(values: &[f64]) -> impl Fn(&usize, &usize) -> Ordering + '_ {
    move |&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b))
}

/// The draws that make one trial vector.
struct TrialDraws {
    cr: f64,
    f: f64,
    pbest: usize,
    r1: usize,
    r2: usize,
    j_rand: usize,
}

/// The population (row-major, `n` rows of `D`) with its values, its
/// p-best ranking, and the external archive of the parents that better
/// trials replaced (Zhang & Sanderson 2009).
struct Population {
    dim: usize,
    n: usize,
    x: Vec<f64>,
    val: Vec<f64>,
    /// The number of p-best candidates, `order[..p_num]`.
    p_num: usize,
    order: Vec<usize>,
    keep: Vec<bool>,
    archive: Vec<f64>,
    archived: usize,
    arc_cap: usize,
}

impl Population {
    /// Row `k` of the population.
    #[inline(always)]
    fn row(&self, k: usize) -> &[f64] {
        &self.x[k * self.dim..(k + 1) * self.dim]
    }

    /// `x̃_r2`: population row `r2`, or archived row `r2 − n`.
    #[inline(always)]
    fn donor(&self, r2: usize) -> &[f64] {
        if r2 < self.n {
            self.row(r2)
        } else {
            let a = r2 - self.n;
            &self.archive[a * self.dim..(a + 1) * self.dim]
        }
    }

    /// The p-best candidates: the `p_num` best, sorted by value, in
    /// `order[..p_num]`.
    #[inline(always)]
    fn rank_p_best(&mut self, p_num: usize) {
        self.p_num = p_num;
        let order = &mut self.order[..self.n];
        for (k, o) in order.iter_mut().enumerate() {
            *o = k;
        }
        if p_num < self.n {
            order.select_nth_unstable_by(p_num - 1, by_value(&self.val));
        }
        order[..p_num].sort_unstable_by(by_value(&self.val));
    }

    /// Selection: a trial no worse than its target replaces it; a strictly
    /// better one also sends the target to the archive (into a free slot,
    /// else over a random one) and adds its `CR`, `F` and improvement to
    /// `successes`.
    #[inline(always)]
    fn select<R: Words + ?Sized>(
        &mut self,
        trials: &Trials,
        successes: &mut Successes,
        rng: &mut R,
    ) {
        let dim = self.dim;
        successes.clear();
        for i in 0..self.n {
            let (fu, fx) = (trials.val[i], self.val[i]);
            if fu > fx {
                continue;
            }
            let xi = i * dim..(i + 1) * dim;
            if fu < fx {
                if self.arc_cap > 0 {
                    let slot = if self.archived < self.arc_cap {
                        self.archived += 1;
                        self.archived - 1
                    } else {
                        rng.index(self.arc_cap)
                    };
                    self.archive[slot * dim..(slot + 1) * dim].copy_from_slice(&self.x[xi.clone()]);
                }
                successes.cr.push(trials.cr[i]);
                successes.f.push(trials.f[i]);
                successes.delta.push(fx - fu);
            }
            self.x[xi.clone()].copy_from_slice(&trials.u[xi]);
            self.val[i] = fu;
        }
    }

    /// Linear population size reduction: keeps the `plan` best in their
    /// order, and deletes random archived rows down to `arc_cap`.
    #[inline(always)]
    fn shrink<R: Words + ?Sized>(&mut self, plan: usize, arc_cap: usize, rng: &mut R) {
        let (n, dim) = (self.n, self.dim);
        let order = &mut self.order[..n];
        for (k, o) in order.iter_mut().enumerate() {
            *o = k;
        }
        order.select_nth_unstable_by(plan, by_value(&self.val));
        self.keep[..n].fill(false);
        for &k in &order[..plan] {
            self.keep[k] = true;
        }
        let mut w = 0;
        for k in 0..n {
            if self.keep[k] {
                if w != k {
                    self.x.copy_within(k * dim..(k + 1) * dim, w * dim);
                    self.val[w] = self.val[k];
                }
                w += 1;
            }
        }
        self.n = plan;
        self.arc_cap = arc_cap;
        while self.archived > arc_cap {
            let k = rng.index(self.archived);
            self.archived -= 1;
            if k != self.archived {
                let last = self.archived;
                self.archive
                    .copy_within(last * dim..(last + 1) * dim, k * dim);
            }
        }
    }
}

/// One generation's trial vectors `u_i`, their values and the `CR_i` and
/// `F_i` that made them, with the crossover uniforms of the trial in hand.
struct Trials {
    u: Vec<f64>,
    val: Vec<f64>,
    cr: Vec<f64>,
    f: Vec<f64>,
    units: Vec<f64>,
}

impl Trials {
    /// Room for `n` trials of `dim` variables.
    fn new(n: usize, dim: usize) -> Self {
        Trials {
            u: vec![0.0; n * dim],
            val: vec![f64::INFINITY; n],
            cr: vec![0.0; n],
            f: vec![0.0; n],
            units: vec![0.0; dim],
        }
    }
}

/// The successful `CR` and `F` of a generation, `S_CR` and `S_F`, with the
/// improvements `Δf` that weight them.
struct Successes {
    cr: Vec<f64>,
    f: Vec<f64>,
    delta: Vec<f64>,
}

impl Successes {
    /// Room for `n` successes.
    fn new(n: usize) -> Self {
        Successes {
            cr: Vec::with_capacity(n),
            f: Vec::with_capacity(n),
            delta: Vec::with_capacity(n),
        }
    }

    /// Forgets the last generation's successes.
    fn clear(&mut self) {
        self.cr.clear();
        self.f.clear();
        self.delta.clear();
    }
}

impl Optimiser for Lshade {
    /// The initial population, its trial vectors and the archive at its
    /// capacity ((2 N_init + ⌈r^arc N_init⌉) × D, N_init = r^N_init · D:
    /// quadratic in D), and a few D-vectors.
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        let n = self.initial_population(dim);
        super::vectors_bytes(2 * n + self.archive_capacity(n) + 4, dim)
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        dispatch(
            #[inline(always)]
            |_| self.evolve(eval, rng),
        )
    }
}

impl Lshade {
    /// The memory cell, `CR_i` and `F_i`, the p-best rank and `r1`, `r2`,
    /// `j_rand` of one trial, drawn in the documented order.
    #[inline(always)]
    fn draw<R: Words + ?Sized>(
        memory: &Memory,
        i: usize,
        n: usize,
        archived: usize,
        p_num: usize,
        dim: usize,
        rng: &mut R,
    ) -> TrialDraws {
        let r = rng.index(memory.f.len());
        let cr = match memory.cr[r] {
            None => 0.0,
            Some(m) => (m + SPREAD * rng.gaussian()).clamp(0.0, 1.0),
        };
        let mf = memory.f[r];
        let f = loop {
            let f = mf + SPREAD * (PI * (rng.unit() - 0.5)).tan();
            if f > 0.0 {
                break f.min(1.0);
            }
        };
        let pbest = rng.index(p_num);
        let r1 = loop {
            let r1 = rng.index(n);
            if r1 != i {
                break r1;
            }
        };
        let r2 = loop {
            let r2 = rng.index(n + archived);
            if r2 != i && r2 != r1 {
                break r2;
            }
        };
        let j_rand = rng.index(dim);
        TrialDraws {
            cr,
            f,
            pbest,
            r1,
            r2,
            j_rand,
        }
    }

    /// The generations of L-SHADE until the budget is spent: the body of
    /// [`Optimiser::minimise`], compiled for the CPU by [`dispatch`].
    #[inline(always)]
    fn evolve<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let bounds = eval.bounds();
        let dim = bounds.len();
        if dim == 0 {
            // Nothing to vary: spend the budget on the only point there is.
            while eval.remaining() > 0 {
                eval.evaluate(&[]);
            }
            return;
        }
        let n_init = self.initial_population(dim);
        let Some(mut pop) = self.initial(eval, rng, n_init) else {
            return;
        };
        let lower: Vec<f64> = bounds.iter().map(|b| b.lower).collect();
        let upper: Vec<f64> = bounds.iter().map(|b| b.upper).collect();
        let mut trials = Trials::new(n_init, dim);
        let mut successes = Successes::new(n_init);
        let mut memory = Memory::new(self.memory);
        loop {
            pop.rank_p_best(self.p_best_count(pop.n));
            let n = pop.n;
            let m = usize::try_from(eval.remaining()).map_or(n, |r| r.min(n));
            self.make_trials(&pop, &mut trials, &memory, m, (&lower, &upper, bounds), rng);
            if eval.evaluate_batch(&trials.u[..m * dim], &mut trials.val[..m]) < n
                || eval.remaining() == 0
            {
                return;
            }
            pop.select(&trials, &mut successes, rng);
            memory.update(&successes.cr, &successes.f, &successes.delta);
            let plan = planned_population(n_init, eval.used(), eval.budget());
            if plan < n {
                pop.shrink(plan, self.archive_capacity(plan), rng);
            }
        }
    }

    /// The initial population: `N_init` uniform points in the box (or as
    /// many as the budget allows, moved to the evaluator's start), with an
    /// empty archive of capacity `⌈r^arc N_init⌉`; `None` when the budget
    /// ends before or with it.
    #[inline(always)]
    fn initial<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
        n_init: usize,
    ) -> Option<Population> {
        let bounds = eval.bounds();
        let dim = bounds.len();
        let first = usize::try_from(eval.remaining()).map_or(n_init, |r| r.min(n_init));
        let mut x = vec![0.0; first * dim];
        let mut val = vec![f64::INFINITY; first];
        rng.units(&mut x);
        for row in x.chunks_exact_mut(dim) {
            for (v, b) in row.iter_mut().zip(bounds) {
                *v = b.lerp(*v);
            }
        }
        eval.place_start(&mut x);
        if eval.evaluate_batch(&x, &mut val) < n_init || eval.remaining() == 0 {
            return None;
        }
        let arc_cap = self.archive_capacity(n_init);
        Some(Population {
            dim,
            n: n_init,
            x,
            val,
            p_num: 0,
            order: (0..n_init).collect(),
            keep: vec![false; n_init],
            archive: vec![0.0; arc_cap * dim],
            archived: 0,
            arc_cap,
        })
    }

    /// The trials of the first `m` targets: each one's draws
    /// ([`Self::draw`]), then its `D` crossover uniforms, then its vector
    /// ([`Self::make_trial`]).
    #[inline(always)]
    fn make_trials<R: Words + ?Sized>(
        &self,
        pop: &Population,
        trials: &mut Trials,
        memory: &Memory,
        m: usize,
        domain: (&[f64], &[f64], &[Bounds]),
        rng: &mut R,
    ) {
        let dim = pop.dim;
        for i in 0..m {
            let d = Self::draw(memory, i, pop.n, pop.archived, pop.p_num, dim, rng);
            rng.units(&mut trials.units);
            trials.cr[i] = d.cr;
            trials.f[i] = d.f;
            self.make_trial(
                &mut trials.u[i * dim..(i + 1) * dim],
                [
                    pop.row(i),
                    pop.row(pop.order[d.pbest]),
                    pop.row(d.r1),
                    pop.donor(d.r2),
                ],
                &trials.units,
                &d,
                domain,
            );
        }
    }

    /// Trial `u_i` from the target, p-best, `r1` and `r2` rows `x`: the
    /// mutant `x_i + F(x_pbest − x_i) + F(x_r1 − x̃_r2)` on the crossed-over
    /// coordinates, repaired, and the target's coordinates elsewhere.
    #[inline(always)]
    fn make_trial(
        &self,
        u: &mut [f64],
        x: [&[f64]; 4],
        units: &[f64],
        d: &TrialDraws,
        (lower, upper, bounds): (&[f64], &[f64], &[Bounds]),
    ) {
        let n = u.len();
        let [xi, pb, a, b] = x.map(|r| &r[..n]);
        let (units, lower, upper) = (&units[..n], &lower[..n], &upper[..n]);
        let (f, cr, j_rand) = (d.f, d.cr, d.j_rand);
        match self.repair {
            Repair::Midpoint => {
                for j in 0..n {
                    let here = xi[j];
                    let v = here + f * (pb[j] - here) + f * (a[j] - b[j]);
                    // A NaN also goes to the lower midpoint.
                    let v = select(
                        v < lower[j] || v.is_nan(),
                        (lower[j] + here) / 2.0,
                        select(v > upper[j], (upper[j] + here) / 2.0, v),
                    );
                    u[j] = select(units[j] < cr || j == j_rand, v, here);
                }
            }
            Repair::Clip => {
                for j in 0..n {
                    let here = xi[j];
                    let v = here + f * (pb[j] - here) + f * (a[j] - b[j]);
                    let v = clamp(Bounds::new(lower[j], upper[j]), v);
                    u[j] = select(units[j] < cr || j == j_rand, v, here);
                }
            }
            Repair::Reflect => {
                for j in 0..n {
                    let here = xi[j];
                    u[j] = if units[j] < cr || j == j_rand {
                        bounds[j].reflect(here + f * (pb[j] - here) + f * (a[j] - b[j]))
                    } else {
                        here
                    };
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::bowl::assert_solves_sphere_10;
    use crate::optim::params::Raw;

    fn build(settings: &[(&str, Raw)]) -> Lshade {
        let mut p = ParamSet::defaults(&PARAMS);
        for (name, raw) in settings {
            p.set(name, raw).unwrap();
        }
        Lshade::from_params(&p).unwrap()
    }

    #[test]
    fn defaults_are_the_published_ones() {
        let a = Lshade::default();
        assert_eq!(
            (a.r_n_init, a.memory, a.arc_rate, a.p_best, a.repair),
            (18.0, 6, 2.6, 0.11, Repair::Midpoint)
        );
        assert_eq!(a.initial_population(10), 180);
        assert_eq!(a.archive_capacity(180), 468);
        assert_eq!(a.p_best_count(180), 20);
        assert_eq!(a.p_best_count(10), 2, "at least two");
        assert_eq!(a.p_best_count(4), 2);
        assert_eq!(
            ParamSet::defaults(&PARAMS).canonical(),
            "r_n_init=18;memory=6;arc_rate=2.6;p_best=0.11;bounds=midpoint"
        );
    }

    #[test]
    fn small_populations_start_at_n_min() {
        let a = build(&[("r_n_init", Raw::Float(0.2))]);
        assert_eq!(a.initial_population(10), 4, "round(2) < 4");
        assert_eq!(a.initial_population(30), 6);
        assert_eq!(Lshade::default().initial_population(1), 18);
    }

    #[test]
    fn the_population_shrinks_linearly_to_n_min() {
        assert_eq!(planned_population(180, 0, 100_000), 180);
        assert_eq!(planned_population(180, 50_000, 100_000), 92);
        assert_eq!(planned_population(180, 100_000, 100_000), 4);
        assert_eq!(planned_population(4, 10, 100), 4);
        assert_eq!(planned_population(10, 5, 0), 10);
        let sizes: Vec<usize> = (0..=100)
            .map(|t| planned_population(180, t * 1000, 100_000))
            .collect();
        assert!(sizes.windows(2).all(|w| w[0] >= w[1]));
    }

    #[test]
    fn the_weighted_lehmer_mean_weights_by_improvement() {
        // Equal weights: Σs²/Σs.
        let m = weighted_lehmer_mean(&[0.2, 0.6], &[1.0, 1.0]).unwrap();
        assert!((m - 0.4 / 0.8).abs() < 1e-15);
        // Weights 1 and 3: (0.04 + 3·0.36)/(0.2 + 3·0.6).
        let m = weighted_lehmer_mean(&[0.2, 0.6], &[2.0, 6.0]).unwrap();
        assert!((m - 1.12 / 2.0).abs() < 1e-14, "{m}");
        // An infinite improvement takes all the weight.
        let m = weighted_lehmer_mean(&[0.2, 0.6, 0.9], &[1.0, f64::INFINITY, 5.0]).unwrap();
        assert_eq!(m, 0.6);
        assert_eq!(weighted_lehmer_mean(&[0.0, 0.0], &[1.0, 2.0]), None);
        assert_eq!(weighted_lehmer_mean(&[], &[]), None);
        // Huge improvements do not overflow.
        let m = weighted_lehmer_mean(&[0.5, 0.5], &[1e308, 1e308]).unwrap();
        assert_eq!(m, 0.5);
    }

    #[test]
    fn the_memory_cycles_and_keeps_the_terminal_value() {
        let mut m = Memory::new(2);
        m.update(&[], &[], &[]);
        assert_eq!(m, Memory::new(2), "no success, no update");
        m.update(&[0.0, 0.0], &[0.3, 0.7], &[1.0, 1.0]);
        assert_eq!(m.cr, vec![None, Some(0.5)], "max S_CR = 0 gives ⊥");
        assert!((m.f[0] - 0.58 / 1.0).abs() < 1e-15);
        assert_eq!(m.k, 1);
        m.update(&[0.9], &[0.4], &[3.0]);
        let close = |a: f64, b: f64| (a - b).abs() < 1e-15;
        assert!(close(m.cr[1].unwrap(), 0.9) && close(m.f[1], 0.4));
        assert_eq!(m.k, 0, "k cycles");
        m.update(&[0.8], &[0.5], &[1.0]);
        assert_eq!(m.cr[0], None, "⊥ stays");
        assert!(close(m.f[0], 0.5));
    }

    #[test]
    fn the_midpoint_rule_stays_between_parent_and_bound() {
        let a = Lshade::default();
        let lower = [0.0, -1.0];
        let upper = [1.0, 3.0];
        let bounds = [Bounds::new(0.0, 1.0), Bounds::new(-1.0, 3.0)];
        let d = TrialDraws {
            cr: 1.0,
            f: 1.0,
            pbest: 0,
            r1: 0,
            r2: 0,
            j_rand: 0,
        };
        let mut u = [0.0; 2];
        // v = x + (pb − x) + (a − b) = pb + a − b = (5, −7).
        a.make_trial(
            &mut u,
            [&[0.5, 2.0], &[1.0, -2.0], &[4.0, 0.0], &[0.0, 5.0]],
            &[0.0, 0.0],
            &d,
            (&lower, &upper, &bounds),
        );
        assert_eq!(u, [0.75, 0.5]);
    }

    /// Default L-SHADE drives Sphere-10 on [−100, 100]¹⁰ below 1e-8 within
    /// 100 000 evaluations for five seeds.
    #[test]
    fn solves_sphere_10() {
        assert_solves_sphere_10(&Lshade::default(), 100_000, 1e-8);
    }

    #[test]
    fn out_of_range_parameters_are_refused() {
        let mut p = ParamSet::defaults(&PARAMS);
        for (name, raw) in [
            ("r_n_init", Raw::Int(0)),
            ("r_n_init", Raw::Float(-1.0)),
            ("memory", Raw::Int(0)),
            ("arc_rate", Raw::Float(-0.1)),
            ("p_best", Raw::Int(0)),
            ("p_best", Raw::Float(1.5)),
            ("bounds", Raw::Text("wrap".into())),
        ] {
            assert!(p.set(name, &raw).is_err(), "{name} = {raw}");
        }
        p.set("p_best", &Raw::Int(1)).unwrap();
        p.set("arc_rate", &Raw::Int(0)).unwrap();
        assert!(Lshade::from_params(&p).is_ok());
    }
}
