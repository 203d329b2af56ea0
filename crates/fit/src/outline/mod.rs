//! Outline input: ordered boundary points from PNG images, CSV point lists
//! and font glyphs, and their segmentation at corners, as data for curve
//! reconstruction.
//!
//! One concept per module, in the style of [`crate::geometry`]:
//! [`Outline`] (the ordered points), Otsu thresholding and Suzuki–Abe
//! border following for images, CSV point lists, exact glyph outlines
//! (TrueType quadratic, CFF cubic) with their dense sampling and true break
//! points, corner detection, the `*.png` / `*.csv` / `font:PATH:GLYPH`
//! input strings of the command line, and the paths of SVG files (other
//! tools' curves, to be scored against the same points).
//!
//! Every outline is in a y-up frame. Image pixel `(col, row)` of an image of
//! height `H` is the point `(col, H − 1 − row)`; CSV coordinates are taken as
//! given; glyphs are in font units. Outer boundaries run counter-clockwise.
//!
//! ```no_run
//! use metabezier_fit::outline::{load, parse_input, Options};
//!
//! let input = parse_input("data/outlines/horse.png")?;
//! let outlines = load(&input, &Options::default())?;
//! println!("{} points", outlines[0].len());
//! # Ok::<(), metabezier_fit::outline::OutlineError>(())
//! ```

mod border;
mod corners;
mod csv_error;
mod csv_points;
mod error;
mod glyph;
mod image;
mod input;
mod noise;
mod otsu;
mod svg;

pub use self::image::{
    binarize, boundaries, grey_from_bytes, grey_outlines, load_grey, load_image, luminance,
    select_outlines, Boundary, BoundaryPoints, Foreground, GreyImage, ImageOptions, Threshold,
    MAX_DEFLATE_RATIO, MAX_IMAGE_PIXELS, MAX_IMAGE_SIDE, MAX_PNG_METADATA_BYTES,
};
pub use crate::geometry::Orientation;
pub use border::{find_borders, BinaryImage, Border, BorderKind, Side};
pub use corners::{find_corners, split_at, turning_angles, CornerOptions};
pub use csv_error::CsvError;
pub use csv_points::{
    csv_from_bytes, load_csv, outline_from_points, CsvOptions, MAX_COORDINATE, MAX_CSV_LINE_BYTES,
    MAX_CSV_POINTS, MIN_EXTENT, MIN_RELATIVE_EXTENT,
};
pub use error::OutlineError;
pub use glyph::{
    glyph_from_bytes, load_glyph, Glyph, SampledContour, Sampling, Segment, CORNER_DEGREES,
    MAX_GLYPH_COMPONENTS, MAX_GLYPH_CONTOURS, MAX_GLYPH_SAMPLES, MAX_GLYPH_SEGMENTS,
};
pub use input::{load, parse_glyph, parse_input, Input, Options};
pub use noise::noise_level;
pub use otsu::{histogram, otsu_threshold};
pub use svg::{load_svg, svg_from_str, SvgError, SvgPaths, SvgProblem, NON_RENDERED};

/// An outline: the ordered boundary points of a shape in an image or a
/// glyph, a [`Polyline`](crate::geometry::Polyline) (outer boundaries run
/// counter-clockwise, holes clockwise, so the shape is on the left).
pub type Outline = crate::geometry::Polyline;
