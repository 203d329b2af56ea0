//! The verdict sections shared by the chapter-6 validations: the families
//! of verdict rows (curve fits against both baselines, per metric, at scope
//! `all` and per width), their design text, tables and `verdicts.csv`.

use std::fmt::Write as _;

use super::plausibility::FAILURE_DISTANCE_MM;
use super::units::{
    case_differences, decide_families, scoped_rows, Comparison, ImplantRopes, Observation,
    SliceCluster,
};
use crate::files::csv_bytes;
use crate::markdown::{self, Alignment};
use crate::reconstruction::Method;
use crate::stats::{median, smallest_signed_rank_p, VerdictRow, VERDICT_COLUMNS};
use metabezier_plot::format::{effect_interval, posterior};

/// The `table` of the one-slice validation's rows in `verdicts.csv`.
pub const VALIDATION_2D_TABLE: &str = "validation-2d";

/// The `table` of the one-slice validation's verdicts without its
/// implausible rows.
pub const VALIDATION_2D_PLAUSIBLE_TABLE: &str = "validation-2d-plausible";

/// The `table` of the 3D validation's rows in `verdicts.csv`.
pub const VALIDATION_3D_TABLE: &str = "validation-3d";

/// The `table` of the 3D validation's verdicts without its implausible
/// rows.
pub const VALIDATION_3D_PLAUSIBLE_TABLE: &str = "validation-3d-plausible";

/// `verdicts.csv`: every verdict row of the validations, in the columns
/// [`VERDICT_COLUMNS`] shared with `metabezier report`.
pub fn verdicts_csv(rows: &[VerdictRow]) -> Vec<u8> {
    csv_bytes(&VERDICT_COLUMNS, rows.iter().map(VerdictRow::csv_fields))
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
/// verdict (an "undecided" over no unit would read as a finding); returns
/// whether that is so.
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

/// The verdict tables of both readings of the implausible rows
/// ([`super::plausibility::Reading`]): what they make of them, the tables
/// that read them as failures, and, where any row is implausible, the
/// tables `without` them (already decided, in table `without.0`). Returns
/// every verdict row, the primary reading's first.
pub(crate) fn both_readings(
    report: &mut String,
    (implausible, rows): (usize, usize),
    verdicts: Vec<(VerdictRow, usize)>,
    without: Option<(&str, Vec<(VerdictRow, usize)>)>,
) -> Vec<VerdictRow> {
    let _ = writeln!(report, "{}\n", implausible_text(implausible, rows));
    verdict_tables(report, &verdicts, "`verdicts.csv`");
    let mut out: Vec<VerdictRow> = verdicts.into_iter().map(|v| v.0).collect();
    if let Some((table, w)) = without {
        let _ = writeln!(report, "The same verdicts without the {implausible} implausible rows (table `{table}` of `verdicts.csv`):\n");
        verdict_tables(report, &w, "`verdicts.csv`");
        out.extend(w.into_iter().map(|v| v.0));
    }
    out
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
    (alpha, ropes): (f64, ImplantRopes),
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
                    rope: ropes.of(measure),
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
        format!(" Here p_min = {p_min:.3} ≥ α = {alpha}: no row can reject, whatever the data; no verdict can be `better` or `worse` by design, only `equivalent` (the Bayesian signed-rank test) or `undecided`.")
    } else {
        String::new()
    };
    format!(
        "{} × {} = **{units}: the effective n** (the {cases} cases are pooled into them). Per case d = the curve fit's median over its runs − the baseline's value; a unit's summary is the median of d over its cases ({within}; in a `width_mm=…` scope only the cases of that width). Two-sided Wilcoxon signed-rank test of the unit summaries against zero (`stats::across_units`), Holm-corrected within each family: the {family} rows of one scope. With n non-zero units no p can fall below p_min = 2/2ⁿ ({units}: {p_min:.2e}), which bounds every p. Beside it, the Hodges–Lehmann estimate of the unit summaries with its exact 95 % interval, and the Bayesian signed-rank test (Benavoli et al. 2017) with a region of practical equivalence (rope) per metric. A verdict is `equivalent` where P(rope) ≥ 0.95, `better` or `worse` where the Holm-corrected p is below α = {alpha}, `undecided` otherwise (no detectable difference, which is not equality).{unreachable} `better/equal/worse` count units; `cases better` counts cases where the curve fit is strictly better and is a description, not a test. Every row is in `verdicts.csv`.",
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

/// The cells of verdict row `v` in its scope's table (see
/// [`verdict_tables`]), `cases_better` the cases favouring the compared
/// method.
fn verdict_row(v: &VerdictRow, cases_better: usize) -> Vec<String> {
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
        effect_interval(v.shift.estimate, v.shift.low, v.shift.high),
        format!("±{}", v.equivalence.rope),
        posterior(
            v.equivalence.better,
            v.equivalence.within,
            v.equivalence.worse,
        ),
        v.verdict.to_string(),
        format!("{cases_better}/{}", v.problems),
    ]
}

/// The pivot's cell of verdict row `v`: its verdict (abbreviated) and
/// the units better/equal/worse.
fn pivot_cell(v: &VerdictRow) -> String {
    let a = &v.across;
    let word = match v.verdict.as_str() {
        "undecided" => "und.",
        "equivalent" => "equiv.",
        w => w,
    };
    format!("{word} {}/{}/{}", a.better, a.equal, a.worse)
}

/// One markdown table of verdict rows per scope, with the cases favouring
/// the compared method (descriptive); the pivot below them says every row
/// is kept in `kept_in` (`verdicts.csv`, or "the table above").
pub(crate) fn verdict_tables(report: &mut String, rows: &[(VerdictRow, usize)], kept_in: &str) {
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
        "HL [95 % CI]",
        "rope",
        "P(better/≈/worse)",
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
            .map(|(v, cases_better)| verdict_row(v, *cases_better))
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
                    .map_or_else(|| "—".to_owned(), |(v, _)| pivot_cell(v))
            }));
            row
        })
        .collect();
    let _ = writeln!(
        report,
        "Per scope (verdict and units better/equal/worse; und. = undecided, equiv. = equivalent; \
         every p and effect is in {kept_in}):\n"
    );
    report.push_str(&markdown::table(&pivot_header, &pivot, Alignment::Unmarked));
    let _ = writeln!(report);
}
