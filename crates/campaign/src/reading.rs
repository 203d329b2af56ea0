//! Opening a campaign's CSV files under their size caps: every reader of
//! `runs.csv`, the keyed files beside it, `outlines.csv` and the journal
//! goes through here, so an endless stream (`/dev/zero`) or a file far
//! larger than a campaign within its limits writes is refused at a stated
//! cap, with the file named (by the reader's error, which adds the line),
//! instead of filling the memory.

use std::path::Path;

use crate::files::{IoError, LimitedReader, ReadLimits};

/// The largest `runs.csv` (or external runs file) read: 4 GiB.
///
/// A campaign within its limits has at most [`crate::MAX_RUNS`] = 10⁷
/// runs, one row each; a row of ≈ 150 bytes (names of at most 100
/// characters, reals in shortest form) is typical, and 4 GiB leaves 429
/// bytes a row. The records read from a file this size take about the
/// memory [`crate::runner::MAX_RESULT_BYTES`] allows a campaign.
pub const MAX_RUNS_FILE_BYTES: u64 = 4 << 30;

/// The largest journal, `convergence.csv`, `timing.csv`, `hits.csv`,
/// `fits.csv`, `segments.csv` or `outlines.csv` read: 64 GiB.
///
/// These hold several rows a run (a convergence row repeats the run's key,
/// ≈ 100 bytes, for each 16-byte trace point held in memory), so their text
/// is up to ≈ 6 times the records' memory, itself at most
/// [`crate::runner::MAX_RESULT_BYTES`] = 4 GiB: 64 GiB is generous for a
/// campaign within its limits and still stops an endless stream.
pub const MAX_RESULT_FILE_BYTES: u64 = 64 << 30;

/// The longest line of any results file or journal: 64 MiB.
///
/// The longest line this tool writes is a journal line of a fitting run,
/// which carries all its segment rows: at most
/// `MAX_GLYPH_SEGMENTS` = 20,000 rows of ≈ 500 bytes, ≈ 10 MB. A line is
/// read whole into memory, so this cap is what keeps a file without
/// newlines (`/dev/zero`) from growing one record without end.
pub const MAX_RESULT_LINE_BYTES: u64 = 64 << 20;

/// What to do when a results file passes a cap.
const ADVICE: &str = "give a file a campaign of this tool wrote (a campaign over the \
                      limits runs as shards, each read on its own)";

/// The caps of `runs.csv` and of an external runs file.
pub const RUNS_LIMITS: ReadLimits = ReadLimits {
    file_bytes: MAX_RUNS_FILE_BYTES,
    line_bytes: MAX_RESULT_LINE_BYTES,
    what: "a runs file",
    advice: ADVICE,
};

/// The caps of the files beside `runs.csv` (keyed by run, and
/// `outlines.csv`).
pub const RESULT_LIMITS: ReadLimits = ReadLimits {
    file_bytes: MAX_RESULT_FILE_BYTES,
    line_bytes: MAX_RESULT_LINE_BYTES,
    what: "a results file",
    advice: ADVICE,
};

/// The caps of a journal.
pub const JOURNAL_LIMITS: ReadLimits = ReadLimits {
    file_bytes: MAX_RESULT_FILE_BYTES,
    line_bytes: MAX_RESULT_LINE_BYTES,
    what: "a journal",
    advice: "give the journal.csv a campaign of this tool wrote",
};

/// A CSV file being read under its caps.
pub type CsvFile = csv::Reader<LimitedReader<std::fs::File>>;

/// Opens the CSV file at `path` (with a header row when `header`, rows of
/// any width) under `limits`.
pub fn open_csv(path: &Path, limits: ReadLimits, header: bool) -> Result<CsvFile, IoError> {
    let file = std::fs::File::open(path).map_err(|e| IoError::new("read", path, e))?;
    Ok(csv::ReaderBuilder::new()
        .has_headers(header)
        .flexible(true)
        .from_reader(LimitedReader::new(file, limits)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    #[test]
    fn a_csv_file_over_a_test_cap_is_refused_with_the_file_and_cap_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("runs.csv");
        std::fs::write(&path, "a,b\n1,2\n3,4\n5,6\n").unwrap();
        let small = ReadLimits {
            file_bytes: 10,
            ..RUNS_LIMITS
        };
        let mut reader = open_csv(&path, small, true).unwrap();
        let e = reader
            .records()
            .find_map(Result::err)
            .map(|e| e.to_string())
            .expect("refused");
        assert!(
            e.starts_with("it is larger than the 10 bytes a runs file may be; give a file"),
            "{e}"
        );
        // Within the cap it reads whole.
        let mut reader = open_csv(&path, RUNS_LIMITS, true).unwrap();
        assert_eq!(reader.records().count(), 3);
        let mut rest = String::new();
        reader.into_inner().read_to_string(&mut rest).unwrap();
        assert!(rest.is_empty());
    }
}
