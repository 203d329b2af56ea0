//! `[[problem]] suite = "bbob"`: problems of COCO's bbob suite, evaluated
//! by COCO's own code ([`crate::functions::bbob`]).
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

use super::{choices_hint, Budget, Parser, ProblemEntry, ProblemKind, SpecError, Table, Value};
use crate::functions::bbob::{bbob_function, BbobProblem, BBOB_DIMENSIONS, BBOB_NAMES};
use crate::functions::Transform;

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
                    let fopt = BbobProblem::new(f, d, k as usize)
                        .map_err(|e| {
                            self.error(dspan.clone(), &format!("{section}.dim"), e.to_string())
                        })?
                        .fopt();
                    for b in self.dim_budgets(budget, d, dspan, section)? {
                        let p = ProblemEntry {
                            kind: ProblemKind::Bbob { function: f, fopt },
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
