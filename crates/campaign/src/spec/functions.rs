//! The `[[problem]]` sections without `suite`: the thesis's functions
//! ([`Benchmark`]), at a dimension, transform and instance, and the
//! problems a library user registers ([`RegisteredProblem`]) beside them.
//!
//! ```toml
//! [[problem]]
//! function = ["sphere", "rastrigin"]   # a name or a list of names
//! dim = [10, 30]                       # a dimension or a list
//! # transform = "shift-rotate"         # optional: "none", "shift", "shift-rotate"
//! # instances = [6, 7, 8]              # of a transform: a count N (1..N) or a list
//! ```

use std::fmt::{self, Write as _};
use std::ops::Range;
use std::sync::{Arc, OnceLock};

use super::family::{FamilyProblem, ProblemFamily, ProblemSection, ProblemSink};
use super::problem::{benchmark_evaluator, execute_benchmark, metaheuristic};
use super::{choices_hint, ProblemEntry, ProblemKind, Spec, SpecError, WithSpan};
use crate::functions::{Function, TestProblem, Transform};
use crate::optim::Outcome;
use crate::outcome::FitDetail;
use crate::reconstruction::Method;
use crate::registry::{ProblemDef, Registry, SharedProblem};
use crate::rng::run_rng;

/// One of the thesis's functions at a dimension, transform and instance;
/// the problem is drawn on its first run (a rotation costs `O(D³)`) and
/// shared by all its runs.
#[derive(Debug)]
pub struct Benchmark {
    /// The function.
    pub function: Function,
    problem: OnceLock<TestProblem>,
}

impl Benchmark {
    /// The function `function`, drawn when first run.
    pub fn new(function: Function) -> Benchmark {
        Benchmark {
            function,
            problem: OnceLock::new(),
        }
    }

    /// The problem of `entry` (its dimension, transform and instance).
    pub fn problem(&self, entry: &ProblemEntry) -> &TestProblem {
        self.problem.get_or_init(|| {
            TestProblem::instance(self.function, entry.dim, entry.transform, entry.instance)
                .expect("instance checked when the spec loaded")
        })
    }
}

impl ProblemKind for Benchmark {
    fn name(&self, _: &ProblemEntry) -> String {
        self.function.name().to_owned()
    }

    fn optimum(&self) -> f64 {
        self.function.optimum_value()
    }

    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        let problem = self.problem(entry);
        let mut eval = benchmark_evaluator(spec, entry, problem, self.optimum());
        metaheuristic(method).minimise_benchmark(&mut eval, &mut run_rng(seed));
        (eval.finish(), None)
    }
}

/// A benchmark problem at one dimension with its optimum `f*`, built once
/// and shared by its runs: a registered problem, or one of a registered
/// suite's (its [`ProblemFamily::read`] may build it so).
#[derive(Clone)]
pub struct RegisteredProblem {
    /// Its name in results.
    pub name: String,
    /// Its optimum value `f*` at this dimension.
    pub optimum: f64,
    /// The problem.
    pub problem: SharedProblem,
}

impl fmt::Debug for RegisteredProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RegisteredProblem")
            .field("name", &self.name)
            .field("optimum", &self.optimum)
            .finish()
    }
}

impl ProblemKind for RegisteredProblem {
    fn name(&self, _: &ProblemEntry) -> String {
        self.name.clone()
    }

    fn optimum(&self) -> f64 {
        self.optimum
    }

    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        execute_benchmark(spec, entry, method, &*self.problem, self.optimum, seed)
    }
}

/// The largest instance count, and instance number, of a `[[problem]]` of
/// the thesis's functions.
const MAX_INSTANCES: u64 = 10_000;

/// The keys of a `[[problem]]` of the thesis's functions.
const PROBLEM_KEYS: [&str; 7] = [
    "suite",
    "function",
    "dim",
    "budget",
    "budget_per_dim",
    "transform",
    "instances",
];

/// The family of the `[[problem]]` sections without `suite`: the thesis's
/// functions and the registered problems.
#[derive(Clone, Copy, Debug, Default)]
pub struct Functions;

impl ProblemFamily for Functions {
    /// Empty: these are the sections without `suite`.
    fn suite(&self) -> &str {
        ""
    }

    fn keys(&self) -> &[&str] {
        &PROBLEM_KEYS
    }

    /// Every function × dimension × transform × instance of the section.
    fn read(
        &self,
        section: &ProblemSection<'_, '_>,
        sink: &mut ProblemSink<'_>,
    ) -> Result<(), SpecError> {
        let functions = problem_functions(section)?;
        let dims = problem_dims(section)?;
        let transforms = problem_transforms(section)?;
        let instances = section.instances(MAX_INSTANCES, MAX_INSTANCES)?;
        let count = [
            functions.len(),
            dims.len(),
            transforms.len(),
            instances.len(),
        ]
        .iter()
        .fold(1u128, |n, &k| n.saturating_mul(k as u128));
        sink.reserve(count)?;
        for (f, fspan) in &functions {
            match f {
                FunctionRef::Builtin(f) => {
                    let axes = (&dims[..], &transforms[..], &instances[..]);
                    builtin_problems(section, sink, (*f, fspan), axes)?;
                }
                FunctionRef::Registered(def) => {
                    registered_problems(section, sink, (def, fspan), &dims, &transforms)?;
                }
            }
        }
        Ok(())
    }

    /// The functions with their domains and optima, the registered
    /// problems with their sources, and the transforms.
    fn list_entry(&self, registry: &Registry) -> String {
        let mut w = String::from("\nBenchmark functions (name, domain, optimum):\n");
        for f in Function::ALL {
            let b = f.domain();
            let dim = match f.fixed_dim() {
                Some(d) => format!(", dimension {d} only"),
                None => String::new(),
            };
            let transforms = if f.is_transformable() {
                ""
            } else {
                " (no transforms)"
            };
            let _ = writeln!(
                w,
                "  {:<16} [{}, {}]^D, f* = {}{dim}{transforms}",
                f.name(),
                b.lower,
                b.upper,
                f.optimum_value()
            );
        }
        for p in registry.problems() {
            let _ = writeln!(w, "  {:<16} registered: {}", p.name, p.source);
        }
        w.push_str("\nBenchmark transforms ([[problem]] transform = ..., instances = N):\n");
        for t in [Transform::None, Transform::Shift, Transform::ShiftRotate] {
            let _ = writeln!(w, "  {:<16} {}", t.name(), t.doc());
        }
        w
    }
}

/// The problems of a built-in function at each dimension × transform ×
/// instance (the published function, untransformed, has one instance).
fn builtin_problems(
    section: &ProblemSection<'_, '_>,
    sink: &mut ProblemSink<'_>,
    (f, fspan): (Function, &Range<usize>),
    (dims, transforms, instances): (&[Dim], &[TransformAt], &[u32]),
) -> Result<(), SpecError> {
    for (dim, dspan) in dims {
        let dim = problem_dim(section, f, *dim, fspan, dspan)?;
        for (t, tspan) in transforms {
            TestProblem::check_instance(f, dim, *t).map_err(|e| {
                section.error(tspan.clone(), &section.field("transform"), e.to_string())
            })?;
            let listed: &[u32] = if *t == Transform::None {
                &[1]
            } else {
                instances
            };
            for &instance in listed {
                sink.add(FamilyProblem {
                    kind: Arc::new(Benchmark::new(f)),
                    dim,
                    transform: *t,
                    instance,
                    budget_span: dspan.clone(),
                    span: fspan.clone(),
                })?;
            }
        }
    }
    Ok(())
}

/// The optional `transform` of a `[[problem]]`: a name or a list.
fn problem_transforms(section: &ProblemSection<'_, '_>) -> Result<Vec<TransformAt>, SpecError> {
    let Some(tv) = section.get(section.table, "transform") else {
        return Ok(vec![(Transform::None, section.span())]);
    };
    let field = section.field("transform");
    section
        .one_or_many(tv, &field)?
        .into_iter()
        .map(|v| {
            let name = section.string(v, &field)?;
            let t = Transform::from_name(&name).ok_or_else(|| {
                section.error(
                    v.span(),
                    &field,
                    format!(
                        "unknown transform \"{name}\"; {}",
                        choices_hint(&name, &Transform::NAMES)
                    ),
                )
            })?;
            Ok((t, v.span()))
        })
        .collect()
}

/// The problems of a registered function `def` at each of `dims`; a
/// registered problem has no transform and no instances, and is built
/// here, so that a builder's refusal is an error of the spec, located at
/// the dimension.
fn registered_problems(
    section: &ProblemSection<'_, '_>,
    sink: &mut ProblemSink<'_>,
    (def, fspan): (&ProblemDef, &Range<usize>),
    dims: &[Dim],
    transforms: &[TransformAt],
) -> Result<(), SpecError> {
    if let Some((_, tspan)) = transforms.iter().find(|(t, _)| *t != Transform::None) {
        return Err(section.error(
            tspan.clone(),
            &section.field("transform"),
            format!(
                "{} is a registered problem, which has no transforms; give it in a [[problem]] of its own without \"transform\"",
                def.name
            ),
        ));
    }
    for (dim, dspan) in dims {
        let Some(dim) = *dim else {
            return Err(section.error(
                fspan.clone(),
                &section.field("dim"),
                format!(
                    "missing \"dim\": {} is a registered problem and needs a dimension",
                    def.name
                ),
            ));
        };
        let problem = def
            .instance(dim)
            .map_err(|e| section.error(dspan.clone(), &section.field("dim"), e.to_string()))?;
        sink.add(FamilyProblem {
            kind: Arc::new(RegisteredProblem {
                name: def.name.clone(),
                optimum: def.optimum(dim),
                problem,
            }),
            dim,
            transform: Transform::None,
            instance: 1,
            budget_span: dspan.clone(),
            span: fspan.clone(),
        })?;
    }
    Ok(())
}

/// The required `function` of a `[[problem]]`: the benchmark functions
/// (built-in or registered) with their spans.
fn problem_functions(
    section: &ProblemSection<'_, '_>,
) -> Result<Vec<WithSpan<FunctionRef>>, SpecError> {
    let fv = section.required(section.table, section.name, "function", section.span())?;
    let field = section.field("function");
    let mut functions = Vec::new();
    for v in section.one_or_many(fv, &field)? {
        let name = section.string(v, &field)?;
        let builtin = Function::from_name(&name).map(FunctionRef::Builtin);
        let registered = || {
            section
                .registry
                .problem(&name)
                .map(|d| FunctionRef::Registered(d.clone()))
        };
        let f = builtin.or_else(registered).ok_or_else(|| {
            let names = section.registry.function_names();
            section.error(
                v.span(),
                &field,
                format!(
                    "unknown function \"{name}\"; {}",
                    choices_hint(&name, &names)
                ),
            )
        })?;
        functions.push((f, v.span()));
    }
    Ok(functions)
}

/// The optional `dim` of a `[[problem]]`: the dimensions with their
/// spans, or one unset dimension (each function's fixed one).
fn problem_dims(section: &ProblemSection<'_, '_>) -> Result<Vec<Dim>, SpecError> {
    let Some(dv) = section.get(section.table, "dim") else {
        return Ok(vec![(None, section.span())]);
    };
    let field = section.field("dim");
    section
        .one_or_many(dv, &field)?
        .into_iter()
        .map(|v| {
            Ok((
                Some(section.integer(v, &field, 1, 1_000_000)? as usize),
                v.span(),
            ))
        })
        .collect()
}

/// The dimension of function `f` (the one given, else its fixed one),
/// checked against the function.
fn problem_dim(
    section: &ProblemSection<'_, '_>,
    f: Function,
    dim: Option<usize>,
    fspan: &Range<usize>,
    dspan: &Range<usize>,
) -> Result<usize, SpecError> {
    let dim = match (dim, f.fixed_dim()) {
        (Some(d), _) => d,
        (None, Some(d)) => d,
        (None, None) => {
            return Err(section.error(
                fspan.clone(),
                &section.field("dim"),
                format!(
                    "missing \"dim\": {} is scalable and needs a dimension",
                    f.name()
                ),
            ))
        }
    };
    if let Err(e) = TestProblem::new(f, dim) {
        return Err(section.error(dspan.clone(), &section.field("dim"), e.to_string()));
    }
    Ok(dim)
}

/// A dimension given (or none, for a function's fixed one), with its span.
type Dim = WithSpan<Option<usize>>;

/// A transform with its span.
type TransformAt = WithSpan<Transform>;

/// A `[[problem]] function` name, resolved.
enum FunctionRef {
    /// One of the thesis's functions.
    Builtin(Function),
    /// A registered problem.
    Registered(Arc<ProblemDef>),
}
