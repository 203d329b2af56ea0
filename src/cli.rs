//! The command line: argument parsing and dispatch to the library.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand};

use crate::error::Error;
use crate::experiment::runner::{self, RunOptions, Shard};
use crate::experiment::slurm::{self, SlurmOptions};
use crate::experiment::Registry;
use crate::experiment::{coco_log, Spec, SpecError, SpecLimits};
use crate::files::{check_output_dir, IoError};
use crate::geometry::Point;
use crate::outline::{load_svg, OutlineError};
use crate::reconstruction::{score, ContourChoice, LoadOptions, Source, SourceError};
use crate::report::{self, ReportOptions};

/// Appends one line of output to the buffer printed when the command ends.
macro_rules! say {
    ($out:expr, $($arg:tt)*) => {
        let _ = writeln!($out, $($arg)*);
    };
}

mod archive;
mod compare;
mod fit;
mod fit_outputs;
mod list_markdown;
mod named;

use archive::ArchiveArgs;
use fit::FitArgs;

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
        /// Output directory [default: results/<experiment name>]; a shard
        /// writes into its own shard-K-of-N/ beneath it.
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
        #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
        max_runs: Option<u32>,
        /// No progress bar.
        #[arg(long, short)]
        quiet: bool,
        /// Also write COCO-format logs of the bbob runs into this directory
        /// (for cocopp), by replaying them on one thread once they finish.
        #[arg(long, value_name = "DIR")]
        coco_log: Option<PathBuf>,
        /// Run campaigns over 10 million runs, an estimated 4 GiB of results
        /// in memory, or 10^10 evaluations per run.
        #[arg(long)]
        allow_large: bool,
    },
    /// Check a spec and print what it would run, without running it; exits
    /// non-zero, with `run`'s message, where `run` would refuse it.
    Check {
        /// The experiment spec (TOML).
        spec: PathBuf,
        /// Check under `run --allow-large`'s limits.
        #[arg(long)]
        allow_large: bool,
    },
    /// Join the shards of a campaign into files equal to a single run's.
    Merge {
        /// The directory holding the shard-K-of-N/ directories (the --out of
        /// the shards), or the shard directories themselves.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory [default: the one directory given, when it holds
        /// the shards; else results/<experiment name>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// The campaign's spec [default: the shards' copy]; needed when the
        /// spec names fitting inputs by paths relative to itself.
        #[arg(long)]
        spec: Option<PathBuf>,
    },
    /// Print a Slurm array job (an sbatch script) that runs a campaign as
    /// N shards, one per task.
    Slurm(SlurmArgs),
    /// Write report.md, tables/*.csv, plots/ and report.html (the same as one
    /// page) for a results directory.
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
        /// The correction of the post-hoc tests after Friedman's test.
        #[arg(long, default_value = "holm", value_parser = named::named::<crate::report::PostHoc>())]
        post_hoc: crate::report::PostHoc,
        /// The region of practical equivalence of a measure's Bayesian
        /// signed-rank test, `MEASURE=HALF-WIDTH` (repeatable): final-error
        /// in decades [default 0.3, or the spec's `[report]`], anytime-auc
        /// [default 0.05]. A verdict is `equivalent` where P(rope) ≥ 0.95.
        #[arg(long, value_name = "MEASURE=HALF-WIDTH", value_parser = rope_arg)]
        rope: Vec<(String, f64)>,
        /// A claims file (experiments/claims.toml): the summary answers each
        /// thesis claim of this campaign with its primary row first.
        #[arg(long, value_name = "TOML")]
        claims: Option<PathBuf>,
        /// Exit 0 even when figures the results should allow could not be
        /// drawn (the report is written and names them either way).
        #[arg(long)]
        keep_going: bool,
    },
    /// Compare two or more campaigns' results directories side by side:
    /// compare.md, compare.html, tables/ and plots/ (A against the others).
    Compare(compare::CompareArgs),
    /// Bundle a results directory (one campaign, or a results/ directory of
    /// several) into a reproducible .tar.gz with CITATION.cff, SHA256SUMS
    /// and Zenodo's .zenodo.json; or check one with --verify.
    Archive(ArchiveArgs),
    /// Fit piecewise (rational) Bézier curves to an outline.
    Fit(Box<FitArgs>),
    /// Score the paths of an SVG file (another tool's curves) against the
    /// outline points `fit` would use: orthogonal max and RMS distance.
    Score(ScoreArgs),
    /// List the algorithms with their parameters, and the benchmark functions.
    List {
        /// Print the documents' tables instead: the optimisers and "Which
        /// optimiser?" by dimension and budget, as Markdown.
        #[arg(long)]
        markdown: bool,
    },
    /// Design a cranial implant from CT slices (thesis chapter 6): the real
    /// defect to implant.stl, overlays, a 3D preview, and the
    /// artificial-defect validation.
    Implant {
        /// The chapter-6 spec (TOML, see `experiments/ch6_cranial.toml`).
        spec: PathBuf,
        /// Output directory [default: results/<spec file stem>].
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write the implant of the slices that pass the plausibility
        /// checks as implant.partial.stl (the report's first line names the
        /// refused slices) instead of refusing the whole design.
        #[arg(long)]
        allow_partial: bool,
    },
}

/// Arguments of `metabezier slurm`.
#[derive(Debug, clap::Args)]
struct SlurmArgs {
    /// The experiment spec (TOML).
    spec: PathBuf,
    /// Array tasks, one shard each (at most the campaign's runs).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    tasks: u32,
    /// The campaign's output directory, on a filesystem every node sees
    /// [default: results/<experiment name>]; the shards go beneath it.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Time limit per task, HH:MM:SS or D-HH:MM:SS [default: the partition's].
    #[arg(long, value_name = "HH:MM:SS")]
    time: Option<String>,
    /// CPUs per task; each task runs that many threads [default: 1].
    #[arg(long, value_name = "C", value_parser = clap::value_parser!(u16).range(1..))]
    cpus: Option<u16>,
    /// Further sbatch options, one #SBATCH line each, such as
    /// "--partition=short --account=proj".
    #[arg(long, value_name = "ARGS", allow_hyphen_values = true)]
    sbatch: Option<String>,
    /// Allow a campaign over 10 million runs, an estimated 4 GiB of results
    /// or 10^10 evaluations per run (each task runs with --allow-large).
    #[arg(long)]
    allow_large: bool,
}

/// Arguments of `metabezier score`.
#[derive(Debug, clap::Args)]
struct ScoreArgs {
    /// The outline: a PNG image, a CSV file of x,y points, or font:PATH:GLYPH.
    input: String,
    /// The SVG file whose paths are scored (M L H V C S Q T Z; translate,
    /// scale and matrix transforms).
    curves: PathBuf,
    /// Added to the SVG's coordinates after reflecting y about the
    /// viewBox: potrace puts pixel corners at integers, so its output needs
    /// -0.5,-0.5 against an image's outline points.
    #[arg(long, value_name = "DX,DY", value_parser = parse_offset, allow_hyphen_values = true, default_value = "0,0")]
    offset: Point,
    /// Score against this contour only (0 is the largest); default all.
    #[arg(long, value_name = "N")]
    contour: Option<usize>,
    /// Write score.csv into this directory.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// An `--offset` that is not two numbers `DX,DY`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("expected an offset DX,DY of two finite numbers, such as -0.5,-0.5, found \"{0}\"")]
struct OffsetError(String);

/// Parses `DX,DY`.
fn parse_offset(text: &str) -> Result<Point, OffsetError> {
    let bad = || OffsetError(text.to_owned());
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    let x: f64 = x.trim().parse().map_err(|_| bad())?;
    let y: f64 = y.trim().parse().map_err(|_| bad())?;
    if !(x.is_finite() && y.is_finite()) {
        return Err(bad());
    }
    Ok(Point::new(x, y))
}

/// Parses the command line, runs it, and reports errors on stderr.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    let mut text = String::new();
    let result = dispatch(cli, &mut text);
    let written = write_stdout(text.as_bytes());
    match result {
        Ok(()) => match written {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                let _ = writeln!(
                    std::io::stderr(),
                    "metabezier: error: cannot write the output: {e}"
                );
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            // A closed or full stderr must not turn the error into a panic.
            let _ = writeln!(std::io::stderr(), "metabezier: error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Writes `bytes` to standard output and flushes it. A reader that closed
/// the pipe early (`metabezier list | head`) is not an error; any other
/// failure (a full disk behind `> job.sh`) is, so that no command exits 0
/// after losing its output.
fn write_stdout(bytes: &[u8]) -> std::io::Result<()> {
    let mut stdout = std::io::stdout().lock();
    match stdout.write_all(bytes).and_then(|()| stdout.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => other,
    }
}

/// Runs one subcommand, appending its output to `w`.
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
            coco_log,
            allow_large,
        } => {
            let opts = RunOptions {
                out,
                threads: threads.map(usize::from),
                resume,
                shard,
                max_runs: max_runs.map(|n| n as usize),
                progress: !quiet,
                allow_large,
            };
            run(&spec, &opts, coco_log.as_deref(), w)
        }
        Command::Check { spec, allow_large } => check(&spec, allow_large, w),
        Command::Merge { dirs, out, spec } => merge(&dirs, out, spec.as_deref(), w),
        Command::Slurm(args) => slurm(args, w),
        Command::Report {
            dir,
            reference,
            alpha,
            external,
            post_hoc,
            rope,
            claims,
            keep_going,
        } => {
            let opts = ReportOptions {
                reference,
                alpha,
                external,
                post_hoc,
                ropes: rope,
                families: crate::report::Families::default(),
                claims,
            };
            write_report(&dir, &opts, keep_going, w)
        }
        Command::Compare(args) => compare::compare(args, w),
        Command::Archive(args) => archive::archive(args, w),
        Command::Fit(args) => fit::fit(*args, w),
        Command::Score(args) => score_curves(args, w),
        Command::Implant {
            spec,
            out,
            allow_partial,
        } => implant(&spec, out, allow_partial, w),
        Command::List { markdown } => {
            if markdown {
                w.push_str(&list_markdown::list_markdown(Registry::builtin()));
            } else {
                list(w);
            }
            Ok(())
        }
    }
}

/// `metabezier run`: load the spec, run (or resume) the campaign, and say
/// how far it got.
fn run(
    spec: &Path,
    opts: &RunOptions,
    coco_log: Option<&Path>,
    w: &mut String,
) -> Result<(), Error> {
    let spec = Spec::load_with(spec, SpecLimits::new(opts.allow_large))?;
    if let Some(dir) = coco_log {
        // Refuse a spec without bbob problems or an unwritable folder
        // before anything runs.
        coco_log::check(&spec, dir)?;
    }
    let s = crate::experiment::run_campaign(&spec, opts)?;
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
    for dropped in &s.dropped {
        say!(w, "  warning: {dropped}");
    }
    if let Some(dir) = coco_log {
        if s.complete {
            for folder in coco_log::write_coco_log(&spec, opts.shard, dir)? {
                say!(w, "  COCO log in {}", folder.display());
            }
        } else {
            say!(w, "  the COCO log is written when the campaign is complete");
        }
    }
    Ok(())
}

/// `metabezier check`: load the spec under `run`'s limits, refuse it as
/// `run` would, and list its problems and cells.
fn check(spec: &Path, allow_large: bool, w: &mut String) -> Result<(), Error> {
    let spec = Spec::load_with(spec, SpecLimits::new(allow_large))?;
    let opts = RunOptions {
        allow_large,
        ..RunOptions::default()
    };
    runner::check_limits(&spec, &opts).map_err(crate::experiment::ExperimentError::from)?;
    say!(w, "{}: valid", spec.path.display());
    say!(w,
        "experiment {} (seed {}): {} problems × {} algorithm cells × {} runs = {} runs, {} evaluations",
        spec.name,
        spec.seed,
        spec.problems.len(),
        spec.cells.len(),
        spec.runs,
        spec.run_count(),
        spec.total_evaluations()
    );
    say!(
        w,
        "estimated memory of the results before they are written: {:.1} MiB",
        runner::estimated_bytes(&spec) as f64 / f64::from(1u32 << 20)
    );
    for p in &spec.problems {
        say!(w, "  problem {} (budget {})", p.key(), p.budget);
    }
    for c in &spec.cells {
        say!(w, "  cell    {} [{}]", c.label, c.params.canonical());
    }
    Ok(())
}

/// `metabezier merge`: find the shards, check them, and join them, with
/// the spec given or else the one copied into the first.
fn merge(
    dirs: &[PathBuf],
    out: Option<PathBuf>,
    spec: Option<&Path>,
    w: &mut String,
) -> Result<(), Error> {
    let inputs = crate::experiment::find_shards(dirs)?;
    let spec = match spec {
        // The shards ran already: merging is not refused for their size.
        Some(path) => Spec::load_with(path, SpecLimits::LARGE)?,
        None => {
            let copy = inputs.dirs[0].join("spec.toml");
            Spec::parse_with(&copy, &SpecError::read(&copy)?, SpecLimits::LARGE)?
        }
    };
    let s = crate::experiment::shards::merge_found(&spec, &inputs, out)?;
    say!(
        w,
        "{}: merged {} shard directories, {} runs, into {}",
        spec.name,
        inputs.dirs.len(),
        s.total,
        s.out.display()
    );
    Ok(())
}

/// `metabezier slurm`: print the sbatch array script of a campaign, with
/// absolute paths so that it runs from any directory of the cluster.
fn slurm(a: SlurmArgs, w: &mut String) -> Result<(), Error> {
    let spec = Spec::load_with(&a.spec, SpecLimits::new(a.allow_large))?;
    let limits = RunOptions {
        allow_large: a.allow_large,
        ..RunOptions::default()
    };
    runner::check_limits(&spec, &limits).map_err(crate::experiment::ExperimentError::from)?;
    let absolute =
        |p: &Path| std::path::absolute(p).map_err(|e| IoError::new("resolve the path", p, e));
    let exe = std::env::current_exe()
        .map_err(|e| IoError::new("find the running binary", Path::new("metabezier"), e))?;
    let out = runner::campaign_dir(&spec, a.out.as_deref(), None);
    let opts = SlurmOptions {
        tasks: a.tasks as usize,
        out: absolute(&out)?,
        time: a.time,
        cpus: a.cpus,
        sbatch: a.sbatch,
        allow_large: a.allow_large,
    };
    let script = slurm::sbatch_script(&spec, &absolute(&a.spec)?, &exe, &opts)
        .map_err(crate::experiment::ExperimentError::from)?;
    w.push_str(&script);
    Ok(())
}

/// `metabezier report`: write the report of a results directory and list
/// its notes.
fn write_report(
    dir: &Path,
    opts: &ReportOptions,
    keep_going: bool,
    w: &mut String,
) -> Result<(), Error> {
    let s = report::write_report(dir, opts)?;
    say!(
        w,
        "{} and {}: {} algorithm configurations × {} problems, {} runs; {} tables, {} plots",
        s.report.display(),
        s.html.display(),
        s.algorithms,
        s.problems,
        s.runs,
        s.tables.len(),
        s.plots.len()
    );
    for note in &s.notes {
        say!(w, "  note: {note}");
    }
    if s.faults.is_empty() || keep_going {
        Ok(())
    } else {
        Err(Error::Figures {
            report: s.report,
            faults: s.faults,
        })
    }
}

/// `metabezier list`: the algorithms with their parameters, and the
/// benchmark functions.
fn list(w: &mut String) {
    w.push_str(&crate::experiment::listing::list(Registry::builtin()));
}

/// `metabezier implant`: load and check the spec, then run it; nothing is
/// written when the spec is invalid, and the STL only for a checked mesh.
fn implant(
    spec: &Path,
    out: Option<PathBuf>,
    allow_partial: bool,
    w: &mut String,
) -> Result<(), Error> {
    let s = crate::implant::ImplantSpec::load(spec)?;
    let out = out.unwrap_or_else(|| {
        let stem = spec
            .file_stem()
            .map_or("implant".into(), |n| n.to_string_lossy().into_owned());
        PathBuf::from("results").join(stem)
    });
    check_output_dir(&out)?;
    let options = crate::implant::RunOptions { allow_partial };
    let r = crate::implant::run_implant_with(&s, &out, options)?;
    if let Some(t) = r.pipeline_seconds {
        say!(w, "real defect: load to STL in {t:.2} s");
    }
    if r.validation_rows > 0 {
        say!(w, "validation: {} rows", r.validation_rows);
    }
    if r.validation_3d_rows > 0 {
        say!(w, "3D validation: {} rows", r.validation_3d_rows);
    }
    say!(w, "{} files written to {}", r.files.len(), out.display());
    Ok(())
}

/// `metabezier score`: the orthogonal distances of the outline's points to
/// the SVG's curves, printed and (with `--out`) written to `score.csv`.
fn score_curves(a: ScoreArgs, w: &mut String) -> Result<(), Error> {
    let load = LoadOptions {
        contour: a.contour.map_or(ContourChoice::All, ContourChoice::Index),
        ..LoadOptions::default()
    };
    let source = Source::load(&a.input, Path::new(""), &load)?;
    let svg = load_svg(&a.curves).map_err(|e| SourceError(OutlineError::Svg(e)))?;
    let s = score(&source, &svg.to_frame(a.offset)).map_err(|source| Error::Score {
        curves: a.curves.clone(),
        source,
    })?;
    let curves = a.curves.display().to_string();
    let skipped = match svg.skipped {
        0 => String::new(),
        n => format!(" ({n} path(s) in non-rendered containers skipped)"),
    };
    say!(
        w,
        "{} against {curves} (offset {},{}): {} segments{skipped}",
        a.input,
        a.offset.x,
        a.offset.y,
        s.segments
    );
    say!(
        w,
        "  curve -> data {:.6} (the curves sampled against the outline polylines); Hausdorff distance {:.6}",
        s.curve_distance,
        s.hausdorff
    );
    say!(
        w,
        "  {:<8} {:>8} {:>14} {:>14}",
        "contour",
        "points",
        "max distance",
        "RMS distance"
    );
    let mut rows = Vec::new();
    let named = s
        .contours
        .iter()
        .map(|(c, d)| (c.to_string(), *d))
        .chain(std::iter::once(("all".to_owned(), s.total)));
    for (name, d) in named {
        say!(
            w,
            "  {:<8} {:>8} {:>14.6} {:>14.6}",
            name,
            d.points,
            d.max_distance,
            d.rms_distance
        );
        rows.push(vec![
            a.input.clone(),
            curves.clone(),
            a.offset.x.to_string(),
            a.offset.y.to_string(),
            name.clone(),
            d.points.to_string(),
            if name == "all" {
                s.segments.to_string()
            } else {
                String::new()
            },
            d.max_distance.to_string(),
            d.rms_distance.to_string(),
            if name == "all" {
                s.curve_distance.to_string()
            } else {
                String::new()
            },
            if name == "all" {
                s.hausdorff.to_string()
            } else {
                String::new()
            },
        ]);
    }
    if let Some(dir) = &a.out {
        crate::files::create_dir(dir)?;
        let path = dir.join("score.csv");
        let header = [
            "input",
            "curves",
            "offset_x",
            "offset_y",
            "contour",
            "points",
            "segments",
            "max_distance",
            "rms_distance",
            "curve_distance",
            "hausdorff",
        ];
        crate::files::write_atomic(&path, &crate::files::csv_bytes(&header, rows))?;
        say!(w, "  wrote {}", path.display());
    }
    Ok(())
}

/// A `--rope` value, `MEASURE=HALF-WIDTH`: a measure of
/// [`crate::report::Ropes::NAMES`] and a finite half-width ≥ 0, checked
/// once here.
fn rope_arg(text: &str) -> Result<(String, f64), String> {
    let (measure, value) = text.split_once('=').ok_or_else(|| {
        format!(
            "expected MEASURE=HALF-WIDTH, such as final-error=0.3; the measures are {}",
            crate::report::Ropes::NAMES.join(", ")
        )
    })?;
    let x: f64 = value
        .trim()
        .parse()
        .map_err(|_| format!("\"{value}\" is not a number (expected MEASURE=HALF-WIDTH)"))?;
    crate::report::Ropes::default()
        .set(measure.trim(), x)
        .map_err(|e| e.to_string())?;
    Ok((measure.trim().to_owned(), x))
}
