//! Reproducibility of campaigns: thread count, resume and shards must not
//! change a single byte of runs.csv or convergence.csv.

use std::path::{Path, PathBuf};

use metabezier::experiment::Spec;
use metabezier::experiment::{merge, run_campaign, RunOptions, Shard};

const SPEC: &str = r#"
[experiment]
name = "determinism"
seed = 99
runs = 3
budget = 1500
threshold = 1e-2

[[problem]]
function = ["sphere", "rastrigin"]
dim = 5

[[problem]]
function = "six_hump_camel"

[[algorithm]]
name = "hs"

[[algorithm]]
name = "ghs"

[[algorithm]]
name = "ga"
pop = 20

[[algorithm]]
name = "pso"
swarm = 10

[[algorithm]]
name = "mhs"
l = [1, 3]
"#;

fn spec(dir: &Path) -> Spec {
    let path = dir.join("spec.toml");
    std::fs::write(&path, SPEC).unwrap();
    Spec::load(&path).unwrap()
}

fn run(spec: &Spec, out: PathBuf, threads: usize) -> PathBuf {
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(threads),
        ..RunOptions::default()
    };
    let s = run_campaign(spec, &opts).unwrap();
    assert!(s.complete);
    out
}

fn read(dir: &Path, file: &str) -> Vec<u8> {
    std::fs::read(dir.join(file)).unwrap()
}

#[test]
fn one_and_two_threads_give_identical_files() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let a = run(&spec, tmp.path().join("a"), 1);
    let b = run(&spec, tmp.path().join("b"), 2);
    for file in ["runs.csv", "convergence.csv", "spec.toml", "meta.toml"] {
        assert_eq!(read(&a, file), read(&b, file), "{file} differs");
    }
    // 3 problems × 6 cells (mhs has a 2-value grid) × 3 runs.
    let runs = String::from_utf8(read(&a, "runs.csv")).unwrap();
    assert_eq!(runs.lines().count(), 1 + 3 * 6 * 3);
    assert!(
        !a.join("journal.csv").exists(),
        "the journal is removed once complete"
    );
    // Seeds differ between runs, and every run spent exactly its budget.
    let recs = metabezier::experiment::records::read_runs(&a.join("runs.csv")).unwrap();
    let mut seeds: Vec<u64> = recs.iter().map(|r| r.seed).collect();
    seeds.sort_unstable();
    seeds.dedup();
    assert_eq!(seeds.len(), recs.len());
    assert!(recs.iter().all(|r| r.evaluations == 1500));
}

#[test]
fn resuming_an_interrupted_campaign_gives_the_same_files() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = run(&spec, tmp.path().join("whole"), 2);

    let out = tmp.path().join("resumed");
    let first = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        max_runs: Some(20),
        ..RunOptions::default()
    };
    let s = run_campaign(&spec, &first).unwrap();
    assert!(!s.complete);
    assert_eq!(s.executed, 20);
    assert!(
        !out.join("runs.csv").exists(),
        "no result file before the campaign is complete"
    );
    // An interruption in the middle of a write leaves a torn last line.
    let journal = out.join("journal.csv");
    let mut bytes = std::fs::read(&journal).unwrap();
    bytes.extend_from_slice(b"HS,hs,hms=5;hmcr=0.9,sph");
    std::fs::write(&journal, bytes).unwrap();

    // Without --resume the existing runs are protected.
    let err = run_campaign(
        &spec,
        &RunOptions {
            resume: false,
            ..first.clone()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("already holds runs of a campaign; pass --resume"),
        "{err}"
    );

    let again = RunOptions {
        resume: true,
        max_runs: None,
        threads: Some(1),
        ..first
    };
    let s = run_campaign(&spec, &again).unwrap();
    assert!(s.complete);
    assert_eq!(s.reused, 20);
    assert_eq!(s.executed, 54 - 20);
    for file in ["runs.csv", "convergence.csv"] {
        assert_eq!(read(&whole, file), read(&out, file), "{file} differs");
    }
    // Resuming a finished campaign runs nothing and changes nothing.
    let s = run_campaign(&spec, &again).unwrap();
    assert_eq!((s.executed, s.reused), (0, 54));
    assert_eq!(read(&whole, "runs.csv"), read(&out, "runs.csv"));
}

#[test]
fn resuming_with_a_changed_spec_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec1 = spec(tmp.path());
    let out = tmp.path().join("out");
    let opts = RunOptions {
        out: Some(out.clone()),
        max_runs: Some(3),
        ..RunOptions::default()
    };
    run_campaign(&spec1, &opts).unwrap();
    let path = tmp.path().join("changed.toml");
    std::fs::write(&path, SPEC.replace("seed = 99", "seed = 100")).unwrap();
    let spec2 = Spec::load(&path).unwrap();
    let err = run_campaign(
        &spec2,
        &RunOptions {
            resume: true,
            ..opts
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("cannot resume"), "{err}");
    assert!(err.contains("differs from"), "{err}");
}

#[test]
fn merged_shards_equal_one_run() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = run(&spec, tmp.path().join("whole"), 2);
    let mut dirs = Vec::new();
    for k in 1..=3 {
        let out = tmp.path().join(format!("shard{k}"));
        let opts = RunOptions {
            out: Some(out.clone()),
            threads: Some(1),
            shard: Some(Shard { k, n: 3 }),
            ..RunOptions::default()
        };
        let s = run_campaign(&spec, &opts).unwrap();
        assert_eq!(s.total, 18);
        dirs.push(out);
    }
    // Two of three shards are not enough.
    let err = merge(&spec, &dirs[..2], Some(tmp.path().join("partial")))
        .unwrap_err()
        .to_string();
    assert!(err.contains("18 of 54 runs are missing"), "{err}");
    let merged = tmp.path().join("merged");
    merge(&spec, &dirs, Some(merged.clone())).unwrap();
    for file in ["runs.csv", "convergence.csv", "spec.toml", "meta.toml"] {
        assert_eq!(read(&whole, file), read(&merged, file), "{file} differs");
    }
}

#[test]
fn shard_syntax_is_checked() {
    assert_eq!(Shard::parse("2/8"), Ok(Shard { k: 2, n: 8 }));
    for bad in ["0/3", "4/3", "3", "a/b", "1/0"] {
        let e = Shard::parse(bad).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("expected a shard as K/N with 1 ≤ K ≤ N, such as 2/8, found \"{bad}\"")
        );
    }
}

#[test]
fn adding_cells_and_problems_keeps_the_other_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let base = spec(tmp.path());
    let a = run(&base, tmp.path().join("a"), 2);
    // The same spec with one more problem and one more algorithm cell.
    let wider = SPEC.replace(
        "[[problem]]\nfunction = \"six_hump_camel\"",
        "[[problem]]\nfunction = \"six_hump_camel\"\n\n[[problem]]\nfunction = \"ackley\"\ndim = 3",
    ) + "\n[[algorithm]]\nname = \"hs\"\nlabel = \"HS-wide\"\nbw = 0.1\n";
    let path = tmp.path().join("wider.toml");
    std::fs::write(&path, wider).unwrap();
    let wider = Spec::load(&path).unwrap();
    assert_eq!(wider.problems.len(), base.problems.len() + 1);
    assert_eq!(wider.cells.len(), base.cells.len() + 1);
    let b = run(&wider, tmp.path().join("b"), 2);
    let rows = |dir: &Path| -> Vec<String> {
        String::from_utf8(read(dir, "runs.csv"))
            .unwrap()
            .lines()
            .map(str::to_owned)
            .collect()
    };
    let (ra, rb) = (rows(&a), rows(&b));
    assert_eq!(rb.len(), 1 + wider.run_ids().len());
    // Every run of the narrower campaign appears unchanged (seed and
    // results) in the wider one.
    for row in &ra {
        assert!(rb.contains(row), "missing or changed: {row}");
    }
}
