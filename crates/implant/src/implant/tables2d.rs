//! The one-slice validation's table `validation.csv` and its section of
//! `report.md`: medians by method and width, by region, and the verdicts of
//! the curve fit against the baselines across independent units
//! ([`super::units`]); its implausible rows read as failures
//! ([`super::plausibility::Reading`]).

use std::fmt::Write as _;

use super::plausibility::{check_columns, check_fields, describe, Reading};
use super::regions::{region_tables, RegionRow};
use super::spec::ValidationSpec;
use super::tables::r;
use super::tables3d::position_unit_text;
use super::units::{
    position_extents, position_units, slice_clusters_within, unit_position, within_gap,
    Observation, SliceCluster,
};
use super::validation::{CaseMetrics, ValidationRow};
use super::verdict_tables::{
    both_readings, cluster_list, decided_rows, design_text, family_size, medians_by_width,
    no_case_built, unit_count, units_observed, REGION_TEXT, VALIDATION_2D_PLAUSIBLE_TABLE,
    VALIDATION_2D_TABLE,
};
use crate::files::csv_bytes;
use crate::markdown::{self, Alignment};
use crate::stats::{median, VerdictRow};

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
            if let Some(u) = unit_position(units, r.case.position_deg) {
                o.unit.position_deg = u;
            }
            Some(o)
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
    let extents = position_extents(
        &val.positions,
        rows.iter().map(|r| (r.case.position_deg, r.half_width_deg)),
    );
    let units = position_units(&extents);
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
        decided_rows(
            table,
            &val.methods,
            &METRICS,
            obs,
            &val.widths,
            (val.alpha, val.ropes),
        )
    };
    let verdicts = decide(VALIDATION_2D_TABLE, &obs);
    let without = (implausible > 0).then(|| {
        let w = decide(VALIDATION_2D_PLAUSIBLE_TABLE, &read(Reading::Without));
        (VALIDATION_2D_PLAUSIBLE_TABLE, w)
    });
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
        position_unit_text(&extents, &units),
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
    both_readings(report, (implausible, rows.len()), verdicts, without)
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
