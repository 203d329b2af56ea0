//! Budgets: `budget` or `budget_per_dim` of `[experiment]` or of a
//! section, one value or a grid of values, each within the limit of
//! evaluations per run; and the limit on the problems of a spec.

use std::ops::Range;

use super::reader::Parser;
use super::{raw, SpecError, Table, Value, MAX_PROBLEMS};
use crate::optim::Raw;

impl Parser<'_> {
    /// One budget value: an integer in 1..=`limits.max_budget`, the limit
    /// named when it is passed.
    pub(crate) fn budget_value(&self, v: &Value<'_>, field: &str) -> Result<u64, SpecError> {
        let max = self.limits.max_budget;
        match raw(v.get_ref()) {
            Raw::Int(n) if n >= 1 && (n as u64) > max => Err(self.error(
                v.span(),
                field,
                format!(
                    "{n} evaluations per run pass the limit of {max}; pass --allow-large to run budgets above it"
                ),
            )),
            _ => self.integer(v, field, 1, u64::MAX),
        }
    }

    /// The budgets of a problem of dimension `dim` (a per-dimension budget
    /// times `dim`), each within `limits.max_budget`; errors at `span`.
    pub(crate) fn dim_budgets(
        &self,
        budget: &Budget,
        dim: usize,
        span: &Range<usize>,
        section: &str,
    ) -> Result<Vec<u64>, SpecError> {
        let max = self.limits.max_budget;
        let budgets = budget.for_dim(dim);
        if let Some(b) = budgets.iter().find(|&&b| b > max) {
            return Err(self.error(
                span.clone(),
                &format!("{section}.budget_per_dim"),
                format!(
                    "budget_per_dim × dim = {b} evaluations per run at D = {dim} pass the limit of {max}; pass --allow-large to run budgets above it"
                ),
            ));
        }
        Ok(budgets)
    }

    /// Refuses a spec whose problems would pass [`MAX_PROBLEMS`] once
    /// `more` are added to the `have` already expanded.
    pub(crate) fn check_problem_count(
        &self,
        have: usize,
        more: u128,
        span: &Range<usize>,
        section: &str,
    ) -> Result<(), SpecError> {
        if have as u128 + more > MAX_PROBLEMS as u128 {
            return Err(self.error(
                span.clone(),
                section,
                format!(
                    "this section makes {more} problems{}, over the limit of {MAX_PROBLEMS} problems of a spec; split the spec",
                    if have > 0 {
                        format!(" (after {have} before it)")
                    } else {
                        String::new()
                    }
                ),
            ));
        }
        Ok(())
    }

    /// `budget` or `budget_per_dim` of a table, if present (not both): a
    /// value or a list of values (a budget grid).
    pub(crate) fn budget(
        &self,
        table: &Table<'_>,
        section: &str,
    ) -> Result<Option<Budget>, SpecError> {
        let fixed = self.get(table, "budget");
        let per_dim = self.get(table, "budget_per_dim");
        let values = |v: &Value<'_>, key: &str| -> Result<Vec<u64>, SpecError> {
            let field = format!("{section}.{key}");
            self.one_or_many(v, &field)?
                .into_iter()
                .map(|item| self.budget_value(item, &field))
                .collect()
        };
        match (fixed, per_dim) {
            (Some(_), Some(p)) => Err(self.error(
                p.span(),
                &format!("{section}.budget_per_dim"),
                "give either \"budget\" or \"budget_per_dim\", not both".into(),
            )),
            (Some(b), None) => Ok(Some(Budget::Fixed(values(b, "budget")?))),
            (None, Some(p)) => Ok(Some(Budget::PerDim(values(p, "budget_per_dim")?))),
            (None, None) => Ok(None),
        }
    }
}

/// A budget as written in a spec: one value or a grid of values.
#[derive(Clone, Debug)]
pub(crate) enum Budget {
    /// Evaluations per run.
    Fixed(Vec<u64>),
    /// Evaluations per run and dimension.
    PerDim(Vec<u64>),
}

impl Budget {
    /// The budgets of a problem of dimension `dim`.
    fn for_dim(&self, dim: usize) -> Vec<u64> {
        match self {
            Budget::Fixed(b) => b.clone(),
            Budget::PerDim(b) => b.iter().map(|b| b.saturating_mul(dim as u64)).collect(),
        }
    }

    /// The number of budgets listed.
    pub(crate) fn len(&self) -> usize {
        match self {
            Budget::Fixed(b) | Budget::PerDim(b) => b.len(),
        }
    }

    /// Whether several budgets were listed, making the budget a factor.
    pub(crate) fn is_grid(&self) -> bool {
        match self {
            Budget::Fixed(b) | Budget::PerDim(b) => b.len() > 1,
        }
    }
}
