//! What a spec may name: the optimisers of [`crate::optim::Optimisers`] and
//! the benchmark problems beyond the built-in functions, registered by a
//! library user so that a spec names them beside the built-ins and the
//! same runner, resume, shards, CSV files and report serve them.
//!
//! ```
//! use metabezier_campaign::{ProblemDef, Registry};
//! use metabezier_core::problem::{Bounds, Problem};
//!
//! /// Styblinski & Tang (1990): f(x) = ½ Σ (x_i⁴ − 16 x_i² + 5 x_i) on [−5, 5]^D.
//! struct StyblinskiTang(Vec<Bounds>);
//! impl Problem for StyblinskiTang {
//!     fn dim(&self) -> usize { self.0.len() }
//!     fn bounds(&self) -> &[Bounds] { &self.0 }
//!     fn objective(&self, x: &[f64]) -> f64 {
//!         0.5 * x.iter().map(|v| v.powi(4) - 16.0 * v * v + 5.0 * v).sum::<f64>()
//!     }
//! }
//!
//! let mut reg = Registry::with_builtins();
//! reg.register_problem(ProblemDef::new(
//!     "styblinski_tang",
//!     "Styblinski & Tang 1990",
//!     |dim| Ok(StyblinskiTang(vec![Bounds::new(-5.0, 5.0); dim])),
//!     |dim| -39.166_165_703_771_41 * dim as f64,
//! ))
//! .unwrap();
//! assert!(reg.problem("styblinski_tang").is_some());
//! ```

use std::any::Any;
use std::fmt;
use std::sync::{Arc, OnceLock};

use crate::functions::Function;
use crate::optim::{OptimiserDef, Optimisers, RegistryError};
use crate::problem::Problem;

/// A problem built at one dimension, shared by every run of a campaign.
pub type SharedProblem = Arc<dyn Problem + Send + Sync>;

type Build = dyn Fn(usize) -> Result<SharedProblem, BuildError> + Send + Sync;
type Optimum = dyn Fn(usize) -> f64 + Send + Sync;

/// A registered benchmark problem: a name, a builder for each dimension and
/// the optimum value `f*` at each dimension (errors are `f − f*`).
#[derive(Clone)]
pub struct ProblemDef {
    /// The name a spec's `[[problem]] function` uses.
    pub name: String,
    /// Where it comes from, for readers of the results.
    pub source: String,
    build: Arc<Build>,
    optimum: Arc<Optimum>,
}

impl fmt::Debug for ProblemDef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("ProblemDef")
            .field("name", &self.name)
            .field("source", &self.source)
            .finish()
    }
}

impl ProblemDef {
    /// The problem `name` from `source`: `build(dim)` makes it at a
    /// dimension (or says why it cannot), `optimum(dim)` is its `f*`.
    pub fn new<P, B, F>(name: &str, source: &str, build: B, optimum: F) -> ProblemDef
    where
        P: Problem + Send + Sync + 'static,
        B: Fn(usize) -> Result<P, BuildError> + Send + Sync + 'static,
        F: Fn(usize) -> f64 + Send + Sync + 'static,
    {
        ProblemDef {
            name: name.to_owned(),
            source: source.to_owned(),
            build: Arc::new(move |dim| build(dim).map(|p| Arc::new(p) as SharedProblem)),
            optimum: Arc::new(optimum),
        }
    }

    /// The problem at dimension `dim`, checked: it has that dimension, one
    /// bound per variable, and every bound is finite with `lower < upper`.
    pub fn instance(&self, dim: usize) -> Result<SharedProblem, InstanceError> {
        let name = || self.name.clone();
        if dim == 0 {
            return Err(InstanceError::NoDimension { name: name() });
        }
        let p = (self.build)(dim).map_err(|refusal| InstanceError::Refused {
            name: name(),
            dim,
            refusal,
        })?;
        if p.dim() != dim {
            return Err(InstanceError::WrongDimension {
                name: name(),
                dim,
                reported: p.dim(),
            });
        }
        if p.bounds().len() != dim {
            return Err(InstanceError::WrongBoundCount {
                name: name(),
                dim,
                count: p.bounds().len(),
            });
        }
        if let Some((i, b)) = p
            .bounds()
            .iter()
            .enumerate()
            .find(|(_, b)| !(b.lower.is_finite() && b.upper.is_finite() && b.lower < b.upper))
        {
            return Err(InstanceError::BadBounds {
                name: name(),
                dim,
                variable: i + 1,
                lower: b.lower,
                upper: b.upper,
            });
        }
        let f_star = self.optimum(dim);
        if !f_star.is_finite() {
            return Err(InstanceError::BadOptimum {
                name: name(),
                dim,
                f_star,
            });
        }
        Ok(p)
    }

    /// The optimum value `f*` at dimension `dim`.
    pub fn optimum(&self, dim: usize) -> f64 {
        (self.optimum)(dim)
    }
}

/// Why a registered problem's builder refuses a dimension, in its own
/// words (`"at most 3 variables"`); made from a `&str` or a `String`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct BuildError {
    /// What the builder says.
    pub message: String,
}

impl From<String> for BuildError {
    fn from(message: String) -> Self {
        BuildError { message }
    }
}

impl From<&str> for BuildError {
    fn from(message: &str) -> Self {
        BuildError {
            message: message.to_owned(),
        }
    }
}

/// Why a registered problem has no checked instance at a dimension
/// ([`ProblemDef::instance`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum InstanceError {
    /// The dimension is 0.
    #[error("{name} needs a dimension of at least 1")]
    NoDimension {
        /// The problem's name.
        name: String,
    },
    /// The builder refused the dimension.
    #[error("{name} at D = {dim}: {refusal}")]
    Refused {
        /// The problem's name.
        name: String,
        /// The dimension asked for.
        dim: usize,
        /// The builder's reason.
        refusal: BuildError,
    },
    /// The built problem reports another dimension.
    #[error("{name} built for D = {dim} reports dimension {reported}")]
    WrongDimension {
        /// The problem's name.
        name: String,
        /// The dimension asked for.
        dim: usize,
        /// The dimension the problem reports.
        reported: usize,
    },
    /// The built problem has not one bound per variable.
    #[error("{name} at D = {dim} has {count} bounds; expected one per variable, {dim}")]
    WrongBoundCount {
        /// The problem's name.
        name: String,
        /// The dimension asked for.
        dim: usize,
        /// The number of bounds it has.
        count: usize,
    },
    /// A bound is not finite or not `lower < upper`.
    #[error("{name} at D = {dim}: the bounds of x_{variable} are [{lower}, {upper}]; expected finite bounds with lower < upper")]
    BadBounds {
        /// The problem's name.
        name: String,
        /// The dimension asked for.
        dim: usize,
        /// The variable, from 1.
        variable: usize,
        /// Its lower bound.
        lower: f64,
        /// Its upper bound.
        upper: f64,
    },
    /// The optimum value is not finite.
    #[error("{name} at D = {dim}: its optimum value is {f_star}; expected a finite f*")]
    BadOptimum {
        /// The problem's name.
        name: String,
        /// The dimension asked for.
        dim: usize,
        /// The optimum value `f*` given.
        f_star: f64,
    },
}

/// Why a problem cannot be registered.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ProblemRegistryError {
    /// The name is a built-in function's or an earlier registration's.
    #[error("a problem named \"{0}\" already exists (the built-in functions and registered problems: {1})")]
    Taken(String, String),
    /// The name is not one a spec can write, or would be read as something else.
    #[error("\"{0}\" cannot name a problem: expected 1 to 60 ASCII letters, digits, '_' or '-', starting with a letter, and not starting with \"bbob\" (COCO's suite)")]
    BadName(String),
}

/// The optimisers, problems and problem families a spec may name: the
/// built-ins and a library user's own. [`Registry::builtin`] is what the
/// command line uses.
#[derive(Clone, Debug, Default)]
pub struct Registry {
    /// The optimisers.
    pub optimisers: Optimisers,
    problems: Vec<Arc<ProblemDef>>,
    families: Vec<FamilySlot>,
}

/// A registered problem family as the registry keeps it: an
/// `Arc<dyn ProblemFamily>` behind `Any` (the family's trait belongs to the
/// spec, above the registry).
pub(crate) type FamilySlot = Arc<dyn Any + Send + Sync>;

impl Registry {
    /// The built-in optimisers and functions, shared.
    pub fn builtin() -> &'static Registry {
        static BUILTIN: OnceLock<Registry> = OnceLock::new();
        BUILTIN.get_or_init(|| Registry {
            optimisers: Optimisers::with_builtins(),
            problems: Vec::new(),
            families: Vec::new(),
        })
    }

    /// The built-ins, to register more beside them.
    pub fn with_builtins() -> Registry {
        Registry::builtin().clone()
    }

    /// Adds an optimiser ([`Optimisers::register`]).
    pub fn register_optimiser(&mut self, def: OptimiserDef) -> Result<(), RegistryError> {
        self.optimisers.register(def)
    }

    /// Adds a problem, refusing a name a built-in function or an earlier
    /// problem has, or one a spec cannot write.
    pub fn register_problem(&mut self, def: ProblemDef) -> Result<(), ProblemRegistryError> {
        let name = def.name.as_str();
        if !spec_name(name) || name.to_ascii_lowercase().starts_with("bbob") {
            return Err(ProblemRegistryError::BadName(def.name));
        }
        if Function::from_name(name).is_some() || self.problem(name).is_some() {
            return Err(ProblemRegistryError::Taken(
                def.name.clone(),
                self.function_names().join(", "),
            ));
        }
        self.problems.push(Arc::new(def));
        Ok(())
    }

    /// The registered problem `name`.
    pub fn problem(&self, name: &str) -> Option<&Arc<ProblemDef>> {
        self.problems.iter().find(|p| p.name == name)
    }

    /// The registered problems, in registration order.
    pub fn problems(&self) -> impl Iterator<Item = &ProblemDef> {
        self.problems.iter().map(|p| &**p)
    }

    /// Every name `[[problem]] function` accepts: the built-in functions,
    /// then the registered problems.
    pub fn function_names(&self) -> Vec<&str> {
        Function::ALL
            .iter()
            .map(|f| f.name())
            .chain(self.problems.iter().map(|p| p.name.as_str()))
            .collect()
    }

    /// The problem families a library user registered, type-erased: the
    /// registry sits below the spec, whose `ProblemFamily` they are
    /// (`spec/family.rs` registers and reads them, beside the built-in
    /// COCO suite).
    pub(crate) fn family_slots(&self) -> &[FamilySlot] {
        &self.families
    }

    /// Keeps a registered family (see [`Registry::family_slots`]).
    pub(crate) fn push_family_slot(&mut self, family: FamilySlot) {
        self.families.push(family);
    }
}

/// Whether `name` can name a problem or a suite in a spec: 1 to 60 ASCII
/// letters, digits, `_` or `-`, starting with a letter.
pub(crate) fn spec_name(name: &str) -> bool {
    (1..=60).contains(&name.len())
        && name.starts_with(|c: char| c.is_ascii_alphabetic())
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
}
