//! The `[checks]` section of a chapter-6 spec: the limits of the
//! plausibility checks ([`super::super::plausibility`]), each optional
//! with the default documented there.
//!
//! ```toml
//! [checks]
//! max_width_jump_mm = 15          # a slice's width above its neighbours' ...
//! max_width_jump_fraction = 0.5   # ... or this fraction of theirs
//! max_outside_head_mm = 3         # the section outside the head's hull ...
//! max_outside_head_fraction = 0.5 # ... or this fraction of |A'B'|
//! max_template_ratio = 1.5        # template length / |A'B'|
//! max_volume_ratio = 3            # section area / (|A'B'| x thickness)
//! max_fit_rms_mm = 5              # fit RMS against the template ...
//! max_fit_rms_fraction = 0.1      # ... or this fraction of |A'B'|
//! max_template_join_deg = 120     # the template's turn against the bone
//! max_refused_fraction = 0.5      # above it --allow-partial writes nothing
//! ```

use super::Parser;
use crate::implant::check_limits::PlausibilityLimits;
use metabezier_spec::{SpecError, Value};

/// The keys of `[checks]`, in the order of the module's example.
pub(super) const CHECKS_KEYS: [&str; 10] = [
    "max_width_jump_mm",
    "max_width_jump_fraction",
    "max_outside_head_mm",
    "max_outside_head_fraction",
    "max_template_ratio",
    "max_volume_ratio",
    "max_fit_rms_mm",
    "max_fit_rms_fraction",
    "max_template_join_deg",
    "max_refused_fraction",
];

/// The field of `limits` a key sets.
fn field<'l>(limits: &'l mut PlausibilityLimits, key: &str) -> Option<&'l mut f64> {
    Some(match key {
        "max_width_jump_mm" => &mut limits.max_width_jump_mm,
        "max_width_jump_fraction" => &mut limits.max_width_jump_fraction,
        "max_outside_head_mm" => &mut limits.max_outside_head_mm,
        "max_outside_head_fraction" => &mut limits.max_outside_head_fraction,
        "max_template_ratio" => &mut limits.max_template_ratio,
        "max_volume_ratio" => &mut limits.max_volume_ratio,
        "max_fit_rms_mm" => &mut limits.max_fit_rms_mm,
        "max_fit_rms_fraction" => &mut limits.max_fit_rms_fraction,
        "max_template_join_deg" => &mut limits.max_template_join_deg,
        "max_refused_fraction" => &mut limits.max_refused_fraction,
        _ => return None,
    })
}

impl Parser<'_> {
    /// Reads `[checks]` into `limits`: every key optional, each a positive
    /// real (`max_refused_fraction` within 0..=1, `max_template_join_deg`
    /// within 0..=180); an unknown key is an error listing the valid ones.
    pub(super) fn checks_section(
        &self,
        v: &Value<'_>,
        limits: &mut PlausibilityLimits,
    ) -> Result<(), SpecError> {
        let t = self.table(v, "checks")?;
        self.check_keys(t, "checks", &CHECKS_KEYS)?;
        for key in CHECKS_KEYS {
            let Some(x) = self.get(t, key) else {
                continue;
            };
            let name = format!("checks.{key}");
            let value = self.finite_real(x, &name)?;
            let max = match key {
                "max_refused_fraction" => 1.0,
                "max_template_join_deg" => 180.0,
                _ => f64::INFINITY,
            };
            if !(value > 0.0 && value <= max) {
                let range = if max.is_finite() {
                    format!("a real in (0, {max}]")
                } else {
                    "a positive real".to_string()
                };
                return Err(self.error(
                    x.span(),
                    &name,
                    format!("expected {range}, found {}", self.show(x)),
                ));
            }
            if let Some(f) = field(limits, key) {
                *f = value;
            }
        }
        Ok(())
    }
}
