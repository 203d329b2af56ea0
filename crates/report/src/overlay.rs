//! Drawing overlay figures of fitted outlines: the data points, each fitted
//! curve and, optionally, its control polygons, at equal scale in x and y.
//!
//! The figure's data ([`OverlayFigure`]) comes from the reconstruction
//! room; it knows nothing of how the curves were fitted: it takes
//! polylines. It is used by `metabezier fit` (`fit.svg`, `fit.png`) and by
//! the chapter-5 report (one panel per fitting function).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use super::render::{
    draw_legend, draw_title, font, legend_height, save, text_width, Draw, DrawResult,
};
use super::style::{label_colours, LegendEntry, SeriesStyle};
use super::ReportError;
use crate::geometry::Point;
use crate::reconstruction::{OverlayFigure, OverlayPanel};

const PANEL: u32 = 760;
const TITLE_H: u32 = 40;
/// The font size and line height of a panel's caption.
const CAPTION: (u32, u32) = (16, 22);

/// `text` broken at its `", "` separators into lines at most `width`
/// pixels wide at `size` (a part wider than that gets a line of its own).
fn wrap(text: &str, width: u32, size: u32) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for part in text.split(", ") {
        match lines.last_mut() {
            Some(line) if text_width(&format!("{line}, {part}"), size) <= width => {
                line.push_str(", ");
                line.push_str(part);
            }
            Some(line) => {
                line.push(',');
                lines.push(part.to_owned());
            }
            None => lines.push(part.to_owned()),
        }
    }
    lines
}

/// Writes `figure` as `<dir>/<stem>.svg` and `<dir>/<stem>.png`; returns
/// the two paths.
pub fn save_overlay(
    figure: &OverlayFigure,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ReportError> {
    save(&Overlay(figure), dir, stem)
}

/// The reconstruction room's figure data as a drawing (its layout and
/// [`Draw`]); the data is reached through `Deref`.
pub(crate) struct Overlay<'a>(pub(crate) &'a OverlayFigure);

impl std::ops::Deref for Overlay<'_> {
    type Target = OverlayFigure;

    fn deref(&self) -> &OverlayFigure {
        self.0
    }
}

// The drawing's layout of the reconstruction room's figure data.
impl Overlay<'_> {
    /// The curve labels of every panel, each once, in the order they
    /// first appear: a curve's colour is its label's place here, the same
    /// in every panel.
    fn labels(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for c in self.panels.iter().flat_map(|p| &p.curves) {
            if !out.contains(&c.label.as_str()) {
                out.push(&c.label);
            }
        }
        out
    }

    fn legend(&self) -> Vec<LegendEntry> {
        let mut out: Vec<LegendEntry> =
            vec![("data".into(), SeriesStyle::solid(RGBColor(120, 120, 120)))];
        let labels = self.labels();
        for (label, c) in labels.iter().zip(label_colours(&labels)) {
            out.push(((*label).to_owned(), SeriesStyle::solid(c)));
        }
        out
    }

    fn shape(&self) -> (usize, usize) {
        let cols = self.columns.max(1).min(self.panels.len().max(1));
        let rows = self.panels.len().div_ceil(cols).max(1);
        (rows, cols)
    }
}

/// The bounding box of the points, made square (equal scale) with a 4 %
/// margin.
fn square_box(points: impl Iterator<Item = Point>) -> ((f64, f64), (f64, f64)) {
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for p in points.filter(|p| p.x.is_finite() && p.y.is_finite()) {
        x0 = x0.min(p.x);
        x1 = x1.max(p.x);
        y0 = y0.min(p.y);
        y1 = y1.max(p.y);
    }
    if x0 > x1 {
        return ((0.0, 1.0), (0.0, 1.0));
    }
    let half = ((x1 - x0).max(y1 - y0) * 0.52).max(1e-9);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    ((cx - half, cx + half), (cy - half, cy + half))
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &OverlayPanel,
    labels: &[&str],
) -> DrawResult {
    let colours = label_colours(labels);
    let all = panel.data.iter().copied().chain(
        panel
            .curves
            .iter()
            .flat_map(|c| c.segments.iter().flatten().copied()),
    );
    let ((x0, x1), (y0, y1)) = square_box(all);
    let y_range = if panel.y_down { y1..y0 } else { y0..y1 };
    // The caption, wrapped to the panel's width.
    let (w, _) = area.dim_in_pixel();
    let lines = wrap(&panel.title, w.saturating_sub(24), CAPTION.0);
    let (caption, area) = area.split_vertically(CAPTION.1 * lines.len() as u32 + 6);
    for (cell, line) in caption
        .split_evenly((lines.len().max(1), 1))
        .iter()
        .zip(&lines)
    {
        draw_title(cell, line, CAPTION.0)?;
    }
    let mut chart = ChartBuilder::on(&area)
        .margin(8)
        .x_label_area_size(36)
        .y_label_area_size(52)
        .build_cartesian_2d(x0..x1, y_range)?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(235, 235, 235))
        .label_style(font(13))
        .x_desc("x")
        .y_desc("y")
        .axis_desc_style(font(14))
        .draw()?;
    let grey = RGBColor(120, 120, 120);
    chart.draw_series(
        panel
            .data
            .iter()
            .map(|p| Circle::new((p.x, p.y), 2, grey.filled())),
    )?;
    for curve in &panel.curves {
        let c = colours[labels.iter().position(|l| *l == curve.label).unwrap_or(0)];
        for poly in &curve.control_polygons {
            chart.draw_series(std::iter::once(PathElement::new(
                poly.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>(),
                c.mix(0.45).stroke_width(1),
            )))?;
            chart.draw_series(
                poly.iter()
                    .map(|p| Rectangle::new([(p.x, p.y), (p.x, p.y)], c.stroke_width(4))),
            )?;
        }
        for seg in &curve.segments {
            chart.draw_series(std::iter::once(PathElement::new(
                seg.iter().map(|p| (p.x, p.y)).collect::<Vec<_>>(),
                c.stroke_width(2),
            )))?;
        }
        // Segment ends: the break points of the piecewise fit.
        chart.draw_series(
            curve
                .segments
                .iter()
                .filter_map(|s| s.first())
                .map(|p| Circle::new((p.x, p.y), 4, c.stroke_width(2))),
        )?;
    }
    Ok(())
}

impl Draw for Overlay<'_> {
    fn size(&self) -> (u32, u32) {
        let (rows, cols) = self.shape();
        let w = PANEL * cols as u32;
        (
            w,
            TITLE_H + legend_height(&self.legend(), w) + PANEL * rows as u32,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult {
        root.fill(&WHITE)?;
        let (w, _) = self.size();
        let (title, rest) = root.split_vertically(TITLE_H);
        draw_title(&title, &self.title, 20)?;
        let legend = self.legend();
        let (strip, body) = rest.split_vertically(legend_height(&legend, w));
        draw_legend(&strip, &legend)?;
        let (rows, cols) = self.shape();
        let cells = body.split_evenly((rows, cols));
        let labels = self.labels();
        for (panel, cell) in self.panels.iter().zip(cells.iter()) {
            draw_panel(cell, panel, &labels)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reconstruction::OverlayCurve;

    fn circle(n: usize, r: f64) -> Vec<Point> {
        (0..n)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / n as f64;
                Point::new(r * a.cos(), r * a.sin())
            })
            .collect()
    }

    #[test]
    fn an_overlay_is_written_as_svg_and_png() {
        let dir = tempfile::tempdir().unwrap();
        let data = circle(60, 10.0);
        let fig = OverlayFigure {
            title: "circle".into(),
            panels: vec![OverlayPanel {
                title: "one".into(),
                data: data.clone(),
                curves: vec![OverlayCurve {
                    label: "fit".into(),
                    segments: vec![data[..31].to_vec(), data[30..].to_vec()],
                    control_polygons: vec![vec![data[0], Point::new(0.0, 20.0), data[30]]],
                }],
                y_down: true,
            }],
            columns: 2,
        };
        let files = save_overlay(&fig, dir.path(), "fit").unwrap();
        assert_eq!(files.len(), 2);
        let svg = std::fs::read_to_string(&files[0]).unwrap();
        assert!(
            svg.contains("circle") && svg.contains("<polyline"),
            "{svg:.300}"
        );
        let png = std::fs::read(&files[1]).unwrap();
        assert_eq!(&png[1..4], b"PNG");
    }

    #[test]
    fn long_captions_wrap_at_their_separators() {
        let title = "rational-cubic: C1 E = 1.23e+01 (LM), G1 E = 3.60e+01 (LM), \
                     G1 orthogonal/joint E = 4.21e-01 (LM), C1 orthogonal/joint E = 9.9e-01 (LM)";
        let lines = wrap(title, 400, 16);
        assert!(lines.len() > 1, "{lines:?}");
        assert!(lines.iter().all(|l| text_width(l, 16) <= 400), "{lines:?}");
        assert_eq!(lines.join(" "), title);
        assert_eq!(wrap("short", 400, 16), ["short"]);
    }

    #[test]
    fn the_box_is_square_around_the_points() {
        let ((x0, x1), (y0, y1)) =
            square_box([Point::new(0.0, 0.0), Point::new(10.0, 2.0)].into_iter());
        assert!(((x1 - x0) - (y1 - y0)).abs() < 1e-12);
        assert!(x0 < 0.0 && x1 > 10.0 && y0 < 1.0 - 5.0 && y1 > 1.0 + 5.0);
    }
}
