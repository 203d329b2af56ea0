//! The chapter-6 outputs as bytes: the sections of `report.md`, the CSV
//! tables `metrics.csv` and `validation.csv`, the slice overlays and the 3D
//! preview (see [`super::run`] for the driver that writes them).
//!
//! Markdown tables go through [`crate::markdown::table`]; CSV files hold no
//! wall times, so they are byte-identical for the same spec and seed.

use std::fmt::Write as _;

use super::pipeline::{DefectConfig, Implant, ImplantError, SliceResult};
use super::spec::{ImplantSpec, ValidationSpec};
use super::validation::{CaseMetrics, ValidationRow};
use super::wall::envelope_radius;
use crate::ct::{
    bone_loops, bone_mask_slice, encode_png, loft, mesh_view_rgb, slice_overlay_png, Mesh, Overlay,
    Polyline, View, Volume, Window,
};
use crate::files::{csv_bytes, fmt_real};
use crate::geometry::Point;
use crate::markdown::{self, Alignment};
use crate::stats::{holm_bonferroni, median, wilcoxon, Alternative};

fn r(x: f64) -> String {
    fmt_real(x)
}

/// The title of `report.md` and the line naming the spec and the volume.
pub fn report_header(spec: &ImplantSpec, volume: &Volume) -> String {
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
    report
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
    s: &SliceResult,
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

/// Whether the ray at angle `t` on slice `k` lies in one of the `recess`
/// wedges (volume index, first and last angle in radians; the wedge is the
/// shorter way round between them).
fn in_recess(recess: &[(usize, f64, f64)], k: usize, t: f64) -> bool {
    let tau = std::f64::consts::TAU;
    recess.iter().any(|&(kk, t1, t2)| {
        let w = (t2 - t1).rem_euclid(tau);
        let (lo, w) = if w > std::f64::consts::PI {
            (t2, tau - w)
        } else {
            (t1, w)
        };
        kk == k && (t - lo).rem_euclid(tau) <= w
    })
}

/// The outer envelope of `outer` over 180 rays about `o` on slice `k`
/// (rays that miss keep the previous radius; rays in a `recess` wedge are
/// pulled in to 80 %).
fn envelope_ring(outer: &Polyline, o: Point, k: usize, recess: &[(usize, f64, f64)]) -> Vec<Point> {
    let mut last = None;
    let mut ring = Vec::new();
    for j in 0..180 {
        let t = j as f64 * std::f64::consts::TAU / 180.0;
        let rr = envelope_radius(&[outer], o, t).or(last);
        if let Some(mut rr) = rr {
            last = Some(rr);
            if in_recess(recess, k, t) {
                rr *= 0.8;
            }
            ring.push(o + Point::new(t.cos(), t.sin()) * rr);
        }
    }
    ring
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
        let ring = envelope_ring(outer, o, k, recess);
        if ring.len() >= 3 {
            sections.push(Polyline::closed(ring));
            zs.push(k as f64 * volume.spacing.z);
        }
    }
    Ok(loft(&sections, &zs, 180)?)
}

/// Per implant slice, its volume index and the polar angles of A and B
/// about `(M_x, ȳ)`: where the skull proxy is recessed.
fn implant_recess(cfg: &DefectConfig, implant: &Implant) -> Vec<(usize, f64, f64)> {
    implant
        .slices
        .iter()
        .map(|s| {
            let k = s.z - cfg.first_z;
            let o = Point::new(implant.midline_x, s.outer.vertex_mean().y);
            let ang = |p: Point| (p.y - o.y).atan2(p.x - o.x);
            (k, ang(s.wall.a), ang(s.wall.b))
        })
        .collect()
}

/// Square RGB images of side `size` placed side by side.
fn side_by_side(imgs: &[Vec<u8>], size: usize) -> (Vec<u8>, usize) {
    let w = size * imgs.len();
    let mut rgb = vec![255u8; w * size * 3];
    for (i, img) in imgs.iter().enumerate() {
        for y in 0..size {
            let src = &img[y * size * 3..(y + 1) * size * 3];
            let dst = (y * w + i * size) * 3;
            rgb[dst..dst + src.len()].copy_from_slice(src);
        }
    }
    (rgb, w)
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
    let skull = skull_proxy(
        volume,
        cfg.threshold,
        implant.midline_x,
        k0.saturating_sub(8),
        k1 + 8,
        &implant_recess(cfg, implant),
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
    let (rgb, w) = side_by_side(&imgs, size as usize);
    Ok(encode_png(&rgb, w as u32, size)?)
}

/// The "Real defect" section of `report.md`: the run's settings, the
/// midline, the mesh checks and one table row per slice.
pub fn defect_report(report: &mut String, spec: &ImplantSpec, implant: &Implant) {
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
    report.push_str(&slice_table(implant));
    let _ = writeln!(report);
}

/// The per-slice table of the real defect: width, thickness, fit RMS and
/// join angles.
fn slice_table(implant: &Implant) -> String {
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
    markdown::table(&header, &rows, Alignment::Unmarked)
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

/// A metric's accessor.
type MetricFn = fn(&CaseMetrics) -> f64;

/// One validation metric: its name in tables, its accessor, and whether
/// larger is better.
type Metric = (&'static str, MetricFn, bool);

/// The validation metrics, in table order.
const METRICS: [Metric; 5] = [
    ("Dice", |m| m.dice, true),
    ("boundary Dice", |m| m.boundary_dice, true),
    ("HD95 mm", |m| m.hd95, false),
    ("mean deviation mm", |m| m.dev_mean, false),
    ("max deviation mm", |m| m.dev_max, false),
];

/// The "Validation on perfect data" section of `report.md`: the cases, the
/// median of every metric by method and width, the paired tests of the
/// curve fit against the baselines, and the join quality of the fits.
pub fn validation_report(
    report: &mut String,
    val: &ValidationSpec,
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
    for metric in METRICS {
        median_table(report, metric, val, &methods, rows);
    }
    paired_tests(report, val, rows)?;
    join_summary(report, rows);
    Ok(())
}

/// The median of one metric over cases and runs, by method × width.
fn median_table(
    report: &mut String,
    (name, f, _): Metric,
    val: &ValidationSpec,
    methods: &[String],
    rows: &[ValidationRow],
) {
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

/// A validation case as a sortable key: slice, position and width bits.
type CaseKey = (usize, u64, u64);

/// The distinct cases of `rows`, sorted.
fn case_keys(rows: &[ValidationRow]) -> Vec<CaseKey> {
    let mut keys: Vec<CaseKey> = rows
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
    keys
}

/// One row of the paired-test table: a curve method against a baseline on
/// one metric.
struct PairedTest {
    /// `curve:<method>`.
    curve: String,
    /// `template` or `straight`.
    baseline: &'static str,
    /// The metric's name.
    metric: &'static str,
    /// Cases where both have a finite value.
    cases: usize,
    /// Median of the curve method's per-case medians.
    median_curve: f64,
    /// Median of the baseline's per-case medians.
    median_baseline: f64,
    /// Median of the per-case differences (curve − baseline).
    median_difference: f64,
    /// Cases where the curve method is strictly better.
    better: usize,
    /// Two-sided Wilcoxon signed-rank p-value (NaN when undefined).
    p: f64,
}

/// Pairs, per case, the median over runs of `curve` and of `baseline` on
/// `metric`, and tests the difference.
fn paired_test(
    rows: &[ValidationRow],
    keys: &[CaseKey],
    curve: &str,
    baseline: &'static str,
    (metric, f, larger_better): Metric,
) -> PairedTest {
    let (mut xs, mut ys) = (Vec::new(), Vec::new());
    for &(z, p, w) in keys {
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
        let (c, b) = (of(curve), of(baseline));
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
    PairedTest {
        curve: curve.to_string(),
        baseline,
        metric,
        cases: xs.len(),
        median_curve: median(&xs),
        median_baseline: median(&ys),
        median_difference: median(&diffs),
        better,
        p,
    }
}

/// The paired tests of every curve method against both baselines on every
/// metric, Holm-corrected over the whole table.
fn paired_tests(
    report: &mut String,
    val: &ValidationSpec,
    rows: &[ValidationRow],
) -> Result<(), ImplantError> {
    let _ = writeln!(
        report,
        "### What the curve fit adds (Wilcoxon signed-rank, paired by case)\n"
    );
    let _ = writeln!(
        report,
        "Per case the curve fit's median over its runs is paired with the baseline; two-sided Wilcoxon signed-rank test (src/stats), Holm-corrected over all rows of this table. `better` counts cases where the curve fit is strictly better.\n"
    );
    let keys = case_keys(rows);
    let mut tests = Vec::new();
    for cm in val.methods.iter().map(|m| format!("curve:{}", m.name())) {
        for base in ["template", "straight"] {
            for metric in METRICS {
                tests.push(paired_test(rows, &keys, &cm, base, metric));
            }
        }
    }
    let finite: Vec<f64> = tests
        .iter()
        .map(|t| if t.p.is_finite() { t.p } else { 1.0 })
        .collect();
    let holm = holm_bonferroni(&finite)?;
    report.push_str(&paired_table(&tests, &holm));
    let _ = writeln!(report);
    Ok(())
}

/// The markdown table of the paired tests with their Holm-corrected p.
fn paired_table(tests: &[PairedTest], holm: &[f64]) -> String {
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
    let table: Vec<Vec<String>> = tests
        .iter()
        .zip(holm)
        .map(|(t, ph)| {
            vec![
                t.curve.clone(),
                t.baseline.to_string(),
                t.metric.to_string(),
                t.cases.to_string(),
                format!("{:.3}", t.median_curve),
                format!("{:.3}", t.median_baseline),
                format!("{:+.3}", t.median_difference),
                format!("{}/{}", t.better, t.cases),
                format!("{:.2e}", t.p),
                format!("{ph:.2e}"),
            ]
        })
        .collect();
    markdown::table(&header, &table, Alignment::Unmarked)
}

/// The join quality of the fitted walls: median and max join angle.
fn join_summary(report: &mut String, rows: &[ValidationRow]) {
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
}
