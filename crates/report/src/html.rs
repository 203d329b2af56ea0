//! `report.html`: the report of a results directory as one self-contained
//! page beside its `report.md` (figures inlined, CSV tables attached,
//! sortable tables, a table of contents), made by
//! [`metabezier_plot::markdown::html::markdown_to_html`].

use std::path::{Path, PathBuf};

use super::ReportError;
use crate::files::{read_text_limited, write_atomic, IoError, MAX_TEXT_BYTES};
use metabezier_plot::markdown::html::markdown_to_html;

/// Writes `<dir>/report.html` from `<dir>/report.md` and the figures and
/// CSV tables it links (`plots/`, `tables/`); returns its path.
///
/// Errors when `report.md` cannot be read (missing, not UTF-8, larger than
/// [`MAX_TEXT_BYTES`]) or `report.html` cannot be written; a missing figure
/// or table is named in the page instead.
pub fn write_html(dir: &Path) -> Result<PathBuf, ReportError> {
    write_html_of(dir, "report")
}

/// Writes `<dir>/<stem>.html` from `<dir>/<stem>.md` as [`write_html`]
/// does (`compare.md` → `compare.html`); returns its path.
pub(crate) fn write_html_of(dir: &Path, stem: &str) -> Result<PathBuf, ReportError> {
    let md = dir.join(format!("{stem}.md"));
    let markdown = read_text_limited(&md, MAX_TEXT_BYTES, "a report")
        .map_err(|e| IoError::new("read", &md, e))?;
    let path = dir.join(format!("{stem}.html"));
    write_atomic(&path, markdown_to_html(&markdown, dir).as_bytes())?;
    Ok(path)
}
