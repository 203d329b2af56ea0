//! The crate's error type: every failure a user can cause, with the file
//! and the place it concerns.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use crate::spec::SpecError;

/// An error reported to the user; none of these is a panic.
#[derive(Debug)]
pub enum Error {
    /// An experiment spec is invalid.
    Spec(SpecError),
    /// A file could not be read, written or renamed.
    Io {
        /// What was being done, such as "write" or "create the directory".
        action: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// A results file is malformed.
    Data {
        /// The file.
        path: PathBuf,
        /// 1-based line, or 0 if unknown.
        line: u64,
        /// What is wrong.
        message: String,
    },
    /// A campaign cannot proceed as asked (resume or merge conflicts).
    Campaign(String),
}

impl Error {
    /// An I/O error on `path`.
    pub fn io(action: &'static str, path: &Path, source: io::Error) -> Self {
        Error::Io {
            action,
            path: path.to_owned(),
            source,
        }
    }

    /// A malformed-data error in `path` at `line`.
    pub fn data(path: &Path, line: u64, message: impl Into<String>) -> Self {
        Error::Data {
            path: path.to_owned(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::Spec(e) => e.fmt(f),
            Error::Io {
                action,
                path,
                source,
            } => write!(f, "{}: cannot {action}: {source}", path.display()),
            Error::Data {
                path,
                line: 0,
                message,
            } => write!(f, "{}: {message}", path.display()),
            Error::Data {
                path,
                line,
                message,
            } => write!(f, "{}:{line}: {message}", path.display()),
            Error::Campaign(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Io { source, .. } => Some(source),
            Error::Spec(e) => Some(e),
            _ => None,
        }
    }
}

impl From<SpecError> for Error {
    fn from(e: SpecError) -> Self {
        Error::Spec(e)
    }
}

/// Writes `bytes` to `path` atomically: to a temporary file in the same
/// directory, synced, then renamed over `path`, so that no reader ever sees a
/// half-written file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write;
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty());
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = match dir {
        Some(d) => d.join(format!(".{name}.{}.tmp", std::process::id())),
        None => PathBuf::from(format!(".{name}.{}.tmp", std::process::id())),
    };
    let result = (|| {
        let mut file = std::fs::File::create(&tmp)?;
        file.write_all(bytes)?;
        file.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(Error::io("write", path, e));
    }
    Ok(())
}
