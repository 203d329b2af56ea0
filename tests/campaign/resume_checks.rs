//! Issue 49: a resume trusts a journal row only when it agrees with itself
//! (its checksum, its trace) and with the spec (its seed, its error); a row
//! that disagrees is dropped and its run redone, so the results are those
//! of an uninterrupted campaign. A resume also removes the temporaries a
//! kill left, and nothing else.

use std::path::{Path, PathBuf};

use metabezier::experiment::journal::{journal_line, read_journal};
use metabezier::experiment::{run_campaign, RunOptions, Spec, Summary};

/// Three runs of HS and PSO on Sphere-3 and Rastrigin-3.
const SPEC: &str = "[experiment]\nname = \"checked\"\nseed = 5\nruns = 3\nbudget = 400\n\
                    [[problem]]\nfunction = [\"sphere\", \"rastrigin\"]\ndim = 3\n\
                    [[algorithm]]\nname = \"hs\"\n[[algorithm]]\nname = \"pso\"\nswarm = 10\n";

fn spec(dir: &Path) -> Spec {
    let path = dir.join("spec.toml");
    std::fs::write(&path, SPEC).unwrap();
    Spec::load(&path).unwrap()
}

fn run(spec: &Spec, out: &Path, max_runs: Option<usize>, resume: bool) -> Summary {
    let opts = RunOptions {
        out: Some(out.to_owned()),
        threads: Some(2),
        max_runs,
        resume,
        ..RunOptions::default()
    };
    run_campaign(spec, &opts).unwrap()
}

const RESULTS: [&str; 3] = ["runs.csv", "convergence.csv", "hits.csv"];

fn results(dir: &Path) -> Vec<Vec<u8>> {
    RESULTS
        .iter()
        .map(|f| std::fs::read(dir.join(f)).unwrap())
        .collect()
}

/// Line 2 of the journal of `out` (a campaign stopped after 5 runs)
/// replaced by `edit` of it; returns the journal's path.
fn edit_second_line(out: &Path, edit: impl Fn(&str) -> String) -> PathBuf {
    let journal = out.join("journal.csv");
    let text = std::fs::read_to_string(&journal).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    assert_eq!(lines.len(), 5);
    let edited = edit(&lines[1]);
    assert_ne!(edited, lines[1]);
    lines[1] = edited;
    std::fs::write(&journal, lines.join("\n") + "\n").unwrap();
    journal
}

/// The journal line of the record on line 2, with `change` made to it and
/// a checksum that agrees (the edit a tool would make, not a hand).
fn rejournalled(out: &Path, change: impl Fn(&mut metabezier::experiment::RunRecord)) -> String {
    let mut r = read_journal(&out.join("journal.csv")).unwrap().remove(1);
    change(&mut r);
    String::from_utf8(journal_line(&r))
        .unwrap()
        .trim_end()
        .to_owned()
}

/// Replaces field `k` (no field before it holds a comma in this spec).
fn with_field(line: &str, k: usize, value: &str) -> String {
    let mut fields: Vec<&str> = line.split(',').collect();
    fields[k] = value;
    fields.join(",")
}

#[test]
fn an_edited_journal_row_is_redone_and_the_results_are_the_uninterrupted_ones() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let whole = tmp.path().join("whole");
    assert!(run(&spec, &whole, None, false).complete);
    let total = spec.run_ids().len();
    type Edit = Box<dyn Fn(&Path) -> Box<dyn Fn(&str) -> String>>;
    let cases: Vec<(&str, Edit, &str)> = vec![
        // By hand: the checksum no longer agrees; the trace names best.
        (
            "best",
            Box::new(|_| Box::new(|l| with_field(l, 8, "1e-300"))),
            "field best: 1e-300 is not the trace's last best",
        ),
        // By hand: the spec's derivation names the seed.
        (
            "seed",
            Box::new(|_| Box::new(|l| with_field(l, 7, "12345"))),
            "field seed: 12345 is not the seed the spec derives for this run",
        ),
        // With a checksum that agrees: the spec's checks still see it.
        (
            "reseeded",
            Box::new(|out| {
                let line = rejournalled(out, |r| r.seed ^= 1);
                Box::new(move |_| line.clone())
            }),
            "field seed:",
        ),
        (
            "rebest",
            Box::new(|out| {
                let line = rejournalled(out, |r| r.best /= 2.0);
                Box::new(move |_| line.clone())
            }),
            "field error:",
        ),
    ];
    for (name, edit, want) in cases {
        let out = tmp.path().join(name);
        assert!(!run(&spec, &out, Some(5), false).complete);
        let journal = edit_second_line(&out, edit(&out));
        let s = run(&spec, &out, None, true);
        assert!(s.complete, "{name}");
        assert_eq!((s.reused, s.executed), (4, total - 4), "{name}");
        assert_eq!(s.dropped.len(), 1, "{name}: {:?}", s.dropped);
        let prefix = format!("{}:2: ", journal.display());
        assert!(
            s.dropped[0].starts_with(&prefix)
                && s.dropped[0].contains(want)
                && s.dropped[0].ends_with("; the row is dropped and its run redone"),
            "{name}: {}",
            s.dropped[0]
        );
        assert!(results(&out) == results(&whole), "{name}: results differ");
    }
}

#[test]
fn a_resume_removes_the_temporaries_a_kill_left_and_nothing_else() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec(tmp.path());
    let out = tmp.path().join("killed");
    assert!(!run(&spec, &out, Some(3), false).complete);
    let stale = [
        out.join(".runs.csv.4194303.0123456789abcdef.tmp"),
        out.join(".journal.csv.1.fedcba9876543210.tmp"),
    ];
    let own = out.join(format!(
        ".runs.csv.{}.0123456789abcdef.tmp",
        std::process::id()
    ));
    let kept = [
        own,
        out.join("notes.tmp"),
        out.join(".runs.csv.4194303.0123456789ABCDEF.tmp"),
        out.join(".runs.csv.4194303.0123456789abcdef.tmp.bak"),
    ];
    for p in stale.iter().chain(&kept) {
        std::fs::write(p, "x").unwrap();
    }
    // A link of the pattern to a file outside: neither goes.
    let outside = tmp.path().join("outside.txt");
    std::fs::write(&outside, "keep").unwrap();
    let link = out.join(".meta.toml.77.0123456789abcdef.tmp");
    std::os::unix::fs::symlink(&outside, &link).unwrap();
    assert!(run(&spec, &out, None, true).complete);
    for p in &stale {
        assert!(!p.exists(), "{} is left", p.display());
    }
    for p in kept.iter().chain([&link, &outside]) {
        assert!(
            std::fs::symlink_metadata(p).is_ok(),
            "{} was removed",
            p.display()
        );
    }
    assert_eq!(std::fs::read_to_string(&outside).unwrap(), "keep");
}
