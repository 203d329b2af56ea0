//! Reading the `[[problem]]` sections: each section's keys checked
//! against the thesis's functions' and its family's together, its budget,
//! its `suite` resolved in the registry, then the section read by its
//! family ([`ProblemFamily::read`]) and expanded over its budgets.

use std::ops::Range;

use super::budget::Budget;
use super::family::{ProblemFamily, ProblemSection, ProblemSink, Problems};
use super::functions::Functions;
use super::reader::Parser;
use super::{choices_hint, SpecError, Table};

impl Parser<'_> {
    /// The `[[problem]]` problems of the spec, each section read by its
    /// family and expanded over its budgets.
    pub(super) fn problems(
        &self,
        root: &Table<'_>,
        default_budget: Option<&Budget>,
        span: Range<usize>,
    ) -> Result<Problems, SpecError> {
        let mut problems = Problems::default();
        for (i, entry) in self
            .array_of_tables(root, "problem", span)?
            .into_iter()
            .enumerate()
        {
            let name = format!("problem[{}]", i + 1);
            let table = self.table(entry, &name)?;
            let section = ProblemSection {
                grammar: self.grammar,
                table,
                name: &name,
                entry,
                registry: self.registry,
            };
            self.problem_section(&section, default_budget, &mut problems)?;
        }
        Ok(problems)
    }

    /// Reads one `[[problem]]` section. Its keys are checked against those
    /// of the thesis's functions and its family's together, then its
    /// budget, then its `suite`, then its family's keys alone.
    fn problem_section(
        &self,
        section: &ProblemSection<'_, '_>,
        default_budget: Option<&Budget>,
        problems: &mut Problems,
    ) -> Result<(), SpecError> {
        let family = self.family(section);
        let default = Functions;
        let mut keys: Vec<&str> = default.keys().to_vec();
        if let Ok(Some(f)) = &family {
            let more: Vec<&str> = f
                .keys()
                .iter()
                .filter(|k| !keys.contains(k))
                .copied()
                .collect();
            keys.extend(more);
        }
        self.check_keys(section.table, section.name, &keys)?;
        let own = self.budget(section.table, section.name)?;
        let budget = own.as_ref().or(default_budget).ok_or_else(|| {
            self.error(
                section.span(),
                &section.field("budget"),
                "no budget: give \"budget\" or \"budget_per_dim\" in [experiment] or in this [[problem]]".into(),
            )
        })?;
        let family: &dyn ProblemFamily = match family? {
            Some(f) => f,
            None => &default,
        };
        self.check_keys(section.table, section.name, family.keys())?;
        let mut sink = ProblemSink {
            parser: self,
            section: section.name,
            span: section.span(),
            budget,
            problems,
        };
        family.read(section, &mut sink)
    }

    /// The family a `[[problem]]` names by `suite`, `None` without it (the
    /// thesis's functions).
    fn family<'r>(
        &self,
        section: &ProblemSection<'r, '_>,
    ) -> Result<Option<&'r dyn ProblemFamily>, SpecError> {
        let Some(v) = self.get(section.table, "suite") else {
            return Ok(None);
        };
        let field = section.field("suite");
        let name = self.string(v, &field)?;
        let Some(family) = section.registry.family(&name) else {
            let suites = section.registry.suites();
            return Err(self.error(
                v.span(),
                &field,
                format!("unknown suite \"{name}\"; {}", choices_hint(&name, &suites)),
            ));
        };
        match family.unavailable() {
            Some(why) => Err(self.error(v.span(), &field, why.to_owned())),
            None => Ok(Some(family)),
        }
    }
}
