//! Tests of the descriptive statistics and their table.

use super::*;
use crate::experiment::RunRecord;
use crate::test_records::record;

fn rec(run: u32, error: f64, evals_to_target: Option<u64>) -> (RunRecord, bool) {
    (
        RunRecord {
            params: "x=1".into(),
            evaluations_to_target: evals_to_target,
            success: evals_to_target.is_some(),
            ..record("A", "sphere", run, error)
        },
        false,
    )
}

#[test]
fn art_counts_evaluations_to_target_of_successes_and_all_of_failures() {
    let ds = Dataset::from_records(vec![
        rec(0, 1e-9, Some(100)),
        rec(1, 0.5, None),
        rec(2, 1e-9, Some(300)),
        rec(3, 0.2, None),
    ]);
    let stats = compute(&ds);
    let s = stats[0][0].as_ref().unwrap();
    let sc = s.success.as_ref().unwrap();
    assert_eq!(sc.success_rate, 0.5);
    assert_eq!(sc.mean_evaluations_to_success, Some(200.0));
    assert_eq!(
        sc.average_runtime,
        Some((100.0 + 1000.0 + 300.0 + 1000.0) / 2.0)
    );
    let t = table(&ds, &stats);
    assert_eq!(t.md_rows.len(), 1);
    assert_eq!(t.md_rows[0][9], "50%");
    assert_eq!(t.md_rows[0][11], "1200");
    assert_eq!(t.csv_rows[0][16], "1200");
}

#[test]
fn single_run_and_nan() {
    let ds = Dataset::from_records(vec![rec(0, f64::NAN, None)]);
    let stats = compute(&ds);
    let t = table(&ds, &stats);
    assert_eq!(t.md_rows[0][6], "\u{2014}");
    assert_eq!(t.md_rows[0][11], "\u{2014}");
    assert_eq!(mean_sd(stats[0][0].as_ref()), "\u{2014}");
    let ds = Dataset::from_records(vec![rec(0, 0.25, None)]);
    let stats = compute(&ds);
    assert_eq!(mean_sd(stats[0][0].as_ref()), "2.50e-01");
}
