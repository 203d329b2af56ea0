//! What an archive holds: the regular files and directories of one
//! campaign's results directory, or of a `results/` directory of
//! campaigns, walked without following a symbolic link, and refused while
//! a campaign runs in it or has not finished.

use std::fs::{File, TryLockError};
use std::path::{Path, PathBuf};

use super::{ArchiveError, CampaignInfo, RESERVED};
use crate::files::{read_text_limited, IoError, MAX_TEXT_BYTES};

/// One entry of the archive below its top directory: a directory, or a
/// regular file with its size when it was listed.
#[derive(Clone, Debug)]
pub struct Entry {
    /// The path below the top directory, `/` between components.
    pub rel: String,
    /// The file on disk (`None` for a directory).
    pub file: Option<(PathBuf, u64)>,
}

/// The campaigns found, their entries in archive order, and the campaign
/// locks held while the archive is written.
pub struct Collected {
    /// The campaigns, in path order.
    pub campaigns: Vec<CampaignInfo>,
    /// Directories and files, sorted as the archive lists them.
    pub entries: Vec<Entry>,
    /// The `.lock` files taken, so that no campaign starts meanwhile.
    _locks: Vec<File>,
}

/// Collects `dir`: one campaign (it holds `runs.csv`) or a directory whose
/// every subdirectory is one.
pub fn collect(dir: &Path) -> Result<Collected, ArchiveError> {
    let meta = std::fs::metadata(dir).map_err(|e| IoError::new("read", dir, e))?;
    if !meta.is_dir() {
        return Err(ArchiveError::NotACampaign {
            dir: dir.to_owned(),
        });
    }
    // The walk first: it refuses a running or unfinished campaign (which
    // has no runs.csv yet) before the directory is judged by its runs.csv.
    let mut walk = Walk::default();
    walk.dir(dir, "")?;
    walk.entries.sort_by_cached_key(sort_key);
    let campaign_dirs = if is_campaign(dir) {
        vec![(String::new(), dir.to_owned())]
    } else {
        let mut subs = Vec::new();
        for (name, path, kind) in list(dir)? {
            if kind.is_dir() {
                if !is_campaign(&path) {
                    return Err(ArchiveError::NotACampaignIn {
                        sub: path,
                        dir: dir.to_owned(),
                    });
                }
                subs.push((name, path));
            }
        }
        if subs.is_empty() {
            return Err(ArchiveError::NotACampaign {
                dir: dir.to_owned(),
            });
        }
        subs
    };
    let campaigns = campaign_dirs
        .iter()
        .map(|(name, path)| campaign_info(path, name))
        .collect();
    Ok(Collected {
        campaigns,
        entries: walk.entries,
        _locks: walk.locks,
    })
}

/// Whether `dir` holds a `runs.csv` of its own (a link is not one).
fn is_campaign(dir: &Path) -> bool {
    std::fs::symlink_metadata(dir.join("runs.csv")).is_ok_and(|m| m.is_file())
}

/// The archive's order: by path, a directory as `path/`.
fn sort_key(e: &Entry) -> String {
    match e.file {
        Some(_) => e.rel.clone(),
        None => format!("{}/", e.rel),
    }
}

/// The entries of `dir` by name, with their types (a link not followed).
fn list(dir: &Path) -> Result<Vec<(String, PathBuf, std::fs::FileType)>, ArchiveError> {
    let read = |e| IoError::new("read the directory", dir, e);
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read)? {
        let entry = entry.map_err(read)?;
        let path = entry.path();
        let name = entry
            .file_name()
            .to_str()
            .filter(|n| !n.contains(['\n', '\r', '\\']))
            .map(str::to_owned)
            .ok_or_else(|| ArchiveError::BadName { path: path.clone() })?;
        out.push((name, path, entry.file_type().map_err(read)?));
    }
    out.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(out)
}

/// The walk of a directory tree.
#[derive(Default)]
struct Walk {
    entries: Vec<Entry>,
    locks: Vec<File>,
}

impl Walk {
    /// Adds the entries of `dir`, which lies at `rel` below the top.
    fn dir(&mut self, dir: &Path, rel: &str) -> Result<(), ArchiveError> {
        // The lock first: a running campaign has a journal too, and is
        // named as running.
        self.take_lock(dir)?;
        for (name, path, kind) in list(dir)? {
            let rel = if rel.is_empty() {
                name.clone()
            } else {
                format!("{rel}/{name}")
            };
            if kind.is_symlink() {
                let target = std::fs::read_link(&path)
                    .map_or_else(|_| "?".to_owned(), |t| t.display().to_string());
                return Err(ArchiveError::Symlink { path, target });
            }
            if !rel.contains('/') && RESERVED.contains(&name.as_str()) {
                return Err(ArchiveError::Reserved { path });
            }
            if kind.is_dir() {
                self.entries.push(Entry {
                    rel: rel.clone(),
                    file: None,
                });
                self.dir(&path, &rel)?;
            } else if !kind.is_file() {
                return Err(ArchiveError::Special { path });
            } else if name == "journal.csv" {
                return Err(ArchiveError::Unfinished { journal: path });
            } else if name != ".lock" {
                let size = std::fs::symlink_metadata(&path)
                    .map_err(|e| IoError::new("read", &path, e))?
                    .len();
                self.entries.push(Entry {
                    rel,
                    file: Some((path, size)),
                });
            }
        }
        Ok(())
    }

    /// Takes the campaign lock of `dir` if it has one (`.lock`, the
    /// advisory `flock` a running campaign holds), without waiting.
    fn take_lock(&mut self, dir: &Path) -> Result<(), ArchiveError> {
        let lock = dir.join(".lock");
        if !std::fs::symlink_metadata(&lock).is_ok_and(|m| m.is_file()) {
            return Ok(());
        }
        let file = File::open(&lock).map_err(|e| IoError::new("open", &lock, e))?;
        match file.try_lock() {
            Ok(()) => {
                self.locks.push(file);
                Ok(())
            }
            Err(TryLockError::WouldBlock) => Err(ArchiveError::Locked {
                dir: dir.to_owned(),
                lock,
            }),
            Err(TryLockError::Error(e)) => Err(IoError::new("lock", &lock, e).into()),
        }
    }
}

/// The experiment name and run count of the campaign in `dir` from its
/// `meta.toml`, or its directory name (`fallback`, or `dir`'s own) when
/// that cannot be read.
fn campaign_info(dir: &Path, fallback: &str) -> CampaignInfo {
    let meta = read_text_limited(&dir.join("meta.toml"), MAX_TEXT_BYTES, "a meta.toml")
        .ok()
        .and_then(|t| t.parse::<toml::Table>().ok());
    let field = |key: &str| meta.as_ref().and_then(|m| m.get(key));
    let name = field("experiment")
        .and_then(|v| v.as_str())
        .map(str::to_owned)
        .unwrap_or_else(|| match fallback {
            "" => super::top_name(dir),
            f => f.to_owned(),
        });
    let runs = field("runs")
        .and_then(|v| v.as_integer())
        .and_then(|n| u64::try_from(n).ok());
    CampaignInfo { name, runs }
}
