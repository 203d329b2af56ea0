//! Outlines from CSV point lists: one `x,y` pair per line.
//!
//! Lines starting with `#` are comments and blank lines are skipped; cells
//! may be padded with spaces. The first record is a header, and skipped, if
//! neither of its cells is a number (such as `x,y`). The outline is closed
//! when its last point repeats the first (the repeat is dropped) or when
//! [`CsvOptions::closed`] says so. Coordinates are taken as given (a y-up
//! frame is assumed).
//!
//! **Limits.** A file may hold at most [`MAX_CSV_POINTS`] points, and a
//! record (a line of cells, after trimming) at most [`MAX_CSV_LINE_BYTES`]
//! bytes; coordinates must be within ±[`MAX_COORDINATE`] and the points
//! must span enough for E to be resolved ([`MIN_EXTENT`],
//! [`MIN_RELATIVE_EXTENT`]). The reader's memory is proportional to the
//! file: 16 bytes a point, from at least 4 bytes of text (`0,0` and a
//! newline).

use std::path::Path;

use super::{CsvError, Outline, OutlineError};
use crate::geometry::{bounding_box, Point};

/// Options for reading a CSV point list.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CsvOptions {
    /// `Some(true)` or `Some(false)` forces a closed or an open outline;
    /// `None` closes it when the last point equals the first.
    pub closed: Option<bool>,
    /// The fewest points accepted (after dropping a closing repeat).
    pub min_points: usize,
}

impl Default for CsvOptions {
    /// Closed when the last point repeats the first, at least 3 points.
    fn default() -> Self {
        CsvOptions {
            closed: None,
            min_points: 3,
        }
    }
}

/// Parses a finite number, or `None`.
fn number(cell: &str) -> Option<f64> {
    cell.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The largest coordinate magnitude accepted, in CSV outlines, SVG curves
/// (after their transforms) and glyphs: squared distances of points this far
/// apart stay far from overflow, and no image or font comes near.
pub const MAX_COORDINATE: f64 = 1e15;

/// The most points a CSV outline may have (160 MB of coordinates); a curve
/// fit of more points than this is beyond what this tool is for.
pub const MAX_CSV_POINTS: usize = 10_000_000;

/// The longest record (`x,y` after trimming the cells) a CSV outline may
/// have, in bytes: two numbers in any notation take well under 100.
/// Comment lines are not limited.
pub const MAX_CSV_LINE_BYTES: usize = 1024;

/// 1-based line numbers of byte offsets, counted forward from the last
/// offset asked (records come in order), so a file is scanned once.
struct Lines<'b> {
    bytes: &'b [u8],
    at: usize,
    line: u64,
}

impl Lines<'_> {
    /// The line of the first record at or after `byte`: the line holding
    /// `byte`, moved past the comment and empty lines the reader skipped.
    fn of(&mut self, byte: usize) -> u64 {
        let byte = byte.min(self.bytes.len());
        if byte < self.at {
            self.at = 0;
            self.line = 1;
        }
        self.line += self.bytes[self.at..byte]
            .iter()
            .filter(|&&b| b == b'\n')
            .count() as u64;
        self.at = byte;
        let (mut start, mut line) = (byte, self.line);
        while let Some(len) = self.bytes[start..].iter().position(|&b| b == b'\n') {
            let text = &self.bytes[start..start + len];
            if !(text.is_empty() || text == b"\r" || text.starts_with(b"#")) {
                break;
            }
            start += len + 1;
            line += 1;
        }
        line
    }
}

/// Reads the CSV point list at `path` (see the module documentation).
pub fn load_csv(path: &Path, options: &CsvOptions) -> Result<Outline, OutlineError> {
    let bytes = std::fs::read(path).map_err(|source| OutlineError::Io {
        path: path.to_owned(),
        source,
    })?;
    csv_from_bytes(&bytes, path, options)
}

/// Reads a CSV point list from `bytes`; `path` only names the source in errors.
pub fn csv_from_bytes(
    bytes: &[u8],
    path: &Path,
    options: &CsvOptions,
) -> Result<Outline, OutlineError> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(bytes);
    // The 1-based line where a record starts. The reader's position points
    // before the comment and empty lines it skipped (and its line count
    // ignores comments), so they are skipped forward from the byte offset.
    let mut lines = Lines {
        bytes,
        at: 0,
        line: 1,
    };
    let mut line_of = |pos: Option<&csv::Position>| pos.map_or(0, |p| lines.of(p.byte() as usize));
    let mut points = Vec::new();
    let mut first = true;
    for record in reader.records() {
        let record = record.map_err(|e| {
            OutlineError::Csv(CsvError::Malformed {
                path: path.to_owned(),
                line: line_of(e.position()),
                message: match e.kind() {
                    csv::ErrorKind::Utf8 { .. } => "expected UTF-8 text".to_string(),
                    _ => e.to_string(),
                },
            })
        })?;
        let line = line_of(record.position());
        let bytes = record.as_slice().len() + record.len().saturating_sub(1);
        if bytes > MAX_CSV_LINE_BYTES {
            return Err(OutlineError::Csv(CsvError::Limit {
                path: path.to_owned(),
                line,
                what: "bytes on one line",
                found: bytes,
                limit: MAX_CSV_LINE_BYTES,
            }));
        }
        // A line of only spaces is a record with one empty cell.
        if record.len() == 1 && record[0].is_empty() {
            continue;
        }
        if record.len() != 2 {
            return Err(OutlineError::Csv(CsvError::Fields {
                path: path.to_owned(),
                line,
                found: record.len(),
            }));
        }
        let (x, y) = (number(&record[0]), number(&record[1]));
        if first && x.is_none() && y.is_none() {
            first = false;
            continue; // a header such as "x,y"
        }
        first = false;
        let bad = |column: usize| {
            OutlineError::Csv(CsvError::Number {
                path: path.to_owned(),
                line,
                column,
                text: record[column - 1].to_string(),
            })
        };
        let x = x.ok_or_else(|| bad(1))?;
        let y = y.ok_or_else(|| bad(2))?;
        for (column, v) in [(1, x), (2, y)] {
            if v.abs() > MAX_COORDINATE {
                return Err(OutlineError::Csv(CsvError::Range {
                    path: path.to_owned(),
                    line,
                    column,
                    value: v,
                }));
            }
        }
        if points.len() == MAX_CSV_POINTS {
            return Err(OutlineError::Csv(CsvError::Limit {
                path: path.to_owned(),
                line,
                what: "points",
                found: MAX_CSV_POINTS + 1,
                limit: MAX_CSV_POINTS,
            }));
        }
        points.push(Point::new(x, y));
    }
    outline_from_points(points, options.closed, options.min_points, path)
}

/// The smallest span of an outline relative to its largest coordinate: with
/// less, f64's 53-bit mantissa leaves fewer than about 20 bits for the shape.
pub const MIN_RELATIVE_EXTENT: f64 = 1e-9;

/// The smallest absolute span of an outline: below it squared distances
/// (E = Σ|R_i − P_i|²) fall towards f64's subnormal range (≈ 1e-308).
pub const MIN_EXTENT: f64 = 1e-100;

/// The outline of `points` read from `path` (a file, or a name such as
/// `points` for points given directly): a last point repeating the first is
/// dropped and closes the outline unless `closed` says otherwise; the points
/// must span a measurable extent and number at least `min_points`. The rule
/// the CSV reader applies, for callers that have the points already.
pub fn outline_from_points(
    mut points: Vec<Point>,
    closed: Option<bool>,
    min_points: usize,
    path: &Path,
) -> Result<Outline, OutlineError> {
    let repeats = points.len() > 1 && points.first() == points.last();
    if repeats {
        points.pop();
    }
    let closed = closed.unwrap_or(repeats);
    check_extent(&points, path)?;
    if points.len() < min_points {
        return Err(OutlineError::TooFewPoints {
            path: path.to_owned(),
            found: points.len(),
            need: min_points,
        });
    }
    Ok(Outline::new(points, closed))
}

/// Refuses points whose bounding box is too small for E to be resolved:
/// its diagonal must be at least [`MIN_EXTENT`] and at least
/// [`MIN_RELATIVE_EXTENT`] of the largest coordinate's magnitude. Fewer than
/// two points are left to the point-count check.
fn check_extent(points: &[Point], path: &Path) -> Result<(), OutlineError> {
    if points.len() < 2 {
        return Ok(());
    }
    let Some((lo, hi)) = bounding_box(points) else {
        return Ok(());
    };
    let largest = [lo.x, lo.y, hi.x, hi.y]
        .iter()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let extent = (hi.x - lo.x).hypot(hi.y - lo.y);
    let need = MIN_EXTENT.max(MIN_RELATIVE_EXTENT * largest);
    if extent < need {
        return Err(OutlineError::Csv(CsvError::Extent {
            path: path.to_owned(),
            extent,
            largest,
            need,
        }));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Outline, OutlineError> {
        csv_from_bytes(
            text.as_bytes(),
            Path::new("pts.csv"),
            &CsvOptions::default(),
        )
    }

    #[test]
    fn huge_coordinates_are_refused_with_their_line_after_comments() {
        let mut text = String::from("x,y\n");
        for i in 0..1000 {
            text.push_str(&format!("# note {i}\n{i},1\n\n"));
        }
        text.push_str("3,1e300\n");
        let e = read(&text).unwrap_err().to_string();
        assert_eq!(
            e,
            "pts.csv:3002: column 2 (y): 1e300 is beyond ±1e15, the range of coordinates this tool fits (squared distances must not overflow)"
        );
    }

    #[test]
    fn outlines_too_small_to_resolve_are_refused() {
        let e = read("1e-300,0\n0,1e-300\n-1e-300,0\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("pts.csv: the points span 2.2360679774997897e-300 units"),
            "{e}"
        );
        let e = read("1e6,1e6\n1e6,1.0000000000001e6\n1.0000000000001e6,1e6\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("at coordinates up to 1.0000000000001e6"), "{e}");
        let e = read("2,2\n2,2\n2,2\n2,3\n2,2\n").unwrap();
        assert_eq!(e.points.len(), 4);
        assert!(read("1,1\n1,1\n1,1\n").is_err());
        assert!(read("1e-20,0\n0,1e-20\n-1e-20,0\n").is_ok());
    }

    #[test]
    fn header_comments_and_closing_repeat() {
        let o = read("# a triangle\nx, y\n0,0\n\n 4 , 0\n# apex\n0,3\n0,0\n").unwrap();
        assert!(o.closed);
        assert_eq!(
            o.points,
            vec![Point::ZERO, Point::new(4.0, 0.0), Point::new(0.0, 3.0)]
        );
        let open = read("0,0\n4,0\n0,3\n1e1,-2.5\n").unwrap();
        assert!(!open.closed);
        assert_eq!(open.points[3], Point::new(10.0, -2.5));
        let forced = csv_from_bytes(
            b"0,0\n4,0\n0,3\n",
            Path::new("p.csv"),
            &CsvOptions {
                closed: Some(true),
                ..CsvOptions::default()
            },
        )
        .unwrap();
        assert!(forced.closed);
    }

    #[test]
    fn errors_name_file_line_and_cell() {
        let e = read("x,y\n0,0\n1,zero\n2,2\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "pts.csv:3: column 2 (y): expected a finite number, found \"zero\""
        );
        let e = read("0,0\n1,1\nnan,2\n").unwrap_err();
        assert!(
            matches!(
                e,
                OutlineError::Csv(CsvError::Number {
                    line: 3,
                    column: 1,
                    ..
                })
            ),
            "{e}"
        );
        let e = read("# c\n\n#\n0,0\n1,1\n# c\nnan,2\n").unwrap_err();
        assert!(
            matches!(
                e,
                OutlineError::Csv(CsvError::Number {
                    line: 7,
                    column: 1,
                    ..
                })
            ),
            "{e}"
        );
        let e = read("0,0\n1,1,1\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "pts.csv:2: expected 2 cells \"x,y\", found 3"
        );
        let e = read("0,0\n1,1\n0,0\n").unwrap_err();
        assert_eq!(
            e.to_string(),
            "pts.csv: 2 point(s) found, but an outline needs at least 3"
        );
        let e = csv_from_bytes(b"0,0\n\xff,1\n", Path::new("b.csv"), &CsvOptions::default())
            .unwrap_err();
        assert!(e.to_string().starts_with("b.csv:2: "), "{e}");
    }
}
