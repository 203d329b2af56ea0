//! Real-coded genetic algorithm, GA (Goldberg 1989, "Genetic Algorithms in
//! Search, Optimization and Machine Learning", Addison-Wesley), with BLX-α
//! crossover (Eshelman & Schaffer 1993, "Real-coded genetic algorithms and
//! interval-schemata", Foundations of Genetic Algorithms 2:187–202) and the
//! arithmetic crossover and uniform mutation of Michalewicz (1996, "Genetic
//! Algorithms + Data Structures = Evolution Programs", 3rd ed., Springer).

use crate::optim::params::Param;
use std::cmp::Ordering;

use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{policy_param, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::{Draw, Words};
use crate::simd::dispatch;

/// The recombination operator applied to a pair of parents `x¹, x²`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossover {
    /// Arithmetic crossover (Michalewicz 1996): children `(1 − γ)x¹ + γx²`
    /// and `γx¹ + (1 − γ)x²` with one `γ ~ U(0,1)` per pair.
    Arithmetic,
    /// BLX-α (Eshelman & Schaffer 1993): each child gene is
    /// `x¹_j + γ_j(x²_j − x¹_j)` with an independent `γ_j ~ U(−α, 1 + α)`,
    /// i.e. uniform on the parents' interval extended by `α` of its length
    /// on both sides.
    Blend,
}

impl Crossover {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["arithmetic", "blend"];

    fn from_name(name: &str) -> Self {
        if name == "arithmetic" {
            Self::Arithmetic
        } else {
            Self::Blend
        }
    }
}

/// The mutation applied to each gene with probability `pm`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mutation {
    /// Gaussian mutation `x_j + σ(t)·(U_j − L_j)·N(0,1)` (Bäck & Schwefel
    /// 1993, "An overview of evolutionary algorithms for parameter
    /// optimization", Evolutionary Computation 1(1):1–23), repaired into the
    /// bounds.
    Gaussian,
    /// Uniform mutation (Michalewicz 1996): `x_j` is redrawn uniformly in
    /// `[L_j, U_j]`.
    Uniform,
}

impl Mutation {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["gaussian", "uniform"];

    fn from_name(name: &str) -> Self {
        if name == "uniform" {
            Self::Uniform
        } else {
            Self::Gaussian
        }
    }
}

/// The floor of the linear σ decay, as a fraction of `sigma`:
/// `σ(t) = sigma·max(1 − t/NI, SIGMA_FLOOR)`, so Gaussian mutation never
/// degenerates to the identity.
pub const SIGMA_FLOOR: f64 = 1e-3;

/// Generational real-coded GA with tournament selection, crossover, per-gene
/// mutation and elitism.
///
/// The initial population is drawn uniformly in the bounds and evaluated.
/// Each generation copies the `elite` best individuals unchanged (they are
/// not re-evaluated) and fills the other `pop − elite` places with children:
/// two parents are chosen by tournaments of size `k` drawn with replacement
/// (Goldberg & Deb 1991, "A comparative analysis of selection schemes used
/// in genetic algorithms", FOGA 1:69–93); with probability `pc` they are
/// recombined by the [`Crossover`], otherwise copied; every gene of a child
/// is then mutated with probability `pm` by the [`Mutation`], and genes that
/// left the box are repaired with the bound policy. The children of a
/// generation are evaluated together, in order ([`Problem::objective_batch`]),
/// and the run stops exactly at the budget, possibly within a generation;
/// when `pop − elite` is odd, the second child of the last pair is discarded
/// unevaluated.
///
/// Mutation sites are drawn by geometric skipping: the number of unmutated
/// genes before the next mutated one, counted across children, is
/// `⌊ln(1 − u)/ln(1 − pm)⌋` with `u ~ U(0,1)`. This is the same
/// distribution as one Bernoulli(`pm`) trial per gene but costs one draw
/// per mutation instead of one per gene.
///
/// Ties are broken towards the lower population index: in a tournament
/// between equal values, and in the ranking that picks the elites (by value,
/// then index).
#[derive(Clone, Debug, PartialEq)]
pub struct GeneticAlgorithm {
    /// Population size.
    pub pop: usize,
    /// Tournament size `k`.
    pub tournament: usize,
    /// Crossover rate `pc`, per pair of parents.
    pub pc: f64,
    /// The crossover operator.
    pub crossover: Crossover,
    /// The BLX extension `α` of [`Crossover::Blend`].
    pub blend_alpha: f64,
    /// Mutation rate `pm`, per gene.
    pub pm: f64,
    /// The mutation operator.
    pub mutation: Mutation,
    /// Standard deviation of Gaussian mutation, as a fraction of each range.
    pub sigma: f64,
    /// Whether `σ` decays linearly over the budget (see [`SIGMA_FLOOR`]).
    pub sigma_decay: bool,
    /// Number of elites copied unchanged into the next generation.
    pub elite: usize,
    /// Bound handling for children outside the box.
    pub policy: BoundPolicy,
}

/// The key of the `pop` parameter.
pub const POP_KEY: Param<u64> = Param::new("pop");
/// The key of the `tournament` parameter.
pub const TOURNAMENT_KEY: Param<u64> = Param::new("tournament");
/// The key of the `pc` parameter.
pub const PC_KEY: Param<f64> = Param::new("pc");
/// The key of the `crossover` parameter.
pub const CROSSOVER_KEY: Param<&'static str> = Param::new("crossover");
/// The key of the `blend_alpha` parameter.
pub const BLEND_ALPHA_KEY: Param<f64> = Param::new("blend_alpha");
/// The key of the `pm` parameter.
pub const PM_KEY: Param<f64> = Param::new("pm");
/// The key of the `mutation` parameter.
pub const MUTATION_KEY: Param<&'static str> = Param::new("mutation");
/// The key of the `sigma` parameter.
pub const SIGMA_KEY: Param<f64> = Param::new("sigma");
/// The key of the `sigma_decay` parameter.
pub const SIGMA_DECAY_KEY: Param<&'static str> = Param::new("sigma_decay");
/// The key of the `elite` parameter.
pub const ELITE_KEY: Param<u64> = Param::new("elite");

/// The parameters of [`GeneticAlgorithm`]; the defaults are this project's
/// choices in the usual ranges of the real-coded GA literature. BLX-0.5
/// supplies most of the variation, so mutation is kept rare (`pm = 0.01`,
/// about one mutated gene per three children at `D = 30`) and its σ decays
/// linearly: in preliminary runs on Sphere, Rastrigin, Ackley and Rosenbrock
/// at `D = 30`, rates of 0.02–0.05 or a constant σ slowed the convergence markedly.
pub static PARAMS: [ParamDef; 11] = [
    ParamDef {
        name: POP_KEY.name,
        doc: "population size",
        kind: Kind::Count {
            min: 2,
            max: 100_000,
        },
        default: Setting::Count(50),
        omit_at_default: false,
    },
    ParamDef {
        name: TOURNAMENT_KEY.name,
        doc: "tournament size k (with replacement; at most pop)",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(2),
        omit_at_default: false,
    },
    ParamDef {
        name: PC_KEY.name,
        doc: "crossover rate pc, per pair of parents",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.9),
        omit_at_default: false,
    },
    ParamDef {
        name: CROSSOVER_KEY.name,
        doc: "\"arithmetic\" (one γ ~ U(0,1) per pair) or \"blend\" (BLX-α, γ_j ~ U(−α, 1+α) per gene)",
        kind: Kind::Choice(&Crossover::NAMES),
        default: Setting::Choice("blend"),
        omit_at_default: false,
    },
    ParamDef {
        name: BLEND_ALPHA_KEY.name,
        doc: "BLX-α extension α of the parents' interval",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.5),
        omit_at_default: false,
    },
    ParamDef {
        name: PM_KEY.name,
        doc: "mutation rate pm, per gene",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.01),
        omit_at_default: false,
    },
    ParamDef {
        name: MUTATION_KEY.name,
        doc: "\"gaussian\" (σ·range·N(0,1) step) or \"uniform\" (redraw in the bounds)",
        kind: Kind::Choice(&Mutation::NAMES),
        default: Setting::Choice("gaussian"),
        omit_at_default: false,
    },
    ParamDef {
        name: SIGMA_KEY.name,
        doc: "standard deviation σ of Gaussian mutation, as a fraction of the range",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.1),
        omit_at_default: false,
    },
    ParamDef {
        name: SIGMA_DECAY_KEY.name,
        doc: "\"none\" or \"linear\": σ(t) = σ·max(1 − t/NI, 0.001)",
        kind: Kind::Choice(&["none", "linear"]),
        default: Setting::Choice("linear"),
        omit_at_default: false,
    },
    ParamDef {
        name: ELITE_KEY.name,
        doc: "number of elites copied unchanged (at most pop − 1)",
        kind: Kind::Count {
            min: 0,
            max: 100_000,
        },
        default: Setting::Count(1),
        omit_at_default: false,
    },
    BOUNDS_PARAM,
];

impl Default for GeneticAlgorithm {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl GeneticAlgorithm {
    /// Builds the GA from validated parameters; `tournament ≤ pop` and
    /// `elite < pop` are required.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let s = Self {
            pop: p.get(POP_KEY) as usize,
            tournament: p.get(TOURNAMENT_KEY) as usize,
            pc: p.get(PC_KEY),
            crossover: Crossover::from_name(p.get(CROSSOVER_KEY)),
            blend_alpha: p.get(BLEND_ALPHA_KEY),
            pm: p.get(PM_KEY),
            mutation: Mutation::from_name(p.get(MUTATION_KEY)),
            sigma: p.get(SIGMA_KEY),
            sigma_decay: p.get(SIGMA_DECAY_KEY) == "linear",
            elite: p.get(ELITE_KEY) as usize,
            policy: policy_param(p),
        };
        if s.tournament > s.pop {
            return Err(ParamError::new(
                "tournament",
                format!(
                    "tournament ({}) must not exceed pop ({})",
                    s.tournament, s.pop
                ),
            ));
        }
        if s.elite >= s.pop {
            return Err(ParamError::new(
                "elite",
                format!(
                    "elite ({}) must be smaller than pop ({}), or no child is ever made",
                    s.elite, s.pop
                ),
            ));
        }
        Ok(s)
    }

    /// The Gaussian mutation σ, as a fraction of the range, at progress `t/NI`.
    #[inline]
    pub fn sigma_at(&self, progress: f64) -> f64 {
        if self.sigma_decay {
            self.sigma * (1.0 - progress).max(SIGMA_FLOOR)
        } else {
            self.sigma
        }
    }
}

/// The winner of a tournament of `k` indices drawn with replacement: the
/// smallest value, the smallest index among equal values.
#[inline]
fn tournament<R: Words + ?Sized>(values: &[f64], k: usize, rng: &mut R) -> usize {
    let n = values.len();
    let mut best = rng.index(n);
    for _ in 1..k {
        let c = rng.index(n);
        if values[c] < values[best] || (values[c] == values[best] && c < best) {
            best = c;
        }
    }
    best
}

/// The per-gene mutation, with its sites drawn by geometric skipping.
struct Mutator {
    pm: f64,
    /// `ln(1 − pm)`.
    ln_keep: f64,
    /// Genes left to skip before the next mutation, carried across children.
    skip: usize,
    kind: Mutation,
    policy: BoundPolicy,
}

impl Mutator {
    fn new<R: Words + ?Sized>(ga: &GeneticAlgorithm, rng: &mut R) -> Self {
        let mut m = Self {
            pm: ga.pm,
            ln_keep: (-ga.pm).ln_1p(),
            skip: 0,
            kind: ga.mutation,
            policy: ga.policy,
        };
        m.skip = m.gap(rng);
        m
    }

    /// The number of unmutated genes before the next mutated one,
    /// `Geometric(pm)` on `{0, 1, …}`.
    #[inline]
    fn gap<R: Words + ?Sized>(&self, rng: &mut R) -> usize {
        if self.pm >= 1.0 {
            0
        } else {
            // Saturating float-to-int cast: a huge gap just means "not soon".
            ((1.0 - rng.unit()).ln() / self.ln_keep) as usize
        }
    }

    /// Mutates the genes of `child` that fall on mutation sites; `sigma[j]`
    /// is the absolute Gaussian σ of variable `j`.
    #[inline]
    fn apply<R: Words + ?Sized>(
        &mut self,
        child: &mut [f64],
        bounds: &[Bounds],
        sigma: &[f64],
        rng: &mut R,
    ) {
        if self.pm <= 0.0 {
            return;
        }
        let dim = child.len();
        let mut j = self.skip;
        while j < dim {
            let b = bounds[j];
            child[j] = match self.kind {
                Mutation::Gaussian => b.repair(child[j] + sigma[j] * rng.gaussian(), self.policy),
                Mutation::Uniform => b.lerp(rng.unit()),
            };
            j = j.saturating_add(1).saturating_add(self.gap(rng));
        }
        self.skip = j - dim;
    }
}

/// One BLX child `x¹_j + γ_j(x²_j − x¹_j)`, repaired into the bounds.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn blend(
    child: &mut [f64],
    xa: &[f64],
    xb: &[f64],
    gamma: &[f64],
    lower: &[f64],
    upper: &[f64],
    bounds: &[Bounds],
    policy: BoundPolicy,
) {
    let n = child.len();
    let (xa, xb, gamma) = (&xa[..n], &xb[..n], &gamma[..n]);
    match policy {
        BoundPolicy::Clip => {
            let (lower, upper) = (&lower[..n], &upper[..n]);
            for j in 0..n {
                // `max`/`min` clip without branches (and so vectorise).
                child[j] = (xa[j] + gamma[j] * (xb[j] - xa[j]))
                    .max(lower[j])
                    .min(upper[j]);
            }
        }
        BoundPolicy::Reflect => {
            for ((((c, &a), &b), &g), bd) in child.iter_mut().zip(xa).zip(xb).zip(gamma).zip(bounds)
            {
                *c = bd.reflect(a + g * (b - a));
            }
        }
    }
}

/// Orders population indices by value, then by index.
#[inline]
fn by_value(values: &[f64]) -> impl Fn(&usize, &usize) -> Ordering + '_ {
    move |&a, &b| values[a].total_cmp(&values[b]).then(a.cmp(&b))
}

impl Optimiser for GeneticAlgorithm {
    /// Parents and offspring (2 × pop × D) and a few D-vectors.
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        super::vectors_bytes(2 * self.pop + 4, dim)
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

impl GeneticAlgorithm {
    /// The generations of the GA until the budget is spent: the body of
    /// [`Optimiser::minimise`], compiled for the CPU by [`dispatch`].
    #[inline(always)]
    fn evolve<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let pop = self.pop.max(2);
        let elite = self.elite.min(pop - 1);
        let k = self.tournament.clamp(1, pop);
        let bounds = eval.bounds();
        let dim = bounds.len();
        // Two flat populations with one spare row each, for the discarded
        // second child of an odd last pair.
        let mut cur = vec![0.0; (pop + 1) * dim];
        let mut next = vec![0.0; (pop + 1) * dim];
        let mut cur_val = vec![f64::INFINITY; pop];
        let mut next_val = vec![f64::INFINITY; pop];
        let mut order: Vec<usize> = (0..pop).collect();
        let mut sigma = vec![0.0; dim];
        let mut gammas = vec![0.0; 2 * dim];
        let lower: Vec<f64> = bounds.iter().map(|b| b.lower).collect();
        let upper: Vec<f64> = bounds.iter().map(|b| b.upper).collect();

        for row in cur.chunks_exact_mut(dim.max(1)).take(pop) {
            let row = &mut row[..dim];
            rng.units(row);
            for (x, b) in row.iter_mut().zip(bounds) {
                *x = b.lerp(*x);
            }
        }
        eval.place_start(&mut cur);
        if eval.evaluate_batch(&cur[..pop * dim], &mut cur_val) < pop {
            return;
        }
        if dim == 0 {
            // Nothing to vary: spend the budget on the only point there is.
            while eval.remaining() > 0 {
                eval.evaluate(&[]);
            }
            return;
        }

        let mut mutator = Mutator::new(self, rng);
        let (lo, span) = (-self.blend_alpha, 1.0 + 2.0 * self.blend_alpha);
        loop {
            let s = self.sigma_at(eval.progress());
            for (sj, b) in sigma.iter_mut().zip(bounds) {
                *sj = s * b.width();
            }
            if elite > 0 {
                for (i, o) in order.iter_mut().enumerate() {
                    *o = i;
                }
                order.select_nth_unstable_by(elite - 1, by_value(&cur_val));
                order[..elite].sort_unstable_by(by_value(&cur_val));
                for (e, &src) in order[..elite].iter().enumerate() {
                    next[e * dim..(e + 1) * dim].copy_from_slice(&cur[src * dim..(src + 1) * dim]);
                    next_val[e] = cur_val[src];
                }
            }
            let mut i = elite;
            while i < pop {
                let p1 = tournament(&cur_val, k, rng);
                let p2 = tournament(&cur_val, k, rng);
                let xa = &cur[p1 * dim..(p1 + 1) * dim];
                let xb = &cur[p2 * dim..(p2 + 1) * dim];
                let (c1, rest) = next[i * dim..(i + 2) * dim].split_at_mut(dim);
                let c2 = rest;
                if rng.chance(self.pc) {
                    match self.crossover {
                        Crossover::Arithmetic => {
                            let g = rng.unit();
                            for ((((y1, y2), &a), &b), bd) in
                                c1.iter_mut().zip(c2.iter_mut()).zip(xa).zip(xb).zip(bounds)
                            {
                                let d = b - a;
                                *y1 = bd.repair(a + g * d, self.policy);
                                *y2 = bd.repair(b - g * d, self.policy);
                            }
                        }
                        Crossover::Blend => {
                            // Draw all γ first, in a tight generator loop,
                            // then combine in a branch-free loop.
                            rng.units(&mut gammas);
                            for g in gammas.iter_mut() {
                                *g = lo + span * *g;
                            }
                            let (g1, g2) = gammas.split_at(dim);
                            blend(c1, xa, xb, g1, &lower, &upper, bounds, self.policy);
                            blend(c2, xa, xb, g2, &lower, &upper, bounds, self.policy);
                        }
                    }
                } else {
                    c1.copy_from_slice(xa);
                    c2.copy_from_slice(xb);
                }
                let pair = i + 1 < pop;
                mutator.apply(c1, bounds, &sigma, rng);
                if pair {
                    mutator.apply(c2, bounds, &sigma, rng);
                }
                i += 2;
            }
            // The children depend only on the current generation, so they
            // are evaluated together, in order (as one by one would).
            if eval.evaluate_batch(&next[elite * dim..pop * dim], &mut next_val[elite..pop])
                < pop - elite
                || eval.remaining() == 0
            {
                return;
            }
            std::mem::swap(&mut cur, &mut next);
            std::mem::swap(&mut cur_val, &mut next_val);
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::optim::bowl::assert_solves_sphere_10;

    use super::*;
    use crate::optim::params::Raw;
    use crate::rng::run_rng;

    fn ga(settings: &[(&str, Raw)]) -> GeneticAlgorithm {
        let mut p = ParamSet::defaults(&PARAMS);
        for (name, raw) in settings {
            p.set(name, raw).unwrap();
        }
        GeneticAlgorithm::from_params(&p).unwrap()
    }

    /// The default GA drives Sphere-10 below 1e-6 in 100 000 evaluations,
    /// for each of five seeds.
    #[test]
    fn solves_sphere_10() {
        assert_solves_sphere_10(&GeneticAlgorithm::default(), 100_000, 1e-6);
    }

    #[test]
    fn geometric_skipping_mutates_at_rate_pm() {
        let algo = ga(&[
            ("pm", Raw::Float(0.1)),
            ("mutation", Raw::Text("uniform".into())),
        ]);
        let bounds = vec![Bounds::new(1.0, 2.0); 7];
        let mut rng = run_rng(3);
        let mut m = Mutator::new(&algo, &mut rng);
        let (mut hits, mut genes) = (0usize, 0usize);
        let mut child = [0.0; 7];
        for _ in 0..50_000 {
            child.fill(0.0);
            m.apply(&mut child, &bounds, &[0.0; 7], &mut rng);
            hits += child.iter().filter(|v| **v != 0.0).count();
            genes += child.len();
        }
        let rate = hits as f64 / genes as f64;
        assert!((rate - 0.1).abs() < 0.003, "rate {rate}");
    }

    #[test]
    fn rejects_invalid_combinations() {
        let build = |settings: &[(&str, Raw)]| {
            let mut p = ParamSet::defaults(&PARAMS);
            for (name, raw) in settings {
                p.set(name, raw).unwrap();
            }
            GeneticAlgorithm::from_params(&p)
        };
        let e = build(&[("pop", Raw::Int(4)), ("tournament", Raw::Int(5))]).unwrap_err();
        assert_eq!(e.param, "tournament");
        let e = build(&[("pop", Raw::Int(4)), ("elite", Raw::Int(4))]).unwrap_err();
        assert_eq!(e.param, "elite");
        assert!(build(&[
            ("pop", Raw::Int(4)),
            ("tournament", Raw::Int(4)),
            ("elite", Raw::Int(3))
        ])
        .is_ok());
        let mut p = ParamSet::defaults(&PARAMS);
        assert!(p.set("pop", &Raw::Int(1)).is_err());
        assert!(p.set("sigma", &Raw::Float(0.0)).is_err());
        assert_eq!(GeneticAlgorithm::default().pop, 50);
    }
}
