//! The Markdown read into blocks and inline pieces.

use std::collections::BTreeMap;

/// The longest link text or destination recognised, in bytes (longer
/// brackets stay text), which keeps hostile input from costing quadratic
/// time.
const MAX_LINK_BYTES: usize = 2000;

/// How a table column is aligned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Align {
    None,
    Left,
    Right,
    Center,
}

/// A block of the Markdown.
#[derive(Debug, PartialEq)]
pub(super) enum Block {
    /// A heading: its level and text.
    Heading(usize, String),
    /// A paragraph, its lines joined by newlines.
    Paragraph(String),
    /// A `-` list: the text of each item.
    List(Vec<String>),
    /// A pipe table: the header, the alignments and the rows (each as wide
    /// as the header).
    Table(Vec<String>, Vec<Align>, Vec<Vec<String>>),
    /// A fenced code block: its lines.
    Code(String),
}

/// The blocks of `md`.
pub(super) fn parse_blocks(md: &str) -> Vec<Block> {
    let lines: Vec<&str> = md.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i];
        if line.trim().is_empty() {
            i += 1;
        } else if let Some(fence) = fence_open(line) {
            let mut code = Vec::new();
            i += 1;
            while i < lines.len() && !fence_closes(lines[i], fence) {
                code.push(lines[i]);
                i += 1;
            }
            i += 1;
            out.push(Block::Code(code.join("\n")));
        } else if let Some((level, text)) = heading(line) {
            out.push(Block::Heading(level, text.to_owned()));
            i += 1;
        } else if let Some((header, align)) = table_start(&lines, i) {
            let mut rows = Vec::new();
            i += 2;
            while i < lines.len() && !lines[i].trim().is_empty() && !starts_block(&lines, i) {
                let mut row = split_row(lines[i]);
                row.resize(header.len(), String::new());
                rows.push(row);
                i += 1;
            }
            out.push(Block::Table(header, align, rows));
        } else if bullet(line).is_some() {
            let mut items: Vec<String> = Vec::new();
            while i < lines.len() {
                let l = lines[i];
                if let Some(item) = bullet(l) {
                    items.push(item.to_owned());
                } else if l.trim().is_empty() {
                    // A blank line ends the list unless an item follows.
                    if lines.get(i + 1).is_none_or(|n| bullet(n).is_none()) {
                        break;
                    }
                } else if starts_block(&lines, i) {
                    break;
                } else if let Some(last) = items.last_mut() {
                    last.push('\n');
                    last.push_str(l.trim());
                }
                i += 1;
            }
            out.push(Block::List(items));
        } else {
            let mut para = vec![line.trim()];
            i += 1;
            while i < lines.len() && !lines[i].trim().is_empty() && !starts_block(&lines, i) {
                para.push(lines[i].trim());
                i += 1;
            }
            out.push(Block::Paragraph(para.join("\n")));
        }
    }
    out
}

/// Whether line `i` starts a block that interrupts a paragraph, a list or
/// a table: a fence, a heading, a list item or a table.
fn starts_block(lines: &[&str], i: usize) -> bool {
    let line = lines[i];
    fence_open(line).is_some()
        || heading(line).is_some()
        || bullet(line).is_some()
        || table_start(lines, i).is_some()
}

/// The fence character and length of a line opening a fenced code block.
fn fence_open(line: &str) -> Option<(u8, usize)> {
    let t = line.trim_start().as_bytes();
    let c = *t.first()?;
    if c != b'`' && c != b'~' {
        return None;
    }
    let n = t.iter().take_while(|&&b| b == c).count();
    // A backtick fence's info string holds no backtick.
    (n >= 3 && (c == b'~' || !t[n..].contains(&b'`'))).then_some((c, n))
}

/// Whether `line` closes a fence opened by `fence`.
fn fence_closes(line: &str, (c, n): (u8, usize)) -> bool {
    let t = line.trim().as_bytes();
    t.len() >= n && t.iter().all(|&b| b == c)
}

/// The level and text of a heading line (`## Text`, closing `#`s dropped).
fn heading(line: &str) -> Option<(usize, &str)> {
    let t = line.trim_start();
    let level = t.bytes().take_while(|&b| b == b'#').count();
    if !(1..=6).contains(&level) {
        return None;
    }
    let rest = &t[level..];
    if !(rest.is_empty() || rest.starts_with(' ') || rest.starts_with('\t')) {
        return None;
    }
    let mut text = rest.trim();
    let stripped = text.trim_end_matches('#');
    if stripped.is_empty() || stripped.ends_with(' ') {
        text = stripped.trim_end();
    }
    Some((level, text))
}

/// The text of a list item line (`- text`, also `*` and `+`).
fn bullet(line: &str) -> Option<&str> {
    let t = line.trim_start();
    if matches!(t, "-" | "*" | "+") {
        return Some("");
    }
    ["- ", "* ", "+ "]
        .iter()
        .find_map(|m| t.strip_prefix(m))
        .map(str::trim)
}

/// The header and alignments of a table starting at line `i`: a row with a
/// pipe, then a separator row of as many cells.
fn table_start(lines: &[&str], i: usize) -> Option<(Vec<String>, Vec<Align>)> {
    let head = lines[i];
    let sep = lines.get(i + 1)?;
    if !head.contains('|') || !sep.contains('-') {
        return None;
    }
    let align: Vec<Align> = split_row(sep)
        .iter()
        .map(|c| {
            let c = c.trim();
            let left = c.starts_with(':');
            let right = c.ends_with(':');
            let dashes = c.trim_start_matches(':').trim_end_matches(':');
            if dashes.is_empty() || !dashes.bytes().all(|b| b == b'-') {
                return None;
            }
            Some(match (left, right) {
                (true, true) => Align::Center,
                (true, false) => Align::Left,
                (false, true) => Align::Right,
                (false, false) => Align::None,
            })
        })
        .collect::<Option<_>>()?;
    let header = split_row(head);
    (!align.is_empty() && header.len() == align.len()).then_some((header, align))
}

/// The cells of a table row, trimmed: split at the pipes that are not
/// escaped (`\|` is a pipe in the cell), without the outer pipes.
fn split_row(line: &str) -> Vec<String> {
    let t = line.trim();
    let t = t.strip_prefix('|').unwrap_or(t);
    let mut cells = Vec::new();
    let mut cell = String::new();
    let mut ended_on_pipe = false;
    let mut chars = t.chars();
    while let Some(c) = chars.next() {
        ended_on_pipe = c == '|';
        match c {
            '\\' => match chars.next() {
                Some('|') => cell.push('|'),
                Some(n) => {
                    cell.push('\\');
                    cell.push(n);
                }
                None => cell.push('\\'),
            },
            '|' => cells.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    if !ended_on_pipe {
        cells.push(cell);
    }
    cells.iter().map(|c| c.trim().to_owned()).collect()
}

/// A piece of inline content.
#[derive(Debug, PartialEq)]
pub(super) enum Tok {
    /// Text, its escapes resolved (escaped again when written).
    Text(String),
    /// A character reference such as `&lt;`, written as it is.
    Entity(String),
    /// A code span.
    Code(String),
    /// `**strong**`.
    Strong(Vec<Tok>),
    /// `*emphasis*`.
    Em(Vec<Tok>),
    /// A link: its text and destination.
    Link(Vec<Tok>, String),
    /// An image: its alternative text and source.
    Image(String, String),
}

/// The inline parser's state: the searches that found nothing, so that a
/// later search from further on is not repeated (no quadratic time on a
/// line of unmatched delimiters).
#[derive(Default)]
struct Scan {
    /// For each length of backtick run, a position from which no run of
    /// that length closes.
    code_fails: BTreeMap<usize, usize>,
    /// For `*` and `**`, a position from which no closing run follows.
    emph_fails: [Option<usize>; 2],
}

/// The inline content of `s`.
pub(super) fn parse_inline(s: &str) -> Vec<Tok> {
    parse_inline_with(s, &mut Scan::default())
}

fn parse_inline_with(s: &str, scan: &mut Scan) -> Vec<Tok> {
    let b = s.as_bytes();
    let mut toks = Vec::new();
    let mut text = String::new();
    let flush = |text: &mut String, toks: &mut Vec<Tok>| {
        if !text.is_empty() {
            toks.push(Tok::Text(std::mem::take(text)));
        }
    };
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'\\' if b.get(i + 1).is_some_and(u8::is_ascii_punctuation) => {
                text.push(char::from(b[i + 1]));
                i += 2;
            }
            b'`' => {
                let n = run_length(b, i, b'`');
                match code_close(b, i + n, n, scan) {
                    Some(close) => {
                        flush(&mut text, &mut toks);
                        toks.push(Tok::Code(code_text(&s[i + n..close])));
                        i = close + n;
                    }
                    None => {
                        text.push_str(&s[i..i + n]);
                        i += n;
                    }
                }
            }
            b'!' if b.get(i + 1) == Some(&b'[') => match link_at(s, i + 1) {
                Some((label, dest, end)) => {
                    flush(&mut text, &mut toks);
                    toks.push(Tok::Image(plain(&parse_inline(label)), dest));
                    i = end;
                }
                None => {
                    text.push('!');
                    i += 1;
                }
            },
            b'[' => match link_at(s, i) {
                Some((label, dest, end)) => {
                    flush(&mut text, &mut toks);
                    toks.push(Tok::Link(parse_inline(label), dest));
                    i = end;
                }
                None => {
                    text.push('[');
                    i += 1;
                }
            },
            b'*' => {
                let n = run_length(b, i, b'*').min(2);
                let opens = b.get(i + n).is_some_and(|c| !c.is_ascii_whitespace());
                match opens.then(|| emph_close(b, i + n, n, scan)).flatten() {
                    Some(close) => {
                        flush(&mut text, &mut toks);
                        let inner = parse_inline_with(&s[i + n..close], &mut Scan::default());
                        toks.push(if n == 2 {
                            Tok::Strong(inner)
                        } else {
                            Tok::Em(inner)
                        });
                        i = close + n;
                    }
                    None => {
                        text.push_str(&s[i..i + n]);
                        i += n;
                    }
                }
            }
            b'&' => match entity_length(&b[i..]) {
                Some(n) => {
                    flush(&mut text, &mut toks);
                    toks.push(Tok::Entity(s[i..i + n].to_owned()));
                    i += n;
                }
                None => {
                    text.push('&');
                    i += 1;
                }
            },
            _ => {
                let Some(ch) = s[i..].chars().next() else {
                    break;
                };
                text.push(ch);
                i += ch.len_utf8();
            }
        }
    }
    flush(&mut text, &mut toks);
    toks
}

/// The length of the run of `c` starting at `i`.
fn run_length(b: &[u8], i: usize, c: u8) -> usize {
    b[i..].iter().take_while(|&&x| x == c).count()
}

/// Where a run of exactly `n` backticks starts at or after `from`.
fn code_close(b: &[u8], from: usize, n: usize, scan: &mut Scan) -> Option<usize> {
    if scan.code_fails.get(&n).is_some_and(|&f| from >= f) {
        return None;
    }
    let mut j = from;
    while j < b.len() {
        if b[j] == b'`' {
            let m = run_length(b, j, b'`');
            if m == n {
                return Some(j);
            }
            j += m;
        } else {
            j += 1;
        }
    }
    scan.code_fails.insert(n, from);
    None
}

/// A code span's text: line breaks as spaces, one space stripped from
/// each end when both ends have one.
fn code_text(raw: &str) -> String {
    let t = raw.replace(['\n', '\r'], " ");
    if t.len() >= 2 && t.starts_with(' ') && t.ends_with(' ') && !t.trim().is_empty() {
        t[1..t.len() - 1].to_owned()
    } else {
        t
    }
}

/// Where the `*` (`n` = 1) or `**` (`n` = 2) closing the one opened before
/// `from` starts: after a non-space, outside code spans and escapes; a
/// `**` inside `*…*` is skipped whole.
fn emph_close(b: &[u8], from: usize, n: usize, scan: &mut Scan) -> Option<usize> {
    if scan.emph_fails[n - 1].is_some_and(|f| from >= f) {
        return None;
    }
    let mut j = from;
    while j < b.len() {
        match b[j] {
            b'\\' => j += 2,
            b'`' => {
                let m = run_length(b, j, b'`');
                j = code_close(b, j + m, m, scan).map_or(j + m, |c| c + m);
            }
            b'*' => {
                let m = run_length(b, j, b'*');
                let after_text = j > from && !b[j - 1].is_ascii_whitespace();
                if after_text && m == n {
                    return Some(j);
                }
                if after_text && n == 2 && m > 2 {
                    // `***`: the inner `*` closes first, then the `**`.
                    return Some(j + m - 2);
                }
                if n == 1 && m >= 2 {
                    // A strong span inside the emphasis.
                    j = emph_close(b, j + 2, 2, scan).map_or(j + m, |c| c + 2);
                } else {
                    j += m;
                }
            }
            _ => j += 1,
        }
    }
    scan.emph_fails[n - 1] = Some(from);
    None
}

/// The length of a character reference at the start of `b` (`&lt;`,
/// `&#8722;`, `&#x2212;`).
fn entity_length(b: &[u8]) -> Option<usize> {
    let body = &b[1..];
    let (digits, start) = match (body.first(), body.get(1)) {
        (Some(b'#'), Some(b'x' | b'X')) => (6, 2),
        (Some(b'#'), _) => (7, 1),
        _ => (32, 0),
    };
    let name: Vec<u8> = body[start..]
        .iter()
        .copied()
        .take_while(u8::is_ascii_alphanumeric)
        .take(digits + 1)
        .collect();
    let valid = match start {
        2 => name.iter().all(u8::is_ascii_hexdigit),
        1 => name.iter().all(u8::is_ascii_digit),
        _ => name.first().is_some_and(u8::is_ascii_alphabetic),
    };
    (valid
        && !name.is_empty()
        && name.len() <= digits
        && body.get(start + name.len()) == Some(&b';'))
    .then_some(1 + start + name.len() + 1)
}

/// The label, destination and end of a link `[label](dest)` whose `[` is
/// at `i`.
fn link_at(s: &str, i: usize) -> Option<(&str, String, usize)> {
    let b = s.as_bytes();
    let mut depth = 0usize;
    let mut j = i;
    let close = loop {
        if j >= b.len() || j - i > MAX_LINK_BYTES {
            return None;
        }
        match b[j] {
            b'\\' => j += 1,
            b'[' => depth += 1,
            b']' => {
                depth -= 1;
                if depth == 0 {
                    break j;
                }
            }
            _ => {}
        }
        j += 1;
    };
    if b.get(close + 1) != Some(&b'(') {
        return None;
    }
    let mut k = close + 2;
    while b.get(k) == Some(&b' ') {
        k += 1;
    }
    let mut dest = String::new();
    if b.get(k) == Some(&b'<') {
        let end = k + 1 + s.get(k + 1..)?.find('>')?;
        dest.push_str(&s[k + 1..end]);
        k = end + 1;
    } else {
        let mut parens = 0usize;
        let start = k;
        while let Some(&c) = b.get(k) {
            match c {
                b'\\' if b.get(k + 1).is_some_and(u8::is_ascii_punctuation) => k += 1,
                b'(' => parens += 1,
                b')' if parens == 0 => break,
                b')' => parens -= 1,
                c if c.is_ascii_whitespace() => break,
                _ => {}
            }
            k += 1;
            if k - start > MAX_LINK_BYTES {
                return None;
            }
        }
        dest.push_str(&unescape(s.get(start..k)?));
    }
    while b.get(k) == Some(&b' ') {
        k += 1;
    }
    if b.get(k) == Some(&b'"') {
        k += 1 + s.get(k + 1..)?.find('"')? + 1;
        while b.get(k) == Some(&b' ') {
            k += 1;
        }
    }
    (b.get(k) == Some(&b')')).then(|| (&s[i + 1..close], dest, k + 1))
}

/// `s` with its backslash escapes resolved.
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, chars.peek()) {
            ('\\', Some(&n)) if n.is_ascii_punctuation() => {
                out.push(n);
                chars.next();
            }
            (c, _) => out.push(c),
        }
    }
    out
}

/// The plain text of inline content (for alternative texts, titles and
/// anchors), with the common character references decoded.
pub(super) fn plain(toks: &[Tok]) -> String {
    let mut out = String::new();
    for t in toks {
        match t {
            Tok::Text(s) | Tok::Code(s) => out.push_str(s),
            Tok::Entity(e) => out.push_str(match e.as_str() {
                "&lt;" => "<",
                "&gt;" => ">",
                "&amp;" => "&",
                "&quot;" => "\"",
                e => e,
            }),
            Tok::Strong(inner) | Tok::Em(inner) | Tok::Link(inner, _) => {
                out.push_str(&plain(inner))
            }
            Tok::Image(alt, _) => out.push_str(alt),
        }
    }
    out.replace('\n', " ")
}

/// Every image source of `toks`, in order.
pub(super) fn images<'t>(toks: &'t [Tok], out: &mut Vec<&'t str>) {
    for t in toks {
        match t {
            Tok::Image(_, src) => out.push(src),
            Tok::Strong(inner) | Tok::Em(inner) | Tok::Link(inner, _) => images(inner, out),
            _ => {}
        }
    }
}
