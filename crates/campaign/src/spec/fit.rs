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

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use super::super::outcome::FitDetail;
use super::budget::Budget;
use super::family::Problems;
use super::parser::Parser;
use super::Factor;
use super::{choices_hint, ProblemEntry, ProblemKind, SpecError, Table, Value};
use crate::files::fmt_real;

/// The most fitting problems one spec may have: 10⁴ (each is loaded and
/// dry-run when the spec is read; the thesis's campaigns have a few
/// hundred).
pub const MAX_FIT_PROBLEMS: usize = 10_000;
use crate::fit::{
    Chain, Closing, ErrorMeasure, FitError, FitOptions, FunctionType, RealOption, SearchSpace,
    SearchSpaceOptions, SegmentProblem, SegmentSolver, Solution, ALPHA_SIZE, PT,
};
use crate::functions::Transform;
use crate::geometry::{Continuity, Parameterisation};
use crate::optim::Outcome;
use crate::outline::{CornerOptions, Sampling};
use crate::problem::Problem;
use crate::reconstruction::{
    ContourChoice, FitMode, LoadOptions, Method, Reconstruction, Segmentation, ShapeFit, Source,
};

const FIT_KEYS: [&str; 21] = [
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
struct Dry;

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
fn dry_run(case: &FitCase) -> Result<ShapeFit, FitError> {
    let r = case.reconstruction();
    match &case.reference {
        Some(reference) => r.fit_per_segment_with(reference, |_, _| Dry),
        None => r.fit_with(&mut Dry),
    }
}

impl Parser<'_> {
    /// A string or list of strings, each checked against `names`.
    fn names<T: Copy>(
        &self,
        table: &Table<'_>,
        key: &str,
        section: &str,
        default: T,
        names: &[&str],
        parse: impl Fn(&str) -> Option<T>,
    ) -> Result<Vec<T>, SpecError> {
        let Some(v) = self.get(table, key) else {
            return Ok(vec![default]);
        };
        let field = format!("{section}.{key}");
        self.one_or_many(v, &field)?
            .into_iter()
            .map(|item| {
                let s = self.string(item, &field)?;
                parse(&s).ok_or_else(|| {
                    self.error(
                        item.span(),
                        &field,
                        format!("unknown value \"{s}\"; {}", choices_hint(&s, names)),
                    )
                })
            })
            .collect()
    }

    /// A finite real in `[lo, hi]` (`lo_open`: strictly above `lo`).
    fn real_in(
        &self,
        table: &Table<'_>,
        key: &str,
        section: &str,
        (lo, hi): (f64, f64),
        lo_open: bool,
    ) -> Result<Option<f64>, SpecError> {
        let Some(v) = self.get(table, key) else {
            return Ok(None);
        };
        let field = format!("{section}.{key}");
        let x = self.real(v, &field)?;
        let ok = x.is_finite() && (if lo_open { x > lo } else { x >= lo }) && x <= hi;
        if !ok {
            let open = if lo_open { "(" } else { "[" };
            return Err(self.error(
                v.span(),
                &field,
                format!("expected a real number in {open}{lo}, {hi}], found {x}"),
            ));
        }
        Ok(Some(x))
    }

    /// The optional real-valued fitting option `option`, in its range.
    fn real_option(
        &self,
        table: &Table<'_>,
        option: &RealOption,
        section: &str,
    ) -> Result<Option<f64>, SpecError> {
        let Some(v) = self.get(table, option.name) else {
            return Ok(None);
        };
        let field = format!("{section}.{}", option.name);
        self.option_value(v, option, &field).map(Some)
    }

    /// The value `v` of `option`, in its range.
    fn option_value(
        &self,
        v: &Value<'_>,
        option: &RealOption,
        field: &str,
    ) -> Result<f64, SpecError> {
        let x = self.real(v, field)?;
        if !option.contains(x) {
            return Err(self.error(
                v.span(),
                field,
                format!("expected {}, found {x}", option.expected),
            ));
        }
        Ok(x)
    }

    /// A pair `[min, max]` with `0 < min < max`, both finite.
    fn positive_range(
        &self,
        table: &Table<'_>,
        key: &str,
        section: &str,
        what: &str,
    ) -> Result<Option<(f64, f64)>, SpecError> {
        let Some(v) = self.get(table, key) else {
            return Ok(None);
        };
        let field = format!("{section}.{key}");
        let items = match v.get_ref() {
            toml::de::DeValue::Array(items) if items.len() == 2 => items,
            _ => {
                return Err(self.error(
                    v.span(),
                    &field,
                    format!("expected a pair [min, max] of {what}"),
                ))
            }
        };
        let a = self.real(&items[0], &field)?;
        let b = self.real(&items[1], &field)?;
        if !(a.is_finite() && b.is_finite() && a > 0.0 && a < b) {
            return Err(self.error(
                v.span(),
                &field,
                format!(
                    "expected 0 < min < max (finite) for {what}, found [{a}, {b}]{}",
                    if a <= 0.0 {
                        ": the range must exclude 0, since weights and ratios must stay positive"
                    } else {
                        ""
                    }
                ),
            ));
        }
        Ok(Some((a, b)))
    }

    /// The `[[fit]]` problems of the spec, appended to `problems`.
    pub(super) fn fits(
        &self,
        root: &Table<'_>,
        default_budget: Option<&Budget>,
        span: Range<usize>,
        problems: &mut Problems,
    ) -> Result<(), SpecError> {
        let base = self
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let first = problems.list.len();
        for (i, entry) in self
            .array_of_tables(root, "fit", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("fit[{}]", i + 1);
            let at = (first, base.as_path());
            self.fit_section(entry, &section, default_budget, at, problems)?;
        }
        // One record layout per campaign: the current one if any section
        // asks for it.
        let fits = &mut problems.list[first..];
        let current = fits
            .iter()
            .any(|p| p.kind_as::<FitCase>().is_some_and(|c| c.extended));
        for p in fits {
            // Each case has one owner until the spec is returned.
            let kind: Option<&mut dyn std::any::Any> =
                Arc::get_mut(&mut p.kind).map(|k| k as &mut dyn std::any::Any);
            if let Some(c) = kind.and_then(|k| k.downcast_mut::<FitCase>()) {
                c.extended = current;
            }
        }
        Ok(())
    }

    /// Appends the problems of one `[[fit]]` section to `problems`, whose
    /// fitting problems start at `first`: every input × function ×
    /// continuity × search space × α_size × budget, each dry-run.
    fn fit_section(
        &self,
        entry: &Value<'_>,
        section: &str,
        default_budget: Option<&Budget>,
        (first, base): (usize, &Path),
        problems: &mut Problems,
    ) -> Result<(), SpecError> {
        let have = problems.list.len() - first;
        let table = self.table(entry, section)?;
        self.check_keys(table, section, &FIT_KEYS)?;
        let settings = self.fit_settings(table, section, entry, default_budget)?;
        let segments = self.fit_segments(table, section, entry)?;
        let iv = self.required(table, section, "input", entry.span())?;
        let input_field = format!("{section}.input");
        let inputs = self.one_or_many(iv, &input_field)?;
        let label = self.fit_label(table, section, inputs.len())?;
        let count = (inputs.len() as u128).saturating_mul(settings.count());
        self.check_problem_count(have, count, &entry.span(), section)?;
        if have as u128 + count > MAX_FIT_PROBLEMS as u128 {
            return Err(self.error(
                entry.span(),
                section,
                format!(
                    "this section makes {count} fitting problems{}, over the limit of {MAX_FIT_PROBLEMS} fitting problems of a spec (each is loaded and dry-run when the spec is read); split the spec",
                    if have == 0 {
                        String::new()
                    } else {
                        format!(" (after {have} before it)")
                    }
                ),
            ));
        }
        for item in inputs {
            let text = self.string(item, &input_field)?;
            let load = settings.load_options(&segments);
            let source = Source::load(&text, base, &load)
                .map_err(|e| self.error(item.span(), &input_field, e.to_string()))?;
            let segmentation = self.fit_segmentation(&segments, &source, &text)?;
            let free_parameters = match segments.kind {
                Segs::FreeParameters(p) => Some(p),
                _ => None,
            };
            let source_name = label.clone().unwrap_or_else(|| source.label());
            let source = Arc::new(source);
            let mut references: HashMap<(FunctionType, Continuity), Arc<ShapeFit>> = HashMap::new();
            let mut held = HashMap::new();
            for options in settings.options(&source, &segments) {
                let segmentation = match (free_parameters, segments.kind) {
                    (Some(p), _) => self.count_for(&segments, p, &options)?,
                    (None, Segs::Tolerance(t)) => {
                        let key = (options.function, options.continuity);
                        match held.get(&key) {
                            Some(s) => Segmentation::clone(s),
                            None => {
                                let s = self.tolerance_breaks(
                                    &source,
                                    &source_name,
                                    &settings,
                                    &options,
                                    t,
                                    &segments,
                                )?;
                                held.insert(key, s.clone());
                                s
                            }
                        }
                    }
                    (None, _) => segmentation.clone(),
                };
                let mut case = FitCase {
                    name: String::new(),
                    source_name: source_name.clone(),
                    source: Arc::clone(&source),
                    segmentation,
                    free_parameters,
                    corners: settings.corners,
                    options,
                    alpha_factor: settings.alpha_grid,
                    mode: settings.mode,
                    reference: None,
                    extended: settings.extended,
                };
                case.name = case.seed_name(&[]);
                if case.mode == FitMode::PerSegment {
                    let key = (options.function, options.continuity);
                    let reference = match references.get(&key) {
                        Some(r) => Arc::clone(r),
                        None => {
                            let r = Arc::new(self.reference_fit(&case, &segments)?);
                            references.insert(key, Arc::clone(&r));
                            r
                        }
                    };
                    case.reference = Some(reference);
                }
                let mut p = self.fit_problem(case, &segments)?;
                p.budget_factor = settings.budget_grid;
                problems.push(self, p, item.span(), section)?;
            }
        }
        Ok(())
    }

    /// The exact (LM) fit of a per-segment case whose segments give the
    /// joins: the case's segmentation and closing, the default search space
    /// and 10 000 evaluations per segment, so that every search space,
    /// α_size and budget of the case meets the same neighbours.
    fn reference_fit(
        &self,
        case: &FitCase,
        segments: &FitSegments<'_, '_>,
    ) -> Result<ShapeFit, SpecError> {
        let mut r = case.reconstruction();
        r.options.search = SearchSpaceOptions::default();
        r.options.budget_per_segment = FitOptions::default().budget_per_segment;
        r.reference().map_err(|e| {
            self.error(
                segments.value.span(),
                &segments.field,
                format!("{}: the exact reference fit failed: {e}", case.name),
            )
        })
    }

    /// The keys of a `[[fit]]` section shared by all its problems, read
    /// in order: budget, contour, the choices, corners, search space,
    /// closing and mode.
    fn fit_settings(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
        default_budget: Option<&Budget>,
    ) -> Result<FitSettings, SpecError> {
        let (budgets, budget_grid) = self.fit_budget(table, section, entry, default_budget)?;
        let contour = self.fit_contour(table, section)?;
        let choices = self.fit_choices(table, section, entry)?;
        let corners = self.fit_corners(table, section)?;
        let search = self.search_overrides(table, section)?;
        let closing = self.names(
            table,
            "closing",
            section,
            Closing::C0,
            &Closing::NAMES,
            Closing::from_name,
        )?;
        let mode = self.names(
            table,
            "mode",
            section,
            FitMode::Outline,
            &FitMode::NAMES,
            FitMode::from_name,
        )?;
        let closing = self.one(
            &closing,
            entry,
            section,
            "closing",
            "expected one closing, not a list",
        )?;
        let mode = self.one(
            &mode,
            entry,
            section,
            "mode",
            "expected one mode, not a list",
        )?;
        if mode == FitMode::PerSegment && choices.chain == Chain::Joint {
            let at = self.get(table, "chain").map_or(entry.span(), |v| v.span());
            return Err(self.error(
                at,
                &format!("{section}.chain"),
                "expected \"sequential\" with mode = \"per-segment\" (each segment is its own \
                 problem there, so there is no chain to solve jointly); use mode = \"outline\" \
                 for the joint chain"
                    .to_owned(),
            ));
        }
        let alpha_grid = search.alpha_sizes.as_ref().is_some_and(|a| a.len() > 1);
        let extended = self.get(table, "closing").is_some()
            || self.get(table, "free_parameters").is_some()
            || self.get(table, "error").is_some()
            || self.get(table, "chain").is_some()
            || self.get(table, "mode").is_some()
            || contour == ContourChoice::All
            || alpha_grid
            || choices.parameterisation.is_none();
        Ok(FitSettings {
            budgets,
            budget_grid,
            contour,
            choices,
            corners,
            search,
            alpha_grid,
            closing,
            mode,
            extended,
        })
    }

    /// The only value of a key that takes one (`closing`, `mode`,
    /// `parameterisation`, `error`); a list of several is refused with the
    /// message `expected` (`one_or_many` refuses an empty one).
    fn one<T: Copy>(
        &self,
        values: &[T],
        entry: &Value<'_>,
        section: &str,
        key: &str,
        expected: &str,
    ) -> Result<T, SpecError> {
        match values {
            [one] => Ok(*one),
            _ => Err(self.error(
                entry.span(),
                &format!("{section}.{key}"),
                expected.to_owned(),
            )),
        }
    }

    /// The optional `contour`: an index (default 0, the largest) or `"all"`.
    fn fit_contour(&self, table: &Table<'_>, section: &str) -> Result<ContourChoice, SpecError> {
        let Some(v) = self.get(table, "contour") else {
            return Ok(ContourChoice::Index(0));
        };
        let field = format!("{section}.contour");
        if let Some(s) = raw_string(v) {
            if s == "all" {
                return Ok(ContourChoice::All);
            }
            return Err(self.error(
                v.span(),
                &field,
                format!("expected a contour number ≥ 0 or \"all\", found \"{s}\""),
            ));
        }
        Ok(ContourChoice::Index(
            self.integer(v, &field, 0, 1_000_000)? as usize
        ))
    }

    /// Evaluations per segment: the section's `budget` (a value or a list),
    /// else the experiment's fixed one (a per-dimension budget does not
    /// apply). Returns the budgets and whether they form a grid.
    fn fit_budget(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
        default_budget: Option<&Budget>,
    ) -> Result<(Vec<u64>, bool), SpecError> {
        match self.get(table, "budget") {
            Some(v) => {
                let field = format!("{section}.budget");
                let values = self
                    .one_or_many(v, &field)?
                    .into_iter()
                    .map(|item| self.budget_value(item, &field))
                    .collect::<Result<Vec<u64>, SpecError>>()?;
                let grid = values.len() > 1;
                Ok((values, grid))
            }
            None => match default_budget {
                Some(b @ Budget::Fixed(values)) => Ok((values.clone(), b.is_grid())),
                Some(Budget::PerDim(_)) | None => Err(self.error(
                    entry.span(),
                    &format!("{section}.budget"),
                    "no budget: give \"budget\" (evaluations per segment) in [experiment] or in this [[fit]]; \"budget_per_dim\" does not apply to fitting".into(),
                )),
            },
        }
    }

    /// The functions, continuities and search spaces to combine, and the
    /// one parameterisation.
    fn fit_choices(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<FitChoices, SpecError> {
        let functions = self.names(
            table,
            "function",
            section,
            FunctionType::RationalCubic,
            &FunctionType::NAMES,
            FunctionType::from_name,
        )?;
        let continuities = self.names(
            table,
            "continuity",
            section,
            Continuity::G1,
            &Continuity::NAMES,
            Continuity::from_name,
        )?;
        let spaces = self.names(
            table,
            "search_space",
            section,
            SearchSpace::Technique,
            &SearchSpace::NAMES,
            SearchSpace::from_name,
        )?;
        let mut names: Vec<&str> = vec!["auto"];
        names.extend(Parameterisation::NAMES);
        let parameterisation = self.names(
            table,
            "parameterisation",
            section,
            Some(Parameterisation::ChordLength),
            &names,
            |n| match n {
                "auto" => Some(None),
                other => Parameterisation::from_name(other).map(Some),
            },
        )?;
        let parameterisation = self.one(
            &parameterisation,
            entry,
            section,
            "parameterisation",
            "expected one parameterisation, not a list",
        )?;
        let error = self.names(
            table,
            "error",
            section,
            ErrorMeasure::Fixed,
            &ErrorMeasure::NAMES,
            ErrorMeasure::from_name,
        )?;
        let error = self.one(
            &error,
            entry,
            section,
            "error",
            "expected one error measure, not a list (one [[fit]] section per measure)",
        )?;
        let chain = self.names(
            table,
            "chain",
            section,
            Chain::Sequential,
            &Chain::NAMES,
            Chain::from_name,
        )?;
        let chain = self.one(
            &chain,
            entry,
            section,
            "chain",
            "expected one chain, not a list (one [[fit]] section per chain)",
        )?;
        Ok(FitChoices {
            functions,
            continuities,
            spaces,
            parameterisation,
            error,
            chain,
        })
    }

    /// The corner detector of `corner_angle` and `corner_k` (none for an
    /// angle of 0).
    fn fit_corners(
        &self,
        table: &Table<'_>,
        section: &str,
    ) -> Result<Option<CornerOptions>, SpecError> {
        let corner_angle = self
            .real_in(table, "corner_angle", section, (0.0, 180.0), false)?
            .unwrap_or(60.0);
        let corner_k = match self.get(table, "corner_k") {
            Some(v) => self.integer(v, &format!("{section}.corner_k"), 1, 10_000)? as usize,
            None => 5,
        };
        Ok((corner_angle > 0.0).then_some(CornerOptions {
            k: corner_k,
            angle_deg: corner_angle,
        }))
    }

    /// The search-space settings a section overrides.
    fn search_overrides(
        &self,
        table: &Table<'_>,
        section: &str,
    ) -> Result<SearchOverrides, SpecError> {
        Ok(SearchOverrides {
            alpha_sizes: self.alpha_sizes(table, section)?,
            pt: self.real_option(table, &PT, section)?,
            weight_range: self.positive_range(
                table,
                "weight_range",
                section,
                "the rational weights",
            )?,
            t_range: self.positive_range(table, "t_range", section, "the G1 ratio T")?,
        })
    }

    /// The optional `alpha_size`: a value or a list, each in the range of
    /// [`ALPHA_SIZE`].
    fn alpha_sizes(&self, table: &Table<'_>, section: &str) -> Result<Option<Vec<f64>>, SpecError> {
        let Some(v) = self.get(table, "alpha_size") else {
            return Ok(None);
        };
        let field = format!("{section}.alpha_size");
        let mut out = Vec::new();
        for item in self.one_or_many(v, &field)? {
            let x = self.option_value(item, &ALPHA_SIZE, &field)?;
            if out.contains(&x) {
                return Err(self.error(item.span(), &field, format!("{x} is listed twice")));
            }
            out.push(x);
        }
        Ok(Some(out))
    }

    /// The required `segments` (a count or `"true-breaks"`), or in its
    /// place `free_parameters` (a count of unknowns per chain).
    fn fit_segments<'t, 'i>(
        &self,
        table: &'t Table<'i>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<FitSegments<'t, 'i>, SpecError> {
        if let Some(value) = self.get(table, "free_parameters") {
            let field = format!("{section}.free_parameters");
            if let Some(s) = self.get(table, "segments") {
                return Err(self.error(
                    s.span(),
                    &format!("{section}.segments"),
                    "expected either segments or free_parameters, not both (free_parameters \
                     sets the number of segments of each function and continuity)"
                        .to_owned(),
                ));
            }
            let p = self.integer(value, &field, 1, 1_000_000)? as usize;
            return Ok(FitSegments {
                kind: Segs::FreeParameters(p),
                value,
                field,
            });
        }
        if let Some(found) = self.fit_tolerance(table, section)? {
            return Ok(found);
        }
        let value = self.required(table, section, "segments", entry.span())?;
        let field = format!("{section}.segments");
        let kind = match raw_string(value) {
            Some(s) if s == "true-breaks" => Segs::TrueBreaks,
            Some(s) => {
                return Err(self.error(
                    value.span(),
                    &field,
                    format!("expected a number of segments ≥ 1 or \"true-breaks\", found \"{s}\""),
                ))
            }
            None => Segs::Count(self.integer(value, &field, 1, 100_000)? as usize),
        };
        Ok(FitSegments { kind, value, field })
    }

    /// The optional `label`, which names a single input only.
    fn fit_label(
        &self,
        table: &Table<'_>,
        section: &str,
        inputs: usize,
    ) -> Result<Option<String>, SpecError> {
        match self.get(table, "label") {
            Some(v) if inputs == 1 => Ok(Some(self.string(v, &format!("{section}.label"))?)),
            Some(v) => Err(self.error(
                v.span(),
                &format!("{section}.label"),
                "a label names one input; with several inputs, leave it out (each is named after its file)".into(),
            )),
            None => Ok(None),
        }
    }

    /// The segmentation of `source` (the input `text`): the count, or a
    /// glyph's true breaks.
    fn fit_segmentation(
        &self,
        segments: &FitSegments<'_, '_>,
        source: &Source,
        text: &str,
    ) -> Result<Segmentation, SpecError> {
        match segments.kind {
            Segs::Count(n) => Ok(Segmentation::Count(n)),
            // Set per function and continuity by `count_for` and
            // `tolerance_breaks`.
            Segs::FreeParameters(_) | Segs::Tolerance(_) => Ok(Segmentation::Count(1)),
            Segs::TrueBreaks => source.true_segmentation().ok_or_else(|| {
                self.error(
                    segments.value.span(),
                    &segments.field,
                    format!("\"true-breaks\" needs a glyph input (font:PATH:GLYPH), but \"{text}\" is not one"),
                )
            }),
        }
    }

    /// The segmentation that gives the function and continuity of
    /// `options` about `p` free parameters: `round(p / k)` segments, at
    /// least one, `k` the scalars a segment adds to a closed chain
    /// ([`FunctionType::chain_dim`]).
    fn count_for(
        &self,
        segments: &FitSegments<'_, '_>,
        p: usize,
        options: &FitOptions,
    ) -> Result<Segmentation, SpecError> {
        let k = options.function.chain_dim(options.continuity);
        if k == 0 {
            return Err(self.error(
                segments.value.span(),
                &segments.field,
                format!(
                    "a {} segment with {} joins adds no free parameter to its chain (its \
                     first segment determines all the others), so free_parameters cannot set \
                     its number of segments; give that function and continuity a section of \
                     their own with segments = N",
                    options.function.name(),
                    options.continuity.name().to_uppercase()
                ),
            ));
        }
        Ok(Segmentation::Count(((p + k / 2) / k).max(1)))
    }

    /// The problem of a case, checked by a dry run: its dimension is its
    /// number of segments, its budget that of every segment (at most the
    /// limit of one run in all).
    fn fit_problem(
        &self,
        case: FitCase,
        segments: &FitSegments<'_, '_>,
    ) -> Result<ProblemEntry, SpecError> {
        let dry = dry_run(&case).map_err(|e| {
            self.error(
                segments.value.span(),
                &segments.field,
                format!("{}: {e}", case.name),
            )
        })?;
        let (segments_span, budget_field) = (segments.value.span(), segments.field.clone());
        let segments = dry.metrics.segments;
        let budget = case
            .options
            .budget_per_segment
            .saturating_mul(segments as u64);
        if budget > self.limits.max_budget {
            return Err(self.error(
                segments_span,
                &budget_field,
                format!(
                    "{}: {} evaluations per segment × {segments} segments = {budget} evaluations per run pass the limit of {}; pass --allow-large to run budgets above it",
                    case.name, case.options.budget_per_segment, self.limits.max_budget
                ),
            ));
        }
        Ok(ProblemEntry {
            budget: case
                .options
                .budget_per_segment
                .saturating_mul(segments as u64),
            kind: Arc::new(case),
            dim: segments,
            budget_factor: false,
            transform: Transform::None,
            instance: 1,
        })
    }
}

/// The keys of a `[[fit]]` section shared by all its problems.
pub(super) struct FitSettings {
    /// Evaluations per segment, one problem each.
    budgets: Vec<u64>,
    /// Whether the budgets were listed (a budget grid).
    budget_grid: bool,
    /// Which outlines of each input.
    contour: ContourChoice,
    /// What to combine.
    choices: FitChoices,
    /// The corner detector.
    pub(super) corners: Option<CornerOptions>,
    /// Search-space settings given in the section.
    search: SearchOverrides,
    /// Whether α_size is listed (a design factor).
    alpha_grid: bool,
    /// How closed outlines close (`c0` unless the section says otherwise).
    closing: Closing,
    /// Outline or per-segment problems.
    mode: FitMode,
    /// Whether the section uses the current fitting records.
    extended: bool,
}

impl FitSettings {
    /// How the inputs are read: the contours asked for, and for a fit at a
    /// glyph's own breaks enough samples on every segment for every function
    /// of the section (segments that had enough keep their samples).
    fn load_options(&self, segments: &FitSegments<'_, '_>) -> LoadOptions {
        let min = match segments.kind {
            Segs::TrueBreaks => self
                .choices
                .functions
                .iter()
                .map(|f| f.min_points() - 1)
                .max()
                .unwrap_or(1),
            Segs::Count(_) | Segs::FreeParameters(_) | Segs::Tolerance(_) => 1,
        };
        LoadOptions {
            contour: self.contour,
            sampling: Sampling::default(),
            min_samples_per_segment: min,
            ..LoadOptions::default()
        }
    }

    /// The α_size values of a search space: the listed ones for the
    /// technique, one value for the bounding box (which does not use it).
    fn alphas(&self, space: SearchSpace) -> Vec<Option<f64>> {
        match &self.search.alpha_sizes {
            Some(a) if space == SearchSpace::Technique => a.iter().copied().map(Some).collect(),
            Some(a) if !self.alpha_grid => vec![a.first().copied()],
            _ => vec![None],
        }
    }

    /// The number of [`FitSettings::options`], counted without listing them.
    fn count(&self) -> u128 {
        let c = &self.choices;
        let alphas: u128 = c.spaces.iter().map(|&s| self.alphas(s).len() as u128).sum();
        (c.functions.len() as u128)
            .saturating_mul(c.continuities.len() as u128)
            .saturating_mul(alphas)
            .saturating_mul(self.budgets.len() as u128)
    }

    /// The fit options of every function × continuity × search space ×
    /// α_size × budget, first function slowest; `auto` parameterisation
    /// resolved for `source`.
    fn options(&self, source: &Source, segments: &FitSegments<'_, '_>) -> Vec<FitOptions> {
        let c = &self.choices;
        let true_breaks = matches!(segments.kind, Segs::TrueBreaks);
        let parameterisation = c
            .parameterisation
            .unwrap_or_else(|| source.auto_parameterisation(true_breaks));
        let mut out = Vec::new();
        for &function in &c.functions {
            for &continuity in &c.continuities {
                for &space in &c.spaces {
                    for alpha in self.alphas(space) {
                        for &budget in &self.budgets {
                            let mut options = FitOptions::new(function, continuity);
                            options.closing = self.closing;
                            options.parameterisation = parameterisation;
                            options.error = c.error;
                            options.chain = c.chain;
                            options.budget_per_segment = budget;
                            options.search.kind = space;
                            if let Some(a) = alpha {
                                options.search.alpha_size = a;
                            }
                            self.search.apply(&mut options);
                            out.push(options);
                        }
                    }
                }
            }
        }
        out
    }
}

/// The lists a `[[fit]]` section combines, and its parameterisation
/// (`None` for `auto`).
struct FitChoices {
    functions: Vec<FunctionType>,
    continuities: Vec<Continuity>,
    spaces: Vec<SearchSpace>,
    parameterisation: Option<Parameterisation>,
    error: ErrorMeasure,
    chain: Chain,
}

/// Search-space settings of a `[[fit]]` section; `None` keeps the default.
struct SearchOverrides {
    alpha_sizes: Option<Vec<f64>>,
    pt: Option<f64>,
    weight_range: Option<(f64, f64)>,
    t_range: Option<(f64, f64)>,
}

impl SearchOverrides {
    /// Sets the given settings other than α_size in `options`.
    fn apply(&self, options: &mut FitOptions) {
        if let Some(p) = self.pt {
            options.search.pt = p;
        }
        if let Some(w) = self.weight_range {
            options.search.weight_range = w;
        }
        if let Some(t) = self.t_range {
            options.search.t_range = t;
        }
    }
}

/// How a section's outlines are cut into segments.
#[derive(Clone, Copy)]
pub(super) enum Segs {
    /// This many segments.
    Count(usize),
    /// A glyph's own break points.
    TrueBreaks,
    /// As many segments as give each function and continuity this many
    /// free parameters.
    FreeParameters(usize),
    /// The segments of the exact fit to this tolerance.
    Tolerance(f64),
}

/// The `segments` key of a section, with its value and field for errors
/// found later (a non-glyph input, a segment that cannot be fitted).
pub(super) struct FitSegments<'t, 'i> {
    pub(super) kind: Segs,
    pub(super) value: &'t Value<'i>,
    pub(super) field: String,
}

fn raw_string(v: &Value<'_>) -> Option<String> {
    match v.get_ref() {
        toml::de::DeValue::String(s) => Some(s.to_string()),
        _ => None,
    }
}
