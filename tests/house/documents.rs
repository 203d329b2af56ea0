//! The documents quote the registry, never a copy of their own: every
//! table `metabezier list --markdown` makes (the optimisers with their
//! defaults; "Which optimiser?" from `optim::recommended`, the rule
//! Python's `minimize` takes its default from) stands in its document
//! (README.md, docs/guide/optimisers.md) exactly as the command prints it,
//! under the line that says so.

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

/// Where each generated table stands: (heading, document).
const PLACES: [(&str, &str); 3] = [
    ("Optimisers", "docs/guide/optimisers.md"),
    ("Parameters", "docs/guide/optimisers.md"),
    ("Which optimiser?", "README.md"),
];

#[test]
fn the_documents_hold_the_registrys_tables_as_they_are() {
    let (marker, sections) = generated();
    assert_eq!(
        sections.iter().map(|(h, _)| h.as_str()).collect::<Vec<_>>(),
        PLACES.map(|(h, _)| h)
    );
    for ((heading, table), (_, file)) in sections.iter().zip(PLACES) {
        let text = std::fs::read_to_string(root().join(file)).unwrap();
        let copy = format!("{marker}\n{table}\n");
        assert!(
            text.contains(&copy),
            "{file} lacks the current \"{heading}\" table; paste `metabezier list --markdown`'s:\n{copy}"
        );
        let here = PLACES.iter().filter(|(_, f)| *f == file).count();
        assert_eq!(
            text.matches(&marker).count(),
            here,
            "{file} holds a stale generated table beside the current ones"
        );
    }
    // No copy elsewhere in the documents, where no test would hold it.
    for file in crate::code_blocks::documents() {
        let text = std::fs::read_to_string(root().join(&file)).unwrap();
        let here = PLACES.iter().any(|(_, f)| std::path::Path::new(f) == file);
        assert!(
            here || !text.contains(&marker),
            "{} holds a generated table; it belongs in {PLACES:?}",
            file.display()
        );
    }
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

#[test]
fn the_readme_stays_short() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(
        lines <= 250,
        "README.md has {lines} lines; at most 250 (the detail belongs in docs/guide/)"
    );
}

/// The README's picture is what its caption's command draws today.
#[test]
fn the_readmes_picture_is_current() {
    let scratch = crate::code_blocks::Scratch::new("picture");
    let run = scratch.sh("metabezier fit data/outlines/horse.png --outputs png --out pic");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let drawn = std::fs::read(scratch.0.join("pic/fit.png")).unwrap();
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    assert!(readme.contains("(docs/img/horse-fit.png)"));
    assert!(readme.contains("`metabezier fit data/outlines/horse.png\n--outputs png`"));
    assert!(
        drawn == std::fs::read(root().join("docs/img/horse-fit.png")).unwrap(),
        "docs/img/horse-fit.png is not what `metabezier fit data/outlines/horse.png --outputs png` draws; copy its fit.png there"
    );
}

/// `experiments/ch6_quick.toml` designs the implant exactly as
/// `ch6_cranial.toml` does: its sections are that spec's first part.
#[test]
fn the_quick_implant_spec_is_the_chapter_specs_first_part() {
    let read = |f: &str| std::fs::read_to_string(root().join("experiments").join(f)).unwrap();
    let body = |t: &str| -> String {
        t.lines()
            .skip_while(|l| !l.starts_with("[implant]"))
            .take_while(|l| !l.starts_with("[validation"))
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .collect::<Vec<_>>()
            .join("\n")
    };
    let quick = body(&read("ch6_quick.toml"));
    assert!(quick.contains("[defect]"), "{quick}");
    assert_eq!(quick, body(&read("ch6_cranial.toml")));
}
