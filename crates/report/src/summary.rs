//! The `## Summary` that opens a report, written for a reader who opens
//! nothing else: the question, what the number of units allows, the best
//! algorithm per problem, each comparison once with its interval and its
//! equivalence reading (the Friedman post-hoc rows in a table of their
//! own), the best setting of every tuned grid, and links to the figures and
//! to the parts skipped.

use crate::stats::{VerdictRow, VerdictTest};

use super::descriptive::{shown_error, CellStats};
use super::format::{effect, p_value, Table};
use super::{data, markdown, plots::Plot, Sections};

/// The most verdicts the summary lists per measure.
const SUMMARY_VERDICTS: usize = 12;

/// The most verdicts the summary lists at design points (when its scopes
/// pool the errors or the sizes).
const SUMMARY_POINT_VERDICTS: usize = 15;

/// The most problems the summary names one by one; beyond it, the counts
/// of problems each algorithm is best on (one line).
const SUMMARY_PROBLEMS: usize = 6;

/// The summary of report `s` of dataset `ds` answering `question` (and the
/// thesis's claims of the campaign, [`super::claims::section`]), tests at
/// level `alpha`, the success threshold `threshold` (a floor under which
/// two medians tie).
pub(crate) fn summary(
    s: &Sections,
    ds: &data::Dataset,
    (question, claims): (&str, &str),
    alpha: f64,
    threshold: Option<f64>,
) -> String {
    let mut md = String::from("## Summary\n\n");
    md.push_str(&markdown::paragraph(&format!("Question: {question}")));
    md.push_str(claims);
    md.push_str(&best_per_problem(ds, &s.stats, threshold));
    match &s.tests.verdict_table {
        Some(t) => md.push_str(&verdicts(t, &s.tests.verdicts, alpha)),
        None => md.push_str(&markdown::paragraph(
            "There is a single algorithm configuration: there is no verdict to state.",
        )),
    }
    md.push_str(&picks(&s.tuning));
    md.push_str(&figure_links(&s.figures));
    if !s.faults.is_empty() {
        md.push_str(&markdown::paragraph(&format!(
            "Warning: {} figure(s) could not be drawn from these results, which should \
             allow them: {}.",
            s.faults.len(),
            s.faults.join("; ")
        )));
    }
    if !s.notes.is_empty() {
        md.push_str(&markdown::paragraph(&format!(
            "{} part(s) were skipped or limited: see the last section.",
            s.notes.len()
        )));
    }
    md
}

/// The cells with the lowest median final error of problem `p` (several
/// where their medians are equal or both at or below the threshold), with
/// that median; `None` where no cell has a summary.
fn best_of(stats: &[Option<CellStats>], threshold: Option<f64>) -> Option<(Vec<usize>, f64)> {
    let floor = |x: f64| threshold.map_or(x, |t| x.max(t));
    let medians: Vec<(usize, f64)> = stats
        .iter()
        .enumerate()
        .filter_map(|(c, s)| Some((c, s.as_ref()?.summary.as_ref()?.median)))
        .filter(|(_, m)| !m.is_nan())
        .collect();
    let best = medians
        .iter()
        .map(|&(_, m)| floor(m))
        .min_by(f64::total_cmp)?;
    let cells = medians
        .iter()
        .filter(|&&(_, m)| floor(m) == best)
        .map(|&(c, _)| c)
        .collect();
    let raw = medians
        .iter()
        .map(|&(_, m)| m)
        .min_by(f64::total_cmp)
        .unwrap_or(best);
    Some((cells, raw))
}

/// "Best per problem": the algorithm(s) with the lowest median final error
/// on each problem, named one by one for up to [`SUMMARY_PROBLEMS`]
/// problems, else counted per algorithm. A description of the runs, not a
/// verdict.
fn best_per_problem(
    ds: &data::Dataset,
    stats: &[Vec<Option<CellStats>>],
    threshold: Option<f64>,
) -> String {
    if ds.cells.len() < 2 {
        return String::new();
    }
    let best: Vec<(usize, Vec<usize>, f64)> = stats
        .iter()
        .enumerate()
        .filter_map(|(p, row)| best_of(row, threshold).map(|(c, m)| (p, c, m)))
        .collect();
    if best.is_empty() {
        return String::new();
    }
    let names = |cells: &[usize]| -> String {
        let n: Vec<&str> = cells.iter().map(|&c| ds.cells[c].name.as_str()).collect();
        if n.len() == ds.cells.len() {
            "all tie".into()
        } else {
            n.join(", ")
        }
    };
    let floor = threshold.map_or(String::new(), |t| {
        format!("; medians at or below the threshold {} tie", effect(t))
    });
    if best.len() <= SUMMARY_PROBLEMS {
        let each: Vec<String> = best
            .iter()
            .map(|(p, c, m)| {
                format!(
                    "{}: {} ({})",
                    ds.problems[*p].title(),
                    names(c),
                    effect(shown_error(*m))
                )
            })
            .collect();
        return markdown::paragraph(&format!(
            "Best per problem (lowest median final error, its value in brackets{floor}), a \
             description of the runs, not a test: {}.",
            each.join("; ")
        ));
    }
    let mut counts: Vec<(usize, usize)> = (0..ds.cells.len()).map(|c| (c, 0)).collect();
    for (_, cells, _) in &best {
        for &c in cells {
            counts[c].1 += 1;
        }
    }
    counts.sort_by_key(|&(c, n)| (std::cmp::Reverse(n), c));
    let parts: Vec<String> = counts
        .iter()
        .filter(|&&(_, n)| n > 0)
        .map(|&(c, n)| format!("{} on {n}", ds.cells[c].name))
        .collect();
    markdown::paragraph(&format!(
        "Best per problem (lowest median final error{floor}; a problem where several tie \
         counts for each), a description of the runs, not a test: {} of the {} problems \
         (tables/descriptive.csv has every median).",
        parts.join(", "),
        best.len()
    ))
}

/// What the number of units allows: for each family of Wilcoxon rows over
/// all problems whose Holm correction can never reach α (family size ×
/// its smallest p_min ≥ α), one sentence saying so.
fn what_n_allows(rows: &[VerdictRow], alpha: f64) -> String {
    let mut families: Vec<(&str, &str, usize, f64, usize)> = Vec::new();
    for r in rows
        .iter()
        .filter(|r| r.test == VerdictTest::WilcoxonSignedRank && r.scope == "all")
    {
        match families
            .iter_mut()
            .find(|f| f.0 == r.table && f.1 == r.measure)
        {
            Some(f) => {
                f.2 = f.2.max(r.across.units);
                f.3 = f.3.min(r.across.p_min);
            }
            None => families.push((
                &r.table,
                &r.measure,
                r.across.units,
                r.across.p_min,
                r.family,
            )),
        }
    }
    let blocked: Vec<String> = families
        .iter()
        .filter(|f| f.4 as f64 * f.3 >= alpha)
        .map(|f| {
            format!(
                "`{}` on {} ({} unit(s): p_min = {}, family of {}: {} × p_min = {})",
                f.0,
                f.1,
                f.2,
                p_value(f.3),
                f.4,
                f.4,
                p_value(f.4 as f64 * f.3)
            )
        })
        .collect();
    if blocked.is_empty() {
        return String::new();
    }
    markdown::paragraph(&format!(
        "What n allows: with these units no test across problems can reject at α = {alpha}, \
         whatever the data, for {}. Those rows can only be equivalent or undecided; a \
         verdict of better or worse needs more independent units (functions, outlines, \
         segments).",
        blocked.join("; ")
    ))
}

/// The verdict part: what n allows, the Wilcoxon verdicts (each comparison
/// once, decided first), the Friedman post-hoc rows in their own table, and
/// the counts over every scope.
fn verdicts(t: &Table, rows: &[VerdictRow], alpha: f64) -> String {
    let mut md = what_n_allows(rows, alpha);
    let (shown, friedman, (differing, checked)) = summary_tables(t);
    if shown.md_rows.is_empty() {
        md.push_str(&markdown::paragraph("No verdict over all problems."));
        return md;
    }
    let at_points = shown.md_header.iter().any(|h| h == "Scope");
    md.push_str(&markdown::paragraph(if at_points {
        "Verdicts at each design point against the reference, Wilcoxon signed-rank test \
         across units (the fixed and the orthogonal error, and equal segments and equal \
         free parameters, measure different things, so no verdict here pools them). Units \
         +/=/− counts the units that favour the algorithm, tie, or favour the reference; HL \
         is the Hodges–Lehmann estimate of their summaries with its 95 % interval; \
         P(better/≈/worse) is the Bayesian signed-rank posterior (≈: within the rope):"
    } else {
        "Verdicts over all problems against the reference, Wilcoxon signed-rank test across \
         units. Units +/=/− counts the units that favour the algorithm, tie, or favour the \
         reference; HL is the Hodges–Lehmann estimate of their summaries with its 95 % \
         interval; P(better/≈/worse) is the Bayesian signed-rank posterior (≈: within the \
         rope). equivalent: P(≈) ≥ 0.95; better or worse: the corrected test rejects; \
         undecided: neither (no detectable difference is not equality):"
    }));
    md.push_str(&by_measure(&shown));
    if checked > 0 && friedman.md_rows.is_empty() {
        md.push_str(&markdown::paragraph(&format!(
            "Friedman's test with the post-hoc z-test of average ranks against the \
             reference, a check of the same comparisons, gives the same verdict in all {checked} \
             of its rows over all problems."
        )));
    } else if checked > 0 {
        md.push_str(&markdown::paragraph(&format!(
            "Friedman's test with the post-hoc z-test of average ranks against the \
             reference, a check of the same comparisons (not further claims), differs from \
             the Wilcoxon verdict in {differing} of its {checked} rows over all problems{}:",
            if differing > friedman.md_rows.len() {
                format!(" ({} shown)", friedman.md_rows.len())
            } else {
                String::new()
            }
        )));
        md.push_str(&by_measure(&friedman));
    }
    let count = |v: &str| {
        t.md_rows
            .iter()
            .filter(|r| r.last().is_some_and(|x| x == v))
            .count()
    };
    md.push_str(&markdown::paragraph(&format!(
        "{} Wilcoxon verdicts shown of {} rows (all scopes and tests: {} better, {} worse, \
         {} equivalent, {} undecided); all are in tables/verdicts.csv.",
        shown.md_rows.len(),
        t.md_rows.len(),
        count("better"),
        count("worse"),
        count("equivalent"),
        count("undecided")
    )));
    md
}

/// The summary's two verdict tables from the full verdict table `t`: the
/// Wilcoxon rows over all problems (or at the design points when the
/// campaign's scopes pool the errors or the sizes), decided first, at most
/// [`SUMMARY_VERDICTS`] ([`SUMMARY_POINT_VERDICTS`]); and the Friedman
/// post-hoc rows over all problems whose verdict differs from the Wilcoxon
/// row's, with the number of those and of all Friedman rows over all
/// problems.
fn summary_tables(t: &Table) -> (Table, Table, (usize, usize)) {
    let col = |name: &str| t.md_header.iter().position(|h| h == name);
    let scope = col("Scope");
    let verdict = col("Verdict");
    let test = col("Test");
    // Scopes that pool the two errors or the two sizes (equal segments,
    // equal free parameters) pool measures of different things: such a
    // campaign's summary states its verdicts at the design points.
    let pools = |key: &str| {
        scope.is_some_and(|i| t.md_rows.iter().any(|r| r[i].contains(&format!("{key}="))))
    };
    let by_point = pools("error") || pools("size");
    let parts = |r: &Vec<String>| scope.map_or(0, |i| r[i].split(';').count());
    let most = t.md_rows.iter().map(parts).max().unwrap_or(0);
    let is_wilcoxon =
        |r: &Vec<String>| test.is_none_or(|i| r[i] == VerdictTest::WilcoxonSignedRank.as_str());
    let mut keep = vec![
        "Algorithm",
        "Reference",
        "Measure",
        "Units +/=/−",
        "HL [95 % CI]",
        "p (adjusted)",
        "P(better/≈/worse)",
        "Verdict",
    ];
    if by_point {
        keep.insert(2, "Scope");
    }
    let idx: Vec<usize> = keep.iter().filter_map(|k| col(k)).collect();
    let in_scope = |r: &&Vec<String>| match scope {
        Some(i) if by_point => parts(r) == most && r[i] != "all",
        Some(i) => r[i] == "all",
        None => true,
    };
    let mut rows: Vec<&Vec<String>> = t
        .md_rows
        .iter()
        .filter(in_scope)
        .filter(|r| is_wilcoxon(r))
        .collect();
    let measure = col("Measure");
    if by_point {
        rows.truncate(SUMMARY_POINT_VERDICTS);
    } else {
        rows = per_measure(rows, measure, verdict);
    }
    // Friedman's rows over all problems whose verdict differs from the
    // Wilcoxon row of the same comparison (the check's disagreements).
    let same_comparison = |a: &Vec<String>, b: &Vec<String>| {
        ["Algorithm", "Reference", "Measure", "Scope"]
            .iter()
            .filter_map(|k| col(k))
            .all(|i| a[i] == b[i])
    };
    let friedman_all: Vec<&Vec<String>> = t
        .md_rows
        .iter()
        .filter(|r| !by_point && scope.is_some_and(|i| r[i] == "all") && !is_wilcoxon(r))
        .collect();
    let checked = friedman_all.len();
    let friedman: Vec<&Vec<String>> = friedman_all
        .into_iter()
        .filter(|f| {
            let v = verdict.map_or("", |i| f[i].as_str());
            !t.md_rows.iter().any(|w| {
                is_wilcoxon(w) && same_comparison(w, f) && verdict.is_some_and(|i| w[i] == v)
            })
        })
        .collect();
    let differing = friedman.len();
    let friedman = per_measure(friedman, measure, verdict);
    let project = |rows: Vec<&Vec<String>>, extra: Option<usize>| {
        let idx: Vec<usize> = extra.into_iter().chain(idx.iter().copied()).collect();
        Table {
            md_header: idx.iter().map(|&i| t.md_header[i].clone()).collect(),
            md_rows: rows
                .into_iter()
                .map(|r| idx.iter().map(|&i| r[i].clone()).collect())
                .collect(),
            ..t.clone()
        }
    };
    (
        project(rows, None),
        project(friedman, test),
        (differing, checked),
    )
}

/// `rows` grouped by their value in column `col` (all in one group
/// without it), the groups in the order their values first appear.
fn grouped<'r>(
    rows: impl IntoIterator<Item = &'r Vec<String>>,
    col: Option<usize>,
) -> Vec<Vec<&'r Vec<String>>> {
    let mut groups: Vec<Vec<&Vec<String>>> = Vec::new();
    for r in rows {
        let same = |g: &&mut Vec<&Vec<String>>| col.is_none_or(|i| g[0][i] == r[i]);
        match groups.iter_mut().find(same) {
            Some(g) => g.push(r),
            None => groups.push(vec![r]),
        }
    }
    groups
}

/// The Markdown of `t`, one table per measure (each under the report's
/// 15-row limit), each followed by a blank line.
fn by_measure(t: &Table) -> String {
    let m = t.md_header.iter().position(|h| h == "Measure");
    grouped(&t.md_rows, m)
        .into_iter()
        .map(|rows| {
            let part = Table {
                md_rows: rows.into_iter().cloned().collect(),
                ..t.clone()
            };
            format!("{}\n", part.markdown())
        })
        .collect()
}

/// Each measure's rows (in the order the measures first appear), decided
/// verdicts first, at most [`SUMMARY_VERDICTS`] per measure.
fn per_measure(
    rows: Vec<&Vec<String>>,
    measure: Option<usize>,
    verdict: Option<usize>,
) -> Vec<&Vec<String>> {
    grouped(rows, measure)
        .into_iter()
        .flat_map(|mut of| {
            of.sort_by_key(|r| verdict.is_some_and(|i| r[i] == "undecided"));
            of.truncate(SUMMARY_VERDICTS);
            of
        })
        .collect()
}

/// The best setting of every tuned grid (lowest mean rank), with its
/// runner-up and a link to its table.
fn picks(tuning: &[Table]) -> String {
    use metabezier_plot::markdown::escape;
    let picks: Vec<String> = tuning
        .iter()
        .filter(|t| t.stem.starts_with("tuning_picks_"))
        .filter_map(|t| {
            let row = t.md_rows.first()?;
            let runner = t.md_header.iter().position(|h| h == "Runner-up");
            let grid = t
                .title
                .strip_prefix("Parameter tuning of ")
                .and_then(|r| r.split(':').next())
                .unwrap_or("");
            Some(format!(
                "- {}: {} (mean rank {}){}; [`tables/{}.csv`](tables/{}.csv)\n",
                escape(grid),
                escape(&row[0]),
                escape(row.get(1).map_or("", String::as_str)),
                runner
                    .and_then(|i| row.get(i))
                    .map_or_else(String::new, |r| format!(", runner-up {}", escape(r))),
                t.stem,
                t.stem
            ))
        })
        .collect();
    if picks.is_empty() {
        return String::new();
    }
    format!(
        "Best settings (lowest mean rank over the problems):\n\n{}\n",
        picks.concat()
    )
}

/// Links to the first page of every figure, those that answer the
/// question first.
fn figure_links(figures: &[Plot]) -> String {
    if figures.is_empty() {
        return String::new();
    }
    let (answers, others): (Vec<&Plot>, Vec<&Plot>) = figures
        .iter()
        .filter(|p| p.page.index == 1)
        .partition(|p| super::plots::fit_factors::ANSWER_STEMS.contains(&p.stem.as_str()));
    let link = |p: &&Plot| {
        format!(
            "[{}](plots/{}.png)",
            metabezier_plot::markdown::escape(&p.figure_heading()),
            p.stem
        )
    };
    let answers: Vec<String> = answers.iter().map(link).collect();
    let links: Vec<String> = others.iter().map(link).collect();
    let answer = if answers.is_empty() {
        String::new()
    } else {
        format!(
            "The figure that answers the question: {}. ",
            answers.join("; ")
        )
    };
    let others = match (answers.is_empty(), links.is_empty()) {
        (_, true) => String::new(),
        (true, false) => format!("Figures: {}.", links.join(", ")),
        (false, false) => format!("Other figures: {}.", links.join(", ")),
    };
    format!("{}\n\n", format!("{answer}{others}").trim_end())
}
