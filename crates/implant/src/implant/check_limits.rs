//! The limits of the plausibility checks (`[checks]` in a spec), apart from
//! the checks themselves ([`super::plausibility`], where each default and
//! its source are documented) so that the wall options can carry them.

/// The limits of the checks (`[checks]` in a spec; defaults in the module
/// table).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlausibilityLimits {
    /// `max_width_jump_mm`: the largest rise of a slice's width above its
    /// neighbours' (mm) ...
    pub max_width_jump_mm: f64,
    /// `max_width_jump_fraction`: ... or this fraction of the neighbours'
    /// largest width, whichever is larger.
    pub max_width_jump_fraction: f64,
    /// `max_outside_head_mm`: how far the section may leave the hull of the
    /// bone and its mirror image (mm) ...
    pub max_outside_head_mm: f64,
    /// `max_outside_head_fraction`: ... or this fraction of `|A′B′|`,
    /// whichever is larger. Where the mirror cannot cover the defect
    /// (across the midline) the hull cuts the chord A′B′, and an arc over
    /// a chord `w` rises at most `w/2` above it (a semicircle); a template
    /// continued across the forehead was measured 13.4 mm outside at
    /// `w` = 41.7 mm.
    pub max_outside_head_fraction: f64,
    /// `max_refused_fraction`: where more than this fraction of a design's
    /// slices is refused, the detection failed on the defect as a whole
    /// and `--allow-partial` does not write the rest either.
    pub max_refused_fraction: f64,
    /// `max_template_ratio`: the longest template, in `|A′B′|`.
    pub max_template_ratio: f64,
    /// `max_volume_ratio`: the largest section area, in `|A′B′|` times the
    /// mean thickness.
    pub max_volume_ratio: f64,
    /// `max_fit_rms_mm`: the largest fit RMS (mm) ...
    pub max_fit_rms_mm: f64,
    /// `max_fit_rms_fraction`: ... or this fraction of `|A′B′|`, whichever
    /// is larger.
    pub max_fit_rms_fraction: f64,
    /// `max_template_join_deg`: the largest turn of the bare template
    /// against the bone at A′ or B′ (degrees).
    pub max_template_join_deg: f64,
}

impl Default for PlausibilityLimits {
    fn default() -> Self {
        PlausibilityLimits {
            max_width_jump_mm: 15.0,
            max_width_jump_fraction: 0.5,
            max_outside_head_mm: 3.0,
            max_outside_head_fraction: 0.5,
            max_refused_fraction: 0.5,
            max_template_ratio: 1.5,
            max_volume_ratio: 3.0,
            max_fit_rms_mm: 5.0,
            max_fit_rms_fraction: 0.1,
            max_template_join_deg: 120.0,
        }
    }
}
