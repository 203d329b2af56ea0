//! Curve reconstruction end to end: an outline source, how it is cut into
//! segments, and the method that fits each segment.
//!
//! This is the glue between [`crate::outline`] (where the data points come
//! from), [`crate::fit`] (the fitting problem and its solvers) and
//! [`crate::optim`] (the metaheuristics). Both `metabezier fit` and fitting
//! campaigns declared in a spec go through [`Reconstruction::fit`], so a
//! campaign run and a single command-line fit of the same case with the
//! same seed give the same curve.
//!
//! | module | concept |
//! |---|---|
//! | [`Source`], [`ContourChoice`] | an input's contours (outer boundaries and holes) and which are fitted |
//! | [`Reconstruction`], [`Method`], [`FitMode`] | the fitting task: whole outlines or per-segment problems |
//! | [`ShapeFit`] | every contour's fit, with the totals and the best-so-far trace |
//! | [`shape_svg`], [`save_shape_svg`], [`save_shape_png`] | the fit as one even-odd SVG path and its PNG |
//! | [`shape_dxf`] | the fit as exact DXF `SPLINE`s (control points and weights) |
//! | [`score`] | other tools' curves against the same data points |
//! | [`OverlayFigure`] | the data and the curves on axes, drawn by the report |

mod drawing;
mod dxf;
mod overlay;
mod score;
mod shape;
mod source;

use crate::fit::{
    fit_adaptive, fit_breaks, fit_independent, fit_segment_count, FitError, FitOptions,
    HybridSolver, LmSolver, OptimiserSolver, PiecewiseFit, SegmentSolver, SplitOptions,
};
use crate::optim::{Algorithm, Optimisers};
use crate::outline::{find_corners, CornerOptions};
use crate::rng::{run_rng, splitmix64};

pub use drawing::{cubic_pieces, save_shape_png, save_shape_svg, shape_raster, shape_svg};
pub use dxf::shape_dxf;
pub use overlay::{OverlayCurve, OverlayFigure, OverlayPanel};
pub use score::{score, segment_distance, Distances, Score, ScoreError, MAX_SCORE_COORDINATE};
pub use shape::{ContourFit, PartialShapeFit, ShapeFit};
pub use source::{ContourChoice, LoadOptions, Source, SourceContour, SourceError};

/// How a segment problem is solved.
#[derive(Clone, Debug)]
pub enum Method {
    ///
    /// ```
    /// use metabezier_fit::reconstruction::Method;
    ///
    /// assert_eq!(Method::from_name("mhs+lm").unwrap().name(), "mhs+lm");
    /// assert!(!Method::from_name("lm").unwrap().is_stochastic());
    /// assert!(Method::names().contains(&"cmaes".to_string()));
    /// assert!(Method::from_name("lm+lm").is_none());
    /// ```

    /// One of the metaheuristics (HS, GHS, GA, PSO, MHS, L-SHADE, random
    /// search) with its settings.
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

    /// Every method name of the built-in optimisers
    /// ([`Method::names_in`] of [`Optimisers::builtin`]).
    pub fn names() -> Vec<String> {
        Self::names_in(Optimisers::builtin())
    }

    /// Every method name over the optimisers of `reg`: each optimiser,
    /// `lm`, and each `<name>+lm`.
    pub fn names_in(reg: &Optimisers) -> Vec<String> {
        let names = reg.names();
        let mut out: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        out.push(Self::EXACT.into());
        out.extend(names.iter().map(|n| format!("{n}{}", Self::POLISH_SUFFIX)));
        out
    }

    /// [`Method::parse_name_in`] over the built-in optimisers.
    pub fn parse_name(name: &str) -> Option<(Option<&str>, bool)> {
        Self::parse_name_in(name, Optimisers::builtin())
    }

    /// Splits a method name into the optimiser of `reg` whose parameters it
    /// takes (`None` for `lm`) and whether it is polished by LM; `None` if
    /// the name is unknown.
    pub fn parse_name_in<'n>(name: &'n str, reg: &Optimisers) -> Option<(Option<&'n str>, bool)> {
        if name == Self::EXACT {
            return Some((None, false));
        }
        let (base, polish) = match name.strip_suffix(Self::POLISH_SUFFIX) {
            Some(base) => (base, true),
            None => (name, false),
        };
        reg.get(base).is_some().then_some((Some(base), polish))
    }

    /// The method named `name` (see [`Method::names`]) with its
    /// optimiser's default parameters; `None` if the name is unknown.
    pub fn from_name(name: &str) -> Option<Method> {
        Self::from_name_in(name, Optimisers::builtin())
    }

    /// The method named `name` over the optimisers of `reg`, with default
    /// parameters; `None` if the name is unknown.
    pub fn from_name_in(name: &str, reg: &Optimisers) -> Option<Method> {
        let (base, polish) = Self::parse_name_in(name, reg)?;
        let algorithm = match base {
            Some(b) => Some(reg.default_for(b)?),
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

    /// The segment solver of this method; a stochastic one draws from the
    /// run generator seeded with `seed` ([`run_rng`]), one stream for all
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

/// How a fitting case's segments are posed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FitMode {
    /// The whole outline as one chain: segments fitted in sequence, each
    /// inheriting its join from the one the method fitted before it.
    #[default]
    Outline,
    /// Every segment as its own problem, joined to the neighbours of the
    /// exact (Levenberg–Marquardt) fit ([`Reconstruction::fit_per_segment`]),
    /// so that segments are independent units of a study.
    PerSegment,
}

impl FitMode {
    /// The names accepted in specs.
    pub const NAMES: [&'static str; 2] = ["outline", "per-segment"];

    /// Parses a name.
    pub fn from_name(name: &str) -> Option<FitMode> {
        match name {
            "outline" => Some(FitMode::Outline),
            "per-segment" | "per_segment" => Some(FitMode::PerSegment),
            _ => None,
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            FitMode::Outline => "outline",
            FitMode::PerSegment => "per-segment",
        }
    }
}

/// The tolerance of a plain `metabezier fit` (data units; pixels for an
/// image): 1. A traced image's outline is a staircase of pixel edges whose
/// points lie up to about half a pixel off any smooth outline through them,
/// so a tolerance of one pixel follows the shape and not the pixels, and
/// is still below what an eye sees at 1:1 scale; it is also potrace's
/// order of accuracy (0.90 px on the horse). For CSV and glyph input, in
/// their own units, give `--tolerance` to suit them.
pub const DEFAULT_TOLERANCE: f64 = 1.0;

/// How an outline is cut into segments.
#[derive(Clone, Debug, PartialEq)]
pub enum Segmentation {
    /// This many segments per contour: split at the corners, then at equal
    /// arc length. A count below a contour's span count (one segment per
    /// span between corners) is refused by [`Reconstruction::fit`] and raised
    /// to it by [`Reconstruction::fit_each`] ([`ContourFit::raised_from`]).
    Count(usize),
    /// Fit to this tolerance (data units), per contour ([`crate::fit::fit_adaptive`]):
    /// every segment's two-sided distance to the outline beyond the
    /// staircase's allowance within it, with as few segments as the split
    /// and merge passes find, or the contour fails.
    Tolerance(f64),
    /// [`Segmentation::Tolerance`] with coarse trial fits
    /// ([`crate::fit::SplitOptions::coarse`]): each trial of the search is
    /// solved coarsely, and again fully when it misses the tolerance by at
    /// most `recheck` times (`metabezier fit`'s default, `recheck` =
    /// [`crate::fit::COARSE_RECHECK`]).
    Coarse {
        /// The tolerance (data units).
        tolerance: f64,
        /// The recheck factor (`≥ 1`).
        recheck: f64,
    },
    /// A glyph's own break points on each contour, C⁰ at its corners.
    TrueBreaks,
    /// These break indices, used as given on every contour (corners are not
    /// searched); the joints at `corners` (a subset) are C⁰ only.
    Breaks {
        /// Break indices into the outline.
        breaks: Vec<usize>,
        /// The breaks that are corners.
        corners: Vec<usize>,
    },
    /// Break indices of each contour, taken from a reference fit
    /// ([`Segmentation::of_fit`]): how a campaign fits every method to the
    /// segments the exact fit found for a tolerance.
    PerContour(Vec<ContourBreaks>),
}

/// One contour's break indices and which of them are corners (C⁰ joints).
#[derive(Clone, Debug, PartialEq)]
pub struct ContourBreaks {
    /// The contour's number in its input.
    pub contour: usize,
    /// Break indices into its outline, sorted.
    pub breaks: Vec<usize>,
    /// The breaks that are corners.
    pub corners: Vec<usize>,
}

impl Segmentation {
    /// The tolerance of [`Segmentation::Tolerance`] and
    /// [`Segmentation::Coarse`]; `None` for the others.
    pub fn tolerance(&self) -> Option<f64> {
        match *self {
            Segmentation::Tolerance(t) | Segmentation::Coarse { tolerance: t, .. } => Some(t),
            _ => None,
        }
    }

    /// The segmentation of `fit`: every contour's segment starts as breaks,
    /// and as corners those joined C⁰ (and the chain's start where the
    /// chain closes at a corner), so that [`fit_breaks`] poses the same
    /// segments with the same joins.
    pub fn of_fit(fit: &ShapeFit) -> Segmentation {
        let contours = fit
            .contours
            .iter()
            .map(|c| {
                let segments = &c.fit.segments;
                let at_corner = c.fit.closing.is_some_and(|j| j.at_corner);
                let mut corners: Vec<usize> = segments
                    .iter()
                    .enumerate()
                    .filter(|(k, s)| {
                        s.join == crate::geometry::Continuity::C0 && (*k > 0 || at_corner)
                    })
                    .map(|(_, s)| s.first)
                    .collect();
                let mut breaks: Vec<usize> = segments.iter().map(|s| s.first).collect();
                breaks.sort_unstable();
                corners.sort_unstable();
                ContourBreaks {
                    contour: c.contour,
                    breaks,
                    corners,
                }
            })
            .collect();
        Segmentation::PerContour(contours)
    }
}

impl Source {
    /// The glyph's own segmentation ([`Segmentation::TrueBreaks`]); `None`
    /// for an image or CSV source.
    pub fn true_segmentation(&self) -> Option<Segmentation> {
        self.is_glyph().then_some(Segmentation::TrueBreaks)
    }
}

/// One fitting task: the data, the segmentation, the fit options and the
/// corner detector.
#[derive(Clone, Debug)]
pub struct Reconstruction<'a> {
    /// The contours fitted.
    pub source: &'a Source,
    /// How each contour is cut into segments.
    pub segmentation: Segmentation,
    /// Corner detection for [`Segmentation::Count`] and
    /// [`Segmentation::Tolerance`]; `None` finds no corners.
    pub corners: Option<CornerOptions>,
    /// Function, continuity, closing, parameterisation, search space and
    /// budget per segment.
    pub options: FitOptions,
}

impl Reconstruction<'_> {
    /// The corner indices `contour` is split at first.
    pub fn corner_indices(&self, contour: &SourceContour) -> Vec<usize> {
        match (&self.segmentation, self.corners) {
            (
                Segmentation::Breaks { .. }
                | Segmentation::TrueBreaks
                | Segmentation::PerContour(_),
                _,
            )
            | (_, None) => Vec::new(),
            (_, Some(c)) => find_corners(&contour.outline, &c),
        }
    }

    /// Fits every contour with `method`'s solver ([`Method::solver`])
    /// seeded with `seed` (one stream over all contours, in order).
    pub fn fit(&self, method: &Method, seed: u64) -> Result<ShapeFit, FitError> {
        self.fit_with(method.solver(seed).as_mut())
    }

    /// Fits every contour with any segment solver, contour after contour;
    /// fails with the first contour that cannot be fitted.
    pub fn fit_with<S: SegmentSolver + ?Sized>(
        &self,
        solver: &mut S,
    ) -> Result<ShapeFit, FitError> {
        let mut contours = Vec::with_capacity(self.source.contours.len());
        for c in &self.source.contours {
            contours.push(
                self.fit_one_contour(c, &mut *solver, false)
                    .map_err(|e| FitError::in_contour(c.index, e))?,
            );
        }
        Ok(ShapeFit::new(contours))
    }

    /// Fits every contour with `method`'s solver seeded with `seed` (one
    /// stream over all contours, in order), keeping going past a contour
    /// that cannot be fitted: the fitted ones, and the others with why. A
    /// segment count below a contour's span count is raised to it
    /// ([`ContourFit::raised_from`]; [`Reconstruction::fit`] refuses it,
    /// as a campaign's design should not change behind its back).
    pub fn fit_each(&self, method: &Method, seed: u64) -> PartialShapeFit {
        let mut solver = method.solver(seed);
        let mut contours = Vec::with_capacity(self.source.contours.len());
        let mut failed = Vec::new();
        for c in &self.source.contours {
            match self.fit_one_contour(c, solver.as_mut(), true) {
                Ok(fit) => contours.push(fit),
                Err(e) => failed.push((c.index, FitError::in_contour(c.index, e))),
            }
        }
        PartialShapeFit {
            fit: ShapeFit::new(contours),
            failed,
        }
    }

    /// One contour's fit with its number, orientation and, if `raise`, a
    /// segment count below its span count raised to it.
    fn fit_one_contour<S: SegmentSolver + ?Sized>(
        &self,
        c: &SourceContour,
        solver: &mut S,
        raise: bool,
    ) -> Result<ContourFit, FitError> {
        let (fit, raised_from) = match self.fit_contour(c, &mut *solver) {
            Err(FitError::TooFewSegments { requested, minimum }) if raise => {
                (self.fit_count(c, minimum, solver)?, Some(requested))
            }
            other => (other?, None),
        };
        Ok(ContourFit {
            contour: c.index,
            orientation: c.orientation(),
            fit,
            raised_from,
        })
    }

    /// `contour` fitted in exactly `count` segments (corners first).
    fn fit_count<S: SegmentSolver + ?Sized>(
        &self,
        contour: &SourceContour,
        count: usize,
        solver: &mut S,
    ) -> Result<PiecewiseFit, FitError> {
        let points = &contour.outline.points;
        let corners = self.corner_indices(contour);
        let closed = contour.outline.closed;
        fit_segment_count(points, closed, &corners, count, &self.options, solver)
    }

    /// Fits one contour with `solver`. A segment count below the
    /// contour's span count fails here ([`FitError::TooFewSegments`]);
    /// [`Reconstruction::fit_each`] raises it to the span count instead
    /// ([`ContourFit::raised_from`]).
    pub fn fit_contour<S: SegmentSolver + ?Sized>(
        &self,
        contour: &SourceContour,
        solver: &mut S,
    ) -> Result<PiecewiseFit, FitError> {
        let points = &contour.outline.points;
        let closed = contour.outline.closed;
        let options = &self.options;
        match &self.segmentation {
            Segmentation::Breaks { breaks, corners } => {
                fit_breaks(points, closed, breaks, corners, options, solver)
            }
            Segmentation::TrueBreaks => {
                let breaks = contour.true_breaks.clone().unwrap_or_default();
                let corners = contour.true_corners.clone().unwrap_or_default();
                fit_breaks(points, closed, &breaks, &corners, options, solver)
            }
            Segmentation::Count(n) => self.fit_count(contour, *n, solver),
            Segmentation::PerContour(list) => {
                let own = list.iter().find(|b| b.contour == contour.index);
                let (breaks, corners) = own.map_or((&[][..], &[][..]), |b| {
                    (b.breaks.as_slice(), b.corners.as_slice())
                });
                fit_breaks(points, closed, breaks, corners, options, solver)
            }
            Segmentation::Tolerance(t) => self.fit_tolerance(contour, *t, None, solver),
            Segmentation::Coarse { tolerance, recheck } => {
                self.fit_tolerance(contour, *tolerance, Some(*recheck), solver)
            }
        }
    }

    /// `contour` split to `tolerance` ([`fit_adaptive`]), with coarse
    /// trials rechecked at `coarse` times the tolerance if given.
    fn fit_tolerance<S: SegmentSolver + ?Sized>(
        &self,
        contour: &SourceContour,
        tolerance: f64,
        coarse: Option<f64>,
        solver: &mut S,
    ) -> Result<PiecewiseFit, FitError> {
        let corners = self.corner_indices(contour);
        // The staircase's allowance is for traced images only: points
        // sampled from exact curves (glyphs) or given as they are (CSV)
        // turn sharply only at corners of the shape.
        let split = SplitOptions {
            staircase: self.source.is_image(),
            coarse,
            ..SplitOptions::new(tolerance)
        };
        let outline = &contour.outline;
        fit_adaptive(
            &outline.points,
            outline.closed,
            &corners,
            &split,
            &self.options,
            solver,
        )
    }

    /// The exact reference of the per-segment mode: every contour fitted by
    /// Levenberg–Marquardt ([`Method::Exact`]).
    pub fn reference(&self) -> Result<ShapeFit, FitError> {
        self.fit(&Method::Exact, 0)
    }

    /// The per-segment mode ([`fit_independent`]): every segment of
    /// `reference` solved again as its own problem by `method`, joined to
    /// the reference's neighbours, segment `k` of the `c`-th contour seeded
    /// with [`segment_seed`]`(seed, c, k)`.
    pub fn fit_per_segment(
        &self,
        method: &Method,
        seed: u64,
        reference: &ShapeFit,
    ) -> Result<ShapeFit, FitError> {
        self.fit_per_segment_with(reference, |c, k| method.solver(segment_seed(seed, c, k)))
    }

    /// The per-segment mode with the solver `solver_for(c, k)` for segment
    /// `k` of the `c`-th contour.
    pub fn fit_per_segment_with<S, F>(
        &self,
        reference: &ShapeFit,
        mut solver_for: F,
    ) -> Result<ShapeFit, FitError>
    where
        S: SegmentSolver,
        F: FnMut(usize, usize) -> S,
    {
        let mut contours = Vec::with_capacity(reference.contours.len());
        for (pos, (c, r)) in self
            .source
            .contours
            .iter()
            .zip(&reference.contours)
            .enumerate()
        {
            let points = &c.outline.points;
            let fit = fit_independent(points, c.outline.closed, &r.fit, &self.options, |k| {
                solver_for(pos, k)
            })
            .map_err(|e| FitError::in_contour(c.index, e))?;
            contours.push(ContourFit {
                contour: c.index,
                orientation: c.orientation(),
                fit,
                raised_from: None,
            });
        }
        Ok(ShapeFit::new(contours))
    }
}

/// The seed of segment `k` of the `contour`-th fitted contour in the
/// per-segment mode: `splitmix64` folded over (run seed, contour, segment),
/// so that a segment's random numbers do not depend on the others'.
pub fn segment_seed(seed: u64, contour: usize, k: usize) -> u64 {
    let s = splitmix64(seed ^ splitmix64(contour as u64));
    splitmix64(s ^ k as u64)
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::fit::FunctionType;
    use crate::geometry::{Continuity, Point};
    use crate::outline::Outline;

    #[test]
    fn method_names_round_trip() {
        for name in Method::names() {
            assert_eq!(Method::from_name(&name).unwrap().name(), name);
        }
        assert!(Method::parse_name("hz").is_none());
        assert!(Method::parse_name("lm+lm").is_none());
        assert!(Method::from_name("hz").is_none());
        for m in FitMode::NAMES {
            assert_eq!(FitMode::from_name(m).unwrap().name(), m);
        }
    }

    fn square(n: usize) -> Source {
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
        Source::from_outline("square", Outline::new(pts, true))
    }

    #[test]
    fn a_square_is_cut_at_its_corners_and_fitted_exactly() {
        let source = square(20);
        let r = Reconstruction {
            source: &source,
            segmentation: Segmentation::Count(4),
            corners: Some(CornerOptions::default()),
            options: FitOptions::new(FunctionType::Cubic, Continuity::G1),
        };
        assert_eq!(r.corner_indices(&source.contours[0]), vec![0, 20, 40, 60]);
        let fit = r.fit(&Method::Exact, 1).unwrap();
        assert_eq!(fit.contours[0].fit.breaks(), vec![0, 20, 40, 60]);
        assert!(fit.metrics.max_distance < 1e-6, "{:?}", fit.metrics);
        // The chain starts at a corner, so it closes there.
        assert!(fit.contours[0].fit.closing.unwrap().at_corner);
    }

    #[test]
    fn the_same_seed_gives_the_same_fit() {
        let source = square(12);
        let mut options = FitOptions::new(FunctionType::RationalCubic, Continuity::C1);
        options.budget_per_segment = 2000;
        let r = Reconstruction {
            source: &source,
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
        // Per segment: every segment on its own seed, joined to the reference.
        let reference = r.reference().unwrap();
        let p = r.fit_per_segment(&m, 7, &reference).unwrap();
        let q = r.fit_per_segment(&m, 7, &reference).unwrap();
        assert_eq!(p, q);
        assert_eq!(p.metrics.segments, 4);
        assert_ne!(segment_seed(7, 0, 1), segment_seed(7, 0, 2));
        assert_ne!(segment_seed(7, 0, 1), segment_seed(7, 1, 1));
    }

    #[test]
    fn a_source_error_shows_and_chains_its_outline_error() {
        let e = Source::load(
            "a.csv",
            Path::new("/nonexistent-dir"),
            &LoadOptions::default(),
        )
        .unwrap_err();
        let cause = std::error::Error::source(&e).expect("the outline error");
        assert_eq!(e.to_string(), cause.to_string());
        assert_eq!(e.to_string(), e.0.to_string());
    }
}
