//! Rooms stay small, and the public API says what went wrong in types.
//!
//! - **Files.** No Rust source file of the repository is over
//!   [`MAX_FILE_LINES`] lines, except the few in [`EXEMPT`], each with its
//!   reason (at most [`MAX_EXEMPT`] of them, and each still over the limit,
//!   so that an exemption goes when its file is cut). Functions are held by
//!   clippy's `too_many_lines` (at most 100 code lines, the workspace lint
//!   in `Cargo.toml` and `clippy.toml`).
//! - **Errors.** No public item of the library crates returns or takes
//!   `Result<_, String>`: an error a caller can match is an enum (a
//!   `thiserror` type) whose message names what was expected.

use std::path::{Path, PathBuf};

use crate::layering::{code_of, root, rust_files};

/// The most lines a source file may have.
const MAX_FILE_LINES: usize = 1000;

/// The most exemptions [`EXEMPT`] may list.
const MAX_EXEMPT: usize = 5;

/// Files allowed over [`MAX_FILE_LINES`], each with the reason.
const EXEMPT: &[(&str, &str)] = &[];

/// The folders whose Rust files are counted (build outputs and vendored
/// code aside).
const SOURCE_DIRS: [&str; 7] = [
    "crates",
    "src",
    "tests",
    "examples",
    "benches",
    "python/src",
    "native",
];

/// Every Rust source file of the repository, relative to its root.
fn source_files() -> Vec<PathBuf> {
    let mut out = Vec::new();
    for dir in SOURCE_DIRS {
        let d = root().join(dir);
        if d.is_dir() {
            rust_files(&d, &mut out);
        }
    }
    out.retain(|p| !p.components().any(|c| c.as_os_str() == "target"));
    out.iter()
        .map(|p| p.strip_prefix(root()).unwrap().to_path_buf())
        .collect()
}

fn line_count(path: &Path) -> usize {
    std::fs::read_to_string(root().join(path))
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .lines()
        .count()
}

#[test]
fn no_source_file_is_over_a_thousand_lines() {
    let files = source_files();
    assert!(files.len() > 100, "found only {} source files", files.len());
    let long: Vec<String> = files
        .iter()
        .filter(|p| !EXEMPT.iter().any(|(e, _)| Path::new(e) == p.as_path()))
        .filter_map(|p| {
            let n = line_count(p);
            (n > MAX_FILE_LINES).then(|| format!("{}: {n} lines", p.display()))
        })
        .collect();
    assert!(
        long.is_empty(),
        "files over {MAX_FILE_LINES} lines (cut them along their concepts, one concept per file):\n{}",
        long.join("\n")
    );
}

#[test]
fn exemptions_are_few_reasoned_and_still_needed() {
    assert!(
        EXEMPT.len() <= MAX_EXEMPT,
        "{} exemptions; at most {MAX_EXEMPT}",
        EXEMPT.len()
    );
    for (file, reason) in EXEMPT {
        assert!(reason.len() > 20, "{file}: give the exemption its reason");
        let n = line_count(Path::new(file));
        assert!(
            n > MAX_FILE_LINES,
            "{file} has {n} lines: drop its exemption"
        );
    }
}

/// The type arguments of `Result<...>` starting at `text[open..]` (the
/// `<`), split at the top level.
fn type_arguments(text: &str, open: usize) -> Vec<String> {
    let (mut depth, mut args, mut current) = (0i32, Vec::new(), String::new());
    for c in text[open..].chars() {
        match c {
            '<' | '(' | '[' => {
                depth += 1;
                if depth > 1 {
                    current.push(c);
                }
            }
            '>' | ')' | ']' => {
                depth -= 1;
                if depth == 0 {
                    args.push(current.trim().to_owned());
                    return args;
                }
                current.push(c);
            }
            ',' if depth == 1 => args.push(std::mem::take(&mut current).trim().to_owned()),
            _ if depth >= 1 => current.push(c),
            _ => {}
        }
    }
    args
}

/// Whether `signature` names a `Result` whose error type is `String`.
fn has_string_error(signature: &str) -> bool {
    let mut from = 0;
    while let Some(at) = signature[from..].find("Result<") {
        let open = from + at + "Result".len();
        let args = type_arguments(signature, open);
        if args
            .last()
            .is_some_and(|e| e == "String" || e == "std::string::String")
            && args.len() == 2
        {
            return true;
        }
        // On from the `<`: a `Result` nested in the arguments is read too.
        from = open;
    }
    false
}

/// The public items of `text` whose signature has a `Result<_, String>`:
/// `(line, signature)`. An item is public when it starts with `pub `
/// (not `pub(crate)` or `pub(super)`), or is a method of a `pub trait`;
/// its signature runs to the first `{` or `;` (a function's, where
/// clause included) or a field's ending `,`.
fn string_errors(text: &str) -> Vec<(usize, String)> {
    let lines: Vec<&str> = text.lines().map(code_of).collect();
    let (mut found, mut depth, mut trait_depth) = (Vec::new(), 0i32, None::<i32>);
    let mut i = 0;
    while i < lines.len() {
        let t = lines[i].trim_start();
        let public = t.starts_with("pub ")
            || (trait_depth.is_some_and(|d| depth > d) && t.starts_with("fn "));
        if t.starts_with("pub trait ") && lines[i].contains('{') {
            trait_depth = Some(depth);
        }
        if public {
            let function =
                t.contains("fn ") && t.split("fn ").next().is_some_and(|h| !h.contains(':'));
            let (mut sig, mut j) = (String::new(), i);
            while j < lines.len() {
                sig.push_str(lines[j].trim());
                sig.push(' ');
                let l = lines[j].trim_end();
                if l.contains('{') || l.ends_with(';') || (!function && l.ends_with(',')) {
                    break;
                }
                j += 1;
            }
            let sig = sig.split('{').next().unwrap_or("").to_owned();
            if has_string_error(&sig) {
                found.push((i + 1, sig.trim().to_owned()));
            }
        }
        depth += lines[i].matches('{').count() as i32 - lines[i].matches('}').count() as i32;
        if trait_depth.is_some_and(|d| depth <= d) {
            trait_depth = None;
        }
        i += 1;
    }
    found
}

#[test]
fn no_public_result_with_a_string_error() {
    let mut found = Vec::new();
    for file in source_files() {
        let lib = file.starts_with("crates") && file.components().any(|c| c.as_os_str() == "src");
        if !(lib || file.starts_with("src")) {
            continue;
        }
        let text = std::fs::read_to_string(root().join(&file)).unwrap();
        for (line, sig) in string_errors(&text) {
            found.push(format!("{}:{line}: {sig}", file.display()));
        }
    }
    assert!(
        found.is_empty(),
        "public items with a Result<_, String> (give the error a type):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_check_finds_a_string_error_where_it_is_public() {
    let text = "pub fn a(x: u8) -> Result<Vec<(String, String)>, String> {\n}\n\
                pub(crate) fn b() -> Result<u8, String> {}\n\
                pub fn c() -> Result<u8, ParseError> {}\n\
                pub fn d<B>(\n    x: u8,\n) -> u8\nwhere\n    A: Copy,\n    B: Fn(usize) -> Result<u8, String>,\n{}\n\
                pub trait T {\n    fn e(&self) -> Result<(), String>;\n}\n\
                fn f() -> Result<u8, String> {}\n\
                pub struct S {\n    pub g: HashMap<String, String>,\n}\n\
                pub fn h() -> Result<Result<u8, String>, E> {}\n";
    let lines: Vec<usize> = string_errors(text).into_iter().map(|(l, _)| l).collect();
    assert_eq!(lines, [1, 5, 13, 19]);
}
