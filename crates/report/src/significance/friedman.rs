//! Friedman's test over the units on which every algorithm has a
//! final-error standing, with the Nemenyi critical difference (Demšar 2006).

use std::collections::BTreeMap;

use crate::stats::{friedman, median, nemenyi_critical_difference, FriedmanResult, StatsError};

use super::super::data::Dataset;
use super::super::verdicts::{Measure, Standing, STATE_OF_THE_ART};

/// Why there is no Friedman ranking; the text is shown in the report.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub(crate) enum NoRanking {
    /// There is one algorithm only.
    #[error("a single algorithm: there is nothing to rank")]
    SingleAlgorithm,
    /// No unit has a value for every algorithm.
    #[error("no unit was run by every algorithm")]
    NoCommonUnit,
    /// The test rejected the blocks.
    #[error(transparent)]
    Test(#[from] StatsError),
}

/// The Friedman test and the Nemenyi critical difference that goes with it.
#[derive(Clone, Debug)]
pub(crate) struct Ranking {
    /// The Friedman test.
    pub test: FriedmanResult,
    /// The critical difference at α, or why it is not available.
    pub cd: Result<f64, StatsError>,
}

/// The Friedman test over the units and the Nemenyi critical difference.
#[derive(Clone, Debug)]
pub(crate) struct FriedmanReport {
    /// The units used as blocks.
    pub blocks: Vec<String>,
    /// The test and critical difference, or why there are none.
    pub ranking: Result<Ranking, NoRanking>,
    /// What the units are called.
    pub noun: &'static str,
}

/// Friedman's test with blocks = the units on which every algorithm has a
/// final-error standing (the median over the unit's problems of log10 of
/// the floored median error), ranked within each unit.
pub(crate) fn friedman_report(
    ds: &Dataset,
    standings: &[Standing],
    alpha: f64,
    noun: &'static str,
) -> FriedmanReport {
    let k = ds.cells.len();
    let mut by: BTreeMap<(&str, &str), Vec<f64>> = BTreeMap::new();
    for s in standings.iter().filter(|s| {
        (s.table == "reference" || s.table == STATE_OF_THE_ART) && s.measure == Measure::FinalError
    }) {
        by.entry((&s.unit, &s.algorithm)).or_default().push(s.value);
    }
    let mut units: Vec<&str> = by.keys().map(|(u, _)| *u).collect();
    units.dedup();
    let mut blocks = Vec::new();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    for u in units {
        let row: Option<Vec<f64>> = ds
            .cells
            .iter()
            .map(|c| by.get(&(u, c.name.as_str())).map(|v| median(v)))
            .collect();
        if let Some(row) = row {
            blocks.push(u.to_owned());
            rows.push(row);
        }
    }
    let ranking = if k < 2 {
        Err(NoRanking::SingleAlgorithm)
    } else if rows.is_empty() {
        Err(NoRanking::NoCommonUnit)
    } else {
        friedman(&rows)
            .map_err(NoRanking::from)
            .map(|test| Ranking {
                test,
                cd: nemenyi_critical_difference(k, rows.len(), alpha),
            })
    };
    FriedmanReport {
        blocks,
        ranking,
        noun,
    }
}
