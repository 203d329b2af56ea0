//! The comparison families of a report: which correction family each
//! comparison against the reference belongs to, read from where each
//! optimiser is registered ([`crate::optim::OptimiserDef::family`]).

use std::collections::BTreeMap;

use crate::optim::{ComparisonFamily, Optimisers};

/// The comparison set of the algorithms beyond the thesis (CMA-ES, L-SHADE,
/// random search, a library user's own optimisers) against the reference:
/// a family of its own, so that adding one to a campaign leaves the Holm
/// families and the Friedman post-hoc test of the thesis's comparisons
/// (table `reference`) as they were; each question is corrected within its
/// own family (Bender & Lange 2001, "Adjusting for multiple testing — when
/// and how?", J. Clin. Epidemiol. 54(4):343–349). Which optimiser is in
/// which family is declared where it is registered
/// ([`crate::optim::OptimiserDef::family`]).
pub(crate) const STATE_OF_THE_ART: &str = "state-of-the-art";

/// The comparison families of the optimisers a report compares, by their
/// spec names: those of a library user's registry
/// ([`Families::of`]), else the built-in registry's; an optimiser neither
/// knows (an external `runs.csv`'s) is beyond the thesis. `lm`
/// (Levenberg–Marquardt, the exact reference of the fitting chapter) is
/// with the thesis's methods.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Families {
    registered: BTreeMap<String, ComparisonFamily>,
}

impl Families {
    /// The families declared by the optimisers of `registry`.
    pub fn of(registry: &Optimisers) -> Families {
        Families {
            registered: registry
                .names()
                .into_iter()
                .filter_map(|n| Some((n.to_owned(), registry.get(n)?.family)))
                .collect(),
        }
    }

    /// The family of a cell of kind `kind` (a fitting method `cmaes+lm` by
    /// its optimiser).
    pub fn family(&self, kind: &str) -> ComparisonFamily {
        let base = kind.split('+').next().unwrap_or(kind);
        if base == "lm" {
            return ComparisonFamily::Thesis;
        }
        self.registered
            .get(base)
            .copied()
            .or_else(|| Optimisers::builtin().get(base).map(|d| d.family))
            .unwrap_or_default()
    }

    /// Whether a cell of kind `kind` is beyond the thesis.
    pub(crate) fn beyond_the_thesis(&self, kind: &str) -> bool {
        self.family(kind) == ComparisonFamily::BeyondTheThesis
    }

    /// The comparison set of a cell of kind `kind` against the reference:
    /// the cell's family's table, unless the reference itself is beyond the
    /// thesis (`--reference CMA-ES`): then every comparison is in
    /// `reference`.
    pub(crate) fn comparison_set(&self, kind: &str, reference_kind: &str) -> &'static str {
        if self.beyond_the_thesis(kind) && !self.beyond_the_thesis(reference_kind) {
            STATE_OF_THE_ART
        } else {
            "reference"
        }
    }

    /// The comparison set of the pair of methods of kinds `a` and `b`:
    /// [`STATE_OF_THE_ART_PAIRS`] when either is beyond the thesis, else
    /// `method-pairs`.
    pub(crate) fn pair_set(&self, a: &str, b: &str) -> &'static str {
        if self.beyond_the_thesis(a) || self.beyond_the_thesis(b) {
            STATE_OF_THE_ART_PAIRS
        } else {
            "method-pairs"
        }
    }
}

/// The comparisons of two fitting methods of which at least one is beyond
/// the thesis: a family of its own beside `method-pairs`, for the reason
/// of [`STATE_OF_THE_ART`].
pub(crate) const STATE_OF_THE_ART_PAIRS: &str = "state-of-the-art-pairs";
