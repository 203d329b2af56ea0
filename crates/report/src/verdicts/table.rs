//! The verdicts rendered: the cells the report and the summary show of a
//! verdict row, and the `verdicts` table.

use crate::stats::{VerdictRow, VERDICT_COLUMNS};

use super::super::format::{effect, effect_interval, p_value, posterior, sci, Table};

/// A verdict in a table cell: `better (6/0/2, p_Holm 0.012, HL -0.30)`.
pub(crate) fn short(r: &VerdictRow) -> String {
    format!(
        "{} ({}/{}/{}, p_Holm {}, HL {})",
        r.verdict,
        r.across.better,
        r.across.equal,
        r.across.worse,
        p_value(r.p_adjusted),
        effect(r.shift.estimate)
    )
}

/// The row's Hodges–Lehmann estimate and 95 % interval in a cell.
fn interval_cell(r: &VerdictRow) -> String {
    effect_interval(r.shift.estimate, r.shift.low, r.shift.high)
}

/// The row's posterior P(better)/P(rope)/P(worse) in a cell.
fn posterior_cell(r: &VerdictRow) -> String {
    let e = &r.equivalence;
    posterior(e.better, e.within, e.worse)
}

/// The `verdicts` table: every verdict row, with its Markdown rendering.
pub(crate) fn table(rows: &[VerdictRow], unit_noun: &str, alpha: f64) -> Table {
    let mut t = Table {
        stem: "verdicts".into(),
        title: "Verdicts across problems".into(),
        intro: vec![
            format!(
                "Every verdict across problems, from a test whose units are independent \
                 {unit_noun}s. A problem's summary is, for the final error, log10 of the ratio \
                 of the two median errors (floored at the success threshold, so two solved \
                 problems give 0) and, for the anytime measure, the difference of the median \
                 areas under the runs' target ECDFs; the problems of a {unit_noun} within the \
                 scope are summarised by their median. wilcoxon-signed-rank: the Wilcoxon \
                 signed-rank test of the per-{unit_noun} summaries against zero, Holm-corrected \
                 over the rows of one table, measure and scope; friedman-holm and \
                 friedman-finner: Friedman's test over the {unit_noun}s with the z-test of \
                 average ranks against the reference, Holm- or Finner-corrected."
            ),
            format!(
                "better/equal/worse count the {unit_noun}s whose summary favours the algorithm, \
                 is exactly zero, or favours the reference; effect is the median summary, and \
                 HL [95 % CI] the Hodges–Lehmann estimate of the summaries (the median of their \
                 Walsh averages) with its exact signed-rank 95 % confidence interval (Hollander, \
                 Wolfe & Chicken 2014, §3.3; ∞ where {unit_noun}s are too few for one). \
                 P(better/≈/worse) is the posterior of the Bayesian signed-rank test (Benavoli, \
                 Corani, Demšar & Zaffalon 2017; 50,000 seeded samples, prior 0.5 at 0) with the \
                 region of practical equivalence (rope) in the rope column: ±0.3 decades of the \
                 error ratio and ±0.05 of the anytime AUC unless the spec's [report] or --rope \
                 says otherwise. The verdict is decided in this order: equivalent where \
                 P(rope) ≥ 0.95, even where a tiny difference is significant; better or worse \
                 where the corrected p is below α = {alpha}; otherwise undecided (the test did \
                 not reject: no detectable difference, which is not a verdict of equality). \
                 p_min is the smallest p the number of units allows (2/2ⁿ for the signed-rank \
                 test with n non-zero units), and family is the number of rows corrected \
                 together: no adjusted p can fall below family × the family's smallest p_min, \
                 so where that product is at least α no verdict of the family can be better or \
                 worse by construction."
            ),
        ],
        md_header: [
            "Table",
            "Measure",
            "Algorithm",
            "Reference",
            "Scope",
            "Test",
            "Units +/=/−",
            "Effect",
            "HL [95 % CI]",
            "p",
            "p (adjusted)",
            "p_min",
            "Family",
            "Rope",
            "P(better/≈/worse)",
            "Verdict",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: VERDICT_COLUMNS.map(String::from).to_vec(),
        ..Table::default()
    };
    for r in rows {
        t.csv_rows.push(r.csv_fields());
        t.md_rows.push(vec![
            r.table.clone(),
            r.measure.clone(),
            r.algorithm.clone(),
            r.reference.clone(),
            r.scope.clone(),
            r.test.as_str().to_owned(),
            format!("{}/{}/{}", r.across.better, r.across.equal, r.across.worse),
            sci(r.across.effect_size),
            interval_cell(r),
            p_value(r.across.p_value),
            p_value(r.p_adjusted),
            p_value(r.across.p_min),
            r.family.to_string(),
            effect(r.equivalence.rope),
            posterior_cell(r),
            r.verdict.to_string(),
        ]);
    }
    t
}
