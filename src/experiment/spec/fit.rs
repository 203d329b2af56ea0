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
use std::sync::Arc;

use super::{choices_hint, Budget, Parser, ProblemEntry, ProblemKind, SpecError, Table, Value};
use crate::fit::{
    FitOptions, FunctionType, PiecewiseFit, SearchSpace, SegmentProblem, SegmentSolver, Solution,
};
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
        default_budget: Option<Budget>,
        span: Range<usize>,
    ) -> Result<Vec<ProblemEntry>, SpecError> {
        let base = self
            .path
            .parent()
            .map(std::path::Path::to_path_buf)
            .unwrap_or_default();
        let mut out: Vec<ProblemEntry> = Vec::new();
        for (i, entry) in self
            .array_of_tables(root, "fit", span)?
            .into_iter()
            .enumerate()
        {
            let section = format!("fit[{}]", i + 1);
            let table = self.table(entry, &section)?;
            self.check_keys(table, &section, &FIT_KEYS)?;
            let budget = match self.get(table, "budget") {
                Some(v) => self.integer(v, &format!("{section}.budget"), 1, u64::MAX)?,
                None => match default_budget {
                    Some(Budget::Fixed(b)) => b,
                    Some(Budget::PerDim(_)) | None => {
                        return Err(self.error(
                            entry.span(),
                            &format!("{section}.budget"),
                            "no budget: give \"budget\" (evaluations per segment) in [experiment] or in this [[fit]]; \"budget_per_dim\" does not apply to fitting".into(),
                        ))
                    }
                },
            };
            let contour = match self.get(table, "contour") {
                Some(v) => self.integer(v, &format!("{section}.contour"), 0, 1_000_000)? as usize,
                None => 0,
            };
            let functions = self.names(
                table,
                "function",
                &section,
                FunctionType::RationalCubic,
                &FunctionType::NAMES,
                FunctionType::from_name,
            )?;
            let continuities = self.names(
                table,
                "continuity",
                &section,
                Continuity::G1,
                &Continuity::NAMES,
                Continuity::from_name,
            )?;
            let spaces = self.names(
                table,
                "search_space",
                &section,
                SearchSpace::Technique,
                &SearchSpace::NAMES,
                SearchSpace::from_name,
            )?;
            let parameterisation = self.names(
                table,
                "parameterisation",
                &section,
                Parameterisation::ChordLength,
                &Parameterisation::NAMES,
                Parameterisation::from_name,
            )?;
            if parameterisation.len() != 1 {
                return Err(self.error(
                    entry.span(),
                    &format!("{section}.parameterisation"),
                    "expected one parameterisation, not a list".into(),
                ));
            }
            let corner_angle = self
                .real_in(table, "corner_angle", &section, (0.0, 180.0), false)?
                .unwrap_or(60.0);
            let corner_k = match self.get(table, "corner_k") {
                Some(v) => self.integer(v, &format!("{section}.corner_k"), 1, 10_000)? as usize,
                None => 5,
            };
            let alpha_size = self.real_in(table, "alpha_size", &section, (0.0, 1e6), true)?;
            let pt = self.real_in(table, "pt", &section, (0.0, 1.0), false)?;
            let weight_range =
                self.positive_range(table, "weight_range", &section, "the rational weights")?;
            let t_range = self.positive_range(table, "t_range", &section, "the G1 ratio T")?;

            let sv = self.required(table, &section, "segments", entry.span())?;
            let seg_field = format!("{section}.segments");
            enum Segs {
                Count(usize),
                TrueBreaks,
            }
            let segs = match raw_string(sv) {
                Some(s) if s == "true-breaks" => Segs::TrueBreaks,
                Some(s) => {
                    return Err(self.error(
                        sv.span(),
                        &seg_field,
                        format!(
                            "expected a number of segments ≥ 1 or \"true-breaks\", found \"{s}\""
                        ),
                    ))
                }
                None => Segs::Count(self.integer(sv, &seg_field, 1, 100_000)? as usize),
            };

            let iv = self.required(table, &section, "input", entry.span())?;
            let input_field = format!("{section}.input");
            let inputs = self.one_or_many(iv, &input_field)?;
            let label = match self.get(table, "label") {
                Some(v) if inputs.len() == 1 => Some(self.string(v, &format!("{section}.label"))?),
                Some(v) => {
                    return Err(self.error(
                        v.span(),
                        &format!("{section}.label"),
                        "a label names one input; with several inputs, leave it out (each is named after its file)".into(),
                    ))
                }
                None => None,
            };
            for item in inputs {
                let text = self.string(item, &input_field)?;
                let source = Source::load(
                    &text,
                    &base,
                    contour,
                    &ImageOptions::default(),
                    Sampling::default(),
                )
                .map_err(|e| self.error(item.span(), &input_field, e.to_string()))?;
                let segmentation = match segs {
                    Segs::Count(n) => Segmentation::Count(n),
                    Segs::TrueBreaks => match source.true_segmentation() {
                        Some(s) => s,
                        None => {
                            return Err(self.error(
                                sv.span(),
                                &seg_field,
                                format!("\"true-breaks\" needs a glyph input (font:PATH:GLYPH), but \"{text}\" is not one"),
                            ))
                        }
                    },
                };
                let source_name = label.clone().unwrap_or_else(|| source.label());
                let source = Arc::new(source);
                for &function in &functions {
                    for &continuity in &continuities {
                        for &space in &spaces {
                            let mut options = FitOptions::new(function, continuity);
                            options.parameterisation = parameterisation[0];
                            options.budget_per_segment = budget;
                            options.search.kind = space;
                            if let Some(a) = alpha_size {
                                options.search.alpha_size = a;
                            }
                            if let Some(p) = pt {
                                options.search.pt = p;
                            }
                            if let Some(w) = weight_range {
                                options.search.weight_range = w;
                            }
                            if let Some(t) = t_range {
                                options.search.t_range = t;
                            }
                            let mut name =
                                format!("{source_name}/{}/{}", function.name(), continuity.name());
                            if space != SearchSpace::Technique {
                                name = format!("{name}/{}", space.name());
                            }
                            let case = FitCase {
                                name,
                                source_name: source_name.clone(),
                                source: Arc::clone(&source),
                                segmentation: segmentation.clone(),
                                corners: (corner_angle > 0.0).then_some(CornerOptions {
                                    k: corner_k,
                                    angle_deg: corner_angle,
                                }),
                                options,
                            };
                            let dry = dry_run(&case).map_err(|e| {
                                self.error(sv.span(), &seg_field, format!("{}: {e}", case.name))
                            })?;
                            let segments = dry.segments.len();
                            let p = ProblemEntry {
                                kind: ProblemKind::Fit(Box::new(case)),
                                dim: segments,
                                budget: budget.saturating_mul(segments as u64),
                            };
                            if out.iter().any(|q| q.key() == p.key()) {
                                return Err(self.error(
                                    item.span(),
                                    &section,
                                    format!("problem {} is listed twice", p.key()),
                                ));
                            }
                            out.push(p);
                        }
                    }
                }
            }
        }
        Ok(out)
    }
}

fn raw_string(v: &Value<'_>) -> Option<String> {
    match v.get_ref() {
        toml::de::DeValue::String(s) => Some(s.to_string()),
        _ => None,
    }
}
