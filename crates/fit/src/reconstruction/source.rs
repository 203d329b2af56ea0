//! Where the data points come from: an input's contours (outer boundaries
//! and holes, with their orientation), which of them are fitted, and the
//! parameterisation a source calls for.

use std::path::{Path, PathBuf};

use crate::geometry::{Orientation, Parameterisation};
use crate::outline::{
    load_glyph, load_image, parse_input, ImageOptions, Input, Outline, OutlineError, Sampling,
};

/// Which contours of an input are fitted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContourChoice {
    /// Every contour: outer boundaries and holes.
    #[default]
    All,
    /// One contour, by its number in the input's list (by decreasing area;
    /// 0 is the largest).
    Index(usize),
}

impl ContourChoice {
    /// `all` or the index.
    pub fn name(self) -> String {
        match self {
            ContourChoice::All => "all".into(),
            ContourChoice::Index(k) => k.to_string(),
        }
    }
}

/// How an input is read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Which contours.
    pub contour: ContourChoice,
    /// For images: threshold, foreground, minimum area; holes are always
    /// listed (the contour numbers count them).
    pub image: ImageOptions,
    /// For glyphs: the sampling of each segment.
    pub sampling: Sampling,
    /// For glyphs: at least this many samples on every segment (so a fit at
    /// the glyph's own breaks has enough points however short a segment is).
    pub min_samples_per_segment: usize,
}

impl Default for LoadOptions {
    /// All contours, the default image options, 1/200 em glyph spacing, at
    /// least one sample per segment.
    fn default() -> Self {
        LoadOptions {
            contour: ContourChoice::All,
            image: ImageOptions::default(),
            sampling: Sampling::default(),
            min_samples_per_segment: 1,
        }
    }
}

/// One contour of a source.
#[derive(Clone, Debug)]
pub struct SourceContour {
    /// Its number in the input's list of contours (by decreasing area).
    pub index: usize,
    /// Its points (closed; outer boundaries counter-clockwise, holes
    /// clockwise).
    pub outline: Outline,
    /// For a glyph, the sampled indices where its exact segments start.
    pub true_breaks: Option<Vec<usize>>,
    /// For a glyph, those of `true_breaks` that are corners.
    pub true_corners: Option<Vec<usize>>,
}

impl SourceContour {
    /// Counter-clockwise (an outer boundary) or clockwise (a hole).
    pub fn orientation(&self) -> Orientation {
        self.outline.orientation()
    }
}

/// The data points of an input, with the contours chosen.
#[derive(Clone, Debug)]
pub struct Source {
    /// The input as the user wrote it (`horse.png`, `pts.csv`,
    /// `font:PATH:GLYPH`).
    pub input: String,
    /// The parsed input, with paths resolved.
    pub parsed: Input,
    /// The contours fitted, in the input's order (by decreasing area).
    pub contours: Vec<SourceContour>,
    /// How many contours the input has.
    pub available: usize,
    /// For a glyph, its height (font units), the scale of its errors.
    pub glyph_height: Option<f64>,
}

/// A source could not be read; the outline error says why (and is its
/// [`std::error::Error::source`]).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct SourceError(#[from] pub OutlineError);

/// Every contour of `parsed` by decreasing area, with a glyph's true breaks
/// and corners, and the glyph's height.
type Contours = (Vec<SourceContour>, Option<f64>);

fn all_contours(parsed: &Input, options: &LoadOptions) -> Result<Contours, OutlineError> {
    let plain = |outlines: Vec<Outline>| -> Vec<SourceContour> {
        outlines
            .into_iter()
            .enumerate()
            .map(|(index, outline)| SourceContour {
                index,
                outline,
                true_breaks: None,
                true_corners: None,
            })
            .collect()
    };
    Ok(match parsed {
        Input::Image(path) => {
            let image = ImageOptions {
                holes: true,
                ..options.image
            };
            (plain(load_image(path, &image)?), None)
        }
        Input::Csv(path) => (
            plain(vec![crate::outline::load_csv(path, &Default::default())?]),
            None,
        ),
        Input::Glyph { font, glyph } => {
            let g = load_glyph(font, *glyph)?;
            g.check_sample_count(options.sampling, options.min_samples_per_segment)?;
            let mut sampled = g.sample_at_least(options.sampling, options.min_samples_per_segment);
            sampled.sort_by(|a, b| b.outline.area().total_cmp(&a.outline.area()));
            let contours = sampled
                .into_iter()
                .enumerate()
                .map(|(index, c)| SourceContour {
                    index,
                    outline: c.outline,
                    true_breaks: Some(c.breaks),
                    true_corners: Some(c.corners),
                })
                .collect();
            (contours, Some(g.height()))
        }
    })
}

impl Source {
    /// Loads `input` (resolving relative paths against `base`) and keeps the
    /// contours `options.contour` names: for an image its boundaries (outer
    /// and holes) by decreasing area, for a glyph its contours by decreasing
    /// area, for a CSV file its only one.
    pub fn load(input: &str, base: &Path, options: &LoadOptions) -> Result<Source, SourceError> {
        let parsed = match parse_input(input)? {
            Input::Image(p) => Input::Image(resolve(base, &p)),
            Input::Csv(p) => Input::Csv(resolve(base, &p)),
            Input::Glyph { font, glyph } => Input::Glyph {
                font: resolve(base, &font),
                glyph,
            },
        };
        let (mut contours, glyph_height) = all_contours(&parsed, options)?;
        let available = contours.len();
        if let ContourChoice::Index(k) = options.contour {
            if k >= available {
                return Err(SourceError(OutlineError::ContourOutOfRange {
                    input: input.to_owned(),
                    asked: k,
                    count: available,
                }));
            }
            contours = vec![contours.swap_remove(k)];
        }
        Ok(Source {
            input: input.to_owned(),
            parsed,
            contours,
            available,
            glyph_height,
        })
    }

    /// A source of one outline given directly (no file), named `input`.
    pub fn from_outline(input: &str, outline: Outline) -> Source {
        Source {
            input: input.to_owned(),
            parsed: Input::Csv(PathBuf::from(input)),
            contours: vec![SourceContour {
                index: 0,
                outline,
                true_breaks: None,
                true_corners: None,
            }],
            available: 1,
            glyph_height: None,
        }
    }

    /// Whether the source is a glyph (whose samples know their exact
    /// segments and parameters).
    pub fn is_glyph(&self) -> bool {
        matches!(self.parsed, Input::Glyph { .. })
    }

    /// Whether the source is a traced image (its outlines pixel staircases).
    pub fn is_image(&self) -> bool {
        matches!(self.parsed, Input::Image(_))
    }

    /// The parameterisation `auto` stands for: the samples' own parameters
    /// where they are known — a glyph cut at its true breaks is sampled at
    /// uniform `t` on each exact segment, so uniform parameters are exact —
    /// and chord length otherwise (data whose parameters are unknown).
    pub fn auto_parameterisation(&self, true_breaks: bool) -> Parameterisation {
        if true_breaks && self.is_glyph() {
            Parameterisation::Uniform
        } else {
            Parameterisation::ChordLength
        }
    }

    /// Every data point of the fitted contours, contour after contour.
    pub fn points(&self) -> Vec<crate::geometry::Point> {
        self.contours
            .iter()
            .flat_map(|c| c.outline.points.iter().copied())
            .collect()
    }

    /// A short name for tables and file names: the file stem, or
    /// `<font stem>-<glyph>` for a glyph.
    pub fn label(&self) -> String {
        let stem = |p: &Path| {
            p.file_stem()
                .map_or_else(|| "input".into(), |s| s.to_string_lossy().into_owned())
        };
        match &self.parsed {
            Input::Image(p) | Input::Csv(p) => stem(p),
            Input::Glyph { font, glyph } => {
                let g = if glyph.is_ascii_alphanumeric() {
                    glyph.to_string()
                } else {
                    format!("U+{:04X}", u32::from(*glyph))
                };
                format!("{}-{g}", stem(font))
            }
        }
    }
}

fn resolve(base: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() {
        p.to_owned()
    } else {
        base.join(p)
    }
}
