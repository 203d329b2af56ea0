//! The outline input named on the command line: `*.png`, `*.csv` or
//! `font:PATH:GLYPH`, and its loading.

use std::path::PathBuf;

use super::csv_points::{load_csv, CsvOptions};
use super::glyph::{load_glyph, Sampling};
use super::image::{load_image, ImageOptions};
use super::{Outline, OutlineError};

/// Where an outline comes from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Input {
    /// A PNG image (see [`load_image`]).
    Image(PathBuf),
    /// A CSV point list (see [`load_csv`]).
    Csv(PathBuf),
    /// One glyph of a TrueType/OpenType font (see [`load_glyph`]).
    Glyph {
        /// The font file.
        font: PathBuf,
        /// The character.
        glyph: char,
    },
}

/// Options for [`load`], one group per kind of input.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Options {
    /// For images.
    pub image: ImageOptions,
    /// For CSV point lists.
    pub csv: CsvOptions,
    /// The sampling of glyph contours.
    pub glyph: Sampling,
}

/// Parses a glyph given as one character (`g`) or a code point (`U+0067`).
pub fn parse_glyph(s: &str) -> Option<char> {
    let mut chars = s.chars();
    if let (Some(c), None) = (chars.next(), chars.next()) {
        return Some(c);
    }
    let hex = s.strip_prefix("U+").or_else(|| s.strip_prefix("u+"))?;
    if hex.is_empty() || hex.len() > 6 || !hex.bytes().all(|b| b.is_ascii_hexdigit()) {
        return None;
    }
    u32::from_str_radix(hex, 16).ok().and_then(char::from_u32)
}

/// Parses an input string: `font:PATH:GLYPH` (the glyph after the last
/// colon, so `font:a.ttf::` is the colon), otherwise a path ending in `.png`
/// or `.csv` (any case).
pub fn parse_input(s: &str) -> Result<Input, OutlineError> {
    let bad = |message: String| OutlineError::BadInput {
        input: s.to_string(),
        message,
    };
    if let Some(rest) = s.strip_prefix("font:") {
        let (font, glyph) = match rest.rsplit_once(':') {
            Some((f, "")) if f.ends_with(':') => (&f[..f.len() - 1], ":"),
            Some(pair) => pair,
            None => {
                return Err(bad(
                    "expected font:PATH:GLYPH, such as font:DejaVuSans.ttf:g".into(),
                ))
            }
        };
        if font.is_empty() {
            return Err(bad(
                "the font path is empty; expected font:PATH:GLYPH".into()
            ));
        }
        let glyph = parse_glyph(glyph).ok_or_else(|| {
            bad(format!(
                "glyph \"{glyph}\": expected one character (such as g) or a code point (such as U+0067)"
            ))
        })?;
        return Ok(Input::Glyph {
            font: PathBuf::from(font),
            glyph,
        });
    }
    let lower = s.to_ascii_lowercase();
    if lower.ends_with(".png") {
        Ok(Input::Image(PathBuf::from(s)))
    } else if lower.ends_with(".csv") {
        Ok(Input::Csv(PathBuf::from(s)))
    } else {
        Err(bad(
            "expected a .png image, a .csv point list or font:PATH:GLYPH".into(),
        ))
    }
}

/// Loads the outlines of `input`: an image's shapes by decreasing area, a
/// CSV file's single outline, or a glyph's sampled contours in font order.
pub fn load(input: &Input, options: &Options) -> Result<Vec<Outline>, OutlineError> {
    match input {
        Input::Image(path) => load_image(path, &options.image),
        Input::Csv(path) => Ok(vec![load_csv(path, &options.csv)?]),
        Input::Glyph { font, glyph } => {
            let g = load_glyph(font, *glyph)?;
            g.check_sample_count(options.glyph, 1)?;
            Ok(g.outlines(options.glyph))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_three_kinds() {
        assert_eq!(
            parse_input("data/horse.PNG").unwrap(),
            Input::Image("data/horse.PNG".into())
        );
        assert_eq!(
            parse_input("pts.csv").unwrap(),
            Input::Csv("pts.csv".into())
        );
        assert_eq!(
            parse_input("font:fonts/DejaVuSans.ttf:g").unwrap(),
            Input::Glyph {
                font: "fonts/DejaVuSans.ttf".into(),
                glyph: 'g'
            }
        );
        assert_eq!(
            parse_input("font:C:\\fonts\\a.otf:U+00e9").unwrap(),
            Input::Glyph {
                font: "C:\\fonts\\a.otf".into(),
                glyph: 'é'
            }
        );
        assert_eq!(
            parse_input("font:a.ttf::").unwrap(),
            Input::Glyph {
                font: "a.ttf".into(),
                glyph: ':'
            }
        );
    }

    #[test]
    fn rejects_what_it_cannot_read() {
        let e = parse_input("shape.jpg").unwrap_err();
        assert_eq!(
            e.to_string(),
            "input \"shape.jpg\": expected a .png image, a .csv point list or font:PATH:GLYPH"
        );
        let e = parse_input("font:a.ttf:gg").unwrap_err();
        assert!(
            e.to_string()
                .contains("glyph \"gg\": expected one character"),
            "{e}"
        );
        assert!(parse_input("font:a.ttf").is_err());
        assert!(parse_input("font::g").is_err());
        assert!(parse_input("font:a.ttf:U+D800").is_err());
        assert!(parse_input("font:a.ttf:").is_err());
        assert_eq!(parse_glyph("U+1F600"), Some('😀'));
    }
}
