//! The house stays one-way: every top-level module ("room") of `src/` may
//! import only the rooms listed before it in [`ORDER`], and the leaves
//! import nothing of the crate. The order is the one `src/lib.rs` documents
//! and declares; a new room must be placed in it.
//!
//! Inside a room the files form no circle either: for every module, the
//! references between its child modules (`super::x`, `crate::room::x`,
//! through `use` groups) must be acyclic, so that each file can be read
//! before the ones that import it.
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
    "report",
    "implant",
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

/// The module path of a file under `src/` (`src/a/b.rs` → `[a, b]`,
/// `src/a/mod.rs` → `[a]`).
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut path: Vec<String> = rel
        .components()
        .map(|c| c.as_os_str().to_string_lossy().into_owned())
        .collect();
    if path.last().is_some_and(|l| l == "mod") {
        path.pop();
    }
    path
}

/// The paths a `use`-like tail names (`a::b::{c, d::e}` → `[a,b,c]`,
/// `[a,b,d,e]`), from the start of `s`, each at most a few segments deep.
fn paths_in(s: &str) -> Vec<Vec<String>> {
    fn parse(s: &str, prefix: &[String], out: &mut Vec<Vec<String>>) -> usize {
        let mut path = prefix.to_vec();
        let mut i = 0;
        loop {
            let rest = &s[i..];
            let trimmed = rest.trim_start();
            i += rest.len() - trimmed.len();
            if let Some(group) = trimmed.strip_prefix('{') {
                i += 1;
                let mut consumed = 0;
                let mut g = group;
                loop {
                    let used = parse(g, &path, out);
                    consumed += used;
                    let after = g[used..].trim_start();
                    consumed += g[used..].len() - after.len();
                    if let Some(next) = after.strip_prefix(',') {
                        consumed += 1;
                        g = next;
                        continue;
                    }
                    if after.starts_with('}') {
                        consumed += 1;
                    }
                    break;
                }
                return i + consumed;
            }
            let id = ident_at(trimmed);
            if id.is_empty() {
                out.push(path);
                return i;
            }
            path.push(id.to_owned());
            i += id.len();
            if let Some(_next) = s[i..].strip_prefix("::") {
                i += 2;
            } else {
                out.push(path);
                return i;
            }
        }
    }
    let mut out = Vec::new();
    parse(s, &[], &mut out);
    out
}

/// Every module-to-module reference of `src/` as (file, line, from, to),
/// both absolute module paths (`to` may run on into an item's name).
fn module_references(src: &Path) -> Vec<(PathBuf, usize, Vec<String>, Vec<String>)> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut out = Vec::new();
    for file in files {
        let from = module_of(src, &file);
        if from.len() == 1 && (from[0] == "lib" || from[0] == "main") {
            continue;
        }
        let text = std::fs::read_to_string(&file).unwrap();
        let code: String = text.lines().map(|l| format!("{}\n", code_of(l))).collect();
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < code.len() {
            let rest = &code[i..];
            let word_start = i == 0
                || !(bytes[i - 1].is_ascii_alphanumeric()
                    || matches!(bytes[i - 1], b'_' | b'$' | b':'));
            let (base, skip) = if word_start && rest.starts_with("crate::") {
                (Vec::new(), "crate::".len())
            } else if word_start && rest.starts_with("super::") {
                // `super` of module `a::b` (file `a/b.rs` or `a/b/mod.rs`) is `a`.
                let mut base = from.clone();
                let mut skip = 0;
                while rest[skip..].starts_with("super::") {
                    base.pop();
                    skip += "super::".len();
                }
                (base, skip)
            } else {
                i += rest.chars().next().map_or(1, char::len_utf8);
                continue;
            };
            let line = code[..i].matches('\n').count() + 1;
            for tail in paths_in(&code[i + skip..]) {
                let mut to = base.clone();
                to.extend(tail);
                out.push((file.clone(), line, from.clone(), to));
            }
            i += skip;
        }
    }
    out
}

/// Whether `src/<path>` is a module of its own (a file or a directory).
fn is_module(src: &Path, path: &[String]) -> bool {
    let p = path.iter().fold(src.to_path_buf(), |p, s| p.join(s));
    p.with_extension("rs").is_file() || p.join("mod.rs").is_file()
}

/// The cycles among sibling modules inside each room: for every module
/// `P`, the graph whose nodes are `P`'s children and whose edges are the
/// references of one child's files to another child, and the cycles of it.
fn circles_inside_rooms(src: &Path) -> Vec<String> {
    // (parent, from-child) → to-child → first place seen
    let mut edges: BTreeMap<Vec<String>, BTreeMap<String, BTreeMap<String, String>>> =
        BTreeMap::new();
    for (file, line, from, to) in module_references(src) {
        let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
        if common == 0 || common >= from.len() || common >= to.len() {
            continue; // across rooms (the test above) or a parent and its child
        }
        let parent = from[..common].to_vec();
        let (a, b) = (&from[common], &to[common]);
        let mut child = parent.clone();
        child.push(b.clone());
        if !is_module(src, &child) {
            continue; // an item of the parent, not a sibling module
        }
        edges
            .entry(parent)
            .or_default()
            .entry(a.clone())
            .or_default()
            .entry(b.clone())
            .or_insert_with(|| format!("{}:{line}", file.display()));
    }
    let mut circles = Vec::new();
    for (parent, graph) in &edges {
        // Depth-first search for a back edge, reporting the cycle it closes.
        let mut state: BTreeMap<&str, u8> = BTreeMap::new(); // 1 on the stack, 2 done
        fn visit<'a>(
            n: &'a str,
            graph: &'a BTreeMap<String, BTreeMap<String, String>>,
            state: &mut BTreeMap<&'a str, u8>,
            stack: &mut Vec<&'a str>,
            found: &mut Vec<Vec<String>>,
        ) {
            state.insert(n, 1);
            stack.push(n);
            for (m, _) in graph.get(n).into_iter().flatten() {
                match state.get(m.as_str()) {
                    Some(1) => {
                        let start = stack.iter().position(|s| *s == m).unwrap();
                        let mut cycle: Vec<String> = Vec::new();
                        for w in stack[start..]
                            .iter()
                            .zip(stack[start + 1..].iter().chain([&m.as_str()]))
                        {
                            let place = &graph[*w.0][*w.1];
                            cycle.push(format!("{} → {} ({place})", w.0, w.1));
                        }
                        found.push(cycle);
                    }
                    Some(_) => {}
                    None => visit(m, graph, state, stack, found),
                }
            }
            stack.pop();
            state.insert(n, 2);
        }
        let mut found = Vec::new();
        for n in graph.keys() {
            if !state.contains_key(n.as_str()) {
                visit(n, graph, &mut state, &mut Vec::new(), &mut found);
            }
        }
        for cycle in found {
            circles.push(format!("in `{}`: {}", parent.join("::"), cycle.join(", ")));
        }
    }
    circles
}

#[test]
fn no_circle_inside_a_room() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let circles = circles_inside_rooms(&src);
    assert!(
        circles.is_empty(),
        "circles between the files of a room (move the shared part into a file both import):\n{}",
        circles.join("\n")
    );
}

#[test]
fn the_circle_check_finds_a_circle() {
    let dir = std::env::temp_dir().join(format!("layering-{}", std::process::id()));
    let room = dir.join("room");
    std::fs::create_dir_all(room.join("deep")).unwrap();
    let files = [
        (
            "room/mod.rs",
            "pub mod a;\npub mod b;\npub mod deep;\npub use a::X;\n",
        ),
        ("room/a.rs", "use super::b::Y; // a → b\npub struct X;\n"),
        (
            "room/b.rs",
            "use crate::room::{deep::Z, X};\npub struct Y;\n",
        ),
        (
            "room/deep/mod.rs",
            "use super::super::room::a::X;\npub struct Z;\n",
        ),
    ];
    for (name, text) in files {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let circles = circles_inside_rooms(&dir);
    std::fs::remove_dir_all(&dir).unwrap();
    // b → deep → a → b; `X` through the parent is an item, not a sibling.
    assert_eq!(circles.len(), 1, "{circles:?}");
    let c = &circles[0];
    assert!(c.starts_with("in `room`:"), "{c}");
    for edge in ["a → b", "b → deep", "deep → a"] {
        assert!(c.contains(edge), "{edge} missing from {c}");
    }
}
