//! Writing result files: atomically (temporary file, sync, rename), as CSV
//! bytes, with reals in shortest round-trip form; and the I/O error that
//! names the file it concerns.
//!
//! The writing half of today's `files` room; the formatting half
//! ([`fmt_real`], [`csv_bytes`]) lives in `metabezier-core`, which has no
//! I/O, and is re-exported here so that `files::fmt_real` and
//! `files::write_atomic` are found in one place above the core.
#![warn(missing_docs)]

pub use metabezier_core::files::{csv_bytes, excerpt, fmt_real};

use std::io;
use std::path::{Path, PathBuf};

mod limited;
pub use limited::{size_text, LimitedReader, ReadLimits};

/// A file or directory could not be read, written, created or renamed.
#[derive(Debug, thiserror::Error)]
#[error("{}: cannot {action}: {source}", path.display())]
pub struct IoError {
    /// What was being done, such as "write" or "create the directory".
    pub action: &'static str,
    /// The file or directory.
    pub path: PathBuf,
    /// The operating system's error.
    #[source]
    pub source: io::Error,
}

impl IoError {
    /// The failure of `action` on `path`.
    pub fn new(action: &'static str, path: &Path, source: io::Error) -> Self {
        IoError {
            action,
            path: path.to_owned(),
            source,
        }
    }
}

/// Creates `dir` and its parents if they are missing. A dangling symbolic
/// link in the way is named as such (the system says only "File exists").
pub fn create_dir(dir: &Path) -> Result<(), IoError> {
    std::fs::create_dir_all(dir).map_err(|e| {
        let e = match e.kind() {
            io::ErrorKind::AlreadyExists => dangling_link(dir).unwrap_or(e),
            _ => e,
        };
        IoError::new("create the directory", dir, e)
    })
}

/// The error to give for `dir` when it, or one of its ancestors, is a
/// symbolic link to nothing.
fn dangling_link(dir: &Path) -> Option<io::Error> {
    dir.ancestors()
        .filter(|a| !a.as_os_str().is_empty())
        .find_map(|a| {
            let link = std::fs::symlink_metadata(a).ok()?;
            (link.file_type().is_symlink() && std::fs::metadata(a).is_err()).then(|| {
                let target = std::fs::read_link(a).map_or_else(|_| "?".into(), |t| t.display().to_string());
                io::Error::new(
                    io::ErrorKind::NotFound,
                    format!(
                        "{} is a symbolic link to {target}, which does not exist; create the target or remove the link",
                        a.display()
                    ),
                )
            })
        })
}

/// Checks, before any work, that `dir` can become an output directory: it is
/// a directory or does not exist, and its nearest existing ancestor is a
/// directory (no file in the way). Nothing is created.
pub fn check_output_dir(dir: &Path) -> Result<(), IoError> {
    if let Some(e) = dangling_link(dir) {
        return Err(IoError::new("use as the output directory", dir, e));
    }
    let in_the_way = |path: &Path| {
        IoError::new(
            "use as the output directory",
            dir,
            io::Error::new(
                io::ErrorKind::NotADirectory,
                format!("{} is a file, not a directory", path.display()),
            ),
        )
    };
    for ancestor in dir.ancestors().filter(|a| !a.as_os_str().is_empty()) {
        match std::fs::metadata(ancestor) {
            Ok(m) if m.is_dir() => return Ok(()),
            Ok(_) => return Err(in_the_way(ancestor)),
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::NotFound | io::ErrorKind::NotADirectory
                ) =>
            {
                continue
            }
            Err(e) => return Err(IoError::new("use as the output directory", dir, e)),
        }
    }
    Ok(())
}

/// An output directory being written: every file goes first into a hidden
/// staging directory inside it (`.staging-PID-RANDOM`), and
/// [`Staging::publish`] renames them into place only once all are written,
/// so a full disk or an error part-way leaves the directory as it was,
/// never half of a new result beside half of an old one.
///
/// Dropped without `publish`, the staging directory is removed (and the
/// output directory too, when this created it and it is empty). A staging
/// directory left by a killed process is removed by the next `Staging` of
/// the same directory once its process is gone. A staging directory of
/// another process that still runs refuses the new one: two runs writing
/// into one directory at once would leave one's records beside the
/// other's figures (two starting at the same instant both refuse).
pub struct Staging {
    dir: PathBuf,
    tmp: PathBuf,
    created: bool,
    published: bool,
}

impl Staging {
    /// Starts writing into `dir` (created if missing).
    pub fn new(dir: &Path) -> Result<Staging, IoError> {
        let created = !dir.exists();
        create_dir(dir)?;
        remove_stale_staging(dir);
        loop {
            let tmp = dir.join(format!(
                ".staging-{}-{:016x}",
                std::process::id(),
                random_u64()
            ));
            match std::fs::create_dir(&tmp) {
                Ok(()) => {
                    let staging = Staging {
                        dir: dir.to_owned(),
                        tmp,
                        created,
                        published: false,
                    };
                    return match live_staging(dir) {
                        // Dropping `staging` removes what it made.
                        Some(pid) => Err(IoError::new(
                            "write into it",
                            dir,
                            io::Error::other(format!(
                                "another process (pid {pid}) is writing its results into this \
                                 directory; give each run its own output directory"
                            )),
                        )),
                        None => Ok(staging),
                    };
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
                Err(e) => return Err(IoError::new("create the directory", &tmp, e)),
            }
        }
    }

    /// Where the files are to be written now.
    pub fn path(&self) -> &Path {
        &self.tmp
    }

    /// The place in the output directory of a file written at `staged`.
    pub fn final_path(&self, staged: &Path) -> PathBuf {
        match staged.strip_prefix(&self.tmp) {
            Ok(rest) => self.dir.join(rest),
            Err(_) => staged.to_owned(),
        }
    }

    /// Renames every staged file into the output directory (replacing
    /// files of the same name), syncs it and removes the staging
    /// directory; returns the final paths, in name order.
    pub fn publish(mut self) -> Result<Vec<PathBuf>, IoError> {
        let read = |e| IoError::new("read the directory", &self.tmp, e);
        let mut names: Vec<std::ffi::OsString> = std::fs::read_dir(&self.tmp)
            .map_err(read)?
            .map(|e| e.map(|e| e.file_name()))
            .collect::<Result<_, _>>()
            .map_err(read)?;
        names.sort();
        let mut out = Vec::with_capacity(names.len());
        for name in names {
            let to = self.dir.join(&name);
            std::fs::rename(self.tmp.join(&name), &to)
                .map_err(|e| IoError::new("write", &to, e))?;
            out.push(to);
        }
        std::fs::File::open(&self.dir)
            .and_then(|d| d.sync_all())
            .map_err(|e| IoError::new("sync the directory", &self.dir, e))?;
        std::fs::remove_dir(&self.tmp)
            .map_err(|e| IoError::new("remove the directory", &self.tmp, e))?;
        self.published = true;
        Ok(out)
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.published {
            let _ = std::fs::remove_dir_all(&self.tmp);
            if self.created {
                // Fails, as it should, when something else is in it.
                let _ = std::fs::remove_dir(&self.dir);
            }
        }
    }
}

/// The process ids of the staging directories in `dir`, with their paths.
fn staging_dirs(dir: &Path) -> Vec<(u32, PathBuf)> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    entries
        .flatten()
        .filter_map(|entry| {
            let pid = entry
                .file_name()
                .to_str()
                .and_then(|n| n.strip_prefix(".staging-"))
                .and_then(|n| n.split('-').next())
                .and_then(|p| p.parse::<u32>().ok())?;
            Some((pid, entry.path()))
        })
        .collect()
}

/// Whether process `pid` runs (`None` without `/proc`, where it cannot be
/// told).
fn running(pid: u32) -> Option<bool> {
    Path::new("/proc/self")
        .exists()
        .then(|| Path::new("/proc").join(pid.to_string()).exists())
}

/// Removes the staging directories in `dir` whose process has ended
/// (a process that still runs keeps its own; without `/proc`, none is
/// removed).
fn remove_stale_staging(dir: &Path) {
    for (pid, path) in staging_dirs(dir) {
        if pid != std::process::id() && running(pid) == Some(false) {
            let _ = std::fs::remove_dir_all(path);
        }
    }
}

/// Another running process's staging directory in `dir`, by its pid.
fn live_staging(dir: &Path) -> Option<u32> {
    staging_dirs(dir)
        .into_iter()
        .map(|(pid, _)| pid)
        .find(|&pid| pid != std::process::id() && running(pid) == Some(true))
}

/// The largest text file (spec, template) the readers take: 16 MiB.
///
/// A spec of the thesis's campaigns is a few KiB; a generated one with
/// long grids stays far below this. A larger file (or an endless stream
/// such as `/dev/zero`) is refused after reading `MAX_TEXT_BYTES + 1`
/// bytes, before it can take the machine's memory.
pub const MAX_TEXT_BYTES: u64 = 16 << 20;

/// Reads `path` as UTF-8 text of at most `limit` bytes, reading no more
/// than `limit + 1` bytes; `what` names the file in the error ("a spec").
///
/// The errors say which limit was passed, or at which byte the text stops
/// being UTF-8.
pub fn read_text_limited(path: &Path, limit: u64, what: &str) -> io::Result<String> {
    use std::io::Read;
    let file = std::fs::File::open(path)?;
    let mut bytes = Vec::new();
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::new(
            io::ErrorKind::FileTooLarge,
            format!("it is larger than the {} {what} may be", size_text(limit)),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidData,
            format!(
                "it is not UTF-8 text (invalid byte at offset {})",
                e.utf8_error().valid_up_to()
            ),
        )
    })
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same
/// directory, synced, then renamed over `path`, so that no reader ever sees a
/// half-written file.
///
/// The temporary file is created exclusively (`O_EXCL`, atomic on local
/// filesystems and NFSv3+) under a name with 64 random bits, so writers that
/// share a directory never share a temporary file, even two processes with
/// the same id on different nodes of a cluster.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), IoError> {
    use std::io::Write;
    write_atomic_with(path, |file| file.write_all(bytes))
}

/// Writes `path` atomically as [`write_atomic`] does, with the bytes that
/// `write` streams into the temporary file (buffer them: the file is not),
/// so that a large file never has to be held in memory whole.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut std::fs::File) -> io::Result<()>,
) -> Result<(), IoError> {
    let (mut file, tmp) = create_temporary(path).map_err(|e| IoError::new("write", path, e))?;
    let result = (|| {
        write(&mut file)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(IoError::new("write", path, e));
    }
    Ok(())
}

/// Creates a new, empty temporary file beside `path`, named
/// `.NAME.PID.RANDOM.tmp`; a name that exists already is never reused.
fn create_temporary(path: &Path) -> io::Result<(std::fs::File, PathBuf)> {
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    loop {
        let tmp_name = format!(".{name}.{}.{:016x}.tmp", std::process::id(), random_u64());
        let tmp = match dir {
            Some(d) => d.join(tmp_name),
            None => PathBuf::from(tmp_name),
        };
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)
        {
            Ok(file) => return Ok((file, tmp)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
}

/// Whether `name` is that of a temporary file `create_temporary` makes
/// and a kill between its creation and its rename leaves behind:
/// `.NAME.PID.RANDOM.tmp`, `NAME` not empty, `PID` decimal digits and
/// `RANDOM` exactly 16 lowercase hexadecimal digits. Returns the `PID`.
pub fn stale_temporary_pid(name: &str) -> Option<u32> {
    let rest = name.strip_prefix('.')?.strip_suffix(".tmp")?;
    let (rest, random) = rest.rsplit_once('.')?;
    let (target, pid) = rest.rsplit_once('.')?;
    let hex = |c: char| c.is_ascii_digit() || ('a'..='f').contains(&c);
    let valid = !target.is_empty()
        && random.len() == 16
        && random.chars().all(hex)
        && !pid.is_empty()
        && pid.chars().all(|c| c.is_ascii_digit());
    valid.then(|| pid.parse().ok()).flatten()
}

/// Removes from `dir` (not its subdirectories) the temporary files that
/// [`write_atomic`] of another process left there when it was killed
/// between writing and renaming: regular files, never symbolic links or
/// directories, named as [`stale_temporary_pid`] says, whose process is not
/// this one. Returns the paths removed.
///
/// Call it only while holding the directory's lock, so that no other
/// writer of the directory runs: a temporary of a live writer is then
/// either this process's own (kept) or of a process that cannot be
/// writing here.
pub fn remove_stale_temporaries(dir: &Path) -> Result<Vec<PathBuf>, IoError> {
    let read = |e| IoError::new("read the directory", dir, e);
    let mut removed = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(read)? {
        let entry = entry.map_err(read)?;
        let stale = entry
            .file_name()
            .to_str()
            .and_then(stale_temporary_pid)
            .is_some_and(|pid| pid != std::process::id());
        // `file_type` does not follow a symbolic link.
        if stale && entry.file_type().map_err(read)?.is_file() {
            let path = entry.path();
            std::fs::remove_file(&path).map_err(|e| IoError::new("remove", &path, e))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(removed)
}

/// 64 random bits: the standard library's per-process random hash keys
/// (drawn from the operating system), mixed with a counter and the clock.
fn random_u64() -> u64 {
    use std::hash::{BuildHasher, Hasher};
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u64(COUNTER.fetch_add(1, Ordering::Relaxed));
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    h.write_u128(now);
    h.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_directory_another_running_process_writes_into_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        std::fs::create_dir(&out).unwrap();
        // A staging directory of a process that runs (the parent of this
        // test) refuses a second writer, and nothing of the refused one
        // is left.
        let parent = std::os::unix::process::parent_id();
        let live = out.join(format!(".staging-{parent}-0000000000000001"));
        std::fs::create_dir(&live).unwrap();
        let e = Staging::new(&out).err().expect("refused").to_string();
        assert!(
            e.contains(&format!("another process (pid {parent}) is writing")),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
        // One of a process that has ended is removed and the new one runs.
        std::fs::remove_dir(&live).unwrap();
        let stale = out.join(".staging-4194303-0000000000000002");
        std::fs::create_dir(&stale).unwrap();
        let s = Staging::new(&out).unwrap();
        assert!(!stale.exists());
        s.publish().unwrap();
    }

    #[test]
    fn only_the_exact_temporary_pattern_is_stale() {
        let random = "0123456789abcdef";
        assert_eq!(
            stale_temporary_pid(&format!(".runs.csv.42.{random}.tmp")),
            Some(42)
        );
        for name in [
            format!("runs.csv.42.{random}.tmp"),
            format!(".runs.csv.42.{random}.tmp~"),
            format!("..42.{random}.tmp"),
            format!(".runs.csv..{random}.tmp"),
            format!(".runs.csv.4x2.{random}.tmp"),
            format!(".runs.csv.42.{}.tmp", &random[1..]),
            format!(".runs.csv.42.{random}0.tmp"),
            ".runs.csv.42.0123456789ABCDEF.tmp".into(),
            ".runs.csv.42.0123456789abcdeg.tmp".into(),
            format!(".runs.csv.99999999999.{random}.tmp"),
            ".staging-42-0123456789abcdef".into(),
            "notes.tmp".into(),
        ] {
            assert_eq!(stale_temporary_pid(&name), None, "{name}");
        }
        // The name written by `create_temporary` matches.
        let dir = tempfile::tempdir().unwrap();
        let (_, tmp) = create_temporary(&dir.path().join("runs.csv")).unwrap();
        let name = tmp.file_name().unwrap().to_str().unwrap();
        assert_eq!(stale_temporary_pid(name), Some(std::process::id()));
    }

    #[test]
    fn stale_temporaries_of_other_processes_go_and_nothing_else() {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        let stale = d.join(".runs.csv.4194303.0123456789abcdef.tmp");
        std::fs::write(&stale, "x").unwrap();
        let (_, own) = create_temporary(&d.join("fits.csv")).unwrap();
        let kept = [
            d.join("runs.csv"),
            d.join(".runs.csv.4194303.0123456789abcdeX.tmp"),
        ];
        for k in &kept {
            std::fs::write(k, "x").unwrap();
        }
        // A link of the pattern is not followed or removed, nor its target;
        // neither is a directory of the pattern.
        let target = d.join("target.txt");
        std::fs::write(&target, "x").unwrap();
        let link = d.join(".link.7.0123456789abcdef.tmp");
        std::os::unix::fs::symlink(&target, &link).unwrap();
        let sub = d.join(".sub.7.0123456789abcdef.tmp");
        std::fs::create_dir(&sub).unwrap();
        assert_eq!(remove_stale_temporaries(d).unwrap(), vec![stale.clone()]);
        assert!(!stale.exists());
        for k in kept.iter().chain([&own, &target, &link, &sub]) {
            assert!(std::fs::symlink_metadata(k).is_ok(), "{}", k.display());
        }
    }

    #[test]
    fn an_atomic_write_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("out.csv");
        write_atomic(&path, b"x\n").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"x\n");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        // Temporary names never repeat, within a process or across them.
        let names: std::collections::HashSet<PathBuf> = (0..1000)
            .map(|_| {
                let (_, tmp) = create_temporary(&path).unwrap();
                tmp
            })
            .collect();
        assert_eq!(names.len(), 1000);
        assert!(names.iter().all(|t| t.exists()
            && t.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(".out.csv.")));
        let e = write_atomic(&dir.path().join("missing/out.csv"), b"x").unwrap_err();
        assert!(
            e.to_string().contains("missing/out.csv: cannot write"),
            "{e}"
        );
    }
}
