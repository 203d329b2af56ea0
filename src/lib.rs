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
//! # Rooms and the order between them
//!
//! Data flows one way: spec → runner → records → report. The crate is a
//! stack of rooms (top-level modules); a room may import the rooms listed
//! before it and never one after it, and the leaves import nothing of the
//! crate; inside a room, the files form no circle. `tests/layering.rs`
//! reads `src/` and fails on an upward import or a circle of files.
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 0 | [`files`], [`font`], [`linalg`], [`markdown`], [`simd`] | leaves: atomic writes, CSV bytes and reals; the embedded font; the Cholesky solve; Markdown tables and report.html pages; the vector instruction sets |
//! | 1 | [`geometry`] | Bernstein basis, Bézier and rational Bézier curves, joins, offsets (thesis ch. 3) |
//! | 2 | [`stats`] | descriptive statistics and significance tests |
//! | 3 | [`rng`] | seed derivation and the random streams |
//! | 4 | [`problem`] | the [`problem::Problem`] an optimiser minimises |
//! | 5 | [`functions`] | the ten benchmark functions (thesis ch. 4) |
//! | 6 | [`optim`] | HS, GHS, GA, PSO, MHS, L-SHADE, random search and Levenberg–Marquardt |
//! | 7 | [`outline`] | data points from images, CSV files and glyphs |
//! | 8 | [`fit`] | the fitting problem E = Σ‖R_i − P_i‖², search spaces, piecewise fits (ch. 5) |
//! | 9 | [`reconstruction`] | sources, methods, the fitting pipeline, overlay figure data |
//! | 10 | [`ct`] | CT volumes, bone masks, contours, meshes, previews |
//! | 11 | [`experiment`] | spec, runner, journal, records: the campaign machinery |
//! | 12 | [`report`] | tables, tests and plots of results directories |
//! | 13 | [`implant`] | the chapter-6 implant pipeline and its run (its report draws with [`report`]'s plots and colours) |
//! | 14 | [`error`] | the crate's [`error::Error`], wrapping each room's error |
//! | 15 | [`cli`] | the command line |
//!
//! An optimiser knows nothing of curves or files; a fitting problem knows
//! nothing of the algorithm that solves it; the report reads only what
//! [`experiment::records`] writes.
#![warn(missing_docs)]

pub mod files;
pub mod font;
pub mod linalg;
pub mod markdown;
pub mod simd;

pub mod geometry;
pub mod stats;

pub mod rng;

pub mod problem;

pub mod functions;

pub mod optim;

pub mod outline;

pub mod fit;

pub mod reconstruction;

pub mod ct;

pub mod experiment;

pub mod report;

pub mod implant;

pub mod error;

pub mod cli;
