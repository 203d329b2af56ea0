//! `provenance.toml`: where, when and with what build the runs of a
//! campaign directory were made — the metabezier version, the git commit
//! it was built from, the date, the thread count, the SIMD level and the
//! CPU model, one `[[session]]` per invocation that executed runs.
//!
//! It sits beside `meta.toml`, which stays deterministic (the same spec
//! gives the same `meta.toml` on every machine): the comparisons of result
//! directories byte for byte skip `provenance.toml`, as they skip
//! `timing.csv`. A resumed campaign appends a session, so a directory
//! finished on two machines says so; `merge` writes the sessions of its
//! shards in shard order.

use std::path::Path;

use crate::files::{read_text_limited, write_atomic, IoError, MAX_TEXT_BYTES};
use crate::simd::{simd, Simd};

/// The file name.
pub const PROVENANCE_FILE: &str = "provenance.toml";

/// The commit recorded by [`crate::run_campaign`], which names none. The
/// commit is the binary's (`metabezier`'s `build.rs`, passed to
/// [`crate::runner::run_campaign_built`]), kept out of this crate so that a
/// new commit does not rebuild it.
pub const UNKNOWN_COMMIT: &str = "unknown";

/// One invocation that executed runs.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Session {
    /// The metabezier version (`CARGO_PKG_VERSION`).
    pub version: String,
    /// The git commit of the build, or "unknown".
    pub commit: String,
    /// When the session started, UTC, RFC 3339 to the second.
    pub date: String,
    /// The worker threads the runs were spread over.
    pub threads: usize,
    /// The vector instruction set of the hot loops (`portable`, `avx2`,
    /// `avx512`); results do not depend on it, only the speed.
    pub simd: String,
    /// The CPU model (`/proc/cpuinfo`'s "model name"), or "unknown".
    pub cpu: String,
    /// The runs this session executed.
    pub runs: usize,
}

impl Session {
    /// This process's session, begun now, on `threads` worker threads,
    /// having executed `runs` runs, by a build of git commit `commit`.
    pub fn now(commit: &str, threads: usize, runs: usize) -> Session {
        Session {
            version: env!("CARGO_PKG_VERSION").to_owned(),
            commit: commit.to_owned(),
            date: utc_now(),
            threads,
            simd: simd_name(simd()).to_owned(),
            cpu: cpu_model(),
            runs,
        }
    }

    /// The session as a `[[session]]` table.
    fn toml(&self) -> String {
        format!(
            "[[session]]\nversion = {}\ncommit = {}\ndate = {}\nthreads = {}\nsimd = {}\ncpu = {}\nruns = {}\n",
            quote(&self.version),
            quote(&self.commit),
            quote(&self.date),
            self.threads,
            quote(&self.simd),
            quote(&self.cpu),
            self.runs
        )
    }
}

const HEADER: &str = "# Written by metabezier: where, when and with what build the runs of this \
                      directory were made,\n# one [[session]] per invocation that executed runs. \
                      Not a result: results do not depend on it.\n";

/// Appends `session` to `dir/provenance.toml` (written atomically; a file
/// that cannot be read as sessions is replaced rather than extended).
pub fn append(dir: &Path, session: &Session) -> Result<(), IoError> {
    let mut sessions = read(dir);
    sessions.push(session.clone());
    write(dir, &sessions)
}

/// Writes `sessions` as `dir/provenance.toml`, atomically.
pub fn write(dir: &Path, sessions: &[Session]) -> Result<(), IoError> {
    let mut text = HEADER.to_owned();
    for s in sessions {
        text.push('\n');
        text.push_str(&s.toml());
    }
    write_atomic(&dir.join(PROVENANCE_FILE), text.as_bytes())
}

/// The sessions of `dir/provenance.toml`, oldest first; empty when the file
/// is missing, over [`MAX_TEXT_BYTES`] or is not a list of sessions.
pub fn read(dir: &Path) -> Vec<Session> {
    let path = dir.join(PROVENANCE_FILE);
    let Ok(text) = read_text_limited(&path, MAX_TEXT_BYTES, "a provenance.toml") else {
        return Vec::new();
    };
    let Ok(value) = text.parse::<toml::Table>() else {
        return Vec::new();
    };
    let Some(list) = value.get("session").and_then(|v| v.as_array()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for t in list.iter().filter_map(|v| v.as_table()) {
        let text = |k: &str| t.get(k).and_then(|v| v.as_str()).map(str::to_owned);
        let count = |k: &str| {
            t.get(k)
                .and_then(|v| v.as_integer())
                .and_then(|n| usize::try_from(n).ok())
        };
        let session = (|| {
            Some(Session {
                version: text("version")?,
                commit: text("commit")?,
                date: text("date")?,
                threads: count("threads")?,
                simd: text("simd")?,
                cpu: text("cpu")?,
                runs: count("runs")?,
            })
        })();
        match session {
            Some(s) => out.push(s),
            None => return Vec::new(),
        }
    }
    out
}

/// The name of a SIMD level.
pub fn simd_name(level: Simd) -> &'static str {
    match level {
        Simd::Portable => "portable",
        Simd::Avx2 => "avx2",
        Simd::Avx512 => "avx512",
    }
}

/// A TOML basic string.
fn quote(s: &str) -> String {
    toml::Value::String(s.to_owned()).to_string()
}

/// The CPU model from `/proc/cpuinfo`, or "unknown".
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, m)| m.trim().to_owned())
        })
        .filter(|m| !m.is_empty())
        .unwrap_or_else(|| "unknown".into())
}

/// Now, UTC, as `YYYY-MM-DDThh:mm:ssZ`.
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    rfc3339(secs)
}

/// Seconds since 1970-01-01T00:00:00Z as `YYYY-MM-DDThh:mm:ssZ`; the
/// civil date from the day count by Hinnant's algorithm ("chrono-Compatible
/// Low-Level Date Algorithms", 2013, `civil_from_days`).
fn rfc3339(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let rem = secs % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_are_civil_utc() {
        assert_eq!(rfc3339(0), "1970-01-01T00:00:00Z");
        assert_eq!(rfc3339(951_782_400), "2000-02-29T00:00:00Z");
        assert_eq!(rfc3339(1_796_300_000), "2026-12-03T12:13:20Z");
        assert_eq!(rfc3339(4_107_542_399), "2100-02-28T23:59:59Z");
    }

    #[test]
    fn sessions_round_trip_and_append() {
        let dir = tempfile::tempdir().unwrap();
        assert!(read(dir.path()).is_empty());
        let a = Session::now(UNKNOWN_COMMIT, 2, 10);
        append(dir.path(), &a).unwrap();
        let mut b = a.clone();
        b.cpu = "a \"quoted\" model".into();
        b.runs = 3;
        append(dir.path(), &b).unwrap();
        assert_eq!(read(dir.path()), [a.clone(), b]);
        assert_eq!(a.version, env!("CARGO_PKG_VERSION"));
        assert!(
            a.commit == "unknown" || a.commit.len() == 40,
            "{}",
            a.commit
        );
        assert!(["portable", "avx2", "avx512"].contains(&a.simd.as_str()));
        // A damaged file is replaced, not extended.
        std::fs::write(
            dir.path().join(PROVENANCE_FILE),
            "[[session]]\nversion = 1\n",
        )
        .unwrap();
        assert!(read(dir.path()).is_empty());
        append(dir.path(), &a).unwrap();
        assert_eq!(read(dir.path()), [a]);
    }
}
