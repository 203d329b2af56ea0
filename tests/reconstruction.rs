//! Curve reconstruction on the vendored real outlines, end to end: the
//! library path, `metabezier fit`, and fitting campaigns declared in specs.

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::experiment::Spec;
use metabezier::experiment::{merge, run_campaign, RunOptions, Shard};
use metabezier::fit::{FitOptions, FunctionType};
use metabezier::geometry::{Continuity, Parameterisation};
use metabezier::optim::Algorithm;
use metabezier::outline::CornerOptions;
use metabezier::reconstruction::{
    ContourChoice, LoadOptions, Method, Reconstruction, Segmentation, Source,
};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines")
}

fn source(input: &str) -> Source {
    let options = LoadOptions {
        contour: ContourChoice::Index(0),
        ..LoadOptions::default()
    };
    Source::load(input, &data(), &options).unwrap()
}

fn metabezier() -> Command {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
}

#[test]
fn cantarell_g_is_recovered_from_its_true_break_points() {
    let g = source("font:Cantarell-Regular.otf:g");
    let height = g.glyph_height.unwrap();
    assert!(height > 500.0, "glyph height {height} font units");
    let segmentation = g.true_segmentation().unwrap();
    let fit = |parameterisation, reparameterise| {
        let mut options = FitOptions::new(FunctionType::Cubic, Continuity::G1);
        options.parameterisation = parameterisation;
        options.reparameterise = reparameterise;
        Reconstruction {
            source: &g,
            segmentation: segmentation.clone(),
            corners: None,
            options,
        }
        .fit(&Method::Exact, 0)
        .unwrap()
    };
    // The samples sit at uniform t on each exact cubic: uniform parameters
    // recover the font's curves to rounding.
    let exact = fit(Parameterisation::Uniform, 0);
    assert!(
        exact.metrics.max_distance < 1e-9 * height,
        "{:?}",
        exact.metrics
    );
    assert!(exact.joins_hold(1e-9));
    // From chord-length parameters, as for data whose parameters are
    // unknown, five Newton corrections reach well under 0.5 % of the height.
    let chord = fit(Parameterisation::ChordLength, 5);
    assert!(
        chord.metrics.max_distance < 0.005 * height,
        "max distance {} against height {height}",
        chord.metrics.max_distance
    );
    assert!(chord.joins_hold(1e-9));
    // Without correction the chord-length parameters cost accuracy: this is
    // what the correction buys (and why the test asks for it).
    let plain = fit(Parameterisation::ChordLength, 0);
    assert!(plain.metrics.max_distance > 2.0 * chord.metrics.max_distance);
}

#[test]
fn a_metaheuristic_fit_of_the_horse_keeps_every_joint() {
    let horse = source("horse.png");
    // The RMS bound: a few pixels, except for quadratics joined C1, where
    // every segment after a corner is fully determined by its predecessor
    // (no free variable) and the error accumulates along each chain.
    for (function, continuity, rms_max) in [
        (FunctionType::RationalCubic, Continuity::G1, 5.0),
        (FunctionType::RationalCubic, Continuity::C1, 5.0),
        (FunctionType::Cubic, Continuity::C1, 5.0),
        (FunctionType::RationalQuadratic, Continuity::G1, 5.0),
        (FunctionType::Quadratic, Continuity::C1, 20.0),
    ] {
        let mut options = FitOptions::new(function, continuity);
        options.budget_per_segment = 1000;
        let r = Reconstruction {
            source: &horse,
            segmentation: Segmentation::Count(30),
            corners: Some(CornerOptions::default()),
            options,
        };
        let mhs = Method::Metaheuristic(Algorithm::default_for("mhs").unwrap());
        let shape = r.fit(&mhs, 42).unwrap();
        let fit = &shape.contours[0].fit;
        assert_eq!(fit.segments.len(), 30);
        assert!(fit.joins_hold(1e-9), "{function:?} {continuity:?}");
        // The corners found on the outline are C0 joints, the others smooth.
        let corners = r.corner_indices(&horse.contours[0]);
        for s in &fit.segments[1..] {
            let expected = if corners.contains(&s.first) {
                Continuity::C0
            } else {
                continuity
            };
            assert_eq!(s.join, expected);
        }
        assert!(fit.metrics.rms < rms_max, "{function:?}: {:?}", fit.metrics);
    }
}

/// `metabezier fit` of the coin with PSO, 6 segments, seed 3, into `out`.
fn fit_coin(out: &Path) -> std::process::Output {
    fit_coin_with(out, &[])
}

fn fit_coin_with(out: &Path, extra: &[&str]) -> std::process::Output {
    metabezier()
        .args([
            "fit",
            data().join("coin.png").to_str().unwrap(),
            "--algorithm",
            "pso",
            "--segments",
            "6",
            "--budget",
            "2000",
            "--seed",
            "3",
            "--out",
        ])
        .arg(out)
        .args(extra)
        .output()
        .unwrap()
}

#[test]
fn fit_writes_its_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = fit_coin(tmp.path());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.starts_with("coin: "), "{stdout}");
    assert!(stdout.contains("6 segments"), "{stdout}");
    let fit_csv = std::fs::read_to_string(tmp.path().join("fit.csv")).unwrap();
    let mut lines = fit_csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("contour,segment,first,last,points,join,function,c0x,c0y"));
    assert_eq!(lines.count(), 6);
    let metrics = std::fs::read_to_string(tmp.path().join("metrics.csv")).unwrap();
    assert!(
        metrics.starts_with("input,function,continuity,closing,algorithm,seed"),
        "{metrics}"
    );
    assert!(
        metrics.contains(",rational-cubic,g1,smooth,pso,3,2000,"),
        "{metrics}"
    );
    // One row per contour, then the totals.
    let rows: Vec<&str> = metrics.lines().collect();
    assert_eq!(rows.len(), 3, "{metrics}");
    assert!(rows[1].contains(",0,counter-clockwise,"), "{metrics}");
    assert!(rows[2].contains(",all,,"), "{metrics}");
    let svg = std::fs::read_to_string(tmp.path().join("fit.svg")).unwrap();
    assert!(svg.contains("coin: rational-cubic G1, pso"));
    assert!(svg.contains("fill-rule=\"evenodd\""));
    // Rational cubics reach SVG as polynomial cubics, and the file says so.
    let pieces = svg.matches(" C ").count();
    assert!(
        svg.contains(&format!(
            "SVG has no rational curves: the 6 rational segment(s) of this fit are drawn as {pieces} polynomial cubic pieces"
        )),
        "{svg}"
    );
    // The rasters, the DXF and the overlay only on request (`--outputs`).
    for absent in ["fit.png", "fit.dxf", "overlay.svg", "overlay.png"] {
        assert!(!tmp.path().join(absent).exists(), "{absent}");
    }
    let rasters = tmp.path().join("rasters");
    let out = fit_coin_with(&rasters, &["--outputs", "png,overlay,dxf"]);
    assert!(out.status.success());
    assert!(rasters.join("overlay.png").exists() && rasters.join("fit.dxf").exists());
    assert!(!rasters.join("fit.csv").exists() && !rasters.join("fit.svg").exists());
    assert_eq!(
        &std::fs::read(rasters.join("fit.png")).unwrap()[1..4],
        b"PNG"
    );

    // The same seed gives the same fit.csv.
    let again = tmp.path().join("again");
    let out = fit_coin(&again);
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(again.join("fit.csv")).unwrap(),
        fit_csv.as_bytes()
    );
}

fn fit_error(args: &[&str]) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let out = metabezier()
        .current_dir(data())
        .arg("fit")
        .args(args)
        .arg("--out")
        .arg(tmp.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{args:?} should fail");
    assert!(
        std::fs::read_dir(tmp.path()).unwrap().next().is_none(),
        "{args:?} wrote files"
    );
    String::from_utf8(out.stderr).unwrap()
}

#[test]
fn bad_fit_input_gets_a_specific_error() {
    assert_eq!(
        fit_error(&["horse.png", "--tolerance", "0"]),
        "metabezier: error: --tolerance: expected a finite distance > 0 (data units), found 0\n"
    );
    let e = fit_error(&["font:Cantarell-Regular.otf:漢"]);
    assert!(
        e.contains("Cantarell-Regular.otf") && e.contains("no glyph for '漢'"),
        "{e}"
    );
    let e = fit_error(&["horse.png", "--algorithm", "hz"]);
    assert!(
        e.contains("unknown algorithm \"hz\"; valid choices: hs, ghs, ga, pso, mhs, cmaes, lshade, random, lm, hs+lm"),
        "{e}"
    );
    // Fewer segments than the corners make are raised to them, with a
    // note (a campaign refuses them: see bad_fitting_specs_get_specific_errors).
    let tmp = tempfile::tempdir().unwrap();
    let out = metabezier()
        .current_dir(data())
        .args(["fit", "horse.png", "--segments", "5", "--out"])
        .arg(tmp.path())
        .output()
        .unwrap();
    assert!(out.status.success());
    let note = String::from_utf8(out.stderr).unwrap();
    assert!(
        note.starts_with(
            "metabezier: note: contour 0: 5 segment(s) asked for, but its corners make"
        ),
        "{note}"
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    let made: usize = note
        .split("; fitted ")
        .nth(1)
        .unwrap()
        .split(' ')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!(
        made > 5 && stdout.contains(&format!("{made} segments")),
        "{stdout}"
    );
    let e = fit_error(&["horse.png", "--contour", "3"]);
    assert_eq!(
        e,
        "metabezier: error: horse.png: contour 3 was asked for, but the input has 1 contour \
         (numbered from 0 by decreasing area: 0..=0); to fit them all, leave --contour out \
         (or write contour = \"all\" in a spec)\n"
    );
    let e = fit_error(&["font:DejaVuSans.ttf:B", "--contour", "7"]);
    assert!(
        e.contains("contour 7 was asked for, but the input has 3 contours"),
        "{e}"
    );
    let e = fit_error(&["horse.png", "--true-breaks"]);
    assert!(e.contains("horse.png is not a glyph"), "{e}");
    let e = fit_error(&["missing.png"]);
    assert!(e.contains("missing.png"), "{e}");
}

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

fn spec_error(text: &str) -> String {
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
    let records = metabezier::experiment::records::read_results(&one).unwrap();
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

    // The report has the segment-level tables and knows the new factors.
    let summary =
        metabezier::report::write_report(&one, &metabezier::report::ReportOptions::default())
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

/// Runs `metabezier` with `args` in the data directory; (status, stdout,
/// stderr).
fn cli(args: &[&str]) -> (bool, String, String) {
    let out = metabezier()
        .current_dir(data())
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// The `all` row of a `metrics.csv`, as column name → value.
fn all_row(dir: &Path) -> std::collections::HashMap<String, String> {
    let text = std::fs::read_to_string(dir.join("metrics.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let all: Vec<&str> = lines.last().unwrap().split(',').collect();
    header
        .iter()
        .zip(all)
        .map(|(h, v)| (h.to_string(), v.to_string()))
        .collect()
}

#[test]
fn glyphs_keep_every_contour_and_are_recovered_at_their_own_breaks() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    // B: the outer contour and two counters, holes clockwise.
    let (ok, stdout, err) = cli(&[
        "fit",
        "font:DejaVuSans.ttf:B",
        "--true-breaks",
        "--algorithm",
        "lm",
        "--out",
        out,
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("3 contour(s)"), "{stdout}");
    let metrics = std::fs::read_to_string(tmp.path().join("metrics.csv")).unwrap();
    assert_eq!(metrics.lines().count(), 1 + 3 + 1, "{metrics}");
    assert_eq!(
        metrics.matches(",counter-clockwise,").count(),
        1,
        "{metrics}"
    );
    assert_eq!(metrics.matches(",clockwise,").count(), 2, "{metrics}");
    let fit_csv = std::fs::read_to_string(tmp.path().join("fit.csv")).unwrap();
    for contour in ["0", "1", "2"] {
        assert!(fit_csv
            .lines()
            .any(|l| l.starts_with(&format!("{contour},"))));
    }
    // Quadratic TrueType glyphs at their own breaks, with the default
    // parameterisation (auto: the samples' own, uniform, parameters) and G1:
    // recovered to 1e-6 font units. The 'a' has a segment too short for a
    // rational cubic at the default sampling; it gets more samples of the
    // exact outline instead of stopping the fit.
    for (glyph, function) in [
        ("S", "quadratic"),
        ("o", "quadratic"),
        ("8", "cubic"),
        ("a", "rational-cubic"),
    ] {
        let input = format!("font:DejaVuSans.ttf:{glyph}");
        let (ok, _, err) = cli(&[
            "fit",
            &input,
            "--true-breaks",
            "--algorithm",
            "lm",
            "--function",
            function,
            "--out",
            out,
        ]);
        assert!(ok, "{glyph}: {err}");
        let all = all_row(tmp.path());
        assert_eq!(all["parameterisation"], "uniform");
        let max: f64 = all["max_distance"].parse().unwrap();
        assert!(max < 1e-6, "{glyph} {function}: {max}");
    }
    // With the thesis's fixed-parameter E, chord-length parameters miss the
    // same glyph by font units; the orthogonal E (the command line's
    // default) solves for the parameters and recovers it from the same start.
    for (error, bound) in [("fixed", None), ("orthogonal", Some(1e-6))] {
        let (ok, _, _) = cli(&[
            "fit",
            "font:DejaVuSans.ttf:S",
            "--true-breaks",
            "--algorithm",
            "lm",
            "--function",
            "quadratic",
            "--parameterisation",
            "chord",
            "--error",
            error,
            "--out",
            out,
        ]);
        assert!(ok);
        let all = all_row(tmp.path());
        assert_eq!(all["error"], error);
        let max: f64 = all["max_distance"].parse().unwrap();
        match bound {
            None => assert!(max > 1.0, "{max}"),
            Some(b) => assert!(max < b, "{max}"),
        }
    }
}

/// A closed square of side 10 with `n` points per side, as a CSV file.
fn square_csv(dir: &Path, n: usize) -> std::path::PathBuf {
    let mut text = String::from("x,y\n");
    let corners = [(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)];
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        for j in 0..n {
            let t = j as f64 / n as f64;
            text.push_str(&format!(
                "{},{}\n",
                a.0 + t * (b.0 - a.0),
                a.1 + t * (b.1 - a.1)
            ));
        }
    }
    text.push_str("0,0\n");
    let path = dir.join("square.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn score_measures_other_curves_against_the_same_points() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 20);
    // The square moved one unit right, in SVG's y-down user space (the
    // viewBox spans y 0..20, so y_up = 20 − y).
    let svg = tmp.path().join("shifted.svg");
    std::fs::write(
        &svg,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 20 20\">\n\
         <path d=\"M 1 20 H 11 V 10 H 1 Z\"/>\n</svg>\n",
    )
    .unwrap();
    let sq = square.to_str().unwrap();
    let (ok, stdout, err) = cli(&[
        "score",
        sq,
        svg.to_str().unwrap(),
        "--out",
        tmp.path().to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("4 segments"), "{stdout}");
    let csv = std::fs::read_to_string(tmp.path().join("score.csv")).unwrap();
    let all: Vec<&str> = csv.lines().last().unwrap().split(',').collect();
    assert_eq!(all[4], "all");
    assert_eq!(all[7].parse::<f64>().unwrap(), 1.0, "{csv}");
    // The offset moves it back: every point on the curves.
    let (ok, stdout, _) = cli(&["score", sq, svg.to_str().unwrap(), "--offset", "-1,0"]);
    assert!(ok);
    let all: Vec<&str> = stdout.lines().last().unwrap().split_whitespace().collect();
    assert_eq!(all[..2], ["all", "80"], "{stdout}");
    assert!(all[2].parse::<f64>().unwrap() < 1e-12, "{stdout}");

    // potrace's trace of the horse (vendored): 101 segments, pixel corners
    // at integers, hence the offset.
    let (ok, stdout, err) = cli(&[
        "score",
        "horse.png",
        "horse-potrace.svg",
        "--offset",
        "-0.5,-0.5",
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("101 segments"), "{stdout}");
    let all = stdout
        .lines()
        .last()
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>();
    let (max, rms): (f64, f64) = (all[2].parse().unwrap(), all[3].parse().unwrap());
    assert!(
        (max - 1.940).abs() < 1e-3 && (rms - 0.331).abs() < 1e-3,
        "{stdout}"
    );

    // Our own fit.svg reads back in the outline frame with no offset.
    let out = tmp.path().join("fit");
    let (ok, _, err) = cli(&[
        "fit",
        "horse.png",
        "--algorithm",
        "lm",
        "--segments",
        "101",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let fit_max: f64 = all_row(&out)["max_distance"].parse().unwrap();
    let (ok, stdout, _) = cli(&["score", "horse.png", out.join("fit.svg").to_str().unwrap()]);
    assert!(ok);
    let all = stdout
        .lines()
        .last()
        .unwrap()
        .split_whitespace()
        .collect::<Vec<_>>();
    let scored: f64 = all[2].parse().unwrap();
    assert!(
        scored <= fit_max + 1e-3 && scored > fit_max - 0.05,
        "{scored} vs {fit_max}"
    );
}

#[test]
fn bad_curves_and_contours_are_named_with_their_place() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 5);
    let sq = square.to_str().unwrap();
    let write = |name: &str, text: &str| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let cases = [
        (
            "none.svg",
            "<svg>\n<rect width=\"1\" height=\"1\"/>\n</svg>\n",
            "none.svg: no <path> element with a \"d\" attribute",
        ),
        (
            "arc.svg",
            "<svg>\n<path d=\"M 0 0 A 5 5 0 0 1 10 0\"/>\n</svg>\n",
            "arc.svg:2:16: unsupported path command 'A'",
        ),
        (
            "nan.svg",
            "<svg>\n<path d=\"M 0 0 L NaN 3\"/>\n</svg>\n",
            "nan.svg:2:18: expected a number, found \"NaN\"",
        ),
    ];
    for (name, text, expected) in cases {
        let path = write(name, text);
        let (ok, _, err) = cli(&["score", sq, &path]);
        assert!(!ok);
        assert!(
            err.starts_with("metabezier: error: ") && err.contains(expected),
            "{err}"
        );
    }
    let path = write("ok.svg", "<svg><path d=\"M0 0 L 1 1\"/></svg>");
    let (ok, _, err) = cli(&["score", sq, &path, "--contour", "2"]);
    assert!(!ok);
    assert!(
        err.contains("square.csv: contour 2 was asked for, but the input has 1 contour"),
        "{err}"
    );
    let (ok, _, err) = cli(&["score", sq, &path, "--offset", "a,b"]);
    assert!(!ok);
    assert!(
        err.contains("expected an offset DX,DY of two finite numbers"),
        "{err}"
    );
}

/// `score` used to panic (exit 101) on a transform "a)b(", print `inf`
/// distances with exit 0 for an SVG that draws nothing or has 1e308
/// coordinates, and score paths inside `<defs>`.
#[test]
fn score_refuses_what_it_cannot_measure_and_skips_what_is_not_drawn() {
    let tmp = tempfile::tempdir().unwrap();
    let square = square_csv(tmp.path(), 5);
    let sq = square.to_str().unwrap();
    let write = |name: &str, text: &str| {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        p.to_str().unwrap().to_owned()
    };
    let cases = [
        (
            "paren.svg",
            "<svg>\n<g transform=\"a)b(\"><path d=\"M0 0 L 1 1\"/></g>\n</svg>\n",
            "paren.svg:2:15: unsupported transform \"a)b(\"",
        ),
        (
            "empty.svg",
            "<svg>\n<path d=\"M 3 3\"/>\n</svg>\n",
            "empty.svg: no drawable segment: 1 rendered <path> element(s) draw no line or curve",
        ),
        (
            "huge.svg",
            "<svg>\n<path d=\"M 0 0 L 1e308 1e308\"/>\n</svg>\n",
            "huge.svg:2:16: a coordinate (after the transforms) 1e308 is beyond ±1e15",
        ),
        (
            "defs.svg",
            "<svg>\n<defs><path d=\"M 0 0 L 10 10\"/></defs>\n</svg>\n",
            "defs.svg: no drawable segment: 0 rendered <path> element(s) draw no line or curve, and 1 <path> element(s) inside non-rendered containers",
        ),
    ];
    for (name, text, expected) in cases {
        let path = write(name, text);
        let out = metabezier()
            .current_dir(data())
            .args(["score", sq, &path])
            .output()
            .unwrap();
        let (stdout, err) = (
            String::from_utf8(out.stdout).unwrap(),
            String::from_utf8(out.stderr).unwrap(),
        );
        assert_eq!(out.status.code(), Some(1), "{name}: {stdout}{err}");
        assert!(
            !stdout.contains("inf") && !stdout.contains("NaN"),
            "{stdout}"
        );
        assert!(
            err.starts_with("metabezier: error: ") && err.contains(expected),
            "{name}: {err}"
        );
    }
    // An offset that moves the curves out of range is refused by score.
    let ok_svg = write("ok.svg", "<svg><path d=\"M0 0 L 10 0\"/></svg>");
    let (ok, stdout, err) = cli(&["score", sq, &ok_svg, "--offset", "1e300,0"]);
    assert!(!ok, "{stdout}");
    assert!(
        err.contains("ok.svg: segment 0 of subpath 0 has the control point (1e300, 0e0)"),
        "{err}"
    );
    // A path in <defs> is skipped and the rest is scored as if it were not there.
    let with_defs = write(
        "with_defs.svg",
        "<svg viewBox=\"0 0 10 10\"><defs><path d=\"M 0 10 L 5 5\"/></defs>\n\
         <path d=\"M 0 10 H 10 V 0 H 0 Z\"/></svg>",
    );
    let (ok, stdout, err) = cli(&["score", sq, &with_defs]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains(": 4 segments (1 path(s) in non-rendered containers skipped)"),
        "{stdout}"
    );
    let all: Vec<&str> = stdout.lines().last().unwrap().split_whitespace().collect();
    assert_eq!(all[..2], ["all", "20"], "{stdout}");
    assert!(all[2].parse::<f64>().unwrap() < 1e-12, "{stdout}");
}

/// The library's `score` refuses an empty set of curves (every distance
/// would be infinite) and coordinates beyond its range.
#[test]
fn score_never_returns_an_infinite_distance() {
    use metabezier::geometry::Point;
    use metabezier::outline::{Outline, Segment};
    use metabezier::reconstruction::{score, ScoreError};
    let pts = vec![Point::ZERO, Point::new(1.0, 0.0), Point::new(0.0, 1.0)];
    let source = Source::from_outline("tri", Outline::new(pts, true));
    assert_eq!(score(&source, &[]), Err(ScoreError::NoSegment));
    assert_eq!(score(&source, &[vec![]]), Err(ScoreError::NoSegment));
    let line = |a: Point, b: Point| vec![vec![Segment::Line(a, b)]];
    let e = score(&source, &line(Point::ZERO, Point::new(f64::NAN, 0.0))).unwrap_err();
    assert!(
        matches!(
            e,
            ScoreError::CurveRange {
                subpath: 0,
                segment: 0,
                ..
            }
        ),
        "{e}"
    );
    let far = Source::from_outline(
        "far",
        Outline::new(vec![Point::new(1e300, 0.0), Point::ZERO], false),
    );
    let e = score(&far, &line(Point::ZERO, Point::new(1.0, 0.0))).unwrap_err();
    assert_eq!(
        e.to_string(),
        "data point 0 of contour 0 is (1e300, 0e0), beyond ±1e16, the range of coordinates scored"
    );
    let s = score(&source, &line(Point::ZERO, Point::new(1.0, 0.0))).unwrap();
    assert!(s.total.max_distance.is_finite() && s.total.rms_distance.is_finite());
}

/// `fit --segments 1000000` on 40 points used to fit 39 segments without a
/// word; the same rule holds for the library (and so for campaigns).
#[test]
fn more_segments_than_the_outline_allows_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let mut text = String::new();
    for i in 0..40 {
        let t = i as f64 * std::f64::consts::TAU / 40.0;
        text.push_str(&format!("{},{}\n", 10.0 * t.cos(), 10.0 * t.sin()));
    }
    let open = tmp.path().join("open40.csv");
    std::fs::write(&open, &text).unwrap();
    let e = fit_error(&[open.to_str().unwrap(), "--segments", "1000000"]);
    assert_eq!(
        e,
        format!(
            "metabezier: error: {}: contour 0: 1000000 segment(s) requested, but an open outline of 40 points allows at most 39 (each segment spans at least one gap between consecutive points); ask for at most 39\n",
            open.display()
        )
    );
    // Closed (the first point repeated at the end): 40 gaps, so 40 segments.
    text.push_str("10,0\n");
    let closed = tmp.path().join("closed40.csv");
    std::fs::write(&closed, &text).unwrap();
    let e = fit_error(&[closed.to_str().unwrap(), "--segments", "41"]);
    assert!(
        e.contains("a closed outline of 40 points allows at most 40"),
        "{e}"
    );
    let source = Source::load(
        closed.to_str().unwrap(),
        Path::new(""),
        &LoadOptions::default(),
    )
    .unwrap();
    let r = Reconstruction {
        source: &source,
        segmentation: Segmentation::Count(usize::MAX),
        corners: Some(CornerOptions::default()),
        options: FitOptions::new(FunctionType::Cubic, Continuity::G1),
    };
    let e = r.fit(&Method::Exact, 1).unwrap_err();
    assert!(e.to_string().contains("allows at most 40"), "{e}");
    let r = Reconstruction {
        segmentation: Segmentation::Count(40),
        ..r
    };
    let fit = r.fit(&Method::Exact, 1).unwrap();
    assert_eq!(fit.segments().count(), 40);
}

/// A campaign's fit problems share the rule: a spec asking for more
/// segments than the outline has gaps is refused at the `segments` field
/// when it is checked (before, its cells silently fitted fewer).
#[test]
fn a_spec_asking_for_more_segments_than_the_outline_allows_is_refused() {
    let head = "[experiment]\nname = \"x\"\nseed = 1\nruns = 1\nbudget = 100\n\n";
    let e = spec_error(&format!(
        "{head}[[fit]]\ninput = \"coin.png\"\nsegments = 1000\n\n[[algorithm]]\nname = \"hs\"\n"
    ));
    let points = source("coin.png").contours[0].outline.len();
    assert_eq!(
        e,
        format!(
            "9:12: fit[1].segments: coin/rational-cubic/g1: contour 0: 1000 segment(s) requested, but a closed outline of {points} points allows at most {points} (each segment spans at least one gap between consecutive points); ask for at most {points}"
        )
    );
}

#[test]
fn the_command_line_default_fits_the_horse_within_a_pixel() {
    // `metabezier fit` defaults to LM with the orthogonal error and the joint
    // chain: the horse at 101 rational cubics, G1, within 1 px everywhere and
    // 0.30 px RMS (potrace at 101 segments: 1.94 and 0.331 px; the thesis's
    // fixed-parameter E with the sequential chain: 1.33 and 0.316 px).
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().to_str().unwrap();
    let run = |extra: &[&str]| {
        let mut args = vec!["fit", "horse.png", "--segments", "101", "--out", out];
        args.extend_from_slice(extra);
        let (ok, _, err) = cli(&args);
        assert!(ok, "{err}");
        all_row(tmp.path())
    };
    let all = run(&[]);
    assert_eq!(
        (
            all["algorithm"].as_str(),
            all["error"].as_str(),
            all["chain"].as_str()
        ),
        ("lm", "orthogonal", "joint")
    );
    let max: f64 = all["max_distance"].parse().unwrap();
    let rms: f64 = all["rms_distance"].parse().unwrap();
    assert!(max <= 1.0 && rms <= 0.30, "max {max}, RMS {rms}");
    let e =
        |row: &std::collections::HashMap<String, String>| -> f64 { row["sse"].parse().unwrap() };
    let sequential = run(&["--chain", "sequential"]);
    assert!(
        e(&all) < 0.99 * e(&sequential),
        "{} vs {}",
        e(&all),
        e(&sequential)
    );
    let fixed = run(&["--error", "fixed", "--chain", "sequential"]);
    let fixed_max: f64 = fixed["max_distance"].parse().unwrap();
    assert!(fixed_max > 1.2, "{fixed_max}");
    // The joint chain lowers the thesis's E too, by a third.
    let fixed_joint = run(&["--error", "fixed"]);
    assert!(
        e(&fixed_joint) < 0.7 * e(&fixed),
        "{} vs {}",
        e(&fixed_joint),
        e(&fixed)
    );
}
