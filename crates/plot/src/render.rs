//! Rendering plumbing for the plots: the viridis map, text measurement,
//! shared legends, solid and dashed series lines, and a figure drawn as
//! SVG and PNG in memory ([`draw_in_memory`]; the report writes its figures
//! as files with `metabezier-report`'s own `save`).
//!
//! Text is drawn with plotters' `ab_glyph` renderer and the crate's one
//! embedded font ([`crate::font`]), so no system font library is needed.

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::font::{ensure_font, GlyphBackend, FAMILY};
use crate::style::{LegendEntry, SeriesStyle};

/// A drawing failure, as text.
#[derive(Debug)]
pub struct PlotError(pub String);

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for PlotError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        PlotError(e.to_string())
    }
}

/// The result of drawing.
pub type DrawResult = Result<(), PlotError>;

/// Something that draws itself on any plotters backend.
pub trait Draw {
    /// Width and height in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws on the whole canvas.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult;
}

/// `figure` drawn in memory: its SVG text and its PNG bytes (the same
/// drawing as the report's files, for outputs that are written later together, such
/// as the implant's staged files).
pub fn draw_in_memory<F: Draw>(figure: &F) -> Result<(String, Vec<u8>), PlotError> {
    ensure_font().map_err(|e| PlotError(e.to_string()))?;
    let (w, h) = figure.size();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        figure.draw(&root)?;
        root.present()?;
    }
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = GlyphBackend(BitMapBackend::with_buffer(&mut rgb, (w, h))).into_drawing_area();
        figure.draw(&root)?;
        root.present()?;
    }
    let png = crate::png::encode_png(&rgb, w, h).map_err(|e| PlotError(e.to_string()))?;
    Ok((svg, png))
}

/// The viridis colour map at `t` ∈ [0, 1] (linear between 9 samples).
pub fn viridis(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let x = t * (STOPS.len() - 1) as f64;
    let i = (x.floor() as usize).min(STOPS.len() - 2);
    let f = x - i as f64;
    let lerp = |a: u8, b: u8| (f64::from(a) + (f64::from(b) - f64::from(a)) * f).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// A text style of the plot font.
pub fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from((FAMILY, f64::from(size)).into_font())
}

/// Width of `text` in pixels at `size` (an estimate when the font fails).
pub fn text_width(text: &str, size: u32) -> u32 {
    let _ = ensure_font();
    (FAMILY, f64::from(size))
        .into_font()
        .box_size(text)
        .map(|(w, _)| w)
        .unwrap_or_else(|_| (text.chars().count() as u32) * size * 6 / 10)
}

/// Font size of legend entries.
pub const LEGEND_FONT: u32 = 15;
const LEGEND_ROW: u32 = 24;
const SWATCH: u32 = 26;

/// Positions of legend entries (row, x offset) wrapped to `width`.
fn legend_layout(entries: &[LegendEntry], width: u32) -> Vec<(u32, u32)> {
    let mut out = Vec::with_capacity(entries.len());
    let (mut row, mut x) = (0u32, 12u32);
    for (name, _) in entries {
        let w = SWATCH + 6 + text_width(name, LEGEND_FONT) + 22;
        if x > 12 && x + w > width.saturating_sub(12) {
            row += 1;
            x = 12;
        }
        out.push((row, x));
        x += w;
    }
    out
}

/// Height of a shared legend strip of `entries` at `width`.
pub fn legend_height(entries: &[LegendEntry], width: u32) -> u32 {
    let rows = legend_layout(entries, width)
        .last()
        .map_or(0, |&(r, _)| r + 1);
    rows * LEGEND_ROW + 8
}

/// Draws a shared legend strip: a line swatch and the name of every entry.
pub fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[LegendEntry],
) -> DrawResult {
    let (w, _) = area.dim_in_pixel();
    let style = font(LEGEND_FONT).pos(Pos::new(HPos::Left, VPos::Center));
    for ((name, s), (row, x)) in entries.iter().zip(legend_layout(entries, w)) {
        let y = (4 + row * LEGEND_ROW + LEGEND_ROW / 2) as i32;
        let x = x as i32;
        let swatch = vec![(x, y), (x + SWATCH as i32, y)];
        if s.dashed {
            area.draw(&DashedPathElement::new(
                swatch,
                DASH,
                GAP,
                s.colour.stroke_width(3),
            ))?;
        } else {
            area.draw(&PathElement::new(swatch, s.colour.stroke_width(3)))?;
        }
        area.draw_text(name, &style, (x + SWATCH as i32 + 6, y))?;
    }
    Ok(())
}

/// Dash length of a variant's line, in pixels.
const DASH: u32 = 7;
/// Gap between dashes, in pixels.
const GAP: u32 = 4;

/// Draws the polyline `points` in `style` at `width` pixels: solid, or
/// dashed for a variant.
pub fn draw_line<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    points: Vec<(f64, f64)>,
    style: SeriesStyle,
    width: u32,
) -> DrawResult {
    let stroke = style.colour.stroke_width(width);
    if style.dashed {
        chart.draw_series(DashedLineSeries::new(points, DASH, GAP, stroke))?;
    } else {
        chart.draw_series(LineSeries::new(points, stroke))?;
    }
    Ok(())
}

/// Draws a centred title line.
pub fn draw_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    text: &str,
    size: u32,
) -> DrawResult {
    let (w, h) = area.dim_in_pixel();
    let style = font(size).pos(Pos::new(HPos::Center, VPos::Center));
    area.draw_text(text, &style, ((w / 2) as i32, (h / 2) as i32))?;
    Ok(())
}

/// Largest value drawn on a log axis; larger ones are drawn at this value
/// (plotters' log-axis ticks must stay finite).
pub const LOG_MAX: f64 = 1e300;
/// Smallest value drawn on a log axis.
pub const LOG_MIN: f64 = 1e-300;

/// The lowest value a log axis shows, for values that may be ≤ 0 (exact
/// zeros): the whole decade below the smallest positive value, but not
/// below 1e-16 (the relative precision of a double), so that a zero does not
/// stretch the axis over dozens of empty decades; values at or below it are
/// drawn at it and its tick reads "0" or "≤ 10⁻¹⁶" ([`FloorTick`]).
pub fn log_floor(values: impl IntoIterator<Item = f64>) -> f64 {
    let min_pos = values
        .into_iter()
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold(f64::INFINITY, f64::min);
    if min_pos.is_finite() {
        10f64.powf(min_pos.log10().floor() - 1.0).max(1e-16)
    } else {
        1e-16
    }
}

/// The tick of a log axis's floor when some values are drawn at it: at
/// log10 of the floor, reading "0" when they are all exact zeros (or
/// negative), else "≤ 10^k".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloorTick {
    /// log10 of the floor.
    pub at: f64,
    /// Whether every value drawn at the floor is ≤ 0.
    pub zeros_only: bool,
}

impl FloorTick {
    /// The floor tick of `values` drawn above `floor`, or `None` when none
    /// is at or below it.
    pub fn of(values: impl IntoIterator<Item = f64>, floor: f64) -> Option<FloorTick> {
        let mut any = false;
        let mut zeros_only = true;
        for v in values.into_iter().filter(|v| !v.is_nan() && *v <= floor) {
            any = true;
            zeros_only &= v <= 0.0;
        }
        any.then(|| FloorTick {
            at: floor.log10(),
            zeros_only,
        })
    }
}

/// A value for a log axis: at least `floor`, at most [`LOG_MAX`].
pub fn on_log_axis(v: f64, floor: f64) -> f64 {
    v.max(floor).min(LOG_MAX)
}

/// A log-axis range covering positive `lo..hi` with some margin, at least
/// about one decade wide, within [`LOG_MIN`]..[`LOG_MAX`].
pub fn log_range(lo: f64, hi: f64) -> (f64, f64) {
    let clamp = |v: f64| {
        if v.is_finite() && v > 0.0 {
            v.clamp(LOG_MIN, LOG_MAX).log10()
        } else {
            -16.0
        }
    };
    let (mut a, mut b) = (clamp(lo), clamp(hi));
    if b < a {
        b = a;
    }
    a -= 0.15;
    b += 0.15;
    if b - a < 1.2 {
        let m = (a + b) / 2.0;
        a = m - 0.6;
        b = m + 0.6;
    }
    let (lmin, lmax) = (LOG_MIN.log10(), LOG_MAX.log10());
    if a < lmin {
        b = (b + lmin - a).min(lmax);
        a = lmin;
    }
    if b > lmax {
        a = (a - (b - lmax)).max(lmin);
        b = lmax;
    }
    (10f64.powf(a), 10f64.powf(b))
}

/// log10 of a positive value (the coordinate of log-scaled axes, which are
/// drawn as linear axes of log10 values with power-of-ten labels).
pub fn lg(v: f64) -> f64 {
    v.log10()
}

/// log10 of both ends of a range.
pub fn lg_range(r: (f64, f64)) -> (f64, f64) {
    (lg(r.0), lg(r.1))
}

/// Light grid lines for axes in log10 space: at 2..9 × 10^k when the axis
/// spans at most 6 decades, else at every decade (up to 60).
pub fn draw_minor_decades<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    x: (f64, f64),
    y: (f64, f64),
    on_x: bool,
    on_y: bool,
) -> DrawResult {
    let light = RGBColor(238, 238, 238).stroke_width(1);
    let positions = |(lo, hi): (f64, f64)| -> Vec<f64> {
        let span = hi - lo;
        if !(span.is_finite() && span > 0.0) || span > 60.0 {
            return Vec::new();
        }
        let (k0, k1) = (lo.floor() as i64, hi.ceil() as i64);
        let mut out = Vec::new();
        for k in k0..=k1 {
            if span <= 6.0 {
                for m in 2..=9 {
                    out.push(k as f64 + f64::from(m).log10());
                }
            } else {
                out.push(k as f64);
            }
        }
        out.retain(|v| *v > lo && *v < hi);
        out
    };
    if on_x {
        chart.draw_series(
            positions(x)
                .into_iter()
                .map(|v| PathElement::new(vec![(v, y.0), (v, y.1)], light)),
        )?;
    }
    if on_y {
        chart.draw_series(
            positions(y)
                .into_iter()
                .map(|v| PathElement::new(vec![(x.0, v), (x.1, v)], light)),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_and_floors() {
        assert_eq!(log_floor([0.0, 2e-3, 5.0]), 1e-4);
        assert_eq!(log_floor([0.0, 3e-20]), 1e-16);
        assert_eq!(log_floor([f64::NAN, -1.0]), 1e-16);
        assert_eq!(log_floor([0.0, 5e-324]), 1e-16);
        assert_eq!(
            FloorTick::of([0.0, 2e-3], 1e-4),
            Some(FloorTick {
                at: -4.0,
                zeros_only: true
            })
        );
        assert!(!FloorTick::of([0.0, 1e-20, 1.0], 1e-16).unwrap().zeros_only);
        assert_eq!(FloorTick::of([2e-3], 1e-4), None);
        for (lo, hi) in [
            (1e300, 1e300),
            (f64::MAX, f64::MAX),
            (5e-324, 5e-324),
            (1e-300, 1e300),
        ] {
            let (a, b) = log_range(lo, hi);
            assert!(
                a.is_finite() && b.is_finite() && a > 0.0 && b > a,
                "{lo} {hi}: {a} {b}"
            );
            assert!(
                a >= LOG_MIN * 0.999 && b <= LOG_MAX * 1.001,
                "{lo} {hi}: {a} {b}"
            );
        }
        let (lo, hi) = log_range(1.0, 1.0);
        assert!(lo < 1.0 && hi > 1.0 && hi / lo >= 10.0);
        let (lo, hi) = log_range(0.0, f64::INFINITY);
        assert!(lo > 0.0 && hi > lo);
    }

    #[test]
    fn colours() {
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
        assert_eq!(viridis(f64::NAN), RGBColor(68, 1, 84));
    }

    #[test]
    fn the_font_measures_text() {
        assert!(text_width("MHS (hmcr=0.9)", 15) > text_width("MHS", 15));
    }
}
