//! Statistics for comparing optimisers: descriptive summaries, success
//! measures (success rate, COCO aRT), midranks, the Wilcoxon signed-rank,
//! Mann–Whitney U and Friedman tests, the Nemenyi critical difference, Holm's
//! correction and the "+ / − / ≈" marks of metaheuristics papers; beside the
//! p-values, the Hodges–Lehmann estimate with its exact signed-rank interval
//! ([`hodges_lehmann_interval`]) and the Bayesian signed-rank test with a
//! region of practical equivalence ([`bayesian_signed_rank`], as `baycomp`).
//!
//! Pure functions on slices of `f64`; the tests reproduce SciPy 1.17.1
//! (`scipy.stats.wilcoxon`, `mannwhitneyu`, `friedmanchisquare`) and
//! statsmodels 0.15.0 (`multipletests(method="holm")`). Bad input (empty
//! samples, NaN, ragged matrices) yields a [`StatsError`], never a panic.

mod bayes_signed_rank;
mod descriptive;
mod effect;
mod error;
mod friedman;
mod hodges_lehmann;
mod holm;
mod hypothesis;
mod mannwhitney;
mod mark;
mod nemenyi;
mod posthoc;
mod ranks;
mod success;
mod verdict;
mod wilcoxon;

#[cfg(test)]
mod reference_tests;

pub use bayes_signed_rank::{bayesian_signed_rank, BayesSignedRank, RopePosterior};
pub use descriptive::{median, quantile, quantile_sorted, summarize, Summary};
pub use effect::{
    bootstrap_interval, median_in_place, ratio_of_medians, vargha_delaney_a12, Interval, Resampling,
};
pub use error::StatsError;
pub use friedman::{friedman, FriedmanResult};
pub use hodges_lehmann::{hodges_lehmann_interval, ShiftInterval, HODGES_LEHMANN_MAX_N};
pub use holm::holm_bonferroni;
pub use hypothesis::{Alternative, PValueMethod};
pub use mannwhitney::{mann_whitney_u, MannWhitneyResult, MANN_WHITNEY_EXACT_MAX_MIN_N};
pub use mark::{Mark, MarkTally, DEFAULT_ALPHA};
pub use nemenyi::{nemenyi_critical_difference, nemenyi_q};
pub use posthoc::{
    finner, friedman_control_posthoc, smallest_friedman_control_p, ControlComparison,
};
pub use ranks::{average_ranks, tie_term, Ranks};
pub use success::{
    average_runtime, mean_evaluations_to_success, success_rate, success_summary, RunOutcome,
    SuccessSummary,
};
pub use verdict::{
    across_units, decide_family, smallest_signed_rank_p, unit_evidence, verdict_seed, AcrossUnits,
    Equivalence, Verdict, VerdictRow, VerdictTest, EFFECT_CONFIDENCE, EQUIVALENCE_MIN_UNITS,
    EQUIVALENCE_PROBABILITY, VERDICT_COLUMNS,
};
pub use wilcoxon::{
    wilcoxon, wilcoxon_signed_rank, wilcoxon_signed_rank_with, WilcoxonResult,
    WILCOXON_EXACT_MAX_N, WILCOXON_PERMUTATION_MAX_N,
};
