//! The open runner: optimisers and problems defined outside the crate run
//! through the same spec, runner, result files and report as the built-ins
//! (the two examples, included here as modules), with the same bits on 1 and
//! 2 threads; and what a registration or a spec naming it gets wrong is a
//! clear error, never a panic in a worker thread.

use std::path::Path;

use metabezier::experiment::{ProblemDef, Registry, Spec, SpecLimits};
use metabezier::optim::{
    hs, Algorithm, HarmonySearch, OptimiserDef, ParamError, ParamSet, RandomSearch,
};
use metabezier::problem::{Bounds, Problem};

#[allow(dead_code)]
#[path = "../../examples/custom_optimiser.rs"]
mod custom_optimiser;
#[allow(dead_code)]
#[path = "../../examples/custom_problem.rs"]
mod custom_problem;
#[allow(dead_code)]
#[path = "../../examples/shekel_suite.rs"]
mod shekel_suite;

/// An example's campaign: into a directory, with a number of threads.
type Campaign =
    fn(&Path, Option<usize>) -> Result<metabezier::experiment::Summary, Box<dyn std::error::Error>>;

/// `runs.csv` and `report.md` of an example's campaign with 1 and with 2
/// threads, byte for byte equal, with the example's own names in both.
fn same_on_one_and_two_threads(campaign: Campaign, expect_runs: usize, names: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    let s1 = campaign(&one, Some(1)).unwrap();
    let s2 = campaign(&two, Some(2)).unwrap();
    assert_eq!((s1.total, s1.executed), (expect_runs, expect_runs));
    assert!(s1.complete && s2.complete);
    for file in ["runs.csv", "convergence.csv", "hits.csv"] {
        let a = std::fs::read(one.join(file)).unwrap();
        let b = std::fs::read(two.join(file)).unwrap();
        assert!(a == b, "{file} differs between 1 and 2 threads");
    }
    let runs = std::fs::read_to_string(one.join("runs.csv")).unwrap();
    assert_eq!(runs.lines().count(), expect_runs + 1);
    let report = std::fs::read_to_string(one.join("report.md")).unwrap();
    for name in names {
        assert!(runs.contains(name), "{name} missing from runs.csv");
        assert!(report.contains(name), "{name} missing from report.md");
    }
    // Resuming a finished campaign runs nothing and changes nothing.
    let again = campaign(&one, Some(2)).unwrap();
    assert_eq!(again.executed, 0);
    assert_eq!(std::fs::read_to_string(one.join("runs.csv")).unwrap(), runs);
}

#[test]
fn a_custom_optimiser_runs_beside_hs_and_mhs() {
    same_on_one_and_two_threads(
        custom_optimiser::campaign,
        3 * 3 * 10,
        &["(1+1)-ES", "es11", "HS", "MHS", "rosenbrock"],
    );
}

#[test]
fn a_custom_problem_runs_beside_a_builtin_function() {
    same_on_one_and_two_threads(
        custom_problem::campaign,
        4 * 2 * 10,
        &["styblinski_tang", "sphere", "MHS", "PSO"],
    );
}

#[test]
fn a_registered_suite_with_its_own_section_runs() {
    same_on_one_and_two_threads(
        shekel_suite::campaign,
        3 * 2 * 5,
        &["shekel5", "shekel7", "shekel10", "MHS", "PSO"],
    );
}

#[test]
fn a_registered_suite_reads_its_own_keys_and_is_listed() {
    let reg = shekel_suite::registry();
    let text = shekel_suite::SPEC.replace("maxima = [5, 7, 10]", "maxima = [5, 6]");
    let e = Spec::parse_in(Path::new("s.toml"), &text, SpecLimits::DEFAULT, &reg).unwrap_err();
    assert_eq!(e.field, "problem[1].maxima", "{e}");
    assert!(e.message.contains("5, 7 or 10 maxima, not 6"), "{e}");
    // Its key is its own: the thesis's functions do not take it, and it
    // does not take theirs.
    let text = shekel_suite::SPEC.replace("maxima = [5, 7, 10]", "maxima = 5\ndim = 4");
    let e = Spec::parse_in(Path::new("s.toml"), &text, SpecLimits::DEFAULT, &reg).unwrap_err();
    assert_eq!(e.field, "problem[1].dim", "{e}");
    let text =
        shekel_suite::SPEC.replace("suite = \"shekel\"\n", "function = \"sphere\"\ndim = 2\n");
    let e = Spec::parse_in(Path::new("s.toml"), &text, SpecLimits::DEFAULT, &reg).unwrap_err();
    assert_eq!(e.field, "problem[1].maxima", "{e}");
    // A suite is unknown to a registry without it (its own keys, checked
    // before the suite as ever, are unknown there too).
    let text = shekel_suite::SPEC.replace("maxima = [5, 7, 10]\n", "");
    let e = Spec::parse(Path::new("s.toml"), &text).unwrap_err();
    assert!(e.message.contains("unknown suite \"shekel\""), "{e}");
    let list = metabezier::experiment::listing::list(&reg);
    assert!(list.contains("suite = \"shekel\""), "{list}");
    assert!(list.contains("  shekel10 "), "{list}");
}

#[test]
fn the_es_solves_the_sphere_and_its_errors_are_from_f_star() {
    // The (1+1)-ES is a real optimiser: on Sphere-10 it reaches 1e-8 well
    // within 20,000 evaluations, and a registered problem's error is
    // measured from its own f*.
    let tmp = tempfile::tempdir().unwrap();
    custom_optimiser::campaign(tmp.path(), Some(2)).unwrap();
    let runs = std::fs::read_to_string(tmp.path().join("runs.csv")).unwrap();
    let header: Vec<&str> = runs.lines().next().unwrap().split(',').collect();
    let col = |n: &str| header.iter().position(|h| *h == n).unwrap();
    let es_sphere: Vec<Vec<&str>> = runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[col("kind")] == "es11" && r[col("problem")] == "sphere")
        .collect();
    assert_eq!(es_sphere.len(), 10);
    assert!(
        es_sphere.iter().all(|r| r[col("success")] == "true"),
        "{es_sphere:?}"
    );

    let tmp = tempfile::tempdir().unwrap();
    custom_problem::campaign(tmp.path(), Some(2)).unwrap();
    let runs = std::fs::read_to_string(tmp.path().join("runs.csv")).unwrap();
    for r in runs
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
    {
        if r[col("problem")] == "styblinski_tang" {
            let dim: f64 = r[col("dim")].parse().unwrap();
            let best: f64 = r[col("best")].parse().unwrap();
            let error: f64 = r[col("error")].parse().unwrap();
            let f_star = custom_problem::OPTIMUM_PER_DIM * dim;
            // f − f* may round to a few ulps below zero at the optimum.
            assert!(
                error >= -1e-12 * f_star.abs()
                    && (best - f_star - error).abs() <= 1e-12 * f_star.abs(),
                "{r:?}: f* = {f_star}"
            );
        }
    }
}

fn spec_in(reg: &Registry, text: &str) -> Result<Spec, String> {
    Spec::parse_in(Path::new("mine.toml"), text, SpecLimits::DEFAULT, reg)
        .map_err(|e| e.to_string())
}

const HEAD: &str = "[experiment]\nname = \"mine\"\nseed = 1\nruns = 2\nbudget = 100\n\n";

#[test]
fn registered_names_resolve_and_unknown_ones_list_the_registered_choices() {
    let reg = custom_optimiser::registry();
    let ok = format!("{HEAD}[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"es11\"\nsigma0 = [0.1, 0.5]\n");
    assert_eq!(spec_in(&reg, &ok).unwrap().cells.len(), 2);
    // The built-in registry does not know it, and says what it knows.
    let e = spec_in(Registry::builtin(), &ok).unwrap_err();
    assert!(
        e.contains("mine.toml:") && e.contains("unknown algorithm \"es11\""),
        "{e}"
    );
    assert!(e.contains("\"mhs\""), "{e}");
    // A registered parameter is checked against its declaration.
    let bad = ok.replace("[0.1, 0.5]", "2.0");
    let e = spec_in(&reg, &bad).unwrap_err();
    assert!(
        e.contains("algorithm[1].sigma0") && e.contains("(0, 1]"),
        "{e}"
    );
    // The registry's names are the suggestions.
    let typo = ok.replace("es11", "es12");
    let e = spec_in(&reg, &typo).unwrap_err();
    assert!(e.contains("es11"), "{e}");

    let reg = custom_problem::registry();
    let typo = format!("{HEAD}[[problem]]\nfunction = \"styblinski_tanng\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\n");
    let e = spec_in(&reg, &typo).unwrap_err();
    assert!(
        e.contains("problem[1].function") && e.contains("styblinski_tang"),
        "{e}"
    );
    let no_dim = typo.replace("styblinski_tanng\"\ndim = 2", "styblinski_tang\"");
    let e = spec_in(&reg, &no_dim).unwrap_err();
    assert!(e.contains("needs a dimension"), "{e}");
    let rotated = typo
        .replace("tanng", "tang")
        .replace("dim = 2", "dim = 2\ntransform = \"shift\"");
    let e = spec_in(&reg, &rotated).unwrap_err();
    assert!(
        e.contains("problem[1].transform") && e.contains("no transforms"),
        "{e}"
    );
}

#[test]
fn a_clashing_or_malformed_registration_is_refused() {
    let mut reg = Registry::with_builtins();
    let e = reg
        .register_optimiser(OptimiserDef::new(
            "mhs",
            &hs::PARAMS,
            "",
            HarmonySearch::from_params,
        ))
        .unwrap_err();
    assert!(
        e.to_string().contains("\"mhs\" is already registered"),
        "{e}"
    );
    for bad in ["", "lm", "MHS", "hs+lm", "1es", "a b"] {
        let def = OptimiserDef::new(bad, &hs::PARAMS, "", HarmonySearch::from_params);
        assert!(reg.register_optimiser(def).is_err(), "{bad:?} accepted");
    }
    // A factory that refuses its own defaults is refused at registration.
    fn refuses(_: &ParamSet) -> Result<RandomSearch, ParamError> {
        Err(ParamError::new("bounds", "never".into()))
    }
    let e = reg
        .register_optimiser(OptimiserDef::new("never", &hs::PARAMS, "", refuses))
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("refuses its own defaults: bounds: never"),
        "{e}"
    );

    let p = |name: &str| {
        ProblemDef::new(
            name,
            "",
            |d| Ok(Flat(vec![Bounds::new(0.0, 1.0); d], d)),
            |_| 0.0,
        )
    };
    assert!(reg
        .register_problem(p("sphere"))
        .unwrap_err()
        .to_string()
        .contains("already exists"));
    assert!(reg.register_problem(p("bbob_f001")).is_err());
    reg.register_problem(p("flat")).unwrap();
    assert!(reg.register_problem(p("flat")).is_err());
}

/// A constant problem whose builder may lie about its bounds.
struct Flat(Vec<Bounds>, usize);

impl Problem for Flat {
    fn dim(&self) -> usize {
        self.1
    }
    fn bounds(&self) -> &[Bounds] {
        &self.0
    }
    fn objective(&self, _: &[f64]) -> f64 {
        1.0
    }
}

#[test]
fn a_problem_that_cannot_be_built_is_an_error_of_the_spec_at_its_dimension() {
    let mut reg = Registry::with_builtins();
    reg.register_problem(ProblemDef::new(
        "empty_box",
        "",
        |d| Ok(Flat(vec![Bounds::new(1.0, 1.0); d], d)),
        |_| 0.0,
    ))
    .unwrap();
    reg.register_problem(ProblemDef::new(
        "short",
        "",
        |d| Ok(Flat(vec![Bounds::new(0.0, 1.0); d - 1], d)),
        |_| 0.0,
    ))
    .unwrap();
    reg.register_problem(ProblemDef::new(
        "refuses",
        "",
        |d| {
            if d > 3 {
                Err("at most 3 variables".into())
            } else {
                Ok(Flat(vec![Bounds::new(0.0, 1.0); d], d))
            }
        },
        |_| 0.0,
    ))
    .unwrap();
    reg.register_problem(ProblemDef::new(
        "no_optimum",
        "",
        |d| Ok(Flat(vec![Bounds::new(0.0, 1.0); d], d)),
        |_| f64::NAN,
    ))
    .unwrap();
    reg.register_problem(ProblemDef::new(
        "liar",
        "",
        |_| Ok(Flat(vec![Bounds::new(0.0, 1.0)], 1)),
        |_| 0.0,
    ))
    .unwrap();
    let spec = |f: &str, dim: &str| {
        format!(
            "{HEAD}[[problem]]\nfunction = \"{f}\"\ndim = {dim}\n\n[[algorithm]]\nname = \"hs\"\n"
        )
    };
    let cases = [
        ("empty_box", "2", "the bounds of x_1 are [1, 1]"),
        ("short", "3", "has 2 bounds; expected one per variable, 3"),
        ("refuses", "[2, 5]", "refuses at D = 5: at most 3 variables"),
        ("no_optimum", "2", "optimum value is NaN"),
        ("short", "0", "problem[1].dim"),
        ("liar", "4", "built for D = 4 reports dimension 1"),
    ];
    for (f, dim, expect) in cases {
        let e = spec_in(&reg, &spec(f, dim)).unwrap_err();
        assert!(
            e.contains(expect) && e.contains("mine.toml:"),
            "{f} at {dim}: {e}"
        );
    }
    assert!(spec_in(&reg, &spec("refuses", "[2, 3]")).is_ok());
}

#[test]
fn an_algorithm_runs_the_same_through_the_registry_as_its_own_type() {
    use metabezier::functions::{Function, TestProblem};
    use metabezier::optim::Optimiser;
    use metabezier::rng::run_rng;
    let p = TestProblem::new(Function::Rastrigin, 10).unwrap();
    let direct = HarmonySearch::default().run(&p, 5_000, &mut run_rng(3));
    let named = Algorithm::default_for("hs").unwrap();
    let via = named.run(&p, 5_000, &mut run_rng(3));
    // A problem of another type reaches the same optimiser through `dyn`.
    let wrapped = Wrapped(p.clone());
    let via_dyn = named.run(&wrapped, 5_000, &mut run_rng(3));
    for out in [&via, &via_dyn] {
        assert_eq!(out.best_value.to_bits(), direct.best_value.to_bits());
        assert_eq!(out.evaluations, direct.evaluations);
    }
}

/// A problem of a type the registry has no monomorphic path for.
struct Wrapped(metabezier::functions::TestProblem);

impl Problem for Wrapped {
    fn dim(&self) -> usize {
        self.0.dim()
    }
    fn bounds(&self) -> &[Bounds] {
        self.0.bounds()
    }
    fn objective(&self, x: &[f64]) -> f64 {
        self.0.objective(x)
    }
}

#[test]
fn a_registered_problem_runs_as_shards_that_merge_into_the_whole_campaign() {
    use metabezier::experiment::{merge, run_campaign, RunOptions, Shard};
    let reg = custom_problem::registry();
    let spec = Spec::parse_in(
        Path::new("custom_problem.toml"),
        custom_problem::SPEC,
        SpecLimits::DEFAULT,
        &reg,
    )
    .unwrap();
    let tmp = tempfile::tempdir().unwrap();
    let whole = tmp.path().join("whole");
    let opts = |out: &Path, shard| RunOptions {
        out: Some(out.to_owned()),
        threads: Some(2),
        shard,
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts(&whole, None)).unwrap();
    let sharded = tmp.path().join("sharded");
    for k in 1..=2 {
        let s = run_campaign(&spec, &opts(&sharded, Some(Shard { k, n: 2 }))).unwrap();
        assert_eq!(s.total, 40);
    }
    let dirs = vec![sharded.join("shard-1-of-2"), sharded.join("shard-2-of-2")];
    let merged = tmp.path().join("merged");
    merge(&spec, &dirs, Some(merged.clone())).unwrap();
    for file in ["runs.csv", "convergence.csv", "hits.csv"] {
        assert!(
            std::fs::read(whole.join(file)).unwrap() == std::fs::read(merged.join(file)).unwrap(),
            "{file}"
        );
    }
}

/// Random search that panics on problems of dimension 2, as a user's
/// optimiser with a bug might.
#[derive(Clone, Debug)]
struct Fragile;

impl metabezier::optim::Optimiser for Fragile {
    fn minimise<P: Problem + ?Sized, R: metabezier::rng::Words + ?Sized>(
        &self,
        eval: &mut metabezier::optim::Evaluator<'_, P>,
        rng: &mut R,
    ) {
        assert!(eval.dim() != 2, "fragile cannot do two dimensions");
        RandomSearch.minimise(eval, rng)
    }
}

#[test]
fn a_panicking_optimiser_stops_the_campaign_with_the_run_named_and_keeps_finished_runs() {
    use metabezier::experiment::{run_campaign, RunOptions};
    use metabezier::optim::random;
    let with = |fragile: bool| {
        let mut reg = Registry::with_builtins();
        let def = if fragile {
            OptimiserDef::new("fragile", &random::PARAMS, "", |_: &ParamSet| Ok(Fragile))
        } else {
            OptimiserDef::new("fragile", &random::PARAMS, "", RandomSearch::from_params)
        };
        reg.register_optimiser(def).unwrap();
        reg
    };
    let text = format!(
        "{HEAD}[[problem]]\nfunction = \"sphere\"\ndim = [2, 3]\n\n[[algorithm]]\nname = \"fragile\"\n"
    );
    let tmp = tempfile::tempdir().unwrap();
    let opts = |resume| RunOptions {
        out: Some(tmp.path().to_owned()),
        threads: Some(1),
        resume,
        ..RunOptions::default()
    };
    let spec = spec_in(&with(true), &text).unwrap();
    let e = run_campaign(&spec, &opts(false)).unwrap_err().to_string();
    assert!(
        e.contains("run 0 of fragile on sphere-2 panicked: fragile cannot do two dimensions")
            && e.contains("journal.csv")
            && e.contains("--resume"),
        "{e}"
    );
    assert!(!tmp.path().join("runs.csv").exists());
    let journal = std::fs::read_to_string(tmp.path().join("journal.csv")).unwrap();
    assert_eq!(journal.lines().count(), 2, "{journal}");
    // The two runs at D = 3 (the longer, run first) finished before the
    // panic and are reused.
    let spec = spec_in(&with(false), &text).unwrap();
    let s = run_campaign(&spec, &opts(true)).unwrap();
    assert_eq!((s.total, s.reused, s.executed), (4, 2, 2));
}

#[test]
fn external_runs_enter_the_anytime_plots_with_their_directory_or_are_left_out_and_said() {
    use metabezier::experiment::{run_campaign, RunOptions};
    use metabezier::report::{write_report, ReportOptions};
    let tmp = tempfile::tempdir().unwrap();
    let es = tmp.path().join("es");
    custom_optimiser::campaign(&es, Some(2)).unwrap();
    let text = custom_optimiser::SPEC
        .split("[[algorithm]]")
        .next()
        .unwrap()
        .replace("custom_optimiser", "pso_only")
        + "[[algorithm]]\nname = \"pso\"\nlabel = \"PSO\"\n";
    let spec = spec_in(Registry::builtin(), &text).unwrap();
    let ours = tmp.path().join("pso");
    let opts = RunOptions {
        out: Some(ours.clone()),
        threads: Some(2),
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    let report = |external: &Path| {
        let opts = ReportOptions {
            external: Some(external.to_owned()),
            ..ReportOptions::default()
        };
        write_report(&ours, &opts).unwrap();
        let md = std::fs::read_to_string(ours.join("report.md")).unwrap();
        let svg = std::fs::read_to_string(ours.join("plots/ecdf_targets.svg")).unwrap();
        (md, svg)
    };
    // With its results directory: in the 51-target ECDF, no note.
    let (md, svg) = report(&es.join("runs.csv"));
    assert!(svg.contains("(1+1)-ES") && svg.contains("PSO"));
    assert!(!md.contains("come without convergence.csv"), "{md}");
    // runs.csv alone: left out of that plot (not drawn as reaching
    // nothing), and the report says why.
    let alone = tmp.path().join("alone.csv");
    std::fs::copy(es.join("runs.csv"), &alone).unwrap();
    let (md, svg) = report(&alone);
    assert!(!svg.contains("(1+1)-ES") && svg.contains("PSO"));
    assert!(
        md.contains("come without convergence.csv, timing.csv and hits.csv"),
        "{md}"
    );
}

#[test]
fn a_registered_optimiser_leaves_the_thesis_family_unchanged() {
    // Issue 50: the family of a comparison is declared where its optimiser
    // is registered. The (1+1)-ES of the example is registered without a
    // family, so it is beyond the thesis: its verdict against MHS is in
    // `state-of-the-art`, and HS's row of `reference` (its family, its
    // adjusted p) is the same with the ES in the campaign as without it.
    use metabezier::experiment::{run_campaign, RunOptions};
    use metabezier::report::{write_report, ReportOptions};
    let tmp = tempfile::tempdir().unwrap();
    let with_es = tmp.path().join("with");
    custom_optimiser::campaign(&with_es, Some(2)).unwrap();
    let without_text = custom_optimiser::SPEC
        .replace("[[algorithm]]\nname = \"es11\"\nlabel = \"(1+1)-ES\"\n", "");
    assert_ne!(without_text, custom_optimiser::SPEC);
    let spec = spec_in(Registry::builtin(), &without_text).unwrap();
    let without = tmp.path().join("without");
    let opts = RunOptions {
        out: Some(without.clone()),
        threads: Some(2),
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    let reference_rows = |dir: &Path| -> Vec<String> {
        write_report(dir, &ReportOptions::default()).unwrap();
        let csv = std::fs::read_to_string(dir.join("tables/verdicts.csv")).unwrap();
        csv.lines()
            .filter(|l| l.starts_with("reference,"))
            .map(str::to_owned)
            .collect()
    };
    let a = reference_rows(&with_es);
    let b = reference_rows(&without);
    assert!(!a.is_empty());
    assert_eq!(a, b, "the reference family changed with the ES");
    let csv = std::fs::read_to_string(with_es.join("tables/verdicts.csv")).unwrap();
    assert!(
        csv.lines()
            .any(|l| l.starts_with("state-of-the-art,final-error,(1+1)-ES,MHS,all,")),
        "{csv}"
    );
}
