//! A problem defined outside the crate, run by two built-in optimisers in
//! the same campaign machinery: the Styblinski–Tang function (Styblinski &
//! Tang 1990, "Experiments in nonconvex optimization: stochastic
//! approximation with function smoothing and simulated annealing", Neural
//! Networks 3(4):467–483), `f(x) = ½ Σ (x_i⁴ − 16 x_i² + 5 x_i)` on
//! `[−5, 5]^D`, whose minimum `f* = −39.16616570377142 · D` lies at
//! `x_i = −2.903534…`. It is registered by name, a spec names it beside a
//! built-in function, and MHS and PSO solve it into the same `runs.csv`
//! and `report.md` that `metabezier run` and `metabezier report` write.
//!
//! ```text
//! cargo run --release --example custom_problem -- results/custom_problem
//! ```

use std::error::Error;
use std::path::Path;

use metabezier::experiment::{
    run_campaign, BuildError, ProblemDef, Registry, RunOptions, Spec, SpecLimits, Summary,
};
use metabezier::problem::{Bounds, Problem};
use metabezier::report::{write_report, ReportOptions};

/// The Styblinski–Tang function at a dimension.
#[derive(Clone, Debug)]
pub struct StyblinskiTang {
    bounds: Vec<Bounds>,
}

/// `f*/D`: the one-dimensional minimum at `x = −2.903534027771178`.
pub const OPTIMUM_PER_DIM: f64 = -39.166_165_703_771_41;

impl StyblinskiTang {
    /// The function on `[−5, 5]^dim`.
    pub fn new(dim: usize) -> Result<Self, BuildError> {
        if dim == 0 {
            return Err("the dimension must be at least 1".into());
        }
        Ok(StyblinskiTang {
            bounds: vec![Bounds::new(-5.0, 5.0); dim],
        })
    }
}

impl Problem for StyblinskiTang {
    fn dim(&self) -> usize {
        self.bounds.len()
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    fn objective(&self, x: &[f64]) -> f64 {
        0.5 * x
            .iter()
            .map(|&v| v * v * v * v - 16.0 * v * v + 5.0 * v)
            .sum::<f64>()
    }
}

/// The campaign: Styblinski–Tang at D = 2, 5 and 10 beside Sphere at
/// D = 5, solved by MHS and PSO, ten runs each.
pub const SPEC: &str = r#"[experiment]
name = "custom_problem"
description = "A problem defined outside the crate, solved by MHS and PSO"
seed = 2028
runs = 10
budget = 20000
threshold = 1e-6

[[problem]]
function = "styblinski_tang"
dim = [2, 5, 10]

[[problem]]
function = "sphere"
dim = 5

[[algorithm]]
name = "mhs"
label = "MHS"

[[algorithm]]
name = "pso"
label = "PSO"
"#;

/// The registry: the built-ins and Styblinski–Tang.
pub fn registry() -> Registry {
    let mut reg = Registry::with_builtins();
    reg.register_problem(ProblemDef::new(
        "styblinski_tang",
        "Styblinski & Tang 1990",
        StyblinskiTang::new,
        |dim| OPTIMUM_PER_DIM * dim as f64,
    ))
    .expect("styblinski_tang is a free name");
    reg
}

/// Runs the campaign into `out` with `threads` workers (all cores if
/// `None`) and writes its report there.
pub fn campaign(out: &Path, threads: Option<usize>) -> Result<Summary, Box<dyn Error>> {
    let reg = registry();
    let spec = Spec::parse_in(
        Path::new("custom_problem.toml"),
        SPEC,
        SpecLimits::DEFAULT,
        &reg,
    )?;
    let summary = run_campaign(
        &spec,
        &RunOptions {
            out: Some(out.to_owned()),
            threads,
            resume: true,
            ..RunOptions::default()
        },
    )?;
    write_report(out, &ReportOptions::default())?;
    Ok(summary)
}

fn main() {
    let mut args = std::env::args_os().skip(1);
    let (Some(out), None) = (args.next(), args.next()) else {
        eprintln!("usage: custom_problem OUTPUT_DIRECTORY");
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
            eprintln!("custom_problem: {e}");
            std::process::exit(1);
        }
    }
}
