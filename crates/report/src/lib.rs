//! Reports on a finished campaign: descriptive tables, significance tests
//! against a reference algorithm, the Friedman ranking, parameter-tuning
//! summaries and plots, written next to the results as `report.md`,
//! `tables/*.csv` and `plots/*.{svg,png}`.
//!
//! The input is a results directory of `metabezier run` (`runs.csv`,
//! `convergence.csv`, `timing.csv`, `hits.csv` or the fitting files,
//! `spec.toml`, `meta.toml`: a directory with `meta.toml` must hold every
//! result file of its campaign), or a `runs.csv` alone, optionally with an external `runs.csv` whose algorithms are added to the
//! comparison. All statistics come from [`crate::stats`]. The output is
//! deterministic: the same input gives byte-identical `report.md` and CSV
//! files (and plots). Every file is written atomically.
//!
//! A "cell" is an algorithm configuration (label and parameters); cells that
//! share a label are shown with their distinguishing parameters, e.g.
//! `MHS (hmcr=0.9, bw=0.01)`. A "problem" is a function at a dimension.
//!
//! This crate (metabezier-report) reads what `metabezier-campaign` writes
//! and draws with `metabezier-plot`; the rooms it stands on are named at
//! this root (`experiment` is the campaign crate), so that
//! `crate::experiment::records` reads as it did in the one-crate house.
#![warn(missing_docs)]

mod anytime;
mod best2009;
pub mod claims;
mod compare;
mod compare_plots;
mod compare_sections;
mod compare_sides;
mod compare_spec;
mod compare_tests;
mod cumulative_difference;
mod data;
mod descriptive;
mod design;
mod error;
mod external;
mod families;
mod fit_runs;
mod fit_units;
mod fitting;
mod html;
mod integrity;
mod markdown;
mod overlay;
pub(crate) mod plots;
pub(crate) mod render;
mod robustness;
mod setup;
mod significance;
mod summary;
#[cfg(test)]
mod test_records;
mod tuning;
mod verdicts;

use metabezier_campaign as experiment;
use metabezier_core::{functions, geometry, optim, rng, stats};
use metabezier_files as files;
use metabezier_fit::{fit, reconstruction};
use metabezier_plot::{format, style};

use std::path::{Path, PathBuf};

use crate::experiment::records::default_targets;
use crate::files::{create_dir, write_atomic};

pub use self::compare::{write_compare, CompareOptions, CompareSummary};
pub use self::error::ReportError;
use self::format::Table;
pub use self::html::write_html;
pub use self::overlay::save_overlay;
use self::plots::Plot;
pub use self::verdicts::{Families, PostHoc, RopeError, Ropes};

/// How to build a report.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportOptions {
    /// The algorithm every other one is tested against: a label (`MHS`) or
    /// a full configuration name as shown in the report (`MHS (hmcr=0.9)`).
    /// By default `MHS` if present, else the first algorithm. When a label
    /// has several configurations, the first one is the reference.
    pub reference: Option<String>,
    /// Significance level of the tests (default 0.05); the Nemenyi critical
    /// difference is tabulated for 0.05 and 0.10 only.
    pub alpha: f64,
    /// An extra `runs.csv` (for example from another tool) whose algorithms
    /// are added to the comparison; it has no convergence or timing data.
    pub external: Option<PathBuf>,
    /// The correction of the post-hoc tests after Friedman's test.
    pub post_hoc: PostHoc,
    /// The command line's ropes (`--rope final-error=0.3`): (measure,
    /// half-width) of the region of practical equivalence of the Bayesian
    /// signed-rank test beside every verdict. They override the spec's
    /// `[report]` section, which overrides [`Ropes::default`]
    /// ([`effective_ropes`]).
    pub ropes: Vec<(String, f64)>,
    /// A claims file (`experiments/claims.toml`): the primary row of each
    /// thesis claim ([`claims::read_claims`]); the summary answers the
    /// claims of this campaign first.
    pub claims: Option<PathBuf>,
    /// The comparison families of the optimisers of a library user's
    /// registry ([`Families::of`]); the built-ins' by default.
    pub families: Families,
}

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            reference: None,
            alpha: crate::stats::DEFAULT_ALPHA,
            external: None,
            post_hoc: PostHoc::Holm,
            ropes: Vec::new(),
            families: Families::default(),
            claims: None,
        }
    }
}

/// The ropes a report uses: [`Ropes::default`], then the spec's
/// `[report]` keys (`rope_final_error`, `rope_anytime_auc`), then the
/// command line's; an unknown key or a bad value is an error naming where
/// it came from.
pub fn effective_ropes(
    spec_keys: &[(String, f64)],
    options: &ReportOptions,
) -> Result<Ropes, ReportError> {
    let mut ropes = Ropes::default();
    for (key, value) in spec_keys {
        let measure =
            crate::experiment::spec::rope_measure(key).ok_or_else(|| ReportError::Rope {
                origin: format!("spec.toml [report] key \"{key}\""),
                error: RopeError::Measure(key.clone()),
            })?;
        ropes
            .set(&measure, *value)
            .map_err(|error| ReportError::Rope {
                origin: format!("spec.toml [report] {key}"),
                error,
            })?;
    }
    for (measure, value) in &options.ropes {
        ropes
            .set(measure, *value)
            .map_err(|error| ReportError::Rope {
                origin: "--rope".into(),
                error,
            })?;
    }
    Ok(ropes)
}

/// What [`write_report`] wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportSummary {
    /// The Markdown report, `<dir>/report.md`.
    pub report: PathBuf,
    /// The same report as one self-contained page, `<dir>/report.html`
    /// ([`write_html`]).
    pub html: PathBuf,
    /// The CSV tables under `<dir>/tables/`.
    pub tables: Vec<PathBuf>,
    /// The plots under `<dir>/plots/`, SVG and PNG.
    pub plots: Vec<PathBuf>,
    /// Number of algorithm configurations (cells) compared.
    pub algorithms: usize,
    /// Number of problems (function, dimension).
    pub problems: usize,
    /// Number of runs read.
    pub runs: usize,
    /// The reference algorithm of the tests, if there were tests.
    pub reference: Option<String>,
    /// Parts that were skipped and why (also stated in the report).
    pub notes: Vec<String>,
    /// The figures that the results should have allowed but did not (every
    /// error infinite or NaN) or that could not be drawn; the summary of
    /// `report.md` names them and `metabezier report` fails on them unless
    /// given `--keep-going`.
    pub faults: Vec<String>,
}

/// Chooses the reference cell: the requested label or name, else `MHS`,
/// else the first cell. Returns the cell and a note when a label matched
/// several configurations.
fn resolve_reference(
    ds: &data::Dataset,
    requested: Option<&str>,
) -> Result<(usize, Option<String>), ReportError> {
    let by_label = |label: &str| ds.cells.iter().position(|c| c.label == label);
    let found = match requested {
        Some(r) => ds
            .cells
            .iter()
            .position(|c| c.name == r)
            .or_else(|| by_label(r))
            .ok_or_else(|| ReportError::UnknownReference {
                requested: r.to_owned(),
                names: ds.cells.iter().map(|c| c.name.clone()).collect(),
            })?,
        None => by_label("MHS").unwrap_or(0),
    };
    let cell = &ds.cells[found];
    let same_label = ds.cells.iter().filter(|c| c.label == cell.label).count();
    let note = (same_label > 1 && requested != Some(cell.name.as_str())).then(|| {
        format!(
            "{} has {same_label} configurations; the reference is the first of them, {}. \
             Pass a full configuration name to choose another.",
            cell.label, cell.name
        )
    });
    // Without --reference and without an MHS cell the first cell is the
    // reference: said, never silent.
    let first = (requested.is_none() && by_label("MHS").is_none()).then(|| {
        format!(
            "No reference was given (--reference) and no configuration is labelled MHS: the \
             reference is the first configuration of the results, {}.",
            cell.name
        )
    });
    let note = match (first, note) {
        (Some(a), Some(b)) => Some(format!("{a} {b}")),
        (a, b) => a.or(b),
    };
    Ok((found, note))
}

/// The statistical tests of a report, or why there are none.
struct Tests {
    /// The reference algorithm's name, when there are tests.
    reference: Option<String>,
    /// Why the reference was chosen, when a label was ambiguous.
    reference_note: Option<String>,
    /// The first-level test tables and the ranking (empty without tests).
    tables: Vec<Table>,
    /// The paragraph shown instead of the tables when there are none.
    text: Option<String>,
    /// Where the comparisons with the reference hold and where they flip.
    robustness: Vec<Table>,
    /// Every verdict across problems, and its table.
    verdicts: Vec<crate::stats::VerdictRow>,
    /// The table of the verdicts (`tables/verdicts.csv`).
    verdict_table: Option<Table>,
    /// The observations the verdicts were made from.
    observations: Vec<verdicts::Observation>,
}

/// The first-level tests against the reference, the verdicts across
/// problems and the Friedman ranking, or, with a single algorithm, the
/// reason there are none (also added to `notes`).
fn tests(
    ds: &data::Dataset,
    stats: &[Vec<Option<descriptive::CellStats>>],
    options: &ReportOptions,
    provenance: &data::Provenance,
    fits: Option<&fit_runs::FitRuns<'_>>,
    notes: &mut Vec<String>,
) -> Result<Tests, ReportError> {
    let alpha = options.alpha;
    let ropes = effective_ropes(&provenance.report_keys, options)?;
    if ds.cells.len() < 2 {
        if let Some(r) = &options.reference {
            // Still check the name, so that a typo is not silently ignored.
            resolve_reference(ds, Some(r))?;
        }
        let text = "There is a single algorithm configuration: no significance test between \
                    methods, Friedman ranking or Nemenyi critical difference can be computed."
            .to_owned();
        notes.push(text.clone());
        // The comparisons between fitting functions and continuities need
        // one method only.
        let observations = fits
            .map(fitting::treatment_observations)
            .unwrap_or_default();
        let rows = verdicts::verdicts(
            &observations,
            &[],
            verdicts::Settings {
                alpha,
                post_hoc: options.post_hoc,
                reference: None,
                ropes,
            },
        );
        let verdict_table =
            (!rows.is_empty()).then(|| verdicts::table(&rows, design::unit_noun(ds), alpha));
        return Ok(Tests {
            reference: None,
            reference_note: None,
            tables: Vec::new(),
            text: Some(text),
            robustness: Vec::new(),
            verdicts: rows,
            verdict_table,
            observations,
        });
    }
    let (reference, reference_note) = resolve_reference(ds, options.reference.as_deref())?;
    let s = significance::significance(ds, reference, alpha, provenance.threshold);
    if !s.skipped_problems.is_empty() {
        let names: Vec<String> = s
            .skipped_problems
            .iter()
            .map(|&p| ds.problems[p].title())
            .collect();
        notes.push(format!(
            "The reference {} did not run {}: no tests there.",
            ds.cells[reference].name,
            names.join("; ")
        ));
    }
    let ref_name = ds.cells[reference].name.clone();
    let (mut observations, mut standings) = significance::observations(ds, &s);
    if let Some(fr) = fits {
        let (o, st) = fit_units::observations(fr, Some(&ref_name), s.floor);
        observations.extend(o);
        observations.extend(fitting::treatment_observations(fr));
        standings.extend(st);
    }
    let rows = verdicts::verdicts(
        &observations,
        &standings,
        verdicts::Settings {
            alpha,
            post_hoc: options.post_hoc,
            reference: Some(&ref_name),
            ropes,
        },
    );
    let noun = design::unit_noun(ds);
    let f = significance::friedman_report(ds, &standings, alpha, noun);
    let mut tables = vec![
        significance::comparison_table(ds, stats, &s, alpha),
        significance::tests_table(ds, &s, verdicts::Measure::FinalError, alpha),
    ];
    if !s.anytime.is_empty() {
        tables.push(significance::tests_table(
            ds,
            &s,
            verdicts::Measure::AnytimeAuc,
            alpha,
        ));
    }
    tables.push(significance::marks_summary_table(ds, &s));
    tables.push(significance::friedman_table(ds, &f, alpha));
    let budget_note = robustness::budget_pairs_note(ds, &provenance.paired);
    Ok(Tests {
        reference: Some(ref_name),
        reference_note,
        tables,
        text: None,
        robustness: robustness::tables(ds, &s, &rows, noun, budget_note),
        verdict_table: Some(verdicts::table(&rows, noun, alpha)),
        verdicts: rows,
        observations,
    })
}

/// The tuning tables and heat maps of every parameter grid; a grid of two
/// or more parameters without a heat map gets a note.
fn tuning(
    ds: &data::Dataset,
    stats: &[Vec<Option<descriptive::CellStats>>],
    notes: &mut Vec<String>,
) -> (Vec<Table>, Vec<Table>, Vec<tuning::HeatMap>) {
    let mut heat_maps = Vec::new();
    let mut per_grid = Vec::new();
    for g in tuning::grids(ds) {
        per_grid.push((g.clone(), tuning::tables(ds, &g, stats)));
        let g = &g;
        match tuning::heat_map(ds, g, stats) {
            Some(h) => heat_maps.push(h),
            None if g.varying.len() < 2 => {}
            None => notes.push(format!(
                "{}: no heat map, no mean error is defined on the grid.",
                g.label
            )),
        }
    }
    let overview = if per_grid.len() > 1 {
        tuning::overview(&per_grid)
    } else {
        Vec::new()
    };
    let tables = per_grid.into_iter().flat_map(|(_, t)| t).collect();
    (tables, overview, heat_maps)
}

/// The distinct budgets and the distinct numbers of runs per (problem,
/// cell) in the results, both sorted.
fn budgets_and_run_counts(ds: &data::Dataset) -> (Vec<u64>, Vec<usize>) {
    let mut budgets: Vec<u64> = Vec::new();
    let mut run_counts: Vec<usize> = Vec::new();
    for p in 0..ds.problems.len() {
        for c in 0..ds.cells.len() {
            let runs = ds.runs(p, c);
            budgets.extend(runs.iter().map(|r| r.budget));
            if !runs.is_empty() {
                run_counts.push(runs.len());
            }
        }
    }
    run_counts.sort_unstable();
    run_counts.dedup();
    budgets.sort_unstable();
    budgets.dedup();
    (budgets, run_counts)
}

/// Everything a report shows, in the order of its sections.
struct Sections {
    /// The algorithms and problems tables.
    setup: [Table; 2],
    /// The descriptive table.
    results: Table,
    /// The descriptive statistics, `stats[problem][cell]`.
    stats: Vec<Vec<Option<descriptive::CellStats>>>,
    /// The statistical tests.
    tests: Tests,
    /// The average runtime to each target.
    anytime: Vec<Table>,
    /// The parameter-tuning tables, every grid's.
    tuning: Vec<Table>,
    /// The overview of several grids that `report.md` shows in place of
    /// their own tables (empty for a single grid).
    tuning_overview: Vec<Table>,
    /// The curve-fitting tables.
    fitting: Vec<Table>,
    /// The figures.
    figures: Vec<Plot>,
    /// Parts that were skipped or limited, and why.
    notes: Vec<String>,
    /// The figures the data should have allowed but did not, or that could
    /// not be drawn: the summary names them, and the command fails on them
    /// unless told to go on.
    faults: Vec<String>,
}

impl Sections {
    /// Every table, in the order of the report.
    fn tables(&self) -> impl Iterator<Item = &Table> {
        self.setup
            .iter()
            .chain(std::iter::once(&self.results))
            .chain(&self.tests.verdict_table)
            .chain(&self.tests.tables)
            .chain(&self.tests.robustness)
            .chain(&self.anytime)
            .chain(&self.tuning)
            .chain(&self.tuning_overview)
            .chain(&self.fitting)
    }
}

/// The question a report answers, from what its results hold.
fn question(s: &Sections, ds: &data::Dataset) -> String {
    let reference = s.tests.reference.as_deref().unwrap_or("the reference");
    if !s.fitting.is_empty() && ds.cells.len() < 2 {
        "which fitting function and which continuity fit the outlines with the lowest \
         error E, and where does the verdict hold (error, chain, equal segments or equal \
         free parameters)?"
            .into()
    } else if !s.fitting.is_empty() {
        format!(
            "which method fits the outlines with the lowest fitting error E (and RMS and \
             maximum distance), segment by segment, and does it beat {reference}?"
        )
    } else if s.tuning.iter().any(|t| t.stem.starts_with("tuning_picks_")) {
        "which setting of each algorithm's parameter grid is best over the problems?".into()
    } else if ds.cells.len() < 2 {
        "how does this single algorithm configuration perform on each problem?".into()
    } else {
        format!(
            "which algorithm reaches a lower final error than {reference} across the {} \
             problem(s), and where does the verdict hold?",
            ds.problems.len()
        )
    }
}

/// Computes every section of the report of `dir` from its dataset.
fn sections(
    dir: &Path,
    ds: &data::Dataset,
    provenance: &data::Provenance,
    options: &ReportOptions,
) -> Result<Sections, ReportError> {
    let stats = descriptive::compute(ds);
    let mut notes: Vec<String> = Vec::new();
    let setup = [setup::algorithms_table(ds), setup::problems_table(ds)];
    let results = descriptive::table(ds, &stats);
    let fit_records = fitting::records(dir)?;
    let fits = fit_records
        .as_deref()
        .map(|r| fit_runs::FitRuns::group(ds, r));
    let tests = tests(ds, &stats, options, provenance, fits.as_ref(), &mut notes)?;
    let (tuning, tuning_overview, heat_maps) = tuning(ds, &stats, &mut notes);
    let best = best2009_for(ds, &mut notes);
    let drawn = plots::figures(
        ds,
        &stats,
        heat_maps,
        provenance.threshold,
        &best,
        tests.verdict_table.as_ref(),
    );
    let mut figures = drawn.plots;
    notes.extend(drawn.notes);
    let faults = drawn.faults;
    let mut fitting = Vec::new();
    if let Some(f) = fitting::section(
        dir,
        ds,
        fits.as_ref(),
        &tests.observations,
        &tests.verdicts,
        options.alpha,
    )? {
        figures.extend(f.figures);
        notes.extend(f.notes);
        fitting = f.tables;
    }
    if let Some(fr) = fits.as_ref() {
        // The figures that answer the chapter's question come first.
        let series = plots::SeriesSet::of(ds, &stats);
        let answers = plots::fit_factors::figures(ds, &series, fr);
        figures.splice(0..0, answers);
    }
    let targets = default_targets();
    let anytime = anytime::art_table(ds, &targets, &best)
        .into_iter()
        .chain(anytime::reached_table(ds, &targets, &best))
        .collect();
    Ok(Sections {
        setup,
        results,
        stats,
        tests,
        anytime,
        tuning,
        tuning_overview,
        faults,
        fitting,
        figures,
        notes,
    })
}

/// COCO's references best 2009 and best 2009–16 when some problem is a
/// bbob function (none otherwise); a note when the vendored references
/// cannot be read.
fn best2009_for(ds: &data::Dataset, notes: &mut Vec<String>) -> Vec<best2009::Best2009> {
    if !ds
        .problems
        .iter()
        .any(|p| best2009::bbob_key(&p.function).is_some())
    {
        return Vec::new();
    }
    match best2009::Best2009::load_all() {
        Ok(b) => b,
        Err(e) => {
            notes.push(format!("best 2009 and best 2009–16 left out: {e}"));
            Vec::new()
        }
    }
}

/// Writes the tables as CSV under `dir/tables/` and the figures as SVG and
/// PNG under `dir/plots/`; returns the paths of both.
fn write_tables_and_plots(
    dir: &Path,
    s: &mut Sections,
) -> Result<(Vec<PathBuf>, Vec<PathBuf>), ReportError> {
    let tables_dir = dir.join("tables");
    let plots_dir = dir.join("plots");
    create_dir(&tables_dir)?;
    create_dir(&plots_dir)?;
    let mut table_paths = Vec::new();
    for t in s.tables() {
        let path = tables_dir.join(format!("{}.csv", t.stem));
        write_atomic(&path, &t.csv_bytes())?;
        table_paths.push(path);
    }
    let mut plot_paths = Vec::new();
    let mut drawn = Vec::with_capacity(s.figures.len());
    for p in std::mem::take(&mut s.figures) {
        match render::save(&p.figure, &plots_dir, &p.stem) {
            Ok(paths) => {
                plot_paths.extend(paths);
                drawn.push(p);
            }
            // A figure the backend cannot draw is left out and named, so
            // that the rest of the report is still written.
            Err(e @ ReportError::Draw { .. }) => {
                let fault = format!("plots/{}: {e}", p.stem);
                s.notes.push(fault.clone());
                s.faults.push(fault);
            }
            Err(e) => return Err(e),
        }
    }
    s.figures = drawn;
    Ok((table_paths, plot_paths))
}

/// Reads and checks the results directory `dir` (and an `external` runs
/// file) as [`write_report`] does before it computes anything: a finished
/// campaign, every result file a campaign directory must hold, well-formed
/// rows stating the campaign. Returns the number of runs read; writes
/// nothing.
pub fn load_results(dir: &Path, external: Option<&Path>) -> Result<usize, ReportError> {
    integrity::check_finished(dir)?;
    let ds = data::load(dir, external)?;
    fitting::records(dir)?;
    Ok(ds.total_runs)
}

/// Writes the report of the results directory `dir`: `report.md`, the
/// tables as CSV under `dir/tables/`, the plots as SVG and PNG under
/// `dir/plots/`, and `report.html` from them all.
///
/// Errors when `runs.csv` (or the external file) is missing or malformed,
/// when a campaign directory (one with `meta.toml`) lacks one of its result
/// files or a result file is malformed, when `options` are invalid, or when
/// a file cannot be written. A `runs.csv` alone (another tool's), a single
/// algorithm, a single run or no successful run are not errors: the parts
/// that need more are skipped and the report says so.
pub fn write_report(dir: &Path, options: &ReportOptions) -> Result<ReportSummary, ReportError> {
    if !(options.alpha > 0.0 && options.alpha < 1.0) {
        return Err(ReportError::Alpha(options.alpha));
    }
    integrity::check_finished(dir)?;
    integrity::check_written_inside(dir)?;
    let mut ds = data::load(dir, options.external.as_deref())?;
    ds.families = options.families.clone();
    let provenance = data::provenance(dir);
    let mut s = sections(dir, &ds, &provenance, options)?;
    let (table_paths, plot_paths) = write_tables_and_plots(dir, &mut s)?;

    let (budgets, run_counts) = budgets_and_run_counts(&ds);
    let header = markdown::Header {
        provenance: &provenance,
        ds: &ds,
        reference: s.tests.reference.clone(),
        reference_note: s.tests.reference_note.clone(),
        alpha: options.alpha,
        external: options.external.as_ref().map(|p| p.display().to_string()),
        budgets,
        run_counts,
        dir_name: dir.file_name().map(|n| n.to_string_lossy().into_owned()),
    };
    let mut md = markdown::title(&header);
    let claims = match &options.claims {
        Some(path) => claims::section(
            path,
            &claims::read_claims(path).map_err(claims::ClaimError::from)?,
            provenance.name.as_deref().unwrap_or(""),
            &s.tests.verdicts,
            options.alpha,
        )?,
        None => String::new(),
    };
    md.push_str(&summary::summary(
        &s,
        &ds,
        (&question(&s, &ds), &claims),
        options.alpha,
        provenance.threshold,
    ));
    md.push_str(&s.figures_markdown());
    md.push_str(&markdown::provenance(&header));
    md.push_str(&s.markdown());
    let report = dir.join("report.md");
    let mut bytes = md.trim_end().as_bytes().to_vec();
    bytes.push(b'\n');
    write_atomic(&report, &bytes)?;
    let html = write_html(dir)?;

    Ok(ReportSummary {
        report,
        html,
        tables: table_paths,
        plots: plot_paths,
        algorithms: ds.cells.len(),
        problems: ds.problems.len(),
        runs: ds.total_runs,
        reference: s.tests.reference,
        notes: s.notes,
        faults: s.faults,
    })
}
