//! The chapter-6 tables of the real defect: the report's title, summary
//! and "Real defect" section, and `metrics.csv` (the validations' are in
//! [`super::tables2d`] and [`super::tables3d`], their shared verdict
//! sections in [`super::verdict_tables`]; [`super::run`] is the driver
//! that writes them, [`super::render`] draws the pictures).
//!
//! Markdown tables go through [`crate::markdown::table`]; CSV files hold no
//! wall times, so they are byte-identical for the same spec and seed.

use std::fmt::Write as _;

use super::delivered::Delivered;
use super::pipeline::{Implant, SliceResult};
use super::plausibility::{check_columns, check_fields, describe};
use super::spec::ImplantSpec;
use super::verdict_tables::{VALIDATION_2D_TABLE, VALIDATION_3D_TABLE};
use super::wall_input::ThicknessProfile;
use crate::ct::{contour_deviation, Volume};
use crate::files::{csv_bytes, fmt_real};
use crate::markdown::{self, Alignment};
use crate::stats::{median, VerdictRow};

pub(crate) fn r(x: f64) -> String {
    fmt_real(x)
}

/// The summary's word for a verdict row whose smallest reachable p is at
/// least α and that is not equivalent: not "undecided", which would read as
/// a failure of the data rather than of the design.
const UNDECIDABLE: &str = "undecidable";

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

/// The measures of `all` over all units whose verdict for the pair `(table,
/// fit, against)` is `verdict`, each with its evidence: the units and
/// `p_min` for a row no test can decide (its `p_min ≥ alpha`), the Bayesian
/// probabilities for undecided and equivalent rows, the units that favour
/// each side and the adjusted p otherwise; `"none"` when there is none.
fn verdict_measures(
    all: &[&VerdictRow],
    (table, fit, against): (&str, &str, &str),
    verdict: &str,
    alpha: f64,
) -> String {
    let m: Vec<String> = all
        .iter()
        .filter(|v| {
            v.table == table
                && v.algorithm == fit
                && v.reference == against
                && match verdict {
                    // A row that cannot reject is no finding.
                    UNDECIDABLE => v.across.p_min >= alpha && v.verdict.as_str() == "undecided",
                    "undecided" => v.verdict.as_str() == verdict && v.across.p_min < alpha,
                    _ => v.verdict.as_str() == verdict,
                }
        })
        .map(|v| {
            let a = &v.across;
            if verdict == UNDECIDABLE {
                format!("{} ({} units, p_min {:.2})", v.measure, a.units, a.p_min)
            } else if verdict == "undecided" || verdict == "equivalent" {
                let e = &v.equivalence;
                format!(
                    "{} (P(better/≈/worse) {:.2}/{:.2}/{:.2})",
                    v.measure, e.better, e.within, e.worse
                )
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
}

/// The `## Summary` that opens `report.md`, after its title: the
/// chapter's question, every verdict over all units of the curve fit
/// against its baselines (the validation's, 2D and 3D) in one table with a
/// sentence per baseline, and links to the pictures (`pictures`, file
/// names beside the report).
pub fn report_summary(verdicts: &[VerdictRow], pictures: &[String], alpha: f64) -> String {
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
             Holm-corrected, beside the Bayesian signed-rank test with a region of practical \
             equivalence of ±0.01 Dice and ±0.5 mm unless the spec sets `rope_overlap` and \
             `rope_mm`; equivalent where P(rope) ≥ 0.95; a decided verdict gives the units \
             that favour the fit, tie and favour the baseline, and the adjusted p):\n\n",
        );
        let mut pairs: Vec<(&str, &str, &str)> = Vec::new();
        for v in &all {
            let key = (v.table.as_str(), v.algorithm.as_str(), v.reference.as_str());
            if !pairs.contains(&key) {
                pairs.push(key);
            }
        }
        for (table, fit, against) in pairs {
            let of = |verdict: &str| verdict_measures(&all, (table, fit, against), verdict, alpha);
            let scope = match table {
                VALIDATION_2D_TABLE => "slice by slice",
                VALIDATION_3D_TABLE => "in 3D",
                other => other,
            };
            let against = match against {
                "template" => "mirrored template",
                "straight" => "straight bridge",
                other => other,
            };
            s.push_str(&format!(
                "- {scope}, {fit} against the {against}: better on {}; worse on {}; \
                 equivalent on {}; undecided (no detectable difference, no equivalence) on {}; \
                 too few units for any test to decide (p_min ≥ α = {alpha}) on {}.\n",
                of("better"),
                of("worse"),
                of("equivalent"),
                of("undecided"),
                of(UNDECIDABLE)
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

/// The seatability figures of `implant` over its accepted slices, the
/// kinks the worse of design and delivery at each end.
pub fn seatability(implant: &Implant) -> Seatability {
    let ok = || implant.slices.iter().filter(|s| s.accepted());
    let kinks: Vec<f64> = ok()
        .flat_map(|s| {
            let (a, b) = s.judged_kinks_deg();
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
            let (a, b) = s.judged_kinks_deg();
            s.accepted()
                && (s.bone_overlap_fraction > TARGET_OVERLAP || a.max(b) > TARGET_KINK_MAX_DEG)
        })
        .map(|s| s.z)
        .collect()
}

/// The "Real defect" section of `report.md`: the run's settings, the
/// midline, the mesh checks, the seatability figures against their targets
/// The 3D templates' lines of the real defect's section: the plane, the
/// rim surface's residual and, per slice, the template used and why.
fn templates_3d_lines(report: &mut String, t: &super::surface_template::SurfaceTemplates) {
    if let Some(p) = &t.plane {
        let [x, y, z] = p.normal;
        let _ = writeln!(
            report,
            "Mid-sagittal plane (3D, trimmed ICP of the bone surface to its mirror image): normal ({x:.4}, {y:.4}, {z:.4}), offset {:.2} mm.\n",
            p.offset
        );
    }
    if let Some(rms) = t.rim_rms_mm {
        let _ = writeln!(
            report,
            "Rim fill: a sphere and a thin-plate spline through the outer table within {} mm of the defect, {rms:.3} mm RMS from its rim points.\n",
            super::surface_template::RIM_MM
        );
    }
    let rows: Vec<Vec<String>> = t
        .slices
        .iter()
        .map(|(z, s)| vec![z.to_string(), s.kind.name().to_string(), s.reason.clone()])
        .collect();
    let header = ["z", "template", "why"].map(String::from);
    report.push_str(&markdown::table(&header, &rows, Alignment::Unmarked));
    report.push('\n');
}

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
    if let Some(t) = &implant.templates_3d {
        templates_3d_lines(report, t);
    }
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
