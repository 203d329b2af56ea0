//! Reports a reader can use: on a reduced tuning grid (54 settings) and a
//! reduced robustness design, `report.md` opens with `## Summary` (the
//! question, the verdicts, the best settings, links to the figures) before
//! any other section, stays under 300 lines for the robustness design, and
//! shows at most a head of every long table, linking its CSV file.

use crate::common;

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

#[test]
fn a_newcomers_summary_says_what_n_allows_and_the_best_per_problem() {
    // Issue 50: `make quick`'s three problems can never give a verdict
    // across problems (p_min = 0.25); the summary says so before its
    // rows, names the best algorithm per problem, lists each comparison
    // once (Friedman's rows only where they disagree), shows the
    // six-hump camel's −2.2e-16 as 0, and reads its ropes from the spec.
    let tmp = tempfile::tempdir().unwrap();
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("experiments/quick.toml")).unwrap();
    let text = text + "\n[report]\nrope_anytime_auc = 0.02\n";
    let dir = common::campaign(tmp.path(), "quick", &text);
    write_report(&dir, &ReportOptions::default()).unwrap();
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let summary = &md[..md.find("## Plots").unwrap()];
    assert!(
        summary.contains("no test across problems can reject at α = 0.05, whatever the data")
            && summary.contains("(3 unit(s): p_min = 0.250, family of 4: 4 × p_min = 1.000)"),
        "{summary}"
    );
    assert!(
        summary.contains("Best per problem (lowest median final error"),
        "{summary}"
    );
    assert!(
        summary.contains("six_hump_camel, D = 2: GA, PSO, MHS (0)"),
        "{summary}"
    );
    assert!(!summary.contains("-2.2e-16"), "{summary}");
    let wilcoxon_rows = summary
        .lines()
        .filter(|l| l.starts_with("| HS | MHS | final-error |"))
        .count();
    assert_eq!(wilcoxon_rows, 1, "{summary}");
    let verdicts = std::fs::read_to_string(dir.join("tables/verdicts.csv")).unwrap();
    assert!(verdicts
        .lines()
        .any(|l| l.contains(",anytime-auc,") && l.contains(",0.02,")));
    assert!(!verdicts.contains("no detectable difference"));
    // Without an MHS and without --reference the first cell is the
    // reference, and the report says so.
    let no_mhs = text.replace("[[algorithm]]\nname = \"mhs\"\nlabel = \"MHS\"\n", "");
    assert_ne!(no_mhs, text);
    let dir = common::campaign(tmp.path(), "quick_no_mhs", &no_mhs);
    write_report(&dir, &ReportOptions::default()).unwrap();
    assert!(std::fs::read_to_string(dir.join("report.md"))
        .unwrap()
        .contains("no configuration is labelled MHS: the reference is the first configuration"));
    // A bad rope in the spec is refused where the campaign reads it.
    let bad = text.replace("rope_anytime_auc = 0.02", "rope_anytime_auc = -1");
    let e = metabezier::experiment::Spec::parse(Path::new("q.toml"), &bad)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("report.rope_anytime_auc") && e.contains("[0, 10]"),
        "{e}"
    );
}
