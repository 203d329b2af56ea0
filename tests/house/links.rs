//! Every relative link of the project's Markdown documents leads somewhere:
//! its file exists, and its `#anchor`, if any, is a heading of that file
//! (GitHub's slug of it). Links inside code are not links.

use std::path::{Path, PathBuf};

use crate::code_blocks::documents;
use crate::layering::root;

/// The documents whose links are checked, relative to the root: the
/// README, the guide, the FAQ, the reproduction notes and the changelog.
fn linked_documents() -> Vec<PathBuf> {
    let mut files = documents();
    files.extend(["REPRODUCTION.md", "CHANGELOG.md"].map(PathBuf::from));
    let mut notes: Vec<PathBuf> = std::fs::read_dir(root().join("docs/reproduction"))
        .unwrap()
        .map(|e| e.unwrap().path().strip_prefix(root()).unwrap().to_owned())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    notes.sort();
    files.extend(notes);
    files
}

/// The lines of `text` outside fenced blocks, with inline code removed.
fn prose(text: &str) -> Vec<(usize, String)> {
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            let kept: String = line
                .split('`')
                .enumerate()
                .filter(|(k, _)| k % 2 == 0)
                .map(|(_, s)| s)
                .collect();
            out.push((i + 1, kept));
        }
    }
    out
}

/// The targets of the Markdown links `[..](target)` of one line.
fn targets(line: &str) -> Vec<&str> {
    line.match_indices("](")
        .filter_map(|(i, _)| {
            let rest = &line[i + 2..];
            rest.find(')').map(|end| rest[..end].trim())
        })
        .collect()
}

/// GitHub's anchor of a heading: lower case, punctuation dropped (letters,
/// digits, `-` and `_` kept), blanks as `-`.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter(|c| c.is_alphanumeric() || matches!(c, '-' | '_' | ' '))
        .map(|c| if c == ' ' { '-' } else { c })
        .collect()
}

fn anchors(file: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(file).unwrap();
    prose(&text)
        .into_iter()
        .filter_map(|(_, l)| {
            let hashes = l.chars().take_while(|&c| c == '#').count();
            (1..=6)
                .contains(&hashes)
                .then(|| l[hashes..].strip_prefix(' ').map(slug))
                .flatten()
        })
        .collect()
}

/// Where a link from `file` to `target` fails to lead, if it does.
fn broken(file: &Path, target: &str) -> Option<String> {
    if target.contains("://") || target.starts_with("mailto:") {
        return None;
    }
    let (path, anchor) = match target.split_once('#') {
        Some((p, a)) => (p, Some(a)),
        None => (target, None),
    };
    let resolved = if path.is_empty() {
        root().join(file)
    } else {
        root().join(file).parent().unwrap().join(path)
    };
    if !resolved.exists() {
        return Some(format!("no file {}", resolved.display()));
    }
    let anchor = anchor?;
    if resolved.extension().is_some_and(|e| e == "md")
        && !anchors(&resolved).iter().any(|a| a == anchor)
    {
        return Some(format!(
            "no heading with the anchor #{anchor} in {}",
            resolved.display()
        ));
    }
    None
}

#[test]
fn every_relative_link_leads_somewhere() {
    let mut failures = Vec::new();
    let mut links = 0;
    for file in linked_documents() {
        let text = std::fs::read_to_string(root().join(&file)).unwrap();
        for (line, prose) in prose(&text) {
            for target in targets(&prose) {
                links += 1;
                if let Some(why) = broken(&file, target) {
                    failures.push(format!("{}:{line}: ({target}): {why}", file.display()));
                }
            }
        }
    }
    assert!(links > 50, "only {links} links found");
    assert!(
        failures.is_empty(),
        "broken links:\n{}",
        failures.join("\n")
    );
}

#[test]
fn slugs_and_broken_links_are_read_as_github_reads_them() {
    assert_eq!(
        slug("Curve fitting (chapters 3 and 5)"),
        "curve-fitting-chapters-3-and-5"
    );
    assert_eq!(slug("COCO's bbob suite"), "cocos-bbob-suite");
    assert_eq!(slug("Which optimiser?"), "which-optimiser");
    assert_eq!(
        targets("see [a](b.md#c) and ![p](d/e.png)"),
        ["b.md#c", "d/e.png"]
    );
    assert!(broken(Path::new("README.md"), "#which-optimiser").is_none());
    assert!(broken(Path::new("README.md"), "#which-optimizer").is_some());
    assert!(broken(Path::new("README.md"), "docs/guide/nothing.md").is_some());
    assert!(broken(
        Path::new("docs/guide/README.md"),
        "../../README.md#citing-and-licence"
    )
    .is_none());
}
