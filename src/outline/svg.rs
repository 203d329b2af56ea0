//! The paths of an SVG file as Bézier segments, for scoring curves that
//! other tools (potrace, FontForge, Inkscape) produced.
//!
//! Read: every `<path d="…">` element; the path commands `M L H V C S Q T Z`,
//! absolute and relative, with implicit repetition (SVG 1.1, §8.3); the
//! `transform` attributes `translate`, `scale` and `matrix` on `<g>` and
//! `<path>` elements (composed down the element tree, as potrace writes
//! them); and the `viewBox` (or `height`) of the root `<svg>`. Elliptical
//! arcs (`A`) and other transforms are refused with their place.
//!
//! **Frame.** SVG user space has y pointing down. [`SvgPaths::to_frame`]
//! reflects it about the horizontal mid-line of the `viewBox` (so a point at
//! the bottom edge of the view gets the view's smallest y), or about
//! `height/2` without a `viewBox`, or about 0 without either, then adds an
//! offset: the y-up frame of the outlines, where image pixel centres are at
//! integer coordinates. potrace puts pixel *corners* at integers, so its
//! output needs the offset `(−0.5, −0.5)`.
//!
//! Errors name the file, the line and column, what was found and what was
//! expected.

use std::path::{Path, PathBuf};

use super::glyph::Segment;
use crate::geometry::{CubicBez, Point, QuadBez};

/// Why the paths of an SVG file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum SvgError {
    /// The file could not be read.
    #[error("{}: cannot read: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// No `<path>` element with a `d` attribute.
    #[error("{}: no <path> element with a \"d\" attribute; expected an SVG file with at least one path", path.display())]
    NoPath {
        /// The file.
        path: PathBuf,
    },
    /// Something unreadable at a place in the file.
    #[error("{}:{line}:{column}: {problem}", path.display())]
    At {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// What is wrong there.
        problem: SvgProblem,
    },
}

/// What is wrong at a place in an SVG file.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SvgProblem {
    /// A path command this reader does not support.
    #[error("unsupported path command '{0}'; supported: M, L, H, V, C, S, Q, T, Z (absolute and relative)")]
    Command(char),
    /// A number was expected.
    #[error("expected a number, found \"{0}\"")]
    Number(String),
    /// A number is not finite (such as 1e999).
    #[error("the number \"{0}\" is not finite")]
    NonFinite(String),
    /// Path data must start with a move-to.
    #[error("path data must start with M or m, found \"{0}\"")]
    NoMoveTo(String),
    /// A transform this reader does not support.
    #[error("unsupported transform \"{0}\"; supported: translate(x [y]), scale(x [y]), matrix(a b c d e f)")]
    Transform(String),
    /// A tag or attribute is not closed.
    #[error("unterminated {0}")]
    Unterminated(&'static str),
}

/// An affine map `(x, y) ↦ (a x + c y + e, b x + d y + f)` (SVG's matrix).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Affine([f64; 6]);

impl Affine {
    const IDENTITY: Affine = Affine([1.0, 0.0, 0.0, 1.0, 0.0, 0.0]);

    /// `self ∘ other`: apply `other` first.
    fn then(self, other: Affine) -> Affine {
        let [a, b, c, d, e, f] = self.0;
        let [p, q, r, s, t, u] = other.0;
        Affine([
            a * p + c * q,
            b * p + d * q,
            a * r + c * s,
            b * r + d * s,
            a * t + c * u + e,
            b * t + d * u + f,
        ])
    }

    fn apply(self, p: Point) -> Point {
        let [a, b, c, d, e, f] = self.0;
        Point::new(a * p.x + c * p.y + e, b * p.x + d * p.y + f)
    }
}

/// The paths of an SVG file, in user space (y down), transforms applied.
#[derive(Clone, Debug, PartialEq)]
pub struct SvgPaths {
    /// The file.
    pub path: PathBuf,
    /// Every subpath, as its segments.
    pub subpaths: Vec<Vec<Segment>>,
    /// The root `viewBox` `(min_x, min_y, width, height)`, if any.
    pub view_box: Option<[f64; 4]>,
    /// The root `height` in user units (units such as `pt` dropped), if any.
    pub height: Option<f64>,
}

impl SvgPaths {
    /// The number of segments (lines and curves; a closing `Z` counts when
    /// it draws a line of non-zero length).
    pub fn segment_count(&self) -> usize {
        self.subpaths.iter().map(Vec::len).sum()
    }

    /// The subpaths in the y-up frame of the outlines: reflected about the
    /// view's horizontal mid-line (see the module docs), then moved by
    /// `offset`.
    pub fn to_frame(&self, offset: Point) -> Vec<Vec<Segment>> {
        let axis = match (self.view_box, self.height) {
            (Some([_, min_y, _, h]), _) => 2.0 * min_y + h,
            (None, Some(h)) => h,
            (None, None) => 0.0,
        };
        let map = |p: Point| Point::new(p.x + offset.x, axis - p.y + offset.y);
        self.subpaths
            .iter()
            .map(|sub| sub.iter().map(|s| map_segment(s, map)).collect())
            .collect()
    }
}

/// `s` with every control point mapped by `f` (exact for affine maps).
fn map_segment(s: &Segment, f: impl Fn(Point) -> Point) -> Segment {
    match *s {
        Segment::Line(a, b) => Segment::Line(f(a), f(b)),
        Segment::Quad(q) => Segment::Quad(QuadBez::new(f(q.p0), f(q.p1), f(q.p2))),
        Segment::Cubic(c) => Segment::Cubic(CubicBez::new(f(c.p0), f(c.p1), f(c.p2), f(c.p3))),
    }
}

/// Reads the paths of the SVG file at `path`.
pub fn load_svg(path: &Path) -> Result<SvgPaths, SvgError> {
    let text = std::fs::read_to_string(path).map_err(|source| SvgError::Io {
        path: path.to_owned(),
        source,
    })?;
    svg_from_str(&text, path)
}

/// One tag of the document: its name (`g`, `/g`, `path`, …), its
/// attributes with the byte offset of each value, and whether it closes
/// itself.
struct Tag<'t> {
    name: &'t str,
    attributes: Vec<Attribute<'t>>,
    self_closing: bool,
}

/// Reads the paths of SVG `text`; `path` names the file in errors.
pub fn svg_from_str(text: &str, path: &Path) -> Result<SvgPaths, SvgError> {
    let at = |offset: usize, problem: SvgProblem| {
        let before = &text[..offset.min(text.len())];
        let line = before.matches('\n').count() + 1;
        let start = before.rfind('\n').map_or(0, |i| i + 1);
        SvgError::At {
            path: path.to_owned(),
            line,
            column: text[start..offset.min(text.len())].chars().count() + 1,
            problem,
        }
    };
    let mut out = SvgPaths {
        path: path.to_owned(),
        subpaths: Vec::new(),
        view_box: None,
        height: None,
    };
    let mut stack: Vec<Affine> = vec![Affine::IDENTITY];
    let mut found = false;
    let mut pos = 0;
    while let Some(rel) = text[pos..].find('<') {
        let start = pos + rel;
        let (tag, end) = next_tag(text, start).map_err(|(o, p)| at(o, p))?;
        pos = end;
        let Some(tag) = tag else { continue };
        let current = *stack.last().unwrap_or(&Affine::IDENTITY);
        let local = match tag.attributes.iter().find(|(k, _, _)| *k == "transform") {
            Some((_, v, o)) => parse_transform(v).map_err(|(i, p)| at(o + i, p))?,
            None => Affine::IDENTITY,
        };
        match tag.name {
            "svg" if out.view_box.is_none() && out.height.is_none() => {
                root_view(&tag, &mut out).map_err(|(o, p)| at(o, p))?;
                stack.push(current.then(local));
            }
            "path" => {
                if let Some((_, d, o)) = tag.attributes.iter().find(|(k, _, _)| *k == "d") {
                    let m = current.then(local);
                    let subs = parse_path(d).map_err(|(i, p)| at(o + i, p))?;
                    for sub in subs {
                        out.subpaths
                            .push(sub.iter().map(|s| map_segment(s, |p| m.apply(p))).collect());
                    }
                    found = true;
                }
                if !tag.self_closing {
                    stack.push(current);
                }
            }
            name if name.starts_with('/') && stack.len() > 1 => {
                stack.pop();
            }
            name if name.starts_with('/') => {}
            _ if !tag.self_closing => stack.push(current.then(local)),
            _ => {}
        }
    }
    if !found {
        return Err(SvgError::NoPath {
            path: path.to_owned(),
        });
    }
    Ok(out)
}

/// The root's `viewBox` and `height`.
fn root_view(tag: &Tag<'_>, out: &mut SvgPaths) -> Result<(), (usize, SvgProblem)> {
    for (k, v, o) in &tag.attributes {
        match *k {
            "viewBox" => {
                let nums = numbers(v).map_err(|(i, p)| (o + i, p))?;
                if nums.len() != 4 {
                    return Err((*o, SvgProblem::Number((*v).to_owned())));
                }
                out.view_box = Some([nums[0], nums[1], nums[2], nums[3]]);
            }
            "height" => {
                let digits = v.trim_end_matches(|c: char| c.is_ascii_alphabetic() || c == '%');
                out.height = digits.trim().parse().ok().filter(|h: &f64| h.is_finite());
            }
            _ => {}
        }
    }
    Ok(())
}

/// The tag starting at byte `start` (a `<`) and the offset after it;
/// comments, declarations and processing instructions give `None`.
fn next_tag(text: &str, start: usize) -> Result<(Option<Tag<'_>>, usize), (usize, SvgProblem)> {
    let rest = &text[start..];
    for (open, close, what) in [
        ("<!--", "-->", "comment"),
        ("<![CDATA[", "]]>", "CDATA section"),
        ("<?", "?>", "processing instruction"),
        ("<!", ">", "declaration"),
    ] {
        if rest.starts_with(open) {
            let end = rest
                .find(close)
                .ok_or((start, SvgProblem::Unterminated(what)))?;
            return Ok((None, start + end + close.len()));
        }
    }
    let bytes = text.as_bytes();
    let mut i = start + 1;
    let name_start = i;
    while i < bytes.len() && !bytes[i].is_ascii_whitespace() && bytes[i] != b'>' && bytes[i] != b'/'
        || (i == name_start && i < bytes.len() && bytes[i] == b'/')
    {
        i += 1;
    }
    let name = &text[name_start..i];
    let mut attributes = Vec::new();
    loop {
        while i < bytes.len() && bytes[i].is_ascii_whitespace() {
            i += 1;
        }
        match bytes.get(i) {
            None => return Err((start, SvgProblem::Unterminated("tag"))),
            Some(b'>') => {
                let tag = Tag {
                    name,
                    attributes,
                    self_closing: false,
                };
                return Ok((Some(tag), i + 1));
            }
            Some(b'/') if bytes.get(i + 1) == Some(&b'>') => {
                let tag = Tag {
                    name,
                    attributes,
                    self_closing: true,
                };
                return Ok((Some(tag), i + 2));
            }
            _ => {}
        }
        let (attribute, next) = attribute(text, i)?;
        attributes.push(attribute);
        i = next;
    }
}

/// The attribute `key="value"` at byte `i`: the key, the value, the
/// value's byte offset, and the offset after it.
type Attribute<'t> = (&'t str, &'t str, usize);

fn attribute(text: &str, mut i: usize) -> Result<(Attribute<'_>, usize), (usize, SvgProblem)> {
    let bytes = text.as_bytes();
    let key_start = i;
    while i < bytes.len() && bytes[i] != b'=' && !bytes[i].is_ascii_whitespace() && bytes[i] != b'>'
    {
        i += 1;
    }
    let key = &text[key_start..i];
    while i < bytes.len() && (bytes[i].is_ascii_whitespace() || bytes[i] == b'=') {
        i += 1;
    }
    let quote = *bytes
        .get(i)
        .ok_or((key_start, SvgProblem::Unterminated("attribute")))?;
    if quote != b'"' && quote != b'\'' {
        return Err((
            i,
            SvgProblem::Unterminated("attribute value (expected a quote)"),
        ));
    }
    let value_start = i + 1;
    let len = text[value_start..]
        .find(quote as char)
        .ok_or((key_start, SvgProblem::Unterminated("attribute value")))?;
    let value = &text[value_start..value_start + len];
    Ok(((key, value, value_start), value_start + len + 1))
}

/// A `transform` list: `translate`, `scale` and `matrix`, composed left to
/// right; errors carry the byte offset within `text`.
fn parse_transform(text: &str) -> Result<Affine, (usize, SvgProblem)> {
    let mut m = Affine::IDENTITY;
    let mut rest = text;
    let mut offset = 0;
    loop {
        let trimmed = rest.trim_start_matches(|c: char| c.is_whitespace() || c == ',');
        offset += rest.len() - trimmed.len();
        rest = trimmed;
        if rest.is_empty() {
            return Ok(m);
        }
        let open = rest.find('(');
        let close = rest.find(')');
        let (Some(open), Some(close)) = (open, close) else {
            return Err((offset, SvgProblem::Transform(rest.to_owned())));
        };
        let name = rest[..open].trim();
        let args = numbers(&rest[open + 1..close]).map_err(|(i, p)| (offset + open + 1 + i, p))?;
        let t = match (name, args.as_slice()) {
            ("translate", [x]) => Affine([1.0, 0.0, 0.0, 1.0, *x, 0.0]),
            ("translate", [x, y]) => Affine([1.0, 0.0, 0.0, 1.0, *x, *y]),
            ("scale", [s]) => Affine([*s, 0.0, 0.0, *s, 0.0, 0.0]),
            ("scale", [x, y]) => Affine([*x, 0.0, 0.0, *y, 0.0, 0.0]),
            ("matrix", [a, b, c, d, e, f]) => Affine([*a, *b, *c, *d, *e, *f]),
            _ => return Err((offset, SvgProblem::Transform(rest[..=close].to_owned()))),
        };
        m = m.then(t);
        offset += close + 1;
        rest = &rest[close + 1..];
    }
}

/// The numbers of a list separated by spaces or commas; errors carry the
/// byte offset within `text`.
fn numbers(text: &str) -> Result<Vec<f64>, (usize, SvgProblem)> {
    let mut lexer = Lexer { text, at: 0 };
    let mut out = Vec::new();
    while lexer.skip_separators() {
        out.push(lexer.number()?);
    }
    Ok(out)
}

/// A cursor over path data.
struct Lexer<'t> {
    text: &'t str,
    at: usize,
}

impl Lexer<'_> {
    /// Skips whitespace and commas; whether anything is left.
    fn skip_separators(&mut self) -> bool {
        let b = self.text.as_bytes();
        while self.at < b.len() && (b[self.at].is_ascii_whitespace() || b[self.at] == b',') {
            self.at += 1;
        }
        self.at < b.len()
    }

    /// The next non-separator byte, without consuming it.
    fn peek(&mut self) -> Option<u8> {
        self.skip_separators()
            .then(|| self.text.as_bytes()[self.at])
    }

    /// Whether a number starts here.
    fn at_number(&mut self) -> bool {
        matches!(self.peek(), Some(b'0'..=b'9' | b'.' | b'-' | b'+'))
    }

    /// The number here: sign, digits, fraction, exponent.
    fn number(&mut self) -> Result<f64, (usize, SvgProblem)> {
        self.skip_separators();
        let b = self.text.as_bytes();
        let start = self.at;
        let mut i = start;
        if i < b.len() && (b[i] == b'-' || b[i] == b'+') {
            i += 1;
        }
        let mut seen_dot = false;
        while i < b.len() && (b[i].is_ascii_digit() || (b[i] == b'.' && !seen_dot)) {
            seen_dot |= b[i] == b'.';
            i += 1;
        }
        if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
            let mut j = i + 1;
            if j < b.len() && (b[j] == b'-' || b[j] == b'+') {
                j += 1;
            }
            if j < b.len() && b[j].is_ascii_digit() {
                i = j;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
        }
        let word_end = self.text[start..]
            .find(|c: char| c.is_whitespace() || c == ',')
            .map_or(self.text.len(), |k| start + k);
        let token = &self.text[start..i];
        let value: f64 = token.parse().map_err(|_| {
            (
                start,
                SvgProblem::Number(
                    self.text[start..word_end.max(start + 1).min(self.text.len())].to_owned(),
                ),
            )
        })?;
        if !value.is_finite() {
            return Err((start, SvgProblem::NonFinite(token.to_owned())));
        }
        self.at = i;
        Ok(value)
    }

    /// A point `x y`, relative to `origin` when `relative`.
    fn point(&mut self, relative: bool, origin: Point) -> Result<Point, (usize, SvgProblem)> {
        let p = Point::new(self.number()?, self.number()?);
        Ok(if relative { origin + p } else { p })
    }
}

/// The pen of a path: where it is, where the subpath started, and the
/// control point a smooth `S` or `T` reflects.
struct Pen {
    at: Point,
    start: Point,
    cubic_ctrl: Option<Point>,
    quad_ctrl: Option<Point>,
}

/// The subpaths of path data `d`; errors carry the byte offset within `d`.
fn parse_path(d: &str) -> Result<Vec<Vec<Segment>>, (usize, SvgProblem)> {
    let mut lexer = Lexer { text: d, at: 0 };
    let mut subpaths: Vec<Vec<Segment>> = Vec::new();
    let mut current: Vec<Segment> = Vec::new();
    let mut pen = Pen {
        at: Point::ZERO,
        start: Point::ZERO,
        cubic_ctrl: None,
        quad_ctrl: None,
    };
    let mut command: Option<u8> = None;
    while let Some(c) = lexer.peek() {
        let cmd = if c.is_ascii_alphabetic() {
            lexer.at += 1;
            c
        } else {
            match command {
                // After a move-to, further pairs are line-tos.
                Some(b'M') => b'L',
                Some(b'm') => b'l',
                Some(k) if k != b'Z' && k != b'z' => k,
                _ => {
                    return Err((
                        lexer.at,
                        SvgProblem::NoMoveTo(d[lexer.at..].chars().take(12).collect()),
                    ))
                }
            }
        };
        if command.is_none() && cmd != b'M' && cmd != b'm' {
            return Err((
                lexer.at - 1,
                SvgProblem::NoMoveTo((cmd as char).to_string()),
            ));
        }
        let at = lexer.at.saturating_sub(1);
        step(&mut lexer, cmd, &mut pen, &mut current, &mut subpaths).map_err(|e| match e.1 {
            SvgProblem::Command(_) => (at, e.1),
            _ => e,
        })?;
        command = Some(cmd);
        if cmd.eq_ignore_ascii_case(&b'z') && lexer.at_number() {
            return Err((
                lexer.at,
                SvgProblem::NoMoveTo(d[lexer.at..].chars().take(12).collect()),
            ));
        }
    }
    if !current.is_empty() {
        subpaths.push(current);
    }
    Ok(subpaths)
}

/// Executes one path command at the lexer (its arguments follow).
fn step(
    lexer: &mut Lexer<'_>,
    cmd: u8,
    pen: &mut Pen,
    current: &mut Vec<Segment>,
    subpaths: &mut Vec<Vec<Segment>>,
) -> Result<(), (usize, SvgProblem)> {
    let rel = cmd.is_ascii_lowercase();
    let here = pen.at;
    let (mut cubic_ctrl, mut quad_ctrl) = (None, None);
    match cmd.to_ascii_uppercase() {
        b'M' => {
            if !current.is_empty() {
                subpaths.push(std::mem::take(current));
            }
            pen.at = lexer.point(rel, here)?;
            pen.start = pen.at;
        }
        b'L' => {
            let p = lexer.point(rel, here)?;
            current.push(Segment::Line(here, p));
            pen.at = p;
        }
        b'H' => {
            let x = lexer.number()?;
            let p = Point::new(if rel { here.x + x } else { x }, here.y);
            current.push(Segment::Line(here, p));
            pen.at = p;
        }
        b'V' => {
            let y = lexer.number()?;
            let p = Point::new(here.x, if rel { here.y + y } else { y });
            current.push(Segment::Line(here, p));
            pen.at = p;
        }
        b'C' | b'S' => {
            let c1 = if cmd.eq_ignore_ascii_case(&b'c') {
                lexer.point(rel, here)?
            } else {
                pen.cubic_ctrl.map_or(here, |c| here * 2.0 - c)
            };
            let c2 = lexer.point(rel, here)?;
            let p = lexer.point(rel, here)?;
            current.push(Segment::Cubic(CubicBez::new(here, c1, c2, p)));
            cubic_ctrl = Some(c2);
            pen.at = p;
        }
        b'Q' | b'T' => {
            let c1 = if cmd.eq_ignore_ascii_case(&b'q') {
                lexer.point(rel, here)?
            } else {
                pen.quad_ctrl.map_or(here, |c| here * 2.0 - c)
            };
            let p = lexer.point(rel, here)?;
            current.push(Segment::Quad(QuadBez::new(here, c1, p)));
            quad_ctrl = Some(c1);
            pen.at = p;
        }
        b'Z' => {
            if here != pen.start {
                current.push(Segment::Line(here, pen.start));
            }
            pen.at = pen.start;
            if !current.is_empty() {
                subpaths.push(std::mem::take(current));
            }
        }
        _ => return Err((lexer.at, SvgProblem::Command(cmd as char))),
    }
    pen.cubic_ctrl = cubic_ctrl;
    pen.quad_ctrl = quad_ctrl;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(d: &str) -> Vec<Vec<Segment>> {
        parse_path(d).unwrap()
    }

    #[test]
    fn absolute_and_relative_commands_agree() {
        let a =
            parse("M 0 0 L 10 0 H 20 V 10 C 20 20 10 20 10 10 S 0 0 0 10 Q 5 15 10 10 T 20 10 Z");
        let b = parse("m0,0 l10,0 h10 v10 c0,10 -10,10 -10,0 s-10,-10 -10,0 q5,5 10,0 t10,0 z");
        assert_eq!(a, b);
        let segs = &a[0];
        assert_eq!(segs.len(), 8);
        // S reflects the previous cubic's second control point.
        let Segment::Cubic(s) = segs[4] else { panic!() };
        assert_eq!(s.p1, Point::new(10.0, 0.0));
        // T reflects the previous quadratic's control point.
        let Segment::Quad(t) = segs[6] else { panic!() };
        assert_eq!(t.p1, Point::new(15.0, 5.0));
        // Z draws the closing line back to the start.
        assert_eq!(segs[7], Segment::Line(Point::new(20.0, 10.0), Point::ZERO));
    }

    #[test]
    fn implicit_repetition_and_compact_numbers() {
        let a = parse("M0 0 10 0 10-10-.5.5e1z");
        assert_eq!(a[0].len(), 4);
        assert_eq!(
            a[0][2],
            Segment::Line(Point::new(10.0, -10.0), Point::new(-0.5, 5.0))
        );
    }

    #[test]
    fn transforms_compose_down_the_tree() {
        let svg = r##"<?xml version="1.0"?>
<!-- potrace style -->
<svg xmlns="http://www.w3.org/2000/svg" width="10pt" height="8pt" viewBox="0 0 10 8">
<g transform="translate(0,8) scale(0.1,-0.1)" fill="#000">
<path d="M10 20 l30 0 0 40 z"/>
</g>
<path d="M 1 1 L 2 1"/>
</svg>"##;
        let p = svg_from_str(svg, Path::new("t.svg")).unwrap();
        assert_eq!(p.view_box, Some([0.0, 0.0, 10.0, 8.0]));
        assert_eq!(p.height, Some(8.0));
        assert_eq!(p.segment_count(), 4);
        // (10, 20) ↦ (1, 8 − 2) in user space, (1, 2) in the y-up frame.
        assert_eq!(
            p.subpaths[0][0],
            Segment::Line(Point::new(1.0, 6.0), Point::new(4.0, 6.0))
        );
        let framed = p.to_frame(Point::new(-0.5, -0.5));
        assert_eq!(framed[0][0].start(), Point::new(0.5, 1.5));
        assert_eq!(framed[1][0].start(), Point::new(0.5, 6.5));
    }

    #[test]
    fn errors_name_the_place_and_what_was_expected() {
        let e = svg_from_str("<svg>\n  <g/>\n</svg>", Path::new("a.svg")).unwrap_err();
        assert!(e.to_string().starts_with("a.svg: no <path> element"), "{e}");
        let e = svg_from_str(
            "<svg>\n<path d=\"M0 0 A 1 1 0 0 1 2 2\"/></svg>",
            Path::new("a.svg"),
        )
        .unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.svg:2:15: unsupported path command 'A'; supported: M, L, H, V, C, S, Q, T, Z (absolute and relative)"
        );
        let e =
            svg_from_str("<svg><path d=\"M0 NaN L1 1\"/></svg>", Path::new("a.svg")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "a.svg:1:18: expected a number, found \"NaN\""
        );
        let e = svg_from_str("<svg><path d=\"M0 1e999\"/></svg>", Path::new("a.svg")).unwrap_err();
        assert!(
            e.to_string()
                .contains("1:18: the number \"1e999\" is not finite"),
            "{e}"
        );
        let e = svg_from_str("<svg><path d=\"L0 0\"/></svg>", Path::new("a.svg")).unwrap_err();
        assert!(e.to_string().contains("must start with M"), "{e}");
        let e = svg_from_str(
            "<svg><g transform=\"rotate(30)\"><path d=\"M0 0 L1 1\"/></g></svg>",
            Path::new("a.svg"),
        )
        .unwrap_err();
        assert!(
            e.to_string()
                .contains("1:20: unsupported transform \"rotate(30)\""),
            "{e}"
        );
    }
}
