//! `SHA256SUMS`: one line `<64 lowercase hex digits><two spaces><path>`
//! per file, sorted by path, as GNU coreutils' `sha256sum` writes it in
//! text mode and `sha256sum -c` reads it
//! (<https://www.gnu.org/software/coreutils/manual/html_node/md5sum-invocation.html>,
//! whose format `sha256sum` shares). Paths are relative to the directory
//! that holds `SHA256SUMS`, with `/` between components; a name with a
//! newline or a backslash (which `sha256sum` would escape) is never
//! archived.

use std::io::{self, Read};

use sha2::{Digest, Sha256};

/// The name of the checksum file.
pub const SHA256SUMS: &str = "SHA256SUMS";

/// A reader that passes on the bytes of another and hashes them with
/// SHA-256 on the way.
pub struct HashingReader<R> {
    inner: R,
    hasher: Sha256,
    bytes: u64,
}

impl<R: Read> HashingReader<R> {
    /// Hashes what `inner` yields.
    pub fn new(inner: R) -> Self {
        HashingReader {
            inner,
            hasher: Sha256::new(),
            bytes: 0,
        }
    }

    /// The SHA-256 of the bytes passed on, in lowercase hex, and their
    /// number.
    pub fn finish(self) -> (String, u64) {
        let hex = self
            .hasher
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        (hex, self.bytes)
    }
}

impl<R: Read> Read for HashingReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.hasher.update(&buf[..n]);
        self.bytes += n as u64;
        Ok(n)
    }
}

/// The SHA-256 of everything `reader` yields, in lowercase hex, and the
/// number of bytes it yielded.
pub fn sha256_hex(reader: impl Read) -> io::Result<(String, u64)> {
    let mut hashing = HashingReader::new(reader);
    io::copy(&mut hashing, &mut io::sink())?;
    Ok(hashing.finish())
}

/// The text of `SHA256SUMS` for `(path, hex)` pairs, sorted by path.
pub fn format_sums(sums: &[(String, String)]) -> String {
    let mut sorted: Vec<&(String, String)> = sums.iter().collect();
    sorted.sort();
    sorted
        .iter()
        .map(|(path, hex)| format!("{hex}  {path}\n"))
        .collect()
}

/// A line of a `SHA256SUMS` text that is not `<hex>  <path>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("line {line} is not \"<64 hex digits>  <path>\" as sha256sum writes it")]
pub struct SumsLineError {
    /// The line, from 1.
    pub line: usize,
}

/// The `(path, hex)` pairs of a `SHA256SUMS` text, in its order; the
/// error names the line (from 1) that is not `<hex>  <path>` (or the
/// binary-mode `<hex> *<path>`).
pub fn parse_sums(text: &str) -> Result<Vec<(String, String)>, SumsLineError> {
    text.lines()
        .enumerate()
        .map(|(i, line)| {
            let bad = || SumsLineError { line: i + 1 };
            let (hex, rest) = line.split_at_checked(64).ok_or_else(bad)?;
            let path = rest
                .strip_prefix("  ")
                .or_else(|| rest.strip_prefix(" *"))
                .filter(|p| !p.is_empty())
                .ok_or_else(bad)?;
            if !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
                return Err(bad());
            }
            Ok((path.to_owned(), hex.to_ascii_lowercase()))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_digest_is_sha256() {
        // FIPS 180-2's example "abc".
        let (hex, n) = sha256_hex(&b"abc"[..]).unwrap();
        assert_eq!(
            hex,
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
        assert_eq!(n, 3);
    }

    #[test]
    fn sums_are_written_sorted_and_read_back() {
        let a = "a".repeat(64);
        let b = "b".repeat(64);
        let text = format_sums(&[
            ("z.csv".into(), a.clone()),
            ("plots/x.svg".into(), b.clone()),
        ]);
        assert_eq!(text, format!("{b}  plots/x.svg\n{a}  z.csv\n"));
        assert_eq!(
            parse_sums(&text).unwrap(),
            [("plots/x.svg".to_owned(), b), ("z.csv".to_owned(), a)]
        );
        assert_eq!(
            parse_sums("abc  x\n").unwrap_err().to_string(),
            "line 1 is not \"<64 hex digits>  <path>\" as sha256sum writes it"
        );
    }
}
