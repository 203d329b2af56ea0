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

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::list;
    use crate::problem::{Bounds, Problem};
    use crate::registry::{ProblemDef, Registry};
    use crate::spec::{ProblemFamily, ProblemSection, ProblemSink, SpecError};

    /// `f(x) = Σ |x_i|` on `[−1, 1]^D`.
    struct Abs(Vec<Bounds>);

    impl Problem for Abs {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn bounds(&self) -> &[Bounds] {
            &self.0
        }
        fn objective(&self, x: &[f64]) -> f64 {
            x.iter().map(|v| v.abs()).sum()
        }
    }

    /// A suite with no problems, whose entry names it.
    #[derive(Debug)]
    struct Empty;

    impl ProblemFamily for Empty {
        fn suite(&self) -> &str {
            "empty"
        }
        fn keys(&self) -> &[&str] {
            &["suite"]
        }
        fn read(
            &self,
            _: &ProblemSection<'_, '_>,
            _: &mut ProblemSink<'_>,
        ) -> Result<(), SpecError> {
            Ok(())
        }
        fn list_entry(&self, _: &Registry) -> String {
            "\nThe empty suite ([[problem]] suite = \"empty\")\n".to_owned()
        }
    }

    #[test]
    fn the_list_shows_registered_problems_and_suites() {
        let builtin = list(Registry::builtin());
        assert!(!builtin.contains("abs_sum"));
        let mut reg = Registry::with_builtins();
        reg.register_problem(ProblemDef::new(
            "abs_sum",
            "a test of the list",
            |d| Ok(Abs(vec![Bounds::new(-1.0, 1.0); d])),
            |_| 0.0,
        ))
        .unwrap();
        reg.register_family(Arc::new(Empty)).unwrap();
        let text = list(&reg);
        assert!(
            text.contains("  abs_sum          registered: a test of the list\n"),
            "{text}"
        );
        // The suite's entry follows COCO's, before the fitting methods.
        let bbob = text.find("COCO's bbob suite").unwrap();
        let empty = text.find("The empty suite").unwrap();
        let fitting = text.find("Fitting methods").unwrap();
        assert!(bbob < empty && empty < fitting, "{text}");
        // Nothing else changes.
        assert_eq!(
            text.replace("  abs_sum          registered: a test of the list\n", "")
                .replace("\nThe empty suite ([[problem]] suite = \"empty\")\n", ""),
            builtin
        );
    }
}
