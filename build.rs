//! Records the git commit the binary was built from
//! (`METABEZIER_GIT_COMMIT`, "unknown" outside a checkout or without git),
//! which campaigns write to their `provenance.toml`. Only this crate, the
//! binary and its facade, sees the commit: a new commit rebuilds it and none
//! of the crates below it. (COCO's C core is built by `crates/bbob`.)
//!
//! Cargo reruns a build script when a watched file changes, and always when
//! a watched file does not exist; so only files that exist are watched: the
//! HEAD, the loose ref it names, else `packed-refs`, else the refs folder.

use std::path::{Path, PathBuf};
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=METABEZIER_GIT_COMMIT");
    let commit = match std::env::var("METABEZIER_GIT_COMMIT") {
        Ok(c) => c,
        Err(_) => git_commit(),
    };
    println!("cargo:rustc-env=METABEZIER_GIT_COMMIT={commit}");
}

/// `git rev-parse HEAD` of the source tree, or "unknown"; watches the files
/// that say where HEAD points.
fn git_commit() -> String {
    let Some((git_dir, common_dir)) = git_dirs(Path::new(".git")) else {
        return "unknown".into();
    };
    watch(&git_dir.join("HEAD"));
    let head = std::fs::read_to_string(git_dir.join("HEAD")).unwrap_or_default();
    if let Some(r) = head.trim().strip_prefix("ref: ") {
        let loose = common_dir.join(r);
        if !watch(&loose) && !watch(&common_dir.join("packed-refs")) {
            // An unborn branch: the first commit creates the loose ref here.
            watch(&common_dir.join("refs/heads"));
        }
    }
    Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| String::from_utf8(o.stdout).ok())
        .map(|s| s.trim().to_owned())
        .filter(|s| s.len() == 40 && s.bytes().all(|b| b.is_ascii_hexdigit()))
        .unwrap_or_else(|| "unknown".into())
}

/// The git directory and the common directory (where refs live) of the
/// checkout whose `.git` is `dot_git`: a directory, or a file
/// `gitdir: <path>` (a worktree or a submodule).
fn git_dirs(dot_git: &Path) -> Option<(PathBuf, PathBuf)> {
    let git_dir = if dot_git.is_dir() {
        dot_git.to_owned()
    } else {
        let text = std::fs::read_to_string(dot_git).ok()?;
        let path = PathBuf::from(text.trim().strip_prefix("gitdir:")?.trim());
        watch(dot_git);
        path
    };
    let common = match std::fs::read_to_string(git_dir.join("commondir")) {
        Ok(c) => git_dir.join(c.trim()),
        Err(_) => git_dir.clone(),
    };
    Some((git_dir, common))
}

/// Asks cargo to rerun when `path` changes, if it exists; says whether it did.
fn watch(path: &Path) -> bool {
    let exists = path.exists();
    if exists {
        println!("cargo:rerun-if-changed={}", path.display());
    }
    exists
}
