//! The formatting half of writing result files: reals in shortest
//! round-trip form and CSV bytes (RFC 4180), computed in memory. The
//! writing half (atomic writes, the I/O error that names its file) is the
//! `metabezier-files` crate, which re-exports them. And the excerpt of a
//! cell an error quotes when it reads such a file back.
//!
//! A leaf of the crate: it imports nothing of it, so every room may use it.

/// A real in shortest round-trip form: plain notation for magnitudes in
/// `[1e-4, 1e16)` and zero, scientific notation otherwise, so that reading
/// it back gives the same bits.
pub fn fmt_real(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-4..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// CSV bytes (RFC 4180 quoting) of a header and rows; rows may differ in
/// length from the header.
pub fn csv_bytes<H, R, I>(header: &[H], rows: I) -> Vec<u8>
where
    H: AsRef<[u8]>,
    R: IntoIterator,
    R::Item: AsRef<[u8]>,
    I: IntoIterator<Item = R>,
{
    let mut w = csv::WriterBuilder::new()
        .flexible(true)
        .from_writer(Vec::new());
    // Writing to memory cannot fail, and a flexible writer accepts any row.
    w.write_record(header).expect("writing to memory");
    for row in rows {
        w.write_record(row).expect("writing to memory");
    }
    w.into_inner().expect("writing to memory")
}

/// A cell's text as an error quotes it: at most 40 characters, control
/// characters escaped, `…` where cut. Only a cell of a file known to be of
/// its format (its header read) is quoted at all: the first line of a file
/// that is not may be anything (`/etc/passwd` through a link, say).
pub fn excerpt(text: &str) -> String {
    const MAX: usize = 40;
    let mut out: String = text
        .chars()
        .take(MAX)
        .flat_map(char::escape_debug)
        .collect();
    if text.chars().nth(MAX).is_some() {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_round_trip() {
        for x in [
            0.0,
            -0.0,
            0.1 + 0.2,
            1e-5,
            1e-300,
            5e-324,
            f64::MAX,
            123456.789,
            f64::INFINITY,
        ] {
            assert_eq!(fmt_real(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
        }
        assert_eq!(fmt_real(1e-5), "1e-5");
        assert_eq!(fmt_real(0.25), "0.25");
        assert_eq!(fmt_real(2.5e-7), "2.5e-7");
    }

    #[test]
    fn csv_quotes_and_allows_ragged_rows() {
        let bytes = csv_bytes(&["a", "b"], [vec!["1,5", "x"], vec!["2"]]);
        assert_eq!(String::from_utf8(bytes).unwrap(), "a,b\n\"1,5\",x\n2\n");
    }

    #[test]
    fn quoted_cells_are_cut_and_escaped() {
        assert_eq!(excerpt("1.5e"), "1.5e");
        assert_eq!(excerpt("a\u{7}b"), "a\\u{7}b");
        let long = "x".repeat(100);
        assert_eq!(excerpt(&long), format!("{}…", "x".repeat(40)));
    }
}
