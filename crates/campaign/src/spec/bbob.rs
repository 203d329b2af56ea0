//! `[[problem]] suite = "bbob"`: problems of COCO's bbob suite, evaluated
//! by COCO's own code ([`metabezier_bbob`]). Without the `coco` feature a
//! spec that names the suite is refused where it does so.
//!
//! ```toml
//! [[problem]]
//! suite = "bbob"
//! function = [1, 8, "rastrigin-rotated"]   # indices 1..24 or COCO names
//! dim = [2, 5, 10]                         # 2, 3, 5, 10, 20 or 40
//! instances = 3                            # a count (1..N) or a list [1, 2, 3]
//! budget_per_dim = 10000
//! ```
//!
//! Each problem is named by COCO's id (`bbob_f008_i02_d05`); its optimum
//! f* and its targets are COCO's.

use std::fmt::Write as _;
use std::sync::Arc;

use super::family::{FamilyProblem, ProblemFamily, ProblemSection, ProblemSink};
#[cfg(feature = "coco")]
use super::problem::{metaheuristic, minimise_problem};
use super::{choices_hint, Factor, ProblemEntry, ProblemKind, Spec, SpecError, WithSpan};
use crate::functions::Transform;
use crate::optim::Outcome;
use crate::outcome::FitDetail;
use crate::reconstruction::Method;
use crate::registry::Registry;
#[cfg(feature = "coco")]
use metabezier_bbob::BbobProblem;
use metabezier_bbob::{bbob_function, BBOB_DIMENSIONS, BBOB_NAMES};

/// The keys of a bbob `[[problem]]`.
const BBOB_KEYS: [&str; 6] = [
    "suite",
    "function",
    "dim",
    "instances",
    "budget",
    "budget_per_dim",
];

/// COCO's id of a bbob problem: `bbob_f008_i02_d05`.
pub fn bbob_id(function: usize, instance: u32, dim: usize) -> String {
    format!("bbob_f{function:03}_i{instance:02}_d{dim:02}")
}

/// Function `function` (1..=24) of COCO's bbob suite
/// ([`metabezier_bbob`]) at the entry's dimension and instance,
/// whose optimum is `fopt`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bbob {
    /// The bbob function index.
    pub function: usize,
    /// f* of the instance, from COCO.
    pub fopt: f64,
}

impl ProblemKind for Bbob {
    fn name(&self, entry: &ProblemEntry) -> String {
        bbob_id(self.function, entry.instance, entry.dim)
    }

    fn seed_name(&self, entry: &ProblemEntry, paired: &[Factor]) -> String {
        if paired.contains(&Factor::Instance) {
            format!("bbob_f{:03}_d{:02}", self.function, entry.dim)
        } else {
            self.name(entry)
        }
    }

    fn optimum(&self) -> f64 {
        self.fopt
    }

    fn execute(
        &self,
        spec: &Spec,
        entry: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        #[cfg(feature = "coco")]
        {
            // Each run owns its COCO problem: threads never share COCO state.
            let problem = BbobProblem::new(self.function, entry.dim, entry.instance as usize)
                .expect("the bbob problem was built when the spec loaded");
            let out = minimise_problem(
                spec,
                entry,
                metaheuristic(method),
                &problem,
                self.fopt,
                seed,
            );
            debug_assert_eq!(problem.coco_evaluations(), out.evaluations);
            (out, None)
        }
        #[cfg(not(feature = "coco"))]
        {
            // A spec cannot name the suite without COCO (the parser refuses
            // it), so only an entry made by hand reaches this.
            let _ = (spec, method, seed);
            panic!("{}: {NO_COCO}", self.name(entry))
        }
    }
}

/// Why a build without the `coco` feature refuses the bbob suite.
pub const NO_COCO: &str = "the bbob suite needs COCO's C core, which this build leaves out: \
                           build with the `coco` feature (on by default: `cargo build --release`)";

/// f* of bbob function `f` at dimension `d`, instance `k`, from COCO, or
/// COCO's refusal.
#[cfg(feature = "coco")]
fn bbob_fopt(f: usize, d: usize, k: u32) -> Result<f64, String> {
    BbobProblem::new(f, d, k as usize)
        .map(|p| p.fopt())
        .map_err(|e| e.to_string())
}

/// Without COCO there is no f* to look up.
#[cfg(not(feature = "coco"))]
fn bbob_fopt(_f: usize, _d: usize, _k: u32) -> Result<f64, String> {
    Err(NO_COCO.to_owned())
}

/// COCO's bbob suite as a problem family: `suite = "bbob"`.
#[derive(Clone, Copy, Debug, Default)]
pub struct BbobSuite;

impl ProblemFamily for BbobSuite {
    fn suite(&self) -> &str {
        "bbob"
    }

    fn keys(&self) -> &[&str] {
        &BBOB_KEYS
    }

    fn unavailable(&self) -> Option<&str> {
        (!cfg!(feature = "coco")).then_some(NO_COCO)
    }

    /// Every function × dimension × instance of the section.
    fn read(
        &self,
        section: &ProblemSection<'_, '_>,
        sink: &mut ProblemSink<'_>,
    ) -> Result<(), SpecError> {
        let functions = bbob_functions(section)?;
        let dims = bbob_dims(section)?;
        let instances = section.instances(10_000, 1_000_000)?;
        let count = (functions.len() as u128)
            .saturating_mul(dims.len() as u128)
            .saturating_mul(instances.len() as u128);
        sink.reserve(count)?;
        for &(f, _) in &functions {
            for &(d, ref dspan) in &dims {
                for &k in &instances {
                    let fopt = bbob_fopt(f, d, k)
                        .map_err(|e| section.error(dspan.clone(), &section.field("dim"), e))?;
                    sink.add(FamilyProblem {
                        kind: Arc::new(Bbob { function: f, fopt }),
                        dim: d,
                        transform: Transform::None,
                        instance: k,
                        budget_span: dspan.clone(),
                        span: section.span(),
                    })?;
                }
            }
        }
        Ok(())
    }

    /// The 24 functions by index and COCO name, and the dimensions.
    fn list_entry(&self, _: &Registry) -> String {
        let mut w = format!(
            "\nCOCO's bbob suite ([[problem]] suite = \"bbob\", function = 1..=24 or names; dim in {BBOB_DIMENSIONS:?}):\n"
        );
        for (i, name) in BBOB_NAMES.iter().enumerate() {
            let _ = writeln!(w, "  f{:<3} {name}", i + 1);
        }
        w
    }
}

/// The required `function`: indices 1..=24 or COCO names.
fn bbob_functions(section: &ProblemSection<'_, '_>) -> Result<Vec<WithSpan<usize>>, SpecError> {
    let field = section.field("function");
    let v = section.required(section.table, section.name, "function", section.span())?;
    section
        .one_or_many(v, &field)?
        .into_iter()
        .map(|item| {
            let text = match item.get_ref() {
                toml::de::DeValue::Integer(i) => i.as_str().to_owned(),
                _ => section.string(item, &field)?,
            };
            let f = bbob_function(&text).ok_or_else(|| {
                section.error(
                    item.span(),
                    &field,
                    format!(
                        "unknown bbob function \"{text}\"; give an index 1 to 24 or a COCO name ({})",
                        choices_hint(&text, &BBOB_NAMES)
                    ),
                )
            })?;
            Ok((f, item.span()))
        })
        .collect()
}

/// The required `dim`: dimensions COCO defines the suite for.
fn bbob_dims(section: &ProblemSection<'_, '_>) -> Result<Vec<WithSpan<usize>>, SpecError> {
    let field = section.field("dim");
    let v = section.required(section.table, section.name, "dim", section.span())?;
    section
        .one_or_many(v, &field)?
        .into_iter()
        .map(|item| {
            let d = section.integer(item, &field, 1, 1_000_000)? as usize;
            if !BBOB_DIMENSIONS.contains(&d) {
                return Err(section.error(
                    item.span(),
                    &field,
                    format!("bbob is defined for the dimensions 2, 3, 5, 10, 20 and 40, not {d}"),
                ));
            }
            Ok((d, item.span()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::Spec;

    const BBOB_SPEC: &str = "[experiment]\nname = \"b\"\nseed = 1\nruns = 1\nbudget = 100\n\n\
                             [[problem]]\nsuite = \"bbob\"\nfunction = 1\ndim = 2\n\n\
                             [[algorithm]]\nname = \"hs\"\n";

    /// Without COCO the suite is refused where the spec names it.
    #[cfg(not(feature = "coco"))]
    #[test]
    fn without_coco_the_suite_is_a_located_error() {
        let e = Spec::parse(Path::new("b.toml"), BBOB_SPEC).unwrap_err();
        assert_eq!((e.line, e.column), (8, 9), "{e}");
        assert_eq!(e.field, "problem[1].suite", "{e}");
        assert!(e.message.contains("`coco` feature"), "{e}");
    }

    /// With COCO the same spec loads, with COCO's f*.
    #[cfg(feature = "coco")]
    #[test]
    fn with_coco_the_suite_loads() {
        let spec = Spec::parse(Path::new("b.toml"), BBOB_SPEC).unwrap();
        assert_eq!(spec.problems.len(), 1);
        assert_eq!(spec.problems[0].dim, 2);
    }
}
