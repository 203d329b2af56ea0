//! Tests of the CT data layer (`metabezier::ct`) on synthetic data, on the
//! vendored ProMED CT 0051 extract and on pydicom's CT_small.dcm.

use crate::common;
use crate::ct_inputs;
use common::oblique_axes;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use metabezier::ct::*;
use metabezier::geometry::Point;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The vendored extract, read once per test binary.
fn ct0051() -> &'static Volume {
    static V: OnceLock<Volume> = OnceLock::new();
    V.get_or_init(|| read_inv3(&root().join(CT0051_PATH)).expect("vendored CT"))
}

/// Vendored slice index of original slice `z`.
fn vz(z: usize) -> usize {
    z - CT0051_FIRST_Z
}

/// A closed polygon of `n` points on the circle of centre `c` and radius `r`.
fn circle(c: Point, r: f64, n: usize) -> Polyline {
    Polyline::closed(
        (0..n)
            .map(|i| {
                let t = std::f64::consts::TAU * i as f64 / n as f64;
                c + Point::new(r * t.cos(), r * t.sin())
            })
            .collect(),
    )
}

mod anatomy;
mod frames;
mod hardened;
mod mesh;
mod readers;
