//! The campaign machinery, in the order data flows through it:
//! a TOML [`spec`] is checked completely, the [`runner`] executes its seeded
//! runs in parallel (each yielding its trace and, for a fit, an
//! [`outcome::FitDetail`]) and appends each finished run to the [`journal`], and
//! [`records`] writes the tidy CSV result files (with the per-segment
//! columns of fitting runs in [`segments`]). [`fit_files`] writes the same
//! records for a single `metabezier fit`. [`shards`] joins the shards of a
//! campaign, and [`slurm`] writes the array job that runs them on a cluster.
//!
//! This crate (metabezier-campaign, today's `experiment` room) sits above
//! the optimisers (`metabezier-core`), the fitting pipeline
//! (`metabezier-fit`) and the spec grammar (`metabezier-spec`), and below the
//! report and the command line; the report reads what [`records`] writes
//! and nothing else of this crate. The rooms it stands on are named at this
//! root, so that `crate::optim` reads as it did in the one-crate house.
#![warn(missing_docs)]

use metabezier_core::{functions, geometry, optim, problem, rng, simd};
use metabezier_files as files;
use metabezier_fit::{fit, outline, reconstruction};

pub mod archive;
pub mod coco_log;
pub mod fit_files;
pub mod journal;
pub mod journal_check;
pub mod listing;
pub mod outcome;
pub mod provenance;
pub mod reading;
pub mod records;
pub mod registry;
pub mod runner;
pub mod segments;
pub mod shards;
pub mod slurm;
pub mod spec;

use std::fmt;
use std::path::PathBuf;

use crate::files::IoError;

pub use records::{DataError, DataProblem, ReadError, RunRecord};
pub use registry::{
    BuildError, InstanceError, ProblemDef, ProblemRegistryError, Registry, SharedProblem,
};
pub use runner::{run_campaign, RunOptions, Shard, ShardError, ShardProblem, Summary};
pub use shards::{find_shards, merge, MergeInputs, ShardGap};
pub use slurm::{SlurmError, SlurmOptions};
pub use spec::{FamilyRegistryError, Spec, SpecError, SpecLimits};

/// Why a campaign cannot proceed as asked: a resume or a merge that would
/// mix runs of different campaigns, or a machine that cannot start it.
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// The output directory holds runs and `--resume` was not given.
    #[error(
        "{} already holds runs of a campaign; pass --resume to continue it (finished runs are kept), or choose another --out",
        out.display()
    )]
    AlreadyHoldsRuns {
        /// The output directory.
        out: PathBuf,
    },
    /// The spec differs from the copy made when the campaign started.
    #[error(
        "cannot resume: {} differs from {}, the copy made when the campaign started, so finished runs would not match; restore the spec or choose another --out",
        spec.display(),
        copy.display()
    )]
    SpecChanged {
        /// The spec given now.
        spec: PathBuf,
        /// The copy in the output directory.
        copy: PathBuf,
    },
    /// The output directory was started as another shard (or unsharded).
    #[error(
        "cannot resume: {} was started as shard {}, not {}",
        out.display(),
        started.as_deref().unwrap_or("(none)"),
        asked.as_deref().unwrap_or("(none)")
    )]
    ShardChanged {
        /// The output directory.
        out: PathBuf,
        /// The shard it was started as (`K/N`), if any.
        started: Option<String>,
        /// The shard asked for now, if any.
        asked: Option<String>,
    },
    /// A results directory holds a run the spec does not define.
    #[error(
        "cannot {action}: {} holds run {run} of {cell} on {problem}, which the spec does not define",
        dir.display()
    )]
    ForeignRun {
        /// What was being done.
        action: CampaignAction,
        /// The directory holding the run.
        dir: PathBuf,
        /// The run number.
        run: u32,
        /// The run's cell key.
        cell: String,
        /// The run's problem key.
        problem: String,
    },
    /// A shard directory was made from a different spec.
    #[error(
        "cannot merge: {} was made from a different spec than {}; shards of different campaigns (or of a changed spec) cannot be joined",
        copy.display(),
        spec.display()
    )]
    DifferentSpec {
        /// The shard's copy of its spec.
        copy: PathBuf,
        /// The spec of the merge.
        spec: PathBuf,
    },
    /// A directory given to merge holds neither shard directories nor results.
    #[error(
        "cannot merge: {} holds no shard directories (shard-K-of-N/) and no spec.toml of a campaign",
        dir.display()
    )]
    NoShards {
        /// The directory given.
        dir: PathBuf,
    },
    /// Some shards of the campaign are missing or unfinished.
    #[error(
        "cannot merge: {}; finish each with `metabezier run SPEC --shard K/N --out DIR --resume`",
        shards::list_gaps(gaps)
    )]
    IncompleteShards {
        /// Every missing or unfinished shard.
        gaps: Vec<ShardGap>,
    },
    /// The shards found split the campaign in different counts.
    #[error(
        "cannot merge: the shards found split the campaign in {} parts ({}); merge the shard-K-of-N directories of one count",
        counts.iter().map(ToString::to_string).collect::<Vec<_>>().join(" and "),
        dirs.iter().map(|d| d.display().to_string()).collect::<Vec<_>>().join(", ")
    )]
    MixedShardCounts {
        /// The different N found.
        counts: Vec<usize>,
        /// The directories found.
        dirs: Vec<PathBuf>,
    },
    /// Two shards hold different results for the same run.
    #[error("cannot merge: run {run} of {cell} on {problem} differs between shards")]
    ShardsDisagree {
        /// The run number.
        run: u32,
        /// The run's cell key.
        cell: String,
        /// The run's problem key.
        problem: String,
    },
    /// The merged shards do not hold every run of the campaign.
    #[error(
        "cannot merge: {missing} of {total} runs are missing (the first is run #{first}); merge all shards of the campaign"
    )]
    MissingRuns {
        /// Runs missing.
        missing: usize,
        /// Runs in the campaign.
        total: usize,
        /// Index of the first missing run.
        first: usize,
    },
    /// The spec of a resumed campaign differs from the one recorded in its
    /// `meta.toml` (whose spec copy is gone).
    #[error(
        "cannot resume: {} records a campaign of a spec with hash {recorded}, but {} has hash {found}; restore the spec or choose another --out",
        meta.display(),
        spec.display()
    )]
    SpecHashChanged {
        /// The campaign's meta.toml.
        meta: PathBuf,
        /// The spec given now.
        spec: PathBuf,
        /// The hash recorded.
        recorded: String,
        /// The hash of the spec given now.
        found: String,
    },
    /// A merge would write over another campaign's files.
    #[error(
        "cannot merge into {}: it holds {found}; merge into an empty directory or that campaign's own",
        dir.display()
    )]
    OtherCampaign {
        /// The output directory of the merge.
        dir: PathBuf,
        /// What it holds.
        found: &'static str,
    },
    /// A merge's output directory is one of the directories it merges.
    #[error(
        "cannot merge into {}: it is {}, one of the directories merged, whose own files the merged ones would overwrite; merge into their parent directory (the default when it is given) or another --out",
        out.display(),
        match shard {
            Some(s) => format!("shard {s} ({})", dir.display()),
            None => dir.display().to_string(),
        }
    )]
    MergeIntoShard {
        /// The output directory asked for.
        out: PathBuf,
        /// The directory merged that it is.
        dir: PathBuf,
        /// The shard that directory holds, by its meta.toml.
        shard: Option<Shard>,
    },
    /// Another process holds the campaign directory.
    #[error(
        "{} is in use by another metabezier process (it holds {}); wait for it to finish, or choose another --out",
        dir.display(),
        lock.display()
    )]
    Locked {
        /// The campaign directory.
        dir: PathBuf,
        /// Its lock file.
        lock: PathBuf,
    },
    /// The campaign is larger than the limits without `--allow-large`; the
    /// message names the limit it exceeds (or both).
    #[error("{}: {}; split the campaign into shards, or pass --allow-large", spec.display(), too_large(*runs, *gib))]
    TooLarge {
        /// The spec.
        spec: PathBuf,
        /// Its runs.
        runs: u128,
        /// Estimated memory of its records, in GiB.
        gib: f64,
    },
    /// One run's optimiser state is over the limit without `--allow-large`.
    #[error(
        "{}: algorithm \"{cell}\" ({algorithm}) at D = {dim} needs an estimated {:.1} GiB of optimiser state for one run, over the limit of {} GiB per run (its matrices and populations grow with D); lower D or its population, or pass --allow-large on a machine with the memory",
        spec.display(), *bytes as f64 / f64::from(1u32 << 30), crate::optim::MAX_STATE_BYTES >> 30
    )]
    StateTooLarge {
        /// The spec.
        spec: PathBuf,
        /// The cell's label.
        cell: String,
        /// Its optimiser's name.
        algorithm: String,
        /// The problem's dimension.
        dim: usize,
        /// The bytes one run would allocate.
        bytes: u128,
    },
    /// More worker threads than a sane multiple of the cores.
    #[error("--threads {asked}: at most {max} (4 × the {cores} cores of this machine)")]
    TooManyThreads {
        /// Threads asked for.
        asked: usize,
        /// The limit.
        max: usize,
        /// Cores available.
        cores: usize,
    },
    /// The worker thread pool could not be started.
    #[error("cannot start worker threads: {0}")]
    Threads(#[source] rayon::ThreadPoolBuildError),
    /// A run panicked (an optimiser's or a problem's code): the campaign
    /// stopped, and the runs finished before it are kept in the journal.
    #[error(
        "run {run} of {cell} on {problem} panicked: {message}; the campaign stopped, and every run finished before it is kept in {}: fix the cause and pass --resume",
        journal.display()
    )]
    RunPanicked {
        /// The run number.
        run: u32,
        /// The cell's label.
        cell: String,
        /// The problem's key.
        problem: String,
        /// The panic's message.
        message: String,
        /// The journal that holds the finished runs.
        journal: PathBuf,
    },
    /// The host asked every run to end ([`crate::optim::interrupt::request`]:
    /// Ctrl-C in Python): no new run started, the runs in progress were
    /// discarded, and the finished ones are kept in the journal.
    #[error(
        "interrupted: every run finished before the interrupt is kept in {}; pass --resume (resume=True) to finish the others",
        journal.display()
    )]
    Interrupted {
        /// The journal that holds the finished runs.
        journal: PathBuf,
    },
}

/// What a too large campaign exceeds: its runs over [`MAX_RUNS`], its
/// estimated memory over 4 GiB, or both, each with its limit.
fn too_large(runs: u128, gib: f64) -> String {
    let over_runs = runs > MAX_RUNS;
    let over_memory = gib > 4.0;
    match (over_runs, over_memory) {
        (true, false) => format!("{runs} runs exceed the limit of {MAX_RUNS} runs"),
        (false, true) => {
            format!("an estimated {gib:.1} GiB of results in memory exceed the limit of 4 GiB")
        }
        _ => format!(
            "{runs} runs and an estimated {gib:.1} GiB of results in memory exceed the limits of {MAX_RUNS} runs and 4 GiB"
        ),
    }
}

/// The most runs a campaign may have without `--allow-large`.
pub const MAX_RUNS: u128 = 10_000_000;

/// What a campaign was doing when it met a foreign run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CampaignAction {
    /// `metabezier run --resume`.
    Resume,
    /// `metabezier merge`.
    Merge,
}

impl fmt::Display for CampaignAction {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            CampaignAction::Resume => "resume",
            CampaignAction::Merge => "merge",
        })
    }
}

/// Every failure of this room: a spec, a file, a results file, or a
/// campaign that cannot proceed.
#[derive(Debug, thiserror::Error)]
pub enum ExperimentError {
    /// The spec is invalid.
    #[error(transparent)]
    Spec(#[from] SpecError),
    /// A file could not be read or written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// A results file is malformed.
    #[error(transparent)]
    Data(#[from] DataError),
    /// The campaign cannot proceed as asked.
    #[error(transparent)]
    Campaign(#[from] CampaignError),
    /// A COCO log cannot be written.
    #[error(transparent)]
    CocoLog(#[from] coco_log::CocoLogError),
    /// A Slurm array job cannot be written as asked.
    #[error(transparent)]
    Slurm(#[from] SlurmError),
}

impl From<ReadError> for ExperimentError {
    fn from(e: ReadError) -> Self {
        match e {
            ReadError::Io(e) => ExperimentError::Io(e),
            ReadError::Data(e) => ExperimentError::Data(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_too_large_campaign_names_only_the_limit_it_exceeds() {
        let spec = PathBuf::from("big.toml");
        let memory = CampaignError::TooLarge {
            spec: spec.clone(),
            runs: 1_000,
            gib: 5.5,
        }
        .to_string();
        assert!(
            memory.contains("5.5 GiB") && memory.contains("limit of 4 GiB"),
            "{memory}"
        );
        assert!(!memory.contains("runs exceed"), "{memory}");
        let runs = CampaignError::TooLarge {
            spec: spec.clone(),
            runs: 20_000_000,
            gib: 0.5,
        }
        .to_string();
        assert!(
            runs.contains("20000000 runs exceed the limit of 10000000 runs"),
            "{runs}"
        );
        assert!(!runs.contains("GiB"), "{runs}");
        let both = CampaignError::TooLarge {
            spec,
            runs: 20_000_000,
            gib: 9.0,
        }
        .to_string();
        assert!(
            both.contains("limits of 10000000 runs and 4 GiB") && both.starts_with("big.toml: "),
            "{both}"
        );
    }
}
