//! Shared by the benchmarks: the uniform points their bare loops evaluate,
//! and reading criterion's results back for the summary tables they print.

use std::path::Path;

use metabezier::problem::Problem;
use metabezier::rng::{run_rng, Draw};

/// `n` points drawn uniformly in `problem`'s box from `run_rng(1)`, one
/// `u ~ U[0, 1)` a variable, `x_i = L_i + u·(U_i − L_i)` (`Bounds::lerp`):
/// the points a bare loop evaluates, the same in every benchmark. (The
/// fitting benchmarks draw none.)
#[allow(dead_code)]
pub fn uniform_points<P: Problem + ?Sized>(problem: &P, n: usize) -> Vec<Vec<f64>> {
    let mut rng = run_rng(1);
    (0..n)
        .map(|_| {
            problem
                .bounds()
                .iter()
                .map(|b| b.lerp(rng.unit()))
                .collect()
        })
        .collect()
}

/// Reads criterion's mean time per iteration (ns) of one benchmark from
/// `target/criterion/<group>/<id>/new/estimates.json` (under
/// `$CARGO_TARGET_DIR` when that is set, where criterion writes then).
pub fn mean_ns(group: &str, id: &str) -> Option<f64> {
    let target = std::env::var_os("CARGO_TARGET_DIR").unwrap_or_else(|| "target".into());
    let path = Path::new(&target)
        .join("criterion")
        .join(group)
        .join(id)
        .join("new/estimates.json");
    let text = std::fs::read_to_string(path).ok()?;
    let at = text.find("\"mean\"")?;
    let rest = &text[at..];
    let p = rest.find("\"point_estimate\":")? + "\"point_estimate\":".len();
    let end = rest[p..].find([',', '}'])?;
    rest[p..p + end].trim().parse().ok()
}
