//! The documents quote the registry, never a copy of their own: every
//! table `metabezier list --markdown` makes (the optimisers with their
//! defaults; "Which optimiser?" from `optim::recommended`, the rule
//! Python's `minimize` takes its default from) stands in README.md exactly
//! as the command prints it, under the line that says so.

use std::process::Command;

use crate::layering::root;

/// The tables of `metabezier list --markdown`: `(heading, table)`, and the
/// line that marks a generated copy.
fn generated() -> (String, Vec<(String, String)>) {
    let out = Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .args(["list", "--markdown"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let (marker, rest) = text.split_once('\n').unwrap();
    let sections = rest
        .split("### ")
        .filter(|s| !s.trim().is_empty())
        .map(|s| {
            let (heading, table) = s.split_once('\n').unwrap();
            (heading.to_owned(), table.trim_matches('\n').to_owned())
        })
        .collect();
    (marker.to_owned(), sections)
}

#[test]
fn the_readme_holds_the_registrys_tables_as_they_are() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let (marker, sections) = generated();
    assert_eq!(
        sections.iter().map(|(h, _)| h.as_str()).collect::<Vec<_>>(),
        ["Optimisers", "Which optimiser?"]
    );
    for (heading, table) in &sections {
        let copy = format!("{marker}\n{table}\n");
        assert!(
            readme.contains(&copy),
            "README.md lacks the current \"{heading}\" table; paste `metabezier list --markdown`'s:\n{copy}"
        );
    }
    assert_eq!(
        readme.matches(&marker).count(),
        sections.len(),
        "a stale generated table is left in README.md"
    );
}

#[test]
fn the_which_optimiser_table_is_the_rule() {
    let (_, sections) = generated();
    let table = &sections
        .iter()
        .find(|(h, _)| h == "Which optimiser?")
        .unwrap()
        .1;
    let cells = |l: &str| -> Vec<String> {
        l.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_owned())
            .collect()
    };
    // The columns' budgets per dimension, read from the header ("100·D evaluations").
    let per_dim: Vec<u64> = cells(table.lines().next().unwrap())[1..]
        .iter()
        .map(|h| h.split('·').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(per_dim, [100, 1_000, 10_000, 100_000], "{table}");
    let rows: Vec<Vec<String>> = table.lines().skip(2).map(cells).collect();
    assert!(rows.len() >= 5, "{table}");
    for row in rows {
        let dim: usize = row[0].parse().unwrap();
        for (cell, &per_dim) in row[1..].iter().zip(&per_dim) {
            let rule = metabezier::optim::recommended(dim, per_dim * dim as u64);
            assert_eq!(cell, &format!("`{rule}`"), "D = {dim}, {per_dim}·D");
        }
    }
}

#[test]
fn the_optim_module_lists_every_registered_optimiser_in_order() {
    let text = std::fs::read_to_string(root().join("crates/core/src/optim/mod.rs")).unwrap();
    let listed: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("//! | `"))
        .filter_map(|l| l.split_once('`').map(|(name, _)| name))
        .collect();
    let registered = metabezier::optim::Optimisers::builtin().names();
    assert_eq!(listed, registered, "optim/mod.rs's table of optimisers");
}
