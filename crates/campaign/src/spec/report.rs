//! The optional `[report]` section: how the campaign's report reads its
//! verdicts.
//!
//! ```toml
//! [report]
//! rope_final_error = 0.3    # decades of the ratio of median errors (E in a fitting campaign)
//! rope_anytime_auc = 0.05   # difference of the median anytime AUC
//! ```
//!
//! Each key is the half-width of the region of practical equivalence
//! (rope) of the Bayesian signed-rank test beside every verdict of its
//! measure (Benavoli, Corani, Demšar & Zaffalon 2017, JMLR 18(77):1–36).
//! The run only checks the section; `metabezier report` reads it from the
//! results directory's copy of the spec, and its `--rope` overrides it.

use super::{Parser, SpecError, Table};

/// The keys of `[report]`, each `rope_` and a measure's name with `_` for
/// `-`.
pub const REPORT_KEYS: [&str; 2] = ["rope_final_error", "rope_anytime_auc"];

/// The largest rope a spec may set: 10 decades, or 10 AUC (both far beyond
/// any meaningful equivalence, so a typo of scale is caught).
const MAX_ROPE: f64 = 10.0;

/// The measure a `[report]` key sets the rope of: `rope_final_error` →
/// `final-error`.
pub fn rope_measure(key: &str) -> Option<String> {
    REPORT_KEYS
        .contains(&key)
        .then(|| key.trim_start_matches("rope_").replace('_', "-"))
}

impl Parser<'_> {
    /// The optional `[report]` section: the ropes it sets, as (measure,
    /// half-width), each a finite real in [0, 10].
    pub(super) fn report_section(&self, root: &Table<'_>) -> Result<Vec<(String, f64)>, SpecError> {
        let Some(section) = self.get(root, "report") else {
            return Ok(Vec::new());
        };
        let table = self.table(section, "report")?;
        self.check_keys(table, "report", &REPORT_KEYS)?;
        let mut ropes = Vec::new();
        for key in REPORT_KEYS {
            let Some(v) = self.get(table, key) else {
                continue;
            };
            let field = format!("report.{key}");
            let x = self.real(v, &field)?;
            if !(x.is_finite() && (0.0..=MAX_ROPE).contains(&x)) {
                return Err(self.error(
                    v.span(),
                    &field,
                    format!(
                        "expected a rope half-width, a real number in [0, {MAX_ROPE}], found {x}"
                    ),
                ));
            }
            let measure = rope_measure(key).unwrap_or_default();
            ropes.push((measure, x));
        }
        Ok(ropes)
    }
}
