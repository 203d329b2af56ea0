//! `metabezier fit`: its arguments, the fit of every contour, the files,
//! and the summary and notes a person reads.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use super::fit_outputs::{write_drawings, FitOutput};
use super::named::{named, ParameterisationChoice};
use crate::error::{Error, UsageError};
use crate::experiment::fit_files::write_fit_records;
use crate::files::{check_output_dir, Staging};
use crate::fit::{
    Chain, Closing, ErrorMeasure, FitError, FitOptions, FunctionType, SearchSpace, COARSE_RECHECK,
};
use crate::geometry::Continuity;
use crate::outline::{noise_level, parse_input, CornerOptions, Foreground, Input};
use crate::reconstruction::{
    ContourChoice, LoadOptions, Method, Reconstruction, Segmentation, ShapeFit, Source,
    DEFAULT_TOLERANCE,
};

/// How `--tolerance`'s search solves its trial segments (`--trials`; the
/// values are explained in the option's help).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Trials {
    // Levenberg–Marquardt stopped at a 0.3 % gain of E, near misses solved again fully.
    Coarse,
    // Every trial solved to convergence.
    Full,
}

/// Arguments of `metabezier fit`.
#[derive(Debug, clap::Args)]
pub(super) struct FitArgs {
    /// A PNG image, a CSV file of x,y points, or font:PATH:GLYPH.
    input: String,
    /// The fitting function.
    #[arg(long, default_value = "rational-cubic", value_parser = named::<FunctionType>())]
    function: FunctionType,
    /// Continuity at the joints between segments.
    #[arg(long, default_value = "g1", value_parser = named::<Continuity>())]
    continuity: Continuity,
    /// hs, ghs, ga, pso, mhs; lm (Levenberg–Marquardt, the exact reference);
    /// or a metaheuristic polished by LM: hs+lm, …, mhs+lm. Default parameters.
    #[arg(long, default_value = "lm")]
    algorithm: String,
    /// A fixed number of segments per contour (split at corners, then at
    /// equal arc length); a count below a contour's corner spans is raised
    /// to them, with a note.
    #[arg(long, conflicts_with_all = ["tolerance", "true_breaks"], value_parser = clap::value_parser!(u64).range(1..))]
    segments: Option<u64>,
    /// Fit to this two-sided (Hausdorff) distance between curve and outline:
    /// every data point within PX of the curve and the curve within PX of
    /// the outline polyline (plus the pixel staircase's sagitta), with as
    /// few segments as found; a contour that cannot be held to it fails
    /// [default: 1, without --segments or --true-breaks].
    #[arg(
        long,
        value_name = "PX",
        conflicts_with = "true_breaks",
        allow_negative_numbers = true
    )]
    tolerance: Option<f64>,
    /// With --tolerance: how the search's trial segments are solved.
    /// coarse: Levenberg–Marquardt stops once a step gains less than 0.3%
    /// of E, and a trial that then misses the tolerance by at most 1.5
    /// times is solved again fully before it is rejected (1.1–3.4 times
    /// faster on the peer-potrace inputs; segment counts within one or two
    /// of full's either way);
    /// full: every trial solved to convergence (the fit before issue 52).
    #[arg(long, value_enum, default_value_t = Trials::Coarse)]
    trials: Trials,
    /// For a glyph: break at the font's own segment ends.
    #[arg(long)]
    true_breaks: bool,
    /// For an image: which class is the shape. auto: the class that does
    /// not touch the image border (if both do, the one that touches it
    /// less); dark; light [default: auto].
    #[arg(long, value_parser = named::<Foreground>())]
    foreground: Option<Foreground>,
    /// Corner threshold: turning angle in degrees over --corner-k points
    /// (0 disables corner detection).
    #[arg(long, default_value_t = 60.0, allow_negative_numbers = true, value_parser = corner_angle)]
    corner_angle: f64,
    /// Neighbourhood of the corner test, in points.
    #[arg(long, default_value_t = 5, value_parser = clap::value_parser!(u16).range(1..=1000))]
    corner_k: u16,
    /// Fit only this contour of the input (0 is the largest); default: every
    /// contour, outer boundaries and holes.
    #[arg(long, value_name = "N")]
    contour: Option<usize>,
    /// How a closed contour's chain closes: smooth (G1/C1 at the closing
    /// joint unless it is a corner) or c0.
    #[arg(long, default_value = "smooth", value_parser = named::<Closing>())]
    closing: Closing,
    /// Search space: the thesis's technique or the data's bounding box.
    #[arg(long, default_value = "technique", value_parser = named::<SearchSpace>())]
    search_space: SearchSpace,
    /// How data points get their curve parameters s_i: auto is uniform for a
    /// glyph at its true breaks (its samples' own parameters), chord otherwise.
    #[arg(long, default_value = "auto", value_parser = named::<ParameterisationChoice>())]
    parameterisation: ParameterisationChoice,
    /// What E measures: orthogonal (the distance from each point to the
    /// curve, its parameter solved with the fit) or fixed (at the
    /// parameters s_i, the thesis's E; the default in specs).
    #[arg(long, default_value = "orthogonal", value_parser = named::<ErrorMeasure>())]
    error: ErrorMeasure,
    /// How the segments are solved: joint (the sequential chain, then all
    /// segments at once by Levenberg–Marquardt with shared joins, so none
    /// inherits another's error) or sequential (one after another, the
    /// thesis's; the default in specs).
    #[arg(long, default_value = "joint", value_parser = named::<Chain>())]
    chain: Chain,
    /// Rounds of Newton parameter correction after each segment's solve
    /// (Schneider 1990); each round solves again with a fresh budget.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u32).range(0..=100))]
    reparameterise: u32,
    /// Seed of the random generator (the multi-lane Xoshiro256++ of every run).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Objective evaluations per segment.
    #[arg(long, value_name = "EVALS", default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..))]
    budget: u64,
    /// Allow a budget over 10^10 evaluations per segment.
    #[arg(long)]
    allow_large: bool,
    /// Output directory.
    #[arg(long, default_value = "results/fit")]
    out: PathBuf,
    /// The files to write, a comma-separated list: csv (fit.csv,
    /// metrics.csv, timing.csv), svg (fit.svg), png (fit.png), dxf
    /// (fit.dxf, exact), overlay (overlay.svg, overlay.png), all.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "csv,svg",
        value_name = "LIST"
    )]
    outputs: Vec<FitOutput>,
}

/// Parses `--corner-angle`: a turning angle in degrees in [0, 180).
fn corner_angle(text: &str) -> Result<f64, String> {
    let angle: f64 = text
        .parse()
        .map_err(|_| format!("expected an angle in degrees, found \"{text}\""))?;
    if (0.0..180.0).contains(&angle) {
        Ok(angle)
    } else {
        Err(format!(
            "expected an angle in degrees in [0, 180) (0 disables corner detection), found {text}"
        ))
    }
}

/// `metabezier fit`: load, segment, fit, write the files. Contours that
/// cannot be fitted are named (exit 1) and the others written.
pub(super) fn fit(a: FitArgs, w: &mut String) -> Result<(), Error> {
    let method = Method::from_name(&a.algorithm).ok_or_else(|| UsageError::UnknownAlgorithm {
        name: a.algorithm.clone(),
        choices: Method::names(),
    })?;
    if !a.allow_large && a.budget > crate::experiment::spec::MAX_BUDGET {
        return Err(UsageError::Budget(a.budget).into());
    }
    let source = Source::load(&a.input, Path::new(""), &a.load_options()?)?;
    check_output_dir(&a.out)?;
    // Staged from the start: another run writing into the same directory
    // meanwhile is refused, not mixed with this one. Every file is written
    // there and renamed into place once all are written.
    let staging = Staging::new(&a.out)?;
    let r = Reconstruction {
        source: &source,
        segmentation: a.segmentation(&source)?,
        corners: a.corners(),
        options: a.options(&source),
    };
    let start = std::time::Instant::now();
    let outcome = r.fit_each(&method, a.seed);
    let wall = start.elapsed().as_secs_f64();
    note_fit(&r, &outcome.fit, &outcome.failed);
    let fit = outcome.fit;
    if fit.contours.is_empty() {
        let (_, first) = outcome
            .failed
            .into_iter()
            .next()
            .expect("a source has contours");
        return Err(Error::Fit {
            input: a.input.clone(),
            source: first,
        });
    }
    let title = format!(
        "{}: {} {}, {}",
        source.label(),
        r.options.function.name(),
        r.options.continuity.name().to_uppercase(),
        method.name()
    );
    let dir = staging.path();
    let case = a.case(&r, &method);
    let mut paths = if FitOutput::Csv.in_list(&a.outputs) {
        write_fit_records(dir, &fit, &case, wall)?
    } else {
        Vec::new()
    };
    let data = source.points();
    paths.extend(write_drawings(&a.outputs, &fit, &title, &data, dir)?);
    let paths: Vec<PathBuf> = paths.iter().map(|p| staging.final_path(p)).collect();
    staging.publish()?;
    say_fit(w, &source.label(), &fit, wall, &paths);
    if outcome.failed.is_empty() {
        Ok(())
    } else {
        Err(Error::ContoursFailed {
            input: a.input.clone(),
            fitted: fit.contours.len(),
            out: a.out.clone(),
            failed: outcome.failed.into_iter().map(|(_, e)| e).collect(),
        })
    }
}

/// `x` as written for a person: plainly in `[10⁻⁴, 10⁶)`, else in
/// scientific notation (a tolerance of 1e308 is not 309 digits).
fn short(x: f64) -> String {
    if (1e-4..1e6).contains(&x.abs()) {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// How many times a contour's estimated noise ([`noise_level`]) a
/// tolerance must be for the fit not to follow the noise: the largest of
/// a few hundred normal deviates is about 3σ, and a smooth curve through
/// the true shape is that far from some point.
const NOISE_FACTOR: f64 = 3.0;

/// Notes on stderr: segment counts raised to a contour's spans, and a
/// tolerance below what a contour's noise allows.
fn note_fit(r: &Reconstruction<'_>, fit: &ShapeFit, failed: &[(usize, FitError)]) {
    let mut err = std::io::stderr().lock();
    for c in &fit.contours {
        if let Some(asked) = c.raised_from {
            let _ = writeln!(
                err,
                "metabezier: note: contour {}: {asked} segment(s) asked for, but its corners make {} spans; fitted {} (one per span)",
                c.contour, c.fit.metrics.segments, c.fit.metrics.segments
            );
        }
    }
    let Some(t) = r.segmentation.tolerance() else {
        return;
    };
    for c in &r.source.contours {
        let noise = noise_level(&c.outline.points, c.outline.closed);
        let failed_here = failed.iter().any(|(k, _)| *k == c.index);
        let fitted = fit.contours.iter().find(|f| f.contour == c.index);
        // Segments beyond one per corner span are the tolerance's doing;
        // an outline of a couple of dozen points is a polygon, not noise.
        let spans = r.corner_indices(c).len().max(1);
        let per_segment = fitted
            .filter(|f| f.fit.metrics.segments > spans && f.fit.metrics.points >= 24)
            .map(|f| f.fit.metrics.points as f64 / f.fit.metrics.segments as f64);
        if t < NOISE_FACTOR * noise && (failed_here || t < noise) {
            let _ = writeln!(
                err,
                "metabezier: note: contour {}: the tolerance {} is below what its points' noise allows (noise about {noise:.3e}, estimated from their fourth differences): a fit to it follows the noise; a tolerance of {:.3e} or more would not",
                c.index,
                short(t),
                NOISE_FACTOR * noise
            );
        } else if let Some(k) = per_segment.filter(|&k| k < MIN_POINTS_PER_SEGMENT) {
            let _ = writeln!(
                err,
                "metabezier: note: contour {}: the tolerance {} takes a segment every {k:.1} points: the fit follows the points' noise or the pixel staircase; a larger tolerance would follow the shape",
                c.index,
                short(t)
            );
        }
    }
}

/// Fewer data points per segment than this on average, and a tolerance fit
/// follows its points rather than a shape: a rational cubic needs 5 to be
/// determined, and a smooth outline at a sensible tolerance takes dozens
/// (the scikit-image logo at 0.5 px: 7.6 on its smallest letter).
const MIN_POINTS_PER_SEGMENT: f64 = 6.0;

impl FitArgs {
    /// The segmentation asked for: a count, a tolerance, a glyph's true
    /// breaks, or the default tolerance ([`DEFAULT_TOLERANCE`]).
    fn segmentation(&self, source: &Source) -> Result<Segmentation, UsageError> {
        Ok(match (self.segments, self.tolerance, self.true_breaks) {
            (Some(n), _, _) => Segmentation::Count(usize::try_from(n).unwrap_or(usize::MAX)),
            (_, Some(t), _) => {
                if !(t.is_finite() && t > 0.0) {
                    return Err(UsageError::Tolerance(t));
                }
                self.tolerance_segmentation(t)
            }
            (_, _, true) => source
                .true_segmentation()
                .ok_or_else(|| UsageError::NotAGlyph(self.input.clone()))?,
            (None, None, false) => self.tolerance_segmentation(DEFAULT_TOLERANCE),
        })
    }

    /// The fit to tolerance `t`, with coarse trials unless `--trials full`.
    fn tolerance_segmentation(&self, t: f64) -> Segmentation {
        match self.trials {
            Trials::Full => Segmentation::Tolerance(t),
            Trials::Coarse => Segmentation::Coarse {
                tolerance: t,
                recheck: COARSE_RECHECK,
            },
        }
    }

    /// What to load: the contours asked for, the glyph sampling a fit at
    /// true breaks needs, the foreground of an image (refused for other
    /// inputs).
    fn load_options(&self) -> Result<LoadOptions, Error> {
        let function = self.function;
        let mut load = LoadOptions {
            contour: self
                .contour
                .map_or(ContourChoice::All, ContourChoice::Index),
            min_samples_per_segment: if self.true_breaks {
                function.min_points() - 1
            } else {
                1
            },
            ..LoadOptions::default()
        };
        if let Some(foreground) = self.foreground {
            if !matches!(parse_input(&self.input), Ok(Input::Image(_))) {
                return Err(UsageError::ForegroundNotImage(self.input.clone()).into());
            }
            load.image.foreground = foreground;
        }
        Ok(load)
    }

    /// The corner detector (none for an angle of 0).
    fn corners(&self) -> Option<CornerOptions> {
        (self.corner_angle > 0.0).then_some(CornerOptions {
            k: usize::from(self.corner_k),
            angle_deg: self.corner_angle,
        })
    }

    /// Function, continuity, closing, parameterisation (`auto` resolved for
    /// `source`), search space and budget.
    fn options(&self, source: &Source) -> FitOptions {
        let mut options = FitOptions::new(self.function, self.continuity);
        options.budget_per_segment = self.budget;
        options.closing = self.closing;
        options.parameterisation = match self.parameterisation {
            ParameterisationChoice::Auto => source.auto_parameterisation(self.true_breaks),
            ParameterisationChoice::Fixed(p) => p,
        };
        options.reparameterise = self.reparameterise;
        options.error = self.error;
        options.chain = self.chain;
        options.search.kind = self.search_space;
        options
    }

    /// The case columns of the fit's `metrics.csv`: everything that decides
    /// the fit, so that a file read on its own says what made it.
    fn case(&self, r: &Reconstruction<'_>, method: &Method) -> Vec<(&'static str, String)> {
        let options = &r.options;
        let (segmentation, tolerance) = match &r.segmentation {
            Segmentation::Count(n) => (format!("segments {n}"), String::new()),
            Segmentation::Tolerance(t) => ("tolerance".to_owned(), t.to_string()),
            Segmentation::Coarse { tolerance, .. } => (
                "tolerance (coarse trials)".to_owned(),
                tolerance.to_string(),
            ),
            Segmentation::TrueBreaks => ("true-breaks".to_owned(), String::new()),
            Segmentation::Breaks { .. } | Segmentation::PerContour(_) => {
                ("breaks".to_owned(), String::new())
            }
        };
        let foreground = if r.source.is_image() {
            self.foreground
                .unwrap_or(Foreground::Auto)
                .name()
                .to_owned()
        } else {
            String::new()
        };
        vec![
            ("input", self.input.clone()),
            ("function", options.function.name().to_owned()),
            ("continuity", options.continuity.name().to_owned()),
            ("closing", options.closing.name().to_owned()),
            ("algorithm", method.name()),
            ("seed", self.seed.to_string()),
            ("budget_per_segment", self.budget.to_string()),
            ("search_space", options.search.kind.name().to_owned()),
            (
                "parameterisation",
                options.parameterisation.name().to_owned(),
            ),
            ("reparameterise", self.reparameterise.to_string()),
            ("error", options.error.name().to_owned()),
            ("chain", options.chain.name().to_owned()),
            ("segmentation", segmentation),
            ("tolerance_asked", tolerance),
            ("corner_angle", self.corner_angle.to_string()),
            ("corner_k", self.corner_k.to_string()),
            ("foreground", foreground),
            (
                "contours",
                self.contour
                    .map_or(ContourChoice::All, ContourChoice::Index)
                    .name(),
            ),
        ]
    }
}

/// The summary of a fit of `label`: its metrics, each contour's closing
/// joint, and the files written.
fn say_fit(w: &mut String, label: &str, fit: &ShapeFit, wall: f64, paths: &[PathBuf]) {
    let m = &fit.metrics;
    say!(
        w,
        "{label}: {} contour(s), {} points, {} segments, Hausdorff distance = {:.4e} (data -> curve {:.4e}, curve -> data {:.4e}), RMS distance = {:.4e}, E = {:.6e}, RMS = {:.4e}, {} evaluations, {:.3} s",
        fit.contours.len(),
        m.points,
        m.segments,
        m.hausdorff,
        m.max_distance,
        m.curve_distance,
        m.rms_distance,
        m.sse,
        m.rms,
        m.evaluations,
        wall
    );
    if let Some(t) = fit
        .contours
        .iter()
        .filter_map(|c| c.fit.tolerance)
        .reduce(f64::max)
    {
        let staircase = fit.contours.iter().any(|c| c.fit.staircase);
        let (held, what) = if staircase {
            (
                m.excess,
                "two-sided distance beyond the pixel staircase's sagitta",
            )
        } else {
            (m.hausdorff, "Hausdorff distance")
        };
        say!(
            w,
            "  tolerance {} held: largest {what} {held:.4e} (curve sampled {} times per point gap)",
            short(t),
            crate::fit::OUTLINE_SAMPLES
        );
    }
    for c in &fit.contours {
        if let Some(d) = c.fit.joint_rejected {
            let why = if c.fit.tolerance.is_some() {
                "beyond the tolerance"
            } else {
                "curve where no data point is"
            };
            say!(
                w,
                "  contour {}: the joint solve strayed {d:.4e} from the outline ({why}), so the sequential chain was kept",
                c.contour
            );
        }
    }
    let at_bounds: usize = fit.contours.iter().map(|c| c.fit.weights_at_bounds).sum();
    if at_bounds > 0 {
        say!(
            w,
            "  {at_bounds} rational weight(s) at a bound of the weight range: the search box, not the data, decided them"
        );
    }
    for c in &fit.contours {
        if let Some(j) = c.fit.closing {
            let at = if j.at_corner {
                "at a corner, C0".to_owned()
            } else {
                format!("{} imposed", j.imposed.name().to_uppercase())
            };
            say!(
                w,
                "  contour {} ({} segments): closing joint {at}: tangent angle {:.3e}°, relative derivative gap {:.3e}",
                c.contour,
                c.fit.metrics.segments,
                j.angle_degrees,
                j.relative_derivative_gap
            );
        }
    }
    for p in paths {
        say!(w, "  wrote {}", p.display());
    }
}
