//! The conformance suite every registered optimiser passes: the contract of
//! [`Optimiser::minimise`](super::Optimiser::minimise) checked once,
//! generically, over an [`OptimiserDef`], so that a newly registered
//! optimiser is checked without a test written for it.
//!
//! [`check`] runs each property on every setting of [`settings`]: the
//! defaults, each name of every choice parameter (so each bound policy an
//! optimiser offers), each single name and the whole list of every sequence
//! parameter, and each count parameter (the smallest population) and each
//! real parameter with a closed range at its minimum (a rate of 0, an empty
//! archive), one change at a time, leaving out the combinations the
//! optimiser's factory refuses. The properties:
//!
//! | property | the run | holds when |
//! |---|---|---|
//! | [`Property::Budget`] | budgets 0, 1, 2, 3, 7, 13, 71, 72, 73 and 1001 (below a population, odd, L-SHADE's `N_init = 72` at D = 4 and either side) | the outcome counts exactly the budget and the objective is called exactly that often |
//! | [`Property::Bounds`] | 5,000 evaluations on four variables whose ranges differ by five orders of magnitude (one of zero width), the optimum beyond a corner | no point evaluated, and not the best, lies outside its variable's range |
//! | [`Property::NanRegion`] | 3,000 evaluations on a bowl that is NaN on three quarters of the box and `+∞` on another strip | the run spends its budget, its best is finite, lies in the finite region, is the objective's value at the best point, and no trace point is NaN |
//! | [`Property::Seed`] | 3,000 evaluations, seeds 5, 5 and 6 | the same seed gives the same outcome bit for bit (best point, value, trace, hits), another seed another best point |
//! | [`Property::NoVariables`] | a problem with no variables, budget 5 | the run spends the budget on the only point there is |
//! | [`Property::SimdLevels`] | 4,000 evaluations on the built-in Rastrigin-7 and Sphere-33 (a partial block of four; two blocks of 32), at every [`Simd`] level the CPU offers | every level gives the portable level's outcome bit for bit |
//!
//! ```
//! use metabezier_core::optim::{conformance, random, OptimiserDef, RandomSearch};
//!
//! let def = OptimiserDef::new("my-random", &random::PARAMS, "Brooks 1958", RandomSearch::from_params);
//! assert_eq!(conformance::check(&def), Ok(()));
//! ```

use std::any::Any;
use std::cell::Cell;
use std::fmt;

use super::{Algorithm, Kind, OptimiserDef, Outcome, ParamSet, Raw};
use crate::functions::{Function, TestProblem};
use crate::problem::{Bounds, Problem};
use crate::rng::run_rng;
use crate::simd::{simd, with_level, Simd};

/// A property of the conformance suite.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Property {
    /// Exactly the budget is spent, whatever its size.
    Budget,
    /// Every evaluated point lies inside per-variable bounds.
    Bounds,
    /// A NaN region ranks last: the run completes with a finite best.
    NanRegion,
    /// The same seed gives the same outcome, another seed another.
    Seed,
    /// A problem with no variables still spends its budget.
    NoVariables,
    /// Every SIMD level the CPU offers gives the same run, bit for bit.
    SimdLevels,
}

impl Property {
    /// Every property, in the order [`check`] runs them.
    pub const ALL: [Property; 6] = [
        Property::Budget,
        Property::Bounds,
        Property::NanRegion,
        Property::Seed,
        Property::NoVariables,
        Property::SimdLevels,
    ];

    /// The property's name in a [`ConformanceFailure`]'s message.
    pub fn name(self) -> &'static str {
        match self {
            Property::Budget => "budget exactness",
            Property::Bounds => "bounds",
            Property::NanRegion => "NaN region",
            Property::Seed => "seed",
            Property::NoVariables => "no variables",
            Property::SimdLevels => "SIMD levels",
        }
    }
}

impl fmt::Display for Property {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A property an optimiser breaks, located by the optimiser's name and the
/// canonical text of its parameters ([`ParamSet::canonical`]).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("optimiser \"{optimiser}\" [{setting}] fails {property}: {message}")]
pub struct ConformanceFailure {
    /// The registered name.
    pub optimiser: String,
    /// The parameters of the failing run, as [`ParamSet::canonical`] writes them.
    pub setting: String,
    /// The property broken.
    pub property: Property,
    /// What the run did.
    pub message: String,
}

/// Checks every [`Property`] of `def` on every setting of [`settings`]; the
/// first failure, located, or `Ok`.
pub fn check(def: &OptimiserDef) -> Result<(), ConformanceFailure> {
    Property::ALL
        .into_iter()
        .try_for_each(|property| check_property(def, property))
}

/// Checks one `property` of `def` on every setting of [`settings`].
pub fn check_property(def: &OptimiserDef, property: Property) -> Result<(), ConformanceFailure> {
    for p in settings(def) {
        let algo = def.build(&p).map_err(|e| ConformanceFailure {
            optimiser: def.name.clone(),
            setting: p.canonical(),
            property,
            message: format!("its factory refuses the setting: {e}"),
        })?;
        let run = match property {
            Property::Budget => budget(&algo),
            Property::Bounds => bounds(&algo),
            Property::NanRegion => nan_region(&algo),
            Property::Seed => seed(&algo),
            Property::NoVariables => no_variables(&algo),
            Property::SimdLevels => simd_levels(&algo),
        };
        run.map_err(|message| ConformanceFailure {
            optimiser: def.name.clone(),
            setting: p.canonical(),
            property,
            message,
        })?;
    }
    Ok(())
}

/// The settings the suite runs `def` at: its defaults, then one change at
/// a time (each name of a choice; each single name and the whole list of
/// a sequence; a count, and a real with a closed range, at its minimum),
/// each once, without those its factory refuses.
pub fn settings(def: &OptimiserDef) -> Vec<ParamSet> {
    let defaults = ParamSet::defaults(def.params);
    let mut out = vec![defaults.clone()];
    for d in def.params {
        for raw in probes(d.kind) {
            let mut p = defaults.clone();
            let fresh = p.set(d.name, &raw).is_ok()
                && out.iter().all(|q| q.canonical() != p.canonical())
                && def.build(&p).is_ok();
            if fresh {
                out.push(p);
            }
        }
    }
    out
}

/// The values of a parameter of kind `kind` that [`settings`] tries.
fn probes(kind: Kind) -> Vec<Raw> {
    match kind {
        Kind::Choice(names) => names.iter().map(|n| Raw::Text((*n).to_owned())).collect(),
        Kind::Sequence(names) => names
            .iter()
            .map(|n| Raw::Text((*n).to_owned()))
            .chain([Raw::Text(names.join("+"))])
            .collect(),
        Kind::Count { min, .. } => i64::try_from(min).map(Raw::Int).into_iter().collect(),
        Kind::Real {
            min,
            open_min: false,
            ..
        } => vec![Raw::Float(min)],
        Kind::Real { open_min: true, .. } => Vec::new(),
    }
}

/// A problem that counts its objective calls and the points outside its
/// bounds, around an objective `f` on `bounds`.
struct Watched<F> {
    bounds: Vec<Bounds>,
    f: F,
    calls: Cell<u64>,
    outside: Cell<u64>,
}

impl<F: Fn(&[f64]) -> f64> Watched<F> {
    fn new(bounds: Vec<Bounds>, f: F) -> Self {
        Watched {
            bounds,
            f,
            calls: Cell::new(0),
            outside: Cell::new(0),
        }
    }

    /// The first variable of `x` outside its bounds, if any.
    fn first_outside(&self, x: &[f64]) -> Option<usize> {
        x.iter()
            .zip(&self.bounds)
            .position(|(v, b)| !b.contains(*v))
    }
}

impl<F: Fn(&[f64]) -> f64> Problem for Watched<F> {
    fn dim(&self) -> usize {
        self.bounds.len()
    }
    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }
    fn objective(&self, x: &[f64]) -> f64 {
        self.calls.set(self.calls.get() + 1);
        if self.first_outside(x).is_some() {
            self.outside.set(self.outside.get() + 1);
        }
        (self.f)(x)
    }
}

/// Four variables whose ranges differ by five orders of magnitude, one of
/// zero width.
fn skewed_bounds() -> Vec<Bounds> {
    vec![
        Bounds::new(-1e-3, 2e-3),
        Bounds::new(0.0, 10.0),
        Bounds::new(-500.0, 20.0),
        Bounds::new(3.0, 3.0),
    ]
}

/// `Σ (x_j − c_j)²` with the centre `c` one unit beyond every upper bound,
/// so that the search keeps pressing against the box.
fn beyond_the_corner(bounds: &[Bounds]) -> impl Fn(&[f64]) -> f64 {
    let centre: Vec<f64> = bounds.iter().map(|b| b.upper + 1.0).collect();
    move |x: &[f64]| x.iter().zip(&centre).map(|(v, c)| (v - c) * (v - c)).sum()
}

/// `Σ x_j²`.
fn sphere(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum()
}

/// Runs `algo` on `problem` with `budget` evaluations from `seed`.
fn run<P: Problem + Any>(algo: &Algorithm, problem: &P, budget: u64, seed: u64) -> Outcome {
    algo.run(problem, budget, &mut run_rng(seed))
}

/// The budgets [`Property::Budget`] runs.
const BUDGETS: [u64; 10] = [0, 1, 2, 3, 7, 13, 71, 72, 73, 1001];

/// [`Property::Budget`].
fn budget(algo: &Algorithm) -> Result<(), String> {
    for budget in BUDGETS {
        let bounds = skewed_bounds();
        let f = beyond_the_corner(&bounds);
        let p = Watched::new(bounds, f);
        let out = run(algo, &p, budget, budget);
        if out.evaluations != budget {
            return Err(format!(
                "the outcome counts {} evaluations with a budget of {budget}",
                out.evaluations
            ));
        }
        if p.calls.get() != budget {
            return Err(format!(
                "{} objective calls with a budget of {budget}",
                p.calls.get()
            ));
        }
    }
    Ok(())
}

/// [`Property::Bounds`].
fn bounds(algo: &Algorithm) -> Result<(), String> {
    let bounds = skewed_bounds();
    let f = beyond_the_corner(&bounds);
    let p = Watched::new(bounds, f);
    let out = run(algo, &p, 5000, 3);
    if p.outside.get() > 0 {
        return Err(format!(
            "{} of 5000 evaluated points lie outside the bounds",
            p.outside.get()
        ));
    }
    match p.first_outside(&out.best_x) {
        Some(j) => Err(format!(
            "the best point's variable {j} is {}, outside [{}, {}]",
            out.best_x[j], p.bounds[j].lower, p.bounds[j].upper
        )),
        None => Ok(()),
    }
}

/// The first variable's value above which [`Property::NanRegion`]'s
/// objective is NaN.
const NAN_ABOVE: f64 = -50.0;

/// Sphere on `[−100, 100]³`, NaN where `x_0 > −50` (three quarters of the
/// box) and `+∞` where `x_1 > 90`.
fn half_nan(x: &[f64]) -> f64 {
    if x[0] > NAN_ABOVE {
        f64::NAN
    } else if x[1] > 90.0 {
        f64::INFINITY
    } else {
        sphere(x)
    }
}

/// [`Property::NanRegion`].
fn nan_region(algo: &Algorithm) -> Result<(), String> {
    let p = Watched::new(vec![Bounds::new(-100.0, 100.0); 3], half_nan);
    let out = run(algo, &p, 3000, 8);
    if out.evaluations != 3000 {
        return Err(format!(
            "the run ended after {} of 3000 evaluations",
            out.evaluations
        ));
    }
    if !out.best_value.is_finite() {
        return Err(format!("the best value is {}", out.best_value));
    }
    if out.best_x[0] > NAN_ABOVE || out.best_x[0].is_nan() {
        return Err(format!(
            "the best point has x_0 = {}, in the NaN region",
            out.best_x[0]
        ));
    }
    if half_nan(&out.best_x).to_bits() != out.best_value.to_bits() {
        return Err(format!(
            "the best value {} is not the objective's {} at the best point",
            out.best_value,
            half_nan(&out.best_x)
        ));
    }
    match out.trace.iter().find(|t| t.best.is_nan()) {
        Some(t) => Err(format!("the trace is NaN at {} evaluations", t.evaluations)),
        None => Ok(()),
    }
}

/// The bits of everything a run reports, so that `-0.0` and `0.0` (or two
/// NaNs) are told apart.
fn outcome_bits(o: &Outcome) -> Vec<u64> {
    let mut bits: Vec<u64> = o.best_x.iter().map(|v| v.to_bits()).collect();
    bits.push(o.best_value.to_bits());
    bits.push(o.evaluations);
    bits.push(o.evaluations_to_target.unwrap_or(u64::MAX));
    for t in &o.trace {
        bits.extend([t.evaluations, t.best.to_bits()]);
    }
    for h in &o.hits {
        bits.extend([h.precision.to_bits(), h.evaluations]);
    }
    bits
}

/// [`Property::Seed`].
fn seed(algo: &Algorithm) -> Result<(), String> {
    let p = Watched::new(vec![Bounds::new(-100.0, 100.0); 5], sphere);
    let a = run(algo, &p, 3000, 5);
    let b = run(algo, &p, 3000, 5);
    if outcome_bits(&a) != outcome_bits(&b) {
        return Err(format!(
            "two runs from seed 5 differ: best {:e} at {:?}, then {:e} at {:?}",
            a.best_value, a.best_x, b.best_value, b.best_x
        ));
    }
    let c = run(algo, &p, 3000, 6);
    if a.best_x == c.best_x {
        return Err(format!(
            "seeds 5 and 6 give the same best point {:?}",
            a.best_x
        ));
    }
    Ok(())
}

/// [`Property::NoVariables`].
fn no_variables(algo: &Algorithm) -> Result<(), String> {
    let p = Watched::new(Vec::new(), |_: &[f64]| 4.0);
    let out = run(algo, &p, 5, 1);
    if (out.evaluations, p.calls.get(), out.best_value) != (5, 5, 4.0) {
        return Err(format!(
            "with budget 5 the run counts {} evaluations, calls the objective {} times and reports {}",
            out.evaluations,
            p.calls.get(),
            out.best_value
        ));
    }
    Ok(())
}

/// [`Property::SimdLevels`].
fn simd_levels(algo: &Algorithm) -> Result<(), String> {
    let levels: Vec<Simd> = [Simd::Portable, Simd::Avx2, Simd::Avx512]
        .into_iter()
        .filter(|&l| l <= simd())
        .collect();
    for (function, dim) in [(Function::Rastrigin, 7), (Function::Sphere, 33)] {
        let Ok(p) = TestProblem::new(function, dim) else {
            return Err(format!("{function}-{dim} cannot be set up"));
        };
        let portable = with_level(Simd::Portable, || outcome_bits(&run(algo, &p, 4000, 9)));
        for &level in &levels[1..] {
            if with_level(level, || outcome_bits(&run(algo, &p, 4000, 9))) != portable {
                return Err(format!(
                    "{function}-{dim} at {level:?} differs from the portable run"
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
