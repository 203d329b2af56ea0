//! `tolerance = T` in a `[[fit]]` section: every case fits the segments of
//! the exact (Levenberg–Marquardt) fit held to the two-sided distance `T`
//! (see the `[[fit]]` notes in `fit.rs`).

use super::fit::{FitSegments, FitSettings, Segs};
use super::{Parser, SpecError, Table};
use crate::fit::{FitOptions, SearchSpaceOptions};
use crate::reconstruction::{Method, Reconstruction, Segmentation, Source};

/// The largest tolerance a spec may give (data units): beyond any outline
/// the readers accept (coordinates within ±10¹⁵).
const MAX_TOLERANCE: f64 = 1e15;

impl Parser<'_> {
    /// The optional `tolerance` (a distance > 0), which replaces `segments`
    /// and `free_parameters`.
    pub(super) fn fit_tolerance<'t, 'i>(
        &self,
        table: &'t Table<'i>,
        section: &str,
    ) -> Result<Option<FitSegments<'t, 'i>>, SpecError> {
        let Some(value) = self.get(table, "tolerance") else {
            return Ok(None);
        };
        let field = format!("{section}.tolerance");
        if let Some(other) = ["segments", "free_parameters"]
            .into_iter()
            .find(|k| self.get(table, k).is_some())
        {
            return Err(self.error(
                value.span(),
                &field,
                format!(
                    "expected either tolerance or {other}, not both (tolerance sets the segments \
                     as the exact fit to it finds them)"
                ),
            ));
        }
        let t = self.real(value, &field)?;
        if !(t.is_finite() && t > 0.0 && t <= MAX_TOLERANCE) {
            return Err(self.error(
                value.span(),
                &field,
                format!("expected a distance > 0 and ≤ 1e15 (data units), found {t}"),
            ));
        }
        Ok(Some(FitSegments {
            kind: Segs::Tolerance(t),
            value,
            field,
        }))
    }

    /// The segments of the exact fit of `source` to `tolerance` with the
    /// function, continuity, closing, error and chain of `options` (the
    /// default search space and 10 000 evaluations per segment, so that
    /// every search space, α_size and budget of a section fits the same
    /// segments); a fit that cannot hold the tolerance is a spec error.
    pub(super) fn tolerance_breaks(
        &self,
        source: &Source,
        name: &str,
        settings: &FitSettings,
        options: &FitOptions,
        tolerance: f64,
        segments: &FitSegments<'_, '_>,
    ) -> Result<Segmentation, SpecError> {
        let r = Reconstruction {
            source,
            segmentation: Segmentation::Tolerance(tolerance),
            corners: settings.corners,
            options: FitOptions {
                search: SearchSpaceOptions::default(),
                budget_per_segment: FitOptions::default().budget_per_segment,
                ..*options
            },
        };
        let fit = r.fit(&Method::Exact, 0).map_err(|e| {
            self.error(
                segments.value.span(),
                &segments.field,
                format!(
                    "{name}/{}/{}: the exact fit cannot hold the tolerance: {e}",
                    options.function.name(),
                    options.continuity.name()
                ),
            )
        })?;
        Ok(Segmentation::of_fit(&fit))
    }
}
