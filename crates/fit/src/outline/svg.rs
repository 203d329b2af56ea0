//! The paths of an SVG file as Bézier segments, for scoring curves that
//! other tools (potrace, FontForge, Inkscape) produced.
//!
//! Read: every rendered `<path d="…">` element; the path commands
//! `M L H V C S Q T Z`, absolute and relative, with implicit repetition
//! (SVG 1.1, §8.3); the `transform` attributes `translate`, `scale` and
//! `matrix` on `<g>` and `<path>` elements (composed down the element tree,
//! as potrace writes them); and the `viewBox` (or `height`) of the root
//! `<svg>`. Elliptical arcs (`A`), other transforms and `<use>` elements
//! (which draw other elements by reference) are refused with their place.
//!
//! **Skipped.** Paths that are not rendered are not read: everything
//! inside `<defs>`, `<symbol>`, `<clipPath>`, `<mask>`, `<pattern>` and
//! `<marker>` (with or without a namespace prefix such as `svg:`), and
//! every element with `display="none"` (as an attribute or as
//! `display:none` in its `style`) with its descendants. [`SvgPaths::skipped`]
//! counts the skipped paths.
//!
//! **Limits.** Every coordinate, after the transforms, and the root's
//! `viewBox` and `height` must be within ±[`MAX_COORDINATE`] (1e15, as for
//! CSV outlines), so that distances and their squares stay finite; a file
//! must draw at least one segment (a line or curve; a lone move-to draws
//! none). Both are refused with the file and, for a coordinate, its line and
//! column.
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

use super::csv_points::MAX_COORDINATE;
use super::glyph::Segment;
use crate::geometry::{CubicBez, Point, QuadBez};

/// The container elements whose content is never rendered directly (SVG
/// 1.1: §5.3.1 `defs`, §5.5 `symbol`, §14.3.5 `clipPath`, §14.4 `mask`,
/// §13.3 `pattern`, §11.6.2 `marker`); their paths are skipped.
pub const NON_RENDERED: [&str; 6] = ["defs", "symbol", "clipPath", "mask", "pattern", "marker"];

/// The longest excerpt of the file an error message quotes, in characters.
const EXCERPT: usize = 40;

/// At most [`EXCERPT`] characters of `s`, with `…` when cut.
fn excerpt(s: &str) -> String {
    let mut out: String = s.chars().take(EXCERPT).collect();
    if out.len() < s.len() {
        out.push('…');
    }
    out
}

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
    /// Paths were found, but none draws a segment: every rendered path is
    /// empty or a lone move-to, or every path is in a non-rendered container.
    #[error("{}: no drawable segment: {rendered} rendered <path> element(s) draw no line or curve{}; expected at least one segment to score", path.display(), skipped_note(*skipped))]
    NoSegment {
        /// The file.
        path: PathBuf,
        /// The rendered `<path>` elements found.
        rendered: usize,
        /// The `<path>` elements skipped as not rendered.
        skipped: usize,
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

/// `, and N path(s) … were skipped` for [`SvgError::NoSegment`].
fn skipped_note(skipped: usize) -> String {
    if skipped == 0 {
        String::new()
    } else {
        format!(
            ", and {skipped} <path> element(s) inside non-rendered containers (<defs>, <symbol>, <clipPath>, <mask>, <pattern>, <marker>) or with display=\"none\" were skipped"
        )
    }
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
    /// A coordinate (after the transforms) or a `viewBox` or `height` value
    /// beyond ±[`MAX_COORDINATE`].
    #[error("{what} {value:e} is beyond ±1e15, the range of coordinates this tool scores (distances and their squares must stay finite)")]
    Range {
        /// What the value is (`a coordinate after the transforms`, `the viewBox value`, …).
        what: &'static str,
        /// The value (possibly infinite or NaN after an overflowing transform).
        value: f64,
    },
    /// A rendered element this reader cannot draw.
    #[error("unsupported element <{0}> (it draws other elements by reference); expected the paths drawn directly")]
    Element(String),
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
    /// The `<path>` elements skipped as not rendered (see the module docs).
    pub skipped: usize,
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

/// One open element: the transform its content is drawn with, and whether
/// its content is rendered.
#[derive(Clone, Copy)]
struct Frame {
    m: Affine,
    hidden: bool,
}

/// The element's name without a namespace prefix (`svg:defs` → `defs`).
fn local_name(name: &str) -> &str {
    name.rsplit_once(':').map_or(name, |(_, local)| local)
}

/// Whether the element's own attributes say it is not displayed:
/// `display="none"` or `display:none` in its `style`.
fn display_none(tag: &Tag<'_>) -> bool {
    tag.attributes.iter().any(|(k, v, _)| match *k {
        "display" => v.trim() == "none",
        "style" => v.split(';').any(|decl| {
            decl.split_once(':')
                .is_some_and(|(p, v)| p.trim() == "display" && v.trim() == "none")
        }),
        _ => false,
    })
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
        skipped: 0,
    };
    let top = Frame {
        m: Affine::IDENTITY,
        hidden: false,
    };
    let mut stack: Vec<Frame> = vec![top];
    let mut rendered = 0usize;
    let mut pos = 0;
    while let Some(rel) = text[pos..].find('<') {
        let start = pos + rel;
        let (tag, end) = next_tag(text, start).map_err(|(o, p)| at(o, p))?;
        pos = end;
        let Some(tag) = tag else { continue };
        if tag.name.starts_with('/') {
            if stack.len() > 1 {
                stack.pop();
            }
            continue;
        }
        let current = *stack.last().unwrap_or(&top);
        let name = local_name(tag.name);
        let hidden = current.hidden || NON_RENDERED.contains(&name) || display_none(&tag);
        let local = match tag.attributes.iter().find(|(k, _, _)| *k == "transform") {
            Some((_, v, o)) if !hidden => parse_transform(v).map_err(|(i, p)| at(o + i, p))?,
            _ => Affine::IDENTITY,
        };
        let inner = Frame {
            m: current.m.then(local),
            hidden,
        };
        match name {
            "svg" if out.view_box.is_none() && out.height.is_none() => {
                root_view(&tag, &mut out).map_err(|(o, p)| at(o, p))?;
            }
            "path" => {
                if let Some((_, d, o)) = tag.attributes.iter().find(|(k, _, _)| *k == "d") {
                    if hidden {
                        out.skipped += 1;
                    } else {
                        rendered += 1;
                        let subs = parse_path(d, inner.m).map_err(|(i, p)| at(o + i, p))?;
                        out.subpaths.extend(subs);
                    }
                }
            }
            "use" if !hidden => {
                return Err(at(start, SvgProblem::Element(excerpt(tag.name))));
            }
            _ => {}
        }
        if !tag.self_closing {
            // A path's children (such as <title>) are drawn without its
            // transform, as before; other elements pass theirs on.
            let pushed = if name == "path" {
                Frame { hidden, ..current }
            } else {
                inner
            };
            stack.push(pushed);
        }
    }
    if rendered + out.skipped == 0 {
        return Err(SvgError::NoPath {
            path: path.to_owned(),
        });
    }
    if out.segment_count() == 0 {
        return Err(SvgError::NoSegment {
            path: path.to_owned(),
            rendered,
            skipped: out.skipped,
        });
    }
    Ok(out)
}

/// Whether `v` is within ±[`MAX_COORDINATE`] (false for NaN).
fn in_range(v: f64) -> bool {
    v.abs() <= MAX_COORDINATE
}

/// The root's `viewBox` and `height`.
fn root_view(tag: &Tag<'_>, out: &mut SvgPaths) -> Result<(), (usize, SvgProblem)> {
    for (k, v, o) in &tag.attributes {
        match *k {
            "viewBox" => {
                let nums = numbers(v).map_err(|(i, p)| (o + i, p))?;
                if nums.len() != 4 {
                    return Err((*o, SvgProblem::Number(excerpt(v))));
                }
                if let Some(&value) = nums.iter().find(|x| !in_range(**x)) {
                    let what = "the viewBox value";
                    return Err((*o, SvgProblem::Range { what, value }));
                }
                out.view_box = Some([nums[0], nums[1], nums[2], nums[3]]);
            }
            "height" => {
                let digits = v.trim_end_matches(|c: char| c.is_ascii_alphabetic() || c == '%');
                out.height = digits.trim().parse().ok().filter(|h: &f64| h.is_finite());
                if let Some(value) = out.height.filter(|h| !in_range(*h)) {
                    let what = "the height";
                    return Err((*o, SvgProblem::Range { what, value }));
                }
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
        // The closing parenthesis after the opening one (a ')' before the
        // '(' is not a transform, such as "a)b(").
        let open = rest.find('(');
        let close = open.and_then(|open| rest[open..].find(')').map(|k| open + k));
        let (Some(open), Some(close)) = (open, close) else {
            return Err((offset, SvgProblem::Transform(excerpt(rest))));
        };
        let name = rest[..open].trim();
        let args = numbers(&rest[open + 1..close]).map_err(|(i, p)| (offset + open + 1 + i, p))?;
        let t = match (name, args.as_slice()) {
            ("translate", [x]) => Affine([1.0, 0.0, 0.0, 1.0, *x, 0.0]),
            ("translate", [x, y]) => Affine([1.0, 0.0, 0.0, 1.0, *x, *y]),
            ("scale", [s]) => Affine([*s, 0.0, 0.0, *s, 0.0, 0.0]),
            ("scale", [x, y]) => Affine([*x, 0.0, 0.0, *y, 0.0, 0.0]),
            ("matrix", [a, b, c, d, e, f]) => Affine([*a, *b, *c, *d, *e, *f]),
            _ => return Err((offset, SvgProblem::Transform(excerpt(&rest[..=close])))),
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
        let token = &self.text[start..i];
        let value: f64 = token.parse().map_err(|_| {
            // The word quoted: up to the next separator, and at least the
            // character found (whole, even when it is a multi-byte space
            // such as U+2003, which the separators do not include).
            let rest = &self.text[start..];
            let len = match rest.find(|c: char| c.is_whitespace() || c == ',') {
                None => rest.len(),
                Some(0) => rest.chars().next().map_or(0, char::len_utf8),
                Some(k) => k,
            };
            (start, SvgProblem::Number(excerpt(&rest[..len])))
        })?;
        if !value.is_finite() {
            return Err((start, SvgProblem::NonFinite(excerpt(token))));
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

/// Where the segments of a path go: mapped by the path's transform,
/// checked against [`MAX_COORDINATE`], and gathered into subpaths.
struct Sink {
    m: Affine,
    current: Vec<Segment>,
    subpaths: Vec<Vec<Segment>>,
}

impl Sink {
    /// Adds `s` (in the path's own coordinates) to the current subpath.
    fn push(&mut self, s: Segment) -> Result<(), SvgProblem> {
        let m = self.m;
        let s = map_segment(&s, |p| m.apply(p));
        let points: &[Point] = match &s {
            Segment::Line(a, b) => &[*a, *b],
            Segment::Quad(q) => &[q.p0, q.p1, q.p2],
            Segment::Cubic(c) => &[c.p0, c.p1, c.p2, c.p3],
        };
        if let Some(value) = points
            .iter()
            .flat_map(|p| [p.x, p.y])
            .find(|v| !in_range(*v))
        {
            let what = "a coordinate (after the transforms)";
            return Err(SvgProblem::Range { what, value });
        }
        self.current.push(s);
        Ok(())
    }

    /// Ends the current subpath, if it has segments.
    fn finish(&mut self) {
        if !self.current.is_empty() {
            let mut done = std::mem::take(&mut self.current);
            done.shrink_to_fit();
            self.subpaths.push(done);
        }
    }
}

/// The subpaths of path data `d`, mapped by `m`; errors carry the byte
/// offset within `d`.
fn parse_path(d: &str, m: Affine) -> Result<Vec<Vec<Segment>>, (usize, SvgProblem)> {
    let mut lexer = Lexer { text: d, at: 0 };
    let mut sink = Sink {
        m,
        current: Vec::new(),
        subpaths: Vec::new(),
    };
    let mut pen = Pen {
        at: Point::ZERO,
        start: Point::ZERO,
        cubic_ctrl: None,
        quad_ctrl: None,
    };
    let mut command: Option<u8> = None;
    while let Some(c) = lexer.peek() {
        // The command letter, or the first argument of a repeated command.
        let here = lexer.at;
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
            return Err((here, SvgProblem::NoMoveTo((cmd as char).to_string())));
        }
        step(&mut lexer, cmd, &mut pen, &mut sink).map_err(|e| match e.1 {
            SvgProblem::Command(_) | SvgProblem::Range { .. } => (here, e.1),
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
    sink.finish();
    Ok(sink.subpaths)
}

/// Executes one path command at the lexer (its arguments follow).
fn step(
    lexer: &mut Lexer<'_>,
    cmd: u8,
    pen: &mut Pen,
    sink: &mut Sink,
) -> Result<(), (usize, SvgProblem)> {
    let rel = cmd.is_ascii_lowercase();
    let here = pen.at;
    let (mut cubic_ctrl, mut quad_ctrl) = (None, None);
    let mut push = |s: Segment| sink.push(s).map_err(|p| (0, p));
    match cmd.to_ascii_uppercase() {
        b'M' => {
            sink.finish();
            pen.at = lexer.point(rel, here)?;
            pen.start = pen.at;
        }
        b'L' => {
            let p = lexer.point(rel, here)?;
            push(Segment::Line(here, p))?;
            pen.at = p;
        }
        b'H' => {
            let x = lexer.number()?;
            let p = Point::new(if rel { here.x + x } else { x }, here.y);
            push(Segment::Line(here, p))?;
            pen.at = p;
        }
        b'V' => {
            let y = lexer.number()?;
            let p = Point::new(here.x, if rel { here.y + y } else { y });
            push(Segment::Line(here, p))?;
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
            push(Segment::Cubic(CubicBez::new(here, c1, c2, p)))?;
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
            push(Segment::Quad(QuadBez::new(here, c1, p)))?;
            quad_ctrl = Some(c1);
            pen.at = p;
        }
        b'Z' => {
            if here != pen.start {
                push(Segment::Line(here, pen.start))?;
            }
            pen.at = pen.start;
            sink.finish();
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
        parse_path(d, Affine::IDENTITY).unwrap()
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
