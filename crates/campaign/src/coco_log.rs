//! COCO-format logs of a campaign's bbob runs (`metabezier run --coco-log
//! DIR`), for COCO's post-processing `cocopp` (Hansen et al. 2021).
//!
//! COCO's observer keeps process-wide state and writes as the evaluations
//! happen, so it cannot watch runs that execute in parallel threads. The
//! log is therefore made by a deterministic replay once the campaign's runs
//! are finished: every bbob run of the campaign (or of the shard) is run
//! again, on one thread, with the same seed and so the same evaluations,
//! on a problem observed by one COCO observer per algorithm cell. The
//! replay costs the bbob runs' time once more and works the same after
//! `--resume` and for each `--shard`.

use std::path::{Path, PathBuf};

#[cfg(feature = "coco")]
use super::runner::run_seed;
use super::runner::Shard;
#[cfg(feature = "coco")]
use super::spec::minimise_problem;
use super::spec::{Bbob, Spec};
use super::ExperimentError;
use crate::files::{create_dir, write_atomic, IoError};
#[cfg(feature = "coco")]
use crate::reconstruction::Method;
#[cfg(feature = "coco")]
use metabezier_bbob::{BbobProblem, CocoObserver};

/// Why a COCO log cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum CocoLogError {
    /// The campaign has no bbob problem to log.
    #[error("--coco-log: {spec} has no bbob problems ([[problem]] suite = \"bbob\"), so there is nothing for COCO's logger", spec = .0.display())]
    NoBbob(PathBuf),
    /// COCO refused the folder or a problem.
    #[error("--coco-log: {0}")]
    Coco(#[from] metabezier_bbob::BbobError),
    /// This build has no COCO (made without the `coco` feature).
    #[error("--coco-log: {}", super::spec::NO_COCO)]
    NoCoco,
}

/// An algorithm name COCO's option parser accepts: the label with every
/// character other than letters, digits, `-`, `_` and `.` replaced by `_`.
#[cfg_attr(not(feature = "coco"), allow(dead_code))]
fn coco_name(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Replays the bbob runs of `spec` (those of `shard` when given) with COCO's
/// `bbob` observer into `dir`, one folder per algorithm cell; returns the
/// folders COCO wrote.
pub fn write_coco_log(
    spec: &Spec,
    shard: Option<Shard>,
    dir: &Path,
) -> Result<Vec<PathBuf>, ExperimentError> {
    check(spec, dir)?;
    replay(spec, shard, dir)
}

/// Without COCO there is nothing to replay with ([`check`] says so first).
#[cfg(not(feature = "coco"))]
fn replay(_: &Spec, _: Option<Shard>, _: &Path) -> Result<Vec<PathBuf>, ExperimentError> {
    Err(CocoLogError::NoCoco.into())
}

/// The replay of [`write_coco_log`].
#[cfg(feature = "coco")]
fn replay(spec: &Spec, shard: Option<Shard>, dir: &Path) -> Result<Vec<PathBuf>, ExperimentError> {
    let outer = dir.to_string_lossy().into_owned();
    let ids: Vec<_> = spec
        .run_ids()
        .into_iter()
        .filter(|id| shard.is_none_or(|s| s.contains(id.index)))
        .collect();
    let mut folders = Vec::new();
    for (c, cell) in spec.cells.iter().enumerate() {
        let Method::Metaheuristic(algorithm) = &cell.method else {
            continue;
        };
        let name = coco_name(&cell.label);
        let observer = CocoObserver::new(&outer, &name, &name).map_err(CocoLogError::from)?;
        for id in ids.iter().filter(|id| id.cell == c) {
            let entry = &spec.problems[id.problem];
            let Some(&Bbob { function, fopt }) = entry.kind_as::<Bbob>() else {
                continue;
            };
            let problem =
                BbobProblem::observed(function, entry.dim, entry.instance as usize, &observer)
                    .map_err(CocoLogError::from)?;
            minimise_problem(spec, entry, algorithm, &*problem, fopt, run_seed(spec, *id));
        }
        folders.push(PathBuf::from(observer.folder()));
    }
    Ok(folders)
}

/// Checks that `spec` has bbob problems and that `dir` can be created and
/// written, before any run (and before COCO, which ends the process when it
/// cannot create its folders).
pub fn check(spec: &Spec, dir: &Path) -> Result<(), ExperimentError> {
    if cfg!(not(feature = "coco")) {
        return Err(CocoLogError::NoCoco.into());
    }
    if !spec.problems.iter().any(|p| p.kind_as::<Bbob>().is_some()) {
        return Err(CocoLogError::NoBbob(spec.path.clone()).into());
    }
    create_dir(dir)?;
    let probe = dir.join(".metabezier-write-test");
    write_atomic(&probe, b"")?;
    std::fs::remove_file(&probe).map_err(|e| IoError::new("remove", &probe, e))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn algorithm_names_lose_white_space() {
        assert_eq!(super::coco_name("MHS (tuned), L=3"), "MHS__tuned___L_3");
    }
}
