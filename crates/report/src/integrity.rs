//! A report states the runs of one finished campaign: it refuses a results
//! directory whose `runs.csv` has duplicated rows, or rows that do not match
//! the campaign's spec (missing or foreign runs), and an unfinished one.
//! An `--external` file is another tool's runs and is not held to the spec.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use super::ReportError;
use crate::experiment::records::RunKey;
use crate::experiment::runner::RunIndex;
use crate::experiment::{RunRecord, Spec};
use crate::files::{read_text_limited, MAX_TEXT_BYTES};

/// What is wrong with the rows of `runs.csv`.
#[derive(Debug, thiserror::Error)]
pub enum RowProblem {
    /// A run appears twice.
    #[error("run {run} of {cell} on {problem} appears twice")]
    Duplicate {
        /// The run number.
        run: u32,
        /// The cell key.
        cell: String,
        /// The problem key.
        problem: String,
    },
    /// A run of the spec is absent.
    #[error(
        "{missing} of {total} runs are missing (the first is run {run} of {cell} on {problem})"
    )]
    Missing {
        /// Runs missing.
        missing: usize,
        /// Runs the spec defines.
        total: usize,
        /// The first missing run's number.
        run: u32,
        /// Its cell key.
        cell: String,
        /// Its problem key.
        problem: String,
    },
    /// A row is not a run of the spec.
    #[error("run {run} of {cell} on {problem} is not a run of spec.toml")]
    Foreign {
        /// The run number.
        run: u32,
        /// The cell key.
        cell: String,
        /// The problem key.
        problem: String,
    },
}

/// The places a report writes in its results directory.
const WRITTEN: [&str; 4] = ["tables", "plots", "report.md", "report.html"];

/// Refuses, before anything is computed, a results directory where a place
/// the report writes (`tables/`, `plots/`, `report.md`, `report.html`) is a
/// symbolic link that leads out of the directory: the report writes only
/// inside it. A link within the directory is followed as before.
pub(crate) fn check_written_inside(dir: &Path) -> Result<(), ReportError> {
    check_inside(dir, &WRITTEN)
}

/// Refuses an output directory `dir` where one of the places `names` that
/// a command writes is a symbolic link leading out of it (the check of
/// [`check_written_inside`], for any list of places).
pub(crate) fn check_inside(dir: &Path, names: &[&str]) -> Result<(), ReportError> {
    let Ok(root) = std::fs::canonicalize(dir) else {
        return Ok(());
    };
    for name in names {
        let path = dir.join(name);
        let is_link = std::fs::symlink_metadata(&path).is_ok_and(|m| m.file_type().is_symlink());
        if !is_link {
            continue;
        }
        let target = std::fs::read_link(&path).unwrap_or_default();
        let inside = std::fs::canonicalize(&path).is_ok_and(|t| t.starts_with(&root));
        if !inside {
            return Err(ReportError::LinkOut { path, target });
        }
    }
    Ok(())
}

/// Refuses a directory whose campaign is unfinished: a journal and no
/// `runs.csv`.
pub(crate) fn check_finished(dir: &Path) -> Result<(), ReportError> {
    if !dir.join("runs.csv").exists() && dir.join("journal.csv").exists() {
        return Err(ReportError::Unfinished {
            dir: dir.to_owned(),
        });
    }
    Ok(())
}

/// Where the spec does not load here (`why`: a fitting spec names its
/// inputs relative to its original place, or a library program registered
/// the optimisers or problems it names), checks what its text alone allows:
/// every (algorithm, problem) of runs.csv has the runs 0..R−1 of the spec's
/// `runs = R`. Returns the note that says so.
fn check_run_numbers(
    spec_path: &Path,
    path: &Path,
    records: &[RunRecord],
    why: &crate::experiment::SpecError,
) -> Result<Option<String>, ReportError> {
    let runs = read_text_limited(spec_path, MAX_TEXT_BYTES, "a spec")
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok())
        .and_then(|t| t.get("experiment")?.get("runs")?.as_integer());
    let Some(runs) = runs.and_then(|r| u32::try_from(r).ok()) else {
        return Ok(Some(
            "spec.toml cannot be read here, so runs.csv was checked for duplicated rows only."
                .into(),
        ));
    };
    let mut groups: std::collections::BTreeMap<(String, String, u64), Vec<u32>> =
        Default::default();
    for r in records {
        groups
            .entry((r.cell_key(), r.match_key(), r.budget))
            .or_default()
            .push(r.run);
    }
    for ((cell, problem, _), mut found) in groups {
        found.sort_unstable();
        if let Some(run) = (0..runs).find(|k| found.binary_search(k).is_err()) {
            return Err(ReportError::Rows {
                path: path.to_owned(),
                problem: RowProblem::Missing {
                    missing: (runs as usize).saturating_sub(found.len()),
                    total: runs as usize,
                    run,
                    cell,
                    problem,
                },
            });
        }
        if let Some(&run) = found.iter().find(|&&k| k >= runs) {
            return Err(ReportError::Rows {
                path: path.to_owned(),
                problem: RowProblem::Foreign { run, cell, problem },
            });
        }
    }
    // The usual causes: a fitting spec names its inputs relative to its
    // original place, or the spec names optimisers or problems registered
    // by the program that ran it.
    let why = why.to_string().replace('`', "'");
    Ok(Some(format!(
        "spec.toml does not load here (`{why}`), so runs.csv was checked against its number of runs, not against its problems."
    )))
}

/// The runs (cell, problem, budget, run number) of `records`, each once;
/// or the index of the first record whose run an earlier one already gave.
pub(crate) fn runs_once(records: &[RunRecord]) -> Result<HashSet<RunKey>, usize> {
    let mut seen: HashSet<RunKey> = HashSet::new();
    match records.iter().position(|r| !seen.insert(r.key())) {
        Some(i) => Err(i),
        None => Ok(seen),
    }
}

/// Checks the rows of `runs.csv` in `dir`: no run twice, and, when the
/// directory's `spec.toml` loads, exactly the runs it defines. Returns a
/// note when the spec could not be loaded here (a fitting spec whose
/// inputs are named relative to its original place), so only duplicates
/// were checked.
pub(crate) fn check_rows(dir: &Path, records: &[RunRecord]) -> Result<Option<String>, ReportError> {
    let path = dir.join("runs.csv");
    let rows = |problem| ReportError::Rows {
        path: path.clone(),
        problem,
    };
    let seen = runs_once(records).map_err(|i| {
        let r = &records[i];
        rows(RowProblem::Duplicate {
            run: r.run,
            cell: r.cell_key(),
            problem: r.match_key(),
        })
    })?;
    let spec_path: PathBuf = dir.join("spec.toml");
    if !spec_path.exists() {
        return Ok(None);
    }
    let spec = match Spec::load(&spec_path) {
        Ok(s) => s,
        Err(e) => return check_run_numbers(&spec_path, &path, records, &e),
    };
    let index = RunIndex::of(&spec);
    if let Some(r) = records.iter().find(|r| index.get(&r.key()).is_none()) {
        return Err(rows(RowProblem::Foreign {
            run: r.run,
            cell: r.cell_key(),
            problem: r.match_key(),
        }));
    }
    if records.len() < index.len() {
        let key = (0..index.len())
            .map(|i| index.key(spec.run_id(i)))
            .find(|k| !seen.contains(k))
            .expect("fewer rows than runs, none foreign or twice");
        return Err(rows(RowProblem::Missing {
            missing: index.len() - records.len(),
            total: index.len(),
            run: key.3,
            cell: key.0.clone(),
            problem: key.1.clone(),
        }));
    }
    Ok(None)
}
