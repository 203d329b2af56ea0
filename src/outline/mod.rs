//! Outline input: ordered boundary points from images, CSV point lists and
//! font glyphs, and their segmentation at corners.

mod border;
mod error;
mod image;
mod otsu;
mod polygon;

pub use self::image::{
    binarize, boundaries, grey_outlines, load_grey, load_image, luminance, select_outlines,
    Boundary, BoundaryPoints, Foreground, GreyImage, ImageOptions, Threshold,
};
pub use border::{find_borders, BinaryImage, Border, BorderKind, Side};
pub use error::OutlineError;
pub use otsu::{histogram, otsu_threshold};
pub use polygon::{Orientation, Outline};
