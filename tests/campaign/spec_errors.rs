//! Every kind of bad spec gets its own exact message: file, line, column,
//! field, what was expected and the valid choices.

use std::path::Path;

use metabezier::experiment::Spec;

const BASE: &str = r#"[experiment]
name = "t"
seed = 1
runs = 2
budget = 100

[[problem]]
function = "sphere"
dim = 2

[[algorithm]]
name = "hs"
"#;

fn error_of(text: &str) -> String {
    match Spec::parse(Path::new("spec.toml"), text) {
        Ok(_) => panic!("the spec was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn with_line(extra: &str) -> String {
    format!("{BASE}{extra}\n")
}

#[test]
fn the_base_spec_is_valid() {
    let spec = Spec::parse(Path::new("spec.toml"), BASE).unwrap();
    assert_eq!(spec.run_ids().len(), 2);
    assert_eq!(spec.threshold, 1e-8);
}

#[test]
fn out_of_range_parameters_are_refused_before_anything_runs() {
    assert_eq!(
        error_of(&with_line("hmcr = 1.5")),
        "spec.toml:13:8: algorithm[1].hmcr: expected a real number in [0, 1], found 1.5"
    );
    assert_eq!(
        error_of(&with_line("par = -0.1")),
        "spec.toml:13:7: algorithm[1].par: expected a real number in [0, 1], found -0.1"
    );
    assert_eq!(
        error_of(&with_line("hms = 0")),
        "spec.toml:13:7: algorithm[1].hms: expected an integer in 1..=100000, found 0"
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100", "budget = 0")),
        "spec.toml:5:10: experiment.budget: expected an integer ≥ 1, found 0"
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"mhs\"\nl = 0")),
        "spec.toml:13:5: algorithm[1].l: expected an integer in 1..=1000, found 0"
    );
    assert_eq!(
        error_of(&BASE.replace("runs = 2", "runs = 0")),
        "spec.toml:4:8: experiment.runs: expected an integer in 1..=4294967295, found 0"
    );
    let lshade = |extra: &str| {
        error_of(&BASE.replace("name = \"hs\"", &format!("name = \"lshade\"\n{extra}")))
    };
    assert_eq!(
        lshade("p_best = 0"),
        "spec.toml:13:10: algorithm[1].p_best: expected a real number in (0, 1], found 0"
    );
    assert_eq!(
        lshade("r_n_init = -18"),
        "spec.toml:13:12: algorithm[1].r_n_init: expected a real number in (0, 1000], found -18"
    );
    assert_eq!(
        lshade("memory = 0"),
        "spec.toml:13:10: algorithm[1].memory: expected an integer in 1..=1000, found 0"
    );
    assert_eq!(
        lshade("arc_rate = -0.5"),
        "spec.toml:13:12: algorithm[1].arc_rate: expected a real number in [0, 100], found -0.5"
    );
    assert_eq!(
        lshade("bounds = \"wrap\""),
        "spec.toml:13:10: algorithm[1].bounds: expected one of \"midpoint\", \"clip\" or \"reflect\", found \"wrap\""
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"random\"\nhms = 5")),
        "spec.toml:13:1: algorithm[1].hms: unknown parameter for random (it has none); valid choices: \"name\" or \"label\""
    );
    // A bad value inside a grid list is located at the element.
    assert_eq!(
        error_of(&with_line("hmcr = [0.7, 0.8, 1.9]")),
        "spec.toml:13:19: algorithm[1].hmcr: expected a real number in [0, 1], found 1.9"
    );
}

#[test]
fn unknown_names_list_the_valid_choices() {
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"hz\"")),
        "spec.toml:12:8: algorithm[1].name: unknown algorithm \"hz\"; did you mean \"hs\"? \
         Valid choices: \"hs\", \"ghs\", \"ga\", \"pso\", \"mhs\", \"cmaes\", \"lshade\" or \"random\""
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"simplex\"")),
        "spec.toml:12:8: algorithm[1].name: unknown algorithm \"simplex\"; \
         valid choices: \"hs\", \"ghs\", \"ga\", \"pso\", \"mhs\", \"cmaes\", \"lshade\" or \"random\""
    );
    assert_eq!(
        error_of(&with_line("hmc = 0.9")),
        "spec.toml:13:1: algorithm[1].hmc: unknown parameter for hs; did you mean \"hms\"? \
         Valid choices: \"name\", \"label\", \"hms\", \"hmcr\", \"par\", \"bw\", \"bw_decay\", \"bw_min\" or \"bounds\""
    );
    assert_eq!(
        error_of(&BASE.replace("\"sphere\"", "\"rastrign\"")),
        "spec.toml:8:12: problem[1].function: unknown function \"rastrign\"; did you mean \"rastrigin\"? \
         Valid choices: \"sphere\", \"schwefel_2_22\", \"rosenbrock\", \"step\", \"schwefel_1_2\", \
         \"schwefel_2_26\", \"rastrigin\", \"ackley\", \"griewank\" or \"six_hump_camel\""
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100", "budjet = 100")),
        "spec.toml:5:1: experiment.budjet: unknown field; did you mean \"budget\"? Valid choices: \
         \"name\", \"description\", \"seed\", \"runs\", \"budget\", \"budget_per_dim\", \"threshold\", \
         \"checkpoints_per_decade\", \"paired\" or \"stop\""
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100", "budget = 100\nstop = \"tagret\"")),
        "spec.toml:6:8: experiment.stop: expected where a run ends, found \"tagret\"; did you mean \
         \"target\"? Valid choices: \"budget\" or \"target\""
    );
    assert_eq!(
        error_of(&with_line("bounds = \"wrap\"")),
        "spec.toml:13:10: algorithm[1].bounds: expected one of \"clip\" or \"reflect\", found \"wrap\""
    );
    assert_eq!(
        error_of(&format!("{BASE}\n[[algorithms]]\nname = \"ga\"\n")),
        "spec.toml:14:3: algorithms: unknown section; did you mean \"algorithm\"? \
         Valid choices: \"experiment\", \"problem\", \"fit\", \"algorithm\" or \"report\""
    );
}

#[test]
fn wrong_types_say_what_was_expected() {
    assert_eq!(
        error_of(&with_line("hmcr = \"high\"")),
        "spec.toml:13:8: algorithm[1].hmcr: expected a real number in [0, 1], found \"high\""
    );
    assert_eq!(
        error_of(&BASE.replace("seed = 1", "seed = \"one\"")),
        "spec.toml:3:8: experiment.seed: expected an integer ≥ 0, found \"one\""
    );
    assert_eq!(
        error_of(&with_line("hms = 2.5")),
        "spec.toml:13:7: algorithm[1].hms: expected an integer in 1..=100000, found the float 2.5"
    );
}

#[test]
fn inconsistent_specs_are_refused() {
    assert_eq!(
        error_of(&BASE.replace("\"sphere\"\ndim = 2", "\"six_hump_camel\"\ndim = 30")),
        "spec.toml:9:7: problem[1].dim: six_hump_camel is defined only for dimension 2, not 30"
    );
    assert_eq!(
        error_of(&BASE.replace(
            "name = \"hs\"",
            "name = \"ghs\"\npar_min = 0.9\npar_max = 0.5"
        )),
        "spec.toml:13:11: algorithm[1].par_min: par_min (0.9) must not exceed par_max (0.5)"
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"cmaes\"\nlambda = 1")),
        "spec.toml:13:10: algorithm[1].lambda: λ must be at least 2 (or 0 for 4 + ⌊3 ln D⌋), found 1"
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"cmaes\"\nsigma0 = 0")),
        "spec.toml:13:10: algorithm[1].sigma0: expected a real number in (0, 1], found 0"
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"cmaes\"\nrestarts = \"foo\"")),
        "spec.toml:13:12: algorithm[1].restarts: expected one of \"ipop\", \"bipop\" or \"none\", found \"foo\""
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"hs\"", "name = \"cmaes\"\ninc_popsize = 1")),
        "spec.toml:13:15: algorithm[1].inc_popsize: expected a real number in (1, 10], found 1"
    );
    assert_eq!(
        error_of(&with_line("hmcr = []")),
        "spec.toml:13:8: algorithm[1].hmcr: expected a value or a non-empty list, found an empty list"
    );
    assert_eq!(
        error_of(&format!("{BASE}\n[[algorithm]]\nname = \"hs\"\n")),
        "spec.toml:14:1: algorithm[2]: algorithm cell hs [hms=5;hmcr=0.9;par=0.3;bw=0.01;bw_decay=none;bw_min=0.000001;bounds=clip] \
         appears twice; give the entries different labels or parameters"
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100\n", "")),
        "spec.toml:6:1: problem[1].budget: no budget: give \"budget\" or \"budget_per_dim\" in [experiment] or in this [[problem]]"
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100", "budget = 100\nbudget_per_dim = 10")),
        "spec.toml:6:18: experiment.budget_per_dim: give either \"budget\" or \"budget_per_dim\", not both"
    );
}

#[test]
fn missing_parts_and_broken_toml_are_located() {
    assert_eq!(
        error_of(&BASE.replace("name = \"t\"\n", "")),
        "spec.toml:1:1: experiment.name: missing required field \"name\" in [experiment]"
    );
    assert_eq!(
        error_of(&BASE.replace("[experiment]", "[experiment")),
        "spec.toml:1:12: invalid TOML: unclosed table, expected `]`"
    );
    assert_eq!(
        error_of("[experiment]\nname = \"t\"\nseed = 1\nruns = 1\nbudget = 5\n"),
        "spec.toml:1:1: problem: missing [[problem]] entries; the spec needs at least one"
    );
    assert_eq!(
        error_of(&BASE.replace("name = \"t\"", "name = \"../etc\"")),
        "spec.toml:2:8: experiment.name: expected a name of letters, digits, '-', '_' or '.' \
         (it names the results directory), found \"../etc\""
    );
}

#[test]
fn a_missing_file_is_named() {
    let e = Spec::load(Path::new("no/such/spec.toml"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("no/such/spec.toml: cannot read the spec: "),
        "{e}"
    );
}

#[test]
fn instances_budgets_and_pairing_are_checked_before_anything_runs() {
    let problem = |extra: &str| BASE.replace("dim = 2\n", &format!("dim = 2\n{extra}\n"));
    assert_eq!(
        error_of(&problem("transform = \"rotate\"")),
        "spec.toml:10:13: problem[1].transform: unknown transform \"rotate\"; valid choices: \"none\", \"shift\" or \"shift-rotate\""
    );
    assert_eq!(
        error_of(&problem("transform = \"shift\"\ninstances = 0")),
        "spec.toml:11:13: problem[1].instances: expected an integer in 1..=10000, found 0"
    );
    let e = error_of(&BASE.replace(
        "function = \"sphere\"",
        "function = \"schwefel_2_26\"\ntransform = [\"none\", \"shift\"]",
    ));
    assert!(
        e.starts_with("spec.toml:9:22: problem[1].transform: schwefel_2_26 has no \"shift\" instances: only sphere,"),
        "{e}"
    );
    let e = error_of(&BASE.replace(
        "function = \"sphere\"\ndim = 2",
        "function = \"six_hump_camel\"\ntransform = \"shift-rotate\"",
    ));
    assert!(e.contains("two global minimisers"), "{e}");
    assert_eq!(
        error_of(&BASE.replace("runs = 2", "runs = 2\npaired = [\"budjet\"]")),
        "spec.toml:5:11: experiment.paired: unknown factor \"budjet\"; did you mean \"budget\"? Valid choices: \"budget\", \"transform\", \"instance\", \"search_space\" or \"alpha_size\""
    );
    assert_eq!(
        error_of(&BASE.replace("runs = 2", "runs = 2\npaired = \"budget\"")),
        "spec.toml:5:10: experiment.paired: \"budget\" does not vary among this spec's problems, so there is nothing to pair; no factor varies here"
    );
    let e = error_of(
        &BASE
            .replace("runs = 2", "runs = 2\npaired = [\"instance\"]")
            .replace("budget = 100", "budget = [100, 1000]"),
    );
    assert!(
        e.ends_with("\"instance\" does not vary among this spec's problems, so there is nothing to pair; the varying factors are \"budget\""),
        "{e}"
    );
    assert_eq!(
        error_of(&BASE.replace("budget = 100", "budget = [100, 0]")),
        "spec.toml:5:16: experiment.budget: expected an integer ≥ 1, found 0"
    );
}

#[test]
fn grids_of_transforms_instances_and_budgets_expand_with_keys() {
    let spec = Spec::parse(
        Path::new("spec.toml"),
        &BASE
            .replace("budget = 100", "budget = [100, 1000]")
            .replace(
                "dim = 2\n",
                "dim = 2\ntransform = [\"none\", \"shift-rotate\"]\ninstances = 2\n",
            ),
    )
    .unwrap();
    let keys: Vec<String> = spec.problems.iter().map(|p| p.key()).collect();
    assert_eq!(
        keys,
        [
            "sphere-2|budget=100",
            "sphere-2|budget=1000",
            "sphere-2|budget=100|transform=shift-rotate",
            "sphere-2|budget=1000|transform=shift-rotate",
            "sphere-2|budget=100|transform=shift-rotate|instance=2",
            "sphere-2|budget=1000|transform=shift-rotate|instance=2",
        ]
    );
    // The base spec keeps the key it had before factors existed.
    let base = Spec::parse(Path::new("spec.toml"), BASE).unwrap();
    assert_eq!(base.problems[0].key(), "sphere-2");
}

#[test]
fn instance_lists_name_fixed_instances_and_are_checked() {
    let with = |extra: &str| BASE.replace("dim = 2\n", &format!("dim = 2\n{extra}\n"));
    let keys = |text: &str| -> Vec<String> {
        Spec::parse(Path::new("spec.toml"), text)
            .unwrap()
            .problems
            .iter()
            .map(|p| p.key())
            .collect()
    };
    // A list names its instances, in its order; the published function
    // keeps its one instance.
    assert_eq!(
        keys(&with(
            "transform = [\"none\", \"shift-rotate\"]\ninstances = [8, 6, 7]"
        )),
        [
            "sphere-2",
            "sphere-2|transform=shift-rotate|instance=8",
            "sphere-2|transform=shift-rotate|instance=6",
            "sphere-2|transform=shift-rotate|instance=7",
        ]
    );
    // The list 1..N is the count N, key for key.
    assert_eq!(
        keys(&with("transform = \"shift\"\ninstances = [1, 2, 3]")),
        keys(&with("transform = \"shift\"\ninstances = 3"))
    );
    let problem =
        |instances: &str| with(&format!("transform = \"shift\"\ninstances = {instances}"));
    assert_eq!(
        error_of(&problem("[]")),
        "spec.toml:11:13: problem[1].instances: expected a value or a non-empty list, found an empty list"
    );
    assert_eq!(
        error_of(&problem("[6, 7, 6]")),
        "spec.toml:11:20: problem[1].instances: instance 6 is listed twice; give a count N (instances 1..N) or a list of distinct instance numbers"
    );
    assert_eq!(
        error_of(&problem("[6, 0]")),
        "spec.toml:11:17: problem[1].instances: expected an integer in 1..=10000, found 0"
    );
    assert_eq!(
        error_of(&problem("[6, 7.5]")),
        "spec.toml:11:17: problem[1].instances: expected an integer in 1..=10000, found the float 7.5"
    );
    assert_eq!(
        error_of(&problem("[\"6\"]")),
        "spec.toml:11:14: problem[1].instances: expected an integer in 1..=10000, found \"6\""
    );
    assert_eq!(
        error_of(&problem("[6, 10001]")),
        "spec.toml:11:17: problem[1].instances: expected an integer in 1..=10000, found 10001"
    );
    assert_eq!(
        error_of(&problem("10001")),
        "spec.toml:11:13: problem[1].instances: expected an integer in 1..=10000, found 10001"
    );
    // A bbob list is checked by the same code.
    let bbob = BASE.replace(
        "function = \"sphere\"\ndim = 2",
        "suite = \"bbob\"\nfunction = 1\ndim = 2\ninstances = [2, 2]",
    );
    assert_eq!(
        error_of(&bbob),
        "spec.toml:11:17: problem[1].instances: instance 2 is listed twice; give a count N (instances 1..N) or a list of distinct instance numbers"
    );
}

/// The error for an algorithm named `name` in the base spec.
fn hint_for(name: &str) -> String {
    error_of(&BASE.replace("name = \"hs\"", &format!("name = \"{name}\"")))
}

/// The "did you mean" suggester counts a transposition of two adjacent
/// letters as one edit (Damerau–Levenshtein), so a swapped pair of letters
/// is suggested back rather than a shorter name at the same distance.
#[test]
fn transposed_letters_suggest_the_name_they_come_from() {
    for (typo, meant) in [
        ("msh", "mhs"),
        ("pos", "pso"),
        ("cmase", "cmaes"),
        ("lshaed", "lshade"),
    ] {
        let e = hint_for(typo);
        assert!(
            e.contains(&format!("did you mean \"{meant}\"?")),
            "{typo}: {e}"
        );
    }
}

#[test]
fn a_name_far_from_every_choice_gets_no_suggestion() {
    let e = hint_for("simplex");
    assert!(!e.contains("did you mean"), "{e}");
}
