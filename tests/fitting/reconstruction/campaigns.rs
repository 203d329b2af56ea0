//! Fitting campaigns declared in specs: reproducible and mergeable on 1 and 2
//! threads, their spec errors, the orthogonal error and the joint chain where a
//! section asks, and the current fitting records.

use super::*;

const FIT_SPEC: &str = r#"
[experiment]
name = "fit_test"
seed = 5
runs = 2
budget = 400

[[fit]]
input = "coin.png"
function = ["cubic", "rational-cubic"]
continuity = ["c1", "g1"]
segments = 4

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "lm"
label = "LM"

[[algorithm]]
name = "mhs+lm"
label = "MHS+LM"
"#;

fn spec_in(dir: &Path, text: &str) -> Spec {
    for f in ["coin.png", "horse.png"] {
        std::fs::copy(data().join(f), dir.join(f)).unwrap();
    }
    let path = dir.join("spec.toml");
    std::fs::write(&path, text).unwrap();
    Spec::load(&path).unwrap()
}

fn run(spec: &Spec, out: &Path, threads: usize, shard: Option<Shard>) {
    let opts = RunOptions {
        out: Some(out.to_owned()),
        threads: Some(threads),
        resume: false,
        shard,
        max_runs: None,
        progress: false,
        allow_large: false,
    };
    run_campaign(spec, &opts).unwrap();
}

#[test]
fn a_fitting_campaign_is_reproducible_and_mergeable() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = spec_in(tmp.path(), FIT_SPEC);
    assert_eq!(spec.problems.len(), 4);
    assert_eq!(spec.problems[0].key(), "coin/cubic/c1-4");
    assert_eq!(spec.problems[0].budget, 1600);

    let one = tmp.path().join("one");
    let two = tmp.path().join("two");
    run(&spec, &one, 1, None);
    run(&spec, &two, 2, None);
    for f in ["runs.csv", "convergence.csv", "fits.csv", "segments.csv"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
            "{f} differs between 1 and 2 threads"
        );
    }
    let runs = std::fs::read_to_string(one.join("runs.csv")).unwrap();
    assert_eq!(runs.lines().count(), 1 + 4 * 4 * 2);
    assert!(runs.contains("MHS+LM,mhs+lm,"), "{runs}");
    let segments = std::fs::read_to_string(one.join("segments.csv")).unwrap();
    assert_eq!(segments.lines().count(), 1 + 4 * 4 * 2 * 4);
    // With C1 joins the polynomial fit is a linear least-squares problem, so
    // LM is the exact reference there: no metaheuristic run has a lower E.
    // (With G1 joins the magnitudes make it non-linear and LM is a local
    // method, which a lucky HS run may beat.)
    let records = metabezier::experiment::records::read_results(&one).unwrap();
    assert!(spec.problems.iter().any(|p| p.name() == "coin/cubic/c1"));
    for p in &spec.problems {
        let e = |label: &str| -> f64 {
            records
                .iter()
                .filter(|r| r.problem == p.name() && r.algorithm == label)
                .map(|r| r.best)
                .fold(f64::INFINITY, f64::min)
        };
        if p.name() == "coin/cubic/c1" {
            assert!(e("LM") <= e("HS") * (1.0 + 1e-9), "{}", p.name());
        }
        assert!(records.iter().filter(|r| r.problem == p.name()).all(|r| r
            .fit
            .as_ref()
            .unwrap()
            .segments
            .len()
            == 4));
    }

    // The rows rebuild the fitted segments: each starts where the previous
    // one ends.
    let r0 = records.iter().find(|r| r.fit.is_some()).unwrap();
    let segs: Vec<_> = r0
        .fit
        .as_ref()
        .unwrap()
        .segments
        .iter()
        .map(|row| metabezier::experiment::segments::segment_from_row(row).unwrap())
        .collect();
    use metabezier::geometry::Curve;
    for w in segs.windows(2) {
        assert!(w[0].end().distance(w[1].start()) < 1e-12);
    }

    // The report adds the fitting section, its tables and an overlay.
    let summary =
        metabezier::report::write_report(&one, &metabezier::report::ReportOptions::default())
            .unwrap();
    assert!(
        summary.notes.iter().all(|n| !n.contains("overlay")),
        "{:?}",
        summary.notes
    );
    let md = std::fs::read_to_string(one.join("report.md")).unwrap();
    for needle in [
        "## Curve fitting",
        "### Fit quality and the gap to the best E found",
        "### Best E per fitting function",
        "### Hybrid against its parts",
        "![Best fits of coin](plots/overlay_coin.png)",
    ] {
        assert!(md.contains(needle), "report.md lacks {needle}");
    }
    let quality = std::fs::read_to_string(one.join("tables/fit_quality.csv")).unwrap();
    assert_eq!(quality.lines().count(), 1 + 4 * 4);
    let hybrid = std::fs::read_to_string(one.join("tables/fit_hybrid.csv")).unwrap();
    assert_eq!(hybrid.lines().count(), 1 + 4);
    assert!(one.join("plots/overlay_coin.png").exists());

    // Shards merge into the same files, fits included.
    let s1 = tmp.path().join("s1");
    let s2 = tmp.path().join("s2");
    run(&spec, &s1, 1, Some(Shard::parse("1/2").unwrap()));
    run(&spec, &s2, 1, Some(Shard::parse("2/2").unwrap()));
    let merged = tmp.path().join("merged");
    merge(&spec, &[s1, s2], Some(merged.clone())).unwrap();
    for f in ["runs.csv", "fits.csv", "segments.csv"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(merged.join(f)).unwrap(),
            "{f} differs after merging"
        );
    }
}

pub(super) fn spec_error(text: &str) -> String {
    let tmp = tempfile::tempdir().unwrap();
    for f in ["coin.png", "horse.png"] {
        std::fs::copy(data().join(f), tmp.path().join(f)).unwrap();
    }
    let path = tmp.path().join("spec.toml");
    std::fs::write(&path, text).unwrap();
    let e = Spec::load(&path).unwrap_err();
    assert_eq!(e.path, path);
    format!("{}:{}: {}: {}", e.line, e.column, e.field, e.message)
}

#[test]
fn bad_fitting_specs_get_specific_errors() {
    let head = "[experiment]\nname = \"x\"\nseed = 1\nruns = 1\nbudget = 100\n\n";
    let alg = "\n[[algorithm]]\nname = \"hs\"\n";
    let e = spec_error(&format!(
        "{head}[[fit]]\ninput = \"nowhere.png\"\nsegments = 4\n{alg}"
    ));
    assert!(
        e.starts_with("8:9: fit[1].input: ") && e.contains("nowhere.png: cannot read"),
        "{e}"
    );
    // (the [[fit]] body after `input`, the start of the expected message)
    let cases = [
        (
            "input = \"coin.png\"\nsegments = 4\nweight_range = [0, 10]",
            "10:16: fit[1].weight_range: expected 0 < min < max (finite) for the rational weights, found [0, 10]: the range must exclude 0",
        ),
        (
            "input = \"coin.png\"\nsegments = \"true-breaks\"",
            "9:12: fit[1].segments: \"true-breaks\" needs a glyph input",
        ),
        (
            "input = \"horse.png\"\nsegments = 5",
            "9:12: fit[1].segments: horse/rational-cubic/g1: contour 0: 5 segment(s) requested",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\ncontour = \"every\"",
            "10:11: fit[1].contour: expected a contour number ≥ 0 or \"all\", found \"every\"",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\ncontour = 3",
            "8:9: fit[1].input: coin.png: contour 3 was asked for, but the input has 1 contour",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nclosing = \"round\"",
            "10:11: fit[1].closing: unknown value \"round\"; valid choices: \"smooth\" or \"c0\"",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nmode = \"per-segmnet\"",
            "10:8: fit[1].mode: unknown value \"per-segmnet\"; did you mean \"per-segment\"?",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nalpha_size = [0.1, 0]",
            "10:20: fit[1].alpha_size: expected a real number in (0, 1000000], found 0",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nerror = \"orthogonl\"",
            "10:9: fit[1].error: unknown value \"orthogonl\"; did you mean \"orthogonal\"?",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nerror = [\"fixed\", \"orthogonal\"]",
            "7:1: fit[1].error: expected one error measure, not a list",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nchain = \"jiont\"",
            "10:9: fit[1].chain: unknown value \"jiont\"; did you mean \"joint\"?",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nchain = [\"sequential\", \"joint\"]",
            "7:1: fit[1].chain: expected one chain, not a list",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nmode = \"per-segment\"\nchain = \"joint\"",
            "11:9: fit[1].chain: expected \"sequential\" with mode = \"per-segment\"",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nfree_parameters = 20",
            "9:12: fit[1].segments: expected either segments or free_parameters, not both",
        ),
        (
            "input = \"coin.png\"\nfree_parameters = 0",
            "9:19: fit[1].free_parameters: expected an integer",
        ),
        (
            "input = \"coin.png\"\nfree_parameters = 20\nfunction = \"quadratic\"\ncontinuity = \"c1\"",
            "9:19: fit[1].free_parameters: a quadratic segment with C1 joins adds no free parameter to its chain",
        ),
        (
            "input = \"coin.png\"\nsegments = 4\nfunction = \"quartic\"",
            "10:12: fit[1].function: unknown value \"quartic\"; did you mean \"quadratic\"? Valid choices: \"quadratic\"",
        ),
    ];
    for (body, expected) in cases {
        let e = spec_error(&format!("{head}[[fit]]\n{body}\n{alg}"));
        assert!(e.starts_with(expected), "{e}");
    }
    let e = spec_error(&format!(
        "{head}[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"lm\"\n"
    ));
    assert!(
        e.starts_with("12:8: algorithm[1].name: \"lm\" uses Levenberg–Marquardt, which solves least-squares fitting problems only"),
        "{e}"
    );
}

/// A one-run LM campaign of the coin in 6 rational cubics joined G1, named
/// `name`: one `[[fit]]` section with the spec defaults, a second with
/// `key` added. Returns the problem keys and the best E of each problem.
fn coin_sections(name: &str, key: &str) -> (Vec<String>, Vec<(String, f64)>) {
    let tmp = tempfile::tempdir().unwrap();
    let body = "input = \"coin.png\"\nfunction = \"rational-cubic\"\ncontinuity = \"g1\"\nsegments = 6\nbudget = 2000\n";
    let text = format!(
        "[experiment]\nname = \"{name}\"\nseed = 1\nruns = 1\n\n[[fit]]\n{body}\n[[fit]]\n{body}{key}\n\n[[algorithm]]\nname = \"lm\"\n"
    );
    let spec = spec_in(tmp.path(), &text);
    let names = spec.problems.iter().map(|p| p.key()).collect();
    let out = tmp.path().join("out");
    run(&spec, &out, 2, None);
    let records = metabezier::experiment::records::read_results(&out).unwrap();
    let best = records
        .iter()
        .map(|r| (r.problem.clone(), r.best))
        .collect();
    (names, best)
}

/// The best E of `problem` among `records`.
fn best_of(records: &[(String, f64)], problem: &str) -> f64 {
    records
        .iter()
        .find(|(p, _)| p == problem)
        .unwrap_or_else(|| panic!("{problem} in {records:?}"))
        .1
}

#[test]
fn a_campaign_measures_the_orthogonal_error_where_a_section_asks() {
    let (names, records) = coin_sections("err", "error = \"orthogonal\"");
    assert_eq!(
        names,
        [
            "coin/rational-cubic/g1-6",
            "coin/rational-cubic/g1/orthogonal-6"
        ]
    );
    let (fixed, orthogonal) = (
        best_of(&records, "coin/rational-cubic/g1"),
        best_of(&records, "coin/rational-cubic/g1/orthogonal"),
    );
    // The orthogonal E is the distance from each point to the curve, at
    // most the distance to the point at its fixed parameter: lower (7.2
    // against 12.8 here).
    assert!(orthogonal < 0.8 * fixed, "{orthogonal} vs {fixed}");
}

#[test]
fn a_campaign_solves_the_chain_jointly_where_a_section_asks() {
    let (names, records) = coin_sections("chain", "chain = \"joint\"");
    assert_eq!(
        names,
        ["coin/rational-cubic/g1-6", "coin/rational-cubic/g1/joint-6"]
    );
    let (sequential, joint) = (
        best_of(&records, "coin/rational-cubic/g1"),
        best_of(&records, "coin/rational-cubic/g1/joint"),
    );
    // The same curves, their joins chosen together: never worse, here lower.
    assert!(joint < 0.95 * sequential, "{joint} vs {sequential}");
}

#[test]
fn free_parameters_give_each_function_its_segments() {
    let tmp = tempfile::tempdir().unwrap();
    let text = "[experiment]\nname = \"params\"\nseed = 1\nruns = 1\nbudget = 2000\n\n\
        [[fit]]\ninput = \"coin.png\"\nfunction = [\"quadratic\", \"cubic\", \"rational-quadratic\", \"rational-cubic\"]\n\
        continuity = \"g1\"\nfree_parameters = 30\nclosing = \"smooth\"\n\n\
        [[fit]]\ninput = \"coin.png\"\nfunction = [\"cubic\", \"rational-cubic\"]\ncontinuity = \"c1\"\n\
        free_parameters = 30\nclosing = \"smooth\"\nerror = \"orthogonal\"\nchain = \"joint\"\n\n\
        [[algorithm]]\nname = \"lm\"\n";
    let spec = spec_in(tmp.path(), text);
    let names: Vec<String> = spec.problems.iter().map(|p| p.key()).collect();
    // round(30 / k) segments, k = 1, 3, 2, 5 with G1 joins and 2, 4 with C1
    // (the coin has no corner, so its chain is closed and cyclic).
    assert_eq!(
        names,
        [
            "coin/quadratic/g1/params=30-30",
            "coin/cubic/g1/params=30-10",
            "coin/rational-quadratic/g1/params=30-15",
            "coin/rational-cubic/g1/params=30-6",
            "coin/cubic/c1/params=30/orthogonal/joint-15",
            "coin/rational-cubic/c1/params=30/orthogonal/joint-8",
        ]
    );
    let out = tmp.path().join("out");
    run(&spec, &out, 2, None);
    let records = metabezier::experiment::records::read_results(&out).unwrap();
    assert_eq!(records.len(), 6);
    for r in &records {
        assert!(
            r.best.is_finite() && r.best > 0.0,
            "{}: {}",
            r.problem,
            r.best
        );
    }
    // A function with fewer unknowns per segment gets more segments: at
    // equal unknowns on a circle-like outline the cubic is not behind the
    // rational quadratic.
    let e = |p: &str| {
        records
            .iter()
            .find(|r| r.problem == p)
            .unwrap_or_else(|| panic!("{p}"))
            .best
    };
    assert!(e("coin/cubic/g1/params=30") < e("coin/rational-quadratic/g1/params=30"));
}

/// A campaign with every fitting key that came with the smooth closing:
/// per-segment problems with listed α_size and budgets (paired), and a
/// glyph's every contour closed smoothly.
const CURRENT_SPEC: &str = r#"
[experiment]
name = "fit_current"
seed = 11
runs = 3
paired = ["search_space", "alpha_size", "budget"]

[[fit]]
input = "coin.png"
function = "rational-cubic"
continuity = "g1"
segments = 4
search_space = ["technique", "bounding-box"]
alpha_size = [0.1, 0.5]
budget = [100, 300]
mode = "per-segment"
closing = "smooth"

[[fit]]
input = "font:DejaVuSans.ttf:o"
function = "cubic"
continuity = "g1"
segments = "true-breaks"
contour = "all"
closing = "smooth"
budget = 200

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs"
label = "MHS"
"#;

#[test]
fn a_campaign_with_the_current_fitting_records() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::copy(
        data().join("DejaVuSans.ttf"),
        tmp.path().join("DejaVuSans.ttf"),
    )
    .unwrap();
    let spec = spec_in(tmp.path(), CURRENT_SPEC);
    let names: Vec<String> = spec.problems.iter().map(|p| p.key()).collect();
    assert_eq!(
        names,
        [
            "coin/rational-cubic/g1/alpha=0.1/per-segment-4|budget=400",
            "coin/rational-cubic/g1/alpha=0.1/per-segment-4|budget=1200",
            "coin/rational-cubic/g1/per-segment-4|budget=400",
            "coin/rational-cubic/g1/per-segment-4|budget=1200",
            "coin/rational-cubic/g1/bounding-box/per-segment-4|budget=400",
            "coin/rational-cubic/g1/bounding-box/per-segment-4|budget=1200",
            "DejaVuSans-o/cubic/g1-16",
        ]
    );
    // Paired: the search spaces, α_size and budgets of a case share seeds.
    let seeds: Vec<String> = spec.problems[..6]
        .iter()
        .map(|p| p.seed_key(&spec.paired))
        .collect();
    assert!(
        seeds
            .iter()
            .all(|k| k == "coin/rational-cubic/g1/per-segment-4"),
        "{seeds:?}"
    );

    let one = tmp.path().join("one");
    let two = tmp.path().join("two");
    run(&spec, &one, 1, None);
    run(&spec, &two, 2, None);
    for f in ["runs.csv", "convergence.csv", "fits.csv", "segments.csv"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
            "{f} differs between 1 and 2 threads"
        );
    }
    has_the_fitting_records(&one);

    reports_the_segment_tables(&one);

    // An interrupted campaign resumes to the same files.
    let part = tmp.path().join("part");
    let opts = RunOptions {
        out: Some(part.clone()),
        threads: Some(2),
        max_runs: Some(10),
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    let opts = RunOptions {
        out: Some(part.clone()),
        threads: Some(2),
        resume: true,
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    for f in ["runs.csv", "convergence.csv", "fits.csv", "segments.csv"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(part.join(f)).unwrap(),
            "{f} differs after resuming"
        );
    }
}

/// The fitting records: fits.csv and segments.csv headers, both contours of the glyph, best-so-far traces ending at E, and the glyph closing smoothly.
fn has_the_fitting_records(one: &Path) {
    let fits = std::fs::read_to_string(one.join("fits.csv")).unwrap();
    assert!(fits.lines().next().unwrap().ends_with(
        "run,rms,max_distance,rms_distance,curve_distance,hausdorff,closing_angle_degrees,closing_relative_derivative_gap"
    ), "{fits}");
    let segments = std::fs::read_to_string(one.join("segments.csv")).unwrap();
    assert!(segments
        .lines()
        .next()
        .unwrap()
        .contains(",run,contour,segment,first,"));
    // The glyph's two contours (outer and counter) are both fitted.
    assert!(
        segments
            .lines()
            .any(|l| l.starts_with("HS,hs,") && l.contains("DejaVuSans-o") && l.contains(",1,0,")),
        "{segments}"
    );
    // Fitting runs record a best-so-far trace ending at their E.
    let records = metabezier::experiment::records::read_results(one).unwrap();
    for r in &records {
        let last = r.trace.last().expect("a trace");
        assert_eq!(last.evaluations, r.evaluations, "{}", r.problem);
        assert!(
            (last.best - r.best).abs() <= 1e-9 * r.best.max(1e-300),
            "{}",
            r.problem
        );
        assert!(
            r.trace.windows(2).all(|w| w[1].best <= w[0].best),
            "{}",
            r.problem
        );
        assert!(r.fit.as_ref().unwrap().rms_distance.is_some());
    }
    // The glyph closes smoothly where it has no corner, exactly enough.
    let o = records
        .iter()
        .find(|r| r.problem.starts_with("DejaVuSans-o"))
        .unwrap();
    assert!(o.fit.as_ref().unwrap().closing_angle_degrees.unwrap() < 1e-6);
}

/// The report of a fitting campaign has the segment-level tables and knows its factors.
fn reports_the_segment_tables(one: &Path) {
    // The report has the segment-level tables and knows the new factors.
    let summary =
        metabezier::report::write_report(one, &metabezier::report::ReportOptions::default())
            .unwrap();
    let md = std::fs::read_to_string(one.join("report.md")).unwrap();
    for needle in [
        "### Search space per segment: the technique against the bounding box",
        "### Methods per segment, in pairs",
        "HS against MHS (technique):",
        "MHS, α_size 0.1: the technique against the bounding box:",
        "![Convergence](plots/convergence.png)",
    ] {
        assert!(
            md.contains(needle),
            "report.md lacks {needle}; notes {:?}",
            summary.notes
        );
    }
    let robustness = std::fs::read_to_string(one.join("tables/robustness.csv")).unwrap();
    assert!(
        robustness.starts_with(
            "function,budget_per_segment,search_space,alpha_size,mode,algorithm,kind,params,\
             measure,better,same,worse,both_solved\n"
        ),
        "{robustness}"
    );
}
