//! `metabezier compare`: its arguments, and the lines it prints.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::error::Error;
use crate::report::{write_compare, CompareOptions};

/// Arguments of `metabezier compare`.
#[derive(Debug, clap::Args)]
pub(super) struct CompareArgs {
    /// Two or more results directories of finished campaigns: the first (A)
    /// is compared with each of the others.
    #[arg(required = true, num_args = 2..)]
    dirs: Vec<PathBuf>,
    /// Output directory [default: A/compare-<B name>].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Significance level of the tests.
    #[arg(long, default_value_t = crate::stats::DEFAULT_ALPHA)]
    alpha: f64,
    /// The region of practical equivalence of a measure's Bayesian
    /// signed-rank test, `MEASURE=HALF-WIDTH` (repeatable), as for `report`.
    #[arg(long, value_name = "MEASURE=HALF-WIDTH", value_parser = super::rope_arg)]
    rope: Vec<(String, f64)>,
}

/// `metabezier compare`: writes the comparison and says what it found.
pub(super) fn compare(args: CompareArgs, w: &mut String) -> Result<(), Error> {
    let opts = CompareOptions {
        out: args.out,
        alpha: args.alpha,
        ropes: args.rope,
    };
    let s = write_compare(&args.dirs, &opts)?;
    let _ = writeln!(
        w,
        "{} and {}: {} shared (configuration, problem) pairs; {} tables, {} plots{}",
        s.markdown.display(),
        s.html.display(),
        s.shared,
        s.tables.len(),
        s.plots.len(),
        if s.identical { "; identical runs" } else { "" }
    );
    for v in &s.verdicts {
        let _ = writeln!(w, "  {v}");
    }
    for note in &s.notes {
        let _ = writeln!(w, "  note: {note}");
    }
    Ok(())
}
