//! The reproducible `.tar.gz`: entries in path order, every header the
//! same whatever the machine (GNU format, mtime 0, uid and gid 0, no user
//! or group names, mode 0755 for a directory and 0644 for a file), and a
//! gzip header with mtime 0, no file name and the "unknown" system byte.

use std::io::{self, Read, Write};
use std::path::PathBuf;

use flate2::{Compression, GzBuilder};
use tar::{Builder, EntryType, Header};

use super::sums::HashingReader;

/// What one entry of the archive holds.
pub enum Content {
    /// A directory.
    Dir,
    /// A file on disk: its path, its size and its SHA-256 when listed; the
    /// bytes written must still match them.
    Disk(PathBuf, u64, String),
    /// Bytes made by the archive (`SHA256SUMS`, `.zenodo.json`,
    /// `CITATION.cff`).
    Bytes(Vec<u8>),
}

/// An upper bound of the bytes of the tar stream of entries at paths of
/// the given lengths, of the given sizes (`None` for a directory): a
/// 512-byte header each (and, for a path of 100 bytes or more, a GNU
/// long-name header and the name padded to 512 bytes), the data padded to
/// 512 bytes, and the 1024 zero bytes that end the stream.
pub fn tar_bytes(entries: impl Iterator<Item = (usize, Option<u64>)>) -> u64 {
    let pad = |n: u64| n.div_ceil(512) * 512;
    let body: u64 = entries
        .map(|(path_len, size)| {
            let long = if path_len >= 100 {
                512 + pad(path_len as u64 + 1)
            } else {
                0
            };
            512 + long + pad(size.unwrap_or(0))
        })
        .sum();
    body + 1024
}

/// Writes the gzip-compressed tar of `entries` (archive path, content; in
/// the order given) into `out`. A file on disk whose bytes no longer match
/// the size and digest it was listed with fails with the path named.
pub fn write_tar_gz(out: impl Write, entries: &[(String, Content)]) -> io::Result<()> {
    let gz = GzBuilder::new().mtime(0).write(out, Compression::default());
    let mut tar = Builder::new(gz);
    for (path, content) in entries {
        let mut header = Header::new_gnu();
        header.set_uid(0);
        header.set_gid(0);
        header.set_mtime(0);
        match content {
            Content::Dir => {
                header.set_entry_type(EntryType::Directory);
                header.set_mode(0o755);
                header.set_size(0);
                tar.append_data(&mut header, format!("{path}/"), io::empty())?;
            }
            Content::Bytes(bytes) => {
                file_header(&mut header, bytes.len() as u64);
                tar.append_data(&mut header, path, &bytes[..])?;
            }
            Content::Disk(disk, size, hex) => {
                file_header(&mut header, *size);
                let file = std::fs::File::open(disk)?;
                // One byte more than listed, so that a file that grew is
                // told from one that did not.
                let mut hashing = HashingReader::new(file.take(size + 1));
                tar.append_data(&mut header, path, (&mut hashing).take(*size))?;
                let rest = io::copy(&mut hashing, &mut io::sink())?;
                let (h, n) = hashing.finish();
                let unchanged = rest == 0 && n == *size && &h == hex;
                if !unchanged {
                    return Err(io::Error::other(format!(
                        "{}: changed while being archived; archive again once nothing writes into the directory",
                        disk.display()
                    )));
                }
            }
        }
    }
    tar.into_inner()?.finish()?.flush()
}

/// The header of a regular file of `size` bytes.
fn file_header(header: &mut Header, size: u64) {
    header.set_entry_type(EntryType::Regular);
    header.set_mode(0o644);
    header.set_size(size);
}
