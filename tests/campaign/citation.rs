//! The project is citable and its version is one number (issue 53): the
//! crate's version (Cargo.toml's `[workspace.package]`), the Python
//! package's, `CITATION.cff`'s and the newest release in `CHANGELOG.md`
//! agree; the licence Cargo.toml names is the one the licence files and
//! `CITATION.cff` carry. (`make citation` validates `CITATION.cff` against
//! the Citation File Format schema with cffconvert.)

use std::path::Path;

fn read(path: &str) -> String {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The value of the first line `key = "value"` or `key: value` after the
/// line `section` (the whole file when `section` is empty).
fn field(text: &str, section: &str, key: &str) -> Option<String> {
    let start = if section.is_empty() {
        0
    } else {
        text.find(&format!("\n{section}\n"))?
    };
    text[start..].lines().find_map(|l| {
        let rest = l.strip_prefix(key)?.trim_start();
        let v = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
        Some(v.trim().trim_matches('"').to_string())
    })
}

#[test]
fn the_version_is_one_number_everywhere() {
    let version = env!("CARGO_PKG_VERSION");
    let pyproject = read("python/pyproject.toml");
    assert_eq!(
        field(&pyproject, "[project]", "version").as_deref(),
        Some(version)
    );
    let cff = read("CITATION.cff");
    assert_eq!(field(&cff, "", "version").as_deref(), Some(version));
    let changelog = read("CHANGELOG.md");
    let newest = changelog
        .lines()
        .filter_map(|l| l.strip_prefix("## ["))
        .map(|l| l.split(']').next().unwrap_or(""))
        .find(|v| *v != "Unreleased");
    assert_eq!(newest, Some(version), "the newest release in CHANGELOG.md");
}

#[test]
fn the_licence_is_the_same_in_every_file() {
    let cargo = read("Cargo.toml");
    assert_eq!(
        field(&cargo, "[workspace.package]", "license").as_deref(),
        Some("MIT OR Apache-2.0")
    );
    assert!(read("LICENSE-MIT").contains("Permission is hereby granted, free of charge"));
    let apache = read("LICENSE-APACHE");
    assert!(apache.contains("Apache License") && apache.contains("Version 2.0, January 2004"));
    let cff = read("CITATION.cff");
    assert!(
        cff.contains("  - MIT\n") && cff.contains("  - Apache-2.0\n"),
        "{cff}"
    );
    // The thesis is cited by what is known of it, and no author is invented.
    assert!(cff.contains(
        "title: \"Curve Reconstruction by Metaheuristics Algorithms on Cubic Rational Bézier Function\""
    ));
    assert!(cff.contains("Author not named in the surviving front matter"));
}
