//! `[[fit]]` sections: outline-fitting problems of a spec.
//!
//! ```toml
//! [[fit]]
//! input = ["../data/outlines/horse.png", "font:../data/outlines/Cantarell-Regular.otf:g"]
//! function = ["cubic", "rational-cubic"]   # quadratic, cubic, rational-quadratic, rational-cubic
//! continuity = ["c1", "g1"]                # c0, c1, g1
//! segments = 24                            # or "true-breaks" for glyphs
//! search_space = "technique"               # or "bounding-box", or both in a list
//! budget = 5000                            # evaluations per segment
//! ```
//!
//! Relative input paths are resolved against the spec file's directory.
//! Every combination of input × function × continuity × search space is one
//! problem, named `source/function/continuity` (with `/bounding-box`
//! appended for the naive search space). Each input is loaded and each
//! problem's segmentation is checked when the spec loads, so a missing
//! image, a glyph absent from its font or a segment with too few points is
//! reported before anything runs.

use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use super::{choices_hint, Budget, Parser, ProblemEntry, ProblemKind, SpecError, Table, Value};
use crate::fit::{
    FitOptions, FunctionType, PiecewiseFit, SearchSpace, SegmentProblem, SegmentSolver, Solution,
};
use crate::functions::Transform;
use crate::geometry::{Continuity, Parameterisation};
use crate::outline::{CornerOptions, ImageOptions, Sampling};
use crate::problem::Problem;
use crate::reconstruction::{Reconstruction, Segmentation, Source};

const FIT_KEYS: [&str; 15] = [
    "input",
    "contour",
    "function",
    "continuity",
    "segments",
    "corner_angle",
    "corner_k",
    "search_space",
    "alpha_size",
    "pt",
    "weight_range",
    "t_range",
    "parameterisation",
    "budget",
    "label",
];

/// One outline-fitting problem of a spec, from a `[[fit]]` section.
///
/// ```toml
/// [[fit]]
/// input = ["../data/outlines/horse.png", "font:../data/outlines/Cantarell-Regular.otf:g"]
/// function = ["cubic", "rational-cubic"]   # quadratic, cubic, rational-quadratic, rational-cubic
/// continuity = ["c1", "g1"]                # c0, c1, g1
/// segments = 24                            # or "true-breaks" for glyphs
/// search_space = "technique"               # or "bounding-box", or both in a list
/// budget = 5000                            # evaluations per segment
/// ```
///
/// Relative input paths are resolved against the spec file's directory.
/// Every combination of input × function × continuity × search space is one
/// problem, named `source/function/continuity` (with `/bounding-box`
/// appended for the naive search space). Each input is loaded and each
/// problem's segmentation is checked when the spec loads, so a missing
/// image, a glyph absent from its font or a segment with too few points is
/// reported before anything runs.
#[derive(Clone, Debug)]
pub struct FitCase {
    /// The problem name in results, `source/function/continuity` (and
    /// `/bounding-box` for the naive search space).
    pub name: String,
    /// `source/function/continuity`: the name without the search space
    /// (the seed key when `search_space` is paired).
    pub base_name: String,
    /// The source's name, the first part of `name`.
    pub source_name: String,
    /// The loaded outline, shared by the cases of one input.
    pub source: Arc<Source>,
    /// How the outline is cut into segments.
    pub segmentation: Segmentation,
    /// The corner detector used by the segmentation.
    pub corners: Option<CornerOptions>,
    /// Function, continuity, search space and budget per segment.
    pub options: FitOptions,
}

impl FitCase {
    /// The fitting task of this case.
    pub fn reconstruction(&self) -> Reconstruction<'_> {
        Reconstruction {
            outline: &self.source.outline,
            segmentation: self.segmentation.clone(),
            corners: self.corners,
            options: self.options,
        }
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
        }
    }
}

/// Checks a case by fitting it with [`Dry`]; returns the dry fit.
fn dry_run(case: &FitCase) -> Result<PiecewiseFit, crate::fit::FitError> {
    case.reconstruction().fit_with(&mut Dry)
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

    /// The `[[fit]]` problems of the spec.
    pub(super) fn fits(
        &self,
        root: &Table<'_>,
        default_budget: Option<&Budget>,
        span: Range<usize>,
    ) -> Result<Vec<ProblemEntry>, SpecError> {
        let base = self
            .path
            .parent()
            .map(Path::to_path_buf)
            .unwrap_or_default();
        let mut out: Vec<ProblemEntry> = Vec::new();
        for (i, entry) in self
            .array_of_tables(root, "fit", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("fit[{}]", i + 1);
            self.fit_section(entry, &section, default_budget, &base, &mut out)?;
        }
        Ok(out)
    }

    /// Appends the problems of one `[[fit]]` section to `out`: every input
    /// × function × continuity × search space, each dry-run.
    fn fit_section(
        &self,
        entry: &Value<'_>,
        section: &str,
        default_budget: Option<&Budget>,
        base: &Path,
        out: &mut Vec<ProblemEntry>,
    ) -> Result<(), SpecError> {
        let table = self.table(entry, section)?;
        self.check_keys(table, section, &FIT_KEYS)?;
        let settings = self.fit_settings(table, section, entry, default_budget)?;
        let segments = self.fit_segments(table, section, entry)?;
        let iv = self.required(table, section, "input", entry.span())?;
        let input_field = format!("{section}.input");
        let inputs = self.one_or_many(iv, &input_field)?;
        let label = self.fit_label(table, section, inputs.len())?;
        for item in inputs {
            let text = self.string(item, &input_field)?;
            let source = Source::load(
                &text,
                base,
                settings.contour,
                &ImageOptions::default(),
                Sampling::default(),
            )
            .map_err(|e| self.error(item.span(), &input_field, e.to_string()))?;
            let segmentation = self.fit_segmentation(&segments, &source, &text)?;
            let source_name = label.clone().unwrap_or_else(|| source.label());
            let source = Arc::new(source);
            for options in settings.options() {
                let case = FitCase {
                    name: case_name(&source_name, &options),
                    base_name: base_name(&source_name, &options),
                    source_name: source_name.clone(),
                    source: Arc::clone(&source),
                    segmentation: segmentation.clone(),
                    corners: settings.corners,
                    options,
                };
                let mut p = self.fit_problem(case, &segments)?;
                p.budget_factor = settings.budget_grid;
                if out.iter().any(|q| q.key() == p.key()) {
                    return Err(self.error(
                        item.span(),
                        section,
                        format!("problem {} is listed twice", p.key()),
                    ));
                }
                out.push(p);
            }
        }
        Ok(())
    }

    /// The keys of a `[[fit]]` section shared by all its problems, read
    /// in order: budget, contour, the choices, corners, search space.
    fn fit_settings(
        &self,
        table: &Table<'_>,
        section: &str,
        entry: &Value<'_>,
        default_budget: Option<&Budget>,
    ) -> Result<FitSettings, SpecError> {
        let (budgets, budget_grid) = self.fit_budget(table, section, entry, default_budget)?;
        let contour = match self.get(table, "contour") {
            Some(v) => self.integer(v, &format!("{section}.contour"), 0, 1_000_000)? as usize,
            None => 0,
        };
        let choices = self.fit_choices(table, section, entry)?;
        let corners = self.fit_corners(table, section)?;
        let search = self.search_overrides(table, section)?;
        Ok(FitSettings {
            budgets,
            budget_grid,
            contour,
            choices,
            corners,
            search,
        })
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
                    .map(|item| self.integer(item, &field, 1, u64::MAX))
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
        let parameterisation = self.names(
            table,
            "parameterisation",
            section,
            Parameterisation::ChordLength,
            &Parameterisation::NAMES,
            Parameterisation::from_name,
        )?;
        let [parameterisation] = parameterisation[..] else {
            return Err(self.error(
                entry.span(),
                &format!("{section}.parameterisation"),
                "expected one parameterisation, not a list".into(),
            ));
        };
        Ok(FitChoices {
            functions,
            continuities,
            spaces,
            parameterisation,
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
            alpha_size: self.real_in(table, "alpha_size", section, (0.0, 1e6), true)?,
            pt: self.real_in(table, "pt", section, (0.0, 1.0), false)?,
            weight_range: self.positive_range(
                table,
                "weight_range",
                section,
                "the rational weights",
            )?,
            t_range: self.positive_range(table, "t_range", section, "the G1 ratio T")?,
        })
    }

    /// The required `segments`: a count or `"true-breaks"`.
    fn fit_segments<'t, 'i>(
        &self,
        table: &'t Table<'i>,
        section: &str,
        entry: &Value<'_>,
    ) -> Result<FitSegments<'t, 'i>, SpecError> {
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
            Segs::TrueBreaks => source.true_segmentation().ok_or_else(|| {
                self.error(
                    segments.value.span(),
                    &segments.field,
                    format!("\"true-breaks\" needs a glyph input (font:PATH:GLYPH), but \"{text}\" is not one"),
                )
            }),
        }
    }

    /// The problem of a case, checked by a dry run: its dimension is its
    /// number of segments, its budget that of every segment.
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
        let segments = dry.segments.len();
        Ok(ProblemEntry {
            budget: case
                .options
                .budget_per_segment
                .saturating_mul(segments as u64),
            kind: ProblemKind::Fit(Box::new(case)),
            dim: segments,
            budget_factor: false,
            transform: Transform::None,
            instance: 1,
        })
    }
}

/// The keys of a `[[fit]]` section shared by all its problems.
struct FitSettings {
    /// Evaluations per segment, one problem each.
    budgets: Vec<u64>,
    /// Whether the budgets were listed (a budget grid).
    budget_grid: bool,
    /// Which outline of each input.
    contour: usize,
    /// What to combine.
    choices: FitChoices,
    /// The corner detector.
    corners: Option<CornerOptions>,
    /// Search-space settings given in the section.
    search: SearchOverrides,
}

impl FitSettings {
    /// The fit options of every function × continuity × search space ×
    /// budget, first function slowest.
    fn options(&self) -> Vec<FitOptions> {
        let c = &self.choices;
        let mut out = Vec::new();
        for &function in &c.functions {
            for &continuity in &c.continuities {
                for &space in &c.spaces {
                    for &budget in &self.budgets {
                        let mut options = FitOptions::new(function, continuity);
                        options.parameterisation = c.parameterisation;
                        options.budget_per_segment = budget;
                        options.search.kind = space;
                        self.search.apply(&mut options);
                        out.push(options);
                    }
                }
            }
        }
        out
    }
}

/// The lists a `[[fit]]` section combines, and its parameterisation.
struct FitChoices {
    functions: Vec<FunctionType>,
    continuities: Vec<Continuity>,
    spaces: Vec<SearchSpace>,
    parameterisation: Parameterisation,
}

/// Search-space settings of a `[[fit]]` section; `None` keeps the default.
struct SearchOverrides {
    alpha_size: Option<f64>,
    pt: Option<f64>,
    weight_range: Option<(f64, f64)>,
    t_range: Option<(f64, f64)>,
}

impl SearchOverrides {
    /// Sets the given settings in `options`.
    fn apply(&self, options: &mut FitOptions) {
        if let Some(a) = self.alpha_size {
            options.search.alpha_size = a;
        }
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
enum Segs {
    /// This many segments.
    Count(usize),
    /// A glyph's own break points.
    TrueBreaks,
}

/// The `segments` key of a section, with its value and field for errors
/// found later (a non-glyph input, a segment that cannot be fitted).
struct FitSegments<'t, 'i> {
    kind: Segs,
    value: &'t Value<'i>,
    field: String,
}

/// A case's name without its search space: `source/function/continuity`.
fn base_name(source_name: &str, options: &FitOptions) -> String {
    format!(
        "{source_name}/{}/{}",
        options.function.name(),
        options.continuity.name()
    )
}

/// A case's problem name: `source/function/continuity`, and the search
/// space unless it is the technique's.
fn case_name(source_name: &str, options: &FitOptions) -> String {
    let mut name = base_name(source_name, options);
    if options.search.kind != SearchSpace::Technique {
        name = format!("{name}/{}", options.search.kind.name());
    }
    name
}

fn raw_string(v: &Value<'_>) -> Option<String> {
    match v.get_ref() {
        toml::de::DeValue::String(s) => Some(s.to_string()),
        _ => None,
    }
}
