//! `metabezier fit --outputs`: which files a single fit writes.

use std::path::{Path, PathBuf};

use crate::error::Error;
use crate::reconstruction::{save_shape_png, save_shape_svg, shape_dxf, OverlayFigure, ShapeFit};
use crate::report::save_overlay;
use metabezier_core::geometry::Point;

/// A group of files `metabezier fit` writes (`--outputs`, a comma-separated
/// list; `csv,svg` by default: the records and the vector drawing, the
/// rasters only on request, as they cost a third of a fixed-error fit).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub(super) enum FitOutput {
    /// `fit.csv` (the control points and weights), `metrics.csv`, `timing.csv`.
    Csv,
    /// `fit.svg`, the fit as one even-odd path over the data points.
    Svg,
    /// `fit.png`, the fit's raster (800 pixels).
    Png,
    /// `fit.dxf`, the exact (rational) curves as DXF SPLINEs.
    Dxf,
    /// `overlay.svg` and `overlay.png`, the data and the fit in panels.
    Overlay,
    /// Every file above.
    All,
}

impl FitOutput {
    /// Whether `chosen` asks for `self`'s files.
    pub(super) fn in_list(self, chosen: &[FitOutput]) -> bool {
        chosen.contains(&self) || chosen.contains(&FitOutput::All)
    }
}

/// Writes the drawing files `chosen` asks for (all but the CSV records,
/// which the caller writes) into `dir`, titled `title`, the data points
/// `data` under the fit; returns their paths.
pub(super) fn write_drawings(
    chosen: &[FitOutput],
    fit: &ShapeFit,
    title: &str,
    data: &[Point],
    dir: &Path,
) -> Result<Vec<PathBuf>, Error> {
    let mut paths = Vec::new();
    if FitOutput::Svg.in_list(chosen) {
        paths.push(save_shape_svg(fit, data, title, dir, "fit")?);
    }
    if FitOutput::Png.in_list(chosen) {
        paths.push(save_shape_png(fit, data, dir, "fit")?);
    }
    if FitOutput::Dxf.in_list(chosen) {
        let dxf = dir.join("fit.dxf");
        crate::files::write_atomic(&dxf, shape_dxf(fit).as_bytes())?;
        paths.push(dxf);
    }
    if FitOutput::Overlay.in_list(chosen) {
        let figure = OverlayFigure::of_fit(title, data, fit);
        paths.extend(save_overlay(&figure, dir, "overlay")?);
    }
    Ok(paths)
}
