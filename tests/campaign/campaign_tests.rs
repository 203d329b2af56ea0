//! Reproducibility of campaigns: thread count, resume and shards must not
//! change a single byte of runs.csv or convergence.csv; shards keep to
//! their own directories, and a merge names what it lacks.

use std::path::{Path, PathBuf};

use metabezier::experiment::runner::{campaign_dir, shard_dir};
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

fn run_shard(spec: &Spec, parent: &Path, k: usize, n: usize, max_runs: Option<usize>) -> PathBuf {
    let opts = RunOptions {
        out: Some(parent.to_owned()),
        threads: Some(1),
        resume: true,
        shard: Some(Shard { k, n }),
        max_runs,
        ..RunOptions::default()
    };
    run_campaign(spec, &opts).unwrap().out
}

/// The names of the files (not directories) in `dir`.
fn files(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.path().is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn shards_run_at_once_into_one_out_and_merge_into_it() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = run(&spec, tmp.path().join("whole"), 2);
    // Three shards at the same moment, all given the same --out: each
    // writes into its own shard-K-of-3/ directory.
    let parent = tmp.path().join("cluster");
    let outs: Vec<PathBuf> = std::thread::scope(|scope| {
        let handles: Vec<_> = (1..=3)
            .map(|k| {
                let (spec, parent) = (&spec, &parent);
                scope.spawn(move || run_shard(spec, parent, k, 3, None))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    for (k, out) in (1..=3).zip(&outs) {
        assert_eq!(*out, parent.join(format!("shard-{k}-of-3")));
        let runs = String::from_utf8(read(out, "runs.csv")).unwrap();
        assert_eq!(runs.lines().count(), 1 + 18);
    }
    // `merge DIR` finds the shards and writes into DIR the very files of a
    // single run, hits.csv included.
    let s = merge(&spec, std::slice::from_ref(&parent), None).unwrap();
    assert_eq!(s.out, parent);
    assert_eq!(files(&parent), files(&whole));
    // Every file but the record of where and when (timing, provenance).
    for file in files(&whole)
        .iter()
        .filter(|f| *f != "timing.csv" && *f != "provenance.toml")
    {
        assert_eq!(read(&whole, file), read(&parent, file), "{file} differs");
    }
    // The merged provenance holds the three shards' sessions, 18 runs each.
    let sessions = metabezier::experiment::provenance::read(&parent);
    assert_eq!(
        sessions.iter().map(|s| s.runs).collect::<Vec<_>>(),
        [18, 18, 18]
    );
    assert!(files(&whole).contains(&"hits.csv".to_owned()));
    // The shard directories themselves merge as well, and again in place.
    let merged = tmp.path().join("merged");
    merge(&spec, &outs, Some(merged.clone())).unwrap();
    merge(&spec, std::slice::from_ref(&parent), None).unwrap();
    for file in ["runs.csv", "convergence.csv", "hits.csv"] {
        assert_eq!(read(&whole, file), read(&merged, file), "{file} differs");
        assert_eq!(read(&whole, file), read(&parent, file), "{file} differs");
    }
}

#[test]
fn a_merge_names_missing_and_unfinished_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let parent = tmp.path().join("cluster");
    let err = |dirs: &[PathBuf]| merge(&spec, dirs, None).unwrap_err().to_string();
    let one = std::slice::from_ref(&parent);
    std::fs::create_dir(&parent).unwrap();
    let e = err(one);
    assert!(
        e.contains("holds no shard directories (shard-K-of-N/)"),
        "{e}"
    );

    run_shard(&spec, &parent, 1, 4, None);
    run_shard(&spec, &parent, 3, 4, Some(5));
    let e = err(one);
    let shard = |k: usize| parent.join(format!("shard-{k}-of-4")).display().to_string();
    for part in [
        format!("shard 2/4 is missing (no {})", shard(2)),
        format!("shard 4/4 is missing (no {})", shard(4)),
        format!(
            "shard 3/4 is unfinished ({}: 5 finished runs in journal.csv, no runs.csv)",
            shard(3)
        ),
        "--resume".to_owned(),
    ] {
        assert!(e.contains(&part), "{part} not in: {e}");
    }
    // Explicit shard directories: the missing ones are named too.
    let e = err(&[parent.join("shard-1-of-4")]);
    assert!(
        e.contains("shard 2/4 is missing (no directory given holds it)"),
        "{e}"
    );
    // Shards of another count beside them.
    run_shard(&spec, &parent, 1, 2, None);
    let e = err(one);
    assert!(
        e.contains("the shards found split the campaign in 2 and 4 parts"),
        "{e}"
    );
    std::fs::remove_dir_all(parent.join("shard-1-of-2")).unwrap();

    // A shard of another spec: named by its copy of the spec.
    for k in [2, 3, 4] {
        run_shard(&spec, &parent, k, 4, None);
    }
    let other_dir = tmp.path().join("other");
    std::fs::create_dir(&other_dir).unwrap();
    let other_path = other_dir.join("spec.toml");
    std::fs::write(&other_path, SPEC.replace("seed = 99", "seed = 100")).unwrap();
    let other = Spec::load(&other_path).unwrap();
    let foreign = run_shard(&other, &other_dir, 4, 4, None);
    let mut dirs: Vec<PathBuf> = (1..=3)
        .map(|k| parent.join(format!("shard-{k}-of-4")))
        .collect();
    dirs.push(foreign.clone());
    let e = err(&dirs);
    assert!(
        e.contains(&format!(
            "{} was made from a different spec",
            foreign.join("spec.toml").display()
        )),
        "{e}"
    );
    // Complete and of one spec: merged.
    merge(&spec, one, None).unwrap();
}

#[test]
fn shard_directories_are_their_own() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let s = Shard { k: 2, n: 3 };
    assert_eq!(s.dir_name(), "shard-2-of-3");
    assert_eq!(Shard::from_dir_name("shard-2-of-3"), Some(s));
    for bad in [
        "shard-0-of-3",
        "shard-4-of-3",
        "shard-02-of-3",
        "shard-2-of-3x",
        "shard-2",
    ] {
        assert_eq!(Shard::from_dir_name(bad), None, "{bad}");
    }
    let base = tmp.path().join("out");
    assert_eq!(shard_dir(&base, s), base.join("shard-2-of-3"));
    // Given its own directory, a shard stays in it.
    assert_eq!(
        shard_dir(&base.join("shard-2-of-3"), s),
        base.join("shard-2-of-3")
    );
    // A shard started by an older version straight in --out still resumes.
    let legacy = tmp.path().join("legacy");
    std::fs::create_dir(&legacy).unwrap();
    std::fs::write(legacy.join("meta.toml"), "runs = 18\nshard = \"2/3\"\n").unwrap();
    assert_eq!(shard_dir(&legacy, s), legacy);
    assert_eq!(
        shard_dir(&legacy, Shard { k: 1, n: 3 }),
        legacy.join("shard-1-of-3")
    );
    assert_eq!(
        campaign_dir(&spec, None, Some(s)),
        Path::new("results/determinism/shard-2-of-3")
    );
    assert_eq!(
        campaign_dir(&spec, None, None),
        Path::new("results/determinism")
    );
}

#[test]
fn shard_syntax_is_checked() {
    assert_eq!(Shard::parse("2/8"), Ok(Shard { k: 2, n: 8 }));
    for (bad, why) in [
        ("0/3", "shard 0 does not exist; the shards of 3 are 1 to 3"),
        ("4/3", "shard 4 does not exist; the shards of 3 are 1 to 3"),
        ("x/3", "K is not a whole number"),
        ("3", "there is no '/' between K and N"),
        ("a/b", "K is not a whole number"),
        ("1/0", "N is not a whole number of at least 1"),
        ("1/y", "N is not a whole number of at least 1"),
    ] {
        let e = Shard::parse(bad).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!("expected a shard as K/N with 1 ≤ K ≤ N, such as 2/8, found \"{bad}\": {why}")
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

// ------------------------------------------------------------- hardening

fn files_of(dir: &Path) -> Vec<Vec<u8>> {
    ["runs.csv", "convergence.csv", "hits.csv"]
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect()
}

#[test]
fn a_campaign_killed_during_its_final_write_resumes_from_its_journal() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = run(&spec, tmp.path().join("whole"), 2);
    // Every run journalled, runs.csv written, convergence.csv not: the state
    // a kill (or a full disk) leaves during the final write.
    let out = tmp.path().join("killed");
    let total = spec.run_ids().len();
    let opts = RunOptions {
        out: Some(out.clone()),
        max_runs: Some(total - 1),
        ..RunOptions::default()
    };
    assert!(!run_campaign(&spec, &opts).unwrap().complete);
    let last = RunOptions {
        resume: true,
        max_runs: Some(1),
        ..opts.clone()
    };
    // Finish the last run but leave a torn runs.csv and no convergence.csv
    // beside the full journal.
    let journal = std::fs::read(out.join("journal.csv")).unwrap();
    run_campaign(&spec, &last).unwrap();
    std::fs::write(out.join("journal.csv"), {
        let mut j = journal;
        j.extend(metabezier::experiment::journal::journal_line(
            &metabezier::experiment::records::read_results(&out)
                .unwrap()
                .into_iter()
                .find(|r| !String::from_utf8_lossy(&j).contains(&format!(",{},", r.seed)))
                .unwrap(),
        ));
        j
    })
    .unwrap();
    std::fs::write(out.join("runs.csv"), b"algorithm,kind").unwrap();
    std::fs::remove_file(out.join("convergence.csv")).unwrap();
    let resumed = run_campaign(
        &spec,
        &RunOptions {
            resume: true,
            ..opts
        },
    )
    .unwrap();
    assert!(resumed.complete && resumed.executed == 0, "{resumed:?}");
    assert_eq!(files_of(&out), files_of(&whole));
}

#[test]
fn resume_refuses_another_spec_even_without_its_copy() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("c");
    let opts = RunOptions {
        out: Some(out.clone()),
        max_runs: Some(5),
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    std::fs::remove_file(out.join("spec.toml")).unwrap();
    let other = Spec::parse(
        &tmp.path().join("other.toml"),
        &SPEC.replace("seed = 99", "seed = 98"),
    )
    .unwrap();
    let err = run_campaign(
        &other,
        &RunOptions {
            resume: true,
            ..opts
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.starts_with("cannot resume: ")
            && err.contains("meta.toml records a campaign of a spec with hash"),
        "{err}"
    );
}

#[test]
fn a_second_writer_is_refused_and_the_lock_dies_with_its_holder() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("locked");
    let lock = metabezier::experiment::runner::DirLock::take(&out).unwrap();
    let opts = RunOptions {
        out: Some(out.clone()),
        ..RunOptions::default()
    };
    let err = run_campaign(&spec, &opts).unwrap_err().to_string();
    assert!(
        err.contains("is in use by another metabezier process"),
        "{err}"
    );
    drop(lock);
    assert!(run_campaign(&spec, &opts).unwrap().complete);
}

#[test]
fn oversized_campaigns_and_thread_counts_are_refused_before_anything_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let text = SPEC.replace("runs = 3", "runs = 4294967295");
    // The default limits refuse it as it is read; read under the lifted
    // limits, the runner still refuses it without allow_large.
    let e = Spec::parse(&tmp.path().join("huge.toml"), &text).unwrap_err();
    assert!(e.message.contains("over the limit of 10000000 runs"), "{e}");
    let huge = Spec::parse_with(
        &tmp.path().join("huge.toml"),
        &text,
        metabezier::experiment::SpecLimits::LARGE,
    )
    .unwrap();
    let out = tmp.path().join("huge");
    let opts = RunOptions {
        out: Some(out.clone()),
        ..RunOptions::default()
    };
    let err = run_campaign(&huge, &opts).unwrap_err().to_string();
    assert!(
        err.contains("exceed the limit") && err.contains("pass --allow-large"),
        "{err}"
    );
    assert!(!out.exists(), "nothing is written before the check");
    let err = run_campaign(
        &spec(tmp.path()),
        &RunOptions {
            threads: Some(65535),
            ..opts
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.starts_with("--threads 65535: at most "), "{err}");
}

#[test]
fn merge_refuses_to_write_over_another_campaign() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    for k in 1..=2 {
        let opts = RunOptions {
            out: Some(tmp.path().join("parent")),
            shard: Some(Shard { k, n: 2 }),
            ..RunOptions::default()
        };
        run_campaign(&spec, &opts).unwrap();
    }
    let busy = tmp.path().join("busy");
    std::fs::create_dir_all(&busy).unwrap();
    std::fs::write(busy.join("journal.csv"), b"").unwrap();
    let err = merge(&spec, &[tmp.path().join("parent")], Some(busy))
        .unwrap_err()
        .to_string();
    assert!(
        err.ends_with("it holds journal.csv; merge into an empty directory or that campaign's own"),
        "{err}"
    );
}

#[test]
fn run_positions_and_keys_agree_with_the_listed_order() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let index = metabezier::experiment::runner::RunIndex::of(&spec);
    let ids = spec.run_ids();
    assert_eq!(index.len(), ids.len());
    assert!(ids.len() > 8);
    for id in &ids {
        assert_eq!(spec.run_id(id.index), *id);
        let key = (
            spec.cells[id.cell].key(),
            spec.problems[id.problem].match_key(),
            spec.problems[id.problem].budget,
            id.run,
        );
        assert_eq!(index.key(*id), key);
        assert_eq!(index.get(&key), Some(id.index));
    }
    let mut foreign = index.key(spec.run_id(0));
    foreign.3 = spec.runs;
    assert_eq!(index.get(&foreign), None, "a run number beyond the spec's");
    foreign = index.key(spec.run_id(0));
    foreign.2 += 1;
    assert_eq!(index.get(&foreign), None, "another budget");
}

#[test]
fn a_merge_into_one_of_its_own_shards_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let parent = tmp.path().join("cluster");
    let first = run_shard(&spec, &parent, 1, 2, None);
    let second = run_shard(&spec, &parent, 2, 2, None);
    let before = std::fs::read(second.join("runs.csv")).unwrap();
    let one = std::slice::from_ref(&parent);
    // Named as merged, and spelled another way.
    let other_spelling = parent.join("..").join("cluster").join("shard-2-of-2");
    for (out, dir, shard) in [
        (first.clone(), &first, "1/2"),
        (other_spelling.clone(), &second, "2/2"),
    ] {
        let e = merge(&spec, one, Some(out.clone()))
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "cannot merge into {}: it is shard {shard} ({}), one of the directories merged, whose own files the merged ones would overwrite; merge into their parent directory (the default when it is given) or another --out",
                out.display(),
                dir.display()
            )
        );
    }
    assert_eq!(std::fs::read(second.join("runs.csv")).unwrap(), before);
    assert_eq!(
        std::fs::read_to_string(second.join("meta.toml"))
            .unwrap()
            .matches("shard = \"2/2\"")
            .count(),
        1
    );
    // Into the parent (the default) it merges.
    assert!(merge(&spec, one, None).unwrap().complete);
}

#[test]
fn a_shard_given_without_meta_toml_is_named_as_given() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let parent = tmp.path().join("cluster");
    let first = run_shard(&spec, &parent, 1, 2, None);
    let second = run_shard(&spec, &parent, 2, 2, None);
    std::fs::remove_file(second.join("meta.toml")).unwrap();
    let err = |dirs: &[PathBuf]| merge(&spec, dirs, None).unwrap_err().to_string();
    let tail = "but has no meta.toml (not a campaign directory, or an unfinished one?)";
    let e = err(&[first.clone(), second.clone()]);
    assert!(
        e.contains(&format!(
            "shard 2/2 ({}) was given {tail}",
            second.display()
        )),
        "{e}"
    );
    assert!(!e.contains("missing"), "{e}");
    // Found in the parent given.
    let e = err(std::slice::from_ref(&parent));
    assert!(
        e.contains(&format!("shard 2/2 ({}) is there {tail}", second.display())),
        "{e}"
    );
    // Under another name.
    let copy = tmp.path().join("copy");
    std::fs::create_dir(&copy).unwrap();
    for f in [
        "spec.toml",
        "runs.csv",
        "convergence.csv",
        "timing.csv",
        "hits.csv",
    ] {
        std::fs::copy(second.join(f), copy.join(f)).unwrap();
    }
    let e = err(&[first, copy.clone()]);
    assert!(
        e.contains(&format!("{} was given {tail}", copy.display())),
        "{e}"
    );
}

#[test]
fn a_resume_refuses_a_timing_file_without_a_row_of_each_run() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = run(&spec, tmp.path().join("whole"), 1);
    let timing = std::fs::read_to_string(out.join("timing.csv")).unwrap();
    let lines: Vec<&str> = timing.lines().collect();
    let resume = || {
        let opts = RunOptions {
            out: Some(out.clone()),
            threads: Some(1),
            resume: true,
            ..RunOptions::default()
        };
        run_campaign(&spec, &opts)
            .map(|_| String::new())
            .unwrap_or_else(|e| e.to_string())
    };
    // The last row cut off: that run's wall time would read as 0.
    std::fs::write(
        out.join("timing.csv"),
        lines[..lines.len() - 1].join("\n") + "\n",
    )
    .unwrap();
    let last = lines[lines.len() - 1];
    let e = resume();
    assert!(
        e.starts_with(&format!(
            "{}: no row for run 2 of mhs:mhs[",
            out.join("timing.csv").display()
        )),
        "{e}"
    );
    assert!(e.ends_with("on six_hump_camel-2 of runs.csv"), "{e}");
    // A row repeated.
    std::fs::write(out.join("timing.csv"), format!("{timing}{last}\n")).unwrap();
    let e = resume();
    assert_eq!(
        e,
        format!(
            "{}:{}: a second row for the run of an earlier row",
            out.join("timing.csv").display(),
            lines.len() + 1
        )
    );
    std::fs::write(out.join("timing.csv"), &timing).unwrap();
    assert_eq!(resume(), "");
}

/// `stop = "target"` ends each run at its first evaluation within the
/// threshold: the same runs succeed after the same evaluations as with the
/// whole budget, a successful run stops there (a generation evaluated as one
/// batch is counted whole), and an unsuccessful one spends its budget.
#[test]
fn stop_at_target_ends_successful_runs_at_their_target() {
    let whole_dir = tempfile::tempdir().unwrap();
    let stop_dir = tempfile::tempdir().unwrap();
    let whole = spec(whole_dir.path());
    let path = stop_dir.path().join("spec.toml");
    std::fs::write(
        &path,
        SPEC.replace("threshold = 1e-2", "threshold = 1e-2\nstop = \"target\""),
    )
    .unwrap();
    let stopping = Spec::load(&path).unwrap();
    assert_eq!(stopping.stop, metabezier::experiment::spec::Stop::Target);
    let a = run(&whole, whole_dir.path().join("out"), 2);
    let b = run(&stopping, stop_dir.path().join("out"), 2);
    let runs = |d: &Path| metabezier::experiment::records::read_runs(&d.join("runs.csv")).unwrap();
    let (full, stopped) = (runs(&a), runs(&b));
    assert_eq!(full.len(), stopped.len());
    let mut ended_early = 0;
    for (f, s) in full.iter().zip(&stopped) {
        let what = format!("{} on {} run {}", f.algorithm, f.problem, f.run);
        assert_eq!((f.seed, f.success), (s.seed, s.success), "{what}");
        assert_eq!(f.evaluations_to_target, s.evaluations_to_target, "{what}");
        match s.evaluations_to_target {
            Some(hit) => {
                assert!(
                    s.evaluations >= hit && s.evaluations < hit + 64,
                    "{what}: {}",
                    s.evaluations
                );
                assert!(s.error <= 1e-2, "{what}");
                ended_early += usize::from(s.evaluations < s.budget);
            }
            None => assert_eq!(s.evaluations, s.budget, "{what}"),
        }
    }
    assert!(ended_early > 10, "only {ended_early} runs ended early");
    // The report says so, and a report of the whole-budget campaign does not.
    let says = |d: &Path| {
        metabezier::report::write_report(d, &metabezier::report::ReportOptions::default()).unwrap();
        String::from_utf8(read(d, "report.md"))
            .unwrap()
            .contains("**Runs end:** at their target")
    };
    assert!(says(&b) && !says(&a));
}
