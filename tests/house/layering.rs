//! The house stays one-way, on two levels.
//!
//! **Crates.** The workspace's crates are its floors, in [`CRATES`] order;
//! a crate may depend only on the crates listed before it (its
//! `Cargo.toml`), and the compiler refuses any import its dependencies do
//! not allow. So an upward import across floors does not compile.
//!
//! **Rooms inside a crate.** Every top-level module ("room") of a crate
//! with several rooms may import only the rooms listed before it, and the
//! leaves import nothing of the crate; a crate of one room (the campaign,
//! the report) is that room. The rooms of lower crates that a crate uses
//! are named at its root (`use metabezier_core::{geometry, optim};`), so
//! `crate::geometry` may name them: they sit below every room of the crate.
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

/// One floor: its package, its source folder, its leaves (they import
/// nothing of the crate) and its other rooms from the bottom up. A crate of
/// one room has neither.
struct Floor {
    package: &'static str,
    src: &'static str,
    leaves: &'static [&'static str],
    order: &'static [&'static str],
}

/// The workspace's crates from the bottom up: each may depend only on
/// those before it.
const CRATES: [Floor; 10] = [
    Floor {
        package: "metabezier-core",
        src: "crates/core/src",
        leaves: &["files", "linalg", "simd"],
        order: &["rng", "geometry", "stats", "problem", "functions", "optim"],
    },
    Floor {
        package: "metabezier-files",
        src: "crates/files/src",
        leaves: &[],
        order: &[],
    },
    Floor {
        package: "metabezier-bbob",
        src: "crates/bbob/src",
        leaves: &[],
        order: &[],
    },
    Floor {
        package: "metabezier-fit",
        src: "crates/fit/src",
        leaves: &[],
        order: &["outline", "fit", "reconstruction"],
    },
    Floor {
        package: "metabezier-spec",
        src: "crates/spec/src",
        leaves: &[],
        order: &[],
    },
    Floor {
        package: "metabezier-plot",
        src: "crates/plot/src",
        leaves: &["font", "markdown", "png"],
        order: &["format", "style", "render", "layout", "factor_lines"],
    },
    Floor {
        package: "metabezier-campaign",
        src: "crates/campaign/src",
        leaves: &[],
        order: &[],
    },
    Floor {
        package: "metabezier-report",
        src: "crates/report/src",
        leaves: &[],
        order: &[],
    },
    Floor {
        package: "metabezier-implant",
        src: "crates/implant/src",
        leaves: &[],
        order: &["ct", "implant"],
    },
    Floor {
        package: "metabezier",
        src: "src",
        leaves: &[],
        order: &["error", "cli"],
    },
];

pub(crate) fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The rooms of a crate, leaves first: `(name, rank)`, leaves at rank 0.
fn rooms(floor: &Floor) -> Vec<(&'static str, usize)> {
    let mut out: Vec<(&str, usize)> = floor.leaves.iter().map(|l| (*l, 0)).collect();
    out.extend(floor.order.iter().enumerate().map(|(i, r)| (*r, i + 1)));
    out
}

/// The names a crate's root imports from the crates below it
/// (`use metabezier_core::{geometry, optim};`, `use metabezier_files as
/// files;`, the facade's `pub use` and its `pub mod functions { … }` of
/// re-exports): `crate::geometry` may name them from any room.
fn imported_rooms(lib: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in lib.lines().filter(|l| !l.starts_with(' ')) {
        if let Some(facade) = line
            .strip_prefix("pub mod ")
            .and_then(|l| l.strip_suffix(" {"))
        {
            out.push(facade.to_owned()); // a facade module of re-exports
            continue;
        }
        let line = line.strip_prefix("pub ").unwrap_or(line);
        let Some(rest) = line.strip_prefix("use metabezier_") else {
            continue;
        };
        let rest = rest.trim_end_matches(';');
        if let Some((_, alias)) = rest.split_once(" as ") {
            out.push(alias.trim().to_owned());
        } else if let Some((_, group)) = rest.split_once("::{") {
            out.extend(
                group
                    .trim_end_matches('}')
                    .split(',')
                    .map(|n| n.trim().to_owned())
                    .filter(|n| !n.is_empty()),
            );
        } else if let Some((_, name)) = rest.rsplit_once("::") {
            out.push(name.to_owned());
        }
    }
    out
}

pub(crate) fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
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
pub(crate) fn code_of(line: &str) -> &str {
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

/// The upward (or unknown) imports of the crate `floor` whose source is
/// `src`, one message each; `imported` are the lower crates' rooms its root
/// names.
fn violations(src: &Path, floor: &Floor, imported: &[String]) -> Vec<String> {
    let rooms = rooms(floor);
    let rank = |room: &str| rooms.iter().find(|(r, _)| *r == room).map(|(_, k)| *k);
    let mut bad = Vec::new();
    if rooms.is_empty() {
        return bad; // one room: only the circle check applies
    }
    for (file, line, from, to) in references(src) {
        if from == to {
            continue;
        }
        let at = format!("{}:{line}", file.display());
        match (rank(&from), rank(&to)) {
            (None, _) => bad.push(format!(
                "{at}: the room `{from}` is not in the layering order; add it to CRATES (tests/house/layering.rs) and to the table in its lib.rs"
            )),
            (_, None) if imported.contains(&to) => {}
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
    let mut bad = Vec::new();
    for floor in &CRATES {
        let src = root().join(floor.src);
        let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
        bad.extend(violations(&src, floor, &imported_rooms(&lib)));
    }
    assert!(bad.is_empty(), "upward imports:\n{}", bad.join("\n"));
}

#[test]
fn each_lib_declares_its_rooms_in_the_layering_order() {
    for floor in CRATES.iter().filter(|f| !f.order.is_empty()) {
        let lib = std::fs::read_to_string(root().join(floor.src).join("lib.rs")).unwrap();
        let declared: Vec<&str> = lib
            .lines()
            .filter_map(|l| l.trim().strip_prefix("pub mod "))
            .filter_map(|l| l.strip_suffix(';'))
            .collect();
        let mut expected: Vec<&str> = floor.leaves.to_vec();
        expected.extend(floor.order);
        assert_eq!(declared, expected, "{}", floor.package);
    }
}

/// The `metabezier*` packages a crate's `Cargo.toml` depends on (normal
/// dependencies).
fn crate_dependencies(manifest: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut in_deps = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            in_deps = line == "[dependencies]";
            continue;
        }
        if in_deps && line.starts_with("metabezier") {
            let name: String = line
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-' || *c == '_')
                .collect();
            out.push(name);
        }
    }
    out
}

#[test]
fn each_crate_depends_only_on_the_floors_below_it() {
    let members: Vec<String> = std::fs::read_to_string(root().join("Cargo.toml"))
        .unwrap()
        .lines()
        .filter_map(|l| l.trim().strip_prefix("\"crates/"))
        .map(|l| l.trim_end_matches("\",").to_owned())
        .collect();
    let listed: Vec<&str> = CRATES
        .iter()
        .filter_map(|f| f.src.strip_prefix("crates/")?.strip_suffix("/src"))
        .collect();
    assert_eq!(
        members, listed,
        "the workspace's members are the floors, in order"
    );
    for (k, floor) in CRATES.iter().enumerate() {
        let dir = root().join(floor.src).parent().unwrap().to_owned();
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        for dep in crate_dependencies(&manifest) {
            let place = CRATES.iter().position(|f| f.package == dep);
            assert!(
                place.is_some_and(|p| p < k),
                "{} depends on {dep}, which is not a floor below it",
                floor.package
            );
        }
    }
    let core = std::fs::read_to_string(root().join("crates/core/Cargo.toml")).unwrap();
    assert!(
        crate_dependencies(&core).is_empty(),
        "the core stands on nothing"
    );
    for heavy in [
        "dicom", "plotters", "image", "clap", "tar", "flate2", "cc", "toml",
    ] {
        assert!(
            !core
                .lines()
                .any(|l| l.trim().starts_with(&format!("{heavy} "))
                    || l.trim().starts_with(&format!("{heavy}."))),
            "metabezier-core depends on {heavy}"
        );
    }
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
    let bad = violations(src, &CRATES[0], &[]);
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
/// In a crate of one room (`one_room`), its top-level modules are that
/// room's files.
fn circles_inside_rooms(src: &Path, one_room: bool) -> Vec<String> {
    // (parent, from-child) → to-child → first place seen
    let mut edges: BTreeMap<Vec<String>, BTreeMap<String, BTreeMap<String, String>>> =
        BTreeMap::new();
    for (file, line, mut from, mut to) in module_references(src) {
        if one_room {
            from.insert(0, String::new());
            to.insert(0, String::new());
        }
        let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
        if common == 0 || common >= from.len() || common >= to.len() {
            continue; // across rooms (the test above) or a parent and its child
        }
        let parent = from[..common].to_vec();
        let (a, b) = (&from[common], &to[common]);
        let mut child = parent.clone();
        child.push(b.clone());
        if !is_module(src, &child[usize::from(one_room)..]) {
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
            let name = parent
                .iter()
                .filter(|p| !p.is_empty())
                .cloned()
                .collect::<Vec<_>>();
            let name = if name.is_empty() {
                "the crate root".to_owned()
            } else {
                name.join("::")
            };
            circles.push(format!(
                "in {}: `{}`: {}",
                src.display(),
                name,
                cycle.join(", ")
            ));
        }
    }
    circles
}

#[test]
fn no_circle_inside_a_room() {
    let mut circles = Vec::new();
    for floor in &CRATES {
        let one_room = floor.order.is_empty() && floor.leaves.is_empty();
        circles.extend(circles_inside_rooms(&root().join(floor.src), one_room));
    }
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
    let circles = circles_inside_rooms(&dir, false);
    std::fs::remove_dir_all(&dir).unwrap();
    // b → deep → a → b; `X` through the parent is an item, not a sibling.
    assert_eq!(circles.len(), 1, "{circles:?}");
    let c = &circles[0];
    assert!(c.contains(": `room`:"), "{c}");
    for edge in ["a → b", "b → deep", "deep → a"] {
        assert!(c.contains(edge), "{edge} missing from {c}");
    }
}

#[test]
fn a_crate_of_one_room_is_checked_at_its_root() {
    let dir = tempfile::tempdir().unwrap();
    let files = [
        ("lib.rs", "pub mod a;\npub mod b;\n"),
        ("a.rs", "use crate::b::Y;\npub struct X;\n"),
        ("b.rs", "use super::a::X;\npub struct Y;\n"),
    ];
    for (name, text) in files {
        std::fs::write(dir.path().join(name), text).unwrap();
    }
    let circles = circles_inside_rooms(dir.path(), true);
    assert_eq!(circles.len(), 1, "{circles:?}");
    assert!(circles[0].contains("the crate root"), "{}", circles[0]);
    // As a crate of several rooms, a and b are rooms: no circle inside one.
    assert!(circles_inside_rooms(dir.path(), false).is_empty());
}
