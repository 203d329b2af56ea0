//! An optimiser written outside the crate, in the same campaign as the
//! built-ins: a (1+1)-ES with the one-fifth success rule (Rechenberg 1973;
//! Schumer & Steiglitz 1968; the step-size update of Kern et al. 2004,
//! "Learning probability distributions in continuous evolutionary
//! algorithms – a comparative review", Natural Computing 3:77–112) is
//! registered beside HS and MHS and run on three of the thesis's functions
//! by the same seeded runner, into the same `runs.csv` and `report.md` that
//! `metabezier run` and `metabezier report` write.
//!
//! ```text
//! cargo run --release --example custom_optimiser -- results/custom_optimiser
//! ```

use std::error::Error;
use std::path::Path;

use metabezier::experiment::{run_campaign, Registry, RunOptions, Spec, SpecLimits, Summary};
use metabezier::optim::{
    Evaluator, Kind, Optimiser, OptimiserDef, Param, ParamDef, ParamError, ParamSet, Setting,
};
use metabezier::problem::Problem;
use metabezier::report::{write_report, ReportOptions};
use metabezier::rng::{Draw, Words};

/// The (1+1)-ES: one parent, one Gaussian offspring per evaluation, kept
/// when it is no worse; the step size grows by `exp(0.8 / d)` on a success
/// and shrinks by `exp(−0.2 / d)` on a failure (`d = 1 + D/2`), so that it
/// stays put at a success rate of one in five.
#[derive(Clone, Debug)]
pub struct OnePlusOneEs {
    /// The initial step size, as a fraction of each variable's range.
    pub sigma0: f64,
}

/// The key of the `sigma0` parameter: its name written once, its kind in
/// its type.
pub const SIGMA0: Param<f64> = Param::new("sigma0");

/// The parameters of [`OnePlusOneEs`], declared as the built-ins declare
/// theirs: a spec may set or grid them, and `check` validates them.
pub static PARAMS: [ParamDef; 1] = [ParamDef {
    name: SIGMA0.name,
    doc: "initial step size σ₀ as a fraction of each variable's range",
    kind: Kind::Real {
        min: 0.0,
        max: 1.0,
        open_min: true,
    },
    default: Setting::Real(0.3),
    omit_at_default: false,
}];

impl OnePlusOneEs {
    /// The ES of a parameter set made from [`PARAMS`].
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        Ok(OnePlusOneEs {
            sigma0: p.get(SIGMA0),
        })
    }
}

impl Optimiser for OnePlusOneEs {
    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let bounds = eval.bounds();
        let d = 1.0 + bounds.len() as f64 / 2.0;
        let (up, down) = ((0.8 / d).exp(), (-0.2 / d).exp());
        let mut x: Vec<f64> = bounds.iter().map(|b| b.lerp(rng.unit())).collect();
        if eval.remaining() == 0 {
            return;
        }
        let mut fx = eval.evaluate(&x);
        let mut sigma = self.sigma0;
        let mut y = x.clone();
        while eval.remaining() > 0 {
            for ((yi, xi), b) in y.iter_mut().zip(&x).zip(bounds) {
                *yi = b.clip(xi + sigma * b.width() * rng.gaussian());
            }
            let fy = eval.evaluate(&y);
            if fy <= fx || fx.is_nan() {
                std::mem::swap(&mut x, &mut y);
                fx = fy;
                sigma *= up;
            } else {
                sigma *= down;
            }
            // Keep the step inside the box's scale and above rounding.
            sigma = sigma.clamp(1e-15, 1.0);
        }
    }
}

/// The campaign: the ES against HS and MHS on Sphere, Rosenbrock and
/// Rastrigin at D = 10, ten runs each.
pub const SPEC: &str = r#"[experiment]
name = "custom_optimiser"
description = "A (1+1)-ES defined outside the crate against HS and MHS"
seed = 2027
runs = 10
budget = 20000
threshold = 1e-8

[[problem]]
function = ["sphere", "rosenbrock", "rastrigin"]
dim = 10

[[algorithm]]
name = "es11"
label = "(1+1)-ES"

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs"
label = "MHS"
"#;

/// The registry: the built-ins and the ES.
pub fn registry() -> Registry {
    let mut reg = Registry::with_builtins();
    reg.register_optimiser(OptimiserDef::new(
        "es11",
        &PARAMS,
        "(1+1)-ES with the 1/5th success rule (Rechenberg 1973; Kern et al. 2004)",
        OnePlusOneEs::from_params,
    ))
    .expect("es11 is a free name");
    reg
}

/// Runs the campaign into `out` with `threads` workers (all cores if
/// `None`) and writes its report there.
pub fn campaign(out: &Path, threads: Option<usize>) -> Result<Summary, Box<dyn Error>> {
    let reg = registry();
    let spec = Spec::parse_in(
        Path::new("custom_optimiser.toml"),
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
        eprintln!("usage: custom_optimiser OUTPUT_DIRECTORY");
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
            eprintln!("custom_optimiser: {e}");
            std::process::exit(1);
        }
    }
}
