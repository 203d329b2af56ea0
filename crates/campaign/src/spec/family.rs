//! Problem families: what a `[[problem]]` section holds, chosen by its
//! `suite`. Without `suite` a section names the thesis's functions and the
//! registered problems ([`super::functions::Functions`]); `suite = "bbob"`
//! names COCO's suite ([`super::bbob::BbobSuite`]); a library user
//! registers more ([`crate::Registry::register_family`]).
//!
//! A family owns its grammar: its keys, the reading of its section into
//! problems at one dimension each, and its entry in `metabezier list`. The
//! spec owns the rest, the same for every family: the budget (`budget` or
//! `budget_per_dim`, of the section or of `[experiment]`), the expansion of
//! each problem over the budgets listed, the limit on the number of
//! problems and the refusal of a problem listed twice. Every family's
//! runs fill the same `runs.csv` columns: `problem` is
//! [`ProblemKind::name`], `dim`, `transform` and `instance` are those of
//! its [`FamilyProblem`].

use std::collections::HashSet;
use std::fmt;
use std::ops::{Deref, Range};
use std::sync::Arc;

use toml::de::DeValue;

use super::budget::Budget;
use super::reader::Parser;
use super::{ProblemEntry, ProblemKind, SpecError, Table, Value};
use crate::functions::Transform;
use crate::registry::Registry;

/// A family of benchmark problems with its own `[[problem]]` section,
/// named there by `suite = "…"`.
pub trait ProblemFamily: Send + Sync + fmt::Debug {
    /// The `suite` value that names it (`"bbob"`).
    fn suite(&self) -> &str;

    /// Every key its section takes, `suite` and the budget keys
    /// (`budget`, `budget_per_dim`) among them.
    fn keys(&self) -> &[&str];

    /// Why this build cannot read the family, if it cannot (COCO's suite
    /// in a build without COCO).
    fn unavailable(&self) -> Option<&str> {
        None
    }

    /// Reads one section: each problem of it, at one dimension, is given
    /// to `sink`, which expands it over the budgets and refuses a
    /// duplicate. Errors are located in the section's text.
    fn read(
        &self,
        section: &ProblemSection<'_, '_>,
        sink: &mut ProblemSink<'_>,
    ) -> Result<(), SpecError>;

    /// Its entry in `metabezier list`: a heading line, then one line per
    /// problem, each ending in a newline.
    fn list_entry(&self, registry: &Registry) -> String;
}

/// One `[[problem]]` section as its family reads it: the grammar's
/// primitives (through `Deref`), the section's table, name and span, and
/// the registry names resolve in.
#[derive(Clone, Copy)]
pub struct ProblemSection<'s, 'i> {
    pub(super) grammar: metabezier_spec::Parser<'s>,
    /// The section's keys and values.
    pub table: &'s Table<'i>,
    /// The section as errors name it: `problem[2]`.
    pub name: &'s str,
    /// The section itself, whose span locates errors about all of it.
    pub entry: &'s Value<'i>,
    /// The optimisers, problems and families of the spec.
    pub registry: &'s Registry,
}

impl<'s> Deref for ProblemSection<'s, '_> {
    type Target = metabezier_spec::Parser<'s>;

    fn deref(&self) -> &Self::Target {
        &self.grammar
    }
}

impl ProblemSection<'_, '_> {
    /// The name of `key` in errors: `problem[2].dim`.
    pub fn field(&self, key: &str) -> String {
        format!("{}.{key}", self.name)
    }

    /// The span of the whole section.
    pub fn span(&self) -> Range<usize> {
        self.entry.span()
    }

    /// The optional `instances`: a count N (instances 1..=N, N ≤
    /// `max_count`) or a list of distinct instance numbers, each in
    /// 1..=`max_instance`; absent, instance 1 alone.
    pub fn instances(&self, max_count: u64, max_instance: u64) -> Result<Vec<u32>, SpecError> {
        let field = self.field("instances");
        let Some(v) = self.get(self.table, "instances") else {
            return Ok(vec![1]);
        };
        let DeValue::Array(_) = v.get_ref() else {
            return Ok((1..=self.integer(v, &field, 1, max_count)? as u32).collect());
        };
        let mut out: Vec<u32> = Vec::new();
        for item in self.one_or_many(v, &field)? {
            let k = self.integer(item, &field, 1, max_instance)? as u32;
            if out.contains(&k) {
                return Err(self.error(
                    item.span(),
                    &field,
                    format!(
                        "instance {k} is listed twice; give a count N (instances 1..N) or a list of distinct instance numbers"
                    ),
                ));
            }
            out.push(k);
        }
        Ok(out)
    }
}

/// One problem of a family at one dimension, before the spec expands it
/// over the budgets.
#[derive(Clone, Debug)]
pub struct FamilyProblem {
    /// What is solved.
    pub kind: Arc<dyn ProblemKind>,
    /// Its dimension (the `dim` column).
    pub dim: usize,
    /// Its transform (the `transform` column; `none` for most families).
    pub transform: Transform,
    /// Its instance (the `instance` column; 1 for most families).
    pub instance: u32,
    /// Where a budget too large for the dimension is reported: the span of
    /// the dimension.
    pub budget_span: Range<usize>,
    /// Where a problem listed twice is reported.
    pub span: Range<usize>,
}

/// The problems of a spec so far, each key once.
#[derive(Default)]
pub(crate) struct Problems {
    /// The problems, in spec order.
    pub(crate) list: Vec<ProblemEntry>,
    seen: HashSet<String>,
}

impl Problems {
    /// Appends `p`, refusing (at `span`, field `section`) a problem whose
    /// key an earlier one has.
    pub(crate) fn push(
        &mut self,
        parser: &Parser<'_>,
        p: ProblemEntry,
        span: Range<usize>,
        section: &str,
    ) -> Result<(), SpecError> {
        if !self.seen.insert(p.key()) {
            let message = format!("problem {} is listed twice", p.key());
            return Err(parser.error(span, section, message));
        }
        self.list.push(p);
        Ok(())
    }
}

/// Where a family puts the problems of a section: each is expanded over
/// the section's budgets into the spec's problems, one key once.
pub struct ProblemSink<'s> {
    pub(super) parser: &'s Parser<'s>,
    pub(super) section: &'s str,
    pub(super) span: Range<usize>,
    pub(super) budget: &'s Budget,
    pub(super) problems: &'s mut Problems,
}

impl ProblemSink<'_> {
    /// Refuses a section of `count` problems (before the budgets) that
    /// would take the spec past [`super::MAX_PROBLEMS`]; a family calls it
    /// before it builds them.
    pub fn reserve(&self, count: u128) -> Result<(), SpecError> {
        let count = count.saturating_mul(self.budget.len() as u128);
        let have = self.problems.list.len();
        self.parser
            .check_problem_count(have, count, &self.span, self.section)
    }

    /// Adds `p` at each budget of the section, refusing a budget above the
    /// limit at its dimension and a problem listed twice.
    pub fn add(&mut self, p: FamilyProblem) -> Result<(), SpecError> {
        let parser = self.parser;
        let budgets = parser.dim_budgets(self.budget, p.dim, &p.budget_span, self.section)?;
        for budget in budgets {
            let entry = ProblemEntry {
                kind: Arc::clone(&p.kind),
                dim: p.dim,
                budget,
                budget_factor: self.budget.is_grid(),
                transform: p.transform,
                instance: p.instance,
            };
            self.problems
                .push(parser, entry, p.span.clone(), self.section)?;
        }
        Ok(())
    }
}
