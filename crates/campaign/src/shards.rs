//! Joining the shards of a campaign: finding their directories, checking
//! that together they are the whole campaign, finished and of one spec, and
//! writing files identical to those of a single run.
//!
//! `metabezier run --shard K/N` writes into `shard-K-of-N/` under its
//! output directory ([`super::runner::shard_dir`]), so `merge DIR` finds the
//! shards of `DIR` itself; a list of shard directories works as well.

use std::collections::{BTreeMap, HashMap};
use std::fmt;
use std::path::{Path, PathBuf};

use super::journal;
use super::records::{self, RunRecord};
use super::runner::{
    default_out, foreign_run, meta_toml, recorded_shard, write_results, DirLock, RunIndex, Shard,
    Summary,
};
use super::spec::Spec;
use super::{CampaignAction, CampaignError, ExperimentError};
use crate::files::{read_text_limited, write_atomic, IoError, MAX_TEXT_BYTES};

/// The result directories a merge joins, found from the directories given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeInputs {
    /// The directories to join, shards in the order of K.
    pub dirs: Vec<PathBuf>,
    /// The one directory given, when it held the shards: the merged files
    /// go there by default.
    pub parent: Option<PathBuf>,
}

/// A gap that keeps a merge from holding the whole campaign.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ShardGap {
    /// No directory holds this shard.
    Missing {
        /// The shard.
        shard: Shard,
        /// Where it was looked for, when one parent directory was given.
        expected: Option<PathBuf>,
    },
    /// A directory was given (or found) as a shard but has no `meta.toml`,
    /// which `run` writes as a campaign starts: not a campaign directory,
    /// or one whose start was cut short or whose files were removed.
    NoMeta {
        /// The shard its name says it holds, if it is so named.
        shard: Option<Shard>,
        /// The directory.
        dir: PathBuf,
        /// Whether it was given itself (else found in a parent given).
        given: bool,
    },
    /// A directory has no `runs.csv` yet.
    Unfinished {
        /// The shard it holds, if it is one.
        shard: Option<Shard>,
        /// The directory.
        dir: PathBuf,
        /// The finished runs in its journal, if it has one.
        journalled: Option<usize>,
    },
}

impl fmt::Display for ShardGap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShardGap::Missing {
                shard,
                expected: Some(dir),
            } => write!(f, "shard {shard} is missing (no {})", dir.display()),
            ShardGap::Missing {
                shard,
                expected: None,
            } => write!(f, "shard {shard} is missing (no directory given holds it)"),
            ShardGap::NoMeta { shard, dir, given } => {
                let how = if *given { "was given" } else { "is there" };
                match shard {
                    Some(s) => write!(f, "shard {s} ({}) {how}", dir.display())?,
                    None => write!(f, "{} {how}", dir.display())?,
                }
                write!(
                    f,
                    " but has no meta.toml (not a campaign directory, or an unfinished one?)"
                )
            }
            ShardGap::Unfinished {
                shard,
                dir,
                journalled,
            } => {
                match shard {
                    Some(s) => write!(f, "shard {s} is unfinished ({}: ", dir.display())?,
                    None => write!(f, "{} is unfinished (", dir.display())?,
                }
                match journalled {
                    Some(n) => write!(f, "{n} finished runs in journal.csv, no runs.csv)"),
                    None => write!(f, "no runs.csv)"),
                }
            }
        }
    }
}

/// The gaps as one sentence for [`CampaignError::IncompleteShards`].
pub(super) fn list_gaps(gaps: &[ShardGap]) -> String {
    let texts: Vec<String> = gaps.iter().map(ToString::to_string).collect();
    texts.join("; ")
}

/// The shard directories inside `dir`, named `shard-K-of-N`, in order.
fn shards_in(dir: &Path) -> Result<Vec<(Shard, PathBuf)>, IoError> {
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| IoError::new("read the directory", dir, e))? {
        let entry = entry.map_err(|e| IoError::new("read the directory", dir, e))?;
        let shard = entry.file_name().to_str().and_then(Shard::from_dir_name);
        if let Some(s) = shard.filter(|_| entry.path().is_dir()) {
            found.push((s, entry.path()));
        }
    }
    found.sort_by_key(|(s, _)| (s.n, s.k));
    Ok(found)
}

/// The shard that `dir` was started as, by its `meta.toml`.
fn shard_of(dir: &Path) -> Option<Shard> {
    recorded_shard(dir).and_then(|t| Shard::parse(&t).ok())
}

/// Finds the directories to merge: each directory given is either a parent
/// holding `shard-K-of-N/` directories or itself a result directory (a
/// shard or a finished run). Errors name every missing or unfinished shard
/// at once, and shards split in different counts.
pub fn find_shards(given: &[PathBuf]) -> Result<MergeInputs, ExperimentError> {
    let mut found: Vec<(Option<Shard>, PathBuf)> = Vec::new();
    let mut parent = None;
    for dir in given {
        let inside = shards_in(dir)?;
        if inside.is_empty() {
            if !dir.join("spec.toml").exists() {
                return Err(CampaignError::NoShards { dir: dir.clone() }.into());
            }
            // Without meta.toml, the directory's name tells which shard it
            // was meant to be (the gap is named below).
            let named = dir
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(Shard::from_dir_name);
            found.push((shard_of(dir).or(named), dir.clone()));
        } else {
            if given.len() == 1 {
                parent = Some(dir.clone());
            }
            // A shard written straight into the directory by an older version.
            if let Some(s) = shard_of(dir) {
                found.push((Some(s), dir.clone()));
            }
            found.extend(inside.into_iter().map(|(s, d)| (Some(s), d)));
        }
    }
    let mut seen = std::collections::HashSet::new();
    found.retain(|(_, d)| seen.insert(d.clone()));
    let gaps = gaps(&found, given, parent.as_deref())?;
    if !gaps.is_empty() {
        return Err(CampaignError::IncompleteShards { gaps }.into());
    }
    found.sort_by_key(|(s, _)| s.map(|s| s.k));
    Ok(MergeInputs {
        dirs: found.into_iter().map(|(_, d)| d).collect(),
        parent,
    })
}

/// The missing and unfinished shards among `found`; an error if they were
/// split in different counts.
fn gaps(
    found: &[(Option<Shard>, PathBuf)],
    given: &[PathBuf],
    parent: Option<&Path>,
) -> Result<Vec<ShardGap>, CampaignError> {
    let mut by_count: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    for s in found.iter().filter_map(|(s, _)| *s) {
        by_count.entry(s.n).or_default().push(s.k);
    }
    if by_count.len() > 1 {
        return Err(CampaignError::MixedShardCounts {
            counts: by_count.keys().copied().collect(),
            dirs: found.iter().map(|(_, d)| d.clone()).collect(),
        });
    }
    let mut gaps = Vec::new();
    if let Some((&n, ks)) = by_count.iter().next() {
        for k in (1..=n).filter(|k| !ks.contains(k)) {
            let shard = Shard { k, n };
            let expected = parent.map(|p| p.join(shard.dir_name()));
            gaps.push(ShardGap::Missing { shard, expected });
        }
    }
    for (shard, dir) in found {
        if !dir.join("meta.toml").is_file() {
            gaps.push(ShardGap::NoMeta {
                shard: *shard,
                dir: dir.clone(),
                given: given.contains(dir),
            });
        } else if !dir.join("runs.csv").exists() {
            let journal = dir.join("journal.csv");
            gaps.push(ShardGap::Unfinished {
                shard: *shard,
                dir: dir.clone(),
                journalled: journal::read_journal(&journal).ok().map(|r| r.len()),
            });
        }
    }
    Ok(gaps)
}

/// Joins the shards of one campaign found from `dirs` ([`find_shards`])
/// into files equal to those of an unsharded run; see [`merge_found`].
pub fn merge(
    spec: &Spec,
    dirs: &[PathBuf],
    out: Option<PathBuf>,
) -> Result<Summary, ExperimentError> {
    merge_found(spec, &find_shards(dirs)?, out)
}

/// Joins the directories of `inputs`, all made from `spec`, into `out`
/// (default: the one parent directory given, else `results/<name>`):
/// `runs.csv`, `convergence.csv`, `timing.csv`, `hits.csv` and the fitting
/// files exactly as [`super::run_campaign`] writes them, a copy of the spec
/// and `meta.toml`.
pub fn merge_found(
    spec: &Spec,
    inputs: &MergeInputs,
    out: Option<PathBuf>,
) -> Result<Summary, ExperimentError> {
    let out = out
        .or_else(|| inputs.parent.clone())
        .unwrap_or_else(|| default_out(spec));
    let mut done = read_shards(spec, &inputs.dirs)?;
    let ids = spec.run_ids();
    let missing: Vec<usize> = ids
        .iter()
        .filter(|id| !done.contains_key(&id.index))
        .map(|id| id.index)
        .collect();
    if let Some(&first) = missing.first() {
        return Err(CampaignError::MissingRuns {
            missing: missing.len(),
            total: ids.len(),
            first,
        }
        .into());
    }
    refuse_own_shard(&out, &inputs.dirs)?;
    let _lock = DirLock::take(&out)?;
    refuse_other_campaign(spec, &out)?;
    let ordered: Vec<RunRecord> = ids
        .iter()
        .map(|id| done.remove(&id.index).expect("complete"))
        .collect();
    write_atomic(&out.join("spec.toml"), spec.text.as_bytes())?;
    write_atomic(
        &out.join("meta.toml"),
        meta_toml(spec, None, ids.len()).as_bytes(),
    )?;
    write_results(spec, &out, &ordered)?;
    // The shards' sessions, in the order the directories were given.
    let sessions: Vec<_> = inputs
        .dirs
        .iter()
        .flat_map(|d| super::provenance::read(d))
        .collect();
    super::provenance::write(&out, &sessions)?;
    Ok(Summary {
        out,
        total: ids.len(),
        reused: ids.len(),
        executed: 0,
        complete: true,
        dropped: Vec::new(),
    })
}

/// Refuses to merge into one of the directories merged (the merged files
/// would overwrite that shard's own), however the two paths are spelled.
fn refuse_own_shard(out: &Path, dirs: &[PathBuf]) -> Result<(), CampaignError> {
    let same = |a: &Path, b: &Path| match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => std::path::absolute(a).ok() == std::path::absolute(b).ok(),
    };
    match dirs.iter().find(|d| same(out, d)) {
        Some(dir) => Err(CampaignError::MergeIntoShard {
            out: out.to_owned(),
            shard: shard_of(dir),
            dir: dir.clone(),
        }),
        None => Ok(()),
    }
}

/// Refuses to merge into a directory that holds another campaign's files:
/// a journal (an unfinished campaign), or results or a report whose
/// `spec.toml` is not `spec`.
fn refuse_other_campaign(spec: &Spec, out: &Path) -> Result<(), CampaignError> {
    if out.join("journal.csv").exists() {
        return Err(CampaignError::OtherCampaign {
            dir: out.to_owned(),
            found: "journal.csv",
        });
    }
    let holds_results = ["runs.csv", "report.md"]
        .iter()
        .any(|f| out.join(f).exists());
    let same_spec = read_text_limited(&out.join("spec.toml"), MAX_TEXT_BYTES, "a spec")
        .is_ok_and(|t| t == spec.text);
    if holds_results && !same_spec {
        return Err(CampaignError::OtherCampaign {
            dir: out.to_owned(),
            found: "results of another spec",
        });
    }
    Ok(())
}

/// The runs of every directory, by position in the campaign's fixed order,
/// after checking that each was made from `spec` and that runs found twice
/// agree.
fn read_shards(
    spec: &Spec,
    dirs: &[PathBuf],
) -> Result<HashMap<usize, RunRecord>, ExperimentError> {
    let index = RunIndex::of(spec);
    let mut done: HashMap<usize, RunRecord> = HashMap::new();
    for dir in dirs {
        let copy = dir.join("spec.toml");
        // A copy over the spec size limit cannot be the spec: read no more.
        let text = read_text_limited(&copy, MAX_TEXT_BYTES, "a spec")
            .map_err(|e| IoError::new("read", &copy, e))?;
        if text != spec.text {
            return Err(CampaignError::DifferentSpec {
                copy,
                spec: spec.path.clone(),
            }
            .into());
        }
        for r in records::read_results(dir)? {
            let i = index
                .get(&r.key())
                .ok_or_else(|| foreign_run(CampaignAction::Merge, dir, &r))?;
            if let Some(prev) = done.get(&i) {
                let same = RunRecord {
                    wall_seconds: prev.wall_seconds,
                    ..r.clone()
                };
                if &same != prev {
                    return Err(CampaignError::ShardsDisagree {
                        run: r.run,
                        cell: r.cell_key(),
                        problem: r.match_key(),
                    }
                    .into());
                }
            }
            done.insert(i, r);
        }
    }
    Ok(done)
}
