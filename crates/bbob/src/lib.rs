//! The 24 noiseless functions of COCO's `bbob` suite (Hansen, Finck, Ros &
//! Auger 2009, "Real-parameter black-box optimization benchmarking 2009:
//! noiseless functions definitions", INRIA RR-6829), evaluated by COCO's own
//! C code (coco-experiment 2.8.2, vendored in `vendor/coco/` under its
//! BSD-3-Clause licence and compiled by this crate's `build.rs` with the
//! `coco` feature), so that the functions,
//! instances, optima and targets are exactly COCO's.
//!
//! A [`BbobProblem`] owns its COCO problem handle: each run creates its own,
//! so runs in parallel threads never share COCO state. COCO ends the process
//! on invalid arguments, so every argument is checked here first
//! (`BbobProblem::check`).
//!
//! Without the `coco` feature this crate holds only the suite's names,
//! dimensions and groups (pure Rust), and no C is compiled.

#![warn(missing_docs)]

#[cfg(feature = "coco")]
mod coco;

#[cfg(feature = "coco")]
pub use coco::{BbobProblem, CocoObserver, Observed};

/// The dimensions COCO's bbob suite defines.
pub const BBOB_DIMENSIONS: [usize; 6] = [2, 3, 5, 10, 20, 40];

/// COCO's short names of the 24 bbob functions, by index 1..=24.
pub const BBOB_NAMES: [&str; 24] = [
    "sphere",
    "ellipsoid",
    "rastrigin",
    "bueche-rastrigin",
    "linear-slope",
    "attractive-sector",
    "step-ellipsoid",
    "rosenbrock",
    "rosenbrock-rotated",
    "ellipsoid-rotated",
    "discus",
    "bent-cigar",
    "sharp-ridge",
    "different-powers",
    "rastrigin-rotated",
    "weierstrass",
    "schaffers-f7",
    "schaffers-f7-ill",
    "griewank-rosenbrock",
    "schwefel",
    "gallagher-101",
    "gallagher-21",
    "katsuura",
    "lunacek",
];

/// The five function groups of the bbob suite (Hansen et al. 2009), by the
/// first function index of each.
pub fn bbob_group(function: usize) -> &'static str {
    match function {
        1..=5 => "separable",
        6..=9 => "moderate conditioning",
        10..=14 => "high conditioning, unimodal",
        15..=19 => "multimodal, adequate structure",
        _ => "multimodal, weak structure",
    }
}

/// The index 1..=24 of a bbob function given by number or COCO name
/// (`f8`, `8` or `rosenbrock`).
pub fn bbob_function(name: &str) -> Option<usize> {
    let n = name.trim();
    let number = n.strip_prefix('f').unwrap_or(n);
    if let Ok(i) = number.parse::<usize>() {
        return (1..=24).contains(&i).then_some(i);
    }
    BBOB_NAMES.iter().position(|b| *b == n).map(|i| i + 1)
}

/// Why a bbob problem cannot be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BbobError {
    /// The function index is not 1..=24.
    #[error("bbob has functions 1 to 24 (or their COCO names), not {0}")]
    Function(usize),
    /// COCO's bbob suite has no such dimension.
    #[error("bbob is defined for the dimensions 2, 3, 5, 10, 20 and 40, not {0}")]
    Dimension(usize),
    /// The instance number is not ≥ 1.
    #[error("bbob instances are numbered from 1 (up to 1000000), not {0}")]
    Instance(usize),
    /// A log folder or algorithm name COCO cannot take (COCO's option
    /// parser splits at white space).
    #[error("COCO cannot log into \"{0}\": the folder and algorithm names must be non-empty, at most 1000 bytes, without white space or NUL bytes")]
    Name(String),
    /// COCO refused the problem although its arguments were checked.
    #[error("COCO could not build bbob f{function} in {dimension}D, instance {instance}")]
    Refused {
        /// The function.
        function: usize,
        /// The dimension.
        dimension: usize,
        /// The instance.
        instance: usize,
    },
}
