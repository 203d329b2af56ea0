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

use std::collections::HashSet;
use std::ops::Range;
use std::sync::Arc;

use super::{
    choices_hint, Budget, Factor, Parser, ProblemEntry, ProblemKind, Spec, SpecError, Table, Value,
};
#[cfg(feature = "coco")]
use super::{metaheuristic, minimise_problem};
use crate::functions::Transform;
use crate::optim::Outcome;
use crate::outcome::FitDetail;
use crate::reconstruction::Method;
#[cfg(feature = "coco")]
use metabezier_bbob::BbobProblem;
use metabezier_bbob::{bbob_function, BBOB_DIMENSIONS, BBOB_NAMES};

/// The keys of a bbob `[[problem]]`.
pub(super) const BBOB_KEYS: [&str; 6] = [
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

/// f* of bbob function `f` at dimension `d`, instance `k`, from COCO.
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

impl Parser<'_> {
    /// The problems of a `[[problem]]` section with `suite = "bbob"`:
    /// every function × dimension × instance × budget, appended to `out`.
    pub(super) fn bbob_problems(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
        budget: &Budget,
        out: &mut Vec<ProblemEntry>,
        seen: &mut HashSet<String>,
    ) -> Result<(), SpecError> {
        self.check_keys(table, section, &BBOB_KEYS)?;
        let functions = self.bbob_functions(table, section, entry)?;
        let dims = self.bbob_dims(table, section, entry)?;
        let instances = self.instances(table, section, 10_000, 1_000_000)?;
        let budgets = match budget {
            Budget::Fixed(b) | Budget::PerDim(b) => b.len(),
        };
        let count = (functions.len() as u128)
            .saturating_mul(dims.len() as u128)
            .saturating_mul(instances.len() as u128)
            .saturating_mul(budgets as u128);
        self.check_problem_count(out.len(), count, &entry.span(), section)?;
        for &(f, _) in &functions {
            for &(d, ref dspan) in &dims {
                for &k in &instances {
                    let fopt = bbob_fopt(f, d, k)
                        .map_err(|e| self.error(dspan.clone(), &format!("{section}.dim"), e))?;
                    for b in self.dim_budgets(budget, d, dspan, section)? {
                        let p = ProblemEntry {
                            kind: Arc::new(Bbob { function: f, fopt }),
                            dim: d,
                            budget: b,
                            budget_factor: budget.is_grid(),
                            transform: Transform::None,
                            instance: k,
                        };
                        if !seen.insert(p.key()) {
                            return Err(self.error(
                                entry.span(),
                                section,
                                format!("problem {} is listed twice", p.key()),
                            ));
                        }
                        out.push(p);
                    }
                }
            }
        }
        Ok(())
    }

    fn bbob_functions(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<Vec<(usize, Range<usize>)>, SpecError> {
        let field = format!("{section}.function");
        let v = self.required(table, section, "function", entry.span())?;
        self.one_or_many(v, &field)?
            .into_iter()
            .map(|item| {
                let text = match item.get_ref() {
                    toml::de::DeValue::Integer(i) => i.as_str().to_owned(),
                    _ => self.string(item, &field)?,
                };
                let f = bbob_function(&text).ok_or_else(|| {
                    self.error(
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

    fn bbob_dims(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<Vec<(usize, Range<usize>)>, SpecError> {
        let field = format!("{section}.dim");
        let v = self.required(table, section, "dim", entry.span())?;
        self.one_or_many(v, &field)?
            .into_iter()
            .map(|item| {
                let d = self.integer(item, &field, 1, 1_000_000)? as usize;
                if !BBOB_DIMENSIONS.contains(&d) {
                    return Err(self.error(
                        item.span(),
                        &field,
                        format!(
                            "bbob is defined for the dimensions 2, 3, 5, 10, 20 and 40, not {d}"
                        ),
                    ));
                }
                Ok((d, item.span()))
            })
            .collect()
    }
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
