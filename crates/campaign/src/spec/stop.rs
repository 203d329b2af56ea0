//! `experiment.stop`: where a benchmark run ends.

use std::fmt;

/// Where a benchmark run ends (`[experiment] stop = "budget" | "target"`).
///
/// The thesis's design compares what each optimiser reaches within a fixed
/// budget (final errors, convergence curves to the budget), so `Budget` is
/// the default. `Target` ends a run at its first evaluation with
/// `f − f* ≤ threshold`, as COCO's experiments stop at their final target
/// (Hansen, Auger, Ros, Mersmann, Tušar & Brockhoff 2021, "COCO: a platform
/// for comparing continuous optimizers in a black-box setting", Optim.
/// Methods Softw. 36(1):114–144): evaluations to target and success rates
/// are unchanged, a successful run's remaining budget is not spent, and its
/// final error is only known to be below the threshold.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Stop {
    /// Every run spends its whole budget.
    #[default]
    Budget,
    /// A run ends when it reaches its target `f* + threshold`.
    Target,
}

impl Stop {
    /// The spec's names, in the order the error messages list them.
    pub const NAMES: [&'static str; 2] = ["budget", "target"];

    /// The choice named `name` in a spec, if any.
    pub fn from_name(name: &str) -> Option<Stop> {
        match name {
            "budget" => Some(Stop::Budget),
            "target" => Some(Stop::Target),
            _ => None,
        }
    }

    /// Its name in a spec.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }
}

impl fmt::Display for Stop {
    /// Writes [`Stop::name`].
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}
