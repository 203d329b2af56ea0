//! `[[fit]]` sections: outline-fitting problems of a spec.
//!
//! ```toml
//! [[fit]]
//! input = ["../data/outlines/horse.png", "font:../data/outlines/Cantarell-Regular.otf:g"]
//! function = ["cubic", "rational-cubic"]   # quadratic, cubic, rational-quadratic, rational-cubic
//! continuity = ["c1", "g1"]                # c0, c1, g1
//! segments = 24                            # or "true-breaks" for glyphs
//! # free_parameters = 60                   # instead of segments: equal unknowns
//! # tolerance = 1.0                        # instead of segments: the exact fit's to 1 px
//! search_space = "technique"               # or "bounding-box", or both in a list
//! budget = 5000                            # evaluations per segment (or a list)
//! # contour = "all"                        # or an index (default 0, the largest)
//! # closing = "smooth"                     # or "c0" (the default in specs)
//! # mode = "per-segment"                   # or "outline" (the default)
//! # alpha_size = [0.1, 0.5]                # a list is a design factor
//! # error = "fixed"                        # or "orthogonal" (one per section)
//! # chain = "sequential"                   # or "joint" (one per section; outline mode)
//! ```
//!
//! Relative input paths are resolved against the spec file's directory.
//! Every combination of input × function × continuity × search space ×
//! α_size × budget is one problem, named `source/function/continuity`, with
//! `/bounding-box` for the naive search space, `/alpha=A` for a listed
//! α_size other than the default 0.5, `/per-segment` in the per-segment
//! mode, `/orthogonal` for `error = "orthogonal"` and `/joint` for
//! `chain = "joint"`, and `/params=P` for `free_parameters = P`.
//!
//! **Equal free parameters.** `free_parameters = P` replaces `segments`:
//! each function × continuity gets `round(P / k)` segments (at least one),
//! where `k` is what one segment adds to a closed chain
//! ([`FunctionType::chain_dim`]: 1/3/2/5 scalars with G1 joins and 0/2/1/4
//! with C1, quadratic, cubic, rational quadratic, rational cubic), so that
//! the functions and continuities of a section are compared at the same
//! number of unknowns rather than the same number of segments. Quadratics
//! with C1 joins add none and are refused. Each input is loaded and each problem's segmentation is checked
//! when the spec loads, so a missing image, a glyph absent from its font or
//! an impossible segmentation is reported before anything runs.
//!
//! **A tolerance.** `tolerance = T` replaces `segments`: each case's
//! segments are those of the exact (Levenberg–Marquardt) fit held to the
//! two-sided distance `T` ([`Segmentation::Tolerance`]), found when the
//! spec loads (a spec whose exact fit cannot hold `T` is refused there);
//! every method then fits those same segments, a paired design, and
//! `fits.csv` records each fit's two-sided distance next to `T`.
//!
//! **Keys stay.** The keys and values that came with the smooth closing
//! (`closing`, `mode`, `contour = "all"`, a list of `alpha_size`,
//! `parameterisation = "auto"`), `error` and `chain` are the only ones that change what a
//! campaign records: a spec with a section that uses one of them gets the
//! current fitting records for all its fitting problems (a best-so-far
//! trace in `convergence.csv`, `rms_distance` in `fits.csv`, `contour` and
//! `rms_distance` in `segments.csv`); a spec that uses none of them gives,
//! bit for bit, the files it gave before.

use std::sync::Arc;

use super::super::outcome::FitDetail;
use super::{Factor, ProblemEntry, ProblemKind};
use crate::files::fmt_real;
use crate::fit::{
    Chain, ErrorMeasure, FitError, FitOptions, SearchSpace, SegmentProblem, SegmentSolver,
    Solution, ALPHA_SIZE,
};
use crate::optim::Outcome;
use crate::outline::CornerOptions;
use crate::problem::Problem;
use crate::reconstruction::{FitMode, Method, Reconstruction, Segmentation, ShapeFit, Source};

mod section;
mod settings;

pub(crate) use settings::{FitSegments, FitSettings, Segs};

/// The most fitting problems one spec may have: 10⁴ (each is loaded and
/// dry-run when the spec is read; the thesis's campaigns have a few
/// hundred).
pub const MAX_FIT_PROBLEMS: usize = 10_000;

/// The keys of a `[[fit]]` section.
pub(super) const FIT_KEYS: [&str; 21] = [
    "input",
    "contour",
    "function",
    "continuity",
    "segments",
    "free_parameters",
    "tolerance",
    "corner_angle",
    "corner_k",
    "search_space",
    "alpha_size",
    "pt",
    "weight_range",
    "t_range",
    "parameterisation",
    "error",
    "chain",
    "budget",
    "label",
    "closing",
    "mode",
];

/// One outline-fitting problem of a spec, from a `[[fit]]` section (see
/// the module docs for the keys).
///
/// Every combination of input × function × continuity × search space ×
/// α_size × budget is one problem. Each input is loaded and each problem's
/// segmentation is checked when the spec loads.
#[derive(Clone, Debug)]
pub struct FitCase {
    /// The problem name in results: `source/function/continuity`, then
    /// `/bounding-box`, `/alpha=A`, `/per-segment` where they apply.
    pub name: String,
    /// The source's name, the first part of `name`.
    pub source_name: String,
    /// The loaded contours, shared by the cases of one input.
    pub source: Arc<Source>,
    /// How each contour is cut into segments.
    pub segmentation: Segmentation,
    /// The section's `free_parameters`, which set the segment count and
    /// end the name with `/params=P`.
    pub free_parameters: Option<usize>,
    /// The corner detector used by the segmentation.
    pub corners: Option<CornerOptions>,
    /// Function, continuity, closing, search space and budget per segment.
    pub options: FitOptions,
    /// Whether α_size is a design factor of the section (listed), so that a
    /// value other than the default is part of the name.
    pub alpha_factor: bool,
    /// The whole outline as one chain, or every segment on its own.
    pub mode: FitMode,
    /// In the per-segment mode, the exact fit whose segments give the joins.
    pub reference: Option<Arc<ShapeFit>>,
    /// Whether the campaign writes the current fitting records (some
    /// section of its spec uses a key that came with them; see the module
    /// docs).
    pub extended: bool,
}

impl FitCase {
    /// The fitting task of this case.
    pub fn reconstruction(&self) -> Reconstruction<'_> {
        Reconstruction {
            source: &self.source,
            segmentation: self.segmentation.clone(),
            corners: self.corners,
            options: self.options,
        }
    }

    /// The name without the `paired` factors (search space, α_size), which
    /// the run seeds derive from; the full name when nothing is paired.
    pub fn seed_name(&self, paired: &[Factor]) -> String {
        let o = &self.options;
        let mut name = format!(
            "{}/{}/{}",
            self.source_name,
            o.function.name(),
            o.continuity.name()
        );
        let technique = o.search.kind == SearchSpace::Technique;
        if !technique && !paired.contains(&Factor::SearchSpace) {
            name = format!("{name}/{}", o.search.kind.name());
        }
        let alpha = o.search.alpha_size;
        let default_alpha = ALPHA_SIZE.default;
        if self.alpha_factor
            && technique
            && alpha != default_alpha
            && !paired.contains(&Factor::AlphaSize)
        {
            name = format!("{name}/alpha={}", fmt_real(alpha));
        }
        if self.mode == FitMode::PerSegment {
            name.push_str("/per-segment");
        }
        if let Some(p) = self.free_parameters {
            name = format!("{name}/params={p}");
        }
        if o.error != ErrorMeasure::Fixed {
            name = format!("{name}/{}", o.error.name());
        }
        if o.chain != Chain::Sequential {
            name = format!("{name}/{}", o.chain.name());
        }
        name
    }

    /// Fits the case with `method` seeded with `seed`: the run's outcome
    /// (`E`, evaluations, success at `threshold`, and with the current
    /// records the best-so-far trace) and its fit detail.
    pub fn run(&self, method: &Method, seed: u64, threshold: f64) -> (Outcome, FitDetail) {
        let r = self.reconstruction();
        let fit = match &self.reference {
            Some(reference) => r.fit_per_segment(method, seed, reference),
            None => r.fit(method, seed),
        }
        .expect("the segmentation was checked when the spec loaded");
        let m = &fit.metrics;
        let success = m.sse <= threshold;
        let outcome = Outcome {
            best_x: Vec::new(),
            best_value: m.sse,
            evaluations: m.evaluations,
            evaluations_to_target: success.then_some(m.evaluations),
            trace: if self.extended {
                fit.trace()
            } else {
                Vec::new()
            },
            hits: Vec::new(),
        };
        (outcome, FitDetail::of(&fit, self.extended))
    }
}

impl ProblemKind for FitCase {
    fn name(&self, _: &ProblemEntry) -> String {
        self.name.clone()
    }

    fn seed_name(&self, _: &ProblemEntry, paired: &[Factor]) -> String {
        FitCase::seed_name(self, paired)
    }

    fn factor_value(&self, factor: Factor) -> Option<String> {
        match factor {
            Factor::SearchSpace => Some(self.options.search.kind.name().to_owned()),
            Factor::AlphaSize => Some(fmt_real(self.options.search.alpha_size)),
            _ => None,
        }
    }

    /// 0: the error of a fit is its `E`.
    fn optimum(&self) -> f64 {
        0.0
    }

    fn execute(
        &self,
        spec: &super::Spec,
        _: &ProblemEntry,
        method: &Method,
        seed: u64,
    ) -> (Outcome, Option<FitDetail>) {
        let (outcome, detail) = self.run(method, seed, spec.threshold);
        (outcome, Some(detail))
    }

    /// With the current records, the union of the segments' checkpoints
    /// and the evaluation each segment stopped at; one row per segment.
    fn record_shape(&self, spec: &super::Spec, entry: &ProblemEntry) -> (usize, usize, usize) {
        let per_segment = entry.budget / entry.dim.max(1) as u64;
        let points = if self.extended {
            crate::optim::evaluator::log_checkpoints(per_segment, spec.checkpoints_per_decade).len()
                + entry.dim
        } else {
            0
        };
        (points, 0, entry.dim)
    }

    fn least_squares(&self) -> bool {
        true
    }

    fn has_targets(&self) -> bool {
        false
    }
}

/// A solver that returns the centre of the search box without searching:
/// it checks that every segment problem of a case can be built.
pub(super) struct Dry;

impl SegmentSolver for Dry {
    fn solve(&mut self, problem: &SegmentProblem, _budget: u64) -> Solution {
        let x = problem.guess().to_vec();
        Solution {
            value: problem.objective(&x),
            x,
            evaluations: 0,
            parts: Vec::new(),
            trace: Vec::new(),
            params: None,
        }
    }
}

/// Checks a case by fitting it with [`Dry`]; returns the dry fit.
pub(super) fn dry_run(case: &FitCase) -> Result<ShapeFit, FitError> {
    let r = case.reconstruction();
    match &case.reference {
        Some(reference) => r.fit_per_segment_with(reference, |_, _| Dry),
        None => r.fit_with(&mut Dry),
    }
}
