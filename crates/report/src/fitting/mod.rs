//! The curve-fitting part of a report, for campaigns with `[[fit]]`
//! problems: fit quality beyond `E`, the gap of every method to the best
//! `E` found by any method, whether the hybrid beats both of its parts, the
//! search-space technique against the bounding box, overlays of the best
//! fit of each function on each outline and, for campaigns in the
//! per-segment mode, the segment-level tests ([`super::fit_units`]).
//!
//! Problem names of fitting campaigns are `source/function/continuity`,
//! then `/bounding-box` for the naive search space, `/alpha=A` for a listed
//! α_size other than 0.5, `/per-segment` in the per-segment mode. When runs
//! of one name differ in budget, each budget per segment is its own problem
//! here, as in the rest of the report.
//!
//! The section is read and computed here and in [`observations`]; its
//! tables are rendered in [`tables`], its overlays drawn in [`overlays`].

mod observations;
mod overlays;
mod tables;

use std::path::Path;

use super::data::Dataset;
use super::fit_runs::FitRuns;
use super::format::Table;
use super::plots::Plot;
use super::verdicts::Observation;
use crate::experiment::records::{read_results, RunRecord};
use crate::experiment::ReadError;
use crate::stats::VerdictRow;

use self::overlays::{overlays, read_outlines};
use self::tables::{functions_table, hybrid_table, quality_table, search_space_table};

pub(crate) use self::observations::treatment_observations;

/// What the fitting section adds to a report.
pub(crate) struct FittingSection {
    /// Its tables.
    pub tables: Vec<Table>,
    /// Its figures (one overlay per source).
    pub figures: Vec<Plot>,
    /// Remarks.
    pub notes: Vec<String>,
}

/// The records of a fitting campaign in `dir` (runs with their fit
/// details), or `None` when it has no `fits.csv`.
pub(crate) fn records(dir: &Path) -> Result<Option<Vec<RunRecord>>, ReadError> {
    if !dir.join("fits.csv").exists() {
        return Ok(None);
    }
    read_results(dir).map(Some)
}

/// The fitting section of the report in `dir`, or `None` if the campaign
/// has no fitting runs; `observations` and `verdicts` are those of the
/// report, whose segment-level rows the per-segment tables show.
pub(crate) fn section(
    dir: &Path,
    ds: &Dataset,
    fits: Option<&FitRuns<'_>>,
    observations: &[Observation],
    verdicts: &[VerdictRow],
    alpha: f64,
) -> Result<Option<FittingSection>, ReadError> {
    let Some(fr) = fits else {
        return Ok(None);
    };
    let best = fr.best();
    let mut notes = Vec::new();
    let mut tables = vec![quality_table(fr, &best), functions_table(fr, &best)];
    let space = search_space_table(fr, alpha);
    if !space.md_rows.is_empty() {
        tables.push(space);
    }
    let (units, unit_notes) = super::fit_units::tables(fr, observations, verdicts, alpha);
    tables.extend(units);
    notes.extend(unit_notes);
    let hybrid = hybrid_table(fr);
    if hybrid.md_rows.is_empty() {
        notes.push(
            "no hybrid table: the campaign does not run a metaheuristic X, LM and X+lm together"
                .into(),
        );
    } else {
        tables.push(hybrid);
    }
    let outlines = read_outlines(dir)?;
    let figures = overlays(ds, fr, &outlines, &mut notes);
    Ok(Some(FittingSection {
        tables,
        figures,
        notes,
    }))
}
