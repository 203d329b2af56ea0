//! The campaigns of `compare` and what they share: each results directory
//! read as `report` reads it (refused without `runs.csv` or with a
//! journal), and the configurations (algorithm label and parameters) A
//! shares with another campaign on a problem at the same budget.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use crate::data::{self, Cell, Dataset, Problem, Provenance, Run};
use crate::files::{read_text_limited, MAX_TEXT_BYTES};
use crate::ReportError;

/// One campaign of a comparison.
pub(crate) struct Side {
    /// `A`, `B`, `C`, … in the order given.
    pub letter: String,
    /// The results directory.
    pub dir: PathBuf,
    /// Its runs.
    pub ds: Dataset,
    /// Its spec, meta and provenance files.
    pub provenance: Provenance,
    /// The FNV-1a 64 hash of its `meta.toml` text, when it has one.
    pub meta_hash: Option<String>,
}

/// One configuration shared by A and another campaign, over the problems
/// both ran it on at the same budget.
pub(crate) struct Shared {
    /// The configuration's name in A.
    pub cell: String,
    /// The other campaign (index into the sides, ≥ 1).
    pub side: usize,
    /// Cell 0: A's runs; cell 1: the other campaign's; problems as A's.
    pub ds: Dataset,
}

/// The letter of the `i`-th campaign: A, B, …, Z, then C27, C28, ….
fn letter(i: usize) -> String {
    match u8::try_from(i) {
        Ok(k) if k < 26 => char::from(b'A' + k).to_string(),
        _ => format!("C{}", i + 1),
    }
}

/// Refuses a directory that is not a finished campaign's.
fn check_input(dir: &Path) -> Result<(), ReportError> {
    let refuse = |why: &str| ReportError::CompareInput {
        dir: dir.to_owned(),
        why: why.to_owned(),
    };
    if !dir.is_dir() {
        return Err(refuse("not a directory"));
    }
    if dir.join("journal.csv").exists() {
        return Err(refuse(
            "campaign unfinished (it has a journal.csv, which a finished run removes): run \
             `metabezier run SPEC --resume` to finish it before comparing",
        ));
    }
    if !dir.join("runs.csv").is_file() {
        return Err(refuse(
            "no runs.csv: not the results directory of a finished campaign",
        ));
    }
    Ok(())
}

/// Reads one campaign.
pub(crate) fn load_side(i: usize, dir: &Path) -> Result<Side, ReportError> {
    check_input(dir)?;
    let ds = data::load(dir, None)?;
    let meta_hash = read_text_limited(&dir.join("meta.toml"), MAX_TEXT_BYTES, "a meta.toml")
        .ok()
        .map(|t| format!("{:016x}", crate::rng::fnv1a64(&t)));
    Ok(Side {
        letter: letter(i),
        dir: dir.to_owned(),
        provenance: data::provenance(dir),
        ds,
        meta_hash,
    })
}

/// The key a problem of one cell matches by: the problem with the budget
/// of its runs.
fn problem_key(p: &Problem, runs: &[Run]) -> Problem {
    Problem {
        budget: runs.first().map(|r| r.budget),
        ..p.clone()
    }
}

/// The configurations A shares with `other` (index `side`), each over the
/// problems both ran it on at the same budget; in A's cell order.
pub(crate) fn shared_cells(a: &Side, other: &Side, side: usize) -> Vec<Shared> {
    let mut out = Vec::new();
    for (ca, cell) in a.ds.cells.iter().enumerate() {
        let Some(cb) = other
            .ds
            .cells
            .iter()
            .position(|c| c.label == cell.label && c.params == cell.params)
        else {
            continue;
        };
        let theirs: BTreeMap<Problem, usize> = (0..other.ds.problems.len())
            .filter(|&p| !other.ds.runs(p, cb).is_empty())
            .map(|p| (problem_key(&other.ds.problems[p], other.ds.runs(p, cb)), p))
            .collect();
        let mut problems = Vec::new();
        let mut runs = Vec::new();
        for (pa, problem) in a.ds.problems.iter().enumerate() {
            let ours = a.ds.runs(pa, ca);
            if ours.is_empty() {
                continue;
            }
            if let Some(&pb) = theirs.get(&problem_key(problem, ours)) {
                problems.push(problem.clone());
                runs.push(vec![ours.to_vec(), other.ds.runs(pb, cb).to_vec()]);
            }
        }
        if problems.is_empty() {
            continue;
        }
        let side_cell = |letter: &str, c: &Cell| Cell {
            name: format!("{}: {}", letter, cell.name),
            ..c.clone()
        };
        let cells = vec![
            side_cell(&a.letter, cell),
            side_cell(&other.letter, &other.ds.cells[cb]),
        ];
        out.push(Shared {
            cell: cell.name.clone(),
            side,
            ds: Dataset::from_parts(cells, problems, runs, &a.ds),
        });
    }
    out
}

/// A few of a campaign's configurations, for the error of nothing shared.
pub(crate) fn some_cells(s: &Side) -> Vec<String> {
    let mut names: Vec<String> =
        s.ds.cells
            .iter()
            .take(5)
            .map(|c| {
                format!(
                    "{} (params `{}`)",
                    c.label,
                    crate::files::excerpt(&c.params)
                )
            })
            .collect();
    if s.ds.cells.len() > 5 {
        names.push(format!("… ({} in all)", s.ds.cells.len()));
    }
    let problems: Vec<String> = s.ds.problems.iter().take(3).map(Problem::title).collect();
    names.push(format!(
        "on {}{}",
        problems.join("; "),
        if s.ds.problems.len() > 3 { "; …" } else { "" }
    ));
    names
}
