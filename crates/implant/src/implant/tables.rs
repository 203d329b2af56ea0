//! The chapter-6 tables: the sections of `report.md` and the CSV files
//! `metrics.csv`, `validation.csv`, `validation_3d.csv` and `verdicts.csv` (see
//! [`super::run`] for the driver that writes them, [`super::render`] for
//! the pictures).
//!
//! Markdown tables go through [`crate::markdown::table`]; CSV files hold no
//! wall times, so they are byte-identical for the same spec and seed.

use std::fmt::Write as _;

use super::delivered::Delivered;
use super::pipeline::{Implant, SliceResult};
use super::plausibility::{check_columns, check_fields, describe, Reading, FAILURE_DISTANCE_MM};
use super::regions::{region_tables, RegionRow};
use super::spec::{ImplantSpec, ValidationSpec};
use super::tables3d::position_unit_text;
use super::units::{
    case_differences, decide_families, position_units, scoped_rows, slice_clusters_within,
    within_gap, Comparison, Observation, SliceCluster,
};
use super::validation::{CaseMetrics, ValidationRow};
use super::wall_input::ThicknessProfile;
use crate::ct::{contour_deviation, Volume};
use crate::files::{csv_bytes, fmt_real};
use crate::markdown::{self, Alignment};
use crate::reconstruction::Method;
use crate::stats::{median, smallest_signed_rank_p, VerdictRow, VERDICT_COLUMNS};

pub(crate) fn r(x: f64) -> String {
    fmt_real(x)
}

/// The seatability targets of the real defect (issue 13): bone overlap per
/// slice, and the median and largest kink against the outer table.
pub const TARGET_OVERLAP: f64 = 0.02;
/// The target for the median kink (degrees).
pub const TARGET_KINK_MEDIAN_DEG: f64 = 5.0;
/// The target for the largest kink (degrees).
pub const TARGET_KINK_MAX_DEG: f64 = 10.0;
/// The target for the thickness step between adjacent slices (mm).
pub const TARGET_THICKNESS_STEP_MM: f64 = 1.0;
/// How far (mm) a thickness step may exceed its target and still meet it:
/// the Lipschitz envelope `t + L·k` makes steps of exactly `L` up to a few
/// units in the last place larger.
const STEP_ROUNDING_MM: f64 = 1e-9;

/// The title of `report.md` and the lines naming the spec, the volume and
/// its frame.
pub fn report_header(spec: &ImplantSpec, volume: &Volume) -> String {
    let mut report = String::new();
    let _ = writeln!(report, "# Chapter 6: cranial implant\n");
    let _ =
        writeln!(
        report,
        "Spec: `{}`; volume `{}` ({}×{}×{} voxels, spacing {} × {} × {} mm; slice 0 is z = {}).",
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
    let f = volume.frame();
    if spec.run_defect {
        let _ = writeln!(
            report,
            "Frame of `implant.stl`: {} (origin {:.3?} mm, axes {:.4?}).",
            f.stl_header(),
            f.origin,
            f.axes
        );
    }
    let _ = writeln!(report);
    report
}

/// The `## Summary` that opens `report.md`, after its title: the
/// chapter's question, every verdict over all units of the curve fit
/// against its baselines (the validation's, 2D and 3D) in one table with a
/// sentence per baseline, and links to the pictures (`pictures`, file
/// names beside the report).
pub fn report_summary(verdicts: &[VerdictRow], pictures: &[String]) -> String {
    let mut s = String::from("## Summary\n\n");
    s.push_str(
        "Question: does the curve-fitted outer wall (with its offset inner wall) rebuild \
         the missing bone better than the mirrored template and than a straight bridge? \
         The real defect has no ground truth; the artificial defects, cut from intact bone, \
         have one: Dice (larger is better), HD95 and the deviation of the wall (mm, smaller \
         is better), slice by slice and in 3D.\n\n",
    );
    let all: Vec<&VerdictRow> = verdicts.iter().filter(|v| v.scope == "all").collect();
    if all.is_empty() {
        s.push_str("No validation ran, so there are no verdicts.\n\n");
    } else {
        s.push_str(
            "Verdicts over all units (Wilcoxon signed-rank test across independent units, \
             Holm-corrected; a decided verdict gives the units that favour the fit, tie and \
             favour the baseline, and the adjusted p):\n\n",
        );
        let mut pairs: Vec<(&str, &str, &str)> = Vec::new();
        for v in &all {
            let key = (v.table.as_str(), v.algorithm.as_str(), v.reference.as_str());
            if !pairs.contains(&key) {
                pairs.push(key);
            }
        }
        for (table, fit, against) in pairs {
            let of = |verdict: &str| -> String {
                let m: Vec<String> = all
                    .iter()
                    .filter(|v| {
                        v.table == table
                            && v.algorithm == fit
                            && v.reference == against
                            && v.verdict.as_str() == verdict
                    })
                    .map(|v| {
                        let a = &v.across;
                        if verdict == "no detectable difference" {
                            v.measure.clone()
                        } else {
                            let p = if v.p_adjusted < 0.001 {
                                "p < 0.001".to_owned()
                            } else {
                                format!("p {:.3}", v.p_adjusted)
                            };
                            format!("{} ({}/{}/{}, {p})", v.measure, a.better, a.equal, a.worse)
                        }
                    })
                    .collect();
                if m.is_empty() {
                    "none".to_owned()
                } else {
                    m.join(", ")
                }
            };
            let scope = match table {
                VALIDATION_2D_TABLE => "slice by slice",
                "validation-3d" => "in 3D",
                other => other,
            };
            let against = match against {
                "template" => "mirrored template",
                "straight" => "straight bridge",
                other => other,
            };
            s.push_str(&format!(
                "- {scope}, {fit} against the {against}: better on {}; worse on {}; no \
                 detectable difference on {}.\n",
                of("better"),
                of("worse"),
                of("no detectable difference")
            ));
        }
        s.push_str("\nEvery verdict, per width and slice range too, is in `verdicts.csv`.\n\n");
    }
    if let Some(p) = pictures
        .iter()
        .find(|p| p.strip_suffix(".png") == Some(super::render::VALIDATION_FIGURE))
    {
        s.push_str(&format!(
            "The figure that answers the question: [Dice and HD95 per method and width]({p}).\n\n"
        ));
    }
    if !pictures.is_empty() {
        let links: Vec<String> = pictures
            .iter()
            .map(|p| format!("[{}]({p})", p.trim_end_matches(".png").replace('_', " ")))
            .collect();
        s.push_str(&format!("Figures: {}.\n\n", links.join(", ")));
        for p in pictures.iter().filter(|p| p.starts_with("preview")) {
            s.push_str(&format!("![{}]({p})\n\n", p.trim_end_matches(".png")));
        }
    }
    s
}

/// The thickness steps of each slice from the previous one (mm, the larger
/// of the two ends; `None` for the first slice or after a gap in z).
pub fn thickness_steps(implant: &Implant) -> Vec<Option<f64>> {
    let s = &implant.slices;
    (0..s.len())
        .map(|i| {
            (i > 0 && s[i].z == s[i - 1].z + 1).then(|| {
                let (a, b) = (s[i].wall.thickness, s[i - 1].wall.thickness);
                (a.0 - b.0).abs().max((a.1 - b.1).abs())
            })
        })
        .collect()
}

fn opt(x: Option<f64>) -> String {
    x.map_or(String::new(), r)
}

/// One slice's `metrics.csv` row (see [`defect_csv`]).
fn slice_row(s: &SliceResult, step: Option<f64>) -> Vec<String> {
    let w = &s.wall;
    let d = &w.design;
    let (ja, jb) = d.join_angles_deg();
    let n = d.template.points.len() as f64;
    let dev = contour_deviation(&d.outer, &d.template, 0.25).ok();
    let centre_y = d.centre.y;
    let mut row = vec![s.z.to_string()];
    row.extend([d.a.x, d.a.y, d.b.x, d.b.y, d.c.x, d.c.y, d.d.x, d.d.y].map(r));
    row.extend([s.midline.x_at(centre_y), s.midline.tilt_deg(), d.width()].map(r));
    row.extend([d.seats.0, d.seats.1].map(r));
    row.extend(
        [
            d.bone_thickness.0,
            d.bone_thickness.1,
            w.thickness.0,
            w.thickness.1,
        ]
        .map(r),
    );
    row.push(opt(step));
    let [k15, k3] = d.iso_kinks_deg();
    row.extend([d.fit_error, (d.fit_error / n).sqrt(), ja, jb].map(r));
    row.extend([k15.0, k15.1, k3.0, k3.1].map(r));
    row.push(d.segments.len().to_string());
    row.extend(
        [
            d.blends.0.offset_mm,
            d.blends.1.offset_mm,
            d.blends.0.length_mm,
            d.blends.1.length_mm,
        ]
        .map(r),
    );
    row.push(d.evaluations.to_string());
    row.extend(
        [
            d.outer.length(),
            w.section.signed_area().abs(),
            w.clipped_fraction,
        ]
        .map(r),
    );
    row.push(s.implant_pixels.to_string());
    row.push(r(s.bone_overlap_fraction));
    row.push(opt(s.roughness_mm));
    row.push(opt(s.template_roughness_mm));
    row.push(r(d.smoothing_shift_mm));
    row.push(dev.map_or("NaN".into(), |d| r(d.mean)));
    row.push(dev.map_or("NaN".into(), |d| r(d.max)));
    row.push(d.template_source.name().into());
    let nan = Delivered {
        kinks_deg: [(f64::NAN, f64::NAN); 2],
        thickness: (f64::NAN, f64::NAN),
    };
    let dl = s.delivered.unwrap_or(nan);
    let [d15, d3] = dl.kinks_deg;
    row.extend([d15.0, d15.1, d3.0, d3.1, dl.thickness.0, dl.thickness.1].map(r));
    let bare = contour_deviation(&d.outer, &d.mirror, 0.25).ok();
    row.push(bare.map_or("NaN".into(), |d| r(d.mean)));
    row.push(bare.map_or("NaN".into(), |d| r(d.max)));
    row.push(if s.accepted() { "ok" } else { "refused" }.into());
    row.extend(check_fields(&s.checks, &s.findings, r));
    row.push(describe(&s.findings));
    row
}

/// `metrics.csv`: one row per reconstructed slice of the real defect: the
/// ends A′, B′, C, D (mm, voxel frame), the midline (x at the slice's polar
/// centre, tilt), the width, how far A′ and B′ were seated back from the
/// tips, the bone thickness measured next to the ends
/// and the thickness used (after smoothing) with its step from the previous
/// slice, the fit (E, RMS against the blended template, evaluations), the
/// join angles with the join tangents, the kinks as the bone sees them
/// (`kink_{a,b}_{1p5mm,3mm}_deg`: the angle between the wall's secant over
/// its last 1.5 mm / 3 mm of arc at the seat and the secant over as much
/// of the bone's 300 HU (`threshold`) iso-contour from the seat,
/// [`crate::implant::OuterDesign::iso_kinks_deg`]), the number of fitted
/// segments, the template's offset from the bone at A′ and B′ (mm,
/// positive: the mirror image lies outside the bone) and the blend
/// lengths over which the bone wins there, the outer
/// wall's length, the section's area and the fraction clipped away, the
/// implant's pixels on the slice and the fraction of them on bone, the
/// outer wall's roughness across z (and the template's, the mirrored
/// bone's) and how far its smoothing moved it,
/// the wall's deviation from the template, and where the template came
/// from (`mirror`, `continuation` or `file`).
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
        "midline_tilt_deg",
        "width_mm",
        "seat_a_mm",
        "seat_b_mm",
        "bone_thickness_a_mm",
        "bone_thickness_b_mm",
        "thickness_a_mm",
        "thickness_b_mm",
        "thickness_step_mm",
        "fit_error_mm2",
        "fit_rms_mm",
        "join_a_deg",
        "join_b_deg",
        "kink_a_1p5mm_deg",
        "kink_b_1p5mm_deg",
        "kink_a_3mm_deg",
        "kink_b_3mm_deg",
        "segments",
        "template_offset_a_mm",
        "template_offset_b_mm",
        "blend_a_mm",
        "blend_b_mm",
        "evaluations",
        "outer_length_mm",
        "section_area_mm2",
        "clipped_fraction",
        "implant_pixels",
        "bone_overlap_fraction",
        "roughness_mm",
        "template_roughness_mm",
        "smoothing_shift_mm",
        "template_dev_mean_mm",
        "template_dev_max_mm",
        "template_source",
        "kink_delivered_a_1p5mm_deg",
        "kink_delivered_b_1p5mm_deg",
        "kink_delivered_a_3mm_deg",
        "kink_delivered_b_3mm_deg",
        "thickness_delivered_a_mm",
        "thickness_delivered_b_mm",
        "template_dev_bare_mean_mm",
        "template_dev_bare_max_mm",
        "status",
    ];
    let header: Vec<&str> = header
        .into_iter()
        .chain(check_columns())
        .chain(["error"])
        .collect();
    let steps = thickness_steps(implant);
    let rows = implant
        .slices
        .iter()
        .zip(steps)
        .map(|(s, step)| slice_row(s, step));
    csv_bytes(&header, rows)
}

/// The seatability figures of an implant: the largest bone overlap, the
/// median and largest kink, the largest thickness step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seatability {
    /// The largest per-slice bone overlap fraction.
    pub max_overlap: f64,
    /// The median kink over both ends of every slice (degrees).
    pub median_kink_deg: f64,
    /// The largest kink (degrees).
    pub max_kink_deg: f64,
    /// The largest kink of the designed walls alone (degrees).
    pub max_design_kink_deg: f64,
    /// The largest kink of the delivered STL rings alone (degrees).
    pub max_delivered_kink_deg: f64,
    /// The largest thickness step between adjacent slices (mm).
    pub max_thickness_step_mm: f64,
}

/// The 3 mm kinks at A′ and B′ of an accepted slice as they are judged:
/// at each end the worse of the designed wall and the delivered STL ring
/// ([`super::delivered`]).
pub fn judged_kinks_deg(s: &SliceResult) -> (f64, f64) {
    let (a, b) = s.wall.kinks_deg();
    match s.delivered {
        Some(d) => (a.max(d.kinks_deg[1].0), b.max(d.kinks_deg[1].1)),
        None => (a, b),
    }
}

/// The seatability figures of `implant` over its accepted slices, the
/// kinks the worse of design and delivery at each end.
pub fn seatability(implant: &Implant) -> Seatability {
    let ok = || implant.slices.iter().filter(|s| s.accepted());
    let kinks: Vec<f64> = ok()
        .flat_map(|s| {
            let (a, b) = judged_kinks_deg(s);
            [a, b]
        })
        .collect();
    let design = ok()
        .map(|s| {
            let (a, b) = s.wall.kinks_deg();
            a.max(b)
        })
        .fold(0.0, f64::max);
    let delivered = ok()
        .filter_map(|s| s.delivered.map(|d| d.max_kink_3mm()))
        .fold(0.0, f64::max);
    Seatability {
        max_design_kink_deg: design,
        max_delivered_kink_deg: delivered,
        max_overlap: implant
            .slices
            .iter()
            .map(|s| s.bone_overlap_fraction)
            .fold(0.0, f64::max),
        median_kink_deg: median(&kinks),
        max_kink_deg: kinks.iter().copied().fold(0.0, f64::max),
        max_thickness_step_mm: thickness_steps(implant)
            .into_iter()
            .flatten()
            .fold(0.0, f64::max),
    }
}

/// The slices that miss a per-slice target: bone overlap above
/// [`TARGET_OVERLAP`] or a kink above [`TARGET_KINK_MAX_DEG`].
pub fn slices_off_target(implant: &Implant) -> Vec<usize> {
    implant
        .slices
        .iter()
        .filter(|s| {
            let (a, b) = judged_kinks_deg(s);
            s.accepted()
                && (s.bone_overlap_fraction > TARGET_OVERLAP || a.max(b) > TARGET_KINK_MAX_DEG)
        })
        .map(|s| s.z)
        .collect()
}

/// The "Real defect" section of `report.md`: the run's settings, the
/// midline, the mesh checks, the seatability figures against their targets
/// and one table row per slice.
pub fn defect_report(report: &mut String, spec: &ImplantSpec, implant: &Implant) {
    let n = implant.slices.len();
    let cfg = &spec.defect_config;
    let _ = writeln!(report, "## Real defect\n");
    let _ = writeln!(
        report,
        "{n} slices z = {}..={}; method `{}`, function `{}`, continuity `{}`, budget {} evaluations per slice, seed {}; join tangents from {} mm of outer table; thickness measured {} mm behind the ends along the table's normal, capped at {} mm, changing by at most {} mm per slice; inner wall's thickness profile {}{}; outer walls smoothed over ±{} slices.",
        implant.slices[0].z,
        implant.slices[n - 1].z,
        spec.method.name(),
        cfg.wall.function.name(),
        cfg.wall.continuity.name(),
        cfg.wall.budget,
        spec.seed,
        cfg.wall.tangent_mm,
        cfg.wall.thickness_setback_mm,
        cfg.wall.max_thickness_mm,
        cfg.smoothing.max_thickness_step_mm,
        match cfg.wall.thickness_profile {
            ThicknessProfile::Linear => "linear from A′ to B′",
            ThicknessProfile::Mirror => "the other side's bone thickness (mirror)",
        },
        if cfg.wall.fill_ends {
            ", ends filled to the bone's cut face"
        } else {
            ""
        },
        cfg.smoothing.wall_half_width
    );
    let m = &implant.midline;
    let _ = writeln!(
        report,
        "Midline: x = {:.2} mm at y = {:.2} mm, tilt {:.2}°{}.\n",
        m.point.x,
        m.point.y,
        m.tilt_deg(),
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
    seatability_lines(report, implant);
    let _ = writeln!(
        report,
        "Bone against template: at each seat the mirrored template's offset from the bone is measured on the seat's ray. Where it is within {:.1} mm they agree; where it is larger the bone wins at the seat, because the implant must meet the bone flush and tangentially (a step or a corner there is what a surgeon cannot use), and the template is blended onto the bone's tangent line over the length in the table (a quintic smoothstep, rising by at most {}° where the defect is wide enough), the template winning beyond it. Seats move back from the tips (up to {} mm) where bone and template agree better or the bone's iso-contour turns less. The fit RMS is against this blended template; an outer wall that misses {} mm RMS with one segment is fitted again as a G¹ chain of up to {} segments.\n",
        cfg.wall.seat_offset_tol_mm,
        cfg.wall.blend_slope_deg,
        cfg.wall.seat_max_mm,
        cfg.wall.fit_tolerance_mm,
        cfg.wall.max_segments
    );
    let _ = writeln!(
        report,
        "Kinks as the bone sees them: at each seat, the angle between the wall's secant over its last 1.5 mm (3 mm) of arc and the secant over 1.5 mm (3 mm) of the bone's {} HU iso-contour from the seat (the marching-squares contour of the bone mask). The 3 mm kink is held to at most {}° per end; a slice that misses it is listed above with its overlay.\n",
        cfg.threshold,
        TARGET_KINK_MAX_DEG
    );
    report.push_str(&slice_table(implant, cfg.wall.seat_offset_tol_mm));
    let _ = writeln!(report);
}

/// The seatability figures against their targets, and the slices that
/// miss one.
fn seatability_lines(report: &mut String, implant: &Implant) {
    let s = seatability(implant);
    let ok = |b: bool| if b { "met" } else { "missed" };
    let _ = writeln!(
        report,
        "Seatability: largest bone overlap {:.2} % (target ≤ {:.0} % per slice: {}); kinks against the bone's iso-contour (3 mm secants, at each end the worse of the designed wall and the delivered STL ring: design max {:.2}°, delivered max {:.2}°) median {:.2}°, max {:.2}° (targets ≤ {}° and ≤ {}°: {}, {}); largest thickness step {:.2} mm (target ≤ {} mm: {}).\n",
        100.0 * s.max_overlap,
        100.0 * TARGET_OVERLAP,
        ok(s.max_overlap <= TARGET_OVERLAP),
        s.max_design_kink_deg,
        s.max_delivered_kink_deg,
        s.median_kink_deg,
        s.max_kink_deg,
        TARGET_KINK_MEDIAN_DEG,
        TARGET_KINK_MAX_DEG,
        ok(s.median_kink_deg <= TARGET_KINK_MEDIAN_DEG),
        ok(s.max_kink_deg <= TARGET_KINK_MAX_DEG),
        s.max_thickness_step_mm,
        TARGET_THICKNESS_STEP_MM,
        ok(s.max_thickness_step_mm <= TARGET_THICKNESS_STEP_MM + STEP_ROUNDING_MM)
    );
    thickness_line(report, implant);
    let refused: Vec<String> = implant
        .refused()
        .map(|s| format!("z = {} ({})", s.z, describe(&s.findings)))
        .collect();
    if !refused.is_empty() {
        let _ = writeln!(
            report,
            "Refused by the plausibility checks (no piece of the implant): {}.\n",
            refused.join("; ")
        );
    }
    let off = slices_off_target(implant);
    if !off.is_empty() {
        let _ = writeln!(
            report,
            "Slices that miss a per-slice target (each has its `overlay_zNNN.png`): {off:?}.\n"
        );
    }
}

/// The designed thickness at the seats against the delivered ring's 3 mm
/// inside them ([`super::delivered`]), over the accepted slices.
fn thickness_line(report: &mut String, implant: &Implant) {
    let ok = || implant.slices.iter().filter(|s| s.accepted());
    let design: Vec<f64> = ok()
        .flat_map(|s| [s.wall.thickness.0, s.wall.thickness.1])
        .collect();
    let delivered: Vec<f64> = ok()
        .filter_map(|s| s.delivered)
        .flat_map(|d| [d.thickness.0, d.thickness.1])
        .filter(|t| t.is_finite())
        .collect();
    if delivered.is_empty() {
        return;
    }
    let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
    let _ = writeln!(
        report,
        "Thickness: designed at the seats median {:.2} mm (min {:.2}); delivered, on the STL rings 3 mm inside the seats, median {:.2} mm (min {:.2}): near its seats the part is an onlay over the bevelled bone ends, thinner than its design there (the worse of the two is the delivered; `thickness_delivered_*` in `metrics.csv`).\n",
        median(&design),
        min(&design),
        median(&delivered),
        min(&delivered)
    );
}

/// Which wins at a seat, bone or template, and why, for the report's
/// per-slice table: "agree" when the template's offset from the bone is at
/// most `tol` mm (the seat rule's tolerance), else "bone" with the offset
/// and the blend length; and how far the seat lies behind the bone tip.
fn which_wins(blend: crate::implant::wall::Blend, seat_mm: f64, tol: f64) -> String {
    let d = blend.offset_mm;
    if d.abs() <= tol {
        format!("agree ({d:+.1} mm; seat {seat_mm:.2} mm back)")
    } else {
        let side = if d > 0.0 { "outside" } else { "inside" };
        format!(
            "bone: template {:.1} mm {side}, blended over {:.1} mm (seat {seat_mm:.2} mm back)",
            d.abs(),
            blend.length_mm
        )
    }
}

/// The per-slice table of the real defect.
fn slice_table(implant: &Implant, tol: f64) -> String {
    let header = [
        "z",
        "width mm",
        "bone t_A / t_B mm",
        "t_A / t_B mm",
        "fit RMS mm",
        "segments",
        "join A / B °",
        "kink 1.5 mm A / B °",
        "kink 3 mm A / B °",
        "at A′",
        "at B′",
        "on bone %",
        "clipped %",
    ]
    .map(String::from);
    let rows: Vec<Vec<String>> = implant
        .slices
        .iter()
        .map(|s| {
            let w = &s.wall;
            let d = &w.design;
            let (ja, jb) = d.join_angles_deg();
            let [k15, k3] = d.iso_kinks_deg();
            let rms = (d.fit_error / d.template.points.len() as f64).sqrt();
            vec![
                s.z.to_string(),
                format!("{:.1}", d.width()),
                format!("{:.1} / {:.1}", d.bone_thickness.0, d.bone_thickness.1),
                format!("{:.1} / {:.1}", w.thickness.0, w.thickness.1),
                format!("{rms:.2}"),
                d.segments.len().to_string(),
                format!("{ja:.0e} / {jb:.0e}"),
                format!("{:.1} / {:.1}", k15.0, k15.1),
                format!("{:.1} / {:.1}", k3.0, k3.1),
                which_wins(d.blends.0, d.seats.0, tol),
                which_wins(d.blends.1, d.seats.1, tol),
                format!("{:.1}", 100.0 * s.bone_overlap_fraction),
                format!("{:.0}", 100.0 * w.clipped_fraction),
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
        "template_source",
        "error",
    ];
    let header: Vec<&str> = header
        .into_iter()
        .chain(check_columns())
        .chain(["region"])
        .collect();
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
                v.push(row.status().into());
                v.extend([m.dice, m.boundary_dice, m.hd95, m.dev_mean, m.dev_max].map(r));
                v.extend([
                    r(row.fit_error),
                    r(row.join_deg.0),
                    r(row.join_deg.1),
                    source_name(row.template_source),
                    describe(&row.findings),
                ]);
            }
            Err(e) => {
                v.push("error".into());
                v.extend(std::iter::repeat_n(String::new(), 8));
                v.push(source_name(row.template_source));
                v.push(e.to_string());
            }
        }
        v.extend(check_fields(&row.checks, &row.findings, r));
        v.push(row.region.name().into());
        v
    });
    csv_bytes(&header, rows)
}

/// A template source's name, empty when the case was not built.
pub(crate) fn source_name(s: Option<super::continuation::TemplateSource>) -> String {
    s.map_or(String::new(), |s| s.name().to_owned())
}

/// `verdicts.csv`: every verdict row of the validations, in the columns
/// [`VERDICT_COLUMNS`] shared with `metabezier report`.
pub fn verdicts_csv(rows: &[VerdictRow]) -> Vec<u8> {
    csv_bytes(&VERDICT_COLUMNS, rows.iter().map(VerdictRow::csv_fields))
}

/// A metric's accessor.
type MetricFn = fn(&CaseMetrics) -> f64;

/// One validation metric: its name in tables, its name in `verdicts.csv`,
/// its accessor, and whether larger is better.
type Metric = (&'static str, &'static str, MetricFn, bool);

/// The validation metrics, in table order.
const METRICS: [Metric; 5] = [
    ("Dice", "dice", |m| m.dice, true),
    ("boundary Dice", "boundary-dice", |m| m.boundary_dice, true),
    ("HD95 mm", "hd95-mm", |m| m.hd95, false),
    (
        "mean deviation mm",
        "mean-deviation-mm",
        |m| m.dev_mean,
        false,
    ),
    ("max deviation mm", "max-deviation-mm", |m| m.dev_max, false),
];

/// The `table` of the one-slice validation's rows in `verdicts.csv`.
pub const VALIDATION_2D_TABLE: &str = "validation-2d";

/// The `table` of the one-slice validation's verdicts without its
/// implausible rows.
pub const VALIDATION_2D_PLAUSIBLE_TABLE: &str = "validation-2d-plausible";

/// The "Validation on perfect data" section of `report.md`: the cases, the
/// median of every metric by method and width, the verdicts of the curve
/// fit against the baselines across independent units, and the join
/// quality of the fits. Returns the verdict rows (for `verdicts.csv`).
pub fn validation_report(
    report: &mut String,
    val: &ValidationSpec,
    rows: &[ValidationRow],
    slice_mm: f64,
) -> Vec<VerdictRow> {
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
    let _ = writeln!(report, "### By region\n\n{REGION_TEXT}\n");
    let by_region: Vec<RegionRow<'_>> = rows
        .iter()
        .filter_map(|r| {
            let m = r.metrics.as_ref().ok()?;
            Some(RegionRow {
                region: r.region,
                method: &r.method,
                case: format!("{}-{}-{}", r.z, r.case.position_deg, r.case.width_mm),
                values: vec![m.dice, m.hd95],
            })
        })
        .collect();
    region_tables(report, &["Dice", "HD95 mm"], &methods, &by_region);
    let verdicts = validation_verdicts(report, val, rows, slice_mm);
    join_summary(report, rows);
    verdicts
}

/// Per width of `widths`, the median (three decimals) of the values of
/// `method`'s rows of that width; `cell` reads a row's method, width and
/// value (`None` for a failed row).
pub(crate) fn medians_by_width<'r, R>(
    rows: &'r [R],
    method: &str,
    widths: &[f64],
    cell: impl Fn(&'r R) -> Option<(&'r str, f64, f64)>,
) -> Vec<String> {
    let cells: Vec<(&str, f64, f64)> = rows.iter().filter_map(cell).collect();
    widths
        .iter()
        .map(|&w| {
            let v: Vec<f64> = cells
                .iter()
                .filter(|(m, cw, _)| *m == method && *cw == w)
                .map(|c| c.2)
                .collect();
            format!("{:.3}", median(&v))
        })
        .collect()
}

/// The median of one metric over cases and runs, by method × width.
fn median_table(
    report: &mut String,
    (name, _, f, _): Metric,
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
            line.extend(medians_by_width(rows, m, &val.widths, |r| {
                let v = r.metrics.as_ref().ok().map(f)?;
                Some((r.method.as_str(), r.case.width_mm, v))
            }));
            line
        })
        .collect();
    report.push_str(&markdown::table(&header, &table, Alignment::Unmarked));
    let _ = writeln!(report);
}

/// The observations of one metric: every built row's value as `reading`
/// reads it, with its case and unit (slice cluster × position).
fn observations<'r>(
    rows: &'r [ValidationRow],
    (clusters, units): (&[SliceCluster], &[(f64, f64)]),
    (f, larger_better): (MetricFn, bool),
    reading: Reading,
) -> Vec<Observation<'r>> {
    rows.iter()
        .filter_map(|r| {
            let value = r.metrics.as_ref().ok().map(f)?;
            let value = reading.value(value, !r.findings.is_empty(), larger_better)?;
            let case = (r.case.position_deg, r.case.width_mm);
            let mut o = Observation::at(clusters, (r.z, r.z), case, &r.method, value);
            if let Some(&(_, u)) = units
                .iter()
                .find(|(p, _)| p.to_bits() == r.case.position_deg.to_bits())
            {
                o.unit.position_deg = u;
            }
            Some(o)
        })
        .collect()
}

/// Each position's widest cut over the built rows: `(position_deg,
/// half_width_deg)` in the spec's order (NaN when none was built).
fn position_extents_2d(val: &ValidationSpec, rows: &[ValidationRow]) -> Vec<(f64, f64)> {
    val.positions
        .iter()
        .map(|&p| {
            let h = rows
                .iter()
                .filter(|r| r.case.position_deg.to_bits() == p.to_bits())
                .map(|r| r.half_width_deg)
                .filter(|h| h.is_finite())
                .fold(f64::NAN, f64::max);
            (p, h)
        })
        .collect()
}

/// The verdict rows of every curve method against both baselines on every
/// metric, at scope `all` and per width, decided per family at the spec's
/// α; and their part of `report.md`.
fn validation_verdicts(
    report: &mut String,
    val: &ValidationSpec,
    rows: &[ValidationRow],
    slice_mm: f64,
) -> Vec<VerdictRow> {
    let widest = val.widths.iter().copied().fold(0.0, f64::max);
    let clusters = slice_clusters_within(&val.slices, within_gap(widest, slice_mm));
    let units = position_units(&position_extents_2d(val, rows));
    let implausible = rows.iter().filter(|r| r.status() == "implausible").count();
    let read = |reading: Reading| -> Vec<Vec<Observation<'_>>> {
        METRICS
            .iter()
            .map(|m| observations(rows, (&clusters, &units), (m.2, m.3), reading))
            .collect()
    };
    let obs = read(Reading::AsFailure);
    if no_case_built(report, &obs) {
        return Vec::new();
    }
    let decide = |table: &str, obs: &[Vec<Observation<'_>>]| {
        decided_rows(table, &val.methods, &METRICS, obs, &val.widths, val.alpha)
    };
    let verdicts = decide(VALIDATION_2D_TABLE, &obs);
    let without =
        (implausible > 0).then(|| decide(VALIDATION_2D_PLAUSIBLE_TABLE, &read(Reading::Without)));
    let _ = writeln!(
        report,
        "### What the curve fit adds (verdicts across independent units)\n"
    );
    let cases = verdicts.first().map_or(0, |v| v.0.problems);
    let _ = writeln!(
        report,
        "The validation cases are not independent: the widths of one position are nested cuts of the same bone, and slices closer than the widest cut ({widest} mm, {} slices of {slice_mm} mm) cut bone one 3D patch of that width would share. A *unit* is one position on one slice cluster, a maximal set of validation slices each at most that far from the next ({}). {} {}\n",
        within_gap(widest, slice_mm),
        cluster_list(&clusters),
        position_unit_text(&position_extents_2d(val, rows), &units),
        design_text(
            (
                clusters.len(),
                unit_count(&units),
                units_observed(obs.first().map_or(&[][..], |o| &o[..]))
            ),
            cases,
            "its widths and the slices of its cluster",
            family_size(&verdicts),
            val.alpha
        )
    );
    let _ = writeln!(report, "{}\n", implausible_text(implausible, rows.len()));
    verdict_tables(report, &verdicts);
    let mut out: Vec<VerdictRow> = verdicts.into_iter().map(|v| v.0).collect();
    if let Some(w) = without {
        let _ = writeln!(report, "The same verdicts without the {implausible} implausible rows (table `{VALIDATION_2D_PLAUSIBLE_TABLE}` of `verdicts.csv`):\n");
        verdict_tables(report, &w);
        out.extend(w.into_iter().map(|v| v.0));
    }
    out
}

/// What the region tables are and what a slice-wise method cannot do.
pub(crate) const REGION_TEXT: &str = "Regions (`src/implant/regions.rs`): the vertex is the top 15 mm of the scanned bone and the skull base the lowest 15 mm of the volume (both decided first), the front the positions within 60° of the anterior midline, the back the rest; the straight bridge and the template are beside every curve fit. Limits of a slice-wise method: near the vertex an axial slice runs nearly tangent to the vault, so the ring is wide and flat and its mirror or continuation no guide to the missing bone; at the skull base the ring opens into the face and the foramina, so an automatic defect detection finds natural openings (the plausibility checks refuse them) — both need a 3D template. On the front the forehead and the frontal sinus are less symmetric than the back of the head.";

/// The distinct unit positions of `units` (`(position, unit position)`).
pub(crate) fn unit_count(units: &[(f64, f64)]) -> usize {
    let mut u: Vec<u64> = units.iter().map(|x| x.1.to_bits()).collect();
    u.sort_unstable();
    u.dedup();
    u.len()
}

/// Where no case was built, the verdict section says so and gives no
/// verdict (a "no detectable difference" over no unit would read as a
/// finding); returns whether that is so.
pub(crate) fn no_case_built(report: &mut String, obs: &[Vec<Observation<'_>>]) -> bool {
    let none = obs.iter().all(|o| units_observed(o) == 0);
    if none {
        let _ = writeln!(
            report,
            "### Verdicts\n\nNo case was built (every row failed; see the `error` column), so there is no verdict.\n"
        );
    }
    none
}

/// What the verdicts make of the implausible rows.
pub(crate) fn implausible_text(implausible: usize, rows: usize) -> String {
    if implausible == 0 {
        format!("Every built row of the {rows} passed the plausibility checks (`checks_failed` empty), so no row is read as a failure.")
    } else {
        format!("{implausible} of the {rows} rows are `implausible` (a plausibility check failed; `checks_failed` and `error` say which): the design path would have refused them, so the verdicts read them as failures of their method (overlap 0, distance {FAILURE_DISTANCE_MM:.0e} mm); the verdicts without them follow.")
    }
}

/// The verdict rows of every curve method in `methods` against both
/// baselines on every metric (name, `verdicts.csv` name, accessor, whether
/// larger is better; its observations in `obs`), at scope `all` and per
/// width, in family order and decided per family at level `alpha`; each row
/// with its count of cases where the curve fit is strictly better.
pub(crate) fn decided_rows<F>(
    table: &str,
    methods: &[Method],
    metrics: &[(&'static str, &'static str, F, bool)],
    obs: &[Vec<Observation<'_>>],
    widths: &[f64],
    alpha: f64,
) -> Vec<(VerdictRow, usize)> {
    let mut verdicts = Vec::new();
    for cm in methods.iter().map(|m| format!("curve:{}", m.name())) {
        let cm = cm.as_str();
        for base in ["template", "straight"] {
            for ((_, measure, _, larger_better), obs) in metrics.iter().zip(obs) {
                let cmp = Comparison {
                    table,
                    measure,
                    algorithm: cm,
                    reference: base,
                    lower_is_better: !larger_better,
                };
                let diffs = case_differences(obs, cm, base);
                verdicts.extend(scoped_rows(&cmp, &diffs, widths));
            }
        }
    }
    let mut verdicts = in_family_order(verdicts);
    let mut decided: Vec<VerdictRow> = verdicts.iter().map(|v| v.0.clone()).collect();
    decide_families(&mut decided, alpha);
    for (v, d) in verdicts.iter_mut().zip(&decided) {
        v.0 = d.clone();
    }
    verdicts
}

/// `rows` ordered by scope (`all` first, then the widths in spec order),
/// keeping their order within a scope: one family after another.
pub(crate) fn in_family_order(rows: Vec<(VerdictRow, usize)>) -> Vec<(VerdictRow, usize)> {
    let mut scopes: Vec<String> = Vec::new();
    for r in &rows {
        if !scopes.contains(&r.0.scope) {
            scopes.push(r.0.scope.clone());
        }
    }
    let mut rows: Vec<(usize, (VerdictRow, usize))> = rows
        .into_iter()
        .map(|r| (scopes.iter().position(|s| *s == r.0.scope).unwrap_or(0), r))
        .collect();
    rows.sort_by_key(|r| r.0);
    rows.into_iter().map(|r| r.1).collect()
}

/// The rows of one family (the first scope's rows).
pub(crate) fn family_size(rows: &[(VerdictRow, usize)]) -> usize {
    rows.first().map_or(0, |f| {
        rows.iter().filter(|r| r.0.scope == f.0.scope).count()
    })
}

/// `z = 64; z = 72; z = 88–90`.
pub(crate) fn cluster_list(clusters: &[SliceCluster]) -> String {
    clusters
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("; ")
}

/// The design sentences of a verdict section: the units and effective n,
/// the summary within a unit, the test, the correction, p_min and the
/// verdict rule.
pub(crate) fn design_text(
    (clusters, positions, built): (usize, usize, usize),
    cases: usize,
    within: &str,
    family: usize,
    alpha: f64,
) -> String {
    let planned = clusters * positions;
    let n = built.min(planned);
    let p_min = smallest_signed_rank_p(n);
    let units = if n < planned {
        format!(
            "{}, of which {} with a built case",
            count(planned, "unit"),
            count(n, "unit")
        )
    } else {
        count(n, "unit")
    };
    let unreachable = if p_min >= alpha {
        format!(" Here p_min = {p_min:.3} ≥ α = {alpha}: no row can reject, whatever the data; the verdicts are all `no detectable difference` by design, and the rows are descriptive.")
    } else {
        String::new()
    };
    format!(
        "{} × {} = **{units}: the effective n** (the {cases} cases are pooled into them). Per case d = the curve fit's median over its runs − the baseline's value; a unit's summary is the median of d over its cases ({within}; in a `width_mm=…` scope only the cases of that width). Two-sided Wilcoxon signed-rank test of the unit summaries against zero (`stats::across_units`), Holm-corrected within each family: the {family} rows of one scope. With n non-zero units no p can fall below p_min = 2/2ⁿ ({units}: {p_min:.2e}), which bounds every p. A verdict is `better` or `worse` only where the Holm-corrected p is below α = {alpha}; otherwise it is `no detectable difference`.{unreachable} `better/equal/worse` count units; `cases better` counts cases where the curve fit is strictly better and is a description, not a test. Every row is in `verdicts.csv`.",
        count(clusters, "slice cluster"),
        count(positions, "position"),
    )
}

/// The distinct units of `obs`: the effective n of a verdict section
/// (a unit whose every case failed has no observation).
pub(crate) fn units_observed(obs: &[Observation<'_>]) -> usize {
    obs.iter()
        .map(|o| o.unit)
        .collect::<std::collections::BTreeSet<_>>()
        .len()
}

/// `n` and `noun`, in the plural unless `n` is 1: `1 unit`, `18 units`.
fn count(n: usize, noun: &str) -> String {
    format!("{n} {noun}{}", if n == 1 { "" } else { "s" })
}

/// One markdown table of verdict rows per scope, with the cases favouring
/// the compared method (descriptive).
pub(crate) fn verdict_tables(report: &mut String, rows: &[(VerdictRow, usize)]) {
    let header = [
        "method",
        "baseline",
        "metric",
        "scope",
        "units",
        "cases",
        "units better/equal/worse",
        "median unit difference",
        "p",
        "p (Holm)",
        "p_min",
        "verdict",
        "cases better (descriptive)",
    ]
    .map(String::from);
    let mut scopes: Vec<&str> = Vec::new();
    for r in rows {
        if !scopes.contains(&r.0.scope.as_str()) {
            scopes.push(&r.0.scope);
        }
    }
    let (all, others) = scopes.split_at(1.min(scopes.len()));
    for &scope in all {
        let table: Vec<Vec<String>> = rows
            .iter()
            .filter(|r| r.0.scope == scope)
            .map(|(v, cases_better)| {
                let a = &v.across;
                vec![
                    v.algorithm.clone(),
                    v.reference.clone(),
                    v.measure.clone(),
                    v.scope.clone(),
                    a.units.to_string(),
                    v.problems.to_string(),
                    format!("{}/{}/{}", a.better, a.equal, a.worse),
                    // A difference that rounds to zero is shown as +0.0000.
                    format!(
                        "{:+.4}",
                        if (a.effect_size * 1e4).round() == 0.0 {
                            0.0
                        } else {
                            a.effect_size
                        }
                    ),
                    format!("{:.2e}", a.p_value),
                    format!("{:.2e}", v.p_adjusted),
                    format!("{:.2e}", a.p_min),
                    v.verdict.to_string(),
                    format!("{cases_better}/{}", v.problems),
                ]
            })
            .collect();
        let _ = writeln!(report, "Scope `{scope}`:\n");
        report.push_str(&markdown::table(&header, &table, Alignment::Unmarked));
        let _ = writeln!(report);
    }
    if others.is_empty() {
        return;
    }
    // The other scopes side by side, one column each: where a verdict holds
    // and where it flips (their p-values and effects are in verdicts.csv).
    let mut pivot_header = vec!["method".to_owned(), "baseline".into(), "metric".into()];
    pivot_header.extend(others.iter().map(|s| format!("`{s}`")));
    let mut keys: Vec<(&str, &str, &str)> = Vec::new();
    for (v, _) in rows.iter().filter(|r| others.contains(&r.0.scope.as_str())) {
        let k = (
            v.algorithm.as_str(),
            v.reference.as_str(),
            v.measure.as_str(),
        );
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let pivot: Vec<Vec<String>> = keys
        .iter()
        .map(|&(alg, base, metric)| {
            let mut row = vec![alg.to_owned(), base.to_owned(), metric.to_owned()];
            row.extend(others.iter().map(|&scope| {
                rows.iter()
                    .find(|(v, _)| {
                        v.scope == scope
                            && v.algorithm == alg
                            && v.reference == base
                            && v.measure == metric
                    })
                    .map_or_else(
                        || "—".to_owned(),
                        |(v, _)| {
                            let a = &v.across;
                            let word = match v.verdict.as_str() {
                                "no detectable difference" => "n.d.",
                                w => w,
                            };
                            format!("{word} {}/{}/{}", a.better, a.equal, a.worse)
                        },
                    )
            }));
            row
        })
        .collect();
    let _ = writeln!(
        report,
        "Per scope (verdict and units better/equal/worse; n.d. = no detectable difference; \
         every p and effect is in `verdicts.csv`):\n"
    );
    report.push_str(&markdown::table(&pivot_header, &pivot, Alignment::Unmarked));
    let _ = writeln!(report);
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
