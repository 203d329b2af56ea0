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

use std::path::Path;

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
    /// The class with fewer pixels (a shape is usually smaller than its
    /// background); the dark class on a tie.
    #[default]
    Auto,
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

/// Decodes the PNG file at `path` into luminance (see [`luminance`]).
pub fn load_grey(path: &Path) -> Result<GreyImage, OutlineError> {
    let reader = ::image::io::Reader::open(path).map_err(|source| OutlineError::Io {
        path: path.to_owned(),
        source,
    })?;
    let reader = reader
        .with_guessed_format()
        .map_err(|source| OutlineError::Io {
            path: path.to_owned(),
            source,
        })?;
    let decoded = reader.decode().map_err(|e| match e {
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
    })?;
    Ok(luminance(&decoded))
}

/// The binary image of the shape, with the threshold used: Otsu's or the
/// fixed level, then the foreground class; `None` when Otsu finds no
/// threshold (a single grey level).
pub fn binarize(grey: &GreyImage, options: &ImageOptions) -> Option<(BinaryImage, u8)> {
    let t = match options.threshold {
        Threshold::Otsu => otsu_threshold(&histogram(&grey.pixels))?,
        Threshold::Level(t) => t,
    };
    let dark = grey.pixels.iter().filter(|&&v| v <= t).count();
    let dark_is_shape = match options.foreground {
        Foreground::Dark => true,
        Foreground::Light => false,
        Foreground::Auto => 2 * dark <= grey.pixels.len(),
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
        // Dark is the majority here, so Auto picks the light square.
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
