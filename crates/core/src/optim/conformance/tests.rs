//! The suite over every built-in optimiser, over an optimiser registered
//! here, and against optimisers broken on purpose, so that it can fail.

use super::*;
use crate::optim::{Evaluator, Optimiser, OptimiserDef, Optimisers, ParamDef, ParamError, Setting};
use crate::rng::{Draw, Words};

/// Every built-in optimiser passes the suite, each property on each of its
/// settings.
#[test]
fn every_builtin_optimiser_conforms() {
    for def in Optimisers::builtin().iter() {
        if let Err(e) = check(def) {
            panic!("{e}");
        }
    }
}

#[test]
fn the_settings_cover_every_bound_policy_and_the_smallest_populations() {
    for def in Optimisers::builtin().iter() {
        let texts: Vec<String> = settings(def).iter().map(ParamSet::canonical).collect();
        assert_eq!(texts[0], ParamSet::defaults(def.params).canonical());
        if let Some(d) = def.params.iter().find(|d| d.name == "bounds") {
            let Kind::Choice(names) = d.kind else {
                panic!("{}: bounds is not a choice", def.name)
            };
            for name in names {
                let policy = format!("bounds={name}");
                assert!(
                    texts.iter().any(|t| t.split(';').any(|kv| kv == policy)),
                    "{}: {policy} missing from {texts:?}",
                    def.name
                );
            }
        }
        let mut unique = texts.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), texts.len(), "{}: {texts:?}", def.name);
    }
    let ga = settings(Optimisers::builtin().get("ga").unwrap());
    assert!(ga.iter().any(|p| p.canonical().starts_with("pop=2;")));
    let random = settings(Optimisers::builtin().get("random").unwrap());
    assert_eq!(random.len(), 1, "no parameters, one setting");
}

/// What a test optimiser does wrong.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Fault {
    /// Nothing: a (1+1) random walk that keeps its better point.
    None,
    /// One objective call past the budget, through the problem itself.
    Overspends,
    /// Leaves one evaluation of the budget unspent.
    Underspends,
    /// Steps up to a half width past the upper bounds, unrepaired.
    LeavesItsBounds,
    /// Draws from its own generator, seeded once and for all.
    IgnoresItsSeed,
}

/// A (1+1) random walk, `y_j = clip(x_j + 0.1 (U_j − L_j) z_j)` with
/// `z_j ~ N(0, 1)`, keeping `y` when `f(y) ≤ f(x)`; broken by its `fault`.
#[derive(Debug)]
struct Walk {
    fault: Fault,
}

impl Walk {
    /// The next step from `x` into `y`.
    fn step<R: Words + ?Sized>(&self, x: &[f64], y: &mut [f64], bounds: &[Bounds], rng: &mut R) {
        for ((yj, xj), b) in y.iter_mut().zip(x).zip(bounds) {
            let v = xj + 0.1 * b.width() * rng.gaussian();
            *yj = if self.fault == Fault::LeavesItsBounds {
                b.lower + rng.unit() * 1.5 * b.width()
            } else {
                b.clip(v)
            };
        }
    }

    /// The walk itself.
    fn walk<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let bounds = eval.bounds();
        let mut x: Vec<f64> = bounds.iter().map(|b| b.lerp(rng.unit())).collect();
        let mut best = eval.evaluate(&x);
        let mut y = x.clone();
        let keep = u64::from(self.fault == Fault::Underspends);
        while eval.remaining() > keep {
            self.step(&x, &mut y, bounds, rng);
            let v = eval.evaluate(&y);
            if v <= best {
                best = v;
                x.copy_from_slice(&y);
            }
        }
        if self.fault == Fault::Overspends {
            eval.problem().objective(&x);
        }
    }
}

impl Optimiser for Walk {
    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        if self.fault == Fault::IgnoresItsSeed {
            self.walk(eval, &mut run_rng(0));
        } else {
            self.walk(eval, rng);
        }
    }
}

/// The leaky walk's one parameter: whether its steps are repaired.
static WALK_PARAMS: [ParamDef; 1] = [ParamDef {
    name: "bounds",
    doc: "\"clip\" repairs a step, \"none\" leaves it outside the box",
    kind: Kind::Choice(&["clip", "none"]),
    default: Setting::Choice("clip"),
    omit_at_default: false,
}];

/// The walk registered as `name`, broken by `fault`.
fn walk_def(name: &str, fault: Fault) -> OptimiserDef {
    OptimiserDef::new(name, &[], "a test's own", move |_: &ParamSet| {
        Ok::<_, ParamError>(Walk { fault })
    })
}

#[test]
fn a_newly_registered_optimiser_conforms_with_no_test_of_its_own() {
    let mut reg = Optimisers::with_builtins();
    reg.register(walk_def("walk", Fault::None)).unwrap();
    assert_eq!(check(reg.get("walk").unwrap()), Ok(()));
}

/// The failure of the walk broken by `fault`, registered as `name`.
fn failure(name: &str, fault: Fault) -> ConformanceFailure {
    check(&walk_def(name, fault)).unwrap_err()
}

#[test]
fn an_optimiser_that_overspends_fails_budget_exactness() {
    let e = failure("overspender", Fault::Overspends);
    assert_eq!(
        e.to_string(),
        "optimiser \"overspender\" [] fails budget exactness: 1 objective calls with a budget of 0"
    );
    assert_eq!(e.property, Property::Budget);
}

#[test]
fn an_optimiser_that_underspends_fails_budget_exactness() {
    let e = failure("underspender", Fault::Underspends);
    assert_eq!(
        e.to_string(),
        "optimiser \"underspender\" [] fails budget exactness: the outcome counts 1 evaluations with a budget of 2"
    );
}

#[test]
fn an_optimiser_that_leaves_its_bounds_fails_them_at_the_setting_that_does() {
    // It repairs its steps at "bounds = clip", its default, and leaves the
    // box at "bounds = none", which the suite runs as one of its settings.
    let leaky = OptimiserDef::new(
        "leaky",
        &WALK_PARAMS,
        "broken on purpose",
        |p: &ParamSet| {
            let fault = match p.get(crate::optim::Param::<&str>::new("bounds")) {
                "none" => Fault::LeavesItsBounds,
                _ => Fault::None,
            };
            Ok::<_, ParamError>(Walk { fault })
        },
    );
    let e = check(&leaky).unwrap_err();
    assert_eq!(
        (e.property, e.setting.as_str()),
        (Property::Bounds, "bounds=none")
    );
    assert!(
        e.to_string()
            .starts_with("optimiser \"leaky\" [bounds=none] fails bounds: ")
            && e.message
                .ends_with(" of 5000 evaluated points lie outside the bounds"),
        "{e}"
    );
}

#[test]
fn an_optimiser_that_ignores_its_seed_fails_seed() {
    let e = failure("deaf", Fault::IgnoresItsSeed);
    assert_eq!(e.property, Property::Seed);
    assert!(
        e.message
            .starts_with("seeds 5 and 6 give the same best point ["),
        "{e}"
    );
}
