//! The setup tables of a report: the algorithm configurations compared
//! and the problems with their budgets and run counts, rendered from the
//! dataset.

use super::data;
use super::format::Table;

/// The table of the compared algorithm configurations.
pub(crate) fn algorithms_table(ds: &data::Dataset) -> Table {
    let mut t = Table {
        stem: "algorithms".into(),
        title: "Algorithms".into(),
        intro: vec![
            "The algorithm configurations compared, with their complete parameters.".into(),
        ],
        md_header: ["Algorithm", "Optimiser", "Parameters", "Source"]
            .map(String::from)
            .to_vec(),
        csv_header: ["name", "algorithm", "kind", "params", "external"]
            .map(String::from)
            .to_vec(),
        ..Table::default()
    };
    for c in &ds.cells {
        t.md_rows.push(vec![
            c.name.clone(),
            c.kind.clone(),
            format!("`{}`", c.params.replace('`', "'")),
            if c.external { "external" } else { "results" }.into(),
        ]);
        t.csv_rows.push(vec![
            c.name.clone(),
            c.label.clone(),
            c.kind.clone(),
            c.params.clone(),
            c.external.to_string(),
        ]);
    }
    t
}

/// The table of the problems with their budgets and run counts.
pub(crate) fn problems_table(ds: &data::Dataset) -> Table {
    let mut t = Table {
        stem: "problems".into(),
        title: "Problems".into(),
        intro: vec![if ds.problems.iter().any(|p| p.function.contains('/')) {
            "Each problem is a benchmark function at a dimension D, or a fitting case \
             source/function/continuity, whose D is its number of segments and whose budget \
             is the total over its segments."
                .into()
        } else {
            "Each problem is a benchmark function at a dimension D.".into()
        }],
        md_header: ["Problem", "D", "Budget", "Algorithms", "Runs"]
            .map(String::from)
            .to_vec(),
        csv_header: ["problem", "dim", "budget", "algorithms", "runs"]
            .map(String::from)
            .to_vec(),
        ..Table::default()
    };
    for (p, problem) in ds.problems.iter().enumerate() {
        let mut budgets: Vec<u64> = Vec::new();
        let mut algorithms = 0usize;
        let mut runs = 0usize;
        for c in 0..ds.cells.len() {
            let r = ds.runs(p, c);
            if !r.is_empty() {
                algorithms += 1;
                runs += r.len();
            }
            budgets.extend(r.iter().map(|x| x.budget));
        }
        budgets.sort_unstable();
        budgets.dedup();
        let budget = budgets
            .iter()
            .map(u64::to_string)
            .collect::<Vec<_>>()
            .join(" / ");
        t.md_rows.push(vec![
            problem.short(),
            problem.dim.to_string(),
            budget.clone(),
            algorithms.to_string(),
            runs.to_string(),
        ]);
        t.csv_rows.push(vec![
            problem.label(),
            problem.dim.to_string(),
            budget,
            algorithms.to_string(),
            runs.to_string(),
        ]);
    }
    t
}
