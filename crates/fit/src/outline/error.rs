//! Errors raised while reading an outline from an image, a CSV file or a font.

use std::fmt;
use std::io;
use std::path::{Path, PathBuf};

use super::image::MAX_DEFLATE_RATIO;

/// Why an outline could not be loaded; every message names the file and says
/// what was expected. None of these is a panic.
#[derive(Debug)]
pub enum OutlineError {
    /// The input string is not `*.png`, `*.csv` or `font:PATH:GLYPH`.
    BadInput {
        /// The input string as given.
        input: String,
        /// What is wrong with it.
        message: String,
    },
    /// A file could not be opened or read.
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: io::Error,
    },
    /// An image file could not be decoded (corrupt, truncated or not a PNG).
    Image {
        /// The file.
        path: PathBuf,
        /// The decoder's explanation.
        message: String,
    },
    /// An image has no pixels (a width or height of 0).
    EmptyImage {
        /// The file.
        path: PathBuf,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// An image is larger than [`crate::outline::MAX_IMAGE_SIDE`] a side or
    /// [`crate::outline::MAX_IMAGE_PIXELS`] in all.
    ImageTooLarge {
        /// The file.
        path: PathBuf,
        /// Width in pixels, as the header declares it.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// The pixel data a PNG header declares cannot fit in the rest of the
    /// file, even at deflate's largest expansion
    /// ([`crate::outline::MAX_DEFLATE_RATIO`]).
    ImageData {
        /// The file.
        path: PathBuf,
        /// Width in pixels, as the header declares it.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// Bits per pixel.
        bits: u64,
        /// Bytes of pixel data declared.
        need: u64,
        /// Bytes in the file after the header.
        after: u64,
    },
    /// Every pixel has the same grey level, so no threshold separates a shape
    /// from the background.
    UniformImage {
        /// The file.
        path: PathBuf,
        /// The single grey level (0–255).
        level: u8,
    },
    /// No foreground boundary is left after the minimum-area filter.
    NoShape {
        /// The file.
        path: PathBuf,
        /// The minimum area asked for, in px².
        min_area: f64,
        /// The area of the largest boundary found, in px² (0 if none).
        largest: f64,
    },
    /// A font file could not be parsed.
    Font {
        /// The font file.
        path: PathBuf,
        /// The parser's explanation.
        message: String,
    },
    /// The font file is cut short or its tables cannot be used (the
    /// message says which).
    MalformedFont {
        /// The font file.
        path: PathBuf,
        /// What is wrong, starting "the font file is truncated", "the font
        /// file is malformed" or "the font has".
        message: String,
    },
    /// The glyph's outline data cannot be read.
    MalformedGlyph {
        /// The font file.
        path: PathBuf,
        /// The character asked for.
        glyph: char,
        /// Its glyph id in the font.
        id: u16,
        /// The table holding its outline (`glyf` or `CFF `).
        table: String,
        /// What the font parser reports.
        reported: String,
    },
    /// A glyph goes beyond a limit of this reader
    /// ([`crate::outline::MAX_GLYPH_SEGMENTS`],
    /// [`crate::outline::MAX_GLYPH_CONTOURS`],
    /// [`crate::outline::MAX_GLYPH_COMPONENTS`],
    /// [`crate::outline::MAX_GLYPH_SAMPLES`]).
    GlyphLimit {
        /// The font file.
        path: PathBuf,
        /// The character asked for.
        glyph: char,
        /// What is counted (`segments`, `contours`, `component references`,
        /// `sample points`).
        what: &'static str,
        /// How many were found (at least).
        found: u64,
        /// The limit.
        limit: u64,
    },
    /// The font has no glyph for the character.
    MissingGlyph {
        /// The font file.
        path: PathBuf,
        /// The character asked for.
        glyph: char,
    },
    /// The glyph exists but has no outline (such as a space).
    NoOutline {
        /// The font file.
        path: PathBuf,
        /// The character asked for.
        glyph: char,
    },
    /// A CSV file has fewer points than needed.
    TooFewPoints {
        /// The CSV file.
        path: PathBuf,
        /// Points found (after dropping a closing duplicate).
        found: usize,
        /// Points needed.
        need: usize,
    },
    /// A CSV outline file could not be read: its line, column and why.
    Csv(super::CsvError),
    /// The paths of an SVG file could not be read.
    Svg(super::SvgError),
    /// A contour number beyond the input's contours.
    ContourOutOfRange {
        /// The input as given (a file or `font:PATH:GLYPH`).
        input: String,
        /// The contour asked for.
        asked: usize,
        /// How many contours the input has.
        count: usize,
    },
}

/// `'g' (U+0067)`: a character with its code point, so that invisible or
/// look-alike characters are unambiguous in messages.
pub(crate) fn describe_char(c: char) -> String {
    if c.is_control() || c.is_whitespace() {
        format!("U+{:04X}", c as u32)
    } else {
        format!("'{c}' (U+{:04X})", c as u32)
    }
}

impl fmt::Display for OutlineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::BadInput { input, message } => write!(f, "input \"{input}\": {message}"),
            Self::Io { path, source } => write!(f, "{}: cannot read: {source}", path.display()),
            Self::Image { path, message } => write!(
                f,
                "{}: cannot decode the image (expected a PNG file): {message}",
                path.display()
            ),
            Self::EmptyImage {
                path,
                width,
                height,
            } => write!(
                f,
                "{}: the image is empty ({width}×{height} pixels); expected at least 1×1",
                path.display()
            ),
            Self::ImageTooLarge {
                path,
                width,
                height,
            } => write!(
                f,
                "{}: the PNG header declares {width}×{height} pixels, beyond this reader's limits \
                 of 65536 pixels a side and 16777216 (4096×4096) in all",
                path.display()
            ),
            Self::ImageData {
                path,
                width,
                height,
                bits,
                need,
                after,
            } => image_data(f, path, (*width, *height), *bits, (*need, *after)),
            Self::UniformImage { path, level } => write!(
                f,
                "{}: every pixel has grey level {level}, so no threshold separates a shape \
                 from the background",
                path.display()
            ),
            Self::NoShape {
                path,
                min_area,
                largest,
            } => write!(
                f,
                "{}: no shape with an area of at least {min_area} px² (the largest boundary \
                 found encloses {largest} px²); lower the minimum area or check the foreground \
                 setting",
                path.display()
            ),
            Self::Font { path, message } => write!(
                f,
                "{}: cannot read the font (expected a TrueType or OpenType file): {message}",
                path.display()
            ),
            Self::MalformedFont { path, message } => write!(f, "{}: {message}", path.display()),
            Self::MalformedGlyph {
                path,
                glyph,
                id,
                table,
                reported,
            } => malformed_glyph(f, path, *glyph, (*id, table), reported),
            Self::GlyphLimit {
                path,
                glyph,
                what,
                found,
                limit,
            } => glyph_limit(f, path, *glyph, what, (*found, *limit)),
            Self::MissingGlyph { path, glyph } => write!(
                f,
                "{}: the font has no glyph for {}",
                path.display(),
                describe_char(*glyph)
            ),
            Self::NoOutline { path, glyph } => write!(
                f,
                "{}: the glyph for {} has no outline (nothing to reconstruct)",
                path.display(),
                describe_char(*glyph)
            ),
            Self::TooFewPoints { path, found, need } => write!(
                f,
                "{}: {found} point(s) found, but an outline needs at least {need}",
                path.display()
            ),
            Self::Svg(e) => write!(f, "{e}"),
            Self::ContourOutOfRange {
                input,
                asked,
                count,
            } => contour_out_of_range(f, input, *asked, *count),
            Self::Csv(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for OutlineError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Io { source, .. } => Some(source),
            Self::Svg(e) => std::error::Error::source(e),
            Self::Csv(e) => std::error::Error::source(e),
            _ => None,
        }
    }
}

/// The message of [`OutlineError::ContourOutOfRange`]: contour `asked`
/// of an input with `count` contours.
fn contour_out_of_range(
    f: &mut fmt::Formatter<'_>,
    input: &str,
    asked: usize,
    count: usize,
) -> fmt::Result {
    write!(
        f,
        "{input}: contour {asked} was asked for, but the input has {count} contour{} \
         (numbered from 0 by decreasing area: 0..={}); to fit them all, leave --contour \
         out (or write contour = \"all\" in a spec)",
        if count == 1 { "" } else { "s" },
        count.saturating_sub(1)
    )
}

/// The message of [`OutlineError::ImageData`]: the PNG header's `size`
/// (width, height) at `bits` per pixel needs `need` bytes, which the
/// `after` bytes after the header cannot decompress to.
fn image_data(
    f: &mut fmt::Formatter<'_>,
    path: &Path,
    (width, height): (u32, u32),
    bits: u64,
    (need, after): (u64, u64),
) -> fmt::Result {
    write!(
        f,
        "{}: the PNG header declares {width}×{height} pixels at {bits} bits each, \
         {need} bytes of pixel data, but the {after} bytes after the header decompress \
         to at most {} (deflate expands at most 1032:1): the file is truncated or its \
         header is corrupt",
        path.display(),
        MAX_DEFLATE_RATIO * (after + 1)
    )
}

/// The message of [`OutlineError::MalformedGlyph`]: the outline of the
/// glyph for `glyph` (glyph id, table) cannot be read.
fn malformed_glyph(
    f: &mut fmt::Formatter<'_>,
    path: &Path,
    glyph: char,
    (id, table): (u16, &str),
    reported: &str,
) -> fmt::Result {
    write!(
        f,
        "{}: the font file is malformed: the outline of the glyph for {}, glyph id {id} \
         in table '{table}', cannot be read: {reported}",
        path.display(),
        describe_char(glyph)
    )
}

/// The message of [`OutlineError::GlyphLimit`]: at least `found` of
/// `what`, beyond the reader's `limit`.
fn glyph_limit(
    f: &mut fmt::Formatter<'_>,
    path: &Path,
    glyph: char,
    what: &str,
    (found, limit): (u64, u64),
) -> fmt::Result {
    write!(
        f,
        "{}: the glyph for {} has at least {found} {what}, beyond this reader's limit of \
         {limit} per glyph (the font is malformed, or far beyond any real glyph)",
        path.display(),
        describe_char(glyph)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_file_and_the_place() {
        let e = OutlineError::Csv(crate::outline::CsvError::Number {
            path: "pts.csv".into(),
            line: 7,
            column: 2,
            text: "abc".into(),
        });
        assert_eq!(
            e.to_string(),
            "pts.csv:7: column 2 (y): expected a finite number, found \"abc\""
        );
        let e = OutlineError::MissingGlyph {
            path: "f.otf".into(),
            glyph: '漢',
        };
        assert_eq!(
            e.to_string(),
            "f.otf: the font has no glyph for '漢' (U+6F22)"
        );
        let e = OutlineError::NoOutline {
            path: "f.otf".into(),
            glyph: ' ',
        };
        assert!(e.to_string().contains("U+0020"), "{e}");
    }
}
