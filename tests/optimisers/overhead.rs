//! `make overhead` (benches/overhead.rs, included here as a module) runs
//! every optimiser on a tiny budget and prints a well-formed table; its
//! options are checked and a bad one is refused with the valid choices. No
//! timing is asserted: the figures depend on the machine and its load.

#[allow(dead_code)]
#[path = "../../benches/overhead.rs"]
mod bench;

use bench::{check_table, measure, Options};

fn args(a: &[&str]) -> Vec<String> {
    a.iter().map(|s| s.to_string()).collect()
}

#[test]
fn every_optimiser_gets_a_row_of_positive_figures_on_a_tiny_budget() {
    let o = Options::tiny();
    assert_eq!(o.algorithms, metabezier::optim::Algorithm::names());
    let m = measure(&o);
    let table = m.table();
    check_table(&table, &o.algorithms).unwrap_or_else(|e| panic!("{e}\n{table}"));
    assert!(table.starts_with("Sphere, D = 30: 1 runs of 2000 evaluations"));
    #[cfg(target_os = "linux")]
    assert!(m.cpu_clock && table.contains("thread CPU time"), "{table}");
}

#[test]
fn a_malformed_table_is_caught() {
    let names = vec!["hs".to_string()];
    let head = "| optimiser | bare ns/eval | ns/eval | ratio to bare | ratio min–max | wall-clock ratio |\n|---|---:|---:|---:|---:|---:|\n";
    assert!(check_table(
        &format!("{head}| hs | 8.7 | 77.0 | 9.0 | 8.6–9.1 | 9.0 |\n"),
        &names
    )
    .is_ok());
    for bad in [
        "| hs | 8.7 | 77.0 | 9.0 | 9.1–8.6 | 9.0 |\n",
        "| hs | 8.7 | 77.0 | inf | 8.6–9.1 | 9.0 |\n",
        "| hs | 0.0 | 77.0 | 9.0 | 8.6–9.1 | 9.0 |\n",
        "| ga | 8.7 | 77.0 | 9.0 | 8.6–9.1 | 9.0 |\n",
        "| hs | 8.7 | 77.0 | 9.0 | 8.6–9.1 |\n",
        "",
    ] {
        assert!(
            check_table(&format!("{head}{bad}"), &names).is_err(),
            "{bad}"
        );
    }
}

#[test]
fn options_are_read_and_bad_ones_refused_with_the_choices() {
    let (o, bench) = Options::parse(&args(&["--bench"])).unwrap();
    assert!(bench);
    assert_eq!(o, Options::default());
    let (o, bench) = Options::parse(&args(&[
        "--dim",
        "10",
        "--evals",
        "500",
        "--rounds",
        "3",
        "--algorithms",
        "hs,pso",
    ]))
    .unwrap();
    assert!(!bench);
    assert_eq!((o.dim, o.evals, o.runs, o.rounds), (10, 500, 10, 3));
    assert_eq!(o.algorithms, ["hs", "pso"]);
    let e = Options::parse(&args(&["--algorithms", "hs,sa"])).unwrap_err();
    assert!(e.contains("\"sa\"") && e.contains("lshade"), "{e}");
    let e = Options::parse(&args(&["--evals", "0"])).unwrap_err();
    assert!(e.starts_with("--evals"), "{e}");
    let e = Options::parse(&args(&["--evals", "1099511627776", "--runs", "2"])).unwrap_err();
    assert!(e.contains("2^40 evaluations"), "{e}");
    let (o, _) = Options::parse(&args(&["--function", "rastrigin", "--dim", "2"])).unwrap();
    assert_eq!((o.function.name(), o.dim), ("rastrigin", 2));
    let e = Options::parse(&args(&["--function", "spher"])).unwrap_err();
    assert!(
        e.contains("\"spher\"") && e.contains("six_hump_camel"),
        "{e}"
    );
    let e = Options::parse(&args(&["--function", "six_hump_camel"])).unwrap_err();
    assert!(e.starts_with("--function six_hump_camel --dim 30:"), "{e}");
    let e = Options::parse(&args(&["--dim", "1001"])).unwrap_err();
    assert!(e.starts_with("--dim"), "{e}");
    let e = Options::parse(&args(&["--rounds"])).unwrap_err();
    assert!(e.contains("needs a value"), "{e}");
    let e = Options::parse(&args(&["--threads", "2"])).unwrap_err();
    assert!(e.contains("--threads") && e.contains("--algorithms"), "{e}");
}
