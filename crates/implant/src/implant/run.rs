//! The chapter-6 experiment: the real defect to `implant.stl`, per-slice
//! metrics and overlays, a 3D preview, and the artificial-defect validation
//! with its verdicts against the baselines across independent units
//! (`verdicts.csv`; `metabezier implant`).
//!
//! This module drives the steps; [`super::render`] turns their results into
//! the report, the CSV tables and the pictures. Every output is built in
//! memory and written atomically ([`crate::files::write_atomic`]); the STL is
//! written only once the mesh is checked watertight and consistently
//! oriented. CSV files hold no wall times (they go to `timing.txt`), so they
//! are byte-identical for the same spec and seed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::checks::check_inputs;
use super::pipeline::{reconstruct_defect, resolve_midline, slice_index, ImplantError};
use super::plausibility::{describe, CheckValues};
use super::regions::{Region, RegionRule};
use super::render::{overlay_png, preview_png, validation_figure_of, VALIDATION_FIGURE};
use super::spec::{ImplantSpec, Validation3dSpec, ValidationSpec};
use super::tables::{defect_csv, defect_report, report_header, report_summary, slices_off_target};
use super::tables2d::{validation_csv, validation_report};
use super::tables3d::{validation_3d_csv, validation_3d_report};
use super::validation::{
    case_template_source, evaluate, prepare_case, Case, CaseError, PreparedCase, ValidationRow,
};
use super::validation3d::{evaluate_3d, prepare_case_3d, Case3d, Prepared3d, Row3d};
use super::verdict_tables::verdicts_csv;
use super::wall::WallKind;
use crate::ct::{read_dicom_dir, read_inv3, stl_bytes, Volume};
use crate::files::{write_atomic, Staging};
use crate::fit::{LmSolver, SegmentSolver};
use crate::markdown::html::markdown_to_html;
use crate::reconstruction::Method;
use crate::stats::VerdictRow;

/// Reads a volume: a directory is a DICOM series, anything else an `.inv3`
/// project. Reader errors (truncated or corrupt files, mismatched slice
/// spacing) pass through with their own messages.
pub fn load_volume(path: &Path) -> Result<Volume, ImplantError> {
    let v = if path.is_dir() {
        read_dicom_dir(path)?
    } else {
        read_inv3(path)?
    };
    Ok(v)
}

/// What one run of the experiment produced (for the CLI's summary).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunSummary {
    /// Files written.
    pub files: Vec<PathBuf>,
    /// Seconds for the real-defect pipeline (load → STL written).
    pub pipeline_seconds: Option<f64>,
    /// Rows of `validation.csv`.
    pub validation_rows: usize,
    /// Rows of `validation_3d.csv`.
    pub validation_3d_rows: usize,
}

/// A run in progress: the files built so far (written only once every part
/// has succeeded) and the texts of `report.md` and `timing.txt`.
struct Outputs {
    files: Vec<(String, Vec<u8>)>,
    summary: RunSummary,
    report: String,
    timing: String,
    verdicts: Vec<VerdictRow>,
}

impl Outputs {
    /// Queues `bytes` for the file `name` of the output directory.
    fn add(&mut self, name: &str, bytes: Vec<u8>) {
        self.files.push((name.to_string(), bytes));
    }

    /// Creates `dir` and writes every queued file into it: all into a
    /// staging directory first (`implant.stl` first), with `report.html`
    /// made from the staged `report.md` and pictures, then renamed into
    /// place together ([`Staging`]); returns the seconds spent writing the
    /// STL.
    fn write_all(&mut self, dir: &Path) -> Result<f64, ImplantError> {
        let staging = Staging::new(dir)?;
        self.files
            .sort_by_key(|(name, _)| usize::from(!name.ends_with(".stl")));
        let mut stl_seconds = 0.0;
        for (name, bytes) in &self.files {
            let t = Instant::now();
            write_atomic(&staging.path().join(name), bytes)?;
            if name.ends_with(".stl") {
                stl_seconds = t.elapsed().as_secs_f64();
            }
            self.summary.files.push(dir.join(name));
        }
        if let Some((_, md)) = self.files.iter().find(|(name, _)| name == "report.md") {
            let html = markdown_to_html(&String::from_utf8_lossy(md), staging.path());
            write_atomic(&staging.path().join("report.html"), html.as_bytes())?;
            self.summary.files.push(dir.join("report.html"));
        }
        staging.publish()?;
        Ok(stl_seconds)
    }
}

/// How a run treats a design with refused slices (`metabezier implant`'s
/// flags).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RunOptions {
    /// `--allow-partial`: write the implant of the accepted slices as
    /// `implant.partial.stl` (the report's first line names the refused
    /// slices) instead of refusing the whole design
    /// ([`ImplantError::Implausible`]).
    pub allow_partial: bool,
}

/// The name of the STL of a design with refused slices.
pub const PARTIAL_STL: &str = "implant.partial.stl";

/// Runs the whole experiment of `spec` into `out` (created if needed) with
/// the default [`RunOptions`] (a design with a refused slice is refused).
pub fn run_implant(spec: &ImplantSpec, out: &Path) -> Result<RunSummary, ImplantError> {
    run_implant_with(spec, out, RunOptions::default())
}

/// Runs the whole experiment of `spec` into `out` (created if needed).
///
/// Every input is checked against the volume first ([`check_inputs`]),
/// then every part is computed in memory, and only then are the files
/// written: an error anywhere leaves nothing written (no STL, no CSV). A
/// design whose slices fail a plausibility check is such an error unless
/// `options.allow_partial`.
pub fn run_implant_with(
    spec: &ImplantSpec,
    out: &Path,
    options: RunOptions,
) -> Result<RunSummary, ImplantError> {
    let t0 = Instant::now();
    let volume = load_volume(&spec.volume)?;
    check_inputs(spec, &volume)?;
    let mut outputs = Outputs {
        files: Vec::new(),
        summary: RunSummary::default(),
        report: report_header(spec, &volume),
        timing: String::new(),
        verdicts: Vec::new(),
    };
    let header_len = outputs.report.len();
    let mut pipeline = None;
    let mut partial = None;
    if spec.run_defect {
        let (t, lacks) = run_defect(spec, &volume, (t0, options), &mut outputs)?;
        pipeline = Some(t);
        partial = lacks;
    }
    if !spec.run_defect {
        midline_line(spec, &volume, &mut outputs.report)?;
    }
    let mut rows_2d = Vec::new();
    if let Some(val) = &spec.validation {
        rows_2d = run_validation(spec, val, &volume, &mut outputs)?;
    }
    let mut rows_3d = Vec::new();
    if let Some(val) = &spec.validation_3d {
        rows_3d = run_validation_3d(spec, val, &volume, &mut outputs)?;
    }
    if let Some(f) = validation_figure_of(spec, &rows_2d, &rows_3d)? {
        outputs.add(&format!("{VALIDATION_FIGURE}.png"), f.png);
        outputs.add(&format!("{VALIDATION_FIGURE}.svg"), f.svg);
        outputs.report.push_str(&f.section);
    }
    if !outputs.verdicts.is_empty() {
        let verdicts = verdicts_csv(&outputs.verdicts);
        outputs.add("verdicts.csv", verdicts);
    }
    // The summary goes after the title, once every verdict and picture is
    // known.
    let mut report = std::mem::take(&mut outputs.report);
    let pictures: Vec<String> = outputs
        .files
        .iter()
        .map(|(name, _)| name.clone())
        .filter(|n| n.ends_with(".png"))
        .collect();
    let alpha = spec
        .validation
        .as_ref()
        .map(|v| v.alpha)
        .or(spec.validation_3d.as_ref().map(|v| v.alpha))
        .unwrap_or(crate::stats::DEFAULT_ALPHA);
    report.insert_str(
        header_len,
        &report_summary(&outputs.verdicts, &pictures, alpha),
    );
    if let Some(lacks) = partial {
        report.insert_str(0, &lacks);
    }
    outputs.add("report.md", report.into_bytes());
    if let Some(t) = pipeline {
        // The STL is written first; its write time completes load → STL.
        let _ = writeln!(outputs.timing, "pipeline_seconds_load_to_stl {t:.3}");
    }
    let timing = std::mem::take(&mut outputs.timing);
    outputs.add("timing.txt", timing.into_bytes());
    copy_spec(spec, &mut outputs);
    let stl_seconds = outputs.write_all(out)?;
    outputs.summary.pipeline_seconds = pipeline.map(|t| t + stl_seconds);
    Ok(outputs.summary)
}

/// The real defect: `implant.stl` (once the mesh passes its checks),
/// `metrics.csv`, the overlays, the 3D preview and the report's section.
/// A design with refused slices is refused
/// ([`ImplantError::Implausible`]) unless `options.allow_partial`, and then
/// written as [`PARTIAL_STL`]. Returns the seconds from `t0` (loading) to
/// the STL's bytes, and for a partial design the report's first line.
fn run_defect(
    spec: &ImplantSpec,
    volume: &Volume,
    (t0, options): (Instant, RunOptions),
    outputs: &mut Outputs,
) -> Result<(f64, Option<String>), ImplantError> {
    let cfg = &spec.defect_config;
    let mut solver = spec.method.solver(spec.seed);
    let implant = reconstruct_defect(volume, cfg, &mut *solver)?;
    let refused: Vec<(usize, String)> = implant
        .refused()
        .map(|s| (s.z, describe(&s.findings)))
        .collect();
    let total = implant.slices.len();
    let too_many = refused.len() as f64 > cfg.wall.checks.max_refused_fraction * total as f64;
    if !refused.is_empty() && (!options.allow_partial || too_many) {
        return Err(ImplantError::Implausible {
            slices: refused,
            total,
            allow_partial: options.allow_partial,
        });
    }
    let lacks = (!refused.is_empty()).then(|| partial_line(&refused, total));
    let (watertight, oriented) = (
        implant.mesh.is_watertight(),
        implant.mesh.is_consistently_oriented(),
    );
    if !(watertight && oriented) {
        return Err(ImplantError::BadMesh {
            vertices: implant.mesh.vertices.len(),
            triangles: implant.mesh.triangles.len(),
            watertight,
            oriented,
        });
    }
    let stl = stl_bytes(&implant.patient_mesh(), &implant.frame.stl_header());
    let name = if lacks.is_some() {
        PARTIAL_STL
    } else {
        "implant.stl"
    };
    outputs.add(name, stl);
    let secs = t0.elapsed().as_secs_f64();
    outputs.add("metrics.csv", defect_csv(&implant));
    let mut zs = spec.overlays.clone();
    zs.extend(slices_off_target(&implant));
    zs.sort_unstable();
    zs.dedup();
    for z in zs {
        if let Some(s) = implant.slices.iter().find(|s| s.z == z) {
            let png = overlay_png(volume, cfg, &implant, s)?;
            outputs.add(&format!("overlay_z{z:03}.png"), png);
        }
    }
    outputs.add("preview_3d.png", preview_png(volume, cfg, &implant)?);
    defect_report(&mut outputs.report, spec, &implant);
    Ok((secs, lacks))
}

/// The midline the validation cases are placed about, for a report
/// without a real defect (whose section states it otherwise).
fn midline_line(
    spec: &ImplantSpec,
    volume: &Volume,
    report: &mut String,
) -> Result<(), ImplantError> {
    if spec.validation.is_none() && spec.validation_3d.is_none() {
        return Ok(());
    }
    let (m, dice) = resolve_midline(volume, &spec.defect_config)?;
    let _ = writeln!(
        report,
        "Midline of the validation cases: x = {:.2} mm at y = {:.2} mm, tilt {:.2}°{}.\n",
        m.point.x,
        m.point.y,
        m.tilt_deg(),
        dice.map_or(" (given)".to_string(), |d| format!(
            " (estimated by reflection symmetry, Dice {d:.3})"
        ))
    );
    Ok(())
}

/// The first line of the report of a partial design: which slices the
/// STL lacks and why.
fn partial_line(refused: &[(usize, String)], total: usize) -> String {
    let zs: Vec<String> = refused.iter().map(|(z, _)| z.to_string()).collect();
    format!(
        "**Partial implant (`--allow-partial`): `{PARTIAL_STL}` lacks slices z = {} ({} of {total}), refused by the plausibility checks: {}.**\n\n",
        zs.join(", "),
        refused.len(),
        super::tables3d::refusals(refused)
    )
}

/// The artificial-defect validation: `validation.csv`, its time and the
/// report's section; returns its rows (for the figure).
fn run_validation(
    spec: &ImplantSpec,
    val: &ValidationSpec,
    volume: &Volume,
    outputs: &mut Outputs,
) -> Result<Vec<ValidationRow>, ImplantError> {
    let t1 = Instant::now();
    let rows = validation_rows(spec, val, volume)?;
    let _ = writeln!(
        outputs.timing,
        "validation_seconds {:.3}",
        t1.elapsed().as_secs_f64()
    );
    outputs.add("validation.csv", validation_csv(&rows));
    let verdicts = validation_report(&mut outputs.report, val, &rows, volume.spacing.z);
    outputs.verdicts.extend(verdicts);
    outputs.summary.validation_rows = rows.len();
    Ok(rows)
}

/// The 3D validation: `validation_3d.csv`, its time and the report's
/// section. A patch that cannot be cut or prepared is a failed row for
/// every method ([`ImplantError::CaseNotBuilt`]) and the run goes on.
/// Returns its rows (for the figure).
fn run_validation_3d(
    spec: &ImplantSpec,
    val: &Validation3dSpec,
    volume: &Volume,
    outputs: &mut Outputs,
) -> Result<Vec<Row3d>, ImplantError> {
    let t1 = Instant::now();
    let cfg = &spec.defect_config;
    let (midline, _) = resolve_midline(volume, cfg)?;
    let rule = RegionRule::of(volume, cfg.first_z, cfg.threshold, &midline);
    let mut rows = Vec::new();
    for &range in &val.ranges {
        for &position_deg in &val.positions {
            for &width_mm in &val.widths {
                let case = Case3d {
                    range,
                    position_deg,
                    width_mm,
                };
                let region = rule.region(0.5 * (range.0 + range.1) as f64, position_deg);
                match prepare_case_3d(volume, cfg, case, midline) {
                    Ok(p) => case_rows_3d(spec, val, (&p, region), &mut rows),
                    Err(e) => {
                        let e = std::sync::Arc::new(e);
                        let runs = method_runs(spec.seed, &val.methods, val.runs, |_, _| {
                            Err(ImplantError::CaseNotBuilt(e.clone()))
                        });
                        rows.extend(runs.into_iter().map(|(method, run, seed, metrics)| Row3d {
                            case,
                            method,
                            run,
                            seed,
                            metrics,
                            template_source: String::new(),
                            half_width_deg: f64::NAN,
                            region,
                        }));
                    }
                }
            }
        }
    }
    let _ = writeln!(
        outputs.timing,
        "validation_3d_seconds {:.3}",
        t1.elapsed().as_secs_f64()
    );
    outputs.add("validation_3d.csv", validation_3d_csv(&rows));
    let verdicts = validation_3d_report(&mut outputs.report, val, &rows);
    outputs.verdicts.extend(verdicts);
    outputs.summary.validation_3d_rows = rows.len();
    Ok(rows)
}

/// The rows of one prepared 3D case ([`method_runs`]).
fn case_rows_3d(
    spec: &ImplantSpec,
    val: &Validation3dSpec,
    (p, region): (&Prepared3d, Region),
    rows: &mut Vec<Row3d>,
) {
    let runs = method_runs(spec.seed, &val.methods, val.runs, |kind, solver| {
        // A design that fails is a case not built, as one that cannot be cut.
        evaluate_3d(p, kind, val.margin_mm, solver).map_err(|e| match e {
            ImplantError::CaseNotBuilt(_) => e,
            e => ImplantError::CaseNotBuilt(std::sync::Arc::new(e)),
        })
    });
    rows.extend(runs.into_iter().map(|(method, run, seed, metrics)| {
        Row3d {
            case: p.case,
            method,
            run,
            seed,
            template_source: metrics
                .as_ref()
                .map_or(String::new(), |m| m.template_source_name()),
            metrics,
            half_width_deg: p.half_width_deg,
            region,
        }
    }));
}

/// Every reconstruction of one validation case, in table order: the two
/// baselines (`template`, `straight`; deterministic, one run, seed 0),
/// then each curve-fit method (`curve:<name>`), `runs` seeded runs with
/// seeds `seed, seed + 1, …` for a stochastic one and one run otherwise.
/// `eval` reconstructs and scores the case with a wall kind and a solver;
/// returns (method, run, seed, its result) per reconstruction.
fn method_runs<T>(
    seed: u64,
    methods: &[Method],
    runs: usize,
    mut eval: impl FnMut(WallKind, &mut dyn SegmentSolver) -> T,
) -> Vec<(String, usize, u64, T)> {
    let mut out = Vec::new();
    for kind in [WallKind::Template, WallKind::Straight] {
        let res = eval(kind, &mut LmSolver::default());
        out.push((kind.name().to_string(), 0, 0, res));
    }
    for m in methods {
        let stochastic = m.is_stochastic();
        for run in 0..if stochastic { runs } else { 1 } {
            let seed = if stochastic { seed + run as u64 } else { 0 };
            let mut solver = m.solver(seed);
            let res = eval(WallKind::CurveFit, &mut *solver);
            out.push((format!("curve:{}", m.name()), run, seed, res));
        }
    }
    out
}

/// Every validation row: for each slice × position × width, the case cut
/// out of the slice and reconstructed by every method ([`case_rows`]); a
/// case that cannot be cut is a failed row for every method
/// ([`CaseError::NotBuilt`], its reason in the `error` column) and the run
/// goes on.
fn validation_rows(
    spec: &ImplantSpec,
    val: &ValidationSpec,
    volume: &Volume,
) -> Result<Vec<ValidationRow>, ImplantError> {
    let cfg = &spec.defect_config;
    let (midline, _) = resolve_midline(volume, cfg)?;
    let rule = RegionRule::of(volume, cfg.first_z, cfg.threshold, &midline);
    let mut rows = Vec::new();
    for &z in &val.slices {
        let index = slice_index(cfg, volume, z, "validation slice")?;
        for &pos in &val.positions {
            for &w in &val.widths {
                let case = Case {
                    index,
                    position_deg: pos,
                    width_mm: w,
                };
                let region = rule.region(z as f64, pos);
                match prepare_case(volume, case, midline, cfg.threshold) {
                    Ok(prepared) => case_rows(spec, val, (&prepared, region), z, &mut rows),
                    Err(e) => {
                        let e = std::sync::Arc::new(e);
                        let runs = method_runs(spec.seed, &val.methods, val.runs, |_, _| ());
                        rows.extend(runs.into_iter().map(|(method, run, seed, ())| {
                            ValidationRow {
                                case,
                                z,
                                method,
                                run,
                                seed,
                                metrics: Err(CaseError::NotBuilt(e.clone())),
                                fit_error: f64::NAN,
                                join_deg: (f64::NAN, f64::NAN),
                                template_source: None,
                                checks: CheckValues::default(),
                                findings: Vec::new(),
                                half_width_deg: f64::NAN,
                                region,
                            }
                        }));
                    }
                }
            }
        }
    }
    Ok(rows)
}

/// The rows of one prepared case (slice `z`, [`method_runs`]).
fn case_rows(
    spec: &ImplantSpec,
    val: &ValidationSpec,
    (prepared, region): (&PreparedCase, Region),
    z: usize,
    rows: &mut Vec<ValidationRow>,
) {
    let wall = &spec.defect_config.wall;
    let template_source = Some(case_template_source(prepared, wall));
    let runs = method_runs(spec.seed, &val.methods, val.runs, |kind, solver| {
        evaluate(prepared, kind, wall, val.margin_mm, solver)
    });
    rows.extend(
        runs.into_iter()
            .map(|(method, run, seed, e)| ValidationRow {
                case: prepared.case,
                z,
                method,
                run,
                seed,
                metrics: e.metrics,
                fit_error: e.fit_error,
                join_deg: e.join_deg,
                template_source,
                checks: e.checks,
                findings: e.findings,
                half_width_deg: prepared.half_width_deg,
                region,
            }),
    );
}

/// Queues a copy of the spec file for the output directory (skipped when
/// it cannot be read again).
fn copy_spec(spec: &ImplantSpec, outputs: &mut Outputs) {
    if let Ok(text) = std::fs::read(&spec.path) {
        let name = spec
            .path
            .file_name()
            .map_or("spec.toml".into(), |n| n.to_string_lossy().into_owned());
        outputs.add(&name, text);
    }
}
