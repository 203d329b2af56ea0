//! metabezier-core: the floor every other crate of metabezier stands on,
//! with no I/O and no C: Bézier geometry ([`geometry`], thesis ch. 3), the
//! [`problem::Problem`] an optimiser minimises, seeded random streams
//! ([`rng`]), the ten benchmark functions of Yao, Liu & Lin (1999)
//! ([`functions`], thesis ch. 4), the optimisers and their registry
//! ([`optim`]), descriptive statistics and significance tests ([`stats`]),
//! and the formatting half of result files ([`files`]: reals in shortest
//! round-trip form, CSV bytes).
//!
//! # Rooms and the order between them
//!
//! A room may import the rooms listed before it and never one after it;
//! `tests/house/layering.rs` (at the workspace root) reads every crate's `src/`
//! and fails on an upward import or a circle of files.
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 0 | [`files`], [`linalg`], [`simd`] | leaves: CSV bytes and reals; the Cholesky solve; the vector instruction sets |
//! | 1 | [`rng`] | seed derivation and the random streams |
//! | 2 | [`geometry`] | Bernstein basis, Bézier and rational Bézier curves, joins, offsets (thesis ch. 3) |
//! | 3 | [`stats`] | descriptive statistics and significance tests (the Bayesian signed-rank test draws from [`rng`]) |
//! | 4 | [`problem`] | the [`problem::Problem`] an optimiser minimises |
//! | 5 | [`functions`] | the ten benchmark functions (thesis ch. 4) |
//! | 6 | [`optim`] | HS, GHS, GA, PSO, MHS, CMA-ES, L-SHADE, random search and Levenberg–Marquardt |
//!
//! An optimiser knows nothing of curves or files.
#![warn(missing_docs)]

pub mod files;
pub mod linalg;
pub mod simd;

pub mod rng;

pub mod geometry;
pub mod stats;

pub mod problem;

pub mod functions;

pub mod optim;
