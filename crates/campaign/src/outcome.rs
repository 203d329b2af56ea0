//! What a run yields besides its trace, as the problem families produce it
//! and the records write it: a fit's accuracy and segments
//! ([`FitDetail`]), and the target precisions whose first hits are
//! recorded ([`default_targets`]).

use super::segments::segment_rows;
use crate::reconstruction::ShapeFit;

/// What a fitting run adds to its record: the fit's accuracy beyond `E`
/// and every segment's control points.
#[derive(Clone, Debug, PartialEq)]
pub struct FitDetail {
    /// `√(E/N)`, measured at the parameters `sᵢ`.
    pub rms: f64,
    /// The largest orthogonal distance of a data point to the curve.
    pub max_distance: f64,
    /// The RMS of the orthogonal distances, with the current fitting records
    /// (`None` in the legacy layout, which has no such column).
    pub rms_distance: Option<f64>,
    /// Curve → data and the two-sided (Hausdorff) distance
    /// ([`crate::fit::FitMetrics::curve_distance`], `hausdorff`), with the
    /// current fitting records (`None` in the older layouts).
    pub two_sided: Option<(f64, f64)>,
    /// On closed outlines, the largest tangent angle at a closing joint
    /// (degrees).
    pub closing_angle_degrees: Option<f64>,
    /// On closed outlines, the largest relative derivative gap there.
    pub closing_relative_derivative_gap: Option<f64>,
    /// One row per segment, in the columns of [`super::segments::FIT_SEGMENT_HEADER`] with
    /// the current records, of [`super::segments::SEGMENT_HEADER`] without.
    pub segments: Vec<Vec<String>>,
}

impl FitDetail {
    /// The detail of a finished fit, with the current records or the
    /// legacy ones.
    pub fn of(fit: &ShapeFit, current: bool) -> FitDetail {
        let gap = fit
            .contours
            .iter()
            .filter_map(|c| c.fit.closing.map(|j| j.relative_derivative_gap))
            .reduce(f64::max);
        FitDetail {
            rms: fit.metrics.rms,
            max_distance: fit.metrics.max_distance,
            rms_distance: current.then_some(fit.metrics.rms_distance),
            two_sided: current.then_some((fit.metrics.curve_distance, fit.metrics.hausdorff)),
            closing_angle_degrees: fit.closing_angle_degrees(),
            closing_relative_derivative_gap: gap,
            segments: segment_rows(fit, current),
        }
    }
}

/// The default target precisions `Δf = 10^(k/5)` for `k = 10, 9, …, −40`:
/// 10² down to 10⁻⁸, five per decade (51 targets), as COCO's runtime ECDFs.
pub fn default_targets() -> Vec<f64> {
    (-40..=10)
        .rev()
        .map(|k| 10f64.powf(f64::from(k) / 5.0))
        .collect()
}
