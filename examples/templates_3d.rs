//! The four templates of issue 56 compared by region on CT 0051
//! (`make templates-3d`): the slice-wise template, the 3D mirror, the rim
//! fill and the straight bridge on the 3D validation patches of
//! `experiments/ch6_cranial.toml`, the vertex patch and 15 mm patches,
//! with the mid-sagittal plane found by 3D registration and compared with
//! the per-slice midline. Writes `results/templates_3d/report.md`.
//!
//! `cargo run --release --example templates_3d [-- --quick]` (`--quick`:
//! the first range and two positions only).

use std::fmt::Write as _;
use std::path::Path;

use metabezier::ct::{mid_sagittal_plane, MidLine, Plane3, SymmetryPlane, Volume};
use metabezier::implant::regions::RegionRule;
use metabezier::implant::template_comparison::{
    compare_templates, comparison_report, comparison_verdicts, ComparisonRow,
};
use metabezier::implant::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let quick = std::env::args().any(|a| a == "--quick");
    let spec = ImplantSpec::load(Path::new("experiments/ch6_cranial.toml"))?;
    let volume = load_volume(&spec.volume)?;
    let cfg = &spec.defect_config;
    let (midline, _) = resolve_midline(&volume, cfg)?;
    let t0 = std::time::Instant::now();
    let sym = mid_sagittal_plane(&volume, cfg.threshold, &midline)
        .ok_or("the mid-sagittal plane could not be estimated")?;
    let plane_secs = t0.elapsed().as_secs_f64();
    let line_plane = Plane3::from_midline(&midline);
    let mut report = String::from("# The four templates by region (CT 0051, issue 56)\n\n");
    plane_section(&mut report, (&sym, plane_secs), &midline, &volume, cfg);
    let val = spec
        .validation_3d
        .as_ref()
        .ok_or("the spec has no [validation_3d]")?;
    let cases = cases(val, quick);
    let rule = RegionRule::of(&volume, cfg.first_z, cfg.threshold, &midline);
    let region = |c: &Case3d| rule.region(0.5 * (c.range.0 + c.range.1) as f64, c.position_deg);
    let t1 = std::time::Instant::now();
    // `--plane-from-midline`: the 3D mirror across the per-slice midline's
    // plane (a check of the 3D mirror's implementation: it should then
    // follow the slice-wise mirror).
    let plane = if std::env::args().any(|a| a == "--plane-from-midline") {
        let _ = writeln!(
            report,
            "**The 3D mirror uses the per-slice midline's plane (`--plane-from-midline`).**\n"
        );
        line_plane
    } else {
        sym.plane
    };
    let rows = compare_templates(&volume, cfg, (midline, plane), &cases, &region);
    let _ = writeln!(
        report,
        "{} cases × 4 templates in {:.0} s (LM fits).\n",
        cases.len(),
        t1.elapsed().as_secs_f64()
    );
    let verdicts = comparison_verdicts(&rows, 0.05);
    report.push_str(&comparison_report(&rows, &verdicts));
    named_cases(&mut report, &rows);
    let out = Path::new(if plane == sym.plane {
        "results/templates_3d"
    } else {
        "results/templates_3d_line_plane"
    });
    std::fs::create_dir_all(out)?;
    std::fs::write(out.join("report.md"), &report)?;
    println!("{report}");
    Ok(())
}

/// The mid-sagittal plane `sym` (found in `secs` seconds) against the
/// per-slice `midline`, and its traces on five slices.
fn plane_section(
    report: &mut String,
    (sym, plane_secs): (&SymmetryPlane, f64),
    midline: &MidLine,
    volume: &Volume,
    cfg: &DefectConfig,
) {
    let line_plane = Plane3::from_midline(midline);
    let [nx, ny, nz] = sym.plane.normal;
    let _ = writeln!(
        report,
        "Mid-sagittal plane by trimmed ICP of the bone surface to its mirror image: normal ({nx:.4}, {ny:.4}, {nz:.4}), offset {:.2} mm; residual RMS {:.3} mm over {} kept pairs after {} iterations ({plane_secs:.1} s). Against the per-slice midline (x = {:.2} mm at y = {:.2} mm, tilt {:.2}°, parallel to the slice axis): {:.2}° apart; roll (out of the axial plane) {:.2}°.\n",
        sym.plane.offset,
        sym.rms_mm,
        sym.pairs,
        sym.iterations,
        midline.point.x,
        midline.point.y,
        midline.tilt_deg(),
        sym.plane.angle_deg(&line_plane),
        nz.asin().to_degrees(),
    );
    for z in [56usize, 70, 84, 92, 98] {
        let k = (z - cfg.first_z) as f64 * volume.spacing.z;
        if let Some(t) = sym.plane.trace(k, midline.point) {
            let _ = writeln!(
                report,
                "- z = {z}: the plane's trace is x = {:.2} mm at y = {:.2} mm, tilt {:.2}° ({:+.2} mm from the per-slice midline there)",
                t.x_at(midline.point.y),
                midline.point.y,
                t.tilt_deg(),
                t.x_at(midline.point.y) - midline.x_at(midline.point.y)
            );
        }
    }
    let _ = writeln!(report);
}

/// The cases of `val`'s 3D validation patches (`quick`: the first range and
/// two positions), each position also at 15 mm, and the vertex case of
/// issue 56.
fn cases(val: &Validation3dSpec, quick: bool) -> Vec<Case3d> {
    let mut cases = Vec::new();
    let ranges = if quick {
        &val.ranges[..1]
    } else {
        &val.ranges[..]
    };
    let positions = if quick {
        &val.positions[..2]
    } else {
        &val.positions[..]
    };
    for &range in ranges {
        for &position_deg in positions {
            for &width_mm in &val.widths {
                cases.push(Case3d {
                    range,
                    position_deg,
                    width_mm,
                });
            }
            // Small defects: 15 mm.
            cases.push(Case3d {
                range,
                position_deg,
                width_mm: 15.0,
            });
        }
    }
    // The vertex case of issue 56 (z = 90–100, 95°, 45 mm).
    cases.push(Case3d {
        range: (90, 100),
        position_deg: 95.0,
        width_mm: 45.0,
    });
    cases
}

/// The named cases of `rows`: the 15 mm defects and the vertex patch.
fn named_cases(report: &mut String, rows: &[ComparisonRow]) {
    let _ = writeln!(report, "\n## Named cases\n");
    for r in rows
        .iter()
        .filter(|r| r.case.width_mm == 15.0 || r.case.range == (90, 100))
    {
        let _ = writeln!(
            report,
            "- {}–{} at {}°, {} mm ({}), {}: {}",
            r.case.range.0,
            r.case.range.1,
            r.case.position_deg,
            r.case.width_mm,
            r.region,
            r.template,
            match &r.metrics {
                Ok(m) => format!(
                    "Dice {:.3}, bDSC {:.3}, HD95 {:.2} mm ({})",
                    m.dice,
                    m.boundary_dice,
                    m.hd95,
                    m.template_source_name()
                ),
                Err(e) => format!("not built: {e}"),
            }
        );
    }
}
