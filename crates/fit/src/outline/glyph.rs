//! Exact glyph outlines from TrueType (quadratic) and OpenType CFF (cubic)
//! fonts, read with `ttf-parser`, and their dense sampling.
//!
//! Coordinates are font units, y up (the font's own frame, Apple TrueType
//! Reference Manual ch. 1; Adobe CFF spec, Technical Note #5176). Contours are
//! re-oriented to this module's convention: outer contours counter-clockwise,
//! holes clockwise (TrueType stores outer contours clockwise, CFF
//! counter-clockwise).
//!
//! **Malformed fonts.** A table that the font's table directory places
//! beyond the end of the file is refused as a truncated file, naming the
//! table; a glyph whose outline data `ttf-parser` cannot read is refused as
//! malformed, with what the parser reports; only a glyph that draws nothing
//! (such as a space) "has no outline".
//!
//! **Limits.** A glyph may draw at most [`MAX_GLYPH_SEGMENTS`] segments, a
//! TrueType composite glyph may reference at most [`MAX_GLYPH_COMPONENTS`]
//! components (counted through its nesting), it may have at most
//! [`MAX_GLYPH_CONTOURS`] contours, every coordinate must be within
//! ±[`MAX_COORDINATE`], and a sampling may place at most
//! [`MAX_GLYPH_SAMPLES`] points on a glyph ([`Glyph::check_sample_count`]),
//! so that a small font file cannot make the reader draw, store or sample an
//! outline of unbounded size.

use std::collections::HashMap;
use std::panic::{catch_unwind, resume_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use ttf_parser::{Face, GlyphId, OutlineBuilder, RawFace, Rect, Tag};

use super::csv_points::MAX_COORDINATE;
use super::{Orientation, Outline, OutlineError};
use crate::geometry::{CubicBez, Curve, Point, QuadBez};

/// The most segments one glyph may draw. Real glyphs draw tens to a few
/// hundred (dense CJK glyphs: under 1,000); a TrueType composite or CFF
/// subroutines can repeat a drawing exponentially, so the reader stops
/// there.
pub const MAX_GLYPH_SEGMENTS: usize = 20_000;

/// The most contours one glyph may have (real glyphs: a few, dense CJK
/// glyphs under 100). Orienting the contours tests each against all the
/// others, so the cost grows with contours × segments: at most about
/// 1.6 · 10⁸ point-in-polygon steps within these two limits.
pub const MAX_GLYPH_CONTOURS: usize = 1_000;

/// The most component references a TrueType composite glyph may make,
/// counted through its nesting (a component used twice counts twice):
/// `ttf-parser` walks every reference, drawn or not, so nested composites
/// could otherwise make it work exponentially long. Real accented letters
/// use 2–4.
pub const MAX_GLYPH_COMPONENTS: u64 = 10_000;

/// The most points a sampling may place on one glyph (all contours):
/// real glyphs take a few thousand at the default spacing of 1/200 em.
pub const MAX_GLYPH_SAMPLES: usize = 1_000_000;

/// One segment of a glyph contour, exactly as the font defines it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Segment {
    /// A straight line from the first point to the second.
    Line(Point, Point),
    /// A quadratic Bézier segment (TrueType `glyf` outlines).
    Quad(QuadBez),
    /// A cubic Bézier segment (CFF outlines).
    Cubic(CubicBez),
}

impl Segment {
    /// The start point `P(0)`.
    pub fn start(&self) -> Point {
        match self {
            Segment::Line(a, _) => *a,
            Segment::Quad(q) => q.p0,
            Segment::Cubic(c) => c.p0,
        }
    }

    /// The end point `P(1)`.
    pub fn end(&self) -> Point {
        match self {
            Segment::Line(_, b) => *b,
            Segment::Quad(q) => q.p2,
            Segment::Cubic(c) => c.p3,
        }
    }

    /// The point `P(t)`, `t ∈ [0, 1]` (`(1 − t)A + tB` for a line).
    pub fn eval(&self, t: f64) -> Point {
        match self {
            Segment::Line(a, b) => a.lerp(*b, t),
            Segment::Quad(q) => q.eval(t),
            Segment::Cubic(c) => c.eval(t),
        }
    }

    /// The direction of travel at the start, `P′(0)` (the first non-zero
    /// leg of the control polygon if `P′(0)` vanishes).
    pub fn start_direction(&self) -> Point {
        let cps = self.control_points();
        cps.windows(2)
            .map(|w| w[1] - w[0])
            .find(|d| d.hypot() > 0.0)
            .unwrap_or(Point::ZERO)
    }

    /// The direction of travel at the end, `P′(1)` (the last non-zero leg
    /// of the control polygon if `P′(1)` vanishes).
    pub fn end_direction(&self) -> Point {
        let cps = self.control_points();
        cps.windows(2)
            .rev()
            .map(|w| w[1] - w[0])
            .find(|d| d.hypot() > 0.0)
            .unwrap_or(Point::ZERO)
    }

    fn control_points(&self) -> Vec<Point> {
        match *self {
            Segment::Line(a, b) => vec![a, b],
            Segment::Quad(q) => vec![q.p0, q.p1, q.p2],
            Segment::Cubic(c) => vec![c.p0, c.p1, c.p2, c.p3],
        }
    }

    /// The polynomial degree: 1, 2 or 3.
    pub fn degree(&self) -> usize {
        match self {
            Segment::Line(..) => 1,
            Segment::Quad(_) => 2,
            Segment::Cubic(_) => 3,
        }
    }

    /// The arc length (exact for a line, Gauss–Legendre quadrature of
    /// [`Curve::arclen`] otherwise).
    pub fn arclen(&self) -> f64 {
        match self {
            Segment::Line(a, b) => a.distance(*b),
            Segment::Quad(q) => q.arclen(),
            Segment::Cubic(c) => c.arclen(),
        }
    }

    /// The same curve traversed backwards, `P(1 − t)`.
    pub fn reversed(&self) -> Segment {
        match *self {
            Segment::Line(a, b) => Segment::Line(b, a),
            Segment::Quad(q) => Segment::Quad(QuadBez::new(q.p2, q.p1, q.p0)),
            Segment::Cubic(c) => Segment::Cubic(CubicBez::new(c.p3, c.p2, c.p1, c.p0)),
        }
    }
}

/// How densely a glyph contour is sampled: every segment gets `n ≥ 1`
/// samples at `t = k/n`, `k = 0..n` (its end is the next segment's start).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sampling {
    /// The same number of samples on every segment.
    PerSegment(usize),
    /// `n = ⌈L/d⌉` samples on a segment of arc length `L`, for a spacing `d`
    /// in font units.
    Spacing(f64),
    /// As [`Sampling::Spacing`] with `d` this fraction of the font's units per em.
    EmFraction(f64),
}

impl Default for Sampling {
    /// A spacing of 1/200 em (about 10 units in a 2048-unit font).
    fn default() -> Self {
        Sampling::EmFraction(0.005)
    }
}

/// A dense sampling of one contour: the points, where each original segment
/// starts ("true break points") and the segment parameter of every point.
#[derive(Clone, Debug, PartialEq)]
pub struct SampledContour {
    /// The closed outline through the samples.
    pub outline: Outline,
    /// `breaks[j]` is the index in `outline.points` of segment `j`'s start.
    pub breaks: Vec<usize>,
    /// For every point, `(segment index, t)` with `point = segment.eval(t)`.
    pub params: Vec<(usize, f64)>,
    /// The break points (indices into `outline.points`) where the direction
    /// of travel turns by more than [`CORNER_DEGREES`]: where the font is
    /// not G¹.
    /// At the others the glyph is G¹.
    pub corners: Vec<usize>,
}

/// The turning angle above which a joint of a glyph contour is a corner,
/// that is, not G¹ in the font: any turn beyond floating-point noise.
/// Smooth joints whose control points are exactly collinear (TrueType's
/// implied on-curve points, most CFF joints) turn by 0; explicit on-curve
/// points whose neighbours were rounded to integer font units can turn by a
/// fraction of a degree (DejaVu Sans `S` has joints at 0.22°–1.0°), and
/// the font is only C⁰ there, so a fit at the glyph's own breaks must be
/// too, or it cannot recover the glyph.
pub const CORNER_DEGREES: f64 = 1e-6;

/// The exact outline of one glyph of a font.
#[derive(Clone, Debug, PartialEq)]
pub struct Glyph {
    /// The font file.
    pub font: PathBuf,
    /// The character.
    pub glyph: char,
    /// The font's units per em (the scale of the coordinates).
    pub units_per_em: u16,
    /// The glyph's bounding box `(min, max)` as stored in (or computed by) the font.
    pub bbox: (Point, Point),
    /// The closed contours, each a chain of segments whose ends meet; outer
    /// contours counter-clockwise, holes clockwise.
    pub contours: Vec<Vec<Segment>>,
}

impl Glyph {
    /// The glyph's height `y_max − y_min` from its bounding box, in font units.
    pub fn height(&self) -> f64 {
        self.bbox.1.y - self.bbox.0.y
    }

    /// The glyph's width `x_max − x_min` from its bounding box, in font units.
    pub fn width(&self) -> f64 {
        self.bbox.1.x - self.bbox.0.x
    }

    /// The number of samples for `segment` under `sampling` (at least 1).
    fn samples_on(&self, segment: &Segment, sampling: Sampling) -> usize {
        let by_spacing = |d: f64| {
            if d > 0.0 && d.is_finite() {
                (segment.arclen() / d).ceil().clamp(1.0, 1e6) as usize
            } else {
                1
            }
        };
        match sampling {
            Sampling::PerSegment(n) => n.max(1),
            Sampling::Spacing(d) => by_spacing(d),
            Sampling::EmFraction(f) => by_spacing(f * self.units_per_em as f64),
        }
    }

    /// The number of points [`Glyph::sample_at_least`] would place on all
    /// contours (saturating).
    pub fn sample_count(&self, sampling: Sampling, min: usize) -> usize {
        self.contours.iter().flatten().fold(0usize, |n, seg| {
            n.saturating_add(self.samples_on(seg, sampling).max(min))
        })
    }

    /// Refuses a sampling that would place more than [`MAX_GLYPH_SAMPLES`]
    /// points on the glyph (call it before [`Glyph::sample_at_least`] on a
    /// glyph from a file).
    pub fn check_sample_count(&self, sampling: Sampling, min: usize) -> Result<(), OutlineError> {
        let samples = self.sample_count(sampling, min);
        if samples > MAX_GLYPH_SAMPLES {
            return Err(OutlineError::GlyphLimit {
                path: self.font.clone(),
                glyph: self.glyph,
                what: "sample points",
                found: samples as u64,
                limit: MAX_GLYPH_SAMPLES as u64,
            });
        }
        Ok(())
    }

    /// Every contour sampled at `t = k/n` on each segment, with the indices
    /// where segments start (see [`SampledContour`]).
    pub fn sample(&self, sampling: Sampling) -> Vec<SampledContour> {
        self.sample_at_least(sampling, 1)
    }

    /// As [`Glyph::sample`], with at least `min` samples on every segment
    /// (so that a fit at the glyph's own break points has `min + 1` points
    /// per segment however short the segment is).
    pub fn sample_at_least(&self, sampling: Sampling, min: usize) -> Vec<SampledContour> {
        self.contours
            .iter()
            .map(|contour| {
                let mut points = Vec::new();
                let mut breaks = Vec::with_capacity(contour.len());
                let mut params = Vec::new();
                for (j, seg) in contour.iter().enumerate() {
                    breaks.push(points.len());
                    let n = self.samples_on(seg, sampling).max(min);
                    for k in 0..n {
                        let t = k as f64 / n as f64;
                        points.push(seg.eval(t));
                        params.push((j, t));
                    }
                }
                let corners = (0..contour.len())
                    .filter(|&j| {
                        let before =
                            contour[(j + contour.len() - 1) % contour.len()].end_direction();
                        let after = contour[j].start_direction();
                        before
                            .cross(after)
                            .atan2(before.dot(after))
                            .abs()
                            .to_degrees()
                            > CORNER_DEGREES
                    })
                    .map(|j| breaks[j])
                    .collect();
                SampledContour {
                    outline: Outline::new(points, true),
                    breaks,
                    params,
                    corners,
                }
            })
            .collect()
    }

    /// The sampled contours as outlines only (see [`Glyph::sample`]).
    pub fn outlines(&self, sampling: Sampling) -> Vec<Outline> {
        self.sample(sampling)
            .into_iter()
            .map(|s| s.outline)
            .collect()
    }
}

/// Collects `ttf-parser`'s drawing commands into closed segment chains,
/// skipping zero-length lines and closing every contour with a line if its
/// last point is not its first.
///
/// Past [`MAX_GLYPH_SEGMENTS`] segments it unwinds with [`SegmentCap`]
/// (`ttf-parser` gives a builder no way to stop it), which
/// [`glyph_from_bytes`] catches.
#[derive(Default)]
struct Collector {
    contours: Vec<Vec<Segment>>,
    current: Vec<Segment>,
    start: Point,
    pen: Point,
    segments: usize,
    /// The first coordinate beyond ±[`MAX_COORDINATE`] (or NaN), if any.
    far: Option<f64>,
}

/// The unwinding payload of a [`Collector`] past [`MAX_GLYPH_SEGMENTS`].
struct SegmentCap;

fn pt(x: f32, y: f32) -> Point {
    Point::new(x as f64, y as f64)
}

impl Collector {
    /// Adds a segment to the current contour, or unwinds past the limit.
    fn push(&mut self, s: Segment) {
        self.segments += 1;
        if self.segments > MAX_GLYPH_SEGMENTS {
            resume_unwind(Box::new(SegmentCap));
        }
        let end = s.end();
        let ctrl = match s {
            Segment::Line(a, _) => [a, a],
            Segment::Quad(q) => [q.p1, q.p1],
            Segment::Cubic(c) => [c.p1, c.p2],
        };
        if self.far.is_none() {
            self.far = [end, ctrl[0], ctrl[1], s.start()]
                .iter()
                .flat_map(|p| [p.x, p.y])
                .find(|v| v.is_nan() || v.abs() > MAX_COORDINATE);
        }
        self.current.push(s);
    }

    fn finish(&mut self) {
        if self.pen != self.start && !self.current.is_empty() {
            self.push(Segment::Line(self.pen, self.start));
        }
        if !self.current.is_empty() {
            self.contours.push(std::mem::take(&mut self.current));
        }
        self.pen = self.start;
    }
}

impl OutlineBuilder for Collector {
    fn move_to(&mut self, x: f32, y: f32) {
        self.finish();
        self.start = pt(x, y);
        self.pen = self.start;
    }

    fn line_to(&mut self, x: f32, y: f32) {
        let p = pt(x, y);
        if p != self.pen {
            self.push(Segment::Line(self.pen, p));
            self.pen = p;
        }
    }

    fn quad_to(&mut self, x1: f32, y1: f32, x: f32, y: f32) {
        let p = pt(x, y);
        self.push(Segment::Quad(QuadBez::new(self.pen, pt(x1, y1), p)));
        self.pen = p;
    }

    fn curve_to(&mut self, x1: f32, y1: f32, x2: f32, y2: f32, x: f32, y: f32) {
        let p = pt(x, y);
        self.push(Segment::Cubic(CubicBez::new(
            self.pen,
            pt(x1, y1),
            pt(x2, y2),
            p,
        )));
        self.pen = p;
    }

    fn close(&mut self) {
        self.finish();
    }
}

/// Whether `p` is inside the closed polygon `poly` (even–odd crossing rule,
/// Shimrat 1962, algorithm 112).
fn inside(poly: &[Point], p: Point) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                c = !c;
            }
        }
    }
    c
}

/// Re-orients the contours: a contour inside an even number of the others is
/// an outer contour (made counter-clockwise), otherwise a hole (clockwise).
fn orient_contours(contours: &mut [Vec<Segment>]) {
    let polys: Vec<Outline> = contours
        .iter()
        .map(|c| {
            let pts = c
                .iter()
                .flat_map(|s| (0..8).map(move |k| s.eval(k as f64 / 8.0)))
                .collect();
            Outline::new(pts, true)
        })
        .collect();
    for (i, contour) in contours.iter_mut().enumerate() {
        // A point a little way along the contour, to avoid shared vertices.
        let probe = contour[0].eval(0.5);
        let depth = polys
            .iter()
            .enumerate()
            .filter(|&(j, o)| j != i && inside(&o.points, probe))
            .count();
        let want = if depth % 2 == 0 {
            Orientation::CounterClockwise
        } else {
            Orientation::Clockwise
        };
        let have = polys[i].orientation();
        if have != Orientation::Degenerate && have != want {
            contour.reverse();
            for s in contour.iter_mut() {
                *s = s.reversed();
            }
        }
    }
}

/// Reads the outline of `glyph` from the font file at `path` (face 0).
pub fn load_glyph(path: &Path, glyph: char) -> Result<Glyph, OutlineError> {
    let data = std::fs::read(path).map_err(|source| OutlineError::Io {
        path: path.to_owned(),
        source,
    })?;
    glyph_from_bytes(&data, path, glyph)
}

/// A 4-byte table tag as text, such as `CFF ` or `glyf`.
fn tag_name(tag: Tag) -> String {
    tag.to_bytes().iter().map(|&b| b as char).collect()
}

/// Refuses a font file cut short: a table directory longer than the file,
/// or a table the directory places beyond its end. `ttf-parser` would
/// quietly treat such a table as absent, so that a truncated font seems to
/// lack glyphs or outlines.
fn check_tables(data: &[u8], path: &Path) -> Result<(), OutlineError> {
    let malformed = |message: String| OutlineError::MalformedFont {
        path: path.to_owned(),
        message,
    };
    let magic = data.get(..4).unwrap_or(&[]);
    let single =
        data.len() >= 12 && [&[0, 1, 0, 0][..], b"OTTO", b"true", b"typ1"].contains(&magic);
    if single {
        let tables = usize::from(u16::from_be_bytes([data[4], data[5]]));
        let need = 12 + 16 * tables;
        if data.len() < need {
            return Err(malformed(format!(
                "the font file is truncated: its table directory lists {tables} tables, which need \
                 {need} bytes, but the file has {} bytes",
                data.len()
            )));
        }
    }
    let Ok(raw) = RawFace::parse(data, 0) else {
        return Ok(()); // Face::parse reports it
    };
    for record in raw.table_records {
        let end = u64::from(record.offset) + u64::from(record.length);
        if end > data.len() as u64 {
            return Err(malformed(format!(
                "the font file is truncated: its table directory puts table '{}' at bytes {}..{end}, \
                 but the file has {} bytes",
                tag_name(record.tag),
                record.offset,
                data.len()
            )));
        }
    }
    Ok(())
}

/// The component references of TrueType glyphs, counted through their
/// nesting with every glyph counted once (memoised), and whether they draw
/// anything: the work `ttf-parser` does for a composite, bounded before it
/// starts.
struct Composites<'a> {
    loca: ttf_parser::loca::Table<'a>,
    glyf: &'a [u8],
    /// Per glyph: (glyph visits including itself, draws anything); `None`
    /// while being counted.
    memo: HashMap<u16, Option<(u64, bool)>>,
}

/// A composite glyph that contains itself. `ttf-parser` follows such a
/// cycle to its nesting limit of 32 (each level repeating every
/// component, so exponentially long) and then gives up on the glyph.
struct Cycle;

impl Composites<'_> {
    /// The visits and whether glyph `id` draws, stopping past the limit.
    fn visit(&mut self, id: u16, depth: u32) -> Result<(u64, bool), Cycle> {
        match self.memo.get(&id) {
            Some(Some(known)) => return Ok(*known),
            Some(None) => return Err(Cycle),
            None => {}
        }
        let data = self
            .loca
            .glyph_range(GlyphId(id))
            .and_then(|r| self.glyf.get(r))
            .unwrap_or(&[]);
        let contours = match data {
            [a, b, ..] => i16::from_be_bytes([*a, *b]),
            _ => 0,
        };
        if contours >= 0 || depth >= 32 {
            return Ok((1, contours > 0));
        }
        self.memo.insert(id, None);
        let (mut visits, mut draws) = (1u64, false);
        let mut s = data.get(10..).unwrap_or(&[]);
        // Composite records (OpenType `glyf`): flags, glyph index, the
        // arguments (2 or 4 bytes) and a scale (0, 2, 4 or 8 bytes).
        while let [f0, f1, g0, g1, rest @ ..] = s {
            let flags = u16::from_be_bytes([*f0, *f1]);
            let child = u16::from_be_bytes([*g0, *g1]);
            let (c, d) = self.visit(child, depth + 1)?;
            visits = visits.saturating_add(c);
            draws |= d;
            if visits > MAX_GLYPH_COMPONENTS || flags & 0x0020 == 0 {
                break;
            }
            let args = if flags & 0x0001 != 0 { 4 } else { 2 };
            let scale = if flags & 0x0080 != 0 {
                8
            } else if flags & 0x0040 != 0 {
                4
            } else if flags & 0x0008 != 0 {
                2
            } else {
                0
            };
            s = rest.get(args + scale..).unwrap_or(&[]);
        }
        self.memo.insert(id, Some((visits, draws)));
        Ok((visits, draws))
    }
}

/// For a TrueType glyph, the component references through its nesting and
/// whether it draws anything; `None` without a usable `glyf` table.
fn glyf_structure(face: &Face<'_>, id: GlyphId) -> Option<Result<(u64, bool), Cycle>> {
    face.tables().glyf?;
    let raw = face.raw_face();
    let glyf = raw.table(Tag::from_bytes(b"glyf"))?;
    let loca = ttf_parser::loca::Table::parse(
        std::num::NonZeroU16::new(face.number_of_glyphs())?,
        face.tables().head.index_to_location_format,
        raw.table(Tag::from_bytes(b"loca"))?,
    )?;
    let mut c = Composites {
        loca,
        glyf,
        memo: HashMap::new(),
    };
    Some(c.visit(id.0, 0))
}

/// The errors of one glyph's outline, naming the font, the character and
/// its glyph id.
struct GlyphErrors<'a> {
    path: &'a Path,
    glyph: char,
    id: GlyphId,
}

impl GlyphErrors<'_> {
    /// [`OutlineError::NoOutline`].
    fn no_outline(&self) -> OutlineError {
        OutlineError::NoOutline {
            path: self.path.to_owned(),
            glyph: self.glyph,
        }
    }

    /// [`OutlineError::MalformedGlyph`] in `table`, as `reported`.
    fn malformed(&self, table: &str, reported: String) -> OutlineError {
        OutlineError::MalformedGlyph {
            path: self.path.to_owned(),
            glyph: self.glyph,
            id: self.id.0,
            table: table.to_owned(),
            reported,
        }
    }

    /// [`OutlineError::GlyphLimit`]: at least `found` of `what`, beyond `limit`.
    fn limit(&self, what: &'static str, found: u64, limit: u64) -> OutlineError {
        OutlineError::GlyphLimit {
            path: self.path.to_owned(),
            glyph: self.glyph,
            what,
            found,
            limit,
        }
    }
}

/// Draws the `glyf` outline of glyph `id` into `collector`, as
/// `Face::outline_glyph` does, telling a glyph that draws nothing from one
/// that cannot be read; returns its bounding box.
fn draw_glyf(
    face: &Face<'_>,
    collector: &mut Collector,
    errors: &GlyphErrors<'_>,
) -> Result<Rect, OutlineError> {
    let id = errors.id;
    let (visits, draws) = match glyf_structure(face, id) {
        Some(Ok(structure)) => structure,
        Some(Err(Cycle)) => {
            return Err(errors.malformed(
                "glyf",
                "its components refer back to one another (a cycle)".into(),
            ))
        }
        None => (1, true),
    };
    if visits > MAX_GLYPH_COMPONENTS {
        return Err(errors.limit("component references", visits, MAX_GLYPH_COMPONENTS));
    }
    // The closing line of the last contour counts towards the limit too,
    // so `finish` runs inside the catch.
    let outlined = catch_unwind(AssertUnwindSafe(|| {
        let rect = face.outline_glyph(id, &mut *collector);
        collector.finish();
        rect
    }));
    match outlined {
        Ok(Some(rect)) => Ok(rect),
        Ok(None) if !draws => Err(errors.no_outline()),
        Ok(None) => Err(errors.malformed(
            "glyf",
            "ttf-parser cannot read its outline data (it gives no reason for 'glyf' \
             glyphs: a contour, point or component record is cut short or out of range)"
                .into(),
        )),
        Err(payload) => Err(cap_or_resume(payload, |w, f, l| errors.limit(w, f, l))),
    }
}

/// Draws the CFF outline of glyph `id` into `collector`; returns its
/// bounding box.
fn draw_cff(
    cff: &ttf_parser::cff::Table<'_>,
    collector: &mut Collector,
    errors: &GlyphErrors<'_>,
) -> Result<Rect, OutlineError> {
    let outlined = catch_unwind(AssertUnwindSafe(|| {
        let rect = cff.outline(errors.id, &mut *collector);
        collector.finish();
        rect
    }));
    match outlined {
        Ok(Ok(rect)) => Ok(rect),
        Ok(Err(ttf_parser::CFFError::ZeroBBox)) => Err(errors.no_outline()),
        Ok(Err(e)) => Err(errors.malformed(
            "CFF ",
            format!("ttf-parser reports {e:?} in its charstring"),
        )),
        Err(payload) => Err(cap_or_resume(payload, |w, f, l| errors.limit(w, f, l))),
    }
}

/// The error of a font with neither usable `glyf` nor CFF outlines,
/// saying which tables it has.
fn no_usable_outlines(face: &Face<'_>, path: &Path) -> OutlineError {
    let raw = face.raw_face();
    let has = |t: &[u8; 4]| raw.table(Tag::from_bytes(t)).is_some();
    let message = if has(b"glyf") {
        "the font file is malformed: its 'glyf' outlines cannot be used, because its \
         'loca' index is missing or malformed"
    } else if has(b"CFF ") {
        "the font file is malformed: ttf-parser cannot read its 'CFF ' table"
    } else if has(b"CFF2") {
        "the font has only 'CFF2' (variable) outlines, which this reader does not support"
    } else {
        "the font has no glyph outlines (neither a 'glyf' nor a 'CFF ' table)"
    };
    OutlineError::MalformedFont {
        path: path.to_owned(),
        message: message.into(),
    }
}

/// Reads the outline of `glyph` from font data; `path` only names the font
/// in the result and in errors.
pub fn glyph_from_bytes(data: &[u8], path: &Path, glyph: char) -> Result<Glyph, OutlineError> {
    check_tables(data, path)?;
    let face = Face::parse(data, 0).map_err(|e| OutlineError::Font {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    let id = face
        .glyph_index(glyph)
        .filter(|id| id.0 != 0)
        .ok_or_else(|| OutlineError::MissingGlyph {
            path: path.to_owned(),
            glyph,
        })?;
    let errors = GlyphErrors { path, glyph, id };
    let mut collector = Collector::default();
    // The outline, as `Face::outline_glyph` draws it (glyf first, then CFF).
    let drawn = if face.tables().glyf.is_some() {
        draw_glyf(&face, &mut collector, &errors)?
    } else if let Some(cff) = face.tables().cff.as_ref() {
        draw_cff(cff, &mut collector, &errors)?
    } else {
        return Err(no_usable_outlines(&face, path));
    };
    let mut contours = std::mem::take(&mut collector.contours);
    if contours.is_empty() {
        return Err(errors.no_outline());
    }
    let far = collector.far;
    if contours.len() > MAX_GLYPH_CONTOURS {
        let n = contours.len() as u64;
        return Err(errors.limit("contours", n, MAX_GLYPH_CONTOURS as u64));
    }
    if let Some(value) = far {
        return Err(errors.malformed(
            if face.tables().glyf.is_some() {
                "glyf"
            } else {
                "CFF "
            },
            format!("a coordinate is {value:e}, beyond ±1e15"),
        ));
    }
    orient_contours(&mut contours);
    Ok(Glyph {
        font: path.to_owned(),
        glyph,
        units_per_em: face.units_per_em(),
        bbox: (
            Point::new(drawn.x_min as f64, drawn.y_min as f64),
            Point::new(drawn.x_max as f64, drawn.y_max as f64),
        ),
        contours,
    })
}

/// The error of a [`Collector`] that stopped at [`MAX_GLYPH_SEGMENTS`];
/// any other panic goes on unwinding.
fn cap_or_resume(
    payload: Box<dyn std::any::Any + Send>,
    limit: impl Fn(&'static str, u64, u64) -> OutlineError,
) -> OutlineError {
    if payload.is::<SegmentCap>() {
        limit(
            "segments",
            MAX_GLYPH_SEGMENTS as u64 + 1,
            MAX_GLYPH_SEGMENTS as u64,
        )
    } else {
        resume_unwind(payload)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collector_closes_and_skips_degenerate_lines() {
        let mut c = Collector::default();
        c.move_to(0.0, 0.0);
        c.line_to(10.0, 0.0);
        c.line_to(10.0, 0.0);
        c.quad_to(10.0, 10.0, 0.0, 10.0);
        c.close();
        c.move_to(2.0, 2.0);
        c.curve_to(3.0, 2.0, 4.0, 3.0, 2.0, 2.0);
        c.close();
        c.finish();
        assert_eq!(c.contours.len(), 2);
        let a = &c.contours[0];
        assert_eq!(a.len(), 3);
        assert_eq!(a[2], Segment::Line(Point::new(0.0, 10.0), Point::ZERO));
        assert_eq!(c.contours[1].len(), 1);
        assert_eq!(c.contours[1][0].degree(), 3);
    }

    #[test]
    fn contours_are_oriented_outer_ccw_hole_cw() {
        let sq = |lo: f64, hi: f64| {
            let p = [(lo, lo), (lo, hi), (hi, hi), (hi, lo)].map(Point::from);
            (0..4)
                .map(|i| Segment::Line(p[i], p[(i + 1) % 4]))
                .collect::<Vec<_>>()
        };
        // Both given clockwise, TrueType style.
        let mut contours = vec![sq(0.0, 10.0), sq(3.0, 6.0)];
        orient_contours(&mut contours);
        let g = Glyph {
            font: "t".into(),
            glyph: 'o',
            units_per_em: 1000,
            bbox: (Point::ZERO, Point::new(10.0, 10.0)),
            contours,
        };
        let s = g.sample(Sampling::PerSegment(4));
        assert_eq!(s[0].outline.orientation(), Orientation::CounterClockwise);
        assert_eq!(s[1].outline.orientation(), Orientation::Clockwise);
        assert_eq!(s[0].breaks, vec![0, 4, 8, 12]);
        for (k, seg) in g.contours[0].iter().enumerate() {
            assert_eq!(s[0].outline.points[s[0].breaks[k]], seg.start());
        }
        assert_eq!(g.height(), 10.0);
        let by_length = g.sample(Sampling::Spacing(2.5));
        assert_eq!(by_length[1].breaks, vec![0, 2, 4, 6]);
        assert_eq!(g.sample(Sampling::EmFraction(0.0025))[0].outline.len(), 16);
    }

    #[test]
    fn corrupt_font_is_an_error() {
        let e = glyph_from_bytes(b"not a font", Path::new("x.ttf"), 'a').unwrap_err();
        assert!(
            e.to_string().starts_with("x.ttf: cannot read the font"),
            "{e}"
        );
    }
}
