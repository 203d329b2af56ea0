//! What `metabezier list` prints: the registered optimisers with their
//! parameters, each problem family's entry (the thesis's functions and the
//! registered problems, then every suite), and the fitting methods and
//! functions of `[[fit]]`.

use std::fmt::Write as _;

use crate::fit::FunctionType;
use crate::reconstruction::Method;
use crate::registry::Registry;
use crate::spec::{Functions, ProblemFamily};

/// The text of `metabezier list` for the names `registry` resolves.
///
/// ```
/// use metabezier_campaign::{listing::list, Registry};
///
/// let text = list(Registry::builtin());
/// assert!(text.contains("  mhs  ("));
/// assert!(text.contains("COCO's bbob suite"));
/// ```
pub fn list(registry: &Registry) -> String {
    let mut w = optimisers(registry);
    w.push_str(&Functions.list_entry(registry));
    for family in registry.families() {
        w.push_str(&family.list_entry(registry));
    }
    w.push_str(&fitting());
    w
}

/// The optimisers with their parameters' defaults and admissible values.
fn optimisers(registry: &Registry) -> String {
    let mut w = String::from("Algorithms (parameters with defaults and admissible values):\n");
    for def in registry.optimisers.iter() {
        let _ = writeln!(w, "\n  {}  ({})", def.name, def.source);
        let defs = def.params;
        if defs.is_empty() {
            let _ = writeln!(w, "    (no parameters)");
        }
        let width = defs.iter().map(|d| d.name.len()).max().unwrap_or(0);
        for d in defs {
            let _ = writeln!(
                w,
                "    {:<width$} = {:<12} {} ({})",
                d.name,
                d.default.to_string(),
                d.doc,
                d.expected()
            );
        }
    }
    w
}

/// The methods and the curve functions of `[[fit]]` sections.
fn fitting() -> String {
    let mut w =
        String::from("\nFitting methods ([[fit]] problems and `metabezier fit --algorithm`):\n");
    let _ = writeln!(
        w,
        "  {:<16} Levenberg–Marquardt from the linear least-squares fit (Levenberg 1944; Marquardt 1963)",
        Method::EXACT
    );
    let _ = writeln!(
        w,
        "  {:<16} any algorithm above on 80 % of the budget, then an LM polish, e.g. mhs{}",
        format!("<name>{}", Method::POLISH_SUFFIX),
        Method::POLISH_SUFFIX
    );
    w.push_str("\nFitting functions ([[fit]] function = ..., `metabezier fit --function`):\n");
    for f in FunctionType::ALL {
        let _ = writeln!(
            w,
            "  {:<20} degree {}{}",
            f.name(),
            f.degree(),
            if f.is_rational() {
                ", rational (inner weights free)"
            } else {
                ""
            }
        );
    }
    w
}
