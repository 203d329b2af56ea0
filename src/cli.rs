//! The command line: argument parsing and dispatch to the library.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::error::Error;
use crate::functions::Function;
use crate::optim::Algorithm;
use crate::report::{self, ReportOptions};
use crate::runner::{self, RunOptions, Shard};
use crate::spec::Spec;

/// Appends one line of output to the buffer printed when the command ends.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {
        let _ = writeln!($out, $($arg)*);
    };
}

/// metabezier: curve reconstruction by metaheuristics, and a reproducible
/// experiment runner for the optimisers.
#[derive(Debug, Parser)]
#[command(name = "metabezier", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run an experiment spec: repeated seeded runs, in parallel, to tidy CSV.
    Run {
        /// The experiment spec (TOML).
        spec: PathBuf,
        /// Output directory [default: results/<experiment name>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads [default: all cores]; results do not depend on it.
        #[arg(long, value_parser = clap::value_parser!(u16).range(1..))]
        threads: Option<u16>,
        /// Continue a campaign in the output directory, keeping finished runs.
        #[arg(long)]
        resume: bool,
        /// Run only slice K of N (for array jobs); join with `metabezier merge`.
        #[arg(long, value_name = "K/N", value_parser = Shard::parse)]
        shard: Option<Shard>,
        /// Stop after this many new runs; continue later with --resume.
        #[arg(long, value_name = "N")]
        max_runs: Option<usize>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Check a spec and print what it would run, without running it.
    Check {
        /// The experiment spec (TOML).
        spec: PathBuf,
    },
    /// Join the result directories of all shards of a campaign.
    Merge {
        /// The shard directories (each holds spec.toml and runs.csv).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory [default: results/<experiment name>].
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Write report.md, tables/*.csv and plots/ for a results directory.
    Report {
        /// A results directory of `metabezier run` or `metabezier merge`.
        dir: PathBuf,
        /// The algorithm the others are tested against: a label (`MHS`) or a
        /// configuration as the report names it [default: MHS if present].
        #[arg(long, value_name = "NAME")]
        reference: Option<String>,
        /// Significance level of the tests.
        #[arg(long, default_value_t = crate::stats::DEFAULT_ALPHA)]
        alpha: f64,
        /// A runs.csv from elsewhere (same columns) to add to the comparison.
        #[arg(long, value_name = "CSV")]
        external: Option<PathBuf>,
    },
    /// List the algorithms with their parameters, and the benchmark functions.
    List,
}

/// Parses the command line, runs it, and reports errors on stderr.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut text = String::new();
    let result = dispatch(cli, &mut text);
    // A closed pipe (`metabezier list | head`) is not an error worth a panic.
    let mut stdout = std::io::stdout().lock();
    let _ = stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush());
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("metabezier: error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn dispatch(cli: Cli, w: &mut String) -> Result<(), Error> {
    match cli.command {
        Command::Run {
            spec,
            out,
            threads,
            resume,
            shard,
            max_runs,
            quiet,
        } => {
            let spec = Spec::load(&spec)?;
            let opts = RunOptions {
                out,
                threads: threads.map(usize::from),
                resume,
                shard,
                max_runs,
                progress: !quiet,
            };
            let s = runner::run_campaign(&spec, &opts)?;
            let state = if s.complete {
                format!("complete; results in {}", s.out.join("runs.csv").display())
            } else {
                format!(
                    "{} of {} runs finished; continue with --resume",
                    s.reused + s.executed,
                    s.total
                )
            };
            say!(
                w,
                "{}: {} runs ({} reused, {} executed), {state}",
                spec.name,
                s.total,
                s.reused,
                s.executed
            );
            Ok(())
        }
        Command::Check { spec } => {
            let spec = Spec::load(&spec)?;
            say!(w, "{}: valid", spec.path.display());
            say!(w,
                "experiment {} (seed {}): {} problems × {} algorithm cells × {} runs = {} runs, {} evaluations",
                spec.name,
                spec.seed,
                spec.problems.len(),
                spec.cells.len(),
                spec.runs,
                spec.run_ids().len(),
                spec.total_evaluations()
            );
            for p in &spec.problems {
                say!(w, "  problem {} (budget {})", p.key(), p.budget);
            }
            for c in &spec.cells {
                say!(w, "  cell    {} [{}]", c.label, c.params.canonical());
            }
            Ok(())
        }
        Command::Merge { dirs, out } => {
            let copy = dirs[0].join("spec.toml");
            let text = std::fs::read_to_string(&copy).map_err(|e| Error::io("read", &copy, e))?;
            let spec = Spec::parse(&copy, &text)?;
            let s = runner::merge(&spec, &dirs, out)?;
            say!(
                w,
                "{}: merged {} shard directories, {} runs, into {}",
                spec.name,
                dirs.len(),
                s.total,
                s.out.display()
            );
            Ok(())
        }
        Command::Report {
            dir,
            reference,
            alpha,
            external,
        } => {
            let opts = ReportOptions {
                reference,
                alpha,
                external,
            };
            let s = report::write_report(&dir, &opts)?;
            say!(
                w,
                "{}: {} algorithm configurations × {} problems, {} runs; {} tables, {} plots",
                s.report.display(),
                s.algorithms,
                s.problems,
                s.runs,
                s.tables.len(),
                s.plots.len()
            );
            for note in &s.notes {
                say!(w, "  note: {note}");
            }
            Ok(())
        }
        Command::List => {
            say!(
                w,
                "Algorithms (parameters with defaults and admissible values):"
            );
            for name in Algorithm::NAMES {
                say!(w, "\n  {name}");
                for d in Algorithm::params(name).unwrap_or(&[]) {
                    say!(
                        w,
                        "    {:<10} = {:<12} {} ({})",
                        d.name,
                        d.default.to_string(),
                        d.doc,
                        d.expected()
                    );
                }
            }
            say!(w, "\nBenchmark functions (name, domain, optimum):");
            for f in Function::ALL {
                let b = f.domain();
                let dim = match f.fixed_dim() {
                    Some(d) => format!(", dimension {d} only"),
                    None => String::new(),
                };
                say!(
                    w,
                    "  {:<16} [{}, {}]^D, f* = {}{dim}",
                    f.name(),
                    b.lower,
                    b.upper,
                    f.optimum_value()
                );
            }
            Ok(())
        }
    }
}
