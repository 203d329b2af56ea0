//! The fitting runs of a report grouped by problem and method
//! ([`FitRuns`]), the parts of a fitting problem name ([`split`]) and the
//! two-sample test of two methods or search spaces ([`two_sample_test`]):
//! what both the whole-outline section ([`super::fitting`]) and the
//! segment-level tests ([`super::fit_units`]) read.

use std::collections::BTreeMap;

use super::data::Dataset;
use crate::experiment::records::RunRecord;
use crate::stats::{mann_whitney_u, wilcoxon, Alternative};

/// A fitting problem name split into its parts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Case<'a> {
    /// The source (file stem or `font-glyph`).
    pub source: &'a str,
    /// The fitting function.
    pub function: &'a str,
    /// The continuity.
    pub continuity: &'a str,
    /// `Some("bounding-box")` for the naive search space, `None` for the
    /// technique.
    pub space: Option<&'a str>,
    /// The technique's α_size when it is a listed value other than 0.5.
    pub alpha: Option<&'a str>,
    /// Whether the case is in the per-segment mode.
    pub per_segment: bool,
    /// The section's `free_parameters` (`params=P`), when they set the
    /// segments.
    pub params: Option<&'a str>,
    /// Whether E is the orthogonal error (`orthogonal`) rather than the
    /// thesis's fixed-parameter E.
    pub orthogonal: bool,
    /// Whether the chain was solved jointly (`joint`).
    pub joint: bool,
}

impl Case<'_> {
    /// `source/function/continuity`, `/per-segment` and the variant: what
    /// a technique case and its bounding-box twin share.
    pub fn base(&self) -> String {
        let mut s = format!("{}/{}/{}", self.source, self.function, self.continuity);
        if self.per_segment {
            s.push_str("/per-segment");
        }
        let variant = self.variant();
        if !variant.is_empty() {
            s = format!("{s}/{variant}");
        }
        s
    }

    /// The name's tail after the mode: `params=P`, `orthogonal` and
    /// `joint` as they apply, joined by `/`; empty for the thesis's case
    /// (fixed parameters, sequential chain, a segment count).
    pub fn variant(&self) -> String {
        let mut parts = Vec::new();
        if let Some(p) = self.params {
            parts.push(format!("params={p}"));
        }
        if self.orthogonal {
            parts.push("orthogonal".into());
        }
        if self.joint {
            parts.push("joint".into());
        }
        parts.join("/")
    }

    /// The error as a design level: `fixed` or `orthogonal`.
    pub fn error(&self) -> &'static str {
        if self.orthogonal {
            "orthogonal"
        } else {
            "fixed"
        }
    }

    /// The chain as a design level: `sequential` or `joint`.
    pub fn chain(&self) -> &'static str {
        if self.joint {
            "joint"
        } else {
            "sequential"
        }
    }

    /// What the section held equal as a design level: `segments`, or
    /// `free-parameters` for `free_parameters = P` (whatever `P`, so that
    /// outlines given different counts form one design point).
    pub fn size(&self) -> &'static str {
        if self.params.is_some() {
            "free-parameters"
        } else {
            "segments"
        }
    }

    /// The search space as a design level: `bounding-box`, or
    /// `technique` with its α_size (`technique` alone at the default).
    pub fn space_level(&self) -> String {
        match (self.space, self.alpha) {
            (Some(s), _) => s.to_owned(),
            (None, Some(a)) => format!("technique, α = {a}"),
            (None, None) => "technique".into(),
        }
    }
}

/// The parts of a fitting problem name; `None` for another name.
pub(crate) fn split(name: &str) -> Option<Case<'_>> {
    let mut parts = name.split('/');
    let mut case = Case {
        source: parts.next()?,
        function: parts.next()?,
        continuity: parts.next()?,
        space: None,
        alpha: None,
        per_segment: false,
        params: None,
        orthogonal: false,
        joint: false,
    };
    // The tail in the order `FitCase::seed_name` writes it: space, α_size,
    // mode, free parameters, error, chain.
    let mut tail = false;
    for part in parts {
        match part {
            _ if part.starts_with("params=") && case.params.is_none() && !case.orthogonal => {
                case.params = Some(&part["params=".len()..]);
                tail = true;
            }
            "orthogonal" if !case.orthogonal && !case.joint => {
                case.orthogonal = true;
                tail = true;
            }
            "joint" if !case.joint => {
                case.joint = true;
                tail = true;
            }
            _ if tail => return None,
            "per-segment" if !case.per_segment => case.per_segment = true,
            _ if part.starts_with("alpha=") && case.alpha.is_none() => {
                case.alpha = Some(&part["alpha=".len()..]);
            }
            _ if case.space.is_none() && case.alpha.is_none() && !case.per_segment => {
                case.space = Some(part);
            }
            _ => return None,
        }
    }
    Some(case)
}

/// The display name of a run's method: the name of its cell in the report,
/// or its algorithm label when no cell matches.
pub(crate) fn cell_name(ds: &Dataset, r: &RunRecord) -> String {
    ds.cells
        .iter()
        .find(|c| !c.external && c.label == r.algorithm && c.kind == r.kind && c.params == r.params)
        .map_or_else(|| r.algorithm.clone(), |c| c.name.clone())
}

/// A fitting problem of the section: its name and, when runs of the name
/// differ in budget, its budget per segment.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct FitProblem {
    /// The problem name.
    pub name: String,
    /// The budget per segment, when it tells problems of one name apart.
    pub budget: Option<u64>,
}

impl FitProblem {
    /// The name, with `, budget B per segment` when there is one.
    pub fn label(&self) -> String {
        match self.budget {
            Some(b) => format!("{}, budget {b} per segment", self.name),
            None => self.name.clone(),
        }
    }
}

/// The fitting runs grouped by problem and method, both in the order of
/// their first appearance.
pub(crate) struct FitRuns<'r> {
    /// The problems.
    pub problems: Vec<FitProblem>,
    /// Method (cell) names.
    pub cells: Vec<String>,
    /// (problem, cell) → its runs.
    pub runs: BTreeMap<(usize, usize), Vec<&'r RunRecord>>,
    /// The comparison families of the methods' optimisers.
    pub families: crate::families::Families,
}

impl<'r> FitRuns<'r> {
    /// Groups the records that have fit details.
    pub fn group(ds: &Dataset, records: &'r [RunRecord]) -> Self {
        let fits: Vec<&RunRecord> = records.iter().filter(|r| r.fit.is_some()).collect();
        let mut budgets: BTreeMap<&str, std::collections::BTreeSet<u64>> = BTreeMap::new();
        for r in &fits {
            budgets.entry(&r.problem).or_default().insert(r.budget);
        }
        let mut problems: Vec<FitProblem> = Vec::new();
        let mut cells: Vec<String> = Vec::new();
        let mut runs: BTreeMap<(usize, usize), Vec<&RunRecord>> = BTreeMap::new();
        for r in fits {
            let key = FitProblem {
                name: r.problem.clone(),
                budget: (budgets[r.problem.as_str()].len() > 1)
                    .then(|| r.budget / r.dim.max(1) as u64),
            };
            let p = position_or_push(&mut problems, key);
            let c = position_or_push(&mut cells, cell_name(ds, r));
            runs.entry((p, c)).or_default().push(r);
        }
        FitRuns {
            families: ds.families.clone(),
            problems,
            cells,
            runs,
        }
    }

    /// The final E of every run of cell `c` on problem `p`, if it ran.
    pub fn errors(&self, p: usize, c: usize) -> Option<Vec<f64>> {
        self.runs
            .get(&(p, c))
            .map(|rs| rs.iter().map(|r| r.best).collect())
    }

    /// The best E per problem over every method and run, and the method
    /// that found it.
    pub(crate) fn best(&self) -> Vec<(f64, String)> {
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
    pub(crate) fn kinds(&self) -> Vec<Option<String>> {
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

/// The position of `item` in `list`, appended if absent.
fn position_or_push<T: PartialEq>(list: &mut Vec<T>, item: T) -> usize {
    match list.iter().position(|q| *q == item) {
        Some(i) => i,
        None => {
            list.push(item);
            list.len() - 1
        }
    }
}

/// A test of E with the technique against E in the bounding box: its
/// p-value and its signed statistic (negative when the technique's E
/// tends to be lower).
pub(crate) struct SpaceTest {
    /// The two-sided p-value.
    pub p_value: f64,
    /// Negative when the first sample tends to be lower.
    pub direction: f64,
    /// The statistic written to the CSV file: R⁺ − R⁻ or U.
    pub statistic: f64,
    /// `wilcoxon` (paired) or `mann-whitney`.
    pub test: &'static str,
}

/// The two-sided test of `a` against `b`: Wilcoxon signed-rank paired by
/// run when `paired` (same seeds, run by run), else Mann–Whitney U.
pub(crate) fn two_sample_test(a: &[f64], b: &[f64], paired: bool) -> Option<SpaceTest> {
    if paired && a.len() == b.len() {
        wilcoxon(a, b, Alternative::TwoSided)
            .ok()
            .map(|w| SpaceTest {
                p_value: w.p_value,
                direction: w.r_plus - w.r_minus,
                statistic: w.r_plus - w.r_minus,
                test: "wilcoxon",
            })
    } else {
        mann_whitney_u(a, b, Alternative::TwoSided)
            .ok()
            .map(|m| SpaceTest {
                p_value: m.p_value,
                direction: m.statistic - (m.n1 * m.n2) as f64 / 2.0,
                statistic: m.statistic,
                test: "mann-whitney",
            })
    }
}

/// Whether the runs of cell `c` on problems `p` and `q` share their seeds
/// run by run (so that they are paired).
pub(crate) fn same_seeds(fr: &FitRuns<'_>, p: usize, q: usize, c: usize) -> bool {
    let seeds = |p: usize| -> Option<Vec<(u32, u64)>> {
        let mut v: Vec<(u32, u64)> = fr
            .runs
            .get(&(p, c))?
            .iter()
            .map(|r| (r.run, r.seed))
            .collect();
        v.sort_unstable();
        Some(v)
    };
    matches!((seeds(p), seeds(q)), (Some(a), Some(b)) if a == b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_split_into_their_parts_and_variants() {
        let c = split("horse/rational-cubic/g1").unwrap();
        assert_eq!(
            (c.source, c.function, c.continuity),
            ("horse", "rational-cubic", "g1")
        );
        assert_eq!(
            (c.variant().as_str(), c.error(), c.chain()),
            ("", "fixed", "sequential")
        );
        assert_eq!(c.size(), "segments");

        let c = split("coin/cubic/c1/bounding-box/per-segment/orthogonal").unwrap();
        assert_eq!(c.space, Some("bounding-box"));
        assert!(c.per_segment && c.orthogonal && !c.joint);
        assert_eq!(c.base(), "coin/cubic/c1/per-segment/orthogonal");

        let c = split("g/quadratic/g1/params=60/orthogonal/joint").unwrap();
        assert_eq!(c.params, Some("60"));
        assert_eq!(
            (c.error(), c.chain(), c.size()),
            ("orthogonal", "joint", "free-parameters")
        );
        assert_eq!(c.variant(), "params=60/orthogonal/joint");
        // A technique twin and its bounding box share the variant.
        let t = split("g/quadratic/g1/alpha=0.1/params=60/orthogonal/joint").unwrap();
        assert_eq!(t.base(), c.base());

        // Out of order or repeated: not a fitting name.
        for bad in [
            "g/quadratic/g1/joint/orthogonal",
            "g/quadratic/g1/orthogonal/params=60",
            "g/quadratic/g1/joint/per-segment",
            "g/quadratic/g1/joint/joint",
            "g/quadratic",
        ] {
            assert_eq!(split(bad), None, "{bad}");
        }
    }
}
