//! The curve-fitting part of a report, for campaigns with `[[fit]]`
//! problems: fit quality beyond `E`, the gap of every method to the best
//! `E` found by any method, whether the hybrid beats both of its parts, and
//! overlays of the best fit of each function on each outline.
//!
//! Problem names of fitting campaigns are `source/function/continuity`,
//! with `/bounding-box` appended for the naive search space.

use std::collections::BTreeMap;
use std::path::Path;

use super::data::Dataset;
use super::format::{sci, Table};
use super::plots::{Figure, Plot};
use crate::experiment::records::{read_results, FitDetail, RunRecord};
use crate::experiment::segments::segment_from_row;
use crate::experiment::{DataError, DataProblem, ReadError};
use crate::files::fmt_real;
use crate::fit::Segment;
use crate::geometry::Point;
use crate::reconstruction::{OverlayCurve, OverlayFigure, OverlayPanel};
use crate::stats::{holm_bonferroni, mann_whitney_u, median, wilcoxon, Alternative, Mark};

/// What the fitting section adds to a report.
pub(crate) struct FittingSection {
    /// Its tables.
    pub tables: Vec<Table>,
    /// Its figures (one overlay per source).
    pub figures: Vec<Plot>,
    /// Remarks.
    pub notes: Vec<String>,
}

/// A problem name split into its parts.
struct Case<'a> {
    source: &'a str,
    function: &'a str,
    continuity: &'a str,
    space: Option<&'a str>,
}

fn split(name: &str) -> Option<Case<'_>> {
    let mut parts = name.split('/');
    let case = Case {
        source: parts.next()?,
        function: parts.next()?,
        continuity: parts.next()?,
        space: parts.next(),
    };
    parts.next().is_none().then_some(case)
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// A fitted outline read back from its segment rows, for an overlay;
/// `None` if a row does not describe a segment.
fn overlay_from_rows(label: String, rows: &[Vec<String>]) -> Option<OverlayCurve> {
    let segments: Vec<Segment> = rows
        .iter()
        .map(|r| segment_from_row(r))
        .collect::<Option<_>>()?;
    Some(OverlayCurve::of_segments(label, &segments))
}

/// Reads `outlines.csv` (source, x, y): the data points of every source.
fn read_outlines(dir: &Path) -> Result<BTreeMap<String, Vec<Point>>, ReadError> {
    let path = dir.join("outlines.csv");
    let mut out: BTreeMap<String, Vec<Point>> = BTreeMap::new();
    if !path.exists() {
        return Ok(out);
    }
    let mut reader =
        csv::Reader::from_path(&path).map_err(|e| DataError::new(&path, 0, DataProblem::Csv(e)))?;
    for (i, row) in reader.records().enumerate() {
        let line = i as u64 + 2;
        let row = row.map_err(|e| DataError::new(&path, line, DataProblem::Csv(e)))?;
        let num = |k: usize| -> Result<f64, DataError> {
            row.get(k)
                .unwrap_or("")
                .parse()
                .map_err(|_| DataError::new(&path, line, DataProblem::NotANumber(k + 1)))
        };
        out.entry(row.get(0).unwrap_or("").to_owned())
            .or_default()
            .push(Point::new(num(1)?, num(2)?));
    }
    Ok(out)
}

/// The display name of a run's method: the name of its cell in the report,
/// or its algorithm label when no cell matches.
fn cell_name(ds: &Dataset, r: &RunRecord) -> String {
    ds.cells
        .iter()
        .find(|c| !c.external && c.label == r.algorithm && c.kind == r.kind && c.params == r.params)
        .map_or_else(|| r.algorithm.clone(), |c| c.name.clone())
}

/// The fitting runs grouped by problem and method, both in the order of
/// their first appearance.
struct FitRuns<'r> {
    /// Problem names (`source/function/continuity[/space]`).
    problems: Vec<String>,
    /// Method (cell) names.
    cells: Vec<String>,
    /// (problem, cell) → its runs.
    runs: BTreeMap<(usize, usize), Vec<&'r RunRecord>>,
}

impl<'r> FitRuns<'r> {
    /// Groups the records that have fit details.
    fn group(ds: &Dataset, records: &'r [RunRecord]) -> Self {
        let mut problems: Vec<String> = Vec::new();
        let mut cells: Vec<String> = Vec::new();
        let mut runs: BTreeMap<(usize, usize), Vec<&RunRecord>> = BTreeMap::new();
        for r in records.iter().filter(|r| r.fit.is_some()) {
            let p = match problems.iter().position(|q| *q == r.problem) {
                Some(p) => p,
                None => {
                    problems.push(r.problem.clone());
                    problems.len() - 1
                }
            };
            let name = cell_name(ds, r);
            let c = match cells.iter().position(|q| *q == name) {
                Some(c) => c,
                None => {
                    cells.push(name);
                    cells.len() - 1
                }
            };
            runs.entry((p, c)).or_default().push(r);
        }
        FitRuns {
            problems,
            cells,
            runs,
        }
    }

    /// The final E of every run of cell `c` on problem `p`, if it ran.
    fn errors(&self, p: usize, c: usize) -> Option<Vec<f64>> {
        self.runs
            .get(&(p, c))
            .map(|rs| rs.iter().map(|r| r.best).collect())
    }

    /// The best E per problem over every method and run, and the method
    /// that found it.
    fn best(&self) -> Vec<(f64, String)> {
        (0..self.problems.len())
            .map(|p| {
                (0..self.cells.len())
                    .flat_map(|c| {
                        self.runs
                            .get(&(p, c))
                            .into_iter()
                            .flatten()
                            .map(move |r| (r.best, c))
                    })
                    .fold((f64::INFINITY, String::new()), |acc, (e, c)| {
                        if e < acc.0 {
                            (e, self.cells[c].clone())
                        } else {
                            acc
                        }
                    })
            })
            .collect()
    }

    /// The optimiser kind of every cell (from its first run).
    fn kinds(&self) -> Vec<Option<String>> {
        (0..self.cells.len())
            .map(|c| {
                self.runs
                    .iter()
                    .find(|((_, cc), _)| *cc == c)
                    .map(|(_, rs)| rs[0].kind.clone())
            })
            .collect()
    }
}

/// The empty fit-quality table, with its headers.
fn quality_frame() -> Table {
    Table {
        stem: "fit_quality".into(),
        title: "Fit quality and the gap to the best E found".into(),
        intro: vec![
            "For each fitting problem (source/function/continuity) and method: the mean and \
             best E = Σ|Rᵢ − P(sᵢ)|² over the runs, the relative gap of the mean to the best E \
             found by any method on that problem (the exact reference LM included), the mean \
             RMS distance √(E/N), the mean largest orthogonal distance of a data point to the \
             curve, and the mean tangent angle at the closing joint of the closed outline, \
             where only C⁰ is imposed (data units: pixels for images, font units for glyphs)."
                .into(),
        ],
        md_header: [
            "Problem",
            "Method",
            "Runs",
            "Mean E",
            "Best E",
            "Gap of mean",
            "Mean RMS",
            "Mean max dist",
            "Closing angle (°)",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "method",
            "runs",
            "mean_sse",
            "best_sse",
            "best_known_sse",
            "gap",
            "mean_rms",
            "mean_max_distance",
            "mean_closing_angle_degrees",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// The fit quality of every method on every problem, with the gap of its
/// mean E to the best E found (`known`).
fn quality_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
    let mut quality = quality_frame();
    for (p, problem) in fr.problems.iter().enumerate() {
        for (c, cell) in fr.cells.iter().enumerate() {
            let Some(rs) = fr.runs.get(&(p, c)) else {
                continue;
            };
            let e: Vec<f64> = rs.iter().map(|r| r.best).collect();
            let fit = |f: fn(&FitDetail) -> Option<f64>| -> Vec<f64> {
                rs.iter()
                    .filter_map(|r| r.fit.as_ref().and_then(f))
                    .collect()
            };
            let rms = fit(|d| Some(d.rms));
            let maxd = fit(|d| Some(d.max_distance));
            let angle = fit(|d| d.closing_angle_degrees.filter(|a| a.is_finite()));
            let (m, b, known) = (
                mean(&e),
                e.iter().copied().fold(f64::INFINITY, f64::min),
                best[p].0,
            );
            let gap = if known > 0.0 {
                m / known - 1.0
            } else {
                f64::NAN
            };
            let angle_mean = if angle.is_empty() {
                f64::NAN
            } else {
                mean(&angle)
            };
            quality.md_rows.push(vec![
                problem.clone(),
                cell.clone(),
                rs.len().to_string(),
                sci(m),
                sci(b),
                sci(gap),
                sci(mean(&rms)),
                sci(mean(&maxd)),
                if angle_mean.is_nan() {
                    "—".into()
                } else {
                    format!("{angle_mean:.2}")
                },
            ]);
            quality.csv_rows.push(vec![
                problem.clone(),
                cell.clone(),
                rs.len().to_string(),
                fmt_real(m),
                fmt_real(b),
                fmt_real(known),
                fmt_real(gap),
                fmt_real(mean(&rms)),
                fmt_real(mean(&maxd)),
                fmt_real(angle_mean),
            ]);
        }
    }
    quality
}

/// Which function fits each source best, per continuity (and space): the
/// best E per problem, grouped by source.
fn functions_table(fr: &FitRuns<'_>, best: &[(f64, String)]) -> Table {
    let mut functions = Table {
        stem: "fit_functions".into(),
        title: "Best E per fitting function".into(),
        intro: vec![
            "For each source, continuity and search space, the best E that any method reached \
             with each fitting function, and the method that reached it. The lowest E of a \
             row group is the function that fits that outline best."
                .into(),
        ],
        md_header: ["Source", "Continuity", "Function", "Best E", "Found by"]
            .map(String::from)
            .to_vec(),
        csv_header: [
            "source",
            "continuity",
            "search_space",
            "function",
            "best_sse",
            "found_by",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    };
    let problems = &fr.problems;
    let mut order: Vec<usize> = (0..problems.len()).collect();
    order.sort_by_key(|&p| split(&problems[p]).map(|c| (c.source, c.space, c.continuity, p)));
    for p in order {
        let Some(case) = split(&problems[p]) else {
            continue;
        };
        let cont = match case.space {
            Some(s) => format!("{} ({s})", case.continuity.to_uppercase()),
            None => case.continuity.to_uppercase(),
        };
        functions.md_rows.push(vec![
            case.source.into(),
            cont,
            case.function.into(),
            sci(best[p].0),
            best[p].1.clone(),
        ]);
        functions.csv_rows.push(vec![
            case.source.into(),
            case.continuity.into(),
            case.space.unwrap_or("technique").into(),
            case.function.into(),
            fmt_real(best[p].0),
            best[p].1.clone(),
        ]);
    }
    functions
}

/// The empty hybrid table, with its headers.
fn hybrid_frame() -> Table {
    Table {
        stem: "fit_hybrid".into(),
        title: "Hybrid against its parts".into(),
        intro: vec![
            "For each metaheuristic X run both alone and as X+LM (X on 80 % of the budget, \
             then a Levenberg–Marquardt polish), with LM alone also run: the median E of X, LM \
             and X+LM, and whether the hybrid's median is below both."
                .into(),
        ],
        md_header: [
            "Problem",
            "X",
            "Median E of X",
            "Median E of LM",
            "Median E of X+LM",
            "Beats both",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "x",
            "median_x",
            "median_lm",
            "median_hybrid",
            "beats_both",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// Hybrids against their two parts: for every X+LM whose X and LM also
/// ran, whether its median E is below both of theirs.
fn hybrid_table(fr: &FitRuns<'_>) -> Table {
    let mut hybrid = hybrid_frame();
    let kinds = fr.kinds();
    let Some(lm) = kinds.iter().position(|k| k.as_deref() == Some("lm")) else {
        return hybrid;
    };
    for (p, problem) in fr.problems.iter().enumerate() {
        let med = |c: usize| fr.errors(p, c).map(|e| median(&e));
        for (h, kind) in kinds.iter().enumerate() {
            let Some(base) = kind.as_deref().and_then(|k| k.strip_suffix("+lm")) else {
                continue;
            };
            let Some(x) = kinds.iter().position(|k| k.as_deref() == Some(base)) else {
                continue;
            };
            let (Some(mx), Some(ml), Some(mh)) = (med(x), med(lm), med(h)) else {
                continue;
            };
            let beats = mh < mx.min(ml) * (1.0 - 1e-9);
            hybrid.md_rows.push(vec![
                problem.clone(),
                fr.cells[x].clone(),
                sci(mx),
                sci(ml),
                sci(mh),
                if beats { "yes" } else { "no" }.into(),
            ]);
            hybrid.csv_rows.push(vec![
                problem.clone(),
                fr.cells[x].clone(),
                fmt_real(mx),
                fmt_real(ml),
                fmt_real(mh),
                beats.to_string(),
            ]);
        }
    }
    hybrid
}

/// The empty search-space table, with its headers.
fn search_space_frame(alpha: f64, paired: bool) -> Table {
    let test = if paired {
        "two-sided Wilcoxon signed-rank test paired by run (the search space is paired in \
         the spec, so the runs of the two problems share their seeds)"
    } else {
        "two-sided Mann–Whitney U test of the two samples (the runs of the two problems \
         have different seeds, so they are not paired)"
    };
    Table {
        stem: "fit_search_space".into(),
        title: "Search-space technique against the bounding box".into(),
        intro: vec![format!(
            "For each problem run with both search spaces and each method: the median E \
             inside the technique's boxes and inside the naive bounding box, and the \
             {test}, with Holm's correction over all rows. The mark is from the \
             technique's point of view at α = {alpha}: + significantly lower E with the \
             technique, − significantly higher, ≈ no significant difference."
        )],
        md_header: [
            "Problem",
            "Method",
            "Median E (technique)",
            "Median E (bounding box)",
            "p",
            "p (Holm)",
            "Mark",
        ]
        .map(String::from)
        .to_vec(),
        csv_header: [
            "problem",
            "method",
            "median_technique",
            "median_bounding_box",
            if paired { "r_plus_minus_r_minus" } else { "u" },
            "p_value",
            "p_holm",
            "mark",
        ]
        .map(String::from)
        .to_vec(),
        ..Table::default()
    }
}

/// A test of E with the technique against E in the bounding box: its
/// p-value and its signed statistic (negative when the technique's E
/// tends to be lower).
struct SpaceTest {
    p_value: f64,
    direction: f64,
    /// The statistic written to the CSV file: R⁺ − R⁻ or U.
    statistic: f64,
}

/// A method's runs on a problem in both search spaces: (problem of the
/// technique, method, median E with the technique, median E in the
/// bounding box, the test).
type SpacePair = (String, String, f64, f64, SpaceTest);

/// Every method run on a problem in both search spaces, with the test of
/// its two samples: paired by run when `paired`, else unpaired.
fn space_pairs(fr: &FitRuns<'_>, paired: bool) -> Vec<SpacePair> {
    let mut pairs = Vec::new();
    for (pb, name) in fr.problems.iter().enumerate() {
        let Some(c) = split(name) else { continue };
        if c.space != Some("bounding-box") {
            continue;
        }
        let twin = format!("{}/{}/{}", c.source, c.function, c.continuity);
        let Some(pt) = fr.problems.iter().position(|q| *q == twin) else {
            continue;
        };
        for (cell, cell_name) in fr.cells.iter().enumerate() {
            let (Some(ea), Some(eb)) = (fr.errors(pt, cell), fr.errors(pb, cell)) else {
                continue;
            };
            let test = if paired && ea.len() == eb.len() {
                wilcoxon(&ea, &eb, Alternative::TwoSided).map(|w| SpaceTest {
                    p_value: w.p_value,
                    direction: w.r_plus - w.r_minus,
                    statistic: w.r_plus - w.r_minus,
                })
            } else {
                mann_whitney_u(&ea, &eb, Alternative::TwoSided).map(|m| SpaceTest {
                    p_value: m.p_value,
                    direction: m.statistic - (m.n1 * m.n2) as f64 / 2.0,
                    statistic: m.statistic,
                })
            };
            if let Ok(t) = test {
                pairs.push((twin.clone(), cell_name.clone(), median(&ea), median(&eb), t));
            }
        }
    }
    pairs
}

/// The search-space technique against the naive bounding box, with Holm's
/// correction over all rows.
fn search_space_table(fr: &FitRuns<'_>, alpha: f64, paired: bool) -> Table {
    let mut space = search_space_frame(alpha, paired);
    let pairs = space_pairs(fr, paired);
    if pairs.is_empty() {
        return space;
    }
    let p: Vec<f64> = pairs.iter().map(|x| x.4.p_value).collect();
    let adjusted = holm_bonferroni(&p).unwrap_or(p);
    for ((problem, method, ma, mb, t), ph) in pairs.into_iter().zip(adjusted) {
        let mark = Mark::from_p_value(ph, alpha, t.direction);
        space.md_rows.push(vec![
            problem.clone(),
            method.clone(),
            sci(ma),
            sci(mb),
            sci(t.p_value),
            sci(ph),
            mark.symbol().into(),
        ]);
        space.csv_rows.push(vec![
            problem,
            method,
            fmt_real(ma),
            fmt_real(mb),
            fmt_real(t.statistic),
            fmt_real(t.p_value),
            fmt_real(ph),
            mark.symbol().into(),
        ]);
    }
    space
}

/// The overlay panel of one function on one source: the best fit of each
/// continuity (technique search space), titled with their E and method.
fn overlay_panel(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    source: &str,
    function: &str,
    data: &[Point],
) -> OverlayPanel {
    let mut curves = Vec::new();
    let mut bests = Vec::new();
    for (p, name) in fr.problems.iter().enumerate() {
        let Some(c) = split(name) else { continue };
        if c.source != source || c.function != function || c.space.is_some() {
            continue;
        }
        let best_run = fr
            .runs
            .iter()
            .filter(|((pp, _), _)| *pp == p)
            .flat_map(|(_, rs)| rs.iter())
            .min_by(|a, b| a.best.total_cmp(&b.best));
        let Some(r) = best_run else { continue };
        let cont = c.continuity.to_uppercase();
        if let Some(curve) = r
            .fit
            .as_ref()
            .and_then(|f| overlay_from_rows(cont.clone(), &f.segments))
        {
            bests.push(format!("{cont} E = {} ({})", sci(r.best), cell_name(ds, r)));
            curves.push(curve);
        }
    }
    OverlayPanel {
        title: format!("{function}: {}", bests.join(", ")),
        data: data.to_vec(),
        curves,
        y_down: false,
    }
}

/// The overlay plot of one source: a panel per fitting function, or
/// `None` when it has none.
fn overlay_plot(ds: &Dataset, fr: &FitRuns<'_>, source: &str, data: &[Point]) -> Option<Plot> {
    let mut function_names: Vec<&str> = Vec::new();
    for p in &fr.problems {
        if let Some(c) = split(p) {
            if c.source == source && c.space.is_none() && !function_names.contains(&c.function) {
                function_names.push(c.function);
            }
        }
    }
    let panels: Vec<OverlayPanel> = function_names
        .into_iter()
        .map(|function| overlay_panel(ds, fr, source, function, data))
        .collect();
    if panels.is_empty() {
        return None;
    }
    let slug: String = source
        .chars()
        .map(|ch| if ch.is_ascii_alphanumeric() { ch } else { '_' })
        .collect();
    Some(Plot {
        stem: format!("overlay_{slug}"),
        title: format!("Best fits of {source}"),
        caption: format!(
            "The data points of {source} (grey) and, for each fitting function, the fit \
             with the lowest E over all methods and runs for each continuity (circles mark \
             the segments' start points; the legend gives E and the method). Equal scale \
             in x and y."
        ),
        figure: Figure::Overlay(OverlayFigure {
            title: format!("{source}: best fit of each function"),
            panels,
            columns: 2,
        }),
    })
}

/// Overlays: per source, a panel per function with the best fit of each
/// continuity (technique search space). A source whose points are not in
/// `outlines` gets a note instead.
fn overlays(
    ds: &Dataset,
    fr: &FitRuns<'_>,
    outlines: &BTreeMap<String, Vec<Point>>,
    notes: &mut Vec<String>,
) -> Vec<Plot> {
    let mut sources: Vec<&str> = fr
        .problems
        .iter()
        .filter_map(|p| split(p).map(|c| c.source))
        .collect();
    sources.dedup();
    let mut seen = std::collections::BTreeSet::new();
    sources.retain(|s| seen.insert(*s));
    let mut figures = Vec::new();
    for source in sources {
        let Some(data) = outlines.get(source) else {
            notes.push(format!(
                "no overlay for {source}: outlines.csv does not hold its points"
            ));
            continue;
        };
        figures.extend(overlay_plot(ds, fr, source, data));
    }
    figures
}

/// The fitting section of the report in `dir`, or `None` if the campaign
/// has no fitting runs.
pub(crate) fn section(
    dir: &Path,
    ds: &Dataset,
    alpha: f64,
) -> Result<Option<FittingSection>, ReadError> {
    if !dir.join("fits.csv").exists() {
        return Ok(None);
    }
    let records = read_results(dir)?;
    let fr = FitRuns::group(ds, &records);
    let best = fr.best();
    let mut notes = Vec::new();
    let mut tables = vec![quality_table(&fr, &best), functions_table(&fr, &best)];
    let paired = super::data::provenance(dir)
        .paired
        .iter()
        .any(|f| f == "search_space");
    let space = search_space_table(&fr, alpha, paired);
    if !space.md_rows.is_empty() {
        tables.push(space);
    }
    let hybrid = hybrid_table(&fr);
    if hybrid.md_rows.is_empty() {
        notes.push(
            "no hybrid table: the campaign does not run a metaheuristic X, LM and X+lm together"
                .into(),
        );
    } else {
        tables.push(hybrid);
    }
    let outlines = read_outlines(dir)?;
    let figures = overlays(ds, &fr, &outlines, &mut notes);
    Ok(Some(FittingSection {
        tables,
        figures,
        notes,
    }))
}
