//! `archive --verify`: an archive read back under a size cap, every entry
//! checked against its `SHA256SUMS`.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::Path;

use tar::EntryType;

use super::sums::{parse_sums, HashingReader, SHA256SUMS};
use super::{ArchiveError, Verified};
use crate::files::{size_text, IoError, LimitedReader, ReadLimits, MAX_TEXT_BYTES};

/// What was found in the archive: each file's digest and size, by its
/// path below the top directory, and the text of `SHA256SUMS`.
#[derive(Default)]
struct Found {
    top: Option<String>,
    files: BTreeMap<String, (String, u64)>,
    sums: Option<String>,
}

/// Checks the archive at `path`, reading at most `cap` bytes of its tar
/// stream (uncompressed).
pub fn verify(path: &Path, cap: u64) -> Result<Verified, ArchiveError> {
    let fail = |entry: &str, problem: String| ArchiveError::Verify {
        archive: path.to_owned(),
        entry: entry.to_owned(),
        problem,
    };
    let file = std::fs::File::open(path).map_err(|e| IoError::new("read", path, e))?;
    let limits = ReadLimits {
        file_bytes: cap,
        line_bytes: u64::MAX,
        what: "an archive (uncompressed, MAX_ARCHIVE_BYTES)",
        advice: "an archive this tool writes is never larger",
    };
    let stream = LimitedReader::new(flate2::read::GzDecoder::new(file), limits);
    let found = read_entries(path, tar::Archive::new(stream), &fail)?;
    let top = found
        .top
        .ok_or_else(|| fail(SHA256SUMS, "the archive is empty".into()))?;
    let sums_path = format!("{top}/{SHA256SUMS}");
    let text = found
        .sums
        .ok_or_else(|| fail(&sums_path, "is missing".into()))?;
    let listed = parse_sums(&text).map_err(|e| fail(&sums_path, e.to_string()))?;
    let mut bytes = 0u64;
    let mut seen = BTreeMap::new();
    for (rel, hex) in &listed {
        let name = format!("{top}/{rel}");
        if seen.insert(rel.as_str(), ()).is_some() {
            return Err(fail(&sums_path, format!("lists {rel} twice")));
        }
        match found.files.get(rel) {
            None => {
                return Err(fail(
                    &name,
                    "is listed in SHA256SUMS but not in the archive".into(),
                ))
            }
            Some((got, _)) if got != hex => {
                return Err(fail(
                    &name,
                    format!("differs from SHA256SUMS: its SHA-256 is {got}, SHA256SUMS says {hex}"),
                ))
            }
            Some((_, size)) => bytes += size,
        }
    }
    if let Some(extra) = found.files.keys().find(|k| !seen.contains_key(k.as_str())) {
        return Err(fail(
            &format!("{top}/{extra}"),
            "is in the archive but not listed in SHA256SUMS".into(),
        ));
    }
    Ok(Verified {
        files: listed.len(),
        bytes,
    })
}

/// Reads every entry of `archive`: each regular file hashed, `SHA256SUMS`
/// kept as text; a link, device or unsafe path refused.
fn read_entries<R: Read>(
    path: &Path,
    mut archive: tar::Archive<R>,
    fail: &dyn Fn(&str, String) -> ArchiveError,
) -> Result<Found, ArchiveError> {
    let unreadable = |e: std::io::Error| ArchiveError::Unreadable {
        archive: path.to_owned(),
        problem: match e.kind() {
            std::io::ErrorKind::FileTooLarge => e.to_string(),
            _ => format!("not a readable .tar.gz: {e}"),
        },
    };
    let mut found = Found::default();
    for entry in archive.entries().map_err(unreadable)? {
        let mut entry = entry.map_err(unreadable)?;
        let raw = entry.path_bytes().into_owned();
        let name = String::from_utf8_lossy(&raw).into_owned();
        let kind = entry.header().entry_type();
        let (top, rel) = safe_path(&name).ok_or_else(|| {
            fail(&name, "has an unsafe path (absolute, empty, or with . or ..); it is not an archive of this tool".into())
        })?;
        if found.top.get_or_insert_with(|| top.to_owned()) != top {
            return Err(fail(
                &name,
                "lies outside the archive's one top directory".into(),
            ));
        }
        match kind {
            EntryType::Directory => continue,
            EntryType::Regular | EntryType::Continuous => {}
            other => {
                return Err(fail(
                    &name,
                    format!("is a {other:?} entry, not a regular file or directory; an archive of this tool holds no links or devices"),
                ))
            }
        }
        let rel =
            rel.ok_or_else(|| fail(&name, "is a file where the top directory should be".into()))?;
        if found.files.contains_key(rel) || (rel == SHA256SUMS && found.sums.is_some()) {
            return Err(fail(&name, "is in the archive twice".into()));
        }
        if rel == SHA256SUMS {
            let mut text = String::new();
            (&mut entry)
                .take(MAX_TEXT_BYTES + 1)
                .read_to_string(&mut text)
                .map_err(unreadable)?;
            if text.len() as u64 > MAX_TEXT_BYTES {
                return Err(fail(
                    &name,
                    format!("is larger than the {} it may be", size_text(MAX_TEXT_BYTES)),
                ));
            }
            found.sums = Some(text);
        } else {
            let mut hashing = HashingReader::new(&mut entry);
            std::io::copy(&mut hashing, &mut std::io::sink()).map_err(unreadable)?;
            found.files.insert(rel.to_owned(), hashing.finish());
        }
    }
    Ok(found)
}

/// The top directory of a safe entry path and the rest (`None` for the top
/// directory itself); `None` for a path that is absolute, empty, or has an
/// empty, `.` or `..` component or a backslash.
fn safe_path(name: &str) -> Option<(&str, Option<&str>)> {
    let trimmed = name.strip_suffix('/').unwrap_or(name);
    if trimmed.is_empty() || trimmed.starts_with('/') || trimmed.contains('\\') {
        return None;
    }
    if trimmed
        .split('/')
        .any(|c| c.is_empty() || c == "." || c == "..")
    {
        return None;
    }
    Some(match trimmed.split_once('/') {
        Some((top, rest)) => (top, Some(rest)),
        None => (trimmed, None),
    })
}

#[cfg(test)]
mod tests {
    use super::safe_path;

    #[test]
    fn only_relative_paths_below_one_top_are_safe() {
        assert_eq!(safe_path("ch4/"), Some(("ch4", None)));
        assert_eq!(
            safe_path("ch4/plots/a.svg"),
            Some(("ch4", Some("plots/a.svg")))
        );
        for bad in ["", "/etc/passwd", "ch4/../x", "./ch4", "ch4//x", "a\\b"] {
            assert_eq!(safe_path(bad), None, "{bad}");
        }
    }
}
