//! The columns a campaign's result files carry ([`Schema`]).

use std::collections::HashMap;

use super::*;
use crate::functions::Transform;
use crate::spec::Spec;

/// Whether any record carries the current fitting records.
pub(crate) fn current_fit_records(records: &[RunRecord]) -> bool {
    records
        .iter()
        .any(|r| r.fit.as_ref().is_some_and(|f| f.rms_distance.is_some()))
}

/// Which design-factor columns the result files of a campaign carry, beyond
/// the columns every campaign has. Files of campaigns without transformed
/// instances or budget grids keep exactly the columns they had before these
/// factors existed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Schema {
    /// `transform` and `instance` columns: some run is on a transformed
    /// benchmark instance.
    pub instances: bool,
    /// A `budget` column in the files keyed by run (convergence, timing,
    /// fits, segments, hits): runs of one problem differ in budget.
    pub keyed_budget: bool,
}

impl Schema {
    /// The schema the records need.
    pub fn of<'a>(records: impl IntoIterator<Item = &'a RunRecord>) -> Schema {
        let mut instances = false;
        let mut budgets: HashMap<(String, String, u32), u64> = HashMap::new();
        let mut keyed_budget = false;
        for r in records {
            instances |= r.transform != Transform::None || r.instance != 1;
            let b = budgets
                .entry((r.cell_key(), r.match_key(), r.run))
                .or_insert(r.budget);
            keyed_budget |= *b != r.budget;
        }
        Schema {
            instances,
            keyed_budget,
        }
    }

    /// The schema of the complete records of `spec`, from the spec alone
    /// (equal to [`Schema::of`] of them, without a map over every run):
    /// instances when a problem is a transformed instance, a keyed budget
    /// when two problems differ in budget only.
    pub fn of_spec(spec: &Spec) -> Schema {
        let instances = spec
            .problems
            .iter()
            .any(|p| p.transform != Transform::None || p.instance != 1);
        let mut budgets: HashMap<String, u64> = HashMap::new();
        let mut keyed_budget = false;
        for p in &spec.problems {
            keyed_budget |= *budgets.entry(p.match_key()).or_insert(p.budget) != p.budget;
        }
        Schema {
            instances,
            keyed_budget,
        }
    }

    /// The columns of `runs.csv`: [`RUNS_HEADER`], with `transform` and
    /// `instance` after `budget` when the campaign has instances.
    pub fn runs_header(self) -> Vec<&'static str> {
        let mut h: Vec<&'static str> = RUNS_HEADER.to_vec();
        if self.instances {
            h.splice(6..6, ["transform", "instance"]);
        }
        h
    }

    /// The columns identifying a run in the keyed files, followed by `rest`.
    pub fn keyed_header(self, rest: &[&'static str]) -> Vec<&'static str> {
        let mut h = vec!["algorithm", "kind", "params", "problem", "dim"];
        if self.keyed_budget {
            h.push("budget");
        }
        if self.instances {
            h.extend(["transform", "instance"]);
        }
        h.push("run");
        h.extend_from_slice(rest);
        h
    }

    /// The number of key columns of a keyed file.
    pub(crate) fn key_len(self) -> usize {
        6 + usize::from(self.keyed_budget) + 2 * usize::from(self.instances)
    }

    /// The schema whose [`Schema::runs_header`] is `found`.
    pub(crate) fn from_runs_header(found: &[&str]) -> Option<Schema> {
        [false, true]
            .into_iter()
            .map(|instances| Schema {
                instances,
                keyed_budget: false,
            })
            .find(|s| s.runs_header() == found)
    }

    /// The schema whose [`Schema::keyed_header`] with `rest` is `found`.
    pub(crate) fn from_keyed_header(found: &[&str], rest: &[&'static str]) -> Option<Schema> {
        [(false, false), (false, true), (true, false), (true, true)]
            .into_iter()
            .map(|(instances, keyed_budget)| Schema {
                instances,
                keyed_budget,
            })
            .find(|s| s.keyed_header(rest) == found)
    }

    /// The key fields of `r` in a keyed file.
    pub(crate) fn key_fields(self, r: &RunRecord) -> Vec<String> {
        let mut row = vec![
            r.algorithm.clone(),
            r.kind.clone(),
            r.params.clone(),
            r.problem.clone(),
            r.dim.to_string(),
        ];
        if self.keyed_budget {
            row.push(r.budget.to_string());
        }
        if self.instances {
            row.extend([r.transform.name().to_owned(), r.instance.to_string()]);
        }
        row.push(r.run.to_string());
        row
    }
}
