//! The plain data of an overlay figure: the data points of an outline and
//! the fitted curves over them, as polylines. The report draws it; this
//! module only samples the curves.

use super::ShapeFit;
use crate::fit::Segment;
use crate::geometry::{Curve, Point};

/// Samples per segment in an overlay (plus one: both ends are drawn).
const SAMPLES: usize = 64;

/// One fitted outline drawn over the data.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayCurve {
    /// Legend text, e.g. `rational-cubic, G1 (E = 12.3)`.
    pub label: String,
    /// Each segment sampled densely, in order.
    pub segments: Vec<Vec<Point>>,
    /// The control polygon of each segment (drawn thin and dashed-looking);
    /// empty to omit.
    pub control_polygons: Vec<Vec<Point>>,
}

impl OverlayCurve {
    /// The fitted curves of every contour of `fit`: each segment sampled at
    /// 65 uniform parameters and, if `polygons`, its control polygon.
    pub fn of_fit(label: String, fit: &ShapeFit, polygons: bool) -> OverlayCurve {
        OverlayCurve {
            label,
            segments: fit.segments().map(|(_, s)| sample(&s.segment)).collect(),
            control_polygons: if polygons {
                fit.segments()
                    .map(|(_, s)| s.segment.control_points())
                    .collect()
            } else {
                Vec::new()
            },
        }
    }

    /// A fitted outline given by its segments (such as read back from a
    /// results file), without control polygons.
    pub fn of_segments(label: String, segments: &[Segment]) -> OverlayCurve {
        OverlayCurve {
            label,
            segments: segments.iter().map(sample).collect(),
            control_polygons: Vec::new(),
        }
    }
}

/// One panel: the data points and the curves fitted to them.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayPanel {
    /// Panel title.
    pub title: String,
    /// The data points `R_i`.
    pub data: Vec<Point>,
    /// The fitted curves, each in its own colour.
    pub curves: Vec<OverlayCurve>,
    /// Whether y grows downwards in the source (image rows): the panel is
    /// then drawn with y flipped so the shape looks as in the image.
    pub y_down: bool,
}

/// A figure of one or more overlay panels with a shared title.
#[derive(Clone, Debug, PartialEq)]
pub struct OverlayFigure {
    /// Figure title.
    pub title: String,
    /// The panels, laid out in a grid of at most `columns` columns.
    pub panels: Vec<OverlayPanel>,
    /// Maximum panels per row.
    pub columns: usize,
}

impl OverlayFigure {
    /// The figure of one fit: its data, the fitted curves of every contour
    /// and their control polygons in one panel titled with the fit's totals.
    pub fn of_fit(title: &str, data: &[Point], fit: &ShapeFit) -> OverlayFigure {
        let m = &fit.metrics;
        OverlayFigure {
            title: title.to_owned(),
            panels: vec![OverlayPanel {
                title: format!(
                    "{} contour(s), {} segments, E = {:.4e}, max distance {:.3e}",
                    fit.contours.len(),
                    m.segments,
                    m.sse,
                    m.max_distance
                ),
                data: data.to_vec(),
                curves: vec![OverlayCurve::of_fit("fit".into(), fit, true)],
                y_down: false,
            }],
            columns: 1,
        }
    }
}

/// A segment sampled at 65 uniform parameters, for drawing.
fn sample(s: &Segment) -> Vec<Point> {
    (0..=SAMPLES)
        .map(|j| s.eval(j as f64 / SAMPLES as f64))
        .collect()
}
