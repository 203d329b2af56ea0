//! Shared by the benchmarks: reading criterion's results back for the
//! summary tables they print.

use std::path::Path;

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
