//! Curve reconstruction end to end: an outline source, how it is cut into
//! segments, and the method that fits each segment.
//!
//! This is the glue between [`crate::outline`] (where the data points come
//! from), [`crate::fit`] (the fitting problem and its solvers) and
//! [`crate::optim`] (the metaheuristics). Both `metabezier fit` and fitting
//! campaigns declared in a spec go through [`Reconstruction::fit`], so a
//! campaign run and a single command-line fit of the same case with the
//! same seed give the same curve.

mod overlay;

use std::path::{Path, PathBuf};

use crate::fit::{
    fit_adaptive, fit_breaks, fit_segment_count, FitError, FitOptions, HybridSolver, LmSolver,
    OptimiserSolver, PiecewiseFit, SegmentSolver, SplitOptions,
};
use crate::optim::Algorithm;
use crate::outline::{
    find_corners, load_glyph, load_image, parse_input, CornerOptions, ImageOptions, Input, Outline,
    OutlineError, Sampling,
};
use crate::rng::run_rng;

pub use overlay::{OverlayCurve, OverlayFigure, OverlayPanel};

/// How a segment problem is solved.
#[derive(Clone, Debug)]
pub enum Method {
    /// One of the metaheuristics (HS, GHS, GA, PSO, MHS) with its settings.
    Metaheuristic(Algorithm),
    /// The exact reference: Levenberg–Marquardt (Levenberg 1944; Marquardt
    /// 1963) from the linear least-squares fit with unit weights.
    Exact,
    /// A metaheuristic on 80 % of the budget, then a Levenberg–Marquardt
    /// polish from its best vector on the rest.
    Hybrid(Algorithm),
}

impl Method {
    /// The name of the exact method in specs and on the command line.
    pub const EXACT: &'static str = "lm";
    /// The suffix that turns a metaheuristic into a hybrid (`mhs+lm`).
    pub const POLISH_SUFFIX: &'static str = "+lm";

    /// Every method name: the metaheuristics, `lm`, and each `<name>+lm`.
    pub fn names() -> Vec<String> {
        let mut out: Vec<String> = Algorithm::NAMES.iter().map(|s| s.to_string()).collect();
        out.push(Self::EXACT.into());
        out.extend(
            Algorithm::NAMES
                .iter()
                .map(|n| format!("{n}{}", Self::POLISH_SUFFIX)),
        );
        out
    }

    /// Splits a method name into the metaheuristic whose parameters it
    /// takes (`None` for `lm`) and whether it is polished by LM; `None` if
    /// the name is unknown.
    pub fn parse_name(name: &str) -> Option<(Option<&str>, bool)> {
        if name == Self::EXACT {
            return Some((None, false));
        }
        let (base, polish) = match name.strip_suffix(Self::POLISH_SUFFIX) {
            Some(base) => (base, true),
            None => (name, false),
        };
        Algorithm::NAMES
            .contains(&base)
            .then_some((Some(base), polish))
    }

    /// The method named `name` (see [`Method::names`]) with its
    /// metaheuristic's default parameters; `None` if the name is unknown.
    pub fn from_name(name: &str) -> Option<Method> {
        let (base, polish) = Self::parse_name(name)?;
        let algorithm = match base {
            Some(b) => Some(Algorithm::default_for(b)?),
            None => None,
        };
        Some(Self::build(algorithm, polish))
    }

    /// The method of a parsed name ([`Method::parse_name`]) with its
    /// metaheuristic configured: `lm` without one, else the metaheuristic,
    /// polished by LM if `polish`.
    pub fn build(algorithm: Option<Algorithm>, polish: bool) -> Method {
        match (algorithm, polish) {
            (None, _) => Method::Exact,
            (Some(a), true) => Method::Hybrid(a),
            (Some(a), false) => Method::Metaheuristic(a),
        }
    }

    /// The segment solver of this method; a stochastic one draws from
    /// Xoshiro256++ seeded with `seed` ([`run_rng`]), one stream for all
    /// the segments it solves, in order.
    pub fn solver(&self, seed: u64) -> Box<dyn SegmentSolver> {
        match self {
            Method::Exact => Box::new(LmSolver::default()),
            Method::Metaheuristic(a) => {
                Box::new(OptimiserSolver::new(a.clone(), run_rng(seed)).with_label(a.name()))
            }
            Method::Hybrid(a) => Box::new(HybridSolver::new(a.clone(), run_rng(seed))),
        }
    }

    /// The method's name: `hs`, `lm`, `mhs+lm`, ….
    pub fn name(&self) -> String {
        match self {
            Method::Metaheuristic(a) => a.name().to_owned(),
            Method::Exact => Self::EXACT.to_owned(),
            Method::Hybrid(a) => format!("{}{}", a.name(), Self::POLISH_SUFFIX),
        }
    }

    /// Whether the method draws random numbers (LM alone does not).
    pub fn is_stochastic(&self) -> bool {
        !matches!(self, Method::Exact)
    }
}

/// How an outline is cut into segments.
#[derive(Clone, Debug, PartialEq)]
pub enum Segmentation {
    /// This many segments: split at the corners, then at equal arc length.
    Count(usize),
    /// Schneider's recursive split until every segment's largest orthogonal
    /// distance is at most this (data units).
    Tolerance(f64),
    /// These break indices, used as given (corners are not searched); the
    /// joints at `corners` (a subset) are C⁰ only.
    Breaks {
        /// Break indices into the outline.
        breaks: Vec<usize>,
        /// The breaks that are corners.
        corners: Vec<usize>,
    },
}

/// Where the data points come from and which contour is fitted.
#[derive(Clone, Debug)]
pub struct Source {
    /// The input as the user wrote it (`horse.png`, `pts.csv`,
    /// `font:PATH:GLYPH`).
    pub input: String,
    /// The parsed input, with paths resolved.
    pub parsed: Input,
    /// The outline fitted.
    pub outline: Outline,
    /// For a glyph, the sampled indices where its exact segments start.
    pub true_breaks: Option<Vec<usize>>,
    /// For a glyph, those of `true_breaks` that are corners.
    pub true_corners: Option<Vec<usize>>,
    /// For a glyph, its height (font units), the scale of its errors.
    pub glyph_height: Option<f64>,
}

/// A source could not be read; the outline error says why (and is its
/// [`std::error::Error::source`]).
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct SourceError(#[from] pub OutlineError);

impl Source {
    /// The glyph's own segmentation: its true break points, C⁰ at its
    /// corners; `None` for an image or CSV source.
    pub fn true_segmentation(&self) -> Option<Segmentation> {
        Some(Segmentation::Breaks {
            breaks: self.true_breaks.clone()?,
            corners: self.true_corners.clone().unwrap_or_default(),
        })
    }

    /// Loads `input` (resolving relative paths against `base`) and picks
    /// its `contour`-th outline: for an image its shapes by decreasing
    /// area, for a glyph its contours by decreasing area, for a CSV file
    /// its only one. Glyphs are sampled with `sampling`.
    pub fn load(
        input: &str,
        base: &Path,
        contour: usize,
        image: &ImageOptions,
        sampling: Sampling,
    ) -> Result<Source, SourceError> {
        let parsed = match parse_input(input)? {
            Input::Image(p) => Input::Image(resolve(base, &p)),
            Input::Csv(p) => Input::Csv(resolve(base, &p)),
            Input::Glyph { font, glyph } => Input::Glyph {
                font: resolve(base, &font),
                glyph,
            },
        };
        let pick = |n: usize| -> Result<usize, SourceError> {
            if contour < n {
                Ok(contour)
            } else {
                Err(SourceError(OutlineError::BadInput {
                    input: input.to_owned(),
                    message: format!(
                        "contour {contour} was asked for, but it has {n} (numbered from 0)"
                    ),
                }))
            }
        };
        let (outline, true_breaks, true_corners, glyph_height) = match &parsed {
            Input::Image(path) => {
                let mut shapes = load_image(path, image)?;
                let k = pick(shapes.len())?;
                (shapes.swap_remove(k), None, None, None)
            }
            Input::Csv(path) => {
                let o = crate::outline::load_csv(path, &Default::default())?;
                pick(1)?;
                (o, None, None, None)
            }
            Input::Glyph { font, glyph } => {
                let g = load_glyph(font, *glyph)?;
                let mut contours = g.sample(sampling);
                contours.sort_by(|a, b| b.outline.area().total_cmp(&a.outline.area()));
                let k = pick(contours.len())?;
                let c = contours.swap_remove(k);
                (c.outline, Some(c.breaks), Some(c.corners), Some(g.height()))
            }
        };
        Ok(Source {
            input: input.to_owned(),
            parsed,
            outline,
            true_breaks,
            true_corners,
            glyph_height,
        })
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

/// One fitting task: the data, the segmentation, the fit options and the
/// corner detector.
#[derive(Clone, Debug)]
pub struct Reconstruction<'a> {
    /// The outline fitted.
    pub outline: &'a Outline,
    /// How it is cut into segments.
    pub segmentation: Segmentation,
    /// Corner detection for [`Segmentation::Count`] and
    /// [`Segmentation::Tolerance`]; `None` finds no corners.
    pub corners: Option<CornerOptions>,
    /// Function, continuity, parameterisation, search space and budget per
    /// segment.
    pub options: FitOptions,
}

impl Reconstruction<'_> {
    /// The corner indices this reconstruction splits at first.
    pub fn corner_indices(&self) -> Vec<usize> {
        match (&self.segmentation, self.corners) {
            (Segmentation::Breaks { .. }, _) | (_, None) => Vec::new(),
            (_, Some(c)) => find_corners(self.outline, &c),
        }
    }

    /// Fits the outline with `method`'s solver ([`Method::solver`]) seeded
    /// with `seed`.
    pub fn fit(&self, method: &Method, seed: u64) -> Result<PiecewiseFit, FitError> {
        self.fit_with(method.solver(seed).as_mut())
    }

    /// Fits the outline with any segment solver.
    pub fn fit_with<S: SegmentSolver + ?Sized>(
        &self,
        solver: &mut S,
    ) -> Result<PiecewiseFit, FitError> {
        let points = &self.outline.points;
        let closed = self.outline.closed;
        match &self.segmentation {
            Segmentation::Breaks { breaks, corners } => {
                fit_breaks(points, closed, breaks, corners, &self.options, solver)
            }
            Segmentation::Count(n) => fit_segment_count(
                points,
                closed,
                &self.corner_indices(),
                *n,
                &self.options,
                solver,
            ),
            Segmentation::Tolerance(t) => fit_adaptive(
                points,
                closed,
                &self.corner_indices(),
                &SplitOptions::new(*t),
                &self.options,
                solver,
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit::FunctionType;
    use crate::geometry::{Continuity, Point};

    #[test]
    fn method_names_round_trip() {
        for name in Method::names() {
            assert_eq!(Method::from_name(&name).unwrap().name(), name);
        }
        assert!(Method::parse_name("hz").is_none());
        assert!(Method::parse_name("lm+lm").is_none());
        assert!(Method::from_name("hz").is_none());
    }

    fn square(n: usize) -> Outline {
        // A square with rounded-off sampling: n points per side, closed.
        let corners = [
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
        ];
        let mut pts = Vec::new();
        for k in 0..4 {
            let (a, b) = (corners[k], corners[(k + 1) % 4]);
            for j in 0..n {
                pts.push(a.lerp(b, j as f64 / n as f64));
            }
        }
        Outline::new(pts, true)
    }

    #[test]
    fn a_square_is_cut_at_its_corners_and_fitted_exactly() {
        let outline = square(20);
        let r = Reconstruction {
            outline: &outline,
            segmentation: Segmentation::Count(4),
            corners: Some(CornerOptions::default()),
            options: FitOptions::new(FunctionType::Cubic, Continuity::G1),
        };
        assert_eq!(r.corner_indices(), vec![0, 20, 40, 60]);
        let fit = r.fit(&Method::Exact, 1).unwrap();
        assert_eq!(fit.breaks(), vec![0, 20, 40, 60]);
        assert!(fit.metrics.max_distance < 1e-6, "{:?}", fit.metrics);
    }

    #[test]
    fn the_same_seed_gives_the_same_fit() {
        let outline = square(12);
        let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::C1);
        options.budget_per_segment = 2000;
        let r = Reconstruction {
            outline: &outline,
            segmentation: Segmentation::Count(4),
            corners: Some(CornerOptions::default()),
            options,
        };
        let m = Method::from_name("mhs").unwrap();
        let a = r.fit(&m, 7).unwrap();
        let b = r.fit(&m, 7).unwrap();
        let c = r.fit(&m, 8).unwrap();
        assert_eq!(a.metrics.sse.to_bits(), b.metrics.sse.to_bits());
        assert_ne!(a.metrics.sse.to_bits(), c.metrics.sse.to_bits());
        assert_eq!(a.metrics.evaluations, 4 * 2000);
    }

    #[test]
    fn a_source_error_shows_and_chains_its_outline_error() {
        let e = Source::load(
            "a.csv",
            Path::new("/nonexistent-dir"),
            0,
            &ImageOptions::default(),
            Sampling::default(),
        )
        .unwrap_err();
        let cause = std::error::Error::source(&e).expect("the outline error");
        assert_eq!(e.to_string(), cause.to_string());
        assert_eq!(e.to_string(), e.0.to_string());
    }
}
