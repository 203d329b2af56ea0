//! The one embedded font: DejaVu Sans, registered with plotters under the
//! family `sans-serif` for every text the crate draws (report plots and
//! CT previews), so that no system font library is needed; and
//! [`GlyphBackend`], which draws that text into bitmaps with each glyph at
//! its side bearing (plotters 0.3.7's bitmap text drops it, so "objective"
//! came out "ob jective").
//!
//! A leaf of the crate: it imports nothing of it.

use std::sync::OnceLock;

use ab_glyph::{point, Font, FontRef, ScaleFont};
use plotters::style::FontStyle;
use plotters_backend::text_anchor::{HPos, VPos};
use plotters_backend::{
    BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingBackend, DrawingErrorKind,
};

/// DejaVu Sans 2.37 from Debian's fonts-dejavu-core 2.37-6 (Bitstream Vera
/// licence; see `assets/fonts/LICENSE` and `assets/fonts/PROVENANCE`).
static DEJAVU_SANS: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// The font family every drawn text uses; SVG files name it as is.
pub const FAMILY: &str = "sans-serif";

/// The embedded font could not be registered with plotters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the embedded DejaVu Sans font could not be loaded")]
pub struct FontError;

/// Registers the embedded font with plotters, once per process.
pub fn ensure_font() -> Result<(), FontError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(FontError)
    }
}

/// The embedded font, parsed once.
fn font_ref() -> Option<&'static FontRef<'static>> {
    static FONT: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT.get_or_init(|| FontRef::try_from_slice(DEJAVU_SANS).ok())
        .as_ref()
}

/// A drawing backend that draws text with the embedded font's outlines
/// placed by their side bearings, kerning and advances (the layout of
/// the OpenType `hmtx` and `kern` tables), and everything else through the
/// backend it wraps. Its text occupies the box plotters estimates (the sum
/// of advances and kerning), so layouts do not change.
pub struct GlyphBackend<B>(pub B);

impl<B: DrawingBackend> DrawingBackend for GlyphBackend<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.0.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_line(from, to, style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_path(path, style)
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.fill_polygon(vert, style)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        self.0.blit_bitmap(pos, size, src)
    }

    fn draw_text<S: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &S,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<Self::ErrorType>> {
        let colour = style.color();
        let Some(font) = font_ref() else {
            return self.0.draw_text(text, style, pos);
        };
        if colour.alpha == 0.0 {
            return Ok(());
        }
        let ((min_x, min_y), (max_x, max_y)) = style
            .layout_box(text)
            .map_err(|e| DrawingErrorKind::FontError(Box::new(e)))?;
        let (width, height) = (max_x - min_x, max_y - min_y);
        let dx = match style.anchor().h_pos {
            HPos::Left => 0,
            HPos::Right => -width,
            HPos::Center => -width / 2,
        };
        let dy = match style.anchor().v_pos {
            VPos::Top => 0,
            VPos::Center => -height / 2,
            VPos::Bottom => -height,
        };
        let size = style.size() as f32;
        let scaled = font.as_scaled(size);
        let transform = style.transform();
        let (w, h) = self.0.get_size();
        let mut pixels: Vec<(i32, i32, f32)> = Vec::new();
        let mut x = 0f32;
        let mut previous = None;
        for c in text.chars() {
            let id = scaled.glyph_id(c);
            if let Some(p) = previous {
                x += scaled.kern(p, id);
            }
            previous = Some(id);
            // The outline at (x, 0): its pixel bounds carry the bearing.
            let glyph = id.with_scale_and_position(size, point(x, 0.0));
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                // plotters' vertical placement, so baselines do not move.
                let (ox, oy) = (bounds.min.x as i32, (size / 2.0 + bounds.min.y) as i32);
                outline.draw(|gx, gy, coverage| {
                    pixels.push((ox + gx as i32, oy + gy as i32, coverage));
                });
            }
            x += scaled.h_advance(id);
        }
        for (px, py, coverage) in pixels {
            let (tx, ty) = transform.transform(px + dx - min_x, py + dy - min_y);
            let (tx, ty) = (pos.0 + tx, pos.1 + ty);
            if tx >= 0 && tx < w as i32 && ty >= 0 && ty < h as i32 && coverage > 0.0 {
                self.0.draw_pixel(
                    (tx, ty),
                    BackendColor {
                        alpha: colour.alpha * f64::from(coverage.min(1.0)),
                        rgb: colour.rgb,
                    },
                )?;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use plotters::prelude::*;

    #[test]
    fn the_embedded_font_registers() {
        assert_eq!(super::ensure_font(), Ok(()));
    }

    /// The columns of a rendered line of text that hold ink.
    fn inked_columns(text: &str, fixed: bool) -> Vec<bool> {
        ensure_font().unwrap();
        let (w, h) = (200u32, 40u32);
        let mut buf = vec![255u8; (w * h * 3) as usize];
        {
            let style = TextStyle::from((FAMILY, 20.0).into_font());
            let bitmap = BitMapBackend::with_buffer(&mut buf, (w, h));
            if fixed {
                let root = GlyphBackend(bitmap).into_drawing_area();
                root.draw_text(text, &style, (10, 10)).unwrap();
                root.present().unwrap();
            } else {
                let root = bitmap.into_drawing_area();
                root.draw_text(text, &style, (10, 10)).unwrap();
                root.present().unwrap();
            }
        }
        (0..w as usize)
            .map(|x| (0..h as usize).any(|y| buf[(y * w as usize + x) * 3] < 160))
            .collect()
    }

    /// The widest run of blank columns between the first and last ink.
    fn widest_gap(cols: &[bool]) -> usize {
        let first = cols.iter().position(|&c| c).unwrap();
        let last = cols.iter().rposition(|&c| c).unwrap();
        cols[first..=last]
            .split(|&c| c)
            .map(<[bool]>::len)
            .max()
            .unwrap_or(0)
    }

    #[test]
    fn glyphs_sit_at_their_bearings() {
        // "bj": plotters' own bitmap text leaves a gap before the j, whose
        // left bearing is negative; drawn at the bearing, there is none wider
        // than the letters' own spacing.
        let plain = widest_gap(&inked_columns("objective", false));
        let fixed = widest_gap(&inked_columns("objective", true));
        assert!(
            fixed < plain,
            "gap {fixed} px with the bearings, {plain} px without"
        );
        assert!(fixed <= 2, "a {fixed}-px gap inside \"objective\"");
    }
}
