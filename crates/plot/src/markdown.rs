//! Markdown tables (GitHub-flavoured) for every report the crate writes:
//! the campaign reports and the chapter-6 implant report.
//!
//! [`html`] turns such a report into one self-contained HTML page.
//!
//! A leaf of the crate: it imports nothing of it.

pub mod html;

/// How the columns of a [`table`] are aligned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Alignment {
    /// The first column and text columns left (`:--`), number columns
    /// right (`--:`).
    ByContent,
    /// No alignment marks (`---`): the renderer's default.
    Unmarked,
}

/// A Markdown table: the header, an alignment row, and the rows, each cell
/// escaped with [`escape`] and each row padded with empty cells to the
/// header's width; ends in a newline.
pub fn table(header: &[String], rows: &[Vec<String>], alignment: Alignment) -> String {
    let line = |cells: &[String]| -> String {
        let mut l = String::from("|");
        for c in cells {
            l.push(' ');
            l.push_str(&escape(c));
            l.push_str(" |");
        }
        l.push('\n');
        l
    };
    let mut s = line(header);
    s.push('|');
    for i in 0..header.len() {
        s.push_str(match alignment {
            Alignment::Unmarked => "---|",
            Alignment::ByContent if i == 0 || is_text_column(rows, i) => " :-- |",
            Alignment::ByContent => " --: |",
        });
    }
    s.push('\n');
    for row in rows {
        let mut cells = row.clone();
        cells.resize(header.len(), String::new());
        s.push_str(&line(&cells));
    }
    s
}

/// Whether column `i` holds text (left-aligned) rather than numbers: most
/// of its non-empty cells start with a letter and are not `inf`, `NaN` or
/// `n/a`.
fn is_text_column(rows: &[Vec<String>], i: usize) -> bool {
    let (mut text, mut filled) = (0usize, 0usize);
    for cell in rows.iter().filter_map(|r| r.get(i)) {
        let c = cell.trim();
        if c.is_empty() {
            continue;
        }
        filled += 1;
        let letter = c
            .chars()
            .next()
            .is_some_and(|ch| ch.is_alphabetic() || ch == '`');
        if letter && !matches!(c, "inf" | "NaN" | "n/a") && !c.starts_with("n/a ") {
            text += 1;
        }
    }
    filled > 0 && 2 * text >= filled
}

/// Escapes text for Markdown: pipes, backslashes, asterisks and angle
/// brackets; line breaks and tabs become spaces.
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '|' => out.push_str("\\|"),
            '\\' => out.push_str("\\\\"),
            '\n' | '\r' | '\t' => out.push(' '),
            '*' => out.push_str("\\*"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            c => out.push(c),
        }
    }
    out
}

/// An integer with commas between thousands: `108,000,000`.
pub fn thousands(n: u128) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, d) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(d);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_and_pads() {
        let t = table(
            &["a".into(), "b".into()],
            &[vec!["x|y".into()], vec!["1".into(), "2".into()]],
            Alignment::ByContent,
        );
        assert_eq!(t, "| a | b |\n| :-- | --: |\n| x\\|y |  |\n| 1 | 2 |\n");
        let t = table(
            &["n".into(), "name".into(), "value".into()],
            &[
                vec!["1".into(), "HS".into(), "inf".into()],
                vec!["2".into(), "PSO".into(), "1.0e-03".into()],
            ],
            Alignment::ByContent,
        );
        assert!(t.contains("| :-- | :-- | --: |"), "{t}");
    }

    #[test]
    fn thousands_separators() {
        assert_eq!(thousands(7), "7");
        assert_eq!(thousands(2000), "2,000");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(108_000_000), "108,000,000");
    }

    #[test]
    fn unmarked_columns() {
        let t = table(
            &["z".into(), "width mm".into()],
            &[vec!["56".into(), "15.8".into()]],
            Alignment::Unmarked,
        );
        assert_eq!(t, "| z | width mm |\n|---|---|\n| 56 | 15.8 |\n");
    }
}
