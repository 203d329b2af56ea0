//! A problem suite with its own `[[problem]]` section, defined outside the
//! campaign crate and added by one registration line: Shekel's foxholes
//! S5, S7 and S10 of Dixon & Szegő's test set (L. C. W. Dixon and G. P.
//! Szegő, "The global optimisation problem: an introduction", in Towards
//! Global Optimisation 2, North-Holland 1978, pp. 1–15),
//!
//! `f(x) = −Σ_{i=1}^{m} 1 / (‖x − a_i‖² + c_i)` on `[0, 10]^4`,
//!
//! with their ten points `a_i` and widths `c_i`, for `m` = 5, 7 or 10
//! maxima. A spec names the suite with `suite = "shekel"` and chooses the
//! functions by the suite's own key `maxima`:
//!
//! ```toml
//! [[problem]]
//! suite = "shekel"
//! maxima = [5, 7, 10]
//! ```
//!
//! MHS and PSO solve them into the same `runs.csv` and `report.md` that
//! `metabezier run` and `metabezier report` write.
//!
//! ```text
//! cargo run --release --example shekel_suite -- results/shekel_suite
//! ```

use std::error::Error;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

use metabezier::experiment::spec::{
    FamilyProblem, ProblemFamily, ProblemSection, ProblemSink, RegisteredProblem,
};
use metabezier::experiment::{
    run_campaign, Registry, RunOptions, Spec, SpecError, SpecLimits, Summary,
};
use metabezier::functions::Transform;
use metabezier::problem::{Bounds, Problem};
use metabezier::report::{write_report, ReportOptions};

/// The points `a_i` of Shekel's foxholes (Dixon & Szegő 1978, table 1).
const A: [[f64; 4]; 10] = [
    [4.0, 4.0, 4.0, 4.0],
    [1.0, 1.0, 1.0, 1.0],
    [8.0, 8.0, 8.0, 8.0],
    [6.0, 6.0, 6.0, 6.0],
    [3.0, 7.0, 3.0, 7.0],
    [2.0, 9.0, 2.0, 9.0],
    [5.0, 5.0, 3.0, 3.0],
    [8.0, 1.0, 8.0, 1.0],
    [6.0, 2.0, 6.0, 2.0],
    [7.0, 3.6, 7.0, 3.6],
];

/// The widths `c_i` of the foxholes.
const C: [f64; 10] = [0.1, 0.2, 0.2, 0.4, 0.4, 0.6, 0.3, 0.7, 0.5, 0.5];

/// The numbers of maxima of the suite, with each function's optimum `f*`:
/// the value at the minimiser near `(4, 4, 4, 4)`, found by Newton's
/// method from there to a gradient below 1e-13 (Dixon & Szegő give
/// −10.1532, −10.4029 and −10.5364).
const MAXIMA: [(usize, f64); 3] = [
    (5, -10.153_199_679_058_227),
    (7, -10.402_940_566_818_66),
    (10, -10.536_409_816_692_041),
];

/// Shekel's function with `m` maxima on `[0, 10]^4`.
#[derive(Clone, Debug)]
pub struct Shekel {
    m: usize,
    bounds: Vec<Bounds>,
}

impl Shekel {
    /// The function with the first `m` foxholes.
    pub fn new(m: usize) -> Shekel {
        Shekel {
            m,
            bounds: vec![Bounds::new(0.0, 10.0); 4],
        }
    }
}

impl Problem for Shekel {
    fn dim(&self) -> usize {
        4
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        -A[..self.m]
            .iter()
            .zip(C)
            .map(|(a, c)| {
                let d: f64 = x.iter().zip(a).map(|(xj, aj)| (xj - aj) * (xj - aj)).sum();
                1.0 / (d + c)
            })
            .sum::<f64>()
    }
}

/// The suite: `[[problem]] suite = "shekel"` with its key `maxima`.
#[derive(Debug)]
pub struct ShekelSuite;

impl ProblemFamily for ShekelSuite {
    fn suite(&self) -> &str {
        "shekel"
    }

    fn keys(&self) -> &[&str] {
        &["suite", "maxima", "budget", "budget_per_dim"]
    }

    fn read(
        &self,
        section: &ProblemSection<'_, '_>,
        sink: &mut ProblemSink<'_>,
    ) -> Result<(), SpecError> {
        let field = section.field("maxima");
        let v = section.required(section.table, section.name, "maxima", section.span())?;
        let items = section.one_or_many(v, &field)?;
        sink.reserve(items.len() as u128)?;
        for item in items {
            let m = section.integer(item, &field, 1, 10)? as usize;
            let Some(&(_, optimum)) = MAXIMA.iter().find(|(k, _)| *k == m) else {
                let message = format!("Shekel's functions have 5, 7 or 10 maxima, not {m}");
                return Err(section.error(item.span(), &field, message));
            };
            sink.add(FamilyProblem {
                kind: Arc::new(RegisteredProblem {
                    name: format!("shekel{m}"),
                    optimum,
                    problem: Arc::new(Shekel::new(m)),
                }),
                dim: 4,
                transform: Transform::None,
                instance: 1,
                budget_span: item.span(),
                span: item.span(),
            })?;
        }
        Ok(())
    }

    fn list_entry(&self, _: &Registry) -> String {
        let mut w = String::from(
            "\nShekel's foxholes, Dixon & Szegő 1978 ([[problem]] suite = \"shekel\", maxima = 5, 7 or 10):\n",
        );
        for (m, f_star) in MAXIMA {
            let _ = writeln!(w, "  shekel{m:<10} [0, 10]^4, f* = {f_star}");
        }
        w
    }
}

/// The campaign: S5, S7 and S10 solved by MHS and PSO, five runs each.
pub const SPEC: &str = r#"[experiment]
name = "shekel_suite"
description = "Shekel's foxholes (Dixon & Szegő 1978), a suite with its own section, solved by MHS and PSO"
seed = 2029
runs = 5
budget = 20000
threshold = 1e-6

[[problem]]
suite = "shekel"
maxima = [5, 7, 10]

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "pso"
label = "PSO"
"#;

/// The registry: the built-ins and the Shekel suite.
pub fn registry() -> Registry {
    let mut reg = Registry::with_builtins();
    reg.register_family(Arc::new(ShekelSuite))
        .expect("shekel is a free suite name");
    reg
}

/// Runs the campaign into `out` with `threads` workers (all cores if
/// `None`) and writes its report there.
pub fn campaign(out: &Path, threads: Option<usize>) -> Result<Summary, Box<dyn Error>> {
    let reg = registry();
    let path = Path::new("shekel_suite.toml");
    let spec = Spec::parse_in(path, SPEC, SpecLimits::DEFAULT, &reg)?;
    let options = RunOptions {
        out: Some(out.to_owned()),
        threads,
        resume: true,
        ..RunOptions::default()
    };
    let summary = run_campaign(&spec, &options)?;
    write_report(out, &ReportOptions::default())?;
    Ok(summary)
}

fn main() {
    let mut args = std::env::args_os().skip(1);
    let (Some(out), None) = (args.next(), args.next()) else {
        eprintln!("usage: shekel_suite OUTPUT_DIRECTORY");
        std::process::exit(2);
    };
    match campaign(Path::new(&out), None) {
        Ok(s) => println!(
            "{} runs ({} new) in {}; open {}",
            s.total,
            s.executed,
            s.out.display(),
            s.out.join("report.md").display()
        ),
        Err(e) => {
            eprintln!("shekel_suite: {e}");
            std::process::exit(1);
        }
    }
}
