//! Optimisers by name: the registry that specs, the campaign runner, the
//! fitting pipeline and `metabezier list` read. The built-in optimisers
//! enter it the same way as a library user's own ([`Optimisers::register`]),
//! so nothing downstream matches on a closed list of algorithms.
//!
//! An optimiser is registered as a factory from a [`ParamSet`] (checked
//! against its [`ParamDef`] table) to a value of a type that implements
//! [`Optimiser`]. The factory's value is kept behind the object-safe
//! [`DynOptimiser`], whose methods are the generic
//! [`Optimiser::minimise`] instantiated once per problem type: each
//! optimiser's inner loop stays monomorphic, and the registry adds one
//! indirect call per *run*, not per evaluation, on the built-in benchmark
//! functions ([`TestProblem`]). Every other problem (COCO's bbob, a
//! fitting segment, a user's own) is reached through `dyn Problem`, one
//! indirect call per objective evaluation, which is small beside the cost
//! of those objectives (a call into COCO's C code, or a curve evaluated at
//! every data point).

use std::any::Any;
use std::fmt;
use std::sync::{Arc, OnceLock};

use super::{Evaluator, Optimiser, Outcome, ParamDef, ParamError, ParamSet};
use crate::functions::TestProblem;
use crate::problem::Problem;
use crate::rng::RunRng;

/// An optimiser behind a pointer: [`Optimiser::minimise`] for the problem
/// types a campaign runs, with the run generator [`RunRng`]. Implemented by
/// every `Send + Sync` [`Optimiser`]; object-safe.
pub trait DynOptimiser: Send + Sync + fmt::Debug {
    /// Minimises any problem through its evaluator (one indirect call per
    /// objective evaluation).
    fn minimise_dyn(&self, eval: &mut Evaluator<'_, dyn Problem + '_>, rng: &mut RunRng);

    /// Minimises a built-in benchmark function, with the problem's type
    /// known to the optimiser's loop.
    fn minimise_benchmark(&self, eval: &mut Evaluator<'_, TestProblem>, rng: &mut RunRng);

    /// [`Optimiser::state_bytes`].
    fn state_bytes_dyn(&self, dim: usize, budget: u64) -> u128;
}

impl<O: Optimiser + Send + Sync + fmt::Debug> DynOptimiser for O {
    fn minimise_dyn(&self, eval: &mut Evaluator<'_, dyn Problem + '_>, rng: &mut RunRng) {
        self.minimise(eval, rng)
    }

    fn minimise_benchmark(&self, eval: &mut Evaluator<'_, TestProblem>, rng: &mut RunRng) {
        self.minimise(eval, rng)
    }

    fn state_bytes_dyn(&self, dim: usize, budget: u64) -> u128 {
        self.state_bytes(dim, budget)
    }
}

/// A configured optimiser with its registered name: the unit an
/// experiment spec names and the runner runs.
///
/// ```
/// use metabezier_core::functions::{Function, TestProblem};
/// use metabezier_core::optim::Algorithm;
/// use metabezier_core::rng::run_rng;
///
/// let sphere = TestProblem::new(Function::Sphere, 5).unwrap();
/// let mhs = Algorithm::default_for("mhs").unwrap();
/// let out = mhs.run(&sphere, 2_000, &mut run_rng(7));
/// assert_eq!(out.evaluations, 2_000);
/// // The same seed gives the same run, bit for bit.
/// let again = mhs.run(&sphere, 2_000, &mut run_rng(7));
/// assert_eq!(out.best_value.to_bits(), again.best_value.to_bits());
/// ```
#[derive(Clone, Debug)]
pub struct Algorithm {
    name: Arc<str>,
    optimiser: Arc<dyn DynOptimiser>,
}

impl Algorithm {
    /// `optimiser` under the name `name`.
    pub fn new(name: &str, optimiser: impl DynOptimiser + 'static) -> Algorithm {
        Algorithm {
            name: name.into(),
            optimiser: Arc::new(optimiser),
        }
    }

    /// The names of the built-in optimisers, in registration order.
    pub fn names() -> Vec<&'static str> {
        Optimisers::builtin().names()
    }

    /// The parameter declarations of the built-in optimiser `name`.
    pub fn params(name: &str) -> Option<&'static [ParamDef]> {
        Optimisers::builtin().get(name).map(|d| d.params)
    }

    /// Builds the built-in optimiser `name` from a parameter set made from
    /// [`Algorithm::params`]`(name)`.
    pub fn from_params(name: &str, p: &ParamSet) -> Result<Algorithm, ParamError> {
        Optimisers::builtin().build(name, p)
    }

    /// The built-in optimiser `name` with its default parameters.
    pub fn default_for(name: &str) -> Option<Algorithm> {
        Optimisers::builtin().default_for(name)
    }

    /// The registered name of this optimiser.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The most bytes of state one run allocates at dimension `dim` with
    /// `budget` evaluations ([`Optimiser::state_bytes`]): CMA-ES's 2 D²,
    /// L-SHADE's r^N_init · D², a population's size × D.
    pub fn state_bytes(&self, dim: usize, budget: u64) -> u128 {
        self.optimiser.state_bytes_dyn(dim, budget)
    }

    /// Minimises `eval`'s problem, of any type, until its budget is spent.
    pub fn minimise(&self, eval: &mut Evaluator<'_, dyn Problem + '_>, rng: &mut RunRng) {
        self.optimiser.minimise_dyn(eval, rng)
    }

    /// Minimises a built-in benchmark function until the budget is spent.
    pub fn minimise_benchmark(&self, eval: &mut Evaluator<'_, TestProblem>, rng: &mut RunRng) {
        self.optimiser.minimise_benchmark(eval, rng)
    }

    /// Minimises `problem` with `budget` evaluations and returns the
    /// outcome: the same value [`Optimiser::run`] of the configured
    /// optimiser gives. A built-in benchmark function runs through
    /// [`Algorithm::minimise_benchmark`], any other problem through
    /// [`Algorithm::minimise`].
    pub fn run<P: Problem + Any>(&self, problem: &P, budget: u64, rng: &mut RunRng) -> Outcome {
        if let Some(test) = (problem as &dyn Any).downcast_ref::<TestProblem>() {
            let mut eval = Evaluator::new(test, budget);
            self.minimise_benchmark(&mut eval, rng);
            return eval.finish();
        }
        let mut eval = Evaluator::new(problem as &dyn Problem, budget);
        self.minimise(&mut eval, rng);
        eval.finish()
    }
}

/// What runs a problem of type `P` with a generator of type `R` to its
/// outcome: every [`Optimiser`] (any generator) and every [`Algorithm`]
/// (the run generator), so that a solver built on it takes either.
pub trait Runs<P: ?Sized, R: ?Sized> {
    /// Minimises `problem` with `budget` evaluations.
    fn run_on(&self, problem: &P, budget: u64, rng: &mut R) -> Outcome;
}

impl<O: Optimiser, P: Problem + ?Sized, R: crate::rng::Words + ?Sized> Runs<P, R> for O {
    fn run_on(&self, problem: &P, budget: u64, rng: &mut R) -> Outcome {
        self.run(problem, budget, rng)
    }
}

impl<P: Problem + Any> Runs<P, RunRng> for Algorithm {
    fn run_on(&self, problem: &P, budget: u64, rng: &mut RunRng) -> Outcome {
        self.run(problem, budget, rng)
    }
}

/// What a registered factory builds: a configured optimiser, or why its
/// parameters do not go together.
pub type Factory = dyn Fn(&ParamSet) -> Result<Arc<dyn DynOptimiser>, ParamError> + Send + Sync;

/// The family of comparisons an optimiser's verdicts against the reference
/// are corrected with. Each question is corrected within its own family
/// (Bender & Lange 2001, "Adjusting for multiple testing — when and how?",
/// J. Clin. Epidemiol. 54(4):343–349), so adding an algorithm beyond the
/// thesis to a campaign leaves the Holm families of the thesis's
/// comparisons as they were.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ComparisonFamily {
    /// The thesis's own algorithms (HS, GHS, GA, PSO, MHS): the report's
    /// table `reference`.
    Thesis,
    /// Every other optimiser (the state of the art, the floor, a library
    /// user's own): the report's table `state-of-the-art`. The default of a
    /// newly registered optimiser.
    #[default]
    BeyondTheThesis,
}

impl ComparisonFamily {
    /// The report's table of the family's comparisons against the
    /// reference: `reference` or `state-of-the-art`.
    pub fn table(self) -> &'static str {
        match self {
            ComparisonFamily::Thesis => "reference",
            ComparisonFamily::BeyondTheThesis => "state-of-the-art",
        }
    }
}

/// One registered optimiser: its name, its parameters, its comparison
/// family and the factory that configures it.
#[derive(Clone)]
pub struct OptimiserDef {
    /// The name specs use (`[[algorithm]] name = "…"`).
    pub name: String,
    /// Its parameters, each with its range and default.
    pub params: &'static [ParamDef],
    /// The paper or book it implements, shown by `metabezier list`.
    pub source: String,
    /// The family its verdicts against the reference are corrected in
    /// (default [`ComparisonFamily::BeyondTheThesis`]).
    pub family: ComparisonFamily,
    factory: Arc<Factory>,
}

impl fmt::Debug for OptimiserDef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("OptimiserDef")
            .field("name", &self.name)
            .field("params", &self.params.len())
            .field("source", &self.source)
            .field("family", &self.family)
            .finish()
    }
}

impl OptimiserDef {
    /// The optimiser `name` with parameters `params`, implementing
    /// `source`, configured by `build` from a complete parameter set.
    ///
    /// ```
    /// use metabezier_core::optim::{OptimiserDef, HarmonySearch, hs};
    ///
    /// let def = OptimiserDef::new("my-hs", &hs::PARAMS, "Geem et al. 2001", HarmonySearch::from_params);
    /// assert_eq!(def.name, "my-hs");
    /// ```
    pub fn new<O, F>(name: &str, params: &'static [ParamDef], source: &str, build: F) -> Self
    where
        O: Optimiser + Send + Sync + fmt::Debug + 'static,
        F: Fn(&ParamSet) -> Result<O, ParamError> + Send + Sync + 'static,
    {
        OptimiserDef {
            name: name.to_owned(),
            params,
            source: source.to_owned(),
            family: ComparisonFamily::default(),
            factory: Arc::new(move |p: &ParamSet| {
                build(p).map(|o| Arc::new(o) as Arc<dyn DynOptimiser>)
            }),
        }
    }

    /// The same optimiser in comparison family `family`.
    pub fn in_family(mut self, family: ComparisonFamily) -> Self {
        self.family = family;
        self
    }

    /// The optimiser configured by `p` (a set made from [`Self::params`]).
    pub fn build(&self, p: &ParamSet) -> Result<Algorithm, ParamError> {
        let optimiser = (self.factory)(p)?;
        Ok(Algorithm {
            name: self.name.as_str().into(),
            optimiser,
        })
    }
}

/// Why an optimiser cannot be registered.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum RegistryError {
    /// The name is taken, by a built-in or an earlier registration.
    #[error("an optimiser named \"{0}\" is already registered (registered: {1})")]
    Taken(String, String),
    /// The name is not one a spec can write.
    #[error("\"{0}\" cannot name an optimiser: expected 1 to 40 lowercase ASCII letters, digits, '_' or '-', starting with a letter, and not \"lm\" (Levenberg–Marquardt)")]
    BadName(String),
    /// A parameter name is reserved, repeated or empty.
    #[error("optimiser \"{name}\": parameter \"{param}\" {why}")]
    BadParam {
        /// The optimiser.
        name: String,
        /// The parameter.
        param: String,
        /// What is wrong with it.
        why: String,
    },
    /// The factory refuses the default parameters.
    #[error("optimiser \"{name}\": its factory refuses its own defaults: {param}: {message}")]
    BadDefaults {
        /// The optimiser.
        name: String,
        /// The parameter the factory names.
        param: String,
        /// The factory's message.
        message: String,
    },
}

/// The keys of an `[[algorithm]]` table that are not parameters.
pub const RESERVED_KEYS: [&str; 2] = ["name", "label"];

/// A set of optimisers by name: the built-ins ([`Optimisers::builtin`]) and
/// whatever a library user registers beside them.
///
/// ```
/// use metabezier_core::optim::{Optimisers, OptimiserDef, RandomSearch, random};
///
/// let mut reg = Optimisers::with_builtins();
/// reg.register(OptimiserDef::new("rs2", &random::PARAMS, "Brooks 1958", RandomSearch::from_params))
///     .unwrap();
/// assert!(reg.names().contains(&"rs2"));
/// // A built-in name cannot be taken twice.
/// let again = OptimiserDef::new("mhs", &random::PARAMS, "", RandomSearch::from_params);
/// assert!(reg.register(again).is_err());
/// ```
#[derive(Clone, Debug, Default)]
pub struct Optimisers {
    defs: Vec<OptimiserDef>,
}

impl Optimisers {
    /// The built-in optimisers, shared.
    pub fn builtin() -> &'static Optimisers {
        static BUILTIN: OnceLock<Optimisers> = OnceLock::new();
        BUILTIN.get_or_init(|| {
            let mut reg = Optimisers::default();
            for def in super::builtin_optimisers() {
                reg.register(def).expect("the built-in optimisers register");
            }
            reg
        })
    }

    /// A registry holding the built-ins, to register more beside them.
    pub fn with_builtins() -> Optimisers {
        Optimisers::builtin().clone()
    }

    /// Adds `def`, refusing a name that is taken or that a spec cannot
    /// write, reserved or repeated parameter names, and a factory that
    /// refuses its own defaults.
    pub fn register(&mut self, def: OptimiserDef) -> Result<(), RegistryError> {
        let name = def.name.as_str();
        let good_name = (1..=40).contains(&name.len())
            && name.starts_with(|c: char| c.is_ascii_lowercase())
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '-')
            && name != "lm";
        if !good_name {
            return Err(RegistryError::BadName(def.name));
        }
        if self.get(name).is_some() {
            return Err(RegistryError::Taken(
                def.name.clone(),
                self.names().join(", "),
            ));
        }
        for (i, p) in def.params.iter().enumerate() {
            let why = if p.name.is_empty() {
                Some("is empty".to_owned())
            } else if RESERVED_KEYS.contains(&p.name) {
                Some(format!(
                    "is reserved: {} are the keys of [[algorithm]] itself",
                    super::quoted_list(&RESERVED_KEYS)
                ))
            } else if def.params[..i].iter().any(|q| q.name == p.name) {
                Some("is declared twice".to_owned())
            } else {
                p.check(&p.default.to_raw())
                    .err()
                    .map(|e| format!("has a default outside its own range: {e}"))
            };
            if let Some(why) = why {
                return Err(RegistryError::BadParam {
                    name: def.name.clone(),
                    param: p.name.to_owned(),
                    why,
                });
            }
        }
        if let Err(e) = def.build(&ParamSet::defaults(def.params)) {
            return Err(RegistryError::BadDefaults {
                name: def.name.clone(),
                param: e.param.to_owned(),
                message: e.message,
            });
        }
        self.defs.push(def);
        Ok(())
    }

    /// The registered names, in registration order.
    pub fn names(&self) -> Vec<&str> {
        self.defs.iter().map(|d| d.name.as_str()).collect()
    }

    /// The optimiser named `name`.
    pub fn get(&self, name: &str) -> Option<&OptimiserDef> {
        self.defs.iter().find(|d| d.name == name)
    }

    /// Every registered optimiser, in registration order.
    pub fn iter(&self) -> impl Iterator<Item = &OptimiserDef> {
        self.defs.iter()
    }

    /// The optimiser `name` configured by `p`.
    pub fn build(&self, name: &str, p: &ParamSet) -> Result<Algorithm, ParamError> {
        match self.get(name) {
            Some(def) => def.build(p),
            None => Err(ParamError::new(
                "algorithm",
                format!(
                    "unknown algorithm \"{name}\"; expected one of {}",
                    super::quoted_list(&self.names())
                ),
            )),
        }
    }

    /// The optimiser `name` with its default parameters.
    pub fn default_for(&self, name: &str) -> Option<Algorithm> {
        let def = self.get(name)?;
        def.build(&ParamSet::defaults(def.params)).ok()
    }
}
