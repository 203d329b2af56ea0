//! Reports a reader can use: on a reduced tuning grid (54 settings) and a
//! reduced robustness design, `report.md` opens with `## Summary` (the
//! question, the verdicts, the best settings, links to the figures) before
//! any other section, stays under 300 lines for the robustness design, and
//! shows at most a head of every long table, linking its CSV file.

mod common;

use std::path::{Path, PathBuf};

use metabezier::report::{write_report, ReportOptions};

const GRID: &str = r#"
[experiment]
name = "reduced_tuning"
seed = 11
runs = 2
budget = 300
threshold = 1e-8

[[problem]]
function = ["sphere", "rastrigin"]
dim = 2

[[algorithm]]
name = "hs"
label = "HS"
hms = [5, 10, 20]
hmcr = [0.7, 0.9, 0.99]
bw = [0.001, 0.01, 0.1]

[[algorithm]]
name = "mhs"
label = "MHS"
hms = [5, 10, 20]
hmcr = [0.7, 0.9, 0.99]
bw = [0.001, 0.01, 0.1]
"#;

const ROBUSTNESS: &str = r#"
[experiment]
name = "reduced_robustness"
seed = 12
runs = 3
budget = [300, 1000]
threshold = 1e-8
paired = ["budget"]

[[problem]]
function = ["sphere", "rastrigin", "step"]
dim = 3
transform = ["none", "shift", "shift-rotate"]
instances = 2

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "pso"
label = "PSO"

[[algorithm]]
name = "mhs"
label = "MHS"
"#;

fn report_of(tmp: &Path, name: &str, text: &str) -> (PathBuf, String) {
    let out = common::campaign(tmp, name, text);
    write_report(&out, &ReportOptions::default()).unwrap();
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    (out, md)
}

/// The first `## ` heading of the report.
fn first_section(md: &str) -> &str {
    md.lines().find(|l| l.starts_with("## ")).unwrap_or("")
}

#[test]
fn a_grid_report_opens_with_its_summary_and_best_settings() {
    let tmp = tempfile::tempdir().unwrap();
    let (out, md) = report_of(tmp.path(), "grid", GRID);
    assert_eq!(first_section(&md), "## Summary", "{md}");
    let summary = md.split("\n## Plots").next().unwrap();
    assert!(summary.contains("Question: which setting"), "{summary}");
    assert!(summary.contains("- HS: hms="), "{summary}");
    assert!(summary.contains("- MHS: hms="), "{summary}");
    assert!(
        summary.contains("[`tables/tuning_picks_mhs.csv`]"),
        "{summary}"
    );
    assert!(summary.contains("(plots/boxplots.png)"), "{summary}");
    // 54 settings: the long tables show a head and link their CSV, which
    // has every row.
    assert!(md.contains("The first 3 of 54 rows"), "{md}");
    let friedman = std::fs::read_to_string(out.join("tables/friedman.csv")).unwrap();
    assert_eq!(friedman.lines().count(), 55);
    let longest_table = md
        .split("\n\n")
        .filter(|b| b.starts_with('|'))
        .map(|b| b.lines().count())
        .max()
        .unwrap();
    assert!(longest_table <= 2 + 15, "{longest_table}");
}

#[test]
fn a_robustness_report_is_short_and_answers_first() {
    let tmp = tempfile::tempdir().unwrap();
    let (_, md) = report_of(tmp.path(), "robustness", ROBUSTNESS);
    assert_eq!(first_section(&md), "## Summary", "{md}");
    let lines = md.lines().count();
    assert!(lines < 300, "{lines} lines");
    let summary = md.split("\n## Plots").next().unwrap();
    assert!(summary.contains("| HS | MHS | final-error |"), "{summary}");
}
