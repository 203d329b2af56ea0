//! The chapter-6 experiment: the real defect to `implant.stl`, per-slice
//! metrics and overlays, a 3D preview, and the artificial-defect validation
//! with its statistics against the baselines (`metabezier implant`).
//!
//! Every output is built in memory and written atomically
//! ([`crate::files::write_atomic`]); the STL is written only once the mesh
//! is checked watertight and consistently oriented. CSV files hold no wall
//! times (they go to `timing.txt`), so they are byte-identical for the same
//! spec and seed.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::pipeline::{reconstruct_defect, resolve_midline, DefectConfig, Implant, ImplantError};
use super::spec::ImplantSpec;
use super::validation::{evaluate, prepare_case, Case, ValidationRow};
use super::wall::{envelope_radius, WallKind};
use crate::ct::{
    bone_loops, bone_mask_slice, encode_png, loft, mesh_view_rgb, read_dicom_dir, read_inv3,
    slice_overlay_png, stl_bytes, Mesh, Overlay, Polyline, View, Volume, Window,
};
use crate::files::{csv_bytes, fmt_real, write_atomic, IoError};
use crate::fit::LmSolver;
use crate::geometry::Point;
use crate::markdown::{self, Alignment};
use crate::stats::{holm_bonferroni, median, wilcoxon, Alternative};

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
    /// Seconds for the real-defect pipeline (load → STL).
    pub pipeline_seconds: Option<f64>,
    /// Validation rows.
    pub validation_rows: usize,
}

fn write(
    out: &Path,
    name: &str,
    bytes: &[u8],
    summary: &mut RunSummary,
) -> Result<(), ImplantError> {
    let p = out.join(name);
    write_atomic(&p, bytes)?;
    summary.files.push(p);
    Ok(())
}

fn r(x: f64) -> String {
    fmt_real(x)
}

/// Runs the whole experiment of `spec` into `out` (created if needed).
pub fn run_implant(spec: &ImplantSpec, out: &Path) -> Result<RunSummary, ImplantError> {
    std::fs::create_dir_all(out)
        .map_err(|e| IoError::new("create the output directory", out, e))?;
    let mut summary = RunSummary::default();
    let mut timing = String::new();
    let t0 = Instant::now();
    let volume = load_volume(&spec.volume)?;
    let mut report = String::new();
    let _ = writeln!(report, "# Chapter 6: cranial implant\n");
    let _ =
        writeln!(
        report,
        "Spec: `{}`; volume `{}` ({}×{}×{} voxels, spacing {} × {} × {} mm; slice 0 is z = {}).\n",
        spec.path.file_name().map_or(String::new(), |n| n.to_string_lossy().into()),
        spec.volume_label,
        volume.nx,
        volume.ny,
        volume.nz,
        volume.spacing.x,
        volume.spacing.y,
        volume.spacing.z,
        spec.defect_config.first_z
    );
    let cfg = &spec.defect_config;
    if spec.run_defect {
        let mut solver = spec.method.solver(spec.seed);
        let implant = reconstruct_defect(&volume, cfg, &mut *solver)?;
        if !(implant.mesh.is_watertight() && implant.mesh.is_consistently_oriented()) {
            return Err(ImplantError::BadMesh);
        }
        let stl = stl_bytes(&implant.mesh, "metabezier chapter-6 implant, mm");
        write(out, "implant.stl", &stl, &mut summary)?;
        let secs = t0.elapsed().as_secs_f64();
        summary.pipeline_seconds = Some(secs);
        let _ = writeln!(timing, "pipeline_seconds_load_to_stl {secs:.3}");
        write(out, "metrics.csv", &defect_csv(&implant), &mut summary)?;
        for &z in &spec.overlays {
            if let Some(s) = implant.slices.iter().find(|s| s.z == z) {
                let png = overlay_png(&volume, cfg, s)?;
                write(out, &format!("overlay_z{z:03}.png"), &png, &mut summary)?;
            }
        }
        let preview = preview_png(&volume, cfg, &implant)?;
        write(out, "preview_3d.png", &preview, &mut summary)?;
        defect_report(&mut report, spec, &implant);
    }
    if let Some(val) = &spec.validation {
        let t1 = Instant::now();
        let (mx, _) = resolve_midline(&volume, cfg)?;
        let mut rows = Vec::new();
        for &z in &val.slices {
            let index = z
                .checked_sub(cfg.first_z)
                .filter(|&k| k < volume.nz)
                .ok_or(ImplantError::SliceOutside {
                    what: "validation slice",
                    z,
                    first: cfg.first_z,
                    last: cfg.first_z + volume.nz - 1,
                })?;
            for &pos in &val.positions {
                for &w in &val.widths {
                    let case = Case {
                        index,
                        position_deg: pos,
                        width_mm: w,
                    };
                    let prepared = prepare_case(&volume, case, mx, cfg.threshold)
                        .map_err(|source| ImplantError::Slice { z, source })?;
                    let push = |rows: &mut Vec<ValidationRow>,
                                method: String,
                                run,
                                seed,
                                res: (_, f64, (f64, f64))| {
                        rows.push(ValidationRow {
                            case,
                            z,
                            method,
                            run,
                            seed,
                            metrics: res.0,
                            fit_error: res.1,
                            join_deg: res.2,
                        })
                    };
                    for kind in [WallKind::Template, WallKind::Straight] {
                        let res = evaluate(
                            &prepared,
                            kind,
                            &cfg.wall,
                            val.margin_mm,
                            &mut LmSolver::default(),
                        );
                        push(&mut rows, kind.name().to_string(), 0, 0, res);
                    }
                    for m in &val.methods {
                        let runs = if m.is_stochastic() { val.runs } else { 1 };
                        for run in 0..runs {
                            let seed = if m.is_stochastic() {
                                spec.seed + run as u64
                            } else {
                                0
                            };
                            let mut solver = m.solver(seed);
                            let res = evaluate(
                                &prepared,
                                WallKind::CurveFit,
                                &cfg.wall,
                                val.margin_mm,
                                &mut *solver,
                            );
                            push(&mut rows, format!("curve:{}", m.name()), run, seed, res);
                        }
                    }
                }
            }
        }
        let _ = writeln!(
            timing,
            "validation_seconds {:.3}",
            t1.elapsed().as_secs_f64()
        );
        write(out, "validation.csv", &validation_csv(&rows), &mut summary)?;
        validation_report(&mut report, val, &rows)?;
        summary.validation_rows = rows.len();
    }
    write(out, "report.md", report.as_bytes(), &mut summary)?;
    write(out, "timing.txt", timing.as_bytes(), &mut summary)?;
    if let Ok(text) = std::fs::read(&spec.path) {
        let name = spec
            .path
            .file_name()
            .map_or("spec.toml".into(), |n| n.to_string_lossy().into_owned());
        write(out, &name, &text, &mut summary)?;
    }
    Ok(summary)
}

/// `metrics.csv`: one row per reconstructed slice of the real defect.
pub fn defect_csv(implant: &Implant) -> Vec<u8> {
    let header = [
        "z",
        "a_x_mm",
        "a_y_mm",
        "b_x_mm",
        "b_y_mm",
        "c_x_mm",
        "c_y_mm",
        "d_x_mm",
        "d_y_mm",
        "midline_x_mm",
        "width_mm",
        "thickness_a_mm",
        "thickness_b_mm",
        "fit_error_mm2",
        "fit_rms_mm",
        "join_a_deg",
        "join_b_deg",
        "evaluations",
        "outer_length_mm",
        "section_area_mm2",
        "template_dev_mean_mm",
        "template_dev_max_mm",
    ];
    let rows = implant.slices.iter().map(|s| {
        let w = &s.wall;
        let (ja, jb) = w.join_angles_deg();
        let n = w.template.points.len() as f64;
        let dev = crate::ct::contour_deviation(&w.outer, &w.template, 0.25).ok();
        vec![
            s.z.to_string(),
            r(w.a.x),
            r(w.a.y),
            r(w.b.x),
            r(w.b.y),
            r(w.c.x),
            r(w.c.y),
            r(w.d.x),
            r(w.d.y),
            r(s.midline_x),
            r(w.a.distance(w.b)),
            r(w.thickness.0),
            r(w.thickness.1),
            r(w.fit_error),
            r((w.fit_error / n).sqrt()),
            r(ja),
            r(jb),
            w.evaluations.to_string(),
            r(w.outer.length()),
            r(w.section.signed_area().abs()),
            dev.map_or("NaN".into(), |d| r(d.mean)),
            dev.map_or("NaN".into(), |d| r(d.max)),
        ]
    });
    csv_bytes(&header, rows)
}

/// The bone-window overlay of one reconstructed slice: outer table (green),
/// inner table (blue), mirrored template (magenta), outer wall (red), inner
/// wall (orange), A, B, C, D and `M_x`.
pub fn overlay_png(
    volume: &Volume,
    cfg: &DefectConfig,
    s: &super::pipeline::SliceResult,
) -> Result<Vec<u8>, ImplantError> {
    let slice = volume.slice(s.z - cfg.first_z);
    let w = &s.wall;
    let ov = Overlay {
        polylines: vec![
            (s.outer.clone(), [40, 200, 40]),
            (s.inner.clone(), [60, 140, 255]),
            (w.template.clone(), [255, 0, 255]),
            (w.outer.clone(), [255, 30, 30]),
            (w.inner.clone(), [255, 170, 0]),
        ],
        points: vec![
            ("A".into(), w.a, [255, 255, 0]),
            ("B".into(), w.b, [255, 255, 0]),
            ("C".into(), w.c, [0, 255, 255]),
            ("D".into(), w.d, [0, 255, 255]),
        ],
        vertical_lines: vec![(s.midline_x, [230, 230, 230])],
    };
    Ok(slice_overlay_png(&slice, Window::BONE, 3, &ov)?)
}

/// A closed proxy of the skull surface: on every slice from `z0` to `z1`
/// (volume indices), the outer envelope over 180 rays about `(M_x, ȳ)`
/// (rays that miss keep the previous radius), lofted. On the slices listed
/// in `recess` (volume index, first and last angle in radians), the rays
/// between the two angles are pulled in to 80 % so that an implant there
/// shows in the preview.
pub fn skull_proxy(
    volume: &Volume,
    threshold: i16,
    midline_x: f64,
    z0: usize,
    z1: usize,
    recess: &[(usize, f64, f64)],
) -> Result<Mesh, ImplantError> {
    let mut sections = Vec::new();
    let mut zs = Vec::new();
    for k in z0..=z1.min(volume.nz - 1) {
        let slice = volume.slice(k);
        let Ok(mask) = bone_mask_slice(&slice, threshold) else {
            continue;
        };
        let loops = bone_loops(&slice, &mask, threshold);
        let Some(outer) = loops.iter().find(|l| l.signed_area() > 0.0) else {
            continue;
        };
        let o = Point::new(midline_x, outer.vertex_mean().y);
        let mut last = None;
        let mut ring = Vec::new();
        for j in 0..180 {
            let t = j as f64 * std::f64::consts::TAU / 180.0;
            let rr = envelope_radius(&[outer], o, t).or(last);
            if let Some(mut rr) = rr {
                last = Some(rr);
                let tau = std::f64::consts::TAU;
                if recess.iter().any(|&(kk, t1, t2)| {
                    let w = (t2 - t1).rem_euclid(tau);
                    let (lo, w) = if w > std::f64::consts::PI {
                        (t2, tau - w)
                    } else {
                        (t1, w)
                    };
                    kk == k && (t - lo).rem_euclid(tau) <= w
                }) {
                    rr *= 0.8;
                }
                ring.push(o + Point::new(t.cos(), t.sin()) * rr);
            }
        }
        if ring.len() >= 3 {
            sections.push(Polyline::closed(ring));
            zs.push(k as f64 * volume.spacing.z);
        }
    }
    Ok(loft(&sections, &zs, 180)?)
}

/// Three shaded orthographic views (from the defect side, from the front
/// and from above) of the implant (red) on the skull-surface proxy (grey).
pub fn preview_png(
    volume: &Volume,
    cfg: &DefectConfig,
    implant: &Implant,
) -> Result<Vec<u8>, ImplantError> {
    let k0 = implant.slices.first().map_or(0, |s| s.z - cfg.first_z);
    let k1 = implant.slices.last().map_or(0, |s| s.z - cfg.first_z);
    let recess: Vec<(usize, f64, f64)> = implant
        .slices
        .iter()
        .map(|s| {
            let k = s.z - cfg.first_z;
            let o = Point::new(implant.midline_x, s.outer.vertex_mean().y);
            let ang = |p: Point| (p.y - o.y).atan2(p.x - o.x);
            (k, ang(s.wall.a), ang(s.wall.b))
        })
        .collect();
    let skull = skull_proxy(
        volume,
        cfg.threshold,
        implant.midline_x,
        k0.saturating_sub(8),
        k1 + 8,
        &recess,
    )?;
    // The defect's side: the sign of its x relative to the midline; the
    // image's y grows downwards, so +y is the face here (see overlays).
    let side = implant
        .slices
        .first()
        .map_or(-1.0, |s| (s.wall.a.x - implant.midline_x).signum());
    let views = [
        View {
            direction: [-side, -0.6, 0.0],
            up: [0.0, 0.0, 1.0],
        },
        View {
            direction: [0.0, -1.0, 0.0],
            up: [0.0, 0.0, 1.0],
        },
        View {
            direction: [0.0, 0.0, -1.0],
            up: [0.0, -1.0, 0.0],
        },
    ];
    let size = 360u32;
    let imgs: Vec<Vec<u8>> = views
        .iter()
        .map(|v| {
            mesh_view_rgb(
                &[(&skull, [200, 200, 200]), (&implant.mesh, [230, 40, 40])],
                *v,
                size,
            )
        })
        .collect();
    let w = size as usize * imgs.len();
    let mut rgb = vec![255u8; w * size as usize * 3];
    for (i, img) in imgs.iter().enumerate() {
        for y in 0..size as usize {
            let src = &img[y * size as usize * 3..(y + 1) * size as usize * 3];
            let dst = (y * w + i * size as usize) * 3;
            rgb[dst..dst + src.len()].copy_from_slice(src);
        }
    }
    Ok(encode_png(&rgb, w as u32, size)?)
}

fn defect_report(report: &mut String, spec: &ImplantSpec, implant: &Implant) {
    let n = implant.slices.len();
    let _ = writeln!(report, "## Real defect\n");
    let _ = writeln!(
        report,
        "{n} slices z = {}..={}; method `{}`, function `{}`, continuity `{}`, budget {} evaluations per slice, seed {}.",
        implant.slices[0].z,
        implant.slices[n - 1].z,
        spec.method.name(),
        spec.defect_config.wall.function.name(),
        spec.defect_config.wall.continuity.name(),
        spec.defect_config.wall.budget,
        spec.seed
    );
    let _ = writeln!(
        report,
        "M_x = {:.2} mm{}.\n",
        implant.midline_x,
        implant
            .midline_dice
            .map_or(" (given)".to_string(), |d| format!(
                " (estimated, reflection Dice {d:.3})"
            ))
    );
    let _ = writeln!(
        report,
        "Mesh: {} vertices, {} triangles, watertight {}, consistently oriented {}, volume {:.0} mm³; voxelised implant {} voxels.\n",
        implant.mesh.vertices.len(),
        implant.mesh.triangles.len(),
        implant.mesh.is_watertight(),
        implant.mesh.is_consistently_oriented(),
        implant.mesh.signed_volume(),
        implant.mask.count()
    );
    let header = [
        "z",
        "width mm",
        "t_A mm",
        "t_B mm",
        "fit RMS mm",
        "join A °",
        "join B °",
    ]
    .map(String::from);
    let rows: Vec<Vec<String>> = implant
        .slices
        .iter()
        .map(|s| {
            let w = &s.wall;
            let (ja, jb) = w.join_angles_deg();
            let rms = (w.fit_error / w.template.points.len() as f64).sqrt();
            vec![
                s.z.to_string(),
                format!("{:.1}", w.a.distance(w.b)),
                format!("{:.1}", w.thickness.0),
                format!("{:.1}", w.thickness.1),
                format!("{rms:.2}"),
                format!("{ja:.1e}"),
                format!("{jb:.1e}"),
            ]
        })
        .collect();
    report.push_str(&markdown::table(&header, &rows, Alignment::Unmarked));
    let _ = writeln!(report);
}

/// `validation.csv`: one row per case × method × run.
pub fn validation_csv(rows: &[ValidationRow]) -> Vec<u8> {
    let header = [
        "z",
        "position_deg",
        "width_mm",
        "method",
        "run",
        "seed",
        "status",
        "dice",
        "boundary_dice",
        "hd95_mm",
        "dev_mean_mm",
        "dev_max_mm",
        "fit_error_mm2",
        "join_a_deg",
        "join_b_deg",
        "error",
    ];
    let rows = rows.iter().map(|row| {
        let mut v = vec![
            row.z.to_string(),
            r(row.case.position_deg),
            r(row.case.width_mm),
            row.method.clone(),
            row.run.to_string(),
            row.seed.to_string(),
        ];
        match &row.metrics {
            Ok(m) => {
                v.push("ok".into());
                v.extend([m.dice, m.boundary_dice, m.hd95, m.dev_mean, m.dev_max].map(r));
                v.extend([
                    r(row.fit_error),
                    r(row.join_deg.0),
                    r(row.join_deg.1),
                    String::new(),
                ]);
            }
            Err(e) => {
                v.push("error".into());
                v.extend(std::iter::repeat_n(String::new(), 8));
                v.push(e.to_string());
            }
        }
        v
    });
    csv_bytes(&header, rows)
}

/// Metric names, accessors and whether larger is better.
type MetricFn = fn(&super::validation::CaseMetrics) -> f64;
const METRICS: [(&str, MetricFn, bool); 5] = [
    ("Dice", |m| m.dice, true),
    ("boundary Dice", |m| m.boundary_dice, true),
    ("HD95 mm", |m| m.hd95, false),
    ("mean deviation mm", |m| m.dev_mean, false),
    ("max deviation mm", |m| m.dev_max, false),
];

fn validation_report(
    report: &mut String,
    val: &super::spec::ValidationSpec,
    rows: &[ValidationRow],
) -> Result<(), ImplantError> {
    let mut methods: Vec<String> = vec!["template".into(), "straight".into()];
    methods.extend(val.methods.iter().map(|m| format!("curve:{}", m.name())));
    let failed = rows.iter().filter(|r| r.metrics.is_err()).count();
    let _ = writeln!(
        report,
        "## Validation on perfect data (artificial defects)\n"
    );
    let _ = writeln!(
        report,
        "Slices {:?}, positions {:?}°, widths {:?} mm; {} runs per stochastic method; boundary Dice within {} mm. {} rows, {failed} failed (see `validation.csv`, column `error`).\n",
        val.slices, val.positions, val.widths, val.runs, val.margin_mm, rows.len()
    );
    // Median of each metric by method × width.
    for (name, f, _) in METRICS {
        let _ = writeln!(report, "### {name} (median over cases and runs)\n");
        let mut header = vec!["method".to_string()];
        header.extend(val.widths.iter().map(|w| format!("{w} mm")));
        let table: Vec<Vec<String>> = methods
            .iter()
            .map(|m| {
                let mut line = vec![m.clone()];
                for &w in &val.widths {
                    let v: Vec<f64> = rows
                        .iter()
                        .filter(|r| &r.method == m && r.case.width_mm == w)
                        .filter_map(|r| r.metrics.as_ref().ok().map(f))
                        .collect();
                    line.push(format!("{:.3}", median(&v)));
                }
                line
            })
            .collect();
        report.push_str(&markdown::table(&header, &table, Alignment::Unmarked));
        let _ = writeln!(report);
    }
    // Paired tests: per case, the curve method's median over runs against
    // each baseline.
    let _ = writeln!(
        report,
        "### What the curve fit adds (Wilcoxon signed-rank, paired by case)\n"
    );
    let _ = writeln!(
        report,
        "Per case the curve fit's median over its runs is paired with the baseline; two-sided Wilcoxon signed-rank test (src/stats), Holm-corrected over all rows of this table. `better` counts cases where the curve fit is strictly better.\n"
    );
    let mut keys: Vec<(usize, u64, u64)> = rows
        .iter()
        .map(|r| {
            (
                r.z,
                r.case.position_deg.to_bits(),
                r.case.width_mm.to_bits(),
            )
        })
        .collect();
    keys.sort();
    keys.dedup();
    let mut lines = Vec::new();
    let mut ps = Vec::new();
    for cm in val.methods.iter().map(|m| format!("curve:{}", m.name())) {
        for base in ["template", "straight"] {
            for (name, f, larger_better) in METRICS {
                let (mut xs, mut ys) = (Vec::new(), Vec::new());
                for &(z, p, w) in &keys {
                    let of = |m: &str| -> Vec<f64> {
                        rows.iter()
                            .filter(|r| {
                                r.method == m
                                    && r.z == z
                                    && r.case.position_deg.to_bits() == p
                                    && r.case.width_mm.to_bits() == w
                            })
                            .filter_map(|r| r.metrics.as_ref().ok().map(f))
                            .filter(|v| v.is_finite())
                            .collect()
                    };
                    let (c, b) = (of(&cm), of(base));
                    if !c.is_empty() && !b.is_empty() {
                        xs.push(median(&c));
                        ys.push(median(&b));
                    }
                }
                let better = xs
                    .iter()
                    .zip(&ys)
                    .filter(|(x, y)| if larger_better { x > y } else { x < y })
                    .count();
                let p = wilcoxon(&xs, &ys, Alternative::TwoSided)
                    .map(|t| t.p_value)
                    .unwrap_or(f64::NAN);
                let diffs: Vec<f64> = xs.iter().zip(&ys).map(|(x, y)| x - y).collect();
                ps.push(p);
                lines.push((
                    cm.clone(),
                    base,
                    name,
                    xs.len(),
                    median(&xs),
                    median(&ys),
                    median(&diffs),
                    better,
                    p,
                ));
            }
        }
    }
    let finite: Vec<f64> = ps
        .iter()
        .map(|p| if p.is_finite() { *p } else { 1.0 })
        .collect();
    let holm = holm_bonferroni(&finite)?;
    let header = [
        "curve method",
        "baseline",
        "metric",
        "cases",
        "median curve",
        "median baseline",
        "median difference",
        "better",
        "p",
        "p (Holm)",
    ]
    .map(String::from);
    let table: Vec<Vec<String>> = lines
        .iter()
        .zip(holm)
        .map(|(l, ph)| {
            vec![
                l.0.clone(),
                l.1.to_string(),
                l.2.to_string(),
                l.3.to_string(),
                format!("{:.3}", l.4),
                format!("{:.3}", l.5),
                format!("{:+.3}", l.6),
                format!("{}/{}", l.7, l.3),
                format!("{:.2e}", l.8),
                format!("{ph:.2e}"),
            ]
        })
        .collect();
    report.push_str(&markdown::table(&header, &table, Alignment::Unmarked));
    let _ = writeln!(report);
    // The join quality of the fitted curves.
    let joins: Vec<f64> = rows
        .iter()
        .filter(|r| r.method.starts_with("curve:") && r.metrics.is_ok())
        .flat_map(|r| [r.join_deg.0, r.join_deg.1])
        .collect();
    if !joins.is_empty() {
        let max = joins.iter().copied().fold(0.0, f64::max);
        let _ = writeln!(
            report,
            "Fitted walls: join angle with the intact contour median {:.1e}°, max {:.1e}° (G¹ is built into the decision variables).\n",
            median(&joins),
            max
        );
    }
    Ok(())
}
