//! Writing a figure as SVG and PNG files (both through [`write_atomic`]);
//! the drawing primitives are `metabezier-plot`'s ([`metabezier_plot::render`]),
//! re-exported here for the report's plots.

use std::path::{Path, PathBuf};

use plotters::prelude::{BitMapBackend, IntoDrawingArea, SVGBackend};

pub(crate) use metabezier_plot::render::*;

use crate::files::{write_atomic, IoError};
use crate::ReportError;
use metabezier_plot::font::{ensure_font, GlyphBackend};

/// Writes `figure` as `<dir>/<stem>.svg` and `<dir>/<stem>.png`; returns the
/// two paths.
pub(crate) fn save<F: Draw>(
    figure: &F,
    dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, ReportError> {
    ensure_font()?;
    let (w, h) = figure.size();
    let fail = |kind: &str, e: PlotError| ReportError::Draw {
        file: format!("{stem}.{kind}"),
        message: e.0,
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area();
        figure.draw(&root).map_err(|e| fail("svg", e))?;
        root.present()
            .map_err(|e| fail("svg", PlotError::from(e)))?;
    }
    let svg_path = dir.join(format!("{stem}.svg"));
    write_atomic(&svg_path, svg.as_bytes())?;

    // The bitmap backend encodes PNG only to a file: render to a scratch
    // file beside the target, then publish its bytes atomically.
    let png_path = dir.join(format!("{stem}.png"));
    static SCRATCH: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = SCRATCH.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let scratch = dir.join(format!(".{stem}.{}-{n}.render.png", std::process::id()));
    let drawn = (|| -> DrawResult {
        let root = GlyphBackend(BitMapBackend::new(&scratch, (w, h))).into_drawing_area();
        figure.draw(&root)?;
        root.present()?;
        Ok(())
    })();
    let bytes = drawn.map_err(|e| fail("png", e)).and_then(|()| {
        std::fs::read(&scratch).map_err(|e| IoError::new("read", &scratch, e).into())
    });
    let _ = std::fs::remove_file(&scratch);
    write_atomic(&png_path, &bytes?)?;
    Ok(vec![svg_path, png_path])
}
