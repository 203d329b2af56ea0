//! metabezier: curve reconstruction by metaheuristics on (rational) Bézier
//! functions, with a reproducible experiment runner.
//!
//! Data flows one way: a [`spec::Spec`] is checked, the [`runner`] executes
//! its seeded runs with the [`optim`] optimisers on [`problem::Problem`]s
//! such as the [`functions`], and [`records`] writes the tidy CSV results.
#![warn(missing_docs)]

pub mod cli;
pub mod ct;
pub mod error;
pub mod fit;
pub mod functions;
pub mod geometry;
pub mod implant;
pub mod optim;
pub mod outline;
pub mod problem;
pub mod reconstruction;
pub mod records;
pub mod report;
pub mod rng;
pub mod runner;
pub mod spec;
pub mod stats;
