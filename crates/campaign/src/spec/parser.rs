//! The spec reader: the `[experiment]` header, the sections a spec may
//! have, and the order they are read in.

use std::ops::Range;

use toml::de::DeValue;

use super::budget::Budget;
use super::family::Problems;
use super::reader::Parser;
use super::{
    choices_hint, Factor, ProblemEntry, Spec, SpecError, Stop, Table, WithSpan, MAX_NAME_CHARS,
};
use crate::optim::quoted_list;

const EXPERIMENT_KEYS: [&str; 10] = [
    "name",
    "description",
    "seed",
    "runs",
    "budget",
    "budget_per_dim",
    "threshold",
    "checkpoints_per_decade",
    "paired",
    "stop",
];
const SECTIONS: [&str; 5] = ["experiment", "problem", "fit", "algorithm", "report"];

impl<'a> Parser<'a> {
    pub(super) fn spec(&self) -> Result<Spec, SpecError> {
        let doc = self.toml()?;
        let root = doc.get_ref();
        self.check_sections(root)?;
        let header = self.experiment(root, doc.span())?;
        let problems = self.all_problems(root, header.budget.as_ref(), doc.span())?;
        let benchmarks = problems.iter().any(|p| !p.kind.least_squares());
        if header.stop.0 == Stop::Target && problems.iter().any(|p| !p.kind.has_targets()) {
            return Err(self.error(
                header.stop.1.clone(),
                "experiment.stop",
                "stop = \"target\" ends a benchmark run at f − f* ≤ threshold, but this spec \
                 has [[fit]] problems, which have no target: remove `stop` (a fit ends at its \
                 budget or its `tolerance`) or put the fits in a spec of their own"
                    .into(),
            ));
        }
        let cells = self.cells(root, doc.span(), benchmarks, (problems.len(), header.runs))?;
        let paired = self.paired(root, &problems)?;
        let ropes = self.report_section(root)?;
        Ok(Spec {
            path: self.path.to_owned(),
            text: self.text.to_owned(),
            name: header.name,
            seed: header.seed,
            runs: header.runs,
            threshold: header.threshold,
            checkpoints_per_decade: header.checkpoints_per_decade,
            stop: header.stop.0,
            problems,
            cells,
            paired,
            ropes,
        })
    }

    /// The optional `experiment.paired`: factors that vary among the
    /// problems and are left out of the seeds.
    fn paired(
        &self,
        root: &Table<'_>,
        problems: &[ProblemEntry],
    ) -> Result<Vec<Factor>, SpecError> {
        let Some(experiment) = self
            .get(root, "experiment")
            .and_then(|e| match e.get_ref() {
                DeValue::Table(t) => Some(t),
                _ => None,
            })
        else {
            return Ok(Vec::new());
        };
        let Some(v) = self.get(experiment, "paired") else {
            return Ok(Vec::new());
        };
        let field = "experiment.paired";
        let mut out = Vec::new();
        for item in self.one_or_many(v, field)? {
            let name = self.string(item, field)?;
            let factor = Factor::from_name(&name).ok_or_else(|| {
                self.error(
                    item.span(),
                    field,
                    format!(
                        "unknown factor \"{name}\"; {}",
                        choices_hint(&name, &Factor::NAMES)
                    ),
                )
            })?;
            let values: std::collections::BTreeSet<String> = problems
                .iter()
                .filter_map(|p| p.factor_value(factor))
                .collect();
            if values.len() < 2 {
                let varying: Vec<&str> = Factor::ALL
                    .into_iter()
                    .filter(|&f| {
                        problems
                            .iter()
                            .filter_map(|p| p.factor_value(f))
                            .collect::<std::collections::BTreeSet<_>>()
                            .len()
                            > 1
                    })
                    .map(Factor::name)
                    .collect();
                return Err(self.error(
                    item.span(),
                    field,
                    format!(
                        "\"{name}\" does not vary among this spec's problems, so there is nothing to pair; {}",
                        if varying.is_empty() {
                            "no factor varies here".to_owned()
                        } else {
                            format!("the varying factors are {}", quoted_list(&varying))
                        }
                    ),
                ));
            }
            if !out.contains(&factor) {
                out.push(factor);
            }
        }
        out.sort();
        Ok(out)
    }

    /// Checks that every top-level key is a known section.
    fn check_sections(&self, root: &Table<'_>) -> Result<(), SpecError> {
        for (k, _) in root.iter() {
            let key: &str = k.get_ref();
            if !SECTIONS.contains(&key) {
                return Err(self.error(
                    k.span(),
                    key,
                    format!("unknown section; {}", choices_hint(key, &SECTIONS)),
                ));
            }
        }
        Ok(())
    }

    /// The required `[experiment]` section; `span` is the document's.
    fn experiment(&self, root: &Table<'_>, span: Range<usize>) -> Result<Header, SpecError> {
        let experiment = self
            .get(root, "experiment")
            .ok_or_else(|| self.error(0..0, "experiment", "missing [experiment] section".into()))?;
        let experiment = self.table(experiment, "experiment")?;
        self.check_keys(experiment, "experiment", &EXPERIMENT_KEYS)?;
        let name = self.experiment_name(experiment, span.clone())?;
        let seed_v = self.required(experiment, "experiment", "seed", span.clone())?;
        let seed = self.integer(seed_v, "experiment.seed", 0, i64::MAX as u64)?;
        let runs_v = self.required(experiment, "experiment", "runs", span)?;
        let runs = self.integer(runs_v, "experiment.runs", 1, u64::from(u32::MAX))? as u32;
        let budget = self.budget(experiment, "experiment")?;
        let threshold = match self.get(experiment, "threshold") {
            Some(v) => {
                let t = self.real(v, "experiment.threshold")?;
                if !t.is_finite() || t < 0.0 {
                    return Err(self.error(
                        v.span(),
                        "experiment.threshold",
                        format!("expected a finite real number ≥ 0, found {t}"),
                    ));
                }
                t
            }
            None => 1e-8,
        };
        let checkpoints_per_decade = match self.get(experiment, "checkpoints_per_decade") {
            Some(v) => self.integer(v, "experiment.checkpoints_per_decade", 1, 1000)? as u32,
            None => 10,
        };
        if let Some(v) = self.get(experiment, "description") {
            self.string(v, "experiment.description")?;
        }
        let stop = self.stop(experiment)?;
        Ok(Header {
            name,
            seed,
            runs,
            budget,
            threshold,
            checkpoints_per_decade,
            stop,
        })
    }

    /// The optional `experiment.stop` ([`Stop`]), with its span (the empty
    /// span when absent).
    fn stop(&self, experiment: &Table<'_>) -> Result<WithSpan<Stop>, SpecError> {
        let Some(v) = self.get(experiment, "stop") else {
            return Ok((Stop::default(), 0..0));
        };
        let name = self.string(v, "experiment.stop")?;
        let stop = Stop::from_name(&name).ok_or_else(|| {
            self.error(
                v.span(),
                "experiment.stop",
                format!(
                    "expected where a run ends, found \"{name}\"; {}",
                    choices_hint(&name, &Stop::NAMES)
                ),
            )
        })?;
        Ok((stop, v.span()))
    }

    /// The required `experiment.name`, which names the results directory.
    fn experiment_name(
        &self,
        experiment: &Table<'_>,
        span: Range<usize>,
    ) -> Result<String, SpecError> {
        let name_v = self.required(experiment, "experiment", "name", span)?;
        let name = self.string(name_v, "experiment.name")?;
        if name.chars().count() > MAX_NAME_CHARS {
            return Err(self.error(
                name_v.span(),
                "experiment.name",
                format!(
                    "expected a name of at most {MAX_NAME_CHARS} characters (it names the results directory), found {} characters",
                    name.chars().count()
                ),
            ));
        }
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.')
            || name.starts_with('.')
        {
            return Err(self.error(
                name_v.span(),
                "experiment.name",
                format!("expected a name of letters, digits, '-', '_' or '.' (it names the results directory), found \"{name}\""),
            ));
        }
        Ok(name)
    }

    /// The `[[problem]]` problems (required without `[[fit]]`), then the
    /// `[[fit]]` ones; no problem twice.
    fn all_problems(
        &self,
        root: &Table<'_>,
        budget: Option<&Budget>,
        span: Range<usize>,
    ) -> Result<Vec<ProblemEntry>, SpecError> {
        let mut problems = Problems::default();
        if self.get(root, "problem").is_some() || self.get(root, "fit").is_none() {
            problems = self.problems(root, budget, span.clone())?;
        }
        if self.get(root, "fit").is_some() {
            self.fits(root, budget, span, &mut problems)?;
        }
        Ok(problems.list)
    }
}

/// The `[experiment]` section of a spec.
struct Header {
    name: String,
    seed: u64,
    runs: u32,
    /// The default budget of the problems.
    budget: Option<Budget>,
    threshold: f64,
    checkpoints_per_decade: u32,
    /// `experiment.stop` and its span.
    stop: WithSpan<Stop>,
}
