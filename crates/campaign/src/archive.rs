//! `metabezier archive`: one campaign's results directory (or a `results/`
//! directory of campaigns) as a reproducible `.tar.gz` that an archival
//! repository such as Zenodo takes, and its check.
//!
//! The archive has one top directory, named as the directory archived,
//! holding:
//!
//! - every regular file of the campaign(s) at its path below the directory
//!   (the spec copy, `runs.csv` and the records beside it, `meta.toml`,
//!   `provenance.toml`, the reports, `tables/`, `plots/`), except the
//!   campaign lock `.lock`; a symbolic link is refused, never followed;
//! - `CITATION.cff`, the software's, as embedded in the binary;
//! - `.zenodo.json`, Zenodo's deposition metadata
//!   (<https://developers.zenodo.org/#representation>): title, upload type
//!   `dataset`, creators (the `CITATION.cff` authors), version, licence
//!   (the SPDX id [`zenodo::ZENODO_LICENSE`]), description, related
//!   identifiers (the repository URL of the `CITATION.cff`, when it has
//!   one) and keywords;
//! - `SHA256SUMS`, the SHA-256 of every other file in the format of GNU
//!   coreutils' `sha256sum`
//!   (<https://www.gnu.org/software/coreutils/manual/html_node/md5sum-invocation.html>),
//!   so that `sha256sum -c SHA256SUMS` in the extracted top directory
//!   checks it.
//!
//! The same directory always gives the same bytes: sorted entries, fixed
//! headers and a gzip header without time or name.
//! [`write_archive`] refuses a directory whose campaign runs (its `.lock`
//! held) or has not finished (a `journal.csv` remains), one without
//! `runs.csv`, and one whose archive would pass [`MAX_ARCHIVE_BYTES`];
//! the archive is written to a temporary file and renamed into place, so a
//! refusal or a failure leaves no partial archive.

mod cff;
mod collect;
mod sums;
mod tarball;
mod verify;
pub mod zenodo;

use std::path::{Path, PathBuf};

pub use cff::{read_citation, Citation};
pub use sums::SHA256SUMS;

use crate::files::{write_atomic_with, IoError};
use tarball::Content;

/// The largest archive written or read: 4 GiB of tar stream (the files,
/// their headers and padding, uncompressed).
///
/// A campaign within the default limits holds at most 4 GiB of records in
/// memory ([`crate::runner::MAX_RESULT_BYTES`]) and a `runs.csv` of at most
/// 4 GiB ([`crate::reading::MAX_RUNS_FILE_BYTES`]); its results directory
/// stays well below this. A larger one (run with `--allow-large`) is
/// archived a shard directory at a time. `--verify` stops reading at the
/// same cap, so a crafted archive that inflates without end is refused.
pub const MAX_ARCHIVE_BYTES: u64 = 4 << 30;

/// The files the archive adds beside the campaign's; a file of the same
/// name at the top of the directory archived is refused.
pub const RESERVED: [&str; 3] = [SHA256SUMS, ".zenodo.json", "CITATION.cff"];

/// The software that writes the archive, as its metadata names it.
#[derive(Clone, Copy, Debug)]
pub struct Software<'a> {
    /// Its name ("metabezier").
    pub name: &'a str,
    /// Its version (the crate version).
    pub version: &'a str,
    /// The text of its `CITATION.cff`.
    pub citation_cff: &'a str,
}

/// One campaign in an archive.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CampaignInfo {
    /// Its experiment name (`meta.toml`), else its directory name.
    pub name: String,
    /// Its runs (`meta.toml`), when known.
    pub runs: Option<u64>,
}

/// What [`write_archive`] wrote.
#[derive(Clone, Debug)]
pub struct Written {
    /// The campaigns archived.
    pub campaigns: Vec<CampaignInfo>,
    /// The files listed in `SHA256SUMS` (every file but itself).
    pub files: usize,
    /// Their bytes.
    pub bytes: u64,
}

/// What [`verify_archive`] checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Verified {
    /// The files listed in `SHA256SUMS`, all present and equal.
    pub files: usize,
    /// Their bytes.
    pub bytes: u64,
}

/// Why an archive cannot be written, or does not check.
#[derive(Debug, thiserror::Error)]
pub enum ArchiveError {
    /// The directory holds neither `runs.csv` nor campaign directories.
    #[error(
        "{}: holds no runs.csv, so it is neither a campaign's results directory nor a directory of campaigns; give the --out of `metabezier run` or `metabezier merge`, or the results/ directory above several",
        dir.display()
    )]
    NotACampaign {
        /// The directory.
        dir: PathBuf,
    },
    /// A subdirectory of a directory of campaigns is not a campaign.
    #[error(
        "{}: holds no runs.csv, so {} is not a directory of campaigns only; archive each campaign on its own, or move this directory out",
        sub.display(),
        dir.display()
    )]
    NotACampaignIn {
        /// The subdirectory.
        sub: PathBuf,
        /// The directory archived.
        dir: PathBuf,
    },
    /// A campaign runs in the directory.
    #[error(
        "{}: a campaign is running in it (another process holds {}); wait for it to finish, then archive",
        dir.display(),
        lock.display()
    )]
    Locked {
        /// The campaign directory.
        dir: PathBuf,
        /// Its lock file.
        lock: PathBuf,
    },
    /// A campaign stopped before every run finished.
    #[error(
        "{}: the campaign did not finish (its journal remains); finish it with `metabezier run SPEC --out DIR --resume`, then archive",
        journal.display()
    )]
    Unfinished {
        /// The journal.
        journal: PathBuf,
    },
    /// A symbolic link, which the archive does not follow.
    #[error(
        "{}: is a symbolic link (to {target}), which an archive does not follow; replace it with a copy of what it points to, or remove it",
        path.display()
    )]
    Symlink {
        /// The link.
        path: PathBuf,
        /// What it points to.
        target: String,
    },
    /// Neither a regular file nor a directory.
    #[error("{}: is not a regular file or a directory (a FIFO, socket or device); remove it", path.display())]
    Special {
        /// The entry.
        path: PathBuf,
    },
    /// A name `SHA256SUMS` cannot list plainly.
    #[error("{}: its name is not UTF-8 or has a newline or backslash, which SHA256SUMS cannot list plainly; rename it", path.display())]
    BadName {
        /// The entry.
        path: PathBuf,
    },
    /// A file with the name of one the archive adds.
    #[error("{}: has the name of a file the archive adds ({}); rename it", path.display(), RESERVED.join(", "))]
    Reserved {
        /// The file.
        path: PathBuf,
    },
    /// The archive would pass its cap.
    #[error(
        "{}: its archive would hold {bytes} bytes ({:.2} GiB), over the cap of {} (MAX_ARCHIVE_BYTES); archive its campaigns or shard directories one at a time",
        dir.display(),
        *bytes as f64 / f64::from(1u32 << 30),
        crate::files::size_text(*cap)
    )]
    TooLarge {
        /// The directory.
        dir: PathBuf,
        /// The bytes of its tar stream.
        bytes: u64,
        /// The cap.
        cap: u64,
    },
    /// The output would lie inside the directory archived.
    #[error(
        "--out {}: lies inside {}, so the archive would hold itself; write it outside the directory",
        out.display(),
        dir.display()
    )]
    OutInside {
        /// The output file.
        out: PathBuf,
        /// The directory archived.
        dir: PathBuf,
    },
    /// The `CITATION.cff` names no author.
    #[error("the software's CITATION.cff names no author, and Zenodo needs a creator; add one to CITATION.cff and rebuild")]
    NoCreators,
    /// A file or the archive could not be read or written.
    #[error(transparent)]
    Io(#[from] IoError),
    /// The archive is not a readable `.tar.gz`, or passes its cap.
    #[error("{}: {problem}", archive.display())]
    Unreadable {
        /// The archive.
        archive: PathBuf,
        /// Why it cannot be read.
        problem: String,
    },
    /// An entry of the archive does not check.
    #[error("{}: {entry}: {problem}", archive.display())]
    Verify {
        /// The archive.
        archive: PathBuf,
        /// The entry, by its path in the archive.
        entry: String,
        /// What is wrong with it.
        problem: String,
    },
}

/// Writes the archive of `dir` into `out` (see the module documentation),
/// under [`MAX_ARCHIVE_BYTES`].
pub fn write_archive(dir: &Path, out: &Path, software: &Software) -> Result<Written, ArchiveError> {
    write_archive_capped(dir, out, software, MAX_ARCHIVE_BYTES)
}

/// [`write_archive`] under a cap of `cap` bytes of tar stream.
pub fn write_archive_capped(
    dir: &Path,
    out: &Path,
    software: &Software,
    cap: u64,
) -> Result<Written, ArchiveError> {
    let absolute =
        |p: &Path| std::path::absolute(p).map_err(|e| IoError::new("resolve the path", p, e));
    let (abs_dir, abs_out) = (absolute(dir)?, absolute(out)?);
    if abs_out.starts_with(&abs_dir) {
        return Err(ArchiveError::OutInside {
            out: out.to_owned(),
            dir: dir.to_owned(),
        });
    }
    let collected = collect::collect(dir)?;
    let citation = read_citation(software.citation_cff);
    if citation.authors.is_empty() {
        return Err(ArchiveError::NoCreators);
    }
    let top = top_name(&abs_dir);
    let zenodo = zenodo::zenodo_json(software, &citation, &collected.campaigns);
    let added = [
        (".zenodo.json", zenodo.into_bytes()),
        ("CITATION.cff", software.citation_cff.as_bytes().to_vec()),
    ];
    let bytes = planned_bytes(&top, &collected.entries, &added);
    if bytes > cap {
        return Err(ArchiveError::TooLarge {
            dir: dir.to_owned(),
            bytes,
            cap,
        });
    }
    let mut entries = vec![(top.clone(), Content::Dir)];
    let mut sums = Vec::new();
    let mut payload = 0u64;
    for e in &collected.entries {
        let path = format!("{top}/{}", e.rel);
        let Some((disk, size)) = &e.file else {
            entries.push((path, Content::Dir));
            continue;
        };
        let (hex, _) = std::fs::File::open(disk)
            .and_then(sums::sha256_hex)
            .map_err(|err| IoError::new("read", disk, err))?;
        sums.push((e.rel.clone(), hex.clone()));
        payload += size;
        entries.push((path, Content::Disk(disk.clone(), *size, hex)));
    }
    for (name, content) in added {
        let (hex, n) = sums::sha256_hex(&content[..]).map_err(|e| IoError::new("read", out, e))?;
        sums.push((name.to_owned(), hex));
        payload += n;
        entries.push((format!("{top}/{name}"), Content::Bytes(content)));
    }
    let sums_text = sums::format_sums(&sums).into_bytes();
    entries.push((format!("{top}/{SHA256SUMS}"), Content::Bytes(sums_text)));
    entries.sort_by_cached_key(entry_key);
    write_atomic_with(out, |file| {
        tarball::write_tar_gz(std::io::BufWriter::new(file), &entries)
    })?;
    Ok(Written {
        campaigns: collected.campaigns,
        files: sums.len(),
        bytes: payload,
    })
}

/// An upper bound of the bytes of the tar stream of `entries` and `added`
/// below `top`, with the `SHA256SUMS` that lists them (a line of 64 hex
/// digits, two spaces, the path and a newline for each file), counted
/// before any file is read.
fn planned_bytes(top: &str, entries: &[collect::Entry], added: &[(&str, Vec<u8>)]) -> u64 {
    let files = entries
        .iter()
        .filter_map(|e| e.file.as_ref().map(|f| (e.rel.len(), f.1)))
        .chain(added.iter().map(|(n, b)| (n.len(), b.len() as u64)));
    let sums_bytes: u64 = files.clone().map(|(len, _)| 67 + len as u64).sum();
    let dirs = entries
        .iter()
        .filter(|e| e.file.is_none())
        .map(|e| (e.rel.len() + 1, None));
    let below = files
        .map(|(len, size)| (len, Some(size)))
        .chain(dirs)
        .chain([(SHA256SUMS.len(), Some(sums_bytes)), (0, None)]);
    tarball::tar_bytes(below.map(|(len, size)| (top.len() + 1 + len, size)))
}

/// The archive's order: by path, a directory as `path/`.
fn entry_key((path, content): &(String, Content)) -> String {
    match content {
        Content::Dir => format!("{path}/"),
        _ => path.clone(),
    }
}

/// Checks the archive at `path`: its entries are regular files and
/// directories under one top directory with safe paths, and every file is
/// listed in its `SHA256SUMS` with the digest it has, and every listed file
/// is there. Reads at most [`MAX_ARCHIVE_BYTES`] of tar stream.
pub fn verify_archive(path: &Path) -> Result<Verified, ArchiveError> {
    verify::verify(path, MAX_ARCHIVE_BYTES)
}

/// [`verify_archive`] reading at most `cap` bytes of tar stream.
pub fn verify_archive_capped(path: &Path, cap: u64) -> Result<Verified, ArchiveError> {
    verify::verify(path, cap)
}

/// The name of the archive's top directory: the last component of `dir`
/// (absolute), or "results" for a root.
fn top_name(dir: &Path) -> String {
    dir.components()
        .filter_map(|c| match c {
            std::path::Component::Normal(n) => Some(n.to_string_lossy().into_owned()),
            _ => None,
        })
        .next_back()
        .unwrap_or_else(|| "results".to_owned())
}
