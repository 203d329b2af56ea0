//! The reading of a `[[fit]]` section into its fitting problems.

use std::collections::HashMap;
use std::ops::Range;
use std::path::Path;
use std::sync::Arc;

use super::super::budget::Budget;
use super::super::family::Problems;
use super::super::reader::Parser;
use super::super::{choices_hint, ProblemEntry, SpecError, Table, Value};
use super::settings::{raw_string, FitChoices, SearchOverrides};
use super::*;
use crate::fit::{
    Chain, Closing, ErrorMeasure, FitOptions, FunctionType, RealOption, SearchSpace,
    SearchSpaceOptions, ALPHA_SIZE, PT,
};
use crate::functions::Transform;
use crate::geometry::{Continuity, Parameterisation};
use crate::outline::CornerOptions;
use crate::reconstruction::{ContourChoice, FitMode, Segmentation, ShapeFit, Source};

impl Parser<'_> {
    /// A string or list of strings, each checked against `names`.
    pub(crate) fn names<T: Copy>(
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
    pub(crate) fn real_in(
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
    pub(crate) fn real_option(
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
    pub(crate) fn option_value(
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
    pub(crate) fn positive_range(
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
    pub(crate) fn fits(
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
    pub(crate) fn fit_section(
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
    pub(crate) fn reference_fit(
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
    pub(crate) fn fit_settings(
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
    pub(crate) fn one<T: Copy>(
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
    pub(crate) fn fit_contour(
        &self,
        table: &Table<'_>,
        section: &str,
    ) -> Result<ContourChoice, SpecError> {
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
    pub(crate) fn fit_budget(
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
    pub(crate) fn fit_choices(
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
    pub(crate) fn fit_corners(
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
    pub(crate) fn search_overrides(
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
    pub(crate) fn alpha_sizes(
        &self,
        table: &Table<'_>,
        section: &str,
    ) -> Result<Option<Vec<f64>>, SpecError> {
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
    pub(crate) fn fit_segments<'t, 'i>(
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
    pub(crate) fn fit_label(
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
    pub(crate) fn fit_segmentation(
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
    pub(crate) fn count_for(
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
    pub(crate) fn fit_problem(
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
