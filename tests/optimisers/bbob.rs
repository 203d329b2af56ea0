//! COCO's bbob suite through its own C code: ids, boxes, optima and values
//! equal those of COCO's Python package (tests/data/bbob_reference.csv,
//! made by tools/bbob_reference.py with coco-experiment 2.8.2), and
//! COCO's evaluation counter equals ours.

use std::path::Path;

use metabezier::functions::BbobProblem;
use metabezier::problem::Problem;

/// `|a − b| ≤ 1e-12·max(1, |b|)`.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

#[test]
fn values_equal_cocos_python_package() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bbob_reference.csv");
    let mut reader = csv::Reader::from_path(&path).unwrap();
    let mut rows = 0;
    for row in reader.records() {
        let row = row.unwrap();
        let num = |i: usize| -> usize { row[i].parse().unwrap() };
        let real = |i: usize| -> f64 { row[i].parse().unwrap() };
        let (f, d, k) = (num(0), num(1), num(2));
        let p = BbobProblem::new(f, d, k).unwrap();
        assert_eq!(p.id(), &row[3]);
        assert_eq!(p.bounds()[0].lower, real(4));
        assert_eq!(p.bounds()[d - 1].upper, real(5));
        assert!(
            close(p.fopt(), real(6)),
            "{}: f* {} against COCO's f(x*) {}",
            &row[3],
            p.fopt(),
            real(6)
        );
        let x: Vec<f64> = row[8].split(' ').map(|v| v.parse().unwrap()).collect();
        let y = p.objective(&x);
        assert!(
            close(y, real(9)),
            "{} at point {}: {y} against {}",
            &row[3],
            &row[7],
            real(9)
        );
        assert_eq!(p.coco_evaluations(), 1);
        rows += 1;
    }
    assert_eq!(rows, 24 * 3 * 3 * 3);
}

const SPEC: &str = r#"[experiment]
name = "bbob_test"
seed = 4
runs = 2
budget_per_dim = 500

[[problem]]
suite = "bbob"
function = [1, "rastrigin-rotated"]
dim = [2, 5]
instances = [1, 7]

[[algorithm]]
name = "pso"

[[algorithm]]
name = "mhs"

[[algorithm]]
name = "cmaes"
restarts = "bipop"
"#;

fn spec_error(text: &str) -> String {
    match metabezier::experiment::Spec::parse(Path::new("spec.toml"), text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bbob_specs_are_checked_before_anything_runs() {
    assert_eq!(
        spec_error(&SPEC.replace("suite = \"bbob\"", "suite = \"bbob-noisy\"")),
        "spec.toml:8:9: problem[1].suite: unknown suite \"bbob-noisy\"; valid choices: \"bbob\""
    );
    let e = spec_error(&SPEC.replace("[1, \"rastrigin-rotated\"]", "[1, 25]"));
    assert!(
        e.starts_with("spec.toml:9:16: problem[1].function: unknown bbob function \"25\"; give an index 1 to 24 or a COCO name"),
        "{e}"
    );
    assert_eq!(
        spec_error(&SPEC.replace("dim = [2, 5]", "dim = [2, 4]")),
        "spec.toml:10:11: problem[1].dim: bbob is defined for the dimensions 2, 3, 5, 10, 20 and 40, not 4"
    );
    assert_eq!(
        spec_error(&SPEC.replace("instances = [1, 7]", "instances = 0")),
        "spec.toml:11:13: problem[1].instances: expected an integer in 1..=10000, found 0"
    );
}

#[test]
fn bbob_campaigns_are_identical_with_one_and_two_threads_and_use_cocos_optimum() {
    use metabezier::experiment::{run_campaign, RunOptions, Spec};
    let spec = Spec::parse(Path::new("spec.toml"), SPEC).unwrap();
    assert_eq!(spec.problems.len(), 8);
    assert_eq!(spec.problems[0].name(), "bbob_f001_i01_d02");
    assert_eq!(spec.problems[7].name(), "bbob_f015_i07_d05");
    let tmp = tempfile::tempdir().unwrap();
    let run = |threads: usize, out: &str| {
        let opts = RunOptions {
            out: Some(tmp.path().join(out)),
            threads: Some(threads),
            ..RunOptions::default()
        };
        run_campaign(&spec, &opts).unwrap();
    };
    run(1, "one");
    run(2, "two");
    for f in ["runs.csv", "convergence.csv", "hits.csv"] {
        assert_eq!(
            std::fs::read(tmp.path().join("one").join(f)).unwrap(),
            std::fs::read(tmp.path().join("two").join(f)).unwrap(),
            "{f}"
        );
    }
    let records = metabezier::experiment::records::read_results(&tmp.path().join("one")).unwrap();
    for r in &records {
        let p = BbobProblem::new(
            if r.problem.contains("f001") { 1 } else { 15 },
            r.dim,
            r.instance as usize,
        )
        .unwrap();
        assert_eq!(r.best - r.error, p.fopt(), "{}", r.problem);
        assert_eq!(r.evaluations, r.budget);
    }
}

#[test]
fn pso_reaches_cocos_final_target_on_f1_and_coco_counts_every_evaluation() {
    use metabezier::optim::Algorithm;
    use metabezier::rng::run_rng;
    let p = BbobProblem::new(1, 5, 2).unwrap();
    let pso = Algorithm::default_for("pso").unwrap();
    let out = pso.run(&p, 20_000, &mut run_rng(3));
    assert!(
        out.best_value - p.fopt() <= p.final_target_delta(),
        "{out:?}"
    );
    assert!(p.final_target_hit());
    assert_eq!(p.coco_evaluations(), out.evaluations);
}

#[test]
fn coco_logs_are_written_for_cocopp_and_refused_without_bbob_problems() {
    use metabezier::experiment::coco_log::write_coco_log;
    use metabezier::experiment::Spec;
    let spec = Spec::parse(
        Path::new("spec.toml"),
        &SPEC.replace("dim = [2, 5]", "dim = 2"),
    )
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("coco");
    let folders = write_coco_log(&spec, None, &dir).unwrap();
    // One folder per algorithm cell: PSO, MHS and CMA-ES.
    assert_eq!(folders.len(), 3);
    for folder in &folders {
        let names: Vec<String> = std::fs::read_dir(folder)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert!(names.iter().any(|n| n.ends_with(".info")), "{names:?}");
    }
    let plain = Spec::parse(
        Path::new("plain.toml"),
        "[experiment]\nname = \"p\"\nseed = 1\nruns = 1\nbudget = 10\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n[[algorithm]]\nname = \"hs\"\n",
    )
    .unwrap();
    let e = write_coco_log(&plain, None, &dir).unwrap_err().to_string();
    assert!(e.contains("plain.toml has no bbob problems"), "{e}");
}

#[test]
fn bbob_reports_show_cocos_best_2009_beside_the_algorithms() {
    use metabezier::experiment::{run_campaign, RunOptions, Spec};
    use metabezier::report::{write_report, ReportOptions};
    let spec = Spec::parse(Path::new("spec.toml"), SPEC).unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("bbob");
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    write_report(&out, &ReportOptions::default()).unwrap();
    let read = |name: &str| -> Vec<Vec<String>> {
        let mut r = csv::Reader::from_path(out.join("tables").join(name)).unwrap();
        r.records()
            .map(|x| x.unwrap().iter().map(str::to_owned).collect())
            .collect()
    };
    // cocopp 2.9.1's bbob-bestalg_f01_d02.dat: aRT 6 to 1e-8 on the sphere
    // at D = 2 (NEWUOA), and 1 to Δf = 100.
    let art = read("art_targets.csv");
    let best = |function: &str, target: &str| {
        art.iter()
            .find(|r| r[0] == function && r[3] == "best 2009" && r[6] == target)
            .unwrap_or_else(|| panic!("no best 2009 row for {function} at {target}"))
            .clone()
    };
    let row = best("bbob_f001_d02", "1e-8");
    assert_eq!((row[4].as_str(), row[9].as_str()), ("reference", "6"));
    assert_eq!(best("bbob_f001_d02", "100")[9], "1");
    // best 2009–16 is a second reference row: never slower than best 2009
    // where both reach the target (its data sets include 2009's).
    for r in art.iter().filter(|r| r[3] == "best 2009–16") {
        assert_eq!(r[4], "reference");
        assert_eq!(r[5], "cocopp 2.9.1 refalgs/best09-16-bbob.tar.gz");
        let old = best(&r[0], &r[6]);
        if let (Ok(new), Ok(old)) = (r[9].parse::<f64>(), old[9].parse::<f64>()) {
            assert!(new <= old * 1.01, "{r:?} against {old:?}");
        }
    }
    assert!(art.iter().any(|r| r[3] == "best 2009–16"));
    // Targets reached: best 2009 over 2 functions × 51 targets per D, an
    // algorithm over its (run, target) pairs, 2 functions × 2 instances × 2
    // runs × 51; the runs' budget of 500·D leaves 10³·D and 10⁴·D out for
    // the algorithms, not for best 2009.
    let reached = read("targets_reached.csv");
    for d in ["2", "5"] {
        let rows: Vec<&Vec<String>> = reached.iter().filter(|r| r[0] == d).collect();
        let per_dim = |label: &str| -> Vec<&str> {
            rows.iter()
                .filter(|r| r[1] == label)
                .map(|r| r[4].as_str())
                .collect()
        };
        assert_eq!(per_dim("pso"), ["100"], "D = {d}");
        assert_eq!(per_dim("best 2009"), ["100", "1000", "10000"], "D = {d}");
        assert_eq!(per_dim("best 2009–16"), ["100", "1000", "10000"], "D = {d}");
        for r in &rows {
            let pairs = if r[2] == "reference" { "102" } else { "408" };
            assert_eq!(r[5], pairs, "{r:?}");
            let (hit, pairs): (f64, f64) = (r[6].parse().unwrap(), r[5].parse().unwrap());
            assert_eq!(r[7].parse::<f64>().unwrap(), hit / pairs, "{r:?}");
        }
    }
    let md = std::fs::read_to_string(out.join("report.md")).unwrap();
    assert!(md.contains("### Targets reached at 10²·D, 10³·D and 10⁴·D evaluations"));
    assert!(md.contains("best 2009 is COCO's virtual best"));
    assert!(md.contains("best 2009–16 is COCO's virtual best of the data sets"));
}

/// IPOP-aCMA-ES at its defaults reaches `f − f* ≤ 10⁻⁸` on bbob f10
/// (rotated ellipsoid, condition 10⁶) and f8 (Rosenbrock) at D = 10, on
/// instances 1, 2 and 3, one run each (seed = instance), within 10⁴·D
/// evaluations; pycma's medians are 4,135 and 5,351
/// (tests/optimisers/cmaes_parity.rs). Every one of these runs gets there in its first
/// run (λ = 10), in 4,372 to 5,401 evaluations (5,190 to 7,665 with the
/// positive-only update and the tutorial's schedule before issue 51). Those
/// runtimes are COCO's, exact to the evaluation, and pinned, so that any
/// change of the algorithm, its arithmetic or its random stream shows here.
#[test]
fn ipop_cmaes_reaches_1e_8_on_bbob_f10_and_f8_in_10_d() {
    use metabezier::optim::{CmaEs, Evaluator};
    use metabezier::rng::run_rng;
    let algo = CmaEs::default();
    // (function, instance, evaluations to 1e-8, the run that got there).
    let pinned = [
        (10, 1, 4547, 1),
        (10, 2, 4372, 1),
        (10, 3, 4414, 1),
        (8, 1, 4460, 1),
        (8, 2, 5083, 1),
        (8, 3, 5401, 1),
    ];
    let mut found = Vec::new();
    for (f, instance, _, _) in pinned {
        let p = BbobProblem::new(f, 10, instance).unwrap();
        let mut eval = Evaluator::new(&p, 100_000).with_targets(p.fopt(), vec![1e-8]);
        let runs = algo.minimise_recorded(&mut eval, &mut run_rng(instance as u64));
        let out = eval.finish();
        assert_eq!(out.evaluations, 100_000);
        assert_eq!(p.coco_evaluations(), 100_000);
        assert!(
            out.best_value - p.fopt() <= 1e-8,
            "f{f} instance {instance}: best f − f* = {:e}; runs {runs:?}",
            out.best_value - p.fopt()
        );
        let hit = out.hits.first().map_or(0, |h| h.evaluations);
        assert!(hit > 0 && hit <= 100_000);
        let mut used = 0;
        let run = 1 + runs
            .iter()
            .take_while(|r| {
                used += r.evaluations;
                used < hit
            })
            .count();
        found.push((f, instance, hit, run));
    }
    assert_eq!(found, pinned);
}
