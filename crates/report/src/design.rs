//! The design of a campaign as the report reads it: the factors that vary
//! among its problems, the design points (combinations of their levels),
//! the scopes over which verdicts are stated, and the independent unit of
//! each problem.
//!
//! A design point is one combination of the factors that vary in the
//! results other than the algorithm, the function and the run: the
//! dimension, the budget, the transform and the bbob group of benchmark
//! problems; the fitting function, the continuity, the budget per segment,
//! the search space, the technique's α_size, the problem mode, the error
//! (fixed parameters or orthogonal), the chain (sequential or joint) and
//! what was held equal (segments or free parameters) of fitting cases. A scope is `all`, one factor level (`transform=shift`)
//! or one design point (`transform=shift;budget=10000`).
//!
//! Units are what a test across problems may count as independent: a
//! benchmark function (its instances, dimensions and other factor levels
//! within a scope summarised by their median, so that instances are not
//! counted as replicates), a fitted outline, or, for per-segment fitting
//! problems, a segment.

use std::collections::{BTreeMap, BTreeSet};

use crate::files::fmt_real;
use crate::fit::ALPHA_SIZE;
use metabezier_bbob::bbob_group;

use super::data::{Dataset, Problem};
use super::fit_runs::split;

/// A factor level, ordered numerically where it is a number.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) enum Level {
    /// A numeric level (a dimension, a budget).
    Number(u64),
    /// A named level (a transform, a search space).
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

/// The design factors in their fixed order: (key in scopes and CSV
/// headers, name in the Markdown).
pub(crate) const FACTORS: [(&str, &str); 14] = [
    ("function", "function"),
    ("continuity", "continuity"),
    ("dim", "D"),
    ("budget", "budget"),
    ("budget_per_segment", "budget per segment"),
    ("transform", "transform"),
    ("bbob_group", "bbob group"),
    ("search_space", "search space"),
    ("alpha_size", "α_size"),
    ("mode", "mode"),
    ("error", "error"),
    ("chain", "chain"),
    ("size", "held equal"),
    ("method", "method"),
];

/// The Markdown name of a factor key (`dim` → `D`).
pub(crate) fn factor_name(key: &str) -> &'static str {
    FACTORS
        .iter()
        .find(|(k, _)| *k == key)
        .map_or("factor", |(_, n)| n)
}

/// How a factor and its level read in a sentence: `D = 30`, `budget 1000`.
pub(crate) fn phrase(key: &str, level: &Level) -> String {
    match key {
        "dim" => format!("D = {level}"),
        "search_space" => format!("the {level} search space"),
        "alpha_size" => format!("α_size {level}"),
        "mode" => format!("{level} problems"),
        "function" => format!("{level}"),
        "continuity" => level.to_string().to_uppercase(),
        "error" => format!("the {level} error"),
        "chain" => format!("the {level} chain"),
        "size" => format!("equal {}", level.to_string().replace('-', " ")),
        "method" => format!("{level}"),
        _ => format!("{} {level}", factor_name(key)),
    }
}

/// Factor levels in the order of [`FACTORS`]: a design point or a scope.
#[derive(Clone, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(crate) struct Levels(pub Vec<(&'static str, Level)>);

impl Levels {
    /// `all problems`, or the levels as a phrase: `budget 1000, D = 30`.
    pub fn label(&self) -> String {
        if self.0.is_empty() {
            return "all problems".into();
        }
        self.0
            .iter()
            .map(|(f, l)| phrase(f, l))
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// The scope text of `verdicts.csv`: `all`, or `key=level;key=level`.
    pub fn scope(&self) -> String {
        if self.0.is_empty() {
            return "all".into();
        }
        self.0
            .iter()
            .map(|(f, l)| format!("{f}={l}"))
            .collect::<Vec<_>>()
            .join(";")
    }

    /// Whether every level of `self` is also a level of `other`.
    pub fn within(&self, other: &Levels) -> bool {
        self.0.iter().all(|fl| other.0.contains(fl))
    }
}

/// Every candidate factor of a problem with its level, in the order of
/// [`FACTORS`]; a fitting case's levels are read from its name (see
/// [`super::fit_runs::split`]).
pub(crate) fn factors(p: &Problem) -> Levels {
    if p.is_fit() {
        return fit_levels(&p.function, p.budget.map(|b| b / p.dim.max(1) as u64));
    }
    let mut out = vec![("dim", Level::Number(p.dim as u64))];
    if let Some(b) = p.budget {
        out.push(("budget", Level::Number(b)));
    }
    out.push(("transform", Level::Text(p.transform.name().into())));
    if let Some(f) = bbob_function_of(&p.function) {
        out.push(("bbob_group", Level::Text(bbob_group(f).into())));
    }
    Levels(out)
}

/// The levels of a fitting case named `name` (`source/function/continuity`
/// and its suffixes) with its budget per segment when that is a factor.
pub(crate) fn fit_levels(name: &str, budget_per_segment: Option<u64>) -> Levels {
    let mut out = Vec::new();
    let case = split(name);
    if let Some(c) = case {
        out.push(("function", Level::Text(c.function.into())));
        out.push(("continuity", Level::Text(c.continuity.into())));
    }
    if let Some(b) = budget_per_segment {
        out.push(("budget_per_segment", Level::Number(b)));
    }
    let space = case.and_then(|c| c.space).unwrap_or("technique");
    out.push(("search_space", Level::Text(space.into())));
    let alpha = case
        .and_then(|c| c.alpha)
        .map_or_else(|| fmt_real(ALPHA_SIZE.default), str::to_owned);
    out.push(("alpha_size", Level::Text(alpha)));
    let mode = if case.is_some_and(|c| c.per_segment) {
        "per-segment"
    } else {
        "outline"
    };
    out.push(("mode", Level::Text(mode.into())));
    if let Some(c) = case {
        out.push(("error", Level::Text(c.error().into())));
        out.push(("chain", Level::Text(c.chain().into())));
        out.push(("size", Level::Text(c.size().into())));
    }
    Levels(out)
}

/// `levels` without the factors in `drop`.
pub(crate) fn without(levels: &Levels, drop: &[&str]) -> Levels {
    Levels(
        levels
            .0
            .iter()
            .filter(|(f, _)| !drop.contains(f))
            .cloned()
            .collect(),
    )
}

/// The bbob function index of a COCO problem id (`bbob_f008_i02_d05`, or
/// pooled over instances `bbob_f008_d05`).
pub(crate) fn bbob_function_of(id: &str) -> Option<usize> {
    id.strip_prefix("bbob_f")?.get(..3)?.parse().ok()
}

/// The factor keys that take more than one level among `levels`.
pub(crate) fn varying(levels: &[Levels]) -> BTreeSet<&'static str> {
    let mut seen: BTreeMap<&'static str, BTreeSet<&Level>> = BTreeMap::new();
    for ls in levels {
        for (f, l) in &ls.0 {
            seen.entry(f).or_default().insert(l);
        }
    }
    seen.into_iter()
        .filter(|(_, l)| l.len() > 1)
        .map(|(f, _)| f)
        .collect()
}

/// `levels` restricted to the factor keys in `keep`.
pub(crate) fn restrict(levels: &Levels, keep: &BTreeSet<&'static str>) -> Levels {
    Levels(
        levels
            .0
            .iter()
            .filter(|(f, _)| keep.contains(f))
            .cloned()
            .collect(),
    )
}

/// The design point of every problem: its factors restricted to those that
/// vary among the problems.
pub(crate) fn design_points(ds: &Dataset) -> Vec<Levels> {
    let all: Vec<Levels> = ds.problems.iter().map(factors).collect();
    let keep = varying(&all);
    all.iter().map(|l| restrict(l, &keep)).collect()
}

/// The scopes of a set of design points, in the order verdicts are shown:
/// `all`, then every level of every varying factor, then every design
/// point when two or more factors vary.
pub(crate) fn scopes(points: &[Levels]) -> Vec<Levels> {
    let keep = varying(points);
    let mut out = vec![Levels::default()];
    for (key, _) in FACTORS {
        if !keep.contains(key) {
            continue;
        }
        let levels: BTreeSet<&Level> = points
            .iter()
            .flat_map(|p| p.0.iter().filter(|(f, _)| *f == key).map(|(_, l)| l))
            .collect();
        out.extend(levels.into_iter().map(|l| Levels(vec![(key, l.clone())])));
    }
    if keep.len() > 1 {
        let distinct: BTreeSet<Levels> = points.iter().map(|p| restrict(p, &keep)).collect();
        out.extend(distinct);
    }
    out
}

/// The independent unit of a problem: the benchmark function (a bbob
/// problem's function index, `bbob_f008`), or the fitted outline's source.
/// `None` for a per-segment fitting problem, whose units are its segments.
///
/// The pooling rule, the same for every suite: each (function, instance,
/// dimension, budget, transform) is a problem of its own at the first
/// level (a test of its runs), and the problems of one unit within a
/// scope are pooled into one summary by their median before the test
/// across units. So the thesis's ten functions give at most 10 units
/// whatever their instances and transforms (ch4), bbob's 24 functions at
/// most 24 whatever their instances 1–5 and dimensions (their instances
/// are not independent problems: one function, shifted and rotated), and
/// a fitting campaign as many as its outlines or segments.
pub(crate) fn unit(p: &Problem) -> Option<String> {
    if p.is_fit() {
        let case = split(&p.function)?;
        return (!case.per_segment).then(|| case.source.to_owned());
    }
    match p.function.strip_prefix("bbob_f").and_then(|r| r.get(..3)) {
        Some(f) => Some(format!("bbob_f{f}")),
        None => Some(p.function.clone()),
    }
}

/// What the units of a dataset are called in sentences: `function`,
/// `outline` or `segment`.
pub(crate) fn unit_noun(ds: &Dataset) -> &'static str {
    if !ds.problems.iter().any(Problem::is_fit) {
        "function"
    } else if ds
        .problems
        .iter()
        .filter_map(|p| split(&p.function))
        .any(|c| c.per_segment)
    {
        "segment"
    } else {
        "outline"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn levels(v: &[(&'static str, u64)]) -> Levels {
        Levels(v.iter().map(|(k, l)| (*k, Level::Number(*l))).collect())
    }

    #[test]
    fn scopes_are_all_levels_and_points() {
        let points = vec![
            levels(&[("dim", 10), ("budget", 1000)]),
            levels(&[("dim", 10), ("budget", 2000)]),
            levels(&[("dim", 30), ("budget", 1000)]),
        ];
        let s: Vec<String> = scopes(&points).iter().map(Levels::scope).collect();
        assert_eq!(
            s,
            [
                "all",
                "dim=10",
                "dim=30",
                "budget=1000",
                "budget=2000",
                "dim=10;budget=1000",
                "dim=10;budget=2000",
                "dim=30;budget=1000"
            ]
        );
        // One varying factor: its levels are the design points.
        let one = vec![levels(&[("dim", 10)]), levels(&[("dim", 30)])];
        assert_eq!(scopes(&one).len(), 3);
        assert_eq!(scopes(&[Levels::default()]).len(), 1);
        assert!(levels(&[("dim", 10)]).within(&points[0]));
        assert!(!levels(&[("dim", 30)]).within(&points[0]));
        assert_eq!(points[0].label(), "D = 10, budget 1000");
    }
}
