//! metabezier: curve reconstruction by metaheuristics on (rational) Bézier
//! functions, with a reproducible experiment runner.
//!
//! # Rooms and the order between them
//!
//! Data flows one way: spec → runner → records → report. The crate is a
//! stack of rooms (top-level modules); a room may import the rooms listed
//! before it and never one after it, and the leaves import nothing of the
//! crate. `tests/layering.rs` reads `src/` and fails on an upward import.
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 0 | [`files`], [`font`], [`linalg`], [`markdown`], [`simd`] | leaves: atomic writes, CSV bytes and reals; the embedded font; the Cholesky solve; Markdown tables; the vector instruction sets |
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
//! | 12 | [`implant`] | the chapter-6 implant pipeline and its run |
//! | 13 | [`report`] | tables, tests and plots of results directories |
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

pub mod implant;

pub mod report;

pub mod error;

pub mod cli;
