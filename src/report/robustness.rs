//! Where a verdict holds: the Wilcoxon + Holm marks of every algorithm
//! against the reference, counted over the functions at each design point,
//! summarised per level of each factor, with a one-line verdict per
//! comparison.
//!
//! A design point is one combination of the factors that vary in the
//! results other than the algorithm, the function and the run: the
//! dimension, the budget and the transform of benchmark problems, the
//! budget per segment, the search space, the technique's α_size and the
//! problem mode (whole outline or per segment) of fitting cases. The functions
//! at a design point (each benchmark instance and each fitting case counting
//! as one) are its units. At a design point an algorithm is *better* than
//! the reference when it has more "+" than "−" marks there, *worse* when it
//! has more "−" than "+", and *tied* otherwise.

use std::collections::BTreeMap;

use crate::functions::bbob::bbob_group;
use crate::stats::Mark;

use super::data::{Dataset, Problem};
use super::format::Table;
use super::significance::Significance;

/// The factor values of a design point, in a fixed order.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct DesignPoint(Vec<(&'static str, Level)>);

/// A factor level, ordered numerically where it is a number.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Level {
    Number(u64),
    Text(String),
}

impl std::fmt::Display for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Level::Number(n) => write!(f, "{n}"),
            Level::Text(t) => f.write_str(t),
        }
    }
}

/// How a factor and its level read in a verdict: `D = 30`, `budget 1000`.
fn phrase(factor: &str, level: &Level) -> String {
    match factor {
        "D" => format!("D = {level}"),
        "search space" => format!("the {level} search space"),
        "α_size" => format!("α_size {level}"),
        "mode" => format!("{level} problems"),
        _ => format!("{factor} {level}"),
    }
}

impl DesignPoint {
    fn label(&self) -> String {
        if self.0.is_empty() {
            return "all problems".into();
        }
        self.0
            .iter()
            .map(|(f, l)| phrase(f, l))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The candidate factors of a problem with their levels: for a fitting
/// case the budget per segment, the search space, the technique's α_size
/// and the problem mode (read from its name, see
/// [`super::fitting::split`]).
fn factors(p: &Problem) -> Vec<(&'static str, Level)> {
    if p.is_fit() {
        let case = super::fitting::split(&p.function);
        let mut out = Vec::new();
        if let Some(b) = p.budget {
            out.push(("budget per segment", Level::Number(b / p.dim.max(1) as u64)));
        }
        let space = case.and_then(|c| c.space).unwrap_or("technique");
        out.push(("search space", Level::Text(space.into())));
        let alpha = case.and_then(|c| c.alpha).unwrap_or("0.5");
        out.push(("α_size", Level::Text(alpha.into())));
        let mode = if case.is_some_and(|c| c.per_segment) {
            "per-segment"
        } else {
            "outline"
        };
        out.push(("mode", Level::Text(mode.into())));
        out
    } else {
        let mut out = vec![("D", Level::Number(p.dim as u64))];
        if let Some(b) = p.budget {
            out.push(("budget", Level::Number(b)));
        }
        out.push(("transform", Level::Text(p.transform.name().into())));
        if let Some(f) = bbob_function_of(&p.function) {
            out.push(("bbob group", Level::Text(bbob_group(f).into())));
        }
        out
    }
}

/// The bbob function index of a COCO problem id (`bbob_f008_i02_d05`, or
/// pooled over instances `bbob_f008_d05`).
fn bbob_function_of(id: &str) -> Option<usize> {
    id.strip_prefix("bbob_f")?.get(..3)?.parse().ok()
}

/// The design point of every problem: its candidate factors restricted to
/// those that vary among the problems.
fn design_points(ds: &Dataset) -> Vec<DesignPoint> {
    let all: Vec<Vec<(&'static str, Level)>> = ds.problems.iter().map(factors).collect();
    let mut levels: BTreeMap<&'static str, std::collections::BTreeSet<Level>> = BTreeMap::new();
    for fs in &all {
        for (f, l) in fs {
            levels.entry(f).or_default().insert(l.clone());
        }
    }
    all.into_iter()
        .map(|fs| {
            DesignPoint(
                fs.into_iter()
                    .filter(|(f, _)| levels.get(f).is_some_and(|l| l.len() > 1))
                    .collect(),
            )
        })
        .collect()
}

/// The marks of one algorithm at one design point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Count {
    better: usize,
    same: usize,
    worse: usize,
}

impl Count {
    fn add(&mut self, m: Mark) {
        match m {
            Mark::Better => self.better += 1,
            Mark::Same => self.same += 1,
            Mark::Worse => self.worse += 1,
        }
    }

    fn units(&self) -> usize {
        self.better + self.same + self.worse
    }

    /// `better`, `worse` or `tied` by the majority of decided marks.
    fn verdict(&self) -> &'static str {
        use std::cmp::Ordering::*;
        match self.better.cmp(&self.worse) {
            Greater => "better",
            Less => "worse",
            Equal => "tied",
        }
    }

    fn text(&self) -> String {
        format!("{}/{}/{}", self.better, self.same, self.worse)
    }
}

/// The counts per (design point, cell), the design points in order.
fn counts(ds: &Dataset, s: &Significance) -> (Vec<DesignPoint>, BTreeMap<(usize, usize), Count>) {
    let points = design_points(ds);
    let mut order: Vec<DesignPoint> = points.clone();
    order.sort();
    order.dedup();
    let index: BTreeMap<&DesignPoint, usize> =
        order.iter().enumerate().map(|(i, d)| (d, i)).collect();
    let mut out: BTreeMap<(usize, usize), Count> = BTreeMap::new();
    for row in &s.wilcoxon {
        if let Some(m) = row.mark {
            let d = index[&points[row.problem]];
            out.entry((d, row.cell)).or_default().add(m);
        }
    }
    (order, out)
}

/// The compared cells, in order.
fn compared(ds: &Dataset, s: &Significance) -> Vec<usize> {
    (0..ds.cells.len()).filter(|&c| c != s.reference).collect()
}

/// One line per compared algorithm: at how many design points it is better
/// than, worse than and tied with the reference, naming where it is worse
/// (or, when it is mostly worse, where it is better).
fn verdicts(
    ds: &Dataset,
    s: &Significance,
    points: &[DesignPoint],
    counts: &BTreeMap<(usize, usize), Count>,
) -> Vec<String> {
    let reference = &ds.cells[s.reference].name;
    compared(ds, s)
        .into_iter()
        .filter_map(|c| {
            let at: Vec<(usize, Count)> = (0..points.len())
                .filter_map(|d| counts.get(&(d, c)).map(|k| (d, *k)))
                .filter(|(_, k)| k.units() > 0)
                .collect();
            if at.is_empty() {
                return None;
            }
            let n = at.len();
            let of = |v: &str| at.iter().filter(|(_, k)| k.verdict() == v).count();
            let (better, worse, tied) = (of("better"), of("worse"), of("tied"));
            let named = |v: &str| -> String {
                let list: Vec<String> = at
                    .iter()
                    .filter(|(_, k)| k.verdict() == v)
                    .map(|(d, _)| points[*d].label())
                    .collect();
                if list.len() > 4 {
                    format!("{} and {} more", list[..4].join("; "), list.len() - 4)
                } else {
                    list.join("; ")
                }
            };
            let mut line = format!(
                "{} against {reference}: better at {better} of {n} design point{}",
                ds.cells[c].name,
                if n == 1 { "" } else { "s" }
            );
            if worse > 0 {
                line.push_str(&format!("; worse at {worse} ({})", named("worse")));
            }
            if tied > 0 {
                line.push_str(&format!("; tied at {tied}"));
            }
            if better > 0 && better < n && better <= worse {
                line.push_str(&format!("; better at {}", named("better")));
            }
            line.push('.');
            Some(line)
        })
        .collect()
}

/// The robustness tables: the marks at each design point with the verdicts
/// as the table's introduction, and the summary per factor level.
pub(crate) fn tables(ds: &Dataset, s: &Significance) -> Vec<Table> {
    let (points, counts) = counts(ds, s);
    let cells = compared(ds, s);
    let reference = &ds.cells[s.reference].name;
    let factor_names: Vec<&'static str> = points
        .first()
        .map(|d| d.0.iter().map(|(f, _)| *f).collect())
        .unwrap_or_default();
    let mut intro = vec![format!(
        "Wilcoxon signed-rank marks (paired by run, Holm-corrected per problem) of each \
         algorithm against {reference}, counted over the functions at each design point \
         (each benchmark instance and each fitting case is one function) and written \
         +/≈/−. A design point is one combination of the factors that vary in these \
         results other than the algorithm, the function and the run. An algorithm is \
         better at a design point when it has more + than − marks there, worse when it \
         has more − than +."
    )];
    intro.extend(verdicts(ds, s, &points, &counts));
    let mut by_point = Table {
        stem: "robustness".into(),
        title: format!("Design points against {reference}"),
        intro,
        md_header: std::iter::once("Design point".to_string())
            .chain(cells.iter().map(|&c| ds.cells[c].name.clone()))
            .collect(),
        csv_header: factor_names
            .iter()
            .map(|f| f.replace(' ', "_"))
            .chain(
                [
                    "algorithm",
                    "kind",
                    "params",
                    "better",
                    "same",
                    "worse",
                    "verdict",
                ]
                .map(String::from),
            )
            .collect(),
        ..Table::default()
    };
    for (d, point) in points.iter().enumerate() {
        let mut md = vec![point.label()];
        for &c in &cells {
            let k = counts.get(&(d, c)).copied().unwrap_or_default();
            md.push(if k.units() == 0 {
                "—".into()
            } else {
                format!("{} ({})", k.text(), k.verdict())
            });
            let mut row: Vec<String> = point.0.iter().map(|(_, l)| l.to_string()).collect();
            let cell = &ds.cells[c];
            row.extend([
                cell.label.clone(),
                cell.kind.clone(),
                cell.params.clone(),
                k.better.to_string(),
                k.same.to_string(),
                k.worse.to_string(),
                if k.units() == 0 {
                    String::new()
                } else {
                    k.verdict().into()
                },
            ]);
            by_point.csv_rows.push(row);
        }
        by_point.md_rows.push(md);
    }
    vec![by_point, by_level(ds, &cells, &points, &counts, reference)]
}

/// The marks summed over the design points at each level of each factor.
fn by_level(
    ds: &Dataset,
    cells: &[usize],
    points: &[DesignPoint],
    counts: &BTreeMap<(usize, usize), Count>,
    reference: &str,
) -> Table {
    let mut t = Table {
        stem: "robustness_levels".into(),
        title: format!("Marks per factor level against {reference}"),
        intro: vec![
            "The marks of the design points that share a level of one factor, summed \
             (+/≈/−), with the number of those design points at which the algorithm is \
             better, tied and worse."
                .into(),
        ],
        md_header: ["Factor", "Level"]
            .map(String::from)
            .into_iter()
            .chain(cells.iter().map(|&c| ds.cells[c].name.clone()))
            .collect(),
        csv_header: [
            "factor",
            "level",
            "algorithm",
            "kind",
            "params",
            "better",
            "same",
            "worse",
            "points_better",
            "points_tied",
            "points_worse",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    let mut levels: BTreeMap<(&'static str, Level), Vec<usize>> = BTreeMap::new();
    for (d, p) in points.iter().enumerate() {
        for (f, l) in &p.0 {
            levels.entry((f, l.clone())).or_default().push(d);
        }
    }
    for ((factor, level), ds_at) in &levels {
        let mut md = vec![factor.to_string(), level.to_string()];
        for &c in cells {
            let mut sum = Count::default();
            let mut verdicts = [0usize; 3];
            for d in ds_at {
                if let Some(k) = counts.get(&(*d, c)).filter(|k| k.units() > 0) {
                    sum.better += k.better;
                    sum.same += k.same;
                    sum.worse += k.worse;
                    verdicts[match k.verdict() {
                        "better" => 0,
                        "tied" => 1,
                        _ => 2,
                    }] += 1;
                }
            }
            md.push(format!(
                "{} ({} better, {} tied, {} worse)",
                sum.text(),
                verdicts[0],
                verdicts[1],
                verdicts[2]
            ));
            let cell = &ds.cells[c];
            t.csv_rows.push(vec![
                factor.replace(' ', "_"),
                level.to_string(),
                cell.label.clone(),
                cell.kind.clone(),
                cell.params.clone(),
                sum.better.to_string(),
                sum.same.to_string(),
                sum.worse.to_string(),
                verdicts[0].to_string(),
                verdicts[1].to_string(),
                verdicts[2].to_string(),
            ]);
        }
        t.md_rows.push(md);
    }
    if t.md_rows.is_empty() {
        t.intro
            .push("No factor varies in these results: there is one design point.".into());
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::RunRecord;
    use crate::functions::Transform;
    use crate::report::data::Dataset;
    use crate::report::significance::significance;

    /// Runs of `alg` on `function` at (dim, budget) with errors `base + run`.
    fn runs(
        alg: &str,
        function: &str,
        dim: usize,
        budget: u64,
        base: f64,
    ) -> Vec<(RunRecord, bool)> {
        (0..8)
            .map(|run| {
                let error = base + f64::from(run) * 1e-3;
                (
                    RunRecord {
                        algorithm: alg.into(),
                        kind: alg.to_lowercase(),
                        params: String::new(),
                        problem: function.into(),
                        dim,
                        budget,
                        transform: Transform::None,
                        instance: 1,
                        run,
                        seed: 0,
                        best: error,
                        error,
                        evaluations: budget,
                        evaluations_to_target: None,
                        success: false,
                        trace: Vec::new(),
                        hits: Vec::new(),
                        fit: None,
                        wall_seconds: 0.0,
                    },
                    false,
                )
            })
            .collect()
    }

    #[test]
    fn a_verdict_that_flips_with_the_budget_is_reported_with_its_range() {
        // B beats A on both functions at budget 1000, loses on both at 10000.
        let mut records = Vec::new();
        for f in ["sphere", "ackley"] {
            records.extend(runs("A", f, 10, 1000, 1.0));
            records.extend(runs("B", f, 10, 1000, 0.5));
            records.extend(runs("A", f, 10, 10000, 0.1));
            records.extend(runs("B", f, 10, 10000, 0.2));
        }
        let ds = Dataset::from_records(records);
        assert_eq!(ds.problems.len(), 4, "{:?}", ds.problems);
        let s = significance(&ds, 0, 0.05);
        let t = tables(&ds, &s);
        assert_eq!(
            t[0].md_rows,
            [
                vec!["budget 1000".to_string(), "2/0/0 (better)".into()],
                vec!["budget 10000".to_string(), "0/0/2 (worse)".into()],
            ]
        );
        assert_eq!(
            t[0].intro[1],
            "B against A: better at 1 of 2 design points; worse at 1 (budget 10000); better at budget 1000."
        );
        assert_eq!(t[1].md_rows[0][0], "budget");
        assert_eq!(t[1].md_rows[1][2], "0/0/2 (0 better, 0 tied, 1 worse)");
    }

    #[test]
    fn one_design_point_when_nothing_varies() {
        let mut records = runs("A", "sphere", 10, 1000, 1.0);
        records.extend(runs("B", "sphere", 10, 1000, 1.0));
        let ds = Dataset::from_records(records);
        let s = significance(&ds, 0, 0.05);
        let t = tables(&ds, &s);
        assert_eq!(
            t[0].md_rows,
            [vec!["all problems".to_string(), "0/1/0 (tied)".into()]]
        );
        assert!(t[1].md_rows.is_empty());
    }
}
