//! Reports people read, on reduced versions of the campaigns: a grid of 54
//! settings, a robustness design and a fitting study each give a
//! `report.md` that opens with its summary and stays under 300 lines,
//! pictures no larger than 3,000 px, at most the best and default setting
//! of each grid in a figure, and one fixed colour per algorithm; a fitting
//! campaign over a budget ladder and one over α_size each get the figure
//! that answers its question, and only then. (The implant's report is
//! checked in `tests/implant/implant_tests.rs`, its figure in `tests/implant/implant_figures.rs`.)

use crate::common;

use std::path::{Path, PathBuf};

use metabezier::report::{write_report, ReportOptions};

/// [`common::campaign`] and its report.
fn campaign(tmp: &Path, name: &str, text: &str) -> PathBuf {
    let out = common::campaign(tmp, name, text);
    write_report(&out, &ReportOptions::default()).unwrap();
    out
}

fn read(path: &Path) -> String {
    std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn a_grid_of_fifty_four_settings_reads_on_a_screen() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(
        tmp.path(),
        "grid",
        r#"
[experiment]
name = "grid"
seed = 11
runs = 2
budget = 400

[[problem]]
function = ["sphere", "rastrigin"]
dim = [2, 5]

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

[[algorithm]]
name = "ga"
label = "GA"

[[algorithm]]
name = "pso"
label = "PSO"
"#,
    );
    let faults = common::unreadable(&dir);
    assert!(faults.is_empty(), "{faults:?}");
    let md = read(&dir.join("report.md"));
    assert!(
        md.contains("### Parameter tuning: the pick of every algorithm"),
        "{md}"
    );
    let mut svgs: Vec<PathBuf> = std::fs::read_dir(dir.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        .collect();
    svgs.sort();
    for path in &svgs {
        let stem = path.file_stem().unwrap().to_string_lossy();
        if stem.starts_with("tuning_") {
            continue;
        }
        let svg = read(path);
        // Of each 27-setting grid, only its best and default settings.
        for label in ["HS (", "MHS ("] {
            let shown = svg
                .lines()
                .map(str::trim)
                .filter(|l| l.starts_with(label))
                .collect::<std::collections::BTreeSet<_>>()
                .len();
            assert!(shown <= 2, "{stem}: {shown} settings of {label}");
        }
    }
    for stem in ["convergence", "boxplots", "scalability"] {
        let svg = read(&dir.join(format!("plots/{stem}.svg")));
        let names = svg
            .lines()
            .filter(|l| l.trim_start().starts_with("HS ("))
            .count();
        assert!(names >= 1, "{stem}: no setting of HS");
        // The optimisers' own colours (Okabe & Ito), whatever their place
        // in the spec: HS blue, MHS vermillion, GA bluish green, PSO orange.
        for colour in ["#0072B2", "#D55E00", "#009E73", "#E69F00"] {
            assert!(svg.contains(colour), "{stem}: no {colour}");
        }
    }
    // Runtimes at different dimensions are not pooled.
    assert!(!dir.join("plots/ecdf.png").exists());
    // The scalability figure is of medians with their exponent.
    let scal = read(&dir.join("plots/scalability.svg"));
    assert!(scal.contains("D^"), "no fitted exponent");
}

#[test]
fn a_robustness_design_reads_on_a_screen_with_its_verdict_map() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(
        tmp.path(),
        "design",
        r#"
[experiment]
name = "design"
seed = 12
runs = 3
budget = [300, 900]
paired = ["budget"]

[[problem]]
function = ["sphere", "rastrigin", "ackley", "griewank", "step", "rosenbrock"]
dim = 5
transform = ["none", "shift"]
instances = 2

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "hs"
label = "HS-tuned"
hms = 10

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "pso"
label = "PSO"
"#,
    );
    let faults = common::unreadable(&dir);
    assert!(faults.is_empty(), "{faults:?}");
    let md = read(&dir.join("report.md"));
    let summary = &md[md.find("## Summary").unwrap()..md.find("## Plots").unwrap()];
    assert!(
        summary.contains("(plots/verdicts_final_error.png)"),
        "{summary}"
    );
    let map = read(&dir.join("plots/verdicts_final_error.svg"));
    for point in ["budget = 300", "budget = 900", "transform = shift"] {
        assert!(map.contains(point), "the map has no row {point}");
    }
    // HS-tuned is drawn in HS's blue, dashed: more HS-blue strokes than
    // HS's own solid curves alone would give.
    let conv = read(&dir.join("plots/convergence.svg"));
    assert!(conv.contains("#0072B2"));
}

#[test]
fn a_fitting_study_reads_on_a_screen_in_its_own_vocabulary() {
    let tmp = tempfile::tempdir().unwrap();
    let font = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/DejaVuSans.ttf");
    let inputs: Vec<String> = "ace"
        .chars()
        .map(|g| format!("\"font:{}:{g}\"", font.display()))
        .collect();
    let text = format!(
        "[experiment]\nname = \"fits\"\nseed = 5\nruns = 1\nbudget = 2000\nthreshold = 0\n\n\
         [[fit]]\ninput = [{}]\nfunction = [\"cubic\", \"rational-cubic\"]\n\
         continuity = \"g1\"\nsegments = 8\nclosing = \"smooth\"\n\n\
         [[algorithm]]\nname = \"lm\"\nlabel = \"LM\"\n",
        inputs.join(", ")
    );
    let dir = campaign(tmp.path(), "fits", &text);
    let faults = common::unreadable(&dir);
    assert!(faults.is_empty(), "{faults:?}");
    let md = read(&dir.join("report.md"));
    assert!(
        !md.contains("f − f\\*"),
        "benchmark vocabulary in a fitting report"
    );
    assert!(md.contains("Final error E"), "{md}");
    // One budget and one search space: neither answer figure of chapter 5.
    for stem in ["fit_budget", "fit_alpha_size"] {
        assert!(!dir.join(format!("plots/{stem}.png")).exists(), "{stem}");
        assert!(!md.contains(&format!("plots/{stem}.png")), "{stem}");
    }
}

/// The `## Summary` of a report.
fn summary(md: &str) -> &str {
    &md[md.find("## Summary").unwrap()..md.find("## Plots").unwrap()]
}

/// A reduced ch5_mhs: one outline in the per-segment mode at two budgets
/// per segment, HS (also tuned), PSO and MHS.
fn budget_ladder(extra_fit: &str, budget: &str) -> String {
    let coin = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/coin.png");
    format!(
        "[experiment]\nname = \"ladder\"\nseed = 2014\nruns = 3\nthreshold = 0\n\n\
         [[fit]]\ninput = \"{}\"\nfunction = \"rational-cubic\"\ncontinuity = \"g1\"\n\
         budget = {budget}\nsegments = 8\nmode = \"per-segment\"\nclosing = \"smooth\"\n{extra_fit}\n\
         [[algorithm]]\nname = \"hs\"\nlabel = \"HS\"\n\n\
         [[algorithm]]\nname = \"pso\"\nlabel = \"PSO\"\n\n\
         [[algorithm]]\nname = \"mhs\"\nlabel = \"MHS\"\n\n\
         [[algorithm]]\nname = \"hs\"\nlabel = \"HS-tuned\"\nhms = 20\nhmcr = 0.99\nbw = 0.01\n",
        coin.display()
    )
}

#[test]
fn a_budget_ladder_gets_median_e_against_the_budget() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "ladder", &budget_ladder("", "[200, 600]"));
    let faults = common::unreadable(&dir);
    assert!(faults.is_empty(), "{faults:?}");
    let md = read(&dir.join("report.md"));
    assert!(
        summary(&md).contains("The figure that answers the question: [Median E against the budget per segment](plots/fit_budget.png)"),
        "{md}"
    );
    assert!(md.contains("### Median E against the budget per segment"));
    let (w, h) = common::png_size(&dir.join("plots/fit_budget.png"));
    assert!(w <= 3000 && h <= 3000, "{w} × {h}");
    let svg = read(&dir.join("plots/fit_budget.svg"));
    for text in [
        "coin: rational-cubic G1, 8 segments",
        "evaluations per segment (log scale)",
        "median E (log scale)",
        "HS-tuned",
    ] {
        assert!(svg.contains(text), "no {text:?} in fit_budget.svg");
    }
    for tick in ["200", "600"] {
        assert!(svg.lines().any(|l| l.trim() == tick), "no tick {tick}");
    }
    // The optimisers' own colours: HS blue (HS-tuned too, dashed), PSO
    // orange, MHS vermillion.
    for colour in ["#0072B2", "#E69F00", "#D55E00"] {
        assert!(svg.contains(colour), "no {colour}");
    }
    // One point per method and budget: 4 methods × 2 budgets.
    let dots = svg.matches("<circle").count();
    assert_eq!(dots, 8, "{dots} points");
    // No α_size factor: no α_size figure.
    assert!(!dir.join("plots/fit_alpha_size.png").exists());
}

#[test]
fn an_alpha_size_design_gets_e_against_the_bounding_box() {
    let tmp = tempfile::tempdir().unwrap();
    let text = budget_ladder(
        "search_space = [\"technique\", \"bounding-box\"]\nalpha_size = [0.1, 0.25, 0.5]\n",
        "300",
    )
    .replace("name = \"ladder\"", "name = \"alpha\"")
    .replace(
        "threshold = 0\n",
        "threshold = 0\npaired = [\"search_space\", \"alpha_size\"]\n",
    );
    let dir = campaign(tmp.path(), "alpha", &text);
    let faults = common::unreadable(&dir);
    assert!(faults.is_empty(), "{faults:?}");
    let md = read(&dir.join("report.md"));
    assert!(
        summary(&md).contains("[E per α_size against the bounding box](plots/fit_alpha_size.png)"),
        "{md}"
    );
    let (w, h) = common::png_size(&dir.join("plots/fit_alpha_size.png"));
    assert!(w <= 3000 && h <= 3000, "{w} × {h}");
    let svg = read(&dir.join("plots/fit_alpha_size.svg"));
    for text in [
        "rational-cubic G1",
        "α_size (log scale)",
        "E (technique) / E (bounding box) (log scale)",
        "bounding box",
    ] {
        assert!(svg.contains(text), "no {text:?} in fit_alpha_size.svg");
    }
    for tick in ["0.1", "0.25", "0.5"] {
        assert!(svg.lines().any(|l| l.trim() == tick), "no tick {tick}");
    }
    // One budget: the panel names none.
    assert!(!svg.contains("per segment"));
    // 4 methods × 3 values of α_size.
    assert_eq!(svg.matches("<circle").count(), 12);
    // One budget: no budget figure.
    assert!(!dir.join("plots/fit_budget.png").exists());
}
