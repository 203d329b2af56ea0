//! The descriptive table rendered from the statistics of every (cell,
//! problem): three significant digits in `report.md`, full precision in
//! `tables/descriptive.csv`.

use super::super::data::Dataset;
use super::super::format::{csv_opt, evaluations, percent, sci, sci_opt, Table};
use super::{shown_error, CellStats};

/// The empty descriptive table, with its headers and first paragraph.
fn frame() -> Table {
    Table {
        stem: "descriptive".into(),
        title: "Final error and success per algorithm and problem".into(),
        intro: vec![
            "Final error f − f* over the independent runs: best (minimum), worst \
             (maximum), mean, sample standard deviation (n − 1) and median. SR is the \
             success rate (runs with f − f* ≤ threshold); \"evals to success\" is the mean \
             number of evaluations to reach the threshold over the successful runs; aRT is \
             COCO's average runtime, the evaluations of all runs (to the first success for \
             a successful run, all for an unsuccessful one) divided by the number of \
             successes (— when no run succeeded, i.e. infinite)."
                .into(),
        ],
        md_header: [
            "Problem",
            "D",
            "Algorithm",
            "Runs",
            "Best",
            "Worst",
            "Mean",
            "SD",
            "Median",
            "SR",
            "Evals to success",
            "aRT",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "dim",
            "algorithm",
            "kind",
            "params",
            "runs",
            "best",
            "worst",
            "mean",
            "sd",
            "median",
            "q1",
            "q3",
            "successes",
            "success_rate",
            "mean_evaluations_to_success",
            "aRT",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// The descriptive table's Markdown in a fitting campaign's vocabulary:
/// the error is E, `D` is the number of segments, and the success columns
/// (fitting has no target) are left to the CSV.
fn fitting_vocabulary(t: &mut Table) {
    t.title = "Final fitting error E per method and problem".into();
    t.intro = vec![
        "Final fitting error E = Σ|R_i − P_i|² (the orthogonal E, Σ min_s |R_i − P(s)|², for \
         problems named /orthogonal) over the independent runs: best (minimum), worst \
         (maximum), mean, sample standard deviation (n − 1) and median; Segments is the \
         number of segments of the fit. RMS and maximum distances in pixels (or font \
         units) are in the fitting section below."
            .into(),
    ];
    let keep = t.md_header.len() - 3;
    t.md_header.truncate(keep);
    t.md_header[1] = "Segments".into();
    t.md_header[2] = "Method".into();
    for row in &mut t.md_rows {
        row.truncate(keep);
    }
}

/// A final error in a table cell ([`shown_error`], three digits).
fn error_cell(x: Option<f64>) -> String {
    sci_opt(x.map(shown_error))
}

/// The descriptive table: one row per (problem, cell).
pub(crate) fn table(ds: &Dataset, stats: &[Vec<Option<CellStats>>]) -> Table {
    let mut t = frame();
    let mut nan = false;
    let mut below = 0.0_f64;
    for (p, problem) in ds.problems.iter().enumerate() {
        for (c, cell) in ds.cells.iter().enumerate() {
            let Some(Some(s)) = stats.get(p).and_then(|row| row.get(c)) else {
                continue;
            };
            nan |= s.summary.is_none();
            let sm = s.summary.as_ref();
            let sc = s.success.as_ref();
            if let Some(x) = sm {
                if shown_error(x.best) != x.best {
                    below = below.min(x.best);
                }
            }
            t.md_rows.push(vec![
                problem.short(),
                problem.dim.to_string(),
                cell.name.clone(),
                s.runs.to_string(),
                error_cell(sm.map(|x| x.best)),
                error_cell(sm.map(|x| x.worst)),
                error_cell(sm.map(|x| x.mean)),
                sci_opt(sm.and_then(|x| x.std_dev)),
                error_cell(sm.map(|x| x.median)),
                sc.map_or_else(|| "\u{2014}".into(), |x| percent(x.success_rate)),
                evaluations(sc.and_then(|x| x.mean_evaluations_to_success)),
                evaluations(sc.and_then(|x| x.average_runtime)),
            ]);
            t.csv_rows.push(vec![
                problem.label(),
                problem.dim.to_string(),
                cell.label.clone(),
                cell.kind.clone(),
                cell.params.clone(),
                s.runs.to_string(),
                csv_opt(sm.map(|x| x.best)),
                csv_opt(sm.map(|x| x.worst)),
                csv_opt(sm.map(|x| x.mean)),
                csv_opt(sm.and_then(|x| x.std_dev)),
                csv_opt(sm.map(|x| x.median)),
                csv_opt(sm.map(|x| x.q1)),
                csv_opt(sm.map(|x| x.q3)),
                sc.map_or_else(String::new, |x| x.successes.to_string()),
                csv_opt(sc.map(|x| x.success_rate)),
                csv_opt(sc.and_then(|x| x.mean_evaluations_to_success)),
                csv_opt(sc.and_then(|x| x.average_runtime)),
            ]);
        }
    }
    if ds.fitting_only() {
        fitting_vocabulary(&mut t);
    }
    if nan {
        t.intro
            .push("Some final errors are NaN: their summaries are left empty (—).".into());
    }
    if below < 0.0 {
        t.intro.push(format!(
            "Some runs end below the tabulated optimum, by at most {} (the rounding of f \
             at the optimum in floating point, or of the tabulated f*): such errors are \
             shown as 0 here, and kept as they are in the CSV and in runs.csv.",
            sci(-below)
        ));
    }
    t.intro.push(format!(
        "SD is — for a single run; numbers are rounded to three significant digits \
         here ({} rows; full precision in the CSV).",
        t.md_rows.len()
    ));
    t
}

/// A "mean (sd)" cell for the paper-style comparison table.
pub(crate) fn mean_sd(s: Option<&CellStats>) -> String {
    match s.and_then(|s| s.summary.as_ref()) {
        None => "\u{2014}".into(),
        Some(x) => match x.std_dev {
            Some(sd) => format!("{} ({})", sci(x.mean), sci(sd)),
            None => sci(x.mean),
        },
    }
}
