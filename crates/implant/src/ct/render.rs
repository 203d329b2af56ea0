//! Preview rendering to PNG: a CT slice in a bone window with polylines and
//! labelled points drawn over it, and a shaded orthographic view of a
//! triangle mesh (software rasteriser with a z-buffer and Lambert shading,
//! `I = ambient + (1 − ambient)·|n·v|`, two-sided).
//!
//! Labels use plotters' in-memory bitmap backend with the embedded DejaVu
//! Sans (`assets/fonts/`); PNGs are encoded with the pure-Rust `image`
//! crate and written with [`write_atomic`].

use std::path::Path;

use plotters::prelude::*;

use super::error::CtError;
use super::mesh::Mesh;
use super::volume::Slice;
use crate::files::write_atomic;
use crate::font::{ensure_font, GlyphBackend, FAMILY};
use crate::geometry::Point;
use crate::geometry::Polyline;

/// A CT display window: grey = clamp((HU − (level − width/2)) / width).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Window {
    /// Window width in HU.
    pub width: f64,
    /// Window level (centre) in HU.
    pub level: f64,
}

impl Window {
    /// The bone window W 2000 / L 500.
    pub const BONE: Window = Window {
        width: 2000.0,
        level: 500.0,
    };

    /// The grey value (0..=255) of `hu`.
    pub fn grey(&self, hu: f64) -> u8 {
        let t = (hu - (self.level - self.width / 2.0)) / self.width;
        (t.clamp(0.0, 1.0) * 255.0).round() as u8
    }
}

/// What to draw over a slice (all in the slice's mm frame).
#[derive(Clone, Debug, Default)]
pub struct Overlay {
    /// Polylines with their RGB colour.
    pub polylines: Vec<(Polyline, [u8; 3])>,
    /// Labelled points (label, position, colour).
    pub points: Vec<(String, Point, [u8; 3])>,
    /// Vertical lines `x = const` (such as M_x), with colour.
    pub vertical_lines: Vec<(f64, [u8; 3])>,
    /// Straight segments (such as a tilted midline), with colour.
    pub lines: Vec<(Point, Point, [u8; 3])>,
    /// Pixels `(row, col)` filled with a colour (such as implant pixels on
    /// bone).
    pub pixels: Vec<((usize, usize), [u8; 3])>,
}

/// PNG-encodes an RGB8 buffer ([`metabezier_plot::png::encode_png`]).
pub fn encode_png(rgb: &[u8], w: u32, h: u32) -> Result<Vec<u8>, CtError> {
    metabezier_plot::png::encode_png(rgb, w, h).map_err(|e| CtError::PngEncode {
        source: Box::new(e),
    })
}

/// The PNG of `slice` in `window`, enlarged `scale` times (nearest
/// neighbour), with `overlay` drawn on top.
pub fn slice_overlay_png(
    slice: &Slice,
    window: Window,
    scale: u32,
    overlay: &Overlay,
) -> Result<Vec<u8>, CtError> {
    let scale = scale.max(1);
    let (w, h) = (slice.nx as u32 * scale, slice.ny as u32 * scale);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    for y in 0..h {
        for x in 0..w {
            let g = window.grey(slice.get((y / scale) as usize, (x / scale) as usize) as f64);
            let i = ((y * w + x) * 3) as usize;
            buf[i..i + 3].copy_from_slice(&[g, g, g]);
        }
    }
    // Pixel coordinates of a mm point: pixel centre (row, col) maps to the
    // middle of its enlarged block.
    let s = scale as f64;
    let to_px = |p: Point| {
        (
            ((p.x / slice.sx + 0.5) * s) as i32,
            ((p.y / slice.sy + 0.5) * s) as i32,
        )
    };
    let font_ok = ensure_font().is_ok();
    {
        let root = GlyphBackend(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
        let fail = |message: String| CtError::Draw { message };
        for &(x, c) in &overlay.vertical_lines {
            let px = ((x / slice.sx + 0.5) * s) as i32;
            root.draw(&PathElement::new(
                vec![(px, 0), (px, h as i32)],
                RGBColor(c[0], c[1], c[2]).stroke_width(1),
            ))
            .map_err(|e| fail(e.to_string()))?;
        }
        for &((r, c), col) in &overlay.pixels {
            let (x, y) = ((c as u32 * scale) as i32, (r as u32 * scale) as i32);
            root.draw(&Rectangle::new(
                [(x, y), (x + scale as i32 - 1, y + scale as i32 - 1)],
                RGBColor(col[0], col[1], col[2]).filled(),
            ))
            .map_err(|e| fail(e.to_string()))?;
        }
        for &(a, b, c) in &overlay.lines {
            root.draw(&PathElement::new(
                vec![to_px(a), to_px(b)],
                RGBColor(c[0], c[1], c[2]).stroke_width(1),
            ))
            .map_err(|e| fail(e.to_string()))?;
        }
        for (poly, c) in &overlay.polylines {
            let mut pts: Vec<(i32, i32)> = poly.points.iter().map(|&p| to_px(p)).collect();
            if poly.closed {
                if let Some(&f) = pts.first() {
                    pts.push(f);
                }
            }
            root.draw(&PathElement::new(
                pts,
                RGBColor(c[0], c[1], c[2]).stroke_width(1),
            ))
            .map_err(|e| fail(e.to_string()))?;
        }
        for (label, p, c) in &overlay.points {
            let (x, y) = to_px(*p);
            let col = RGBColor(c[0], c[1], c[2]);
            root.draw(&Circle::new((x, y), 3, col.filled()))
                .map_err(|e| fail(e.to_string()))?;
            if font_ok && !label.is_empty() {
                root.draw(&Text::new(
                    label.clone(),
                    (x + 5, y - 14),
                    (FAMILY, 14).into_font().color(&col),
                ))
                .map_err(|e| fail(e.to_string()))?;
            }
        }
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    encode_png(&buf, w, h)
}

/// A rectangular view of a slice: the millimetre box `[min, max]` drawn
/// into `width × height` pixels (the box is fitted, keeping the aspect
/// ratio), with `+y` up (`y_up`, e.g. to put the face at the top) or down,
/// a 10 mm scale bar, and labels at the top and bottom edges.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceView {
    /// The box's corner with the smallest coordinates (mm).
    pub min: Point,
    /// The opposite corner (mm).
    pub max: Point,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Whether the slice's +y points up in the image.
    pub y_up: bool,
    /// The label at the top edge (such as "anterior").
    pub top_label: String,
    /// The label at the bottom edge.
    pub bottom_label: String,
    /// The label at the left edge (empty: none).
    pub left_label: String,
    /// The label at the right edge (empty: none).
    pub right_label: String,
}

impl SliceView {
    /// Image pixels per millimetre.
    pub fn scale(&self) -> f64 {
        let (w, h) = (self.max.x - self.min.x, self.max.y - self.min.y);
        (self.width as f64 / w.max(1e-9)).min(self.height as f64 / h.max(1e-9))
    }

    /// The image position of the millimetre point `p` (the box centred).
    pub fn to_px(&self, p: Point) -> (f64, f64) {
        let s = self.scale();
        let c = (self.min + self.max) * 0.5;
        let x = self.width as f64 / 2.0 + (p.x - c.x) * s;
        let dy = (p.y - c.y) * s;
        let y = self.height as f64 / 2.0 + if self.y_up { -dy } else { dy };
        (x, y)
    }

    /// The millimetre point shown at image position `(x, y)`.
    pub fn to_mm(&self, x: f64, y: f64) -> Point {
        let s = self.scale();
        let c = (self.min + self.max) * 0.5;
        let dy = (y - self.height as f64 / 2.0) / s;
        Point::new(
            c.x + (x - self.width as f64 / 2.0) / s,
            c.y + if self.y_up { -dy } else { dy },
        )
    }
}

/// An RGB8 image being composed: panels are copied in, text and boxes drawn
/// on top, then it is PNG-encoded.
#[derive(Clone, Debug, PartialEq)]
pub struct Canvas {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major RGB8 samples.
    pub rgb: Vec<u8>,
}

impl Canvas {
    /// A canvas filled with `background`.
    pub fn new(width: u32, height: u32, background: [u8; 3]) -> Canvas {
        let mut rgb = Vec::with_capacity((width * height * 3) as usize);
        for _ in 0..width * height {
            rgb.extend_from_slice(&background);
        }
        Canvas { width, height, rgb }
    }

    /// Copies the `w × h` RGB8 image `src` with its top-left corner at
    /// `(x, y)` (clipped to the canvas).
    pub fn blit(&mut self, src: &[u8], w: u32, h: u32, x: u32, y: u32) {
        for r in 0..h.min(self.height.saturating_sub(y)) {
            let n = w.min(self.width.saturating_sub(x)) as usize * 3;
            let s = (r * w) as usize * 3;
            let d = (((y + r) * self.width + x) * 3) as usize;
            self.rgb[d..d + n].copy_from_slice(&src[s..s + n]);
        }
    }

    /// Draws `text` with its top-left corner at `(x, y)` (no-op when the
    /// embedded font cannot be registered).
    pub fn text(
        &mut self,
        text: &str,
        x: i32,
        y: i32,
        size: u32,
        colour: [u8; 3],
    ) -> Result<(), CtError> {
        if ensure_font().is_err() {
            return Ok(());
        }
        let root = GlyphBackend(BitMapBackend::with_buffer(
            &mut self.rgb,
            (self.width, self.height),
        ))
        .into_drawing_area();
        let col = RGBColor(colour[0], colour[1], colour[2]);
        root.draw(&Text::new(
            text.to_string(),
            (x, y),
            (FAMILY, size as f64).into_font().color(&col),
        ))
        .map_err(draw_err)?;
        root.present().map_err(draw_err)
    }

    /// Draws a rectangle outline (or a filled one) from `(x0, y0)` to
    /// `(x1, y1)`.
    pub fn rect(
        &mut self,
        (x0, y0): (i32, i32),
        (x1, y1): (i32, i32),
        colour: [u8; 3],
        filled: bool,
    ) -> Result<(), CtError> {
        let root = GlyphBackend(BitMapBackend::with_buffer(
            &mut self.rgb,
            (self.width, self.height),
        ))
        .into_drawing_area();
        let col = RGBColor(colour[0], colour[1], colour[2]);
        let style = if filled {
            col.filled()
        } else {
            col.stroke_width(2)
        };
        root.draw(&Rectangle::new([(x0, y0), (x1, y1)], style))
            .map_err(draw_err)?;
        root.present().map_err(draw_err)
    }

    /// Draws a straight line `width` pixels wide from `(x0, y0)` to
    /// `(x1, y1)`.
    pub fn line(
        &mut self,
        (x0, y0): (i32, i32),
        (x1, y1): (i32, i32),
        colour: [u8; 3],
        width: u32,
    ) -> Result<(), CtError> {
        let root = GlyphBackend(BitMapBackend::with_buffer(
            &mut self.rgb,
            (self.width, self.height),
        ))
        .into_drawing_area();
        let col = RGBColor(colour[0], colour[1], colour[2]);
        root.draw(&PathElement::new(
            vec![(x0, y0), (x1, y1)],
            col.stroke_width(width),
        ))
        .map_err(draw_err)?;
        root.present().map_err(draw_err)
    }

    /// A colour key: one swatch and label per entry, in rows from `(x, y)`,
    /// `columns` entries per row `column_width` pixels apart.
    pub fn legend(
        &mut self,
        entries: &[(String, [u8; 3])],
        (x, y): (i32, i32),
        columns: usize,
        column_width: i32,
    ) -> Result<(), CtError> {
        for (i, (label, c)) in entries.iter().enumerate() {
            let (cx, cy) = (
                x + (i % columns.max(1)) as i32 * column_width,
                y + (i / columns.max(1)) as i32 * 22,
            );
            self.rect((cx, cy + 3), (cx + 22, cy + 15), *c, true)?;
            self.text(label, cx + 28, cy, 15, [20, 20, 20])?;
        }
        Ok(())
    }

    /// The PNG bytes of the canvas.
    pub fn png(&self) -> Result<Vec<u8>, CtError> {
        encode_png(&self.rgb, self.width, self.height)
    }
}

fn draw_err<E: std::fmt::Display>(e: E) -> CtError {
    CtError::Draw {
        message: e.to_string(),
    }
}

/// The `view` of `slice` in `window` (nearest-neighbour samples) with
/// `overlay` on top, a 10 mm scale bar (bottom left) and the view's edge
/// labels, as a `width × height` RGB8 buffer.
pub fn slice_view_rgb(
    slice: &Slice,
    window: Window,
    view: &SliceView,
    overlay: &Overlay,
) -> Result<Vec<u8>, CtError> {
    let (w, h) = (view.width, view.height);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    let s = view.scale();
    let pixel_of = |p: Point| ((p.y / slice.sy).round(), (p.x / slice.sx).round());
    for y in 0..h {
        for x in 0..w {
            let (r, c) = pixel_of(view.to_mm(x as f64 + 0.5, y as f64 + 0.5));
            let g = if r >= 0.0 && c >= 0.0 && (r as usize) < slice.ny && (c as usize) < slice.nx {
                window.grey(slice.get(r as usize, c as usize) as f64)
            } else {
                0
            };
            let i = ((y * w + x) * 3) as usize;
            buf[i..i + 3].copy_from_slice(&[g, g, g]);
        }
    }
    let px = |p: Point| {
        let (x, y) = view.to_px(p);
        (x.round() as i32, y.round() as i32)
    };
    {
        let root = GlyphBackend(BitMapBackend::with_buffer(&mut buf, (w, h))).into_drawing_area();
        for &((r, c), col) in &overlay.pixels {
            let centre = Point::new(c as f64 * slice.sx, r as f64 * slice.sy);
            let half = Point::new(0.5 * slice.sx, 0.5 * slice.sy);
            let (a, b) = (px(centre - half), px(centre + half));
            root.draw(&Rectangle::new(
                [a, b],
                RGBColor(col[0], col[1], col[2]).filled(),
            ))
            .map_err(draw_err)?;
        }
        for &(a, b, c) in &overlay.lines {
            root.draw(&PathElement::new(
                vec![px(a), px(b)],
                RGBColor(c[0], c[1], c[2]).stroke_width(1),
            ))
            .map_err(draw_err)?;
        }
        for (poly, c) in &overlay.polylines {
            let mut pts: Vec<(i32, i32)> = poly.points.iter().map(|&p| px(p)).collect();
            if poly.closed {
                if let Some(&f) = pts.first() {
                    pts.push(f);
                }
            }
            root.draw(&PathElement::new(
                pts,
                RGBColor(c[0], c[1], c[2]).stroke_width(2),
            ))
            .map_err(draw_err)?;
        }
        root.present().map_err(draw_err)?;
    }
    let mut canvas = Canvas {
        width: w,
        height: h,
        rgb: buf,
    };
    for (label, p, c) in &overlay.points {
        let (x, y) = px(*p);
        canvas.rect((x - 3, y - 3), (x + 3, y + 3), *c, true)?;
        canvas.text(label, x + 6, y - 16, 15, *c)?;
    }
    let bar = (10.0 * s).round() as i32;
    let (bx, by) = (12, h as i32 - 18);
    canvas.rect((bx, by), (bx + bar, by + 4), [255, 255, 255], true)?;
    canvas.text("10 mm", bx, by - 18, 14, [255, 255, 255])?;
    canvas.text(&view.top_label, (w as i32) / 2 - 30, 4, 14, [255, 255, 160])?;
    canvas.text(
        &view.bottom_label,
        (w as i32) / 2 - 30,
        h as i32 - 20,
        14,
        [255, 255, 160],
    )?;
    if !view.left_label.is_empty() {
        canvas.text(&view.left_label, 4, (h as i32) / 2 - 8, 14, [255, 255, 160])?;
    }
    if !view.right_label.is_empty() {
        let x = w as i32 - 8 * view.right_label.chars().count() as i32 - 4;
        canvas.text(
            &view.right_label,
            x,
            (h as i32) / 2 - 8,
            14,
            [255, 255, 160],
        )?;
    }
    Ok(canvas.rgb)
}

/// A viewing direction for [`mesh_view_rgb`]: the camera looks along
/// `direction` (from the eye into the scene); `up` fixes the image's
/// vertical.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Viewing direction (need not be unit).
    pub direction: [f64; 3],
    /// Up vector (not parallel to `direction`).
    pub up: [f64; 3],
    /// Whether to mirror the image left–right: for meshes in a frame that
    /// is left-handed in the patient (see `Anatomy::right_handed`), so that
    /// the picture shows the patient as seen, not a mirror image.
    pub mirror: bool,
}

fn norm(v: [f64; 3]) -> [f64; 3] {
    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    [v[0] / l, v[1] / l, v[2] / l]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Renders meshes (each with a base colour) orthographically along
/// `view` into a `size × size` RGB8 buffer, fitted with a 5% margin on a
/// white background; returns the buffer. Depth test per pixel (z-buffer),
/// Lambert shading with ambient 0.25.
pub fn mesh_view_rgb(meshes: &[(&Mesh, [u8; 3])], view: View, size: u32) -> Vec<u8> {
    mesh_view(meshes, view, size).rgb
}

/// A rendered view and its projection: what a scale bar and an axis triad
/// drawn over it need.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshView {
    /// Row-major RGB8, `size × size`.
    pub rgb: Vec<u8>,
    /// Millimetres (mesh units) per pixel, the same in x and y.
    pub mm_per_px: f64,
    /// The unit vector drawn towards the image's right.
    pub right: [f64; 3],
    /// The unit vector drawn towards the image's top.
    pub up: [f64; 3],
}

impl MeshView {
    /// Where the mesh-frame unit vector `v` points in the image, in pixels
    /// per unit of its length drawn (`y` downwards, as in the image).
    pub fn screen(&self, v: [f64; 3]) -> [f64; 2] {
        [dot(v, self.right), -dot(v, self.up)]
    }
}

/// [`mesh_view_rgb`] with the projection it used ([`MeshView`]).
pub fn mesh_view(meshes: &[(&Mesh, [u8; 3])], view: View, size: u32) -> MeshView {
    let d = norm(view.direction);
    let right = norm(cross(d, view.up));
    let up = cross(right, d);
    let right = if view.mirror {
        right.map(|c| -c)
    } else {
        right
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (m, _) in meshes {
        for v in &m.vertices {
            let p = [dot(*v, right), dot(*v, up)];
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
    }
    let n = size as usize;
    let mut rgb = vec![255u8; n * n * 3];
    if lo[0] > hi[0] {
        return MeshView {
            rgb,
            mm_per_px: f64::NAN,
            right,
            up,
        };
    }
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-9) * 1.1;
    let c = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let px = |v: [f64; 3]| {
        [
            ((dot(v, right) - c[0]) / span + 0.5) * size as f64,
            (0.5 - (dot(v, up) - c[1]) / span) * size as f64,
            dot(v, d),
        ]
    };
    let mut depth = vec![f64::INFINITY; n * n];
    for (m, base) in meshes {
        for t in 0..m.triangles.len() {
            let nrm = m.normal(t);
            let shade = 0.25 + 0.75 * dot(nrm, d).abs();
            let col = base.map(|b| (b as f64 * shade).round().clamp(0.0, 255.0) as u8);
            let [a, b, cc] = m.triangles[t].map(|i| px(m.vertices[i]));
            let area = (b[0] - a[0]) * (cc[1] - a[1]) - (b[1] - a[1]) * (cc[0] - a[0]);
            if area.abs() < 1e-12 {
                continue;
            }
            let x0 = a[0].min(b[0]).min(cc[0]).floor().max(0.0) as usize;
            let x1 = (a[0].max(b[0]).max(cc[0]).ceil() as usize).min(n - 1);
            let y0 = a[1].min(b[1]).min(cc[1]).floor().max(0.0) as usize;
            let y1 = (a[1].max(b[1]).max(cc[1]).ceil() as usize).min(n - 1);
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let (qx, qy) = (x as f64 + 0.5, y as f64 + 0.5);
                    let w0 = ((b[0] - qx) * (cc[1] - qy) - (b[1] - qy) * (cc[0] - qx)) / area;
                    let w1 = ((cc[0] - qx) * (a[1] - qy) - (cc[1] - qy) * (a[0] - qx)) / area;
                    let w2 = 1.0 - w0 - w1;
                    if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                        continue;
                    }
                    let z = w0 * a[2] + w1 * b[2] + w2 * cc[2];
                    let i = y * n + x;
                    if z < depth[i] {
                        depth[i] = z;
                        rgb[i * 3..i * 3 + 3].copy_from_slice(&col);
                    }
                }
            }
        }
    }
    MeshView {
        rgb,
        mm_per_px: span / size as f64,
        right,
        up,
    }
}

/// Writes PNG bytes to `path` atomically.
pub fn write_png(path: &Path, png: &[u8]) -> Result<(), CtError> {
    write_atomic(path, png)?;
    Ok(())
}
