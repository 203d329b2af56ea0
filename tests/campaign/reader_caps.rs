//! Issue 49: every reader of a results file stops at a stated cap (an
//! endless stream such as `/dev/zero`, or a sparse file far past the cap,
//! is refused at once, with the file and the cap named), and a file that is
//! not of the expected format is named as such, its text never quoted.

use crate::common;

use std::path::{Path, PathBuf};

use common::hand_made;
use metabezier::experiment::{merge, run_campaign, RunOptions, Shard, Spec};
use metabezier::report::{write_report, ReportOptions};

/// The first lines of a file that is not ours at all.
const PASSWD: &str =
    "root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1:daemon:/usr/sbin:/usr/sbin/nologin\n";

/// Two runs of HS on Sphere-2.
const SPEC: &str = "[experiment]\nname = \"capped\"\nseed = 3\nruns = 2\nbudget = 300\n\
                    [[problem]]\nfunction = \"sphere\"\ndim = 2\n[[algorithm]]\nname = \"hs\"\n";

fn spec(dir: &Path) -> Spec {
    let path = dir.join("spec.toml");
    std::fs::write(&path, SPEC).unwrap();
    Spec::load(&path).unwrap()
}

/// A results directory with a hand-made runs.csv of five runs.
fn results_dir(tmp: &Path) -> PathBuf {
    let dir = tmp.join("base");
    std::fs::create_dir_all(&dir).unwrap();
    let rows: Vec<(&str, &str, u32, f64, Option<u64>)> =
        (0..5).map(|r| ("MHS", "sphere", r, 1e-3, None)).collect();
    std::fs::write(dir.join("runs.csv"), hand_made(&rows)).unwrap();
    dir
}

fn report(dir: &Path, external: Option<PathBuf>) -> String {
    let opts = ReportOptions {
        external,
        ..ReportOptions::default()
    };
    write_report(dir, &opts).unwrap_err().to_string()
}

/// A sparse file of `bytes` NUL bytes at `path` (no disk used).
fn sparse(path: &Path, bytes: u64) {
    std::fs::File::create(path).unwrap().set_len(bytes).unwrap();
}

/// A campaign of `spec` stopped after one run in `tmp/stopped`: its
/// journal's path and the options that resume it.
fn stopped(spec: &Spec, tmp: &Path) -> (PathBuf, RunOptions) {
    let out = tmp.join("stopped");
    let opts = RunOptions {
        out: Some(out.clone()),
        max_runs: Some(1),
        ..RunOptions::default()
    };
    assert!(!run_campaign(spec, &opts).unwrap().complete);
    let resume = RunOptions {
        resume: true,
        max_runs: None,
        ..opts
    };
    (out.join("journal.csv"), resume)
}

fn assert_line_cap(e: &str, file: &Path) {
    assert!(
        e.contains(&format!(
            "{}:1: line 1 is longer than the 64 MiB",
            file.display()
        )),
        "{e}"
    );
}

#[test]
fn an_external_or_own_runs_file_without_end_is_refused_at_its_cap() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = results_dir(tmp.path());
    let zero = PathBuf::from("/dev/zero");
    assert_line_cap(&report(&dir, Some(zero.clone())), &zero);
    // A sparse external file of 5 GiB, past the runs file's 4 GiB too.
    let big = tmp.path().join("big.csv");
    sparse(&big, 5 << 30);
    assert_line_cap(&report(&dir, Some(big.clone())), &big);
    // The directory's own runs.csv.
    let own = dir.join("runs.csv");
    sparse(&own, 5 << 30);
    assert_line_cap(&report(&dir, None), &own);
}

#[test]
fn a_shards_runs_file_and_a_journal_without_end_are_refused_at_their_cap() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let parent = tmp.path().join("cluster");
    for k in 1..=2 {
        let opts = RunOptions {
            out: Some(parent.clone()),
            shard: Some(Shard { k, n: 2 }),
            ..RunOptions::default()
        };
        assert!(run_campaign(&spec, &opts).unwrap().complete);
    }
    let runs = parent.join("shard-2-of-2").join("runs.csv");
    std::fs::remove_file(&runs).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &runs).unwrap();
    let e = merge(&spec, std::slice::from_ref(&parent), None)
        .unwrap_err()
        .to_string();
    assert_line_cap(&e, &runs);

    let (journal, resume) = stopped(&spec, tmp.path());
    sparse(&journal, (64 << 20) + 1);
    let e = run_campaign(&spec, &resume).unwrap_err().to_string();
    assert_line_cap(&e, &journal);
}

#[test]
fn a_file_of_another_format_is_named_never_quoted() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = results_dir(tmp.path());
    let passwd = tmp.path().join("passwd");
    std::fs::write(&passwd, PASSWD).unwrap();
    let refused = |e: String, file: &Path| {
        assert!(!e.contains("root:x") && !e.contains("daemon"), "{e}");
        assert!(e.contains(&file.display().to_string()), "{e}");
        e
    };
    // An external runs file, then the directory's own runs.csv.
    let e = refused(report(&dir, Some(passwd.clone())), &passwd);
    assert!(e.contains(":1: expected the header algorithm,kind,"), "{e}");
    assert!(
        e.contains("(it has 1 column): this file is not in that format"),
        "{e}"
    );
    let own = dir.join("runs.csv");
    std::fs::write(&own, PASSWD).unwrap();
    refused(report(&dir, None), &own);
    // A journal.
    let spec = spec(tmp.path());
    let (journal, resume) = stopped(&spec, tmp.path());
    std::fs::write(&journal, PASSWD).unwrap();
    let e = refused(
        run_campaign(&spec, &resume).unwrap_err().to_string(),
        &journal,
    );
    assert!(e.ends_with("journal.csv:1: malformed journal line"), "{e}");
    // A spec.
    let e = Spec::load(&passwd).unwrap_err().to_string();
    refused(e, &passwd);
}
