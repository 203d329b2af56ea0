//! The 3D validation's table `validation_3d.csv` and its section of
//! `report.md`: medians by method and width, and the paired tests of the
//! curve fit against the baselines.

use std::fmt::Write as _;

use super::pipeline::ImplantError;
use super::spec::Validation3dSpec;
use super::tables::{medians_by_width, paired_from, paired_table, r};
use super::validation3d::{Metrics3d, Row3d};
use crate::files::csv_bytes;
use crate::markdown::{self, Alignment};
use crate::stats::{holm_bonferroni, median};

/// `validation_3d.csv`: one row per case × method × run.
pub fn validation_3d_csv(rows: &[Row3d]) -> Vec<u8> {
    let header = [
        "z_first",
        "z_last",
        "position_deg",
        "width_mm",
        "method",
        "run",
        "seed",
        "status",
        "dice",
        "boundary_dice",
        "hd95_mm",
        "truth_voxels",
        "implant_voxels",
        "error",
    ];
    let rows = rows.iter().map(|row| {
        let mut v = vec![
            row.case.range.0.to_string(),
            row.case.range.1.to_string(),
            r(row.case.position_deg),
            r(row.case.width_mm),
            row.method.clone(),
            row.run.to_string(),
            row.seed.to_string(),
        ];
        match &row.metrics {
            Ok(m) => {
                v.push("ok".into());
                v.extend([m.dice, m.boundary_dice, m.hd95].map(r));
                v.extend([m.truth_voxels, m.implant_voxels].map(|n| n.to_string()));
                v.push(String::new());
            }
            Err(e) => {
                v.push("error".into());
                v.extend(std::iter::repeat_n(String::new(), 5));
                v.push(e.to_string());
            }
        }
        v
    });
    csv_bytes(&header, rows)
}

/// A 3D metric: name, accessor, larger is better.
type Metric3d = (&'static str, fn(&Metrics3d) -> f64, bool);

/// The 3D metrics, in table order.
const METRICS_3D: [Metric3d; 3] = [
    ("DSC", |m| m.dice, true),
    ("boundary DSC", |m| m.boundary_dice, true),
    ("HD95 mm", |m| m.hd95, false),
];

/// The methods of the rows, baselines first.
fn methods(val: &Validation3dSpec) -> Vec<String> {
    let mut m: Vec<String> = vec!["template".into(), "straight".into()];
    m.extend(val.methods.iter().map(|x| format!("curve:{}", x.name())));
    m
}

/// The "3D validation" section of `report.md`.
pub fn validation_3d_report(
    report: &mut String,
    val: &Validation3dSpec,
    rows: &[Row3d],
) -> Result<(), ImplantError> {
    let failed = rows.iter().filter(|r| r.metrics.is_err()).count();
    let _ = writeln!(report, "## 3D validation (patches across slices)\n");
    let _ = writeln!(
        report,
        "Slice ranges {:?}, positions {:?}°, widths {:?} mm (at the middle slice; elliptical patches), {} runs per stochastic method; the whole pipeline reconstructs each patch, its voxels are scored in 3D (boundary DSC within {} mm of the defective skull, HD95 on the voxel surfaces). {} rows, {failed} failed (see `validation_3d.csv`, column `error`).\n",
        val.ranges, val.positions, val.widths, val.runs, val.margin_mm, rows.len()
    );
    let header: Vec<String> = std::iter::once("method".to_string())
        .chain(
            METRICS_3D
                .iter()
                .flat_map(|(name, _, _)| val.widths.iter().map(move |w| format!("{name} {w} mm"))),
        )
        .collect();
    let table: Vec<Vec<String>> = methods(val)
        .iter()
        .map(|m| {
            let mut line = vec![m.clone()];
            for (_, f, _) in METRICS_3D {
                line.extend(medians_by_width(rows, m, &val.widths, |r| {
                    let v = r.metrics.as_ref().ok().map(f)?;
                    Some((r.method.as_str(), r.case.width_mm, v))
                }));
            }
            line
        })
        .collect();
    let _ = writeln!(report, "Medians over cases and runs:\n");
    report.push_str(&markdown::table(&header, &table, Alignment::Unmarked));
    let _ = writeln!(report);
    paired_tests_3d(report, val, rows)
}

/// Per case, the median of `method`'s finite values of a metric (cases in
/// row order).
fn per_case(rows: &[Row3d], method: &str, f: fn(&Metrics3d) -> f64) -> Vec<(String, f64)> {
    let mut keys: Vec<String> = Vec::new();
    for r in rows {
        let k = format!("{:?}", r.case);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    keys.into_iter()
        .filter_map(|k| {
            let v: Vec<f64> = rows
                .iter()
                .filter(|r| r.method == method && format!("{:?}", r.case) == k)
                .filter_map(|r| r.metrics.as_ref().ok().map(f))
                .filter(|x| x.is_finite())
                .collect();
            (!v.is_empty()).then(|| (k, median(&v)))
        })
        .collect()
}

/// The paired tests of every curve method against both baselines on every
/// 3D metric, Holm-corrected over the table.
fn paired_tests_3d(
    report: &mut String,
    val: &Validation3dSpec,
    rows: &[Row3d],
) -> Result<(), ImplantError> {
    let mut tests = Vec::new();
    for cm in val.methods.iter().map(|m| format!("curve:{}", m.name())) {
        for base in ["template", "straight"] {
            for (name, f, larger) in METRICS_3D {
                let (c, b) = (per_case(rows, &cm, f), per_case(rows, base, f));
                let pairs: Vec<(f64, f64)> = c
                    .iter()
                    .filter_map(|(k, x)| b.iter().find(|(kb, _)| kb == k).map(|(_, y)| (*x, *y)))
                    .collect();
                let (xs, ys): (Vec<f64>, Vec<f64>) = pairs.into_iter().unzip();
                tests.push(paired_from((&cm, base, name), &xs, &ys, larger));
            }
        }
    }
    let p: Vec<f64> = tests
        .iter()
        .map(|t| if t.p.is_finite() { t.p } else { 1.0 })
        .collect();
    let holm = holm_bonferroni(&p)?;
    let _ = writeln!(
        report,
        "Paired by case (curve = median over its runs), two-sided Wilcoxon signed-rank, Holm over the table:\n"
    );
    report.push_str(&paired_table(&tests, &holm));
    let _ = writeln!(report);
    Ok(())
}
