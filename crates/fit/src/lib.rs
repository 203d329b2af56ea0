//! metabezier-fit: curve fitting of outlines (thesis ch. 5). Data points
//! from images, CSV files and glyphs ([`outline`]); the fitting problem
//! E = Σ‖R_i − P_i‖², its search spaces and the piecewise fits with C1/G1
//! joins ([`fit`]); sources, methods, the fitting pipeline, DXF and SVG
//! drawings and scores ([`reconstruction`]).
//!
//! | # | room | what lives there |
//! |---|---|---|
//! | 7 | [`outline`] | data points from images, CSV files and glyphs |
//! | 8 | [`fit`] | the fitting problem E = Σ‖R_i − P_i‖², search spaces, piecewise fits (ch. 5) |
//! | 9 | [`reconstruction`] | sources, methods, the fitting pipeline, overlay figure data |
//!
//! A fitting problem knows nothing of the algorithm that solves it. The
//! rooms of `metabezier-core` it stands on are named at this root, so that
//! `crate::geometry` reads as it did in the one-crate house.
#![warn(missing_docs)]

use metabezier_core::{geometry, linalg, optim, problem, rng};
use metabezier_files as files;

pub mod outline;

pub mod fit;

pub mod reconstruction;
