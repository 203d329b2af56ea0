//! A reader held to a size cap: a streaming reader (a CSV file read a row
//! at a time) stops at the cap of its file and of each line, so an endless
//! stream (`/dev/zero`, a FIFO) or a file far larger than any this tool
//! writes is refused before it can take the machine's memory.

use std::io::{self, Read};

/// The caps of one kind of file, and the words that name it in a refusal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ReadLimits {
    /// The most bytes the file may hold.
    pub file_bytes: u64,
    /// The most bytes one line may hold, its newline not counted.
    pub line_bytes: u64,
    /// The kind of file, as the refusal names it ("a runs file").
    pub what: &'static str,
    /// What to do about a refusal ("give the runs.csv a campaign wrote").
    pub advice: &'static str,
}

/// `bytes` in the largest binary unit that divides it: "4 GiB", "64 MiB",
/// "100 bytes".
pub fn size_text(bytes: u64) -> String {
    for (shift, unit) in [(30, "GiB"), (20, "MiB"), (10, "KiB")] {
        if bytes >= 1 << shift && bytes.is_multiple_of(1 << shift) {
            return format!("{} {unit}", bytes >> shift);
        }
    }
    format!("{bytes} bytes")
}

/// A reader that passes on at most [`ReadLimits::file_bytes`] bytes of its
/// source, in lines of at most [`ReadLimits::line_bytes`] bytes, and
/// otherwise fails with [`io::ErrorKind::FileTooLarge`] (every read after
/// the first refusal fails the same way). It reads at most one byte past
/// the file cap, and holds nothing itself: a line is refused as soon as
/// it passes the line cap, whatever holds the bytes before it.
pub struct LimitedReader<R> {
    inner: R,
    limits: ReadLimits,
    /// Bytes passed on so far.
    read: u64,
    /// Bytes of the current line so far.
    line: u64,
    /// The current line, from 1.
    line_no: u64,
    /// The refusal, once there is one.
    refused: Option<String>,
}

impl<R: Read> LimitedReader<R> {
    /// `inner` held to `limits`.
    pub fn new(inner: R, limits: ReadLimits) -> Self {
        LimitedReader {
            inner,
            limits,
            read: 0,
            line: 0,
            line_no: 1,
            refused: None,
        }
    }

    fn refusal(&self) -> Option<io::Error> {
        self.refused
            .as_ref()
            .map(|m| io::Error::new(io::ErrorKind::FileTooLarge, m.clone()))
    }

    /// Counts the lines of `bytes`; the message of a line over its cap.
    fn count_lines(&mut self, bytes: &[u8]) -> Option<String> {
        for (k, part) in bytes.split(|&b| b == b'\n').enumerate() {
            if k > 0 {
                self.line = 0;
                self.line_no += 1;
            }
            self.line += part.len() as u64;
            if self.line > self.limits.line_bytes {
                return Some(format!(
                    "line {} is longer than the {} a line of {} may be, so this is not {}; {}",
                    self.line_no,
                    size_text(self.limits.line_bytes),
                    self.limits.what,
                    self.limits.what,
                    self.limits.advice
                ));
            }
        }
        None
    }
}

impl<R: Read> Read for LimitedReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        if let Some(e) = self.refusal() {
            return Err(e);
        }
        let room = self
            .limits
            .file_bytes
            .saturating_add(1)
            .saturating_sub(self.read);
        let take = usize::try_from(room).unwrap_or(usize::MAX).min(buf.len());
        let n = self.inner.read(&mut buf[..take])?;
        self.read += n as u64;
        if self.read > self.limits.file_bytes {
            self.refused = Some(format!(
                "it is larger than the {} {} may be; {}",
                size_text(self.limits.file_bytes),
                self.limits.what,
                self.limits.advice
            ));
        } else {
            self.refused = self.count_lines(&buf[..n]);
        }
        match self.refusal() {
            Some(e) => Err(e),
            None => Ok(n),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SMALL: ReadLimits = ReadLimits {
        file_bytes: 100,
        line_bytes: 10,
        what: "a test file",
        advice: "give a smaller one",
    };

    fn read_all(bytes: &[u8], limits: ReadLimits) -> io::Result<Vec<u8>> {
        let mut out = Vec::new();
        LimitedReader::new(bytes, limits).read_to_end(&mut out)?;
        Ok(out)
    }

    #[test]
    fn a_file_within_its_caps_passes_whole() {
        let text = b"0123456789\n0123456789\n\n";
        assert_eq!(read_all(text, SMALL).unwrap(), text);
        let exact = vec![b'a'; 10];
        assert_eq!(read_all(&exact, SMALL).unwrap(), exact);
    }

    #[test]
    fn a_file_over_its_cap_is_refused_with_the_cap_named() {
        let text = b"12345678\n".repeat(12);
        let e = read_all(&text, SMALL).unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::FileTooLarge);
        assert_eq!(
            e.to_string(),
            "it is larger than the 100 bytes a test file may be; give a smaller one"
        );
    }

    #[test]
    fn a_long_line_is_refused_with_its_number_even_inside_one_read() {
        let e = read_all(b"short\n01234567890\n", SMALL).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("line 2 is longer than the 10 bytes a line of a test file may be"),
            "{e}"
        );
        // An endless stream without a newline stops at the line cap, and
        // every later read fails the same way.
        let limits = ReadLimits {
            file_bytes: u64::MAX,
            line_bytes: 1 << 20,
            ..SMALL
        };
        let mut zero = LimitedReader::new(io::repeat(0), limits);
        let mut sink = Vec::new();
        let e = zero.read_to_end(&mut sink).unwrap_err();
        assert!(e.to_string().contains("the 1 MiB a line"), "{e}");
        assert!(sink.len() <= (1 << 20) + 8192);
        assert!(zero.read(&mut [0; 8]).is_err());
    }

    #[test]
    fn sizes_are_named_in_their_largest_whole_unit() {
        assert_eq!(size_text(4 << 30), "4 GiB");
        assert_eq!(size_text(64 << 20), "64 MiB");
        assert_eq!(size_text(3 << 10), "3 KiB");
        assert_eq!(size_text(1000), "1000 bytes");
    }
}
