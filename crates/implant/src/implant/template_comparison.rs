//! The four templates compared by region (issue 56): the slice-wise
//! template (the mirror per slice, and the continuation across the
//! midline: `template_source = "auto"`, as shipped), the 3D mirror
//! (`mirror3d`), the rim fill (`rim`) and the straight bridge, on 3D
//! artificial defects ([`super::validation3d`]), each scored by Dice and
//! HD95 against the removed bone.
//!
//! The walls are fitted by Levenberg–Marquardt (deterministic: one run per
//! case and template). The verdicts are the validation's: one unit per
//! defect position on a slice cluster ([`super::units`]), the median of a
//! unit's case differences tested across units by the Wilcoxon
//! signed-rank test, Holm's correction over the rows of one scope (one
//! region, or `all`), the effective number of units and the smallest
//! attainable p-value `p_min` stated with each row
//! ([`super::units::verdict_row`]).

use std::fmt::Write as _;

use super::pipeline::{DefectConfig, ImplantError};
use super::regions::{region_tables, Region, RegionRow};
use super::units::{
    case_differences, decide_families, range_clusters, verdict_row, Comparison, ImplantRopes,
    Observation,
};
use super::validation3d::{evaluate_3d, prepare_case_3d, Case3d, Metrics3d};
use super::verdict_tables::verdict_tables;
use super::wall::WallKind;
use super::wall_input::TemplateChoice;
use crate::ct::{MidLine, Plane3, Volume};
use crate::fit::LmSolver;
use crate::stats::VerdictRow;

/// The templates compared: their name in the tables, the template choice
/// and the wall kind.
pub const TEMPLATES: [(&str, TemplateChoice, WallKind); 4] = [
    ("slice", TemplateChoice::Auto, WallKind::CurveFit),
    ("mirror3d", TemplateChoice::Mirror3d, WallKind::CurveFit),
    ("rim", TemplateChoice::Rim, WallKind::CurveFit),
    ("straight", TemplateChoice::Auto, WallKind::Straight),
];

/// The comparisons tested, `(algorithm, reference)`: each 3D template and
/// the straight bridge against the slice-wise template, and the rim fill
/// against the 3D mirror and the straight bridge.
pub const PAIRS: [(&str, &str); 5] = [
    ("mirror3d", "slice"),
    ("rim", "slice"),
    ("straight", "slice"),
    ("rim", "mirror3d"),
    ("rim", "straight"),
];

/// One case reconstructed with one template.
#[derive(Debug)]
pub struct ComparisonRow {
    /// The case.
    pub case: Case3d,
    /// Its region ([`super::regions`]).
    pub region: Region,
    /// The template's name ([`TEMPLATES`]).
    pub template: &'static str,
    /// The metrics, or why the case was not built.
    pub metrics: Result<Metrics3d, ImplantError>,
}

/// Reconstructs every case with every template ([`TEMPLATES`]) about
/// `midline`, the 3D mirror across `plane`; `region` places a case. A
/// case that cannot be cut is a failed row for every template.
pub fn compare_templates(
    volume: &Volume,
    cfg: &DefectConfig,
    (midline, plane): (MidLine, Plane3),
    cases: &[Case3d],
    region: &dyn Fn(&Case3d) -> Region,
) -> Vec<ComparisonRow> {
    let mut rows = Vec::new();
    for &case in cases {
        let prepared = prepare_case_3d(volume, cfg, case, midline).map_err(std::sync::Arc::new);
        for (template, choice, kind) in TEMPLATES {
            let metrics = match &prepared {
                Ok(p) => {
                    let mut p = p.clone();
                    p.config.wall.template = choice;
                    p.config.plane = Some(plane);
                    evaluate_3d(&p, kind, 10.0, &mut LmSolver::default())
                }
                Err(e) => Err(ImplantError::CaseNotBuilt(e.clone())),
            };
            rows.push(ComparisonRow {
                case,
                region: region(&case),
                template,
                metrics,
            });
        }
    }
    rows
}

/// The measures compared: name, value of a metrics row, lower is better.
type Measure = (&'static str, fn(&Metrics3d) -> f64, bool);

const MEASURES: [Measure; 2] = [
    ("dice", |m: &Metrics3d| m.dice, false),
    ("hd95-mm", |m: &Metrics3d| m.hd95, true),
];

/// The verdict rows of [`PAIRS`] for each measure, at scope `all` and per
/// region (`region=<name>`), decided at `alpha` (Holm over each scope),
/// each with the cases favouring the algorithm (descriptive). A failed
/// reconstruction has no value and leaves its case out of that pair.
pub fn comparison_verdicts(rows: &[ComparisonRow], alpha: f64) -> Vec<(VerdictRow, usize)> {
    let ranges: Vec<(usize, usize)> = rows.iter().map(|r| r.case.range).collect();
    let clusters = range_clusters(&ranges);
    let ropes = ImplantRopes::default();
    let mut scopes: Vec<(String, Option<Region>)> = vec![("all".into(), None)];
    for g in Region::ALL {
        if rows.iter().any(|r| r.region == g) {
            scopes.push((format!("region={}", g.name()), Some(g)));
        }
    }
    let mut out: Vec<(VerdictRow, usize)> = Vec::new();
    for (measure, value, lower) in MEASURES {
        for (scope, region) in &scopes {
            let obs: Vec<Observation<'_>> = rows
                .iter()
                .filter(|r| region.is_none_or(|g| r.region == g))
                .filter_map(|r| {
                    let m = r.metrics.as_ref().ok()?;
                    Some(Observation::at(
                        &clusters,
                        r.case.range,
                        (r.case.position_deg, r.case.width_mm),
                        r.template,
                        value(m),
                    ))
                })
                .collect();
            for (algorithm, reference) in PAIRS {
                let cmp = Comparison {
                    table: "templates-3d",
                    measure,
                    algorithm,
                    reference,
                    lower_is_better: lower,
                    rope: ropes.of(measure),
                };
                let diffs = case_differences(&obs, algorithm, reference);
                let better = diffs
                    .iter()
                    .filter(|d| {
                        if lower {
                            d.difference < 0.0
                        } else {
                            d.difference > 0.0
                        }
                    })
                    .count();
                out.push((verdict_row(&cmp, scope, &diffs), better));
            }
        }
    }
    let mut bare: Vec<VerdictRow> = out.iter().map(|r| r.0.clone()).collect();
    decide_families(&mut bare, alpha);
    out.iter_mut().zip(bare).for_each(|(r, b)| r.0 = b);
    out
}

/// The report of a comparison: the medians by region and template, the
/// cases each template failed, and the verdict tables.
pub fn comparison_report(rows: &[ComparisonRow], verdicts: &[(VerdictRow, usize)]) -> String {
    let mut report = String::new();
    let region_rows: Vec<RegionRow<'_>> = rows
        .iter()
        .filter_map(|r| {
            let m = r.metrics.as_ref().ok()?;
            Some(RegionRow {
                region: r.region,
                method: r.template,
                case: format!(
                    "{}-{}/{}/{}",
                    r.case.range.0, r.case.range.1, r.case.position_deg, r.case.width_mm
                ),
                values: vec![m.dice, m.boundary_dice, m.hd95],
            })
        })
        .collect();
    let methods: Vec<String> = TEMPLATES.iter().map(|t| t.0.to_string()).collect();
    region_tables(
        &mut report,
        &["Dice", "boundary Dice", "HD95 (mm)"],
        &methods,
        &region_rows,
    );
    let _ = writeln!(report, "Cases not built, by template:\n");
    for (t, _, _) in TEMPLATES {
        let failed: Vec<String> = rows
            .iter()
            .filter(|r| r.template == t)
            .filter_map(|r| {
                r.metrics.as_ref().err().map(|e| {
                    format!(
                        "{}–{} at {}° / {} mm: {e}",
                        r.case.range.0, r.case.range.1, r.case.position_deg, r.case.width_mm
                    )
                })
            })
            .collect();
        let _ = writeln!(
            report,
            "- {t}: {}",
            if failed.is_empty() {
                "none".into()
            } else {
                failed.join("; ")
            }
        );
    }
    let _ = writeln!(report);
    verdict_tables(&mut report, verdicts, "the table above");
    report
}
