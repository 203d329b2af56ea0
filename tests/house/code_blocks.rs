//! Every code block of README.md, docs/guide/ and docs/FAQ.md is checked,
//! by its kind (the fence's first word), so that what the documents show
//! works as written:
//!
//! - `rust`: a doctest; the file must be one `src/lib.rs` includes.
//! - `toml`: a spec `metabezier check` accepts (one with `[implant]` an
//!   implant spec the implant's reader accepts); `toml fragment` is a
//!   section of a spec, checked inside a minimal one.
//! - `sh`: run, command by command, in a scratch directory that sees
//!   `data/` and `experiments/`; each must exit 0 (only `metabezier`
//!   and `cmp` run). `sh no_run` (long
//!   campaigns, clusters, installs): each command held to what exists —
//!   a Makefile target, a `metabezier` subcommand and its options, an
//!   example or bench of the crate, or a program named in [`EXTERNAL`].
//! - `python`: run by `python/tests/test_guide.py` (`make test-python`).
//! - `text`: output; not run.
//!
//! A block of any other kind, or a `metabezier` command in a run block
//! that fails, fails the test with the file and line of the block.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::layering::root;

/// Programs a block that runs may call: the binary, and `cmp` to show
/// that two of its files are the same bytes.
const RUNS: [&str; 2] = ["metabezier", "cmp"];

/// Programs a `sh no_run` block may name besides `make`, `metabezier` and
/// `cargo`, each outside the project (so not checked further).
const EXTERNAL: [&str; 3] = ["sbatch", "pip", "python3"];

/// One fenced block: where it starts, its fence's words, its text.
pub(crate) struct Block {
    pub(crate) file: PathBuf,
    pub(crate) line: usize,
    pub(crate) info: Vec<String>,
    pub(crate) text: String,
}

impl Block {
    fn at(&self) -> String {
        format!("{}:{}", self.file.display(), self.line)
    }

    fn kind(&self) -> &str {
        self.info.first().map_or("", String::as_str)
    }

    fn marked(&self, word: &str) -> bool {
        self.info.iter().skip(1).any(|w| w == word)
    }
}

/// The documents whose blocks are checked, relative to the root.
pub(crate) fn documents() -> Vec<PathBuf> {
    let mut files = vec![PathBuf::from("README.md"), PathBuf::from("docs/FAQ.md")];
    let mut guide: Vec<PathBuf> = std::fs::read_dir(root().join("docs/guide"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| p.strip_prefix(root()).unwrap().to_owned())
        .collect();
    guide.sort();
    files.extend(guide);
    files
}

/// The fenced blocks of `file` (relative to the root); a fence may be
/// indented (a block inside a list item), and its indentation is removed
/// from the block's lines.
pub(crate) fn blocks(file: &Path) -> Vec<Block> {
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let mut out = Vec::new();
    let mut open: Option<(usize, usize, Vec<String>, String)> = None;
    for (i, line) in text.lines().enumerate() {
        let trimmed = line.trim_start();
        let indent = line.len() - trimmed.len();
        match (&mut open, trimmed.strip_prefix("```")) {
            (None, Some(info)) => {
                let words = info.split_whitespace().map(str::to_owned).collect();
                open = Some((i + 1, indent, words, String::new()));
            }
            (Some(_), Some("")) => {
                let (line, _, info, text) = open.take().unwrap();
                out.push(Block {
                    file: file.to_owned(),
                    line,
                    info,
                    text,
                });
            }
            (Some((_, indent, _, body)), _) => {
                body.push_str(line.get(*indent..).unwrap_or(line.trim_start()));
                body.push('\n');
            }
            (None, None) => {}
        }
    }
    assert!(
        open.is_none(),
        "{}: a fence is never closed",
        file.display()
    );
    out
}

fn all_blocks() -> Vec<Block> {
    documents().iter().flat_map(|f| blocks(f)).collect()
}

#[test]
fn every_block_is_of_a_kind_the_tests_check() {
    let blocks = all_blocks();
    assert!(blocks.len() >= 15, "only {} blocks found", blocks.len());
    for b in &blocks {
        let known: &[&str] = match b.kind() {
            "rust" | "python" | "text" => &[],
            "toml" => &["fragment"],
            "sh" => &["no_run"],
            other => panic!(
                "{}: a block of kind \"{other}\" is not checked; use rust, toml, sh, python or text",
                b.at()
            ),
        };
        for w in b.info.iter().skip(1) {
            assert!(
                known.contains(&w.as_str()),
                "{}: \"{w}\" is not a mark of a {} block (valid: {known:?})",
                b.at(),
                b.kind()
            );
        }
    }
}

#[test]
fn every_file_with_rust_blocks_is_a_doctest() {
    let lib = std::fs::read_to_string(root().join("src/lib.rs")).unwrap();
    for file in documents() {
        if blocks(&file).iter().any(|b| b.kind() == "rust") {
            let include = format!("include_str!(\"../{}\")", file.display());
            assert!(
                lib.contains(&include),
                "{} has Rust blocks but src/lib.rs does not include it as a doctest ({include})",
                file.display()
            );
        }
    }
}

/// A scratch directory that sees the repository's `data/` and
/// `experiments/`, removed when dropped.
pub(crate) struct Scratch(pub(crate) PathBuf);

impl Scratch {
    pub(crate) fn new(tag: &str) -> Scratch {
        let dir =
            std::env::temp_dir().join(format!("metabezier-blocks-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("bin")).unwrap();
        std::fs::create_dir_all(dir.join("experiments")).unwrap();
        std::os::unix::fs::symlink(root().join("data"), dir.join("data")).unwrap();
        // `experiments/` file by file, so that what a block writes there
        // stays in the scratch directory.
        for e in std::fs::read_dir(root().join("experiments")).unwrap() {
            let e = e.unwrap().path();
            std::os::unix::fs::symlink(&e, dir.join("experiments").join(e.file_name().unwrap()))
                .unwrap();
        }
        let bin = PathBuf::from(env!("CARGO_BIN_EXE_metabezier"));
        std::os::unix::fs::symlink(bin, dir.join("bin/metabezier")).unwrap();
        Scratch(dir)
    }

    /// `sh -c script` in the directory with the binary first on `PATH`.
    pub(crate) fn sh(&self, script: &str) -> std::process::Output {
        let path = format!(
            "{}:{}",
            self.0.join("bin").display(),
            std::env::var("PATH").unwrap_or_default()
        );
        Command::new("sh")
            .args(["-e", "-c", script])
            .current_dir(&self.0)
            .env("PATH", path)
            .output()
            .unwrap()
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A `toml fragment` made a whole spec: an `[experiment]` section first
/// and an algorithm if the fragment has none.
fn whole_spec(fragment: &str) -> String {
    let mut spec =
        "[experiment]\nname = \"fragment\"\nseed = 1\nruns = 1\nbudget = 1000\n\n".to_owned();
    spec.push_str(fragment);
    if !fragment.contains("[[algorithm]]") {
        spec.push_str("\n[[algorithm]]\nname = \"hs\"\n");
    }
    spec
}

#[test]
fn every_toml_block_is_a_spec_the_tools_accept() {
    let scratch = Scratch::new("toml");
    let blocks: Vec<Block> = all_blocks()
        .into_iter()
        .filter(|b| b.kind() == "toml")
        .collect();
    assert!(blocks.len() >= 4, "only {} toml blocks", blocks.len());
    for (k, b) in blocks.iter().enumerate() {
        let spec = scratch.0.join(format!("experiments/block-{k}.toml"));
        let text = if b.marked("fragment") {
            whole_spec(&b.text)
        } else {
            b.text.clone()
        };
        if text.contains("[implant]") {
            let parsed = metabezier::implant::spec::ImplantSpec::parse(&spec, &text);
            assert!(parsed.is_ok(), "{}: {}", b.at(), parsed.unwrap_err());
            continue;
        }
        std::fs::write(&spec, &text).unwrap();
        let out = scratch.sh(&format!("metabezier check '{}'", spec.display()));
        std::fs::remove_file(&spec).unwrap();
        assert!(
            out.status.success(),
            "{}: `metabezier check` refuses the block:\n{}",
            b.at(),
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

/// The commands of a shell block: continuation lines joined, comments
/// (a `#` after a blank, outside quotes) and blank lines left out.
pub(crate) fn commands(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut current = String::new();
    for line in text.lines() {
        let code = strip_comment(line);
        match code.trim_end().strip_suffix('\\') {
            Some(head) => {
                current.push_str(head.trim());
                current.push(' ');
            }
            None => {
                current.push_str(code.trim());
                if !current.trim().is_empty() {
                    out.push(current.trim().to_owned());
                }
                current.clear();
            }
        }
    }
    out
}

fn strip_comment(line: &str) -> &str {
    let mut quote: Option<char> = None;
    let mut prev = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (Some(q), c) if c == q => quote = None,
            (None, '"' | '\'') => quote = Some(c),
            (None, '#') if prev.is_whitespace() => return &line[..i],
            _ => {}
        }
        prev = c;
    }
    line
}

/// The words of a command up to its first redirection, pipe or list
/// operator, after any leading `NAME=value` assignments.
fn words(command: &str) -> Vec<&str> {
    command
        .split_whitespace()
        .take_while(|w| !(w.starts_with('>') || w.starts_with('<') || ["|", "&&", ";"].contains(w)))
        .skip_while(|w| {
            w.split_once('=').is_some_and(|(n, _)| {
                !n.is_empty() && n.chars().all(|c| c.is_ascii_uppercase() || c == '_')
            })
        })
        .collect()
}

#[test]
fn every_sh_block_runs_or_names_what_exists() {
    let blocks: Vec<Block> = all_blocks()
        .into_iter()
        .filter(|b| b.kind() == "sh")
        .collect();
    assert!(
        blocks.iter().any(|b| !b.marked("no_run")),
        "no sh block is run"
    );
    let known = Known::get();
    for (k, b) in blocks.iter().enumerate() {
        let commands = commands(&b.text);
        assert!(!commands.is_empty(), "{}: an empty sh block", b.at());
        if b.marked("no_run") {
            for c in &commands {
                if let Err(why) = known.check(c) {
                    panic!("{}: `{c}`: {why}", b.at());
                }
            }
            continue;
        }
        let scratch = Scratch::new(&format!("sh{k}"));
        for c in &commands {
            assert!(
                words(c).first().is_some_and(|p| RUNS.contains(p)),
                "{}: `{c}` in a block that runs: only {RUNS:?} run here; mark the block `sh no_run`",
                b.at()
            );
            let out = scratch.sh(c);
            assert!(
                out.status.success(),
                "{}: `{c}` failed:\n{}",
                b.at(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// What a `sh no_run` command may name: the Makefile's targets, the
/// binary's subcommands with their long options, the crate's examples and
/// benches.
struct Known {
    targets: Vec<String>,
    options: Vec<(String, Vec<String>)>,
}

impl Known {
    /// The binary's and the Makefile's names, read once for every test.
    fn get() -> &'static Known {
        static KNOWN: std::sync::OnceLock<Known> = std::sync::OnceLock::new();
        KNOWN.get_or_init(Known::read)
    }

    fn read() -> Known {
        let makefile = std::fs::read_to_string(root().join("Makefile")).unwrap();
        let targets = makefile
            .lines()
            .filter(|l| !l.starts_with(['\t', '#', '.']) && !l.contains(":=") && !l.contains("?="))
            .filter_map(|l| l.split_once(':'))
            .flat_map(|(t, _)| t.split_whitespace().map(str::to_owned))
            .collect();
        let help = |args: &[&str]| {
            let out = Command::new(env!("CARGO_BIN_EXE_metabezier"))
                .args(args)
                .output()
                .unwrap();
            String::from_utf8(out.stdout).unwrap()
        };
        let top = help(&["--help"]);
        let subcommands: Vec<String> = top
            .split("Commands:")
            .nth(1)
            .unwrap()
            .split("Options:")
            .next()
            .unwrap()
            .lines()
            .filter_map(|l| l.strip_prefix("  ")?.split_whitespace().next())
            .filter(|s| *s != "help")
            .map(str::to_owned)
            .collect();
        let options = subcommands
            .into_iter()
            .map(|s| {
                let text = help(&[&s, "--help"]);
                let long = text
                    .split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
                    .filter(|w| w.starts_with("--") && w.len() > 2)
                    .map(str::to_owned)
                    .collect();
                (s, long)
            })
            .collect();
        Known { targets, options }
    }

    fn check(&self, command: &str) -> Result<(), String> {
        let w = words(command);
        match w.first().copied() {
            Some("make") => w[1..]
                .iter()
                .filter(|t| !t.starts_with('-'))
                .find(|t| !self.targets.iter().any(|k| k == *t))
                .map_or(Ok(()), |t| Err(format!("no make target \"{t}\" in the Makefile"))),
            Some("metabezier" | "target/release/metabezier") => self.check_metabezier(&w[1..]),
            Some("cargo") => check_cargo(&w[1..]),
            Some(p) if EXTERNAL.contains(&p) => Ok(()),
            other => Err(format!("{other:?} is not a program this test knows (make, metabezier, cargo or {EXTERNAL:?})")),
        }
    }

    fn check_metabezier(&self, args: &[&str]) -> Result<(), String> {
        let sub = args.first().ok_or("no subcommand")?;
        let (_, long) = self
            .options
            .iter()
            .find(|(s, _)| s == sub)
            .ok_or_else(|| format!("no subcommand \"{sub}\" in `metabezier --help`"))?;
        args.iter()
            .filter(|a| a.starts_with("--"))
            .map(|a| a.split('=').next().unwrap())
            .find(|a| !long.iter().any(|l| l == a))
            .map_or(Ok(()), |a| {
                Err(format!("`metabezier {sub}` has no option {a}"))
            })
    }
}

fn check_cargo(args: &[&str]) -> Result<(), String> {
    const SUBCOMMANDS: [&str; 7] = [
        "build",
        "test",
        "run",
        "install",
        "doc",
        "bench",
        "generate-lockfile",
    ];
    let sub = args.first().ok_or("no cargo subcommand")?;
    if !SUBCOMMANDS.contains(sub) {
        return Err(format!("cargo {sub} is not one of {SUBCOMMANDS:?}"));
    }
    for (flag, dir) in [("--example", "examples"), ("--bench", "benches")] {
        if let Some(i) = args.iter().position(|a| *a == flag) {
            let name = args.get(i + 1).ok_or(format!("{flag} without a name"))?;
            if !root().join(dir).join(format!("{name}.rs")).is_file() {
                return Err(format!("no {dir}/{name}.rs"));
            }
        }
    }
    Ok(())
}

#[test]
fn the_shell_reading_splits_and_checks_as_meant() {
    assert_eq!(
        commands("a b \\\n  c # note\n\n# only a comment\nd 'e # f'\n"),
        ["a b c", "d 'e # f'"]
    );
    assert_eq!(words("X_Y=1 make fuzz > log"), ["make", "fuzz"]);
    let known = Known::get();
    assert!(known.check("make quick test").is_ok());
    assert!(known.check("make reproduce-everything").is_err());
    assert!(known
        .check("metabezier fit x.png --tolerance 1 --out d")
        .is_ok());
    assert!(known.check("metabezier fit x.png --tolerence 1").is_err());
    assert!(known.check("metabezier fitt x.png").is_err());
    assert!(known
        .check("cargo run --release --example custom_optimiser -- out")
        .is_ok());
    assert!(known.check("cargo run --example no_such_example").is_err());
    assert!(known.check("rm -rf results").is_err());
}

#[test]
fn the_commands_table_names_every_subcommand() {
    let table = std::fs::read_to_string(root().join("docs/guide/running.md")).unwrap();
    for (sub, _) in &Known::get().options {
        assert!(
            table.contains(&format!("| `metabezier {sub}")),
            "docs/guide/running.md's commands table has no row for `metabezier {sub}`"
        );
    }
}
