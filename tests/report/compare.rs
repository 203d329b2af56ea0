//! `metabezier compare`: a campaign against its rerun on another thread
//! count reads identical, against another experiment seed of the same spec
//! never better or worse, against a campaign with nothing in common a
//! located error; unfinished or foreign directories are refused; the
//! output is reproducible and its tables parse.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// A small spec: two configurations, eight functions at D = 2 (enough
/// units for a verdict across functions to reach `better` or `worse`: the
/// smallest two-sided signed-rank p over 8 units is 2/256), 15 runs.
fn spec(seed: u64, algorithms: &str) -> String {
    format!(
        "[experiment]\nname = \"cmp\"\nseed = {seed}\nruns = 15\nbudget = 600\nthreshold = 1e-3\n\n\
         [[problem]]\nfunction = [\"sphere\", \"rastrigin\", \"rosenbrock\", \"ackley\", \"griewank\", \"step\", \"schwefel_2_22\", \"schwefel_1_2\"]\ndim = 2\n\n{algorithms}"
    )
}

const BOTH: &str = "[[algorithm]]\nname = \"hs\"\nlabel = \"HS\"\n\n[[algorithm]]\nname = \"random\"\nlabel = \"RS\"\n";
const PSO_ONLY: &str = "[[algorithm]]\nname = \"pso\"\nlabel = \"PSO\"\nswarm = 10\n";

fn metabezier(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .args(args)
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Runs `text` on `threads` threads into `root/name`.
fn run(root: &Path, name: &str, text: &str, threads: &str) -> PathBuf {
    let spec = root.join(format!("{name}.toml"));
    std::fs::write(&spec, text).unwrap();
    let out = root.join(name);
    let o = metabezier(&[
        "run",
        spec.to_str().unwrap(),
        "--threads",
        threads,
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", self::text(&o));
    out
}

/// The campaigns, made once: A on one thread, A again on two, A with
/// another experiment seed, and one that shares no configuration with A.
struct Campaigns {
    _tmp: tempfile::TempDir,
    root: PathBuf,
    a: PathBuf,
    rerun: PathBuf,
    reseeded: PathBuf,
    foreign: PathBuf,
}

fn campaigns() -> &'static Campaigns {
    static C: OnceLock<Campaigns> = OnceLock::new();
    C.get_or_init(|| {
        let tmp = tempfile::tempdir().unwrap();
        let root = tmp.path().to_owned();
        Campaigns {
            a: run(&root, "a", &spec(11, BOTH), "1"),
            rerun: run(&root, "rerun", &spec(11, BOTH), "2"),
            reseeded: run(&root, "reseeded", &spec(12, BOTH), "2"),
            foreign: run(&root, "foreign", &spec(11, PSO_ONLY), "2"),
            root,
            _tmp: tmp,
        }
    })
}

/// `compare A B --out OUT`; asserts success and returns its output.
fn compare(a: &Path, b: &Path, out: &Path) -> String {
    let o = metabezier(&[
        "compare",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    text(&o)
}

/// Reads a CSV table, checking that every row has the header's width.
fn table(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    let rows: Vec<Vec<String>> = r
        .records()
        .map(|x| {
            let x = x.unwrap();
            assert_eq!(x.len(), header.len(), "{}", path.display());
            x.iter().map(String::from).collect()
        })
        .collect();
    (header, rows)
}

fn column<'r>(header: &[String], rows: &'r [Vec<String>], name: &str) -> Vec<&'r str> {
    let i = header.iter().position(|h| h == name).unwrap();
    rows.iter().map(|r| r[i].as_str()).collect()
}

#[test]
fn a_campaign_and_its_rerun_on_two_threads_read_identical_and_reproducibly() {
    let c = campaigns();
    let out = c.root.join("identical");
    let said = compare(&c.a, &c.rerun, &out);
    assert!(said.contains("identical runs"), "{said}");
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(md.contains("**Identical runs**"), "{md}");
    for section in [
        "## Summary",
        "## Provenance",
        "## Spec differences",
        "## Plots",
    ] {
        assert!(md.contains(section), "{section} missing:\n{md}");
    }
    assert!(md.contains("the same spec text"), "{md}");
    assert!(out.join("compare.html").is_file());
    // No test on identical runs: every design identical, no verdict row.
    let (h, rows) = table(&out.join("tables/tests.csv"));
    assert!(!rows.is_empty());
    assert!(column(&h, &rows, "design")
        .iter()
        .all(|d| *d == "identical"));
    assert!(column(&h, &rows, "p_value").iter().all(|p| p.is_empty()));
    let (_, verdicts) = table(&out.join("tables/verdicts.csv"));
    assert!(verdicts.is_empty(), "{verdicts:?}");
    // The provenance names both thread counts; the cumulative difference
    // of identical runs is zero everywhere.
    let (h, rows) = table(&out.join("tables/campaigns.csv"));
    assert_eq!(column(&h, &rows, "threads"), ["1", "2"]);
    let (h, rows) = table(&out.join("tables/cumulative_difference.csv"));
    assert!(column(&h, &rows, "diff")
        .iter()
        .all(|d| d.parse::<f64>().unwrap() == 0.0));
    for stem in ["01_hs_B_ecdf", "01_hs_B_cumulative_difference"] {
        assert!(out.join(format!("plots/{stem}.svg")).is_file(), "{stem}");
        assert!(out.join(format!("plots/{stem}.png")).is_file(), "{stem}");
    }
    // Reproducible: a second comparison writes the same bytes.
    let again = c.root.join("identical-again");
    compare(&c.a, &c.rerun, &again);
    let md2 = std::fs::read_to_string(again.join("compare.md")).unwrap();
    let strip = |s: &str, dir: &Path| s.replace(dir.to_str().unwrap(), "OUT");
    assert_eq!(strip(&md, &out), strip(&md2, &again));
    for t in ["tests", "verdicts", "campaigns", "cumulative_difference"] {
        let path = |d: &Path| d.join(format!("tables/{t}.csv"));
        assert_eq!(
            std::fs::read(path(&out)).unwrap(),
            std::fs::read(path(&again)).unwrap(),
            "{t}"
        );
    }
    // The same directory twice is a usage error, not an identical reading.
    let o = metabezier(&["compare", c.a.to_str().unwrap(), c.a.to_str().unwrap()]);
    assert!(
        !o.status.success() && text(&o).contains("given twice"),
        "{}",
        text(&o)
    );
}

#[test]
fn two_experiment_seeds_of_one_spec_read_equivalent_or_undecided_never_better_or_worse() {
    let c = campaigns();
    let out = c.root.join("seeds");
    compare(&c.a, &c.reseeded, &out);
    let (h, rows) = table(&out.join("tables/tests.csv"));
    assert!(column(&h, &rows, "design").iter().all(|d| *d == "unpaired"));
    assert!(column(&h, &rows, "test")
        .iter()
        .all(|t| *t == "mann-whitney-u"));
    let (h, rows) = table(&out.join("tables/verdicts.csv"));
    assert!(!rows.is_empty());
    for v in column(&h, &rows, "verdict") {
        assert!(v == "equivalent" || v == "undecided", "{v}: {rows:?}");
    }
    let (h, rows) = table(&out.join("tables/spec_differences.csv"));
    assert_eq!(column(&h, &rows, "key"), ["experiment.seed"]);
    assert_eq!(column(&h, &rows, "a"), ["11"]);
    let md = std::fs::read_to_string(out.join("compare.md")).unwrap();
    assert!(!md.contains("**Identical runs**"), "{md}");
    assert!(md.contains("unpaired (Mann–Whitney U)"), "{md}");
}

#[test]
fn campaigns_with_no_shared_cell_are_a_located_error_naming_both() {
    let c = campaigns();
    let out = c.root.join("nothing");
    let o = metabezier(&[
        "compare",
        c.a.to_str().unwrap(),
        c.foreign.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let e = text(&o);
    for needle in [
        c.a.to_str().unwrap(),
        c.foreign.to_str().unwrap(),
        "share no",
        "HS",
        "PSO",
    ] {
        assert!(e.contains(needle), "{needle} not in: {e}");
    }
    assert!(!out.exists(), "nothing is written");
}

#[test]
fn a_directory_without_runs_or_with_an_unfinished_journal_is_refused_by_name() {
    let c = campaigns();
    let empty = c.root.join("empty");
    std::fs::create_dir_all(&empty).unwrap();
    let o = metabezier(&["compare", c.a.to_str().unwrap(), empty.to_str().unwrap()]);
    assert!(!o.status.success());
    let e = text(&o);
    assert!(
        e.contains(empty.to_str().unwrap()) && e.contains("no runs.csv"),
        "{e}"
    );

    let unfinished = c.root.join("unfinished");
    std::fs::create_dir_all(&unfinished).unwrap();
    for f in ["runs.csv", "journal.csv"] {
        std::fs::copy(c.a.join("runs.csv"), unfinished.join(f)).unwrap();
    }
    let o = metabezier(&[
        "compare",
        unfinished.to_str().unwrap(),
        c.a.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let e = text(&o);
    assert!(
        e.contains(unfinished.to_str().unwrap()) && e.contains("unfinished"),
        "{e}"
    );
}
