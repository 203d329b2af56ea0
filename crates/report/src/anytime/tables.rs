//! The anytime tables rendered from the computed rows: the aRT to each
//! target and the fraction of targets reached at three budgets.

use super::super::best2009::Best2009;
use super::super::data::Dataset;
use super::super::format::{csv_real, evaluations, percent, pow_tick, Table};
use super::{art_rows, reached_rows, ArtRow, ReachedRow, Who, READ_AT};

/// The targets shown in the Markdown table (all are in the CSV file).
const SHOWN: [f64; 6] = [1e2, 1e0, 1e-2, 1e-4, 1e-6, 1e-8];

/// The aRT table ([`art_rows`]): six targets in `report.md`, every target
/// in `tables/art_targets.csv`; `None` when no run has hits.
pub(crate) fn art_table(ds: &Dataset, targets: &[f64], best: &[Best2009]) -> Option<Table> {
    let rows = art_rows(ds, targets, best)?;
    let shown: Vec<usize> = SHOWN
        .iter()
        .filter_map(|s| targets.iter().position(|t| (t / s - 1.0).abs() < 1e-9))
        .collect();
    let mut t = art_frame(targets, best, &shown);
    for row in &rows {
        art_row(ds, targets, &shown, row, &mut t);
    }
    Some(t)
}

/// The aRT table's title, paragraph and headers, without rows.
fn art_frame(targets: &[f64], best: &[Best2009], shown: &[usize]) -> Table {
    Table {
        stem: "art_targets".into(),
        title: "Average runtime to each target".into(),
        intro: vec![format!(
            "COCO's average runtime aRT (evaluations of all runs until they reached the \
             target, or until they ended, divided by the number of runs that reached it; \
             — when none did) to the target precisions Δf above f*, per algorithm and \
             function, pooled over instances and budgets. The table shows six of the {} \
             targets; tables/art_targets.csv has all of them.{}",
            targets.len(),
            best.iter()
                .map(|b| format!(
                    " The row {} is {}, the smallest aRT any of them reached on the \
                     function ({}; beyond the thesis).",
                    b.label, b.what, b.source
                ))
                .chain((!best.is_empty()).then(|| {
                    " In the CSV file a reference's `runs` and `reached` are those of \
                     the algorithm that was best for the target."
                        .to_owned()
                }))
                .collect::<String>()
        )],
        md_header: ["Function", "D", "Transform", "Algorithm"]
            .map(String::from)
            .into_iter()
            .chain(shown.iter().map(|&i| format!("aRT Δf={:.0e}", targets[i])))
            .collect(),
        csv_header: [
            "function",
            "dim",
            "transform",
            "algorithm",
            "kind",
            "params",
            "target",
            "runs",
            "reached",
            "art",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// The shown name and the CSV (algorithm, kind, params) of a row's owner.
fn names(ds: &Dataset, who: Who<'_>) -> (String, [String; 3]) {
    match who {
        Who::Cell(c) => {
            let cell = &ds.cells[c];
            (
                cell.name.clone(),
                [cell.label.clone(), cell.kind.clone(), cell.params.clone()],
            )
        }
        Who::Reference(b) => (
            b.label.to_owned(),
            [
                b.label.to_owned(),
                "reference".to_owned(),
                b.source.to_owned(),
            ],
        ),
    }
}

/// Adds one aRT row: a Markdown row of the shown targets and a CSV row per
/// target.
fn art_row(ds: &Dataset, targets: &[f64], shown: &[usize], row: &ArtRow<'_>, t: &mut Table) {
    let (name, [algorithm, kind, params]) = names(ds, row.who);
    let mut md = vec![
        row.function.clone(),
        row.dim.to_string(),
        row.transform.clone(),
        name,
    ];
    md.extend(shown.iter().map(|&i| evaluations(row.points[i].art)));
    t.md_rows.push(md);
    for (target, point) in targets.iter().zip(&row.points) {
        t.csv_rows.push(vec![
            row.function.clone(),
            row.dim.to_string(),
            row.transform.clone(),
            algorithm.clone(),
            kind.clone(),
            params.clone(),
            csv_real(*target),
            point.runs.to_string(),
            point.reached.to_string(),
            point.art.map_or_else(|| "inf".into(), csv_real),
        ]);
    }
}

/// The targets-reached table ([`reached_rows`]); `None` when the campaign
/// is not all bbob functions covered by the references, or no run has hits.
pub(crate) fn reached_table(ds: &Dataset, targets: &[f64], best: &[Best2009]) -> Option<Table> {
    let rows = reached_rows(ds, targets, best)?;
    let mut t = reached_frame(targets, best);
    for row in &rows {
        reached_row(ds, row, &mut t);
    }
    Some(t)
}

/// The targets-reached table's title, paragraph and headers, without rows.
fn reached_frame(targets: &[f64], best: &[Best2009]) -> Table {
    Table {
        stem: "targets_reached".into(),
        title: "Targets reached at 10²·D, 10³·D and 10⁴·D evaluations".into(),
        intro: vec![format!(
            "The fraction of (function, target) pairs reached within 10²·D, 10³·D and \
             10⁴·D evaluations, over the {n} targets Δf = 10² … 10⁻⁸ and the functions of \
             the campaign at each D: for an algorithm, the fraction of its (run, target) \
             pairs over all instances (the height of its runtime ECDF there); for {label}, \
             the fraction of (function, target) pairs whose aRT is within the budget, as \
             cocopp draws the reference's ECDF. — where the runs' budget is smaller.{refs}",
            n = targets.len(),
            label = best
                .iter()
                .map(|b| b.label)
                .collect::<Vec<_>>()
                .join(" and "),
            refs = best
                .iter()
                .map(|b| format!(
                    " {} is {} ({}), beyond the thesis.",
                    b.label, b.what, b.source
                ))
                .collect::<String>(),
        )],
        md_header: ["D", "Algorithm", "functions"]
            .map(String::from)
            .into_iter()
            .chain(
                READ_AT
                    .iter()
                    .map(|&m| format!("at {}·D", pow_tick((m as f64).log10()))),
            )
            .collect(),
        csv_header: [
            "dim",
            "algorithm",
            "kind",
            "functions",
            "evaluations_per_dim",
            "pairs",
            "reached",
            "fraction",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// Adds one targets-reached row: a Markdown row of the fractions and a CSV
/// row per budget the runs reached.
fn reached_row(ds: &Dataset, row: &ReachedRow<'_>, t: &mut Table) {
    let (label, kind) = match row.who {
        Who::Cell(c) => (ds.cells[c].label.clone(), ds.cells[c].kind.clone()),
        Who::Reference(b) => (b.label.to_owned(), "reference".to_owned()),
    };
    let d = row.dim.to_string();
    let mut md = vec![d.clone(), label.clone(), row.functions.to_string()];
    md.extend(
        row.counts
            .iter()
            .map(|c| c.map_or_else(|| "—".to_owned(), |(r, n)| percent(r as f64 / n as f64))),
    );
    t.md_rows.push(md);
    for (&m, c) in READ_AT.iter().zip(&row.counts) {
        let Some((reached, pairs)) = c else { continue };
        t.csv_rows.push(vec![
            d.clone(),
            label.clone(),
            kind.clone(),
            row.functions.to_string(),
            m.to_string(),
            pairs.to_string(),
            reached.to_string(),
            csv_real(*reached as f64 / *pairs as f64),
        ]);
    }
}
