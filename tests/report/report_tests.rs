//! Reports on campaign results: the files exist, the tables hold the
//! expected rows, the marks are right on data whose outcome is known, and
//! the same input gives the same bytes.
//!
//! Set `METABEZIER_REPORT_KEEP=DIR` to copy the generated results and
//! reports to DIR for inspection.

use crate::common;

use common::{campaign, hand_made, HEADER};

use std::path::{Path, PathBuf};

use metabezier::report::{write_report, ReportOptions};

/// 2 functions (at two dimensions, for the scalability plot) × 3 algorithms
/// × 5 runs, with an MHS grid over hmcr × bw in a second spec.
const SPEC: &str = r#"
[experiment]
name = "report_test"
description = "Tiny campaign for the report tests"
seed = 4242
runs = 5
budget = 3000
threshold = 1e-3

[[problem]]
function = ["sphere", "rastrigin"]
dim = [2, 4]

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "pso"
label = "PSO"
swarm = 10

[[algorithm]]
name = "mhs"
label = "MHS"
"#;

const GRID_SPEC: &str = r#"
[experiment]
name = "report_grid"
seed = 7
runs = 3
budget = 1500
threshold = 1e-2

[[problem]]
function = ["sphere", "rastrigin"]
dim = 3

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs"
label = "MHS"
hmcr = [0.7, 0.9, 0.99]
bw = [0.001, 0.01]
"#;

fn keep(dir: &Path, name: &str) {
    if let Some(target) = std::env::var_os("METABEZIER_REPORT_KEEP") {
        let target = PathBuf::from(target).join(name);
        copy_dir(dir, &target);
    }
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let dest = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &dest);
        } else {
            std::fs::copy(entry.path(), dest).unwrap();
        }
    }
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn all_files(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    for sub in ["tables", "plots"] {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            let bytes = std::fs::read(&p).unwrap();
            out.push((p, bytes));
        }
    }
    out.push((
        dir.join("report.md"),
        std::fs::read(dir.join("report.md")).unwrap(),
    ));
    out
}

#[test]
fn report_of_a_small_campaign() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "results", SPEC);
    let summary = write_report(&dir, &ReportOptions::default()).unwrap();
    assert_eq!(summary.algorithms, 3);
    assert_eq!(summary.problems, 4);
    assert_eq!(summary.runs, 4 * 3 * 5);
    assert_eq!(summary.reference.as_deref(), Some("MHS"));
    // The report names the build and the machine that made the runs.
    let md = read(&dir.join("report.md"));
    let made = md
        .lines()
        .find(|l| l.contains("Made by"))
        .unwrap_or_else(|| panic!("no provenance line in\n{md}"));
    assert!(
        made.contains(&format!("metabezier {}", env!("CARGO_PKG_VERSION")))
            && made.contains("2 thread(s)")
            && made.contains(": 60 run(s)"),
        "{made}"
    );
    has_its_tables_and_plots(&dir);
    assert!(summary.plots.iter().all(|p| p.is_file()));
    assert!(summary.tables.iter().all(|p| p.is_file()));

    has_its_descriptive_tests_and_verdicts(&dir);
    has_its_report_md(&dir);
    keep(&dir, "small");

    // Deterministic: a second report gives the same bytes everywhere.
    let first = all_files(&dir);
    write_report(&dir, &ReportOptions::default()).unwrap();
    let second = all_files(&dir);
    assert_eq!(first.len(), second.len());
    for ((p, a), (_, b)) in first.iter().zip(&second) {
        assert!(a == b, "{} differs between two reports", p.display());
    }

    // Another reference by label, and an unknown one.
    let s = write_report(
        &dir,
        &ReportOptions {
            reference: Some("PSO".into()),
            ..ReportOptions::default()
        },
    )
    .unwrap();
    assert_eq!(s.reference.as_deref(), Some("PSO"));
    let err = write_report(
        &dir,
        &ReportOptions {
            reference: Some("NOPE".into()),
            ..ReportOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("\"NOPE\" is not in the results"), "{err}");
}

/// The small campaign's report has every table, and every plot as SVG and PNG.
fn has_its_tables_and_plots(dir: &Path) {
    for t in [
        "algorithms",
        "problems",
        "descriptive",
        "comparison",
        "tests",
        "anytime_tests",
        "verdicts",
        "marks_summary",
        "friedman",
    ] {
        assert!(dir.join("tables").join(format!("{t}.csv")).is_file(), "{t}");
    }
    for p in ["convergence", "boxplots", "scalability"] {
        for ext in ["svg", "png"] {
            let path = dir.join("plots").join(format!("{p}.{ext}"));
            assert!(path.is_file(), "{}", path.display());
        }
        let png = std::fs::read(dir.join("plots").join(format!("{p}.png"))).unwrap();
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }
}

/// The small campaign's descriptive rows, its tests (unpaired, by design), its verdicts (undecided: two units are too few) and the marks and Friedman tables.
fn has_its_descriptive_tests_and_verdicts(dir: &Path) {
    // One descriptive row per (cell, problem), with the CSV columns.
    let desc = read(&dir.join("tables/descriptive.csv"));
    let mut lines = desc.lines();
    assert_eq!(
        lines.next().unwrap(),
        "problem,dim,algorithm,kind,params,runs,best,worst,mean,sd,median,q1,q3,successes,\
         success_rate,mean_evaluations_to_success,aRT"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 4 * 3);
    for (f, d) in [
        ("sphere", 2),
        ("sphere", 4),
        ("rastrigin", 2),
        ("rastrigin", 4),
    ] {
        for a in ["HS", "PSO", "MHS"] {
            let prefix = format!("{f},{d},{a},");
            assert!(
                rows.iter()
                    .any(|r| r.starts_with(&prefix) && r.contains(",5,")),
                "no row {prefix}"
            );
        }
    }
    // One test per non-reference algorithm and problem, by design: every
    // cell derives its own seeds, so none is paired.
    let tests = read(&dir.join("tables/tests.csv"));
    assert_eq!(tests.lines().count(), 1 + 4 * 2);
    assert!(tests
        .lines()
        .skip(1)
        .all(|l| l.contains(",MHS,mann-whitney-u,")));
    let anytime = read(&dir.join("tables/anytime_tests.csv"));
    assert_eq!(anytime.lines().count(), 1 + 4 * 2);
    let verdicts = read(&dir.join("tables/verdicts.csv"));
    assert!(verdicts.starts_with(
        "table,measure,algorithm,reference,scope,units,problems,better,equal,worse,test,\
         p_value,p_adjusted,p_min,family,effect_size,effect_hl,effect_ci_low,effect_ci_high,\
         rope,prob_better,prob_equivalent,prob_worse,verdict\n"
    ));
    // Two functions are the units (each at two dimensions): p_min = 0.5,
    // so no verdict is better or worse by construction (two units are too
    // few for equivalence too: undecided).
    let all_hs = verdicts
        .lines()
        .find(|l| l.starts_with("reference,final-error,HS,MHS,all,2,4,"))
        .unwrap_or_else(|| panic!("{verdicts}"));
    assert!(
        all_hs.contains(",wilcoxon-signed-rank,") && all_hs.ends_with(",undecided"),
        "{all_hs}"
    );
    assert!(verdicts
        .lines()
        .any(|l| l.starts_with("reference,final-error,HS,MHS,dim=2,")));
    let marks = read(&dir.join("tables/marks_summary.csv"));
    assert_eq!(marks.lines().count(), 1 + 2 * 2);
    let friedman = read(&dir.join("tables/friedman.csv"));
    assert_eq!(friedman.lines().count(), 1 + 3);
}

/// The small campaign's `report.md`: its header, its figures and its verdicts.
fn has_its_report_md(dir: &Path) {
    let md = read(&dir.join("report.md"));
    assert!(md.starts_with("# Report: report_test\n"));
    for needle in [
        "**Master seed:** 4242",
        "**Runs per algorithm and problem:** 5",
        "**Budget (objective evaluations per run):** 3000",
        "**Success threshold:** f − f\\* ≤ 1.0e-03",
        "**Tool version:** metabezier ",
        "CSV: [`tables/descriptive.csv`](tables/descriptive.csv)",
        "![Convergence](plots/convergence.png)",
        "![Final error distributions](plots/boxplots.png)",
        "![Scalability](plots/scalability.png)",
        "Holm's step-down correction is applied per problem",
        "median over the function's problems",
        "## Verdicts",
        "units are independent functions",
        "| +/≈/− |",
    ] {
        assert!(md.contains(needle), "report.md lacks {needle:?}");
    }
}

#[test]
fn report_of_a_parameter_grid() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "grid", GRID_SPEC);
    let summary = write_report(&dir, &ReportOptions::default()).unwrap();
    assert_eq!(summary.algorithms, 7);
    // The reference label has 6 configurations: the first is used.
    assert!(summary
        .reference
        .as_deref()
        .unwrap()
        .starts_with("MHS (hmcr=0.7, bw=0.001)"));
    let best = read(&dir.join("tables/tuning_best_mhs.csv"));
    // Header, one row per problem and the overall row.
    assert_eq!(best.lines().count(), 1 + 2 + 1);
    assert!(best.lines().last().unwrap().starts_with("overall,,MHS,"));
    let ranks = read(&dir.join("tables/tuning_ranks_mhs.csv"));
    assert_eq!(ranks.lines().count(), 1 + 6);
    // The pick, with its stability over bootstrap resamples and its edges.
    let picks = read(&dir.join("tables/tuning_picks_mhs.csv"));
    assert_eq!(picks.lines().count(), 1 + 1);
    assert!(picks.starts_with(
        "algorithm,params,setting,mean_rank,runner_up,runner_up_params,runner_up_mean_rank,stability,"
    ));
    assert!(picks.lines().nth(1).unwrap().starts_with("MHS,"));
    for ext in ["svg", "png"] {
        assert!(dir
            .join("plots")
            .join(format!("tuning_mhs.{ext}"))
            .is_file());
    }
    let md = read(&dir.join("report.md"));
    assert!(md.contains("## Parameter tuning"));
    assert!(md.contains("![Parameter grid of MHS](plots/tuning_mhs.png)"));
    keep(&dir, "grid");
}

#[test]
fn marks_on_hand_made_runs_with_a_known_outcome() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("hand");
    std::fs::create_dir_all(&dir).unwrap();
    let mut rows = Vec::new();
    for run in 0..10u32 {
        let x = f64::from(run);
        // A beats the reference R on every run, B loses on every run,
        // C equals R exactly.
        // Only A reaches the threshold, so no pair is "both solved".
        rows.push(("R", "sphere", run, 1.0 + x, None));
        rows.push(("A", "sphere", run, 0.5 + x, Some(100)));
        rows.push(("B", "sphere", run, 2.0 + 2.0 * x, None));
        rows.push(("C", "sphere", run, 1.0 + x, None));
    }
    std::fs::write(dir.join("runs.csv"), hand_made(&rows)).unwrap();
    let s = write_report(
        &dir,
        &ReportOptions {
            reference: Some("R".into()),
            ..ReportOptions::default()
        },
    )
    .unwrap();
    assert_eq!(s.reference.as_deref(), Some("R"));
    // The hand-made runs share their seeds (seed = run): paired by design.
    let tests = read(&dir.join("tables/tests.csv"));
    let field = |alg: &str, i: usize| -> String {
        let line = tests
            .lines()
            .find(|l| l.starts_with(&format!("sphere,2,{alg},")))
            .unwrap();
        line.split(',').nth(i).unwrap().to_owned()
    };
    assert_eq!(field("A", 6), "wilcoxon-signed-rank");
    assert_eq!(field("A", 14), "+");
    assert_eq!(field("B", 14), "-");
    assert_eq!(field("C", 14), "=");
    // A12 and the ratio of medians: A is lower on every pair, C equal.
    assert_eq!(field("C", 15), "0.5");
    assert_eq!(field("C", 16), "1");
    assert!(field("A", 15).parse::<f64>().unwrap() < 0.5);
    let comparison = read(&dir.join("report.md"));
    assert!(comparison.contains("1/0/0"), "{comparison}");
    assert!(comparison.contains("0/0/1"));
    assert!(comparison.contains("0/1/0"));
    // Only runs.csv: convergence and scalability plots are skipped, the
    // ECDF and box plots are drawn.
    assert!(dir.join("plots/boxplots.png").is_file());
    assert!(dir.join("plots/ecdf.png").is_file());
    assert!(!dir.join("plots/convergence.png").exists());
    let md = read(&dir.join("report.md"));
    assert!(md.contains("convergence plot skipped"));
    assert!(md.contains("scalability plot skipped"));
    assert!(md.contains("convergence.csv and timing.csv not found"));
    assert!(md.contains("spec.toml not found"));
    keep(&dir, "hand");
}

#[test]
fn degenerate_inputs_do_not_fail() {
    let tmp = tempfile::tempdir().unwrap();
    // A single algorithm, a single run, no success, a zero and a huge error.
    let dir = tmp.path().join("single");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("runs.csv"),
        hand_made(&[("A", "sphere", 0, 0.0, None), ("A", "step", 0, 1e300, None)]),
    )
    .unwrap();
    let s = write_report(&dir, &ReportOptions::default()).unwrap();
    assert_eq!(s.reference, None);
    let md = read(&dir.join("report.md"));
    assert!(md.contains("single algorithm configuration: no significance test"));
    assert!(md.contains("runtime ECDF skipped: no run reached the success threshold"));
    assert!(!dir.join("tables/tests.csv").exists());
    assert!(!dir.join("tables/verdicts.csv").exists());

    // NaN and infinite errors, odd labels.
    let dir = tmp.path().join("odd");
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = hand_made(&[
        ("A|B", "sphere", 0, f64::NAN, None),
        ("A|B", "sphere", 1, f64::INFINITY, None),
        ("\"x, y\"", "sphere", 0, 2.0, Some(3)),
        ("\"x, y\"", "sphere", 1, 3.0, None),
    ]);
    text.push('\n');
    std::fs::write(dir.join("runs.csv"), text).unwrap();
    std::fs::write(dir.join("spec.toml"), "this is not = = toml").unwrap();
    let s = write_report(&dir, &ReportOptions::default()).unwrap();
    assert_eq!(s.algorithms, 2);
    let md = read(&dir.join("report.md"));
    assert!(md.contains("spec.toml is not valid TOML"));
    assert!(md.contains("A\\|B"));

    // Header only: an error, not a panic.
    let dir = tmp.path().join("empty");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("runs.csv"), HEADER).unwrap();
    let err = write_report(&dir, &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("no runs to report"), "{err}");

    // No runs.csv at all, a bad column, a bad α.
    let err = write_report(&tmp.path().join("missing"), &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("runs.csv"), "{err}");
    let dir = tmp.path().join("bad");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("runs.csv"),
        format!("{HEADER}A,hs,,sphere,two,1,0,0,1,1,1,,false\n"),
    )
    .unwrap();
    let err = write_report(&dir, &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("column dim"), "{err}");
    let err = write_report(
        &dir,
        &ReportOptions {
            alpha: 1.5,
            ..ReportOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(err.contains("significance level"), "{err}");
}

#[test]
fn external_runs_join_the_comparison() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("base");
    std::fs::create_dir_all(&dir).unwrap();
    let mut rows = Vec::new();
    for run in 0..10u32 {
        rows.push((
            "MHS",
            "sphere",
            run,
            1e-9 * f64::from(run + 1),
            Some(200 + run as u64),
        ));
        rows.push(("HS", "sphere", run, 1e-2 * f64::from(run + 1), None));
    }
    std::fs::write(dir.join("runs.csv"), hand_made(&rows)).unwrap();
    let ext = tmp.path().join("other.csv");
    let mut ext_rows = Vec::new();
    for run in 0..10u32 {
        ext_rows.push((
            "CMA-ES",
            "sphere",
            run,
            1e-12 * f64::from(run + 1),
            Some(100),
        ));
        ext_rows.push(("HS", "sphere", run, 1e-3 * f64::from(run + 1), None));
    }
    std::fs::write(&ext, hand_made(&ext_rows)).unwrap();
    let s = write_report(
        &dir,
        &ReportOptions {
            external: Some(ext.clone()),
            ..ReportOptions::default()
        },
    )
    .unwrap();
    assert_eq!(s.algorithms, 4);
    assert_eq!(s.reference.as_deref(), Some("MHS"));
    let algs = read(&dir.join("tables/algorithms.csv"));
    assert!(algs.contains("CMA-ES,CMA-ES,hs,hms=5,true"));
    assert!(algs.contains("HS (external),HS (external),hs,hms=5,true"));
    let md = read(&dir.join("report.md"));
    assert!(md.contains("**External runs:**"));
    assert!(md.contains("shown as \"&lt;label&gt; (external)\""));
    let tests = read(&dir.join("tables/tests.csv"));
    let cma = tests.lines().find(|l| l.contains(",CMA-ES,")).unwrap();
    let f: Vec<&str> = cma.split(',').collect();
    // Every run of both reached the threshold: "both solved", not a mark,
    // although CMA-ES is lower on every run (A12 = 0).
    assert_eq!(
        (f[6], f[14], f[15]),
        ("wilcoxon-signed-rank", "both solved", "0"),
        "{cma}"
    );
    keep(&dir, "external");
}

#[test]
fn a_report_refuses_rows_that_do_not_state_the_campaign() {
    let tmp = tempfile::tempdir().unwrap();
    let out = campaign(tmp.path(), "honest", SPEC);
    // runs.csv and spec.toml alone (no meta.toml: not a campaign directory,
    // which would have to hold every result file), so that only the rows
    // of runs.csv are at stake.
    for f in ["convergence.csv", "timing.csv", "hits.csv", "meta.toml"] {
        std::fs::remove_file(out.join(f)).unwrap();
    }
    let runs = read(&out.join("runs.csv"));
    let lines: Vec<&str> = runs.lines().collect();
    let report = |text: &str| {
        std::fs::write(out.join("runs.csv"), text).unwrap();
        write_report(&out, &ReportOptions::default())
            .map(|_| String::new())
            .unwrap_or_else(|e| e.to_string())
    };
    // A duplicated row.
    let dup = format!("{}\n{}\n", runs.trim_end(), lines[1]);
    let e = report(&dup);
    assert!(e.ends_with("runs.csv: run 0 of HS:hs[hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip] on sphere-2 appears twice"), "{e}");
    // A missing row.
    let missing = format!("{}\n", lines[..lines.len() - 1].join("\n"));
    let e = report(&missing);
    assert!(
        e.contains("runs.csv: 1 of 60 runs are missing (the first is run 4 of MHS:mhs["),
        "{e}"
    );
    // A foreign row (another seed's problem).
    let foreign = runs.replacen("sphere,2,", "sphere,3,", 1);
    let e = report(&foreign);
    assert!(e.contains("is not a run of spec.toml"), "{e}");
    // The original rows are accepted again.
    assert_eq!(report(&runs), "");
    // An unfinished campaign.
    std::fs::remove_file(out.join("runs.csv")).unwrap();
    std::fs::write(out.join("journal.csv"), b"").unwrap();
    let e = write_report(&out, &ReportOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.ends_with("campaign unfinished (a journal.csv and no runs.csv): run `metabezier run SPEC --resume` to finish it"), "{e}");
}

/// A runs.csv of `rows` (algorithm, problem, run, error) whose seeds are
/// `seed_base + run`, at dimension 2 and budget 1000, none successful.
fn seeded(rows: &[(&str, &str, u32, f64)], seed_base: u64) -> String {
    let mut s = HEADER.to_owned();
    for (alg, problem, run, error) in rows {
        s.push_str(&format!(
            "{alg},hs,hms=5,{problem},2,1000,{run},{},{error},{error},1000,,false\n",
            seed_base + u64::from(*run)
        ));
    }
    s
}

#[test]
fn verdicts_across_functions_have_known_answers() {
    // The reference R on eight functions. External X has exactly R's
    // values on four functions and 1000× smaller errors on the other four;
    // external Y is 1000× smaller on all eight; their seeds differ from R's.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("known");
    std::fs::create_dir_all(&dir).unwrap();
    let functions = ["f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8"];
    let error = |f: usize, run: u32| (1.0 + f as f64) * (1.0 + 0.1 * f64::from(run));
    let mut r = Vec::new();
    let mut ext = Vec::new();
    for (i, f) in functions.iter().enumerate() {
        for run in 0..10u32 {
            let e = error(i, run);
            r.push(("R", *f, run, e));
            ext.push(("X", *f, run, if i < 4 { e } else { e / 1000.0 }));
            ext.push(("Y", *f, run, e / 1000.0));
        }
    }
    std::fs::write(dir.join("runs.csv"), seeded(&r, 0)).unwrap();
    let ext_path = tmp.path().join("external.csv");
    std::fs::write(&ext_path, seeded(&ext, 5000)).unwrap();
    write_report(
        &dir,
        &ReportOptions {
            reference: Some("R".into()),
            external: Some(ext_path),
            ..ReportOptions::default()
        },
    )
    .unwrap();
    // Other seeds: the first level is unpaired.
    let tests = read(&dir.join("tables/tests.csv"));
    assert!(
        tests
            .lines()
            .skip(1)
            .all(|l| l.contains(",mann-whitney-u,")),
        "{tests}"
    );
    let verdicts = read(&dir.join("tables/verdicts.csv"));
    let row = |alg: &str, test: &str| -> Vec<String> {
        verdicts
            .lines()
            .map(|l| l.split(',').map(String::from).collect::<Vec<_>>())
            .find(|f| {
                f[0] == "reference"
                    && f[1] == "final-error"
                    && f[2] == alg
                    && f[4] == "all"
                    && f[10] == test
            })
            .unwrap_or_else(|| panic!("no {alg} {test} row in {verdicts}"))
    };
    // X: the four zero differences are dropped, n = 4, p = 0.125 = p_min
    // (SciPy: wilcoxon([0, 0, 0, 0, -3, -3, -3, -3]).pvalue = 0.125).
    let x = row("X", "wilcoxon-signed-rank");
    assert_eq!(&x[5..10], ["8", "8", "4", "4", "0"], "{x:?}");
    assert_eq!(x[11], "0.125");
    assert_eq!(x[13], "0.125");
    assert_eq!(x[14], "2", "a family of two rows");
    assert_eq!(x[15], "-1.5");
    // Walsh averages: 10 at 0, 16 at −1.5, 10 at −3: HL −1.5; eight units
    // give a finite 95 % interval.
    assert_eq!(x[16], "-1.5");
    assert_eq!((x[17].as_str(), x[18].as_str()), ("-3", "0"), "{x:?}");
    assert_eq!(x[19], "0.3");
    assert_eq!(x[23], "undecided");
    // Y: eight of eight better, p = 2/256 (SciPy: wilcoxon([-3] * 8)), Holm
    // over the family of the two rows doubles it: 0.015625 < 0.05.
    let y = row("Y", "wilcoxon-signed-rank");
    assert_eq!(&y[7..10], ["8", "0", "0"], "{y:?}");
    assert_eq!(y[11], "0.0078125");
    assert_eq!(y[12], "0.015625");
    assert_eq!(y[13], "0.0078125");
    assert_eq!(y[15], "-3");
    assert_eq!(y[23], "better");
    // Friedman over the three, Holm post-hoc against R: average ranks R 2.75,
    // X 2.0, Y 1.25 on 8 blocks, SE 0.5; z(Y) = 3, z(X) = 1.5.
    let y = row("Y", "friedman-holm");
    assert_eq!(y[23], "better");
    let x = row("X", "friedman-holm");
    assert_eq!(x[23], "undecided");
    // 2(1 − Φ(1.5)) = 0.13361440253771617 (scipy.stats.norm.sf(1.5) * 2)
    assert!(
        (x[11].parse::<f64>().unwrap() - 0.13361440253771617).abs() < 1e-9,
        "{x:?}"
    );
    let md = read(&dir.join("report.md"));
    assert!(
        md.contains("| X | R | final-error | 4/4/0 | -1.50 [-3.00, 0] |"),
        "{md}"
    );
}

/// The error of `write_report` on `dir`, or "" when it reports.
fn report_error(dir: &Path) -> String {
    write_report(dir, &ReportOptions::default())
        .map(|_| String::new())
        .unwrap_or_else(|e| e.to_string())
}

#[test]
fn a_campaign_directory_without_one_of_its_result_files_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = campaign(tmp.path(), "whole", SPEC);
    let pristine: Vec<(String, Vec<u8>)> = ["convergence.csv", "timing.csv", "hits.csv"]
        .iter()
        .map(|f| (f.to_string(), std::fs::read(out.join(f)).unwrap()))
        .collect();
    for (f, bytes) in &pristine {
        std::fs::remove_file(out.join(f)).unwrap();
        let e = report_error(&out);
        assert!(
            e.ends_with(&format!(
                "{f}: not found, but the directory holds a campaign (it has meta.toml), whose finished runs always write it; was it deleted, or the directory copied in part?"
            )),
            "{f}: {e}"
        );
        assert!(e.contains(&out.join(f).display().to_string()), "{e}");
        std::fs::write(out.join(f), bytes).unwrap();
    }
    assert_eq!(report_error(&out), "");
}

#[test]
fn a_nan_in_a_result_file_is_refused_with_its_line_and_column() {
    let tmp = tempfile::tempdir().unwrap();
    let out = campaign(tmp.path(), "nan", SPEC);
    // Replace one field of data line `line` (1-based over the file) of `file`.
    let with = |file: &str, line: usize, column: usize, value: &str| {
        let text = read(&out.join(file));
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        let mut fields: Vec<&str> = lines[line - 1].split(',').collect();
        fields[column] = value;
        lines[line - 1] = fields.join(",");
        std::fs::write(out.join(file), lines.join("\n") + "\n").unwrap();
        text
    };
    // convergence.csv: algorithm,kind,params,problem,dim,run,evaluations,best,error
    let cases: [(&str, usize, usize, &str, &str); 6] = [
        ("convergence.csv", 3, 7, "NaN", "convergence.csv:3: column best: expected a number (not NaN), found \"NaN\""),
        ("convergence.csv", 4, 8, "NaN", "convergence.csv:4: column error: expected a number (not NaN), found \"NaN\""),
        ("runs.csv", 2, 8, "NaN", "runs.csv:2: column best: expected a number (not NaN), found \"NaN\""),
        ("timing.csv", 5, 6, "inf", "timing.csv:5: column wall_seconds: expected a finite number of at least 0, found \"inf\""),
        ("hits.csv", 2, 6, "NaN", "hits.csv:2: column target: expected a finite number above 0, found \"NaN\""),
        ("convergence.csv", 3, 6, "1", "convergence.csv:3: column evaluations: must rise strictly from one row of a run to the next, but does not here (a row repeated or out of order)"),
    ];
    for (file, line, column, value, expected) in cases {
        let original = with(file, line, column, value);
        let e = report_error(&out);
        assert!(e.ends_with(expected), "{file}: {e}");
        std::fs::write(out.join(file), original).unwrap();
    }
    assert_eq!(report_error(&out), "");
}

/// Six DejaVu Sans glyphs fitted by LM alone with cubics and rational
/// cubics joined G1, at equal segments and at equal free parameters, under
/// the fixed-parameter E and under the orthogonal error with the joint
/// chain (the design of `experiments/ch5_errors.toml`, reduced).
fn errors_spec() -> String {
    let font = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/DejaVuSans.ttf");
    let inputs: Vec<String> = "aceGs2"
        .chars()
        .map(|g| format!("\"font:{}:{g}\"", font.display()))
        .collect();
    let inputs = format!("[{}]", inputs.join(", "));
    let mut text = String::from(
        "[experiment]\nname = \"errors\"\nseed = 5\nruns = 1\nbudget = 2000\nthreshold = 0\n",
    );
    for size in ["segments = 12", "free_parameters = 60"] {
        for variant in [
            "error = \"fixed\"\nchain = \"sequential\"",
            "error = \"orthogonal\"\nchain = \"joint\"",
        ] {
            text.push_str(&format!(
                "\n[[fit]]\ninput = {inputs}\nfunction = [\"cubic\", \"rational-cubic\"]\n\
                 continuity = \"g1\"\n{size}\nclosing = \"smooth\"\n{variant}\n"
            ));
        }
    }
    text.push_str("\n[[algorithm]]\nname = \"lm\"\nlabel = \"LM\"\n");
    text
}

#[test]
fn functions_are_judged_per_error_and_size_with_a_single_method() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "errors", &errors_spec());
    write_report(&dir, &ReportOptions::default()).unwrap();
    keep(&dir, "errors");
    let verdicts = read(&dir.join("tables/verdicts.csv"));
    let row = |scope: &str| -> Vec<String> {
        let line = verdicts
            .lines()
            .find(|l| {
                l.starts_with("fitting-function,final-error,cubic,rational-cubic,")
                    && l.contains(&format!(",{scope},"))
            })
            .unwrap_or_else(|| panic!("no row at {scope} in\n{verdicts}"));
        line.split(',').map(str::to_owned).collect()
    };
    // One row per design point: the two errors (each with its chain) and
    // the two sizes, six outlines each.
    for error in [
        "error=fixed;chain=sequential",
        "error=orthogonal;chain=joint",
    ] {
        for size in ["segments", "free-parameters"] {
            let r = row(&format!("{error};size={size}"));
            assert_eq!(r[5], "6", "{r:?}");
        }
        // At equal segments the rational cubic has two more unknowns per
        // segment, and it is ahead on every glyph: the verdict is decided.
        let r = row(&format!("{error};size=segments"));
        assert_eq!((r[7].as_str(), r[9].as_str()), ("0", "6"), "{r:?}");
        assert_eq!(r.last().map(String::as_str), Some("worse"), "{r:?}");
    }
    // The summary states the verdicts at the design points, with their
    // scope, and none that pools the errors or the sizes.
    let report = read(&dir.join("report.md"));
    let summary = &report[report.find("## Summary").unwrap()..];
    let summary = &summary[..summary[3..].find("\n## ").map_or(summary.len(), |i| i + 3)];
    assert!(summary.contains("| Scope |"), "{summary}");
    assert!(summary.contains("error=orthogonal;chain=joint;size=free-parameters"));
    assert!(!summary.contains("| all |"), "{summary}");
    assert!(summary.contains("which fitting function and which continuity"));
    // A fitting report speaks of E and segments, not of f − f*, success
    // rates and runtimes to a target.
    assert!(
        report.contains("| Problem | Segments | Method | Runs |"),
        "{report}"
    );
    for benchmark_word in ["f − f", "aRT", "| SR |", "Evals to success"] {
        assert!(
            !report.contains(benchmark_word),
            "{benchmark_word} in\n{report}"
        );
    }
    assert!(report.contains("Final fitting error E per method and problem"));
    // The problem names carry the variant and the free parameters.
    let runs = read(&dir.join("runs.csv"));
    assert!(runs.contains("DejaVuSans-a/cubic/g1/params=60/orthogonal/joint,20,"));
    assert!(runs.contains("DejaVuSans-a/rational-cubic/g1/params=60,12,"));
}

/// The width and height of a PNG file, from its IHDR chunk.
#[test]
fn figures_with_many_panels_are_split_into_pages_that_fit_a_screen() {
    // 8 functions × 3 dimensions = 24 problems, 4 algorithms: convergence
    // plots of 8 rows of 3 panels and a scalability plot of 8 rows (each
    // above 3,000 px in one image); the box plots' 12 rows just fit.
    let spec = r#"
[experiment]
name = "pages"
seed = 3
runs = 2
budget = 300
threshold = 1e-3

[[problem]]
function = ["sphere", "rastrigin", "ackley", "griewank", "rosenbrock", "schwefel_2_22", "step", "schwefel_1_2"]
dim = [2, 3, 4]

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "pso"
label = "PSO"
swarm = 10

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "ga"
label = "GA"
"#;
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "pages", spec);
    write_report(&dir, &ReportOptions::default()).unwrap();
    keep(&dir, "pages");
    let mut pngs: Vec<PathBuf> = std::fs::read_dir(dir.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    pngs.sort();
    for p in &pngs {
        let (w, h) = common::png_size(p);
        assert!(w <= 3000 && h <= 3000, "{}: {w} × {h}", p.display());
    }
    let names: Vec<String> = pngs
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert!(!names.contains(&"boxplots_2.png".to_owned()), "{names:?}");
    for stem in ["convergence", "scalability"] {
        assert!(names.contains(&format!("{stem}.png")), "{names:?}");
        assert!(names.contains(&format!("{stem}_2.png")), "{names:?}");
    }
    // The report has one section per figure, showing its first page and
    // linking every page.
    let md = read(&dir.join("report.md"));
    assert!(md.contains("(plots/convergence_2.png)"), "{md}");
    assert!(md.contains("(plots/scalability_2.png)"), "{md}");
    assert!(md.contains("### Convergence (2 pages)"), "{md}");
    assert!(!md.contains("### Convergence (2 of 2)"), "{md}");
}
