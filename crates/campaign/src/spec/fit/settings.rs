//! The settings a `[[fit]]` section gives all its problems, and its
//! segmentation.

use super::super::Value;
use crate::fit::{Chain, Closing, ErrorMeasure, FitOptions, FunctionType, SearchSpace};
use crate::geometry::{Continuity, Parameterisation};
use crate::outline::{CornerOptions, Sampling};
use crate::reconstruction::{ContourChoice, FitMode, LoadOptions, Source};

/// The keys of a `[[fit]]` section shared by all its problems.
pub(crate) struct FitSettings {
    /// Evaluations per segment, one problem each.
    pub(crate) budgets: Vec<u64>,
    /// Whether the budgets were listed (a budget grid).
    pub(crate) budget_grid: bool,
    /// Which outlines of each input.
    pub(crate) contour: ContourChoice,
    /// What to combine.
    pub(crate) choices: FitChoices,
    /// The corner detector.
    pub(crate) corners: Option<CornerOptions>,
    /// Search-space settings given in the section.
    pub(crate) search: SearchOverrides,
    /// Whether α_size is listed (a design factor).
    pub(crate) alpha_grid: bool,
    /// How closed outlines close (`c0` unless the section says otherwise).
    pub(crate) closing: Closing,
    /// Outline or per-segment problems.
    pub(crate) mode: FitMode,
    /// Whether the section uses the current fitting records.
    pub(crate) extended: bool,
}

impl FitSettings {
    /// How the inputs are read: the contours asked for, and for a fit at a
    /// glyph's own breaks enough samples on every segment for every function
    /// of the section (segments that had enough keep their samples).
    pub(crate) fn load_options(&self, segments: &FitSegments<'_, '_>) -> LoadOptions {
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
    pub(crate) fn alphas(&self, space: SearchSpace) -> Vec<Option<f64>> {
        match &self.search.alpha_sizes {
            Some(a) if space == SearchSpace::Technique => a.iter().copied().map(Some).collect(),
            Some(a) if !self.alpha_grid => vec![a.first().copied()],
            _ => vec![None],
        }
    }

    /// The number of [`FitSettings::options`], counted without listing them.
    pub(crate) fn count(&self) -> u128 {
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
    pub(crate) fn options(
        &self,
        source: &Source,
        segments: &FitSegments<'_, '_>,
    ) -> Vec<FitOptions> {
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
pub(crate) struct FitChoices {
    pub(crate) functions: Vec<FunctionType>,
    pub(crate) continuities: Vec<Continuity>,
    pub(crate) spaces: Vec<SearchSpace>,
    pub(crate) parameterisation: Option<Parameterisation>,
    pub(crate) error: ErrorMeasure,
    pub(crate) chain: Chain,
}

/// Search-space settings of a `[[fit]]` section; `None` keeps the default.
pub(crate) struct SearchOverrides {
    pub(crate) alpha_sizes: Option<Vec<f64>>,
    pub(crate) pt: Option<f64>,
    pub(crate) weight_range: Option<(f64, f64)>,
    pub(crate) t_range: Option<(f64, f64)>,
}

impl SearchOverrides {
    /// Sets the given settings other than α_size in `options`.
    pub(crate) fn apply(&self, options: &mut FitOptions) {
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
pub(crate) enum Segs {
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
pub(crate) struct FitSegments<'t, 'i> {
    pub(crate) kind: Segs,
    pub(crate) value: &'t Value<'i>,
    pub(crate) field: String,
}

pub(crate) fn raw_string(v: &Value<'_>) -> Option<String> {
    match v.get_ref() {
        toml::de::DeValue::String(s) => Some(s.to_string()),
        _ => None,
    }
}
