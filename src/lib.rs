//! metabezier: curve reconstruction by metaheuristics on (rational) Bézier
//! functions, with a reproducible experiment runner.
//!
//! It reproduces and extends the thesis "Curve Reconstruction by
//! Metaheuristics Algorithms on Cubic Rational Bézier Function": Bézier
//! geometry ([`geometry`]), the optimisers HS, GHS, GA, PSO and the
//! thesis's Modified HS with CMA-ES and L-SHADE beside them ([`optim`]),
//! piecewise curve fitting to image outlines ([`fit`], [`reconstruction`]),
//! a cranial implant from CT ([`implant`]), and the campaign machinery that
//! runs them from TOML specs, seeded and in parallel, into tidy CSV files
//! ([`experiment`]) and reports ([`report`]).
//!
//! # Quick start
//!
//! **A problem and a run.** A problem is anything that implements
//! [`problem::Problem`]: its dimension, its box and its objective. Every
//! optimiser is reached by name, with its parameters' defaults, and a run
//! is a function of its seed:
//!
//! ```
//! use metabezier::optim::Algorithm;
//! use metabezier::problem::{Bounds, Problem};
//! use metabezier::rng::run_rng;
//!
//! /// Booth's function, f(1, 3) = 0.
//! struct Booth([Bounds; 2]);
//! impl Problem for Booth {
//!     fn dim(&self) -> usize { 2 }
//!     fn bounds(&self) -> &[Bounds] { &self.0 }
//!     fn objective(&self, x: &[f64]) -> f64 {
//!         (x[0] + 2.0 * x[1] - 7.0).powi(2) + (2.0 * x[0] + x[1] - 5.0).powi(2)
//!     }
//! }
//!
//! let booth = Booth([Bounds::new(-10.0, 10.0); 2]);
//! let mhs = Algorithm::default_for("mhs").unwrap();
//! let out = mhs.run(&booth, 20_000, &mut run_rng(1));
//! assert!(out.best_value < 1e-3, "{}", out.best_value);
//! assert!((out.best_x[0] - 1.0).abs() < 0.05 && (out.best_x[1] - 3.0).abs() < 0.05);
//! ```
//!
//! **Parameters.** Each optimiser declares its parameters
//! ([`optim::ParamDef`]); a [`optim::ParamSet`] starts at the defaults and
//! is checked value by value, as a spec is:
//!
//! ```
//! use metabezier::optim::{Algorithm, ParamSet, Raw};
//!
//! let mut p = ParamSet::defaults(Algorithm::params("hs").unwrap());
//! p.set("hmcr", &Raw::Float(0.95)).unwrap();
//! assert!(p.set("hmcr", &Raw::Float(1.5)).is_err());
//! let hs = Algorithm::from_params("hs", &p).unwrap();
//! assert_eq!(hs.name(), "hs");
//! assert!(p.canonical().contains("hmcr=0.95"));
//! ```
//!
//! **A campaign from a spec.** A spec names problems and algorithms; the
//! runner derives each run's seed from the master seed and the run's keys,
//! runs them on every core and writes `runs.csv`, `convergence.csv`,
//! `hits.csv` and the rest; [`report::write_report`] reads them back into
//! `report.md` with its tests and plots. The same files come out of
//! `metabezier run` and `metabezier report`, and with 1 or N threads.
//!
//! ```
//! use std::path::Path;
//! use metabezier::experiment::{run_campaign, RunOptions, Spec};
//!
//! let text = r#"
//! [experiment]
//! name = "doc"
//! seed = 7
//! runs = 3
//! budget = 2000
//!
//! [[problem]]
//! function = ["sphere", "rastrigin"]
//! dim = 5
//!
//! [[algorithm]]
//! name = "hs"
//! label = "HS"
//!
//! [[algorithm]]
//! name = "mhs"
//! label = "MHS"
//! "#;
//! let spec = Spec::parse(Path::new("doc.toml"), text)?;
//! let dir = std::env::temp_dir().join(format!("metabezier-doc-{}", std::process::id()));
//! let opts = RunOptions { out: Some(dir.clone()), threads: Some(2), ..RunOptions::default() };
//! let summary = run_campaign(&spec, &opts)?;
//! assert_eq!((summary.total, summary.executed), (12, 12));
//! let runs = std::fs::read_to_string(dir.join("runs.csv"))?;
//! assert_eq!(runs.lines().count(), 13);
//! # std::fs::remove_dir_all(&dir)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! **Your own optimiser or problem** enters the same campaign through an
//! [`experiment::Registry`]: [`optim::OptimiserDef`] registers an
//! [`optim::Optimiser`] with its parameters, [`experiment::ProblemDef`] a
//! problem family by dimension, and [`experiment::Spec::parse_in`] resolves
//! a spec's names in it. `examples/custom_optimiser.rs` (a (1+1)-ES against
//! HS and MHS) and `examples/custom_problem.rs` (Styblinski–Tang solved by
//! MHS and PSO) do it end to end, report included.
//!
//! # Crates, rooms and the order between them
//!
//! Data flows one way: spec → runner → records → report. The workspace is a
//! stack of crates, each a floor of rooms; a crate depends only on the
//! crates below it, so an upward import does not compile. Inside a crate a
//! room may import the rooms listed before it and never one after it, and
//! its files form no circle: `tests/house/layering.rs` reads every crate's
//! `src/` and fails on an upward import or a circle of files.
//!
//! | crate | rooms (today's paths, re-exported here) | what lives there |
//! |---|---|---|
//! | `metabezier-core` | [`linalg`], [`simd`], [`geometry`], [`stats`], [`rng`], [`problem`], [`functions`], [`optim`], and the formatting half of [`files`] | Bézier geometry (ch. 3), the benchmark functions and optimisers (ch. 4), statistics; no I/O, no C |
//! | `metabezier-files` | [`files`] | atomic writes, the I/O error that names its file |
//! | `metabezier-bbob` | [`functions::bbob`] | COCO's bbob suite, its C core behind the `coco` feature (on by default) |
//! | `metabezier-fit` | [`outline`], [`fit`], [`reconstruction`] | outlines, piecewise fits E = Σ‖R_i − P_i‖², DXF, scores (ch. 5) |
//! | `metabezier-spec` | (`experiment::spec`'s grammar) | TOML read with located errors, for campaigns and the implant |
//! | `metabezier-plot` | [`font`], [`markdown`] and the report's drawing | figures, colours, the embedded font, PNG, Markdown and report.html |
//! | `metabezier-campaign` | [`experiment`] | spec, runner, journal, records, shards, Slurm |
//! | `metabezier-report` | [`report`] | tables, tests and plots of results directories |
//! | `metabezier-implant` | [`ct`], [`implant`] | CT volumes and the chapter-6 implant pipeline |
//! | `metabezier` | [`error`], [`cli`], this facade | the command line and the crate's [`error::Error`] |
//!
//! An optimiser knows nothing of curves or files; a fitting problem knows
//! nothing of the algorithm that solves it; the report reads only what
//! [`experiment::records`] writes; the implant knows nothing of campaigns.
#![warn(missing_docs)]

pub use metabezier_core::{geometry, linalg, optim, problem, rng, simd, stats};
pub use metabezier_files as files;
pub use metabezier_fit::{fit, outline, reconstruction};
pub use metabezier_implant::{ct, implant};
pub use metabezier_plot::{font, markdown};
pub use metabezier_report as report;

/// The ten benchmark functions (thesis ch. 4, `metabezier-core`) and COCO's
/// bbob suite (`metabezier-bbob`).
pub mod functions {
    pub use metabezier_bbob as bbob;
    pub use metabezier_bbob::BbobError;
    #[cfg(feature = "coco")]
    pub use metabezier_bbob::{BbobProblem, CocoObserver};
    pub use metabezier_core::functions::*;
}

/// The campaign machinery (`metabezier-campaign`), with the commit this
/// binary was built from recorded in every campaign it runs.
pub mod experiment {
    pub use metabezier_campaign::*;

    /// `provenance.toml` (`metabezier-campaign`'s), and the commit of this
    /// build.
    pub mod provenance {
        pub use metabezier_campaign::provenance::*;

        /// The git commit the binary was built from (`git rev-parse HEAD`
        /// at build time, by `build.rs`), or "unknown" outside a checkout.
        pub const GIT_COMMIT: &str = env!("METABEZIER_GIT_COMMIT");
    }

    /// Archives of results directories (`metabezier-campaign`'s), and the
    /// software that writes them as this binary names it.
    pub mod archive {
        pub use metabezier_campaign::archive::*;

        /// This binary as its archives name it: its name, its crate
        /// version, and the repository's `CITATION.cff`, embedded at build
        /// time so that an archive is made from the binary alone.
        pub const SOFTWARE: Software<'static> = Software {
            name: env!("CARGO_PKG_NAME"),
            version: env!("CARGO_PKG_VERSION"),
            citation_cff: include_str!("../CITATION.cff"),
        };
    }

    /// [`metabezier_campaign::run_campaign`] with this build's commit
    /// ([`provenance::GIT_COMMIT`]) recorded in `provenance.toml`.
    pub fn run_campaign(spec: &Spec, opts: &RunOptions) -> Result<Summary, ExperimentError> {
        runner::run_campaign_built(spec, opts, provenance::GIT_COMMIT)
    }
}

pub mod error;

pub mod cli;

/// The README's Rust blocks, compiled and run by `cargo test --doc` (so by
/// `make test`), so that what the README shows builds as written.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

/// The guide's library chapter (`docs/guide/library.md`), its Rust blocks
/// compiled and run by `cargo test --doc` as the README's are.
#[cfg(doctest)]
#[doc = include_str!("../docs/guide/library.md")]
pub struct GuideLibraryDoctests;

/// The guide's extending chapter (`docs/guide/extending.md`), its Rust
/// blocks compiled and run by `cargo test --doc`.
#[cfg(doctest)]
#[doc = include_str!("../docs/guide/extending.md")]
pub struct GuideExtendingDoctests;
