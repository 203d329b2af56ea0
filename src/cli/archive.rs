//! `metabezier archive`: a results directory as a reproducible `.tar.gz`
//! for an archival repository, and `--verify` of such an archive; the work
//! is `experiment::archive`'s.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::error::{Error, UsageError};
use crate::experiment::archive::{verify_archive, write_archive, SOFTWARE};

/// Arguments of `metabezier archive`.
#[derive(Debug, clap::Args)]
pub(super) struct ArchiveArgs {
    /// A campaign's results directory (it holds runs.csv), or a results/
    /// directory whose every subdirectory is one.
    #[arg(required_unless_present = "verify", conflicts_with = "verify")]
    dir: Option<PathBuf>,
    /// The archive to write (FILE.tar.gz).
    #[arg(long, value_name = "FILE", required_unless_present = "verify")]
    out: Option<PathBuf>,
    /// Check an archive against its SHA256SUMS instead of writing one.
    #[arg(long, value_name = "FILE", conflicts_with = "out")]
    verify: Option<PathBuf>,
}

/// Writes or verifies an archive, and says what it holds.
pub(super) fn archive(a: ArchiveArgs, w: &mut String) -> Result<(), Error> {
    match (a.verify, a.dir, a.out) {
        (Some(file), None, None) => {
            let v = verify_archive(&file)?;
            say!(
                w,
                "{}: OK, {} files, {} bytes, each equal to its SHA-256 in SHA256SUMS",
                file.display(),
                v.files,
                v.bytes
            );
        }
        (None, Some(dir), Some(out)) => {
            let written = write_archive(&dir, &out, &SOFTWARE)?;
            let names: Vec<&str> = written.campaigns.iter().map(|c| c.name.as_str()).collect();
            say!(
                w,
                "{}: {} campaign(s) ({}), {} files, {} bytes, with SHA256SUMS and .zenodo.json; check it with `metabezier archive --verify {}`",
                out.display(),
                names.len(),
                names.join(", "),
                written.files,
                written.bytes,
                out.display()
            );
        }
        _ => return Err(UsageError::ArchiveMode.into()),
    }
    Ok(())
}
