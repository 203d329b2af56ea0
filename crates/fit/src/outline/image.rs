//! Outlines from PNG images: luminance, Otsu threshold, border following.
//!
//! **Coordinate convention.** Pixel `(col, row)` of a `W × H` image, row 0 at
//! the top, becomes the point `(x, y) = (col, H − 1 − row)`: pixel centres
//! sit on integer coordinates, the origin is the centre of the bottom-left
//! pixel and y points *up*, the frame of [`crate::geometry`]. In this frame
//! outer boundaries run counter-clockwise and holes clockwise, so the shape
//! is always on the left.
//!
//! **Boundary points.** Borders are followed by Suzuki & Abe (1985). By
//! default ([`BoundaryPoints::MidCrack`]) each boundary point is the midpoint
//! of a pixel edge between the shape and the background, in following order
//! (the mid-crack code, Dunkelberger & Mitchell 1985; the same points as
//! marching squares at level ½ on the binary image). Their polygon encloses
//! the shape's pixel count minus ½ px² for a simply connected, 4-connected
//! shape. [`BoundaryPoints::PixelCentres`] gives the border pixels' centres
//! instead, as OpenCV's `findContours`; that polygon loses about half a pixel
//! all around the perimeter.
//!
//! **Limits.** The PNG header is checked before anything is decoded: an
//! image may have at most [`MAX_IMAGE_SIDE`] pixels a side and
//! [`MAX_IMAGE_PIXELS`] in all, and the pixel data its header declares must
//! fit in what the rest of the file can hold once decompressed (deflate
//! expands at most [`MAX_DEFLATE_RATIO`]:1), so that a small or truncated
//! file cannot make the decoder allocate a large image. The decoder's own
//! buffers for ancillary chunks (an ICC profile, for one) are capped at
//! [`MAX_PNG_METADATA_BYTES`].

use std::io::Cursor;
use std::path::Path;

use ::image::codecs::png::PngDecoder;
use ::image::io::Limits;
use ::image::{DynamicImage, ImageError};

use super::border::{find_borders, BinaryImage, BorderKind};
use super::otsu::{histogram, otsu_threshold};
use super::{Orientation, Outline, OutlineError};
use crate::geometry::Point;

/// Which side of the threshold is the shape.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Foreground {
    /// Pixels at or below the threshold (a dark shape on a light background).
    Dark,
    /// Pixels above the threshold (a light shape on a dark background).
    Light,
    /// The class that does not touch the image's border (the background
    /// surrounds the shape); if both do, the one with fewer pixels on the
    /// border; on a tie, the class with fewer pixels, then dark. So a dark
    /// shape covering most of the image is still the shape, and the image
    /// frame never becomes a contour of its own.
    #[default]
    Auto,
}

impl Foreground {
    /// The names accepted on the command line, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["dark", "light", "auto"];

    /// The foreground called `name`.
    pub fn from_name(name: &str) -> Option<Foreground> {
        match name {
            "dark" => Some(Foreground::Dark),
            "light" => Some(Foreground::Light),
            "auto" => Some(Foreground::Auto),
            _ => None,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Foreground::Dark => "dark",
            Foreground::Light => "light",
            Foreground::Auto => "auto",
        }
    }
}

/// Whether the dark class (`≤ t`) is the shape under [`Foreground::Auto`]:
/// the class with fewer pixels on the image's border, then the one with
/// fewer pixels, then dark.
fn dark_is_auto_shape(grey: &GreyImage, t: u8) -> bool {
    let (w, h) = (grey.width, grey.height);
    let dark_at = |x: usize, y: usize| grey.pixels[y * w + x] <= t;
    let mut border = 0usize;
    let mut dark_border = 0usize;
    for y in 0..h {
        for x in 0..w {
            if y == 0 || y + 1 == h || x == 0 || x + 1 == w {
                border += 1;
                dark_border += usize::from(dark_at(x, y));
            }
        }
    }
    let light_border = border - dark_border;
    if dark_border != light_border {
        return dark_border < light_border;
    }
    let dark = grey.pixels.iter().filter(|&&v| v <= t).count();
    2 * dark <= grey.pixels.len()
}

/// How the grey levels are split into two classes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Threshold {
    /// Otsu's (1979) threshold from the image's histogram.
    #[default]
    Otsu,
    /// A fixed level `t`: dark is `≤ t`, light is `> t`.
    Level(u8),
}

/// Which points represent a traced boundary.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BoundaryPoints {
    /// Midpoints of the pixel edges between shape and background
    /// (Dunkelberger & Mitchell 1985), half-integer on one axis.
    #[default]
    MidCrack,
    /// Centres of the border pixels (Suzuki & Abe 1985), integer coordinates.
    PixelCentres,
}

/// Options for turning an image into outlines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageOptions {
    /// Which class is the shape.
    pub foreground: Foreground,
    /// How the threshold is chosen.
    pub threshold: Threshold,
    /// Boundaries enclosing less than this area (shoelace area of the
    /// boundary polygon, in px²) are dropped as noise.
    pub min_area: f64,
    /// Whether hole boundaries (clockwise) are returned too.
    pub holes: bool,
    /// Which points represent a boundary.
    pub points: BoundaryPoints,
}

impl Default for ImageOptions {
    /// Otsu threshold, automatic foreground, a minimum area of 25 px², no
    /// holes, mid-crack points.
    fn default() -> Self {
        ImageOptions {
            foreground: Foreground::Auto,
            threshold: Threshold::Otsu,
            min_area: 25.0,
            holes: false,
            points: BoundaryPoints::MidCrack,
        }
    }
}

/// An 8-bit luminance image, row-major with row 0 at the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GreyImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width · height` grey levels.
    pub pixels: Vec<u8>,
}

/// One boundary of a binarised image in the y-up frame of this module, with
/// its place in the border hierarchy of [`find_borders`].
#[derive(Clone, Debug, PartialEq)]
pub struct Boundary {
    /// The closed outline (outer: counter-clockwise, hole: clockwise).
    pub outline: Outline,
    /// Outer or hole boundary.
    pub kind: BorderKind,
    /// The index of the surrounding boundary in the same list, if any.
    pub parent: Option<usize>,
}

/// The luminance `Y = 0.2126 R + 0.7152 G + 0.0722 B` (ITU-R BT.709) of each
/// pixel, rounded, after compositing over white with its alpha
/// `Y' = αY + (1 − α)·255`; grey images keep their levels exactly.
pub fn luminance(image: &DynamicImage) -> GreyImage {
    let rgba = image.to_rgba8();
    let pixels = rgba
        .pixels()
        .map(|p| {
            let [r, g, b, a] = p.0.map(u32::from);
            let y = (2126 * r + 7152 * g + 722 * b + 5000) / 10000;
            ((y * a + 255 * (255 - a) + 127) / 255) as u8
        })
        .collect();
    GreyImage {
        width: rgba.width() as usize,
        height: rgba.height() as usize,
        pixels,
    }
}

/// [`luminance`] of an owned image, without the RGBA copy for the two
/// common PNG layouts (8-bit grey keeps its levels; 8-bit RGBA is read in
/// place); the same levels as [`luminance`].
fn into_luminance(image: DynamicImage) -> GreyImage {
    let (width, height) = (image.width() as usize, image.height() as usize);
    let pixels = match image {
        DynamicImage::ImageLuma8(g) => g.into_raw(),
        DynamicImage::ImageRgba8(rgba) => rgba
            .pixels()
            .map(|p| {
                let [r, g, b, a] = p.0.map(u32::from);
                let y = (2126 * r + 7152 * g + 722 * b + 5000) / 10000;
                ((y * a + 255 * (255 - a) + 127) / 255) as u8
            })
            .collect(),
        other => return luminance(&other),
    };
    GreyImage {
        width,
        height,
        pixels,
    }
}

/// The most pixels a side of an image may have (PNG allows 2³¹ − 1).
pub const MAX_IMAGE_SIDE: u32 = 1 << 16;

/// The most pixels an image may have: 16,777,216 (4096 × 4096). Reading
/// takes about 20 bytes per pixel for an image of a few shapes (decoded
/// pixels, grey levels, the binary image and the border labels), and up to
/// about 200 for an adversarial one whose every pixel is a border (a
/// checkerboard), so at most about 3.4 GB.
pub const MAX_IMAGE_PIXELS: u64 = 1 << 24;

/// The largest expansion of deflate (RFC 1951), PNG's compression: a
/// length-258 match coded in 2 bits, 258 · 8 / 2 = 1032 bytes out per byte
/// in. The pixel data a header declares must fit in this many times the
/// bytes after the header.
pub const MAX_DEFLATE_RATIO: u64 = 1032;

/// The most the PNG decoder may allocate for ancillary chunks (such as a
/// compressed ICC profile, which could otherwise inflate a tiny file).
pub const MAX_PNG_METADATA_BYTES: u64 = 16 << 20;

/// The 8-byte PNG signature.
const PNG_SIGNATURE: [u8; 8] = [0x89, b'P', b'N', b'G', b'\r', b'\n', 0x1a, b'\n'];

/// Checks the image header (`IHDR`, which must follow the signature)
/// against the limits and the file's size, before anything is decoded;
/// a header the decoder cannot read is left to it to report.
fn check_png_header(bytes: &[u8], path: &Path) -> Result<(), OutlineError> {
    if bytes.len() < 33 || bytes[..8] != PNG_SIGNATURE || &bytes[12..16] != b"IHDR" {
        return Ok(());
    }
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    let (width, height) = (be(16), be(20));
    let (depth, colour) = (bytes[24], bytes[25]);
    if width == 0 || height == 0 {
        return Err(OutlineError::EmptyImage {
            path: path.to_owned(),
            width,
            height,
        });
    }
    let pixels = u64::from(width) * u64::from(height);
    if width > MAX_IMAGE_SIDE || height > MAX_IMAGE_SIDE || pixels > MAX_IMAGE_PIXELS {
        return Err(OutlineError::ImageTooLarge {
            path: path.to_owned(),
            width,
            height,
        });
    }
    let channels = match colour {
        0 | 3 => 1,
        2 => 3,
        4 => 2,
        6 => 4,
        _ => return Ok(()), // the decoder names the bad colour type
    };
    let bits = u64::from(depth) * channels;
    let need = (pixels * bits).div_ceil(8);
    let after = bytes.len() as u64 - 33;
    // A little slack for the shortest streams (a header and one literal).
    let most = MAX_DEFLATE_RATIO * (after + 1);
    if need > most {
        return Err(OutlineError::ImageData {
            path: path.to_owned(),
            width,
            height,
            bits,
            need,
            after,
        });
    }
    Ok(())
}

/// Decodes the PNG file at `path` into luminance (see [`luminance`]).
pub fn load_grey(path: &Path) -> Result<GreyImage, OutlineError> {
    let bytes = std::fs::read(path).map_err(|source| OutlineError::Io {
        path: path.to_owned(),
        source,
    })?;
    grey_from_bytes(&bytes, path)
}

/// Decodes PNG data into luminance (see [`luminance`]) after checking its
/// header against the limits (see the module documentation); `path` only
/// names the source in errors.
pub fn grey_from_bytes(bytes: &[u8], path: &Path) -> Result<GreyImage, OutlineError> {
    let image_error = |e: ImageError| match e {
        ImageError::IoError(source) => OutlineError::Io {
            path: path.to_owned(),
            source,
        },
        ImageError::Unsupported(u) => OutlineError::Image {
            path: path.to_owned(),
            message: format!("{u} (only PNG is supported)"),
        },
        other => OutlineError::Image {
            path: path.to_owned(),
            message: other.to_string(),
        },
    };
    if !bytes.starts_with(&PNG_SIGNATURE) {
        return Err(OutlineError::Image {
            path: path.to_owned(),
            message: "it does not start with the PNG signature (89 50 4E 47 0D 0A 1A 0A)".into(),
        });
    }
    check_png_header(bytes, path)?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(MAX_PNG_METADATA_BYTES);
    let decoder = PngDecoder::with_limits(Cursor::new(bytes), limits).map_err(image_error)?;
    let decoded = DynamicImage::from_decoder(decoder).map_err(image_error)?;
    Ok(into_luminance(decoded))
}

/// The binary image of the shape, with the threshold used: Otsu's or the
/// fixed level, then the foreground class; `None` when Otsu finds no
/// threshold (a single grey level).
pub fn binarize(grey: &GreyImage, options: &ImageOptions) -> Option<(BinaryImage, u8)> {
    let t = match options.threshold {
        Threshold::Otsu => otsu_threshold(&histogram(&grey.pixels))?,
        Threshold::Level(t) => t,
    };
    let dark_is_shape = match options.foreground {
        Foreground::Dark => true,
        Foreground::Light => false,
        Foreground::Auto => dark_is_auto_shape(grey, t),
    };
    let data = grey
        .pixels
        .iter()
        .map(|&v| (v <= t) == dark_is_shape)
        .collect();
    let binary = BinaryImage::new(grey.width, grey.height, data)?;
    Some((binary, t))
}

/// Every boundary of `binary` as a closed outline in the y-up frame (pixel
/// `(col, row)` centred at `(col, H − 1 − row)`), made of `points`,
/// consecutive duplicates removed, outer boundaries counter-clockwise and
/// holes clockwise.
pub fn boundaries(binary: &BinaryImage, points: BoundaryPoints) -> Vec<Boundary> {
    let top = binary.height() as f64 - 1.0;
    find_borders(binary)
        .into_iter()
        .map(|b| {
            let points = match points {
                BoundaryPoints::PixelCentres => b
                    .pixels
                    .iter()
                    .map(|&(c, r)| Point::new(c as f64, top - r as f64))
                    .collect(),
                BoundaryPoints::MidCrack => b
                    .cracks
                    .iter()
                    .map(|&(c, r, side)| {
                        let (dc, dr) = side.offset();
                        Point::new(c as f64 + dc, top - (r as f64 + dr))
                    })
                    .collect(),
            };
            let mut outline = Outline::new(points, true);
            outline.dedup();
            outline.orient(match b.kind {
                BorderKind::Outer => Orientation::CounterClockwise,
                BorderKind::Hole => Orientation::Clockwise,
            });
            Boundary {
                outline,
                kind: b.kind,
                parent: b.parent,
            }
        })
        .collect()
}

/// The outer boundaries of `binary` (and its holes when `options.holes`)
/// enclosing at least `options.min_area` px², by decreasing area (ties in
/// raster order of their first pixel).
pub fn select_outlines(binary: &BinaryImage, options: &ImageOptions) -> Vec<Outline> {
    let mut kept: Vec<(f64, Outline)> = boundaries(binary, options.points)
        .into_iter()
        .filter(|b| options.holes || b.kind == BorderKind::Outer)
        .map(|b| (b.outline.area(), b.outline))
        .filter(|(a, _)| *a >= options.min_area)
        .collect();
    kept.sort_by(|a, b| b.0.total_cmp(&a.0));
    kept.into_iter().map(|(_, o)| o).collect()
}

/// The outlines of the shapes in `grey` (see [`select_outlines`]); `path`
/// only names the source in errors.
pub fn grey_outlines(
    grey: &GreyImage,
    options: &ImageOptions,
    path: &Path,
) -> Result<Vec<Outline>, OutlineError> {
    if grey.width == 0 || grey.height == 0 {
        return Err(OutlineError::EmptyImage {
            path: path.to_owned(),
            width: grey.width as u32,
            height: grey.height as u32,
        });
    }
    if grey.pixels.len() != grey.width * grey.height {
        return Err(OutlineError::Image {
            path: path.to_owned(),
            message: format!(
                "{} grey levels for {}×{} pixels",
                grey.pixels.len(),
                grey.width,
                grey.height
            ),
        });
    }
    let (binary, _) = binarize(grey, options).ok_or_else(|| OutlineError::UniformImage {
        path: path.to_owned(),
        level: grey.pixels[0],
    })?;
    let outlines = select_outlines(&binary, options);
    if outlines.is_empty() {
        let largest = boundaries(&binary, options.points)
            .iter()
            .filter(|b| options.holes || b.kind == BorderKind::Outer)
            .map(|b| b.outline.area())
            .fold(0.0, f64::max);
        return Err(OutlineError::NoShape {
            path: path.to_owned(),
            min_area: options.min_area,
            largest,
        });
    }
    Ok(outlines)
}

/// The outlines of the shapes in the PNG file at `path`: luminance, threshold,
/// border following, minimum-area filter, by decreasing area.
pub fn load_image(path: &Path, options: &ImageOptions) -> Result<Vec<Outline>, OutlineError> {
    let grey = load_grey(path)?;
    grey_outlines(&grey, options, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grey(rows: &[&str]) -> GreyImage {
        let pixels = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| if b == b'#' { 20 } else { 230 }))
            .collect();
        GreyImage {
            width: rows[0].len(),
            height: rows.len(),
            pixels,
        }
    }

    fn pts(p: &[(f64, f64)]) -> Vec<Point> {
        p.iter().map(|&q| q.into()).collect()
    }

    #[test]
    fn a_filled_rectangle_gives_its_border_loop() {
        // 8 × 6 image, rectangle on columns 2..=5, rows 1..=3: y = 5 − row.
        let g = grey(&[
            "........", "..####..", "..####..", "..####..", "........", "........",
        ]);
        let opts = ImageOptions {
            min_area: 1.0,
            points: BoundaryPoints::PixelCentres,
            ..ImageOptions::default()
        };
        let out = grey_outlines(&g, &opts, Path::new("rect.png")).unwrap();
        assert_eq!(out.len(), 1);
        let o = &out[0];
        assert!(o.closed);
        assert_eq!(
            o.points,
            pts(&[
                (2.0, 4.0),
                (2.0, 3.0),
                (2.0, 2.0),
                (3.0, 2.0),
                (4.0, 2.0),
                (5.0, 2.0),
                (5.0, 3.0),
                (5.0, 4.0),
                (4.0, 4.0),
                (3.0, 4.0),
            ])
        );
        assert_eq!(o.signed_area(), 6.0);
        assert_eq!(o.orientation(), Orientation::CounterClockwise);
        // Mid-crack points: the 14 pixel-edge midpoints, enclosing 12 − ½ px².
        let opts = ImageOptions {
            points: BoundaryPoints::MidCrack,
            ..opts
        };
        let out = grey_outlines(&g, &opts, Path::new("rect.png")).unwrap();
        let o = &out[0];
        assert_eq!(
            o.points,
            pts(&[
                (2.0, 4.5),
                (1.5, 4.0),
                (1.5, 3.0),
                (1.5, 2.0),
                (2.0, 1.5),
                (3.0, 1.5),
                (4.0, 1.5),
                (5.0, 1.5),
                (5.5, 2.0),
                (5.5, 3.0),
                (5.5, 4.0),
                (5.0, 4.5),
                (4.0, 4.5),
                (3.0, 4.5),
            ])
        );
        assert_eq!(o.signed_area(), 11.5);
    }

    #[test]
    fn a_ring_gives_the_outer_loop_and_optionally_the_hole() {
        let g = grey(&[
            ".........",
            ".#######.",
            ".#######.",
            ".##...##.",
            ".##...##.",
            ".#######.",
            ".#######.",
            ".........",
        ]);
        let mut opts = ImageOptions {
            min_area: 1.0,
            foreground: Foreground::Dark,
            points: BoundaryPoints::PixelCentres,
            ..ImageOptions::default()
        };
        let out = grey_outlines(&g, &opts, Path::new("ring.png")).unwrap();
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].signed_area(), 30.0);
        opts.holes = true;
        let out = grey_outlines(&g, &opts, Path::new("ring.png")).unwrap();
        assert_eq!(out.len(), 2);
        // The hole border runs clockwise through the ring's pixels next to the
        // hole, cutting the four diagonal corners: 4 × 3 − 4 × ½ px².
        assert_eq!(out[1].signed_area(), -10.0);
        assert_eq!(out[1].orientation(), Orientation::Clockwise);
        let (lo, hi) = out[1].bbox().unwrap();
        assert_eq!((lo, hi), (Point::new(2.0, 2.0), Point::new(6.0, 5.0)));
        // Mid-crack: both polygons cut the four corners of their pixel-edge
        // rectangles, 7 × 6 − ½ and 3 × 2 − ½.
        opts.points = BoundaryPoints::MidCrack;
        let out = grey_outlines(&g, &opts, Path::new("ring.png")).unwrap();
        assert_eq!(out[0].signed_area(), 41.5);
        assert_eq!(out[1].signed_area(), -5.5);
    }

    #[test]
    fn blobs_are_sorted_by_area_and_filtered() {
        let g = grey(&[
            "...........",
            ".##....###.",
            ".##....###.",
            ".......###.",
            "...........",
        ]);
        let mut opts = ImageOptions {
            min_area: 0.5,
            foreground: Foreground::Dark,
            points: BoundaryPoints::PixelCentres,
            ..ImageOptions::default()
        };
        let out = grey_outlines(&g, &opts, Path::new("blobs.png")).unwrap();
        assert_eq!(out.len(), 2);
        assert_eq!(out[0].area(), 4.0);
        assert_eq!(out[1].area(), 1.0);
        assert_eq!(out[1].bbox().unwrap().0, Point::new(1.0, 2.0));
        opts.min_area = 2.0;
        let out = grey_outlines(&g, &opts, Path::new("blobs.png")).unwrap();
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].area(), 4.0);
        opts.min_area = 100.0;
        let e = grey_outlines(&g, &opts, Path::new("blobs.png")).unwrap_err();
        assert!(matches!(e, OutlineError::NoShape { largest, .. } if largest == 4.0));
        assert!(e.to_string().starts_with("blobs.png: no shape"), "{e}");
    }

    #[test]
    fn foreground_choice() {
        // Dark touches the border here, so Auto picks the light square.
        let g = grey(&["####", "#..#", "#..#", "####"]);
        let opts = ImageOptions {
            min_area: 0.0,
            ..ImageOptions::default()
        };
        let (b, t) = binarize(&g, &opts).unwrap();
        assert_eq!(t, 124);
        assert_eq!(b.count(), 4);
        let dark = ImageOptions {
            foreground: Foreground::Dark,
            ..opts
        };
        assert_eq!(binarize(&g, &dark).unwrap().0.count(), 12);
        let fixed = ImageOptions {
            threshold: Threshold::Level(10),
            foreground: Foreground::Dark,
            ..opts
        };
        assert_eq!(
            binarize(&g, &fixed).unwrap(),
            (BinaryImage::from_fn(4, 4, |_, _| false), 10)
        );
        // A dark shape covering most of the image, on a light frame: the
        // dark class is the majority but does not touch the border, so it
        // is the shape (the minority rule traced the frame).
        let big = grey(&["......", ".####.", ".####.", ".####.", "......"]);
        let (b, _) = binarize(&big, &opts).unwrap();
        assert_eq!(b.count(), 12);
        let outlines = select_outlines(&b, &opts);
        assert_eq!(outlines.len(), 1);
        // Both classes on the border: the one with fewer border pixels.
        let half = grey(&["##....", "##....", "##...."]);
        assert_eq!(binarize(&half, &opts).unwrap().0.count(), 6);
        for n in Foreground::NAMES {
            assert_eq!(Foreground::from_name(n).unwrap().name(), n);
        }
    }

    #[test]
    fn uniform_and_empty_images_are_errors() {
        let g = GreyImage {
            width: 3,
            height: 2,
            pixels: vec![9; 6],
        };
        let e = grey_outlines(&g, &ImageOptions::default(), Path::new("u.png")).unwrap_err();
        assert!(
            matches!(e, OutlineError::UniformImage { level: 9, .. }),
            "{e}"
        );
        let g = GreyImage {
            width: 0,
            height: 0,
            pixels: vec![],
        };
        let e = grey_outlines(&g, &ImageOptions::default(), Path::new("e.png")).unwrap_err();
        assert!(
            e.to_string().contains("e.png: the image is empty (0×0"),
            "{e}"
        );
        let g = GreyImage {
            width: 2,
            height: 2,
            pixels: vec![],
        };
        let e = grey_outlines(&g, &ImageOptions::default(), Path::new("m.png")).unwrap_err();
        assert!(
            e.to_string().contains("0 grey levels for 2×2 pixels"),
            "{e}"
        );
    }

    #[test]
    fn luminance_of_colour_and_alpha() {
        use ::image::{Rgba, RgbaImage};
        let mut img = RgbaImage::new(3, 1);
        img.put_pixel(0, 0, Rgba([255, 0, 0, 255]));
        img.put_pixel(1, 0, Rgba([77, 77, 77, 255]));
        img.put_pixel(2, 0, Rgba([0, 0, 0, 0]));
        let g = luminance(&DynamicImage::ImageRgba8(img));
        assert_eq!(g.pixels, vec![54, 77, 255]);
    }
}
