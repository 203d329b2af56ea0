//! Compiles COCO's C core (vendor/coco, BSD-3-Clause) with metabezier's own
//! shim (native/coco_shim.c) through the `cc` crate: the bbob suite needs
//! only the C compiler every machine has, no libclang and no bindgen.
//!
//! Also records the git commit the binary was built from
//! (`METABEZIER_GIT_COMMIT`, "unknown" outside a checkout or without git),
//! which campaigns write to their `provenance.toml`.

use std::path::Path;
use std::process::Command;

fn main() {
    println!("cargo:rerun-if-changed=native/coco_shim.c");
    println!("cargo:rerun-if-changed=vendor/coco/coco.c");
    println!("cargo:rerun-if-changed=vendor/coco/coco.h");
    cc::Build::new()
        .file("native/coco_shim.c")
        .include("vendor/coco")
        .opt_level(2)
        .warnings(false)
        .flag_if_supported("-w")
        .compile("coco_shim");
    println!("cargo:rustc-env=METABEZIER_GIT_COMMIT={}", git_commit());
}

/// `git rev-parse HEAD` of the source tree, or "unknown"; asks cargo to
/// rerun when HEAD or the branch it names moves.
fn git_commit() -> String {
    println!("cargo:rerun-if-env-changed=METABEZIER_GIT_COMMIT");
    if let Ok(c) = std::env::var("METABEZIER_GIT_COMMIT") {
        return c;
    }
    let git = Path::new(".git");
    if !git.is_dir() {
        return "unknown".into();
    }
    println!("cargo:rerun-if-changed=.git/HEAD");
    println!("cargo:rerun-if-changed=.git/packed-refs");
    if let Ok(head) = std::fs::read_to_string(git.join("HEAD")) {
        if let Some(r) = head.trim().strip_prefix("ref: ") {
            println!("cargo:rerun-if-changed=.git/{r}");
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
