//! Tests of the first-level comparisons and Friedman's ranking.

use super::friedman::NoRanking;
use super::*;
use crate::experiment::RunRecord;
use crate::test_records::record;

fn rec(alg: &str, problem: &str, run: u32, seed: u64, error: f64) -> (RunRecord, bool) {
    (
        RunRecord {
            budget: 100,
            seed,
            evaluations: 100,
            success: error <= 1e-8,
            ..record(alg, problem, run, error)
        },
        false,
    )
}

fn dataset(shared_seeds: bool) -> Dataset {
    let mut v = Vec::new();
    for run in 0..10 {
        let x = f64::from(run);
        let seed = |alg: u64| {
            if shared_seeds {
                u64::from(run)
            } else {
                alg * 100 + u64::from(run)
            }
        };
        // On "a": A always better than R, B always worse, C equal.
        v.push(rec("R", "a", run, seed(0), 1.0 + x));
        v.push(rec("A", "a", run, seed(1), 0.5 + x * 0.9));
        v.push(rec("B", "a", run, seed(2), 20.0 + x));
        v.push(rec("C", "a", run, seed(3), 1.0 + x));
        // On "s": every run of R and A solved, B not.
        v.push(rec("R", "s", run, seed(0), 1e-9));
        v.push(rec("A", "s", run, seed(1), 1e-12));
        v.push(rec("B", "s", run, seed(2), 1.0));
        v.push(rec("C", "s", run, seed(3), 1e-10));
    }
    Dataset::from_records(v)
}

fn row<'s>(ds: &Dataset, s: &'s Significance, alg: &str, prob: &str) -> &'s Comparison {
    s.tests
        .iter()
        .find(|r| ds.cells[r.cell].label == alg && ds.problems[r.problem].function == prob)
        .unwrap()
}

#[test]
fn the_test_follows_the_design_and_marks_are_from_the_compared_view() {
    for shared in [false, true] {
        let ds = dataset(shared);
        let s = significance(&ds, 0, 0.05, Some(1e-8));
        let kind = row(&ds, &s, "A", "a").result.as_ref().unwrap().kind;
        assert_eq!(
            kind,
            if shared {
                TestKind::SignedRank
            } else {
                TestKind::MannWhitney
            }
        );
        let mark = |alg| row(&ds, &s, alg, "a").outcome.unwrap();
        assert_eq!(mark("B"), Outcome::Mark(Mark::Worse));
        assert_eq!(mark("C"), Outcome::Mark(Mark::Same));
        // Paired, A is better on every run; unpaired, its shift is small
        // against the spread (MW cannot tell).
        if shared {
            assert_eq!(mark("A"), Outcome::Mark(Mark::Better));
        }
        // Below the threshold on both sides: both solved, not a mark.
        assert_eq!(row(&ds, &s, "A", "s").outcome, Some(Outcome::BothSolved));
        assert_eq!(row(&ds, &s, "C", "s").outcome, Some(Outcome::BothSolved));
        assert_eq!(
            row(&ds, &s, "B", "s").outcome,
            Some(Outcome::Mark(Mark::Worse))
        );
        // The ratio of floored medians is 1 when both solved.
        assert_eq!(row(&ds, &s, "A", "s").effect, 1.0);
        let c = row(&ds, &s, "C", "a");
        assert_eq!(c.effect, 1.0);
        assert_eq!(c.a12, Some(0.5));
        let ci = c.ci.unwrap();
        assert!(ci.low <= 1.0 && ci.high >= 1.0, "{ci:?}");
        let b = row(&ds, &s, "B", "a");
        assert!(b.a12.unwrap() > 0.5 && b.ci.unwrap().low > 1.0);
        for r in &s.tests {
            let raw = r.result.as_ref().unwrap().p_value;
            assert!(r.p_holm.unwrap() >= raw);
        }
        assert!(s.anytime.is_empty(), "no hits were read");
    }
}

#[test]
fn the_same_data_gives_the_same_intervals() {
    let ds = dataset(false);
    let a = significance(&ds, 0, 0.05, Some(1e-8));
    let b = significance(&ds, 0, 0.05, Some(1e-8));
    assert_eq!(a.tests, b.tests);
}

#[test]
fn friedman_ranks_units_and_single_algorithm() {
    let ds = dataset(false);
    let s = significance(&ds, 0, 0.05, Some(1e-8));
    let (_, standings) = observations(&ds, &s);
    let f = friedman_report(&ds, &standings, 0.05, "function");
    let r = f.ranking.as_ref().unwrap();
    assert_eq!(r.test.n_blocks, 2);
    assert_eq!(r.test.n_treatments, 4);
    let t = friedman_table(&ds, &f, 0.05);
    assert_eq!(t.md_rows.len(), 4);
    assert_eq!(t.md_rows[0][4], "best");

    let one = Dataset::from_records(vec![rec("R", "a", 0, 0, 1.0)]);
    let s = significance(&one, 0, 0.05, None);
    assert!(s.tests.is_empty());
    let (_, standings) = observations(&one, &s);
    let f = friedman_report(&one, &standings, 0.05, "function");
    assert_eq!(f.ranking.as_ref().unwrap_err(), &NoRanking::SingleAlgorithm);
}
