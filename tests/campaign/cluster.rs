//! The cluster path without a cluster: the script `metabezier slurm` prints
//! is run by bash as Slurm would run its array tasks (all at once, with the
//! SLURM_* variables set, one of them resubmitted alone after an
//! interruption), then
//! `metabezier merge DIR` joins the shards into the files of a whole run.
//! `ci/slurm-test.sh` does the same on a real Slurm.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SPEC: &str = "[experiment]\nname = \"array\"\nseed = 5\nruns = 4\nbudget = 2000\n\n\
[[problem]]\nfunction = [\"sphere\", \"rastrigin\"]\ndim = 4\n\n\
[[algorithm]]\nname = \"hs\"\n\n[[algorithm]]\nname = \"pso\"\nswarm = 10\n";

fn metabezier(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap()
}

fn ok(out: Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn error(out: Output) -> String {
    assert_eq!(out.status.code(), Some(1), "{out:?}");
    String::from_utf8(out.stderr).unwrap()
}

fn setup() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("array.toml");
    std::fs::write(&spec, SPEC).unwrap();
    (tmp, spec)
}

#[test]
fn the_array_script_runs_every_shard_and_merge_joins_them() {
    let (tmp, _) = setup();
    let dir = tmp.path();
    let script = ok(metabezier(
        dir,
        &[
            "slurm",
            "array.toml",
            "--tasks",
            "3",
            "--out",
            "scratch",
            "--cpus",
            "2",
            "--time",
            "0:10:00",
            "--sbatch",
            "--partition=short -A proj",
        ],
    ));
    let scratch = dir.join("scratch");
    for line in [
        "#!/bin/bash\n".to_owned(),
        "#SBATCH --array=0-2\n".to_owned(),
        "#SBATCH --cpus-per-task=2\n".to_owned(),
        "#SBATCH --time=0:10:00\n".to_owned(),
        "#SBATCH --requeue\n".to_owned(),
        "#SBATCH --partition=short\n".to_owned(),
        "#SBATCH -A proj\n".to_owned(),
        format!(
            "merge '{}' --spec '{}'\n",
            scratch.display(),
            dir.join("array.toml").display()
        ),
        "--resume --quiet\n".to_owned(),
    ] {
        assert!(script.contains(&line), "{line} not in:\n{script}");
    }
    std::fs::write(dir.join("array.sbatch"), &script).unwrap();

    // Task 1 was interrupted after two runs, in the middle of a journal line.
    ok(metabezier(
        dir,
        &[
            "run",
            "array.toml",
            "--out",
            "scratch",
            "--shard",
            "2/3",
            "--max-runs",
            "2",
            "-q",
        ],
    ));
    let journal = scratch.join("shard-2-of-3/journal.csv");
    let mut bytes = std::fs::read(&journal).unwrap();
    bytes.extend_from_slice(b"HS,hs,hms=5");
    std::fs::write(&journal, bytes).unwrap();

    // The three tasks at once, as Slurm starts them (from another directory).
    let tasks: Vec<_> = (0..3)
        .map(|i| {
            Command::new("bash")
                .arg(dir.join("array.sbatch"))
                .current_dir(std::env::temp_dir())
                .env("SLURM_ARRAY_TASK_ID", i.to_string())
                // Task 1 as resubmitted alone (sbatch --array=1): N stays 3.
                .env("SLURM_ARRAY_TASK_COUNT", if i == 1 { "1" } else { "3" })
                .env("SLURM_CPUS_PER_TASK", "2")
                .stdout(std::process::Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let said: Vec<String> = tasks
        .into_iter()
        .map(|t| ok(t.wait_with_output().unwrap()))
        .collect();
    assert!(
        said[1].contains("5 runs (2 reused, 3 executed), complete"),
        "{}",
        said[1]
    );
    let said = ok(metabezier(dir, &["merge", "scratch"]));
    assert_eq!(
        said,
        "array: merged 3 shard directories, 16 runs, into scratch\n"
    );
    ok(metabezier(
        dir,
        &["run", "array.toml", "--out", "whole", "-q"],
    ));
    for file in [
        "runs.csv",
        "convergence.csv",
        "hits.csv",
        "spec.toml",
        "meta.toml",
    ] {
        assert_eq!(
            std::fs::read(dir.join("whole").join(file)).unwrap(),
            std::fs::read(scratch.join(file)).unwrap(),
            "{file} differs"
        );
    }
}

#[test]
fn cluster_commands_refuse_bad_input_by_name() {
    let (tmp, _) = setup();
    let dir = tmp.path();
    for (args, message) in [
        (
            &["slurm", "array.toml", "--tasks", "17"][..],
            "metabezier: error: --tasks 17: expected 1 to 16 tasks (one shard each); the campaign array has 16 runs\n",
        ),
        (
            &["slurm", "array.toml", "--tasks", "2", "--time", "90"],
            "metabezier: error: --time \"90\": expected a time limit per task as HH:MM:SS or D-HH:MM:SS, such as 02:30:00, with minutes and seconds below 60\n",
        ),
        (
            &["slurm", "array.toml", "--tasks", "2", "--sbatch", "-c 4"],
            "metabezier: error: --sbatch: -c is set by metabezier slurm itself; use --cpus\n",
        ),
    ] {
        assert_eq!(error(metabezier(dir, args)), message);
    }
    let out = metabezier(dir, &["run", "array.toml", "--shard", "4/3"]);
    assert_eq!(out.status.code(), Some(2));
    let e = String::from_utf8(out.stderr).unwrap();
    assert!(
        e.contains("found \"4/3\": shard 4 does not exist; the shards of 3 are 1 to 3"),
        "{e}"
    );

    // A merge of a campaign whose second shard never ran.
    ok(metabezier(
        dir,
        &["run", "array.toml", "--out", "o", "--shard", "1/2", "-q"],
    ));
    let e = error(metabezier(dir, &["merge", "o"]));
    assert!(
        e.starts_with("metabezier: error: cannot merge: shard 2/2 is missing (no o/shard-2-of-2)"),
        "{e}"
    );
    assert!(!dir.join("o/runs.csv").exists(), "nothing merged");
}

#[test]
fn a_fitting_campaign_merges_with_its_spec() {
    // The input is named relative to the spec, so the shards' copies of the
    // spec cannot find it: `merge --spec` reads the spec where it is.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/coin.png");
    std::fs::copy(data, dir.join("coin.png")).unwrap();
    std::fs::write(
        dir.join("fit.toml"),
        "[experiment]\nname = \"fitm\"\nseed = 1\nruns = 2\n\n[[fit]]\ninput = \"coin.png\"\n\
         function = \"cubic\"\ncontinuity = \"c1\"\nsegments = 4\nbudget = 200\n\n\
         [[algorithm]]\nname = \"hs\"\n",
    )
    .unwrap();
    for k in ["1/2", "2/2"] {
        ok(metabezier(
            dir,
            &["run", "fit.toml", "--out", "o", "--shard", k, "-q"],
        ));
    }
    let e = error(metabezier(dir, &["merge", "o"]));
    assert!(e.contains("shard-1-of-2/coin.png: cannot read"), "{e}");
    ok(metabezier(dir, &["merge", "o", "--spec", "fit.toml"]));
    ok(metabezier(
        dir,
        &["run", "fit.toml", "--out", "whole", "-q"],
    ));
    for file in ["runs.csv", "fits.csv", "segments.csv", "outlines.csv"] {
        assert_eq!(
            std::fs::read(dir.join("whole").join(file)).unwrap(),
            std::fs::read(dir.join("o").join(file)).unwrap(),
            "{file} differs"
        );
    }
}

#[test]
fn merge_out_into_a_shard_and_a_shard_without_meta_toml_are_named() {
    let (tmp, _) = setup();
    let dir = tmp.path();
    for k in ["1/2", "2/2"] {
        ok(metabezier(
            dir,
            &["run", "array.toml", "--out", "o", "--shard", k, "-q"],
        ));
    }
    let runs = std::fs::read(dir.join("o/shard-1-of-2/runs.csv")).unwrap();
    let e = error(metabezier(dir, &["merge", "o", "--out", "o/shard-1-of-2"]));
    assert_eq!(
        e,
        "metabezier: error: cannot merge into o/shard-1-of-2: it is shard 1/2 (o/shard-1-of-2), one of the directories merged, whose own files the merged ones would overwrite; merge into their parent directory (the default when it is given) or another --out\n"
    );
    assert_eq!(
        std::fs::read(dir.join("o/shard-1-of-2/runs.csv")).unwrap(),
        runs
    );
    std::fs::remove_file(dir.join("o/shard-2-of-2/meta.toml")).unwrap();
    let e = error(metabezier(
        dir,
        &["merge", "o/shard-1-of-2", "o/shard-2-of-2", "--out", "m"],
    ));
    assert!(
        e.contains("shard 2/2 (o/shard-2-of-2) was given but has no meta.toml (not a campaign directory, or an unfinished one?)"),
        "{e}"
    );
    assert!(!dir.join("m/runs.csv").exists());
}
