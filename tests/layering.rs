//! The house stays one-way: every top-level module ("room") of `src/` may
//! import only the rooms listed before it in [`ORDER`], and the leaves
//! import nothing of the crate. The order is the one `src/lib.rs` documents
//! and declares; a new room must be placed in it.
//!
//! The check reads the source as text: every `crate::room` path outside
//! comments, including the rooms named inside `use crate::{...}` groups.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Leaves: they import nothing of the crate.
const LEAVES: [&str; 5] = ["files", "font", "linalg", "markdown", "simd"];

/// The rooms from the bottom up; each may import only those before it
/// (and the leaves).
const ORDER: [&str; 15] = [
    "geometry",
    "stats",
    "rng",
    "problem",
    "functions",
    "optim",
    "outline",
    "fit",
    "reconstruction",
    "ct",
    "experiment",
    "implant",
    "report",
    "error",
    "cli",
];

/// The rank of a room: leaves 0, then 1.. in [`ORDER`].
fn rank(room: &str) -> Option<usize> {
    if LEAVES.contains(&room) {
        return Some(0);
    }
    ORDER.iter().position(|r| *r == room).map(|i| i + 1)
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The room of a file under `src/`: its first path component, without `.rs`.
fn room_of(src: &Path, file: &Path) -> String {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel
        .components()
        .next()
        .unwrap()
        .as_os_str()
        .to_string_lossy();
    first.trim_end_matches(".rs").to_owned()
}

/// A line with its `//` comment removed (string literals are kept whole).
fn code_of(line: &str) -> &str {
    let mut in_str = false;
    let mut escaped = false;
    let bytes = line.as_bytes();
    for i in 0..bytes.len() {
        let c = bytes[i];
        if in_str {
            if escaped {
                escaped = false;
            } else if c == b'\\' {
                escaped = true;
            } else if c == b'"' {
                in_str = false;
            }
        } else if c == b'"' {
            in_str = true;
        } else if c == b'/' && bytes.get(i + 1) == Some(&b'/') {
            return &line[..i];
        }
    }
    line
}

fn ident_at(s: &str) -> &str {
    let end = s
        .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .unwrap_or(s.len());
    &s[..end]
}

/// The rooms a piece of code names through `crate::`.
fn rooms_named(code: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let before = rest[..i].chars().last();
        rest = &rest[i + "crate::".len()..];
        if before.is_some_and(|c| c.is_ascii_alphanumeric() || c == '_' || c == '$') {
            continue;
        }
        if let Some(group) = rest.strip_prefix('{') {
            // `crate::{a, b::c, d}`: the first identifier of each top-level item.
            let mut depth = 0usize;
            let mut item_start = true;
            for (j, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => break,
                    '}' => depth -= 1,
                    ',' if depth == 0 => item_start = true,
                    c if item_start && (c.is_ascii_alphabetic() || c == '_') => {
                        out.push(ident_at(&group[j..]).to_owned());
                        item_start = false;
                    }
                    _ => {}
                }
            }
        } else {
            out.push(ident_at(rest).to_owned());
        }
    }
    out
}

/// Every `crate::` reference of `src/`, as (file, line, from-room, to-room).
fn references(src: &Path) -> Vec<(PathBuf, usize, String, String)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut out = Vec::new();
    for file in files {
        let room = room_of(src, &file);
        if room == "lib" || room == "main" {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        // Join a `use crate::{` group split over several lines.
        let mut pending: Option<(usize, String)> = None;
        for (n, line) in text.lines().enumerate() {
            let code = code_of(line);
            let (start, code) = match pending.take() {
                Some((start, mut acc)) => {
                    acc.push(' ');
                    acc.push_str(code.trim());
                    (start, acc)
                }
                None => (n + 1, code.to_owned()),
            };
            if code.contains("crate::{") && !code.contains('}') {
                pending = Some((start, code));
                continue;
            }
            for to in rooms_named(&code) {
                out.push((file.clone(), start, room.clone(), to));
            }
        }
    }
    out
}

/// The upward (or unknown) imports of `src`, one message each.
fn violations(src: &Path) -> Vec<String> {
    let mut bad = Vec::new();
    for (file, line, from, to) in references(src) {
        if from == to {
            continue;
        }
        let at = format!("{}:{line}", file.display());
        match (rank(&from), rank(&to)) {
            (None, _) => bad.push(format!(
                "{at}: the room `{from}` is not in the layering order; add it to ORDER (tests/layering.rs) and to the table in src/lib.rs"
            )),
            (_, None) => bad.push(format!("{at}: `{from}` imports `crate::{to}`, which is not a room")),
            (Some(0), _) => bad.push(format!(
                "{at}: the leaf `{from}` imports `crate::{to}`; leaves import nothing of the crate"
            )),
            (Some(a), Some(b)) if b >= a => bad.push(format!(
                "{at}: `{from}` imports `crate::{to}`, which sits above it; move the shared item down or invert the dependency"
            )),
            _ => {}
        }
    }
    bad
}

#[test]
fn no_room_imports_one_above_it() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let bad = violations(&src);
    assert!(bad.is_empty(), "upward imports:\n{}", bad.join("\n"));
}

#[test]
fn lib_declares_the_rooms_in_the_layering_order() {
    let lib =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs")).unwrap();
    let declared: Vec<&str> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|l| l.trim_end_matches(';'))
        .collect();
    let mut expected: Vec<&str> = LEAVES.to_vec();
    expected.extend(ORDER);
    assert_eq!(declared, expected);
}

#[test]
fn an_upward_import_is_found() {
    // A scratch tree: geometry importing the report, a leaf importing
    // geometry through a group, and a room that is not in the order.
    let dir = tempfile::tempdir().unwrap();
    let src = dir.path();
    std::fs::create_dir_all(src.join("geometry")).unwrap();
    let files: BTreeMap<&str, &str> = [
        (
            "geometry/curve.rs",
            "// crate::report in a comment is fine\nuse crate::report::save_overlay;\n",
        ),
        ("files.rs", "use crate::{\n    geometry::Point,\n};\n"),
        ("stats.rs", "use crate::geometry::Point;\n"),
        ("newroom.rs", "use crate::stats::median;\n"),
    ]
    .into_iter()
    .collect();
    for (name, text) in &files {
        std::fs::write(src.join(name), text).unwrap();
    }
    let bad = violations(src);
    assert_eq!(bad.len(), 3, "{bad:#?}");
    assert!(bad[0].contains("files.rs:1: the leaf `files` imports `crate::geometry`"));
    assert!(bad[1].contains("curve.rs:2: `geometry` imports `crate::report`"));
    assert!(bad[2].contains("the room `newroom` is not in the layering order"));
}
