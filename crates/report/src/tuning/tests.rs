//! Tests of the parameter tuning: grids, picks, heat maps.

use super::pick::{add_midranks, argmin};
use super::tables::duration;
use super::*;
use crate::descriptive::compute;
use crate::experiment::RunRecord;
use crate::test_records::record;

fn rec(alg: &str, params: &str, problem: &str, run: u32, error: f64) -> (RunRecord, bool) {
    (
        RunRecord {
            kind: "mhs".into(),
            params: params.into(),
            budget: 100,
            seed: 0,
            evaluations: 100,
            ..record(alg, problem, run, error)
        },
        false,
    )
}

#[test]
fn grid_best_settings_and_heat_map() {
    let mut v = Vec::new();
    for run in 0..3 {
        for (hmcr, bw, e1, e2) in [
            ("0.9", "0.1", 1.0, 4.0),
            ("0.7", "0.1", 2.0, 1.0),
            ("0.9", "0.01", 0.5, 3.0),
            ("0.7", "0.01", 3.0, 2.0),
        ] {
            let params = format!("hms=5;hmcr={hmcr};bw={bw}");
            v.push(rec("MHS", &params, "f", run, e1));
            v.push(rec("MHS", &params, "g", run, e2));
        }
        v.push(rec("HS", "hms=5", "f", run, 9.0));
    }
    let ds = Dataset::from_records(v);
    let stats = compute(&ds);
    let g = grids(&ds);
    assert_eq!(g.len(), 1);
    assert_eq!(g[0].varying, ["hmcr", "bw"]);
    let t = tables(&ds, &g[0], &stats);
    assert_eq!(t[0].md_rows[0][2], "hmcr=0.9, bw=0.01");
    assert_eq!(t[0].md_rows[1][2], "hmcr=0.7, bw=0.1");
    // Ranks on f and g: (0.9,0.1): 2,4 → 3; (0.7,0.1): 3,1 → 2; (0.9,0.01):
    // 1,3 → 2; (0.7,0.01): 4,2 → 3. The tie goes to the first setting.
    assert_eq!(
        t[0].md_rows[2][2],
        "hmcr=0.7, bw=0.1 (tied with 1 other setting(s); the first in spec order is shown)"
    );
    assert_eq!(t[0].md_rows[2][3], "rank 2.00");
    assert_eq!(t[1].md_rows[0][1], "hmcr=0.7, bw=0.1");
    assert_eq!(t[1].md_rows[1][1], "hmcr=0.9, bw=0.01");
    assert_eq!(t[1].md_rows[3][1], "hmcr=0.7, bw=0.01");
    let h = heat_map(&ds, &g[0], &stats).unwrap();
    assert_eq!(h.x_values, ["0.7", "0.9"]);
    assert_eq!(h.y_values, ["0.01", "0.1"]);
    assert_eq!(h.panels[0].mean[0][1], Some(0.5));
    assert_eq!(h.panels[0].best, Some((0, 1)));
}

#[test]
fn a_wider_grid_is_mapped_through_its_best_setting() {
    // l varies too: l=3 is better everywhere, so the hmcr × bw map is the
    // l=3 slice, whatever order the parameters come in.
    let mut v = Vec::new();
    for run in 0..2 {
        for l in ["1", "3"] {
            for (bw, hmcr, e) in [
                ("0.1", "0.9", 4.0),
                ("0.1", "0.7", 3.0),
                ("0.01", "0.9", 2.0),
            ] {
                let e = if l == "3" { e / 10.0 } else { e };
                let params = format!("l={l};bw={bw};hmcr={hmcr}");
                v.push(rec("MHS", &params, "f", run, e));
            }
        }
    }
    let ds = Dataset::from_records(v);
    let stats = compute(&ds);
    let g = grids(&ds);
    assert_eq!(g[0].varying, ["l", "bw", "hmcr"]);
    let h = heat_map(&ds, &g[0], &stats).unwrap();
    assert_eq!((h.x_param.as_str(), h.y_param.as_str()), ("hmcr", "bw"));
    assert_eq!(h.fixed, [("l".to_string(), "3".to_string())]);
    assert_eq!(h.y_values, ["0.01", "0.1"]);
    assert_eq!(h.panels[0].mean[1][0], Some(0.3));
    assert_eq!(
        h.panels[0].mean[0][0], None,
        "(hmcr 0.7, bw 0.01) was not run"
    );
    assert_eq!(h.panels[0].best, Some((0, 1)));
}

/// A grid of HS over hmcr × bw on `problems`, with `runs` runs of final
/// error `error(hmcr, bw, problem, run)`, each run taking half a second.
fn hs_grid(
    hmcr: &[&str],
    bw: &[&str],
    problems: &[&str],
    runs: u32,
    error: impl Fn(&str, &str, usize, u32) -> f64,
) -> Dataset {
    let mut v = Vec::new();
    for run in 0..runs {
        for h in hmcr {
            for b in bw {
                for (p, problem) in problems.iter().enumerate() {
                    let params = format!("hms=5;hmcr={h};bw={b}");
                    let mut r = rec("HS", &params, problem, run, error(h, b, p, run));
                    r.0.wall_seconds = 0.5;
                    v.push(r);
                }
            }
        }
    }
    let mut ds = Dataset::from_records(v);
    ds.has_timing = true;
    ds
}

#[test]
fn a_pick_far_ahead_is_stable_and_its_edge_is_flagged() {
    let ds = hs_grid(
        &["0.7", "0.9", "0.99"],
        &["0.01", "0.1"],
        &["f", "g"],
        5,
        |h, b, p, run| {
            let spread = 1.0 + f64::from(run) + p as f64;
            if (h, b) == ("0.99", "0.01") {
                1e-3 * spread
            } else {
                spread + h.parse::<f64>().unwrap()
            }
        },
    );
    let stats = compute(&ds);
    let g = &grids(&ds)[0];
    let t = tables(&ds, g, &stats);
    let picks = &t[2];
    assert_eq!(picks.stem, "tuning_picks_hs");
    let row = &picks.csv_rows[0];
    let col = |name: &str| {
        let i = picks.csv_header.iter().position(|h| h == name).unwrap();
        row[i].as_str()
    };
    assert_eq!(col("setting"), "hmcr=0.99, bw=0.01");
    assert_eq!(col("params"), "hms=5;hmcr=0.99;bw=0.01");
    assert_eq!(col("mean_rank"), "1");
    assert_eq!(col("stability"), "1");
    assert_eq!(col("instead"), "");
    assert_eq!(col("resamples"), "200");
    // bw has two values only: not an edge.
    assert_eq!(col("edge"), "hmcr=0.99 (largest of 0.7, 0.9, 0.99)");
    assert_eq!(col("runs"), "60");
    assert_eq!(col("evaluations"), "6000");
    assert_eq!(col("wall_seconds"), "30");
    assert!(
        picks.intro[1].contains(
            "the 60 runs of the 6 settings of HS used 6,000 evaluations and 30.0 s of wall time"
        ),
        "{}",
        picks.intro[1]
    );
    assert!(picks.intro[2]
        .starts_with("Warning: the pick hmcr=0.99, bw=0.01 is on the edge of its grid"));
    assert!(picks.intro[2].ends_with("the best setting may lie outside it."));
    assert_eq!(picks.md_rows[0][4], "1.000");
    assert_eq!(picks.md_rows[0][5], "none");
}

#[test]
fn a_pick_within_noise_of_another_is_unstable() {
    // Two settings whose errors are the same numbers in another order
    // (one a hair larger), on three problems: either may win a resample.
    let ds = hs_grid(
        &["0.7", "0.9"],
        &["0.01"],
        &["f", "g", "h"],
        6,
        |h, _, p, run| {
            let k = (f64::from(run) + 2.0 * p as f64) % 6.0;
            if h == "0.7" {
                1.0 + k
            } else {
                1.0 + (5.0 - k) + 1e-9
            }
        },
    );
    let stats = compute(&ds);
    let g = &grids(&ds)[0];
    let picks = &tables(&ds, g, &stats)[2];
    let header = |name: &str| picks.csv_header.iter().position(|h| h == name).unwrap();
    let row = &picks.csv_rows[0];
    let stability: f64 = row[header("stability")].parse().unwrap();
    assert!((0.2..0.8).contains(&stability), "stability {stability}");
    let instead = &row[header("instead")];
    assert_ne!(instead, &row[header("setting")]);
    assert!(!instead.is_empty());
    let share: f64 = row[header("instead_share")].parse().unwrap();
    assert_eq!(stability + share, 1.0);
    assert_eq!(row[header("runner_up")], *instead);
    // Two values of hmcr: no edge to flag.
    assert_eq!(row[header("edge")], "");
    assert_eq!(picks.md_rows[0][6], "no");
    // A pick that fewer than half the resamples make gets a caution.
    let caution = picks.intro.iter().any(|p| p.starts_with("Caution: only "));
    assert_eq!(caution, stability < 0.5);
    assert_eq!(picks.intro.len(), 2 + usize::from(caution));
}

#[test]
fn the_tuning_tables_are_the_same_on_repeat() {
    let make = || {
        let ds = hs_grid(
            &["0.7", "0.9", "0.99"],
            &["0.001", "0.01", "0.1"],
            &["f", "g"],
            4,
            |h, b, p, run| {
                let x = h.parse::<f64>().unwrap() * 7.0 + b.parse::<f64>().unwrap() * 13.0;
                (x + f64::from(run) * 0.37 + p as f64).sin().abs()
            },
        );
        let stats = compute(&ds);
        let g = grids(&ds).remove(0);
        tables(&ds, &g, &stats)
            .iter()
            .map(|t| (t.csv_bytes(), t.markdown(), t.intro.clone()))
            .collect::<Vec<_>>()
    };
    let (a, b) = (make(), make());
    assert_eq!(a.len(), 3);
    assert_eq!(a, b);
}

#[test]
fn mid_ranks_share_ties_and_the_first_minimum_wins() {
    let mut sums = vec![0.0; 4];
    add_midranks(&[3.0, 1.0, 1.0, 2.0], &mut Vec::new(), &mut sums);
    assert_eq!(sums, [4.0, 1.5, 1.5, 3.0]);
    assert_eq!(argmin(&sums), 1);
    assert_eq!(duration(754.2), "754.2 s (12.6 min)");
}
