//! The errors of one slice of the implant pipeline: the CT layer's own
//! ([`CtError`]: reading, bone, contours, the mirror technique) and the
//! implant's, of which the CT layer knows nothing: no defect found, the
//! template, the tangents and the thickness at the defect ends, the fit of
//! the outer wall, clipping to the tissue, and the artificial defects of
//! the validation. [`super::ImplantError::Slice`] names the slice.

use crate::ct::CtError;
use crate::fit::FitError;

/// An error on one slice of the implant pipeline (or of one validation
/// case): a CT-layer error, with its message unchanged, or one of the
/// implant's own.
#[derive(Debug, thiserror::Error)]
pub enum SliceError {
    /// A CT-layer error (reading, bone, contours, the mirror technique).
    #[error(transparent)]
    Ct(#[from] CtError),
    /// Defect detection found no gap in the bone ring.
    #[error("no defect found (the bone ring is closed): give A and B for this slice")]
    NoDefectFound,

    // The implant wall.
    /// Too few rays across the defect meet the mirrored contour to make a
    /// template.
    #[error("the mirrored contour does not cover the defect")]
    TemplateNotCovered {
        /// Template points found.
        points: usize,
        /// Points the wall's function needs.
        needed: usize,
    },
    /// Too few rays next to a defect end meet the intact contour to fit its
    /// tangent.
    #[error("too little intact outer contour next to the defect ends")]
    TooLittleIntactContour {
        /// Envelope points found before A.
        before: usize,
        /// Envelope points found after B.
        after: usize,
    },
    /// No bone along the inward ray next to a defect end, so the wall has
    /// no thickness.
    #[error("no bone next to the defect ends: cannot measure the bone thickness")]
    NoBoneAtEnds {
        /// Thickness measured next to A, in mm.
        thickness_a: f64,
        /// Thickness measured next to B, in mm.
        thickness_b: f64,
    },
    /// The curve fit of the outer wall (or of a neighbouring tangent) was
    /// refused.
    #[error("the outer-wall fit failed: {source}")]
    OuterWallFit {
        /// The fitting error.
        source: FitError,
    },

    // Artificial defects of the validation.
    /// The outer envelope has no point at the defect's centre angle.
    #[error("no outer contour at {position_deg}° from the centre")]
    NoContourAt {
        /// The defect's centre angle in degrees.
        position_deg: f64,
    },
    /// A ray of the artificial defect misses the outer contour.
    #[error("the defect leaves the outer contour")]
    DefectLeavesContour,
    /// The artificial defect's wedge holds no bone pixel.
    #[error("the cut removed no bone")]
    CutRemovedNoBone,

    /// Clipping the implant section to the tissue left nothing: the section
    /// lies entirely in bone.
    #[error("the implant section lies entirely in bone (nothing left after clipping to the tissue below the threshold)")]
    ClippedAway,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_error_is_the_source() {
        use std::error::Error as _;
        let fit = FitError::TooFewOutlinePoints {
            found: 2,
            needed: 4,
        };
        let e = SliceError::OuterWallFit {
            source: fit.clone(),
        };
        assert_eq!(e.to_string(), format!("the outer-wall fit failed: {fit}"));
        assert!(e.source().is_some());
    }

    #[test]
    fn a_ct_error_keeps_its_message() {
        let ct = CtError::NoClosedContour;
        let text = ct.to_string();
        assert_eq!(SliceError::from(ct).to_string(), text);
    }
}
