//! The counts of first-level outcomes per algorithm: marks and "both
//! solved".

use crate::stats::Mark;

use super::{Comparison, Outcome};

/// Mark counts per cell (the "both solved" rows are not marks).
pub(crate) fn tally(rows: &[Comparison], cells: usize) -> Vec<Tally> {
    let mut t = vec![Tally::default(); cells];
    for row in rows {
        if let (Some(o), Some(slot)) = (row.outcome, t.get_mut(row.cell)) {
            slot.add(o);
        }
    }
    t
}

/// Counts of first-level outcomes: marks and "both solved".
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct Tally {
    /// `+` marks.
    pub better: usize,
    /// `≈` marks.
    pub same: usize,
    /// `−` marks.
    pub worse: usize,
    /// Problems both solved on every run.
    pub both_solved: usize,
}

impl Tally {
    /// Adds one outcome.
    pub fn add(&mut self, o: Outcome) {
        match o {
            Outcome::Mark(Mark::Better) => self.better += 1,
            Outcome::Mark(Mark::Same) => self.same += 1,
            Outcome::Mark(Mark::Worse) => self.worse += 1,
            Outcome::BothSolved => self.both_solved += 1,
        }
    }

    /// Adds another tally.
    pub fn merge(&mut self, o: &Tally) {
        self.better += o.better;
        self.same += o.same;
        self.worse += o.worse;
        self.both_solved += o.both_solved;
    }

    /// The number of outcomes counted.
    pub fn total(&self) -> usize {
        self.better + self.same + self.worse + self.both_solved
    }
}
