//! `metabezier compare A B [C …]`: two or more finished campaigns side by
//! side, A against each of the others.
//!
//! A shared cell is an algorithm configuration (the `algorithm` label and
//! the `params` of runs.csv) that both campaigns ran on a problem (function,
//! dimension, transform and instance) at the same budget. For each, the
//! runs of A and of the other campaign are compared problem by problem
//! ([`crate::compare_tests`]): paired by seed where the design pairs them,
//! unpaired otherwise, and not at all where every run agrees bit for bit
//! ("identical runs"). The per-problem summaries then make the report's
//! verdicts across problems ([`crate::verdicts`]): the Wilcoxon
//! signed-rank test of the per-function summaries, Holm-corrected over the
//! shared cells of one pair of campaigns, with the Hodges–Lehmann interval
//! and the Bayesian signed-rank test's region of practical equivalence.
//! The figures ([`crate::compare_plots`]) overlay the campaigns' runtime
//! ECDFs and draw the cumulative difference of their error ranks.
//!
//! The output (`compare.md`, `compare.html`, `tables/*.csv`,
//! `plots/*.{svg,png}`) is deterministic: the same directories give the
//! same bytes. Every file is written atomically.

use std::path::{Path, PathBuf};

use crate::compare_sides::{load_side, shared_cells, some_cells, Side};
use crate::files::{create_dir, write_atomic};
use crate::ReportError;

/// How to compare campaigns.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareOptions {
    /// The output directory; by default `<A>/compare-<B>` (the other
    /// directories' names joined by `-`).
    pub out: Option<PathBuf>,
    /// Significance level of the tests (default 0.05).
    pub alpha: f64,
    /// The ropes of the Bayesian signed-rank test, as `report --rope`
    /// gives them (measure, half-width); they override A's spec `[report]`
    /// keys, which override [`crate::Ropes::default`].
    pub ropes: Vec<(String, f64)>,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            out: None,
            alpha: crate::stats::DEFAULT_ALPHA,
            ropes: Vec::new(),
        }
    }
}

/// What [`write_compare`] wrote and found.
#[derive(Clone, Debug, PartialEq)]
pub struct CompareSummary {
    /// The output directory.
    pub out: PathBuf,
    /// `<out>/compare.md`.
    pub markdown: PathBuf,
    /// `<out>/compare.html`, the same as one page.
    pub html: PathBuf,
    /// The CSV tables under `<out>/tables/`.
    pub tables: Vec<PathBuf>,
    /// The plots under `<out>/plots/`, SVG and PNG.
    pub plots: Vec<PathBuf>,
    /// Shared (cell, problem) pairs over all compared campaigns.
    pub shared: usize,
    /// Whether every shared run of every campaign agrees with A's bit for
    /// bit.
    pub identical: bool,
    /// The verdicts across problems at scope `all` on the final error, as
    /// `cell: verdict` (or `identical`), one per shared cell and campaign.
    pub verdicts: Vec<String>,
    /// Parts that were skipped and why.
    pub notes: Vec<String>,
}

/// The places `compare` writes in its output directory.
const WRITTEN: [&str; 4] = ["tables", "plots", "compare.md", "compare.html"];

/// The output directory: the one asked for, or `<A>/compare-<B>[-<C>…]`.
fn output_dir(dirs: &[PathBuf], out: Option<&Path>) -> PathBuf {
    out.map(Path::to_owned).unwrap_or_else(|| {
        let names: Vec<String> = dirs[1..]
            .iter()
            .map(|d| {
                d.file_name()
                    .map_or_else(|| "campaign".into(), |n| n.to_string_lossy().into_owned())
            })
            .collect();
        dirs[0].join(format!("compare-{}", names.join("-")))
    })
}

/// Refuses fewer than two directories, one given twice, and an output
/// directory that is one of the campaigns (its tables and plots would be
/// overwritten).
fn check_usage(dirs: &[PathBuf], out: &Path) -> Result<(), ReportError> {
    if dirs.len() < 2 {
        return Err(ReportError::CompareUsage(
            "give at least two results directories".into(),
        ));
    }
    let canonical: Vec<Option<PathBuf>> =
        dirs.iter().map(|d| std::fs::canonicalize(d).ok()).collect();
    for (i, c) in canonical.iter().enumerate() {
        if c.is_some() && canonical[..i].contains(c) {
            return Err(ReportError::CompareUsage(format!(
                "{} is given twice; a campaign compared with itself says nothing (compare it \
                 with its rerun)",
                dirs[i].display()
            )));
        }
    }
    if let Ok(o) = std::fs::canonicalize(out) {
        if let Some(i) = canonical.iter().position(|c| c.as_ref() == Some(&o)) {
            return Err(ReportError::CompareUsage(format!(
                "--out {} is the campaign directory {}: its report's tables and plots would be \
                 overwritten; choose another directory",
                out.display(),
                dirs[i].display()
            )));
        }
    }
    Ok(())
}

/// Compares the campaigns of `dirs` (A first, then the others): writes
/// `compare.md`, `compare.html`, `tables/*.csv` and `plots/*.{svg,png}`
/// into the output directory ([`CompareOptions::out`]).
///
/// Errors when fewer than two directories are given or one twice, when a
/// directory has no `runs.csv` or an unfinished journal, when a campaign's
/// files are malformed (as `report` reads them), when A shares no
/// configuration on a problem at the same budget with one of the others
/// (naming both and a few of their configurations), when a place it writes
/// is a symbolic link out of the output directory, or when a file cannot
/// be written.
pub fn write_compare(
    dirs: &[PathBuf],
    options: &CompareOptions,
) -> Result<CompareSummary, ReportError> {
    if !(options.alpha > 0.0 && options.alpha < 1.0) {
        return Err(ReportError::Alpha(options.alpha));
    }
    let out = output_dir(dirs, options.out.as_deref());
    check_usage(dirs, &out)?;
    let sides: Vec<Side> = dirs
        .iter()
        .enumerate()
        .map(|(i, d)| load_side(i, d))
        .collect::<Result<_, _>>()?;
    let mut shared = Vec::new();
    for (i, other) in sides.iter().enumerate().skip(1) {
        let found = shared_cells(&sides[0], other, i);
        if found.is_empty() {
            return Err(ReportError::NothingShared {
                a: sides[0].dir.clone(),
                b: other.dir.clone(),
                a_cells: some_cells(&sides[0]),
                b_cells: some_cells(other),
            });
        }
        shared.extend(found);
    }
    let ropes = crate::effective_ropes(
        &sides[0].provenance.report_keys,
        &crate::ReportOptions {
            ropes: options.ropes.clone(),
            ..crate::ReportOptions::default()
        },
    )?;
    let analysis = crate::compare_tests::analyse(&sides, &shared, options.alpha, ropes);
    create_dir(&out)?;
    crate::integrity::check_inside(&out, &WRITTEN)?;
    let mut doc = crate::compare_sections::document(&sides, &shared, &analysis, options.alpha);
    let (tables, plots) = write_files(&out, &mut doc)?;
    let markdown = out.join("compare.md");
    write_atomic(&markdown, doc.markdown().as_bytes())?;
    let html = crate::html::write_html_of(&out, "compare")?;
    Ok(CompareSummary {
        out,
        markdown,
        html,
        tables,
        plots,
        shared: shared.iter().map(|s| s.ds.problems.len()).sum(),
        identical: analysis.all_identical(),
        verdicts: analysis.verdict_lines(&sides, &shared),
        notes: doc.notes.clone(),
    })
}

/// Writes the document's tables and figures; a figure the backend cannot
/// draw is left out and named in the notes.
fn write_files(
    out: &Path,
    doc: &mut crate::compare_sections::Document,
) -> Result<(Vec<PathBuf>, Vec<PathBuf>), ReportError> {
    let tables_dir = out.join("tables");
    let plots_dir = out.join("plots");
    create_dir(&tables_dir)?;
    create_dir(&plots_dir)?;
    let mut table_paths = Vec::new();
    for t in &doc.tables {
        let path = tables_dir.join(format!("{}.csv", t.stem));
        write_atomic(&path, &t.csv_bytes())?;
        table_paths.push(path);
    }
    let mut plot_paths = Vec::new();
    let mut drawn = Vec::new();
    for p in std::mem::take(&mut doc.figures) {
        match crate::render::save(&p.figure, &plots_dir, &p.stem) {
            Ok(paths) => {
                plot_paths.extend(paths);
                drawn.push(p);
            }
            Err(e @ ReportError::Draw { .. }) => doc.notes.push(format!("plots/{}: {e}", p.stem)),
            Err(e) => return Err(e),
        }
    }
    doc.figures = drawn;
    Ok((table_paths, plot_paths))
}
