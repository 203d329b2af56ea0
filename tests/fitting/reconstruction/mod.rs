//! Curve reconstruction on the vendored real outlines, end to end: the
//! library path, `metabezier fit`, and fitting campaigns declared in specs.

use std::path::{Path, PathBuf};
use std::process::Command;

use metabezier::experiment::Spec;
use metabezier::experiment::{merge, run_campaign, RunOptions, Shard};
use metabezier::fit::{FitOptions, FunctionType};
use metabezier::geometry::{Continuity, Parameterisation};
use metabezier::optim::Algorithm;
use metabezier::outline::CornerOptions;
use metabezier::reconstruction::{
    ContourChoice, LoadOptions, Method, Reconstruction, Segmentation, Source,
};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines")
}

fn source(input: &str) -> Source {
    let options = LoadOptions {
        contour: ContourChoice::Index(0),
        ..LoadOptions::default()
    };
    Source::load(input, &data(), &options).unwrap()
}

fn metabezier() -> Command {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
}

fn fit_error(args: &[&str]) -> String {
    let tmp = tempfile::tempdir().unwrap();
    let out = metabezier()
        .current_dir(data())
        .arg("fit")
        .args(args)
        .arg("--out")
        .arg(tmp.path())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{args:?} should fail");
    assert!(
        std::fs::read_dir(tmp.path()).unwrap().next().is_none(),
        "{args:?} wrote files"
    );
    String::from_utf8(out.stderr).unwrap()
}

mod campaigns;
mod fit_command;
mod glyphs_and_score;
