//! Tests of the verdicts across problems.

use super::*;
use crate::design::Level;

fn obs(alg: &str, unit: &str, budget: u64, value: f64) -> Observation {
    Observation {
        table: "reference",
        measure: Measure::FinalError,
        algorithm: alg.into(),
        reference: "R".into(),
        unit: unit.into(),
        levels: Levels(vec![("budget", Level::Number(budget))]),
        value,
    }
}

#[test]
fn four_equal_four_better_is_no_detectable_difference_eight_better_is_better() {
    let mut o = Vec::new();
    for (i, f) in ["f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8"]
        .iter()
        .enumerate()
    {
        o.push(obs("X", f, 1000, if i < 4 { 0.0 } else { -3.0 }));
        o.push(obs("Y", f, 1000, -3.0));
    }
    let rows = verdicts(
        &o,
        &[],
        Settings {
            alpha: 0.05,
            post_hoc: PostHoc::Holm,
            reference: Some("R"),
            ropes: Ropes::default(),
        },
    );
    assert_eq!(rows.len(), 2, "one scope, two rows: {rows:?}");
    let x = &rows[0];
    assert_eq!((x.across.better, x.across.equal, x.across.worse), (4, 4, 0));
    assert!((x.across.p_value - 0.125).abs() < 1e-12);
    assert_eq!(x.verdict, Verdict::Undecided);
    let y = &rows[1];
    assert!((y.p_adjusted - 0.015625).abs() < 1e-12, "{}", y.p_adjusted);
    assert_eq!(y.verdict, Verdict::Better);
}

#[test]
fn known_answers_equivalent_and_better_on_24_functions() {
    // Issue 50: an algorithm within ±0.02 decades of the reference on
    // 24 functions is equivalent (rope ±0.3); one 10^0.5 better on 16
    // of 24 and equal on 8 is better, with an HL interval below 0.
    let mut o = Vec::new();
    for i in 0..24 {
        let f = format!("f{i:02}");
        let wobble = 0.02 * ((f64::from(i) * 1.7).sin());
        o.push(obs("Same", &f, 1000, wobble));
        o.push(obs("Better", &f, 1000, if i < 16 { -0.5 } else { 0.0 }));
    }
    let settings = Settings {
        alpha: 0.05,
        post_hoc: PostHoc::Holm,
        reference: None,
        ropes: Ropes::default(),
    };
    let rows = verdicts(&o, &[], settings);
    let same = rows.iter().find(|r| r.algorithm == "Same").unwrap();
    assert_eq!(same.verdict, Verdict::Equivalent, "{same:?}");
    assert!(same.equivalence.within > 0.99, "{:?}", same.equivalence);
    assert!(
        same.shift.low > -0.02 && same.shift.high < 0.02,
        "{:?}",
        same.shift
    );
    let better = rows.iter().find(|r| r.algorithm == "Better").unwrap();
    assert_eq!(better.verdict, Verdict::Better, "{better:?}");
    assert!(better.shift.high < 0.0, "{:?}", better.shift);
    // Walsh averages: 136 at −0.5, 128 at −0.25, 36 at 0; median −0.25.
    assert_eq!(better.shift.estimate, -0.25);
    // The Bayesian test judges Walsh averages against the rope: half
    // the pairs (−0.5 with 0) fall within ±0.3, so it does not call
    // this one better, but never worse; the verdict is the test's.
    assert!(better.equivalence.worse < 0.01, "{:?}", better.equivalence);
    // The same rows from the same data: the seeded posterior is
    // bit-identical, and independent of the other rows.
    let again = verdicts(&o[1..], &[], settings);
    let b2 = again.iter().find(|r| r.algorithm == "Better").unwrap();
    assert_eq!(
        b2.equivalence.better.to_bits(),
        better.equivalence.better.to_bits()
    );
    // A rope of 0 leaves no room for equivalence.
    let strict = Settings {
        ropes: Ropes {
            final_error: 0.0,
            anytime_auc: 0.0,
        },
        ..settings
    };
    let rows = verdicts(&o, &[], strict);
    let same = rows.iter().find(|r| r.algorithm == "Same").unwrap();
    assert_eq!(same.verdict, Verdict::Undecided);
}

#[test]
fn ropes_are_checked_by_name_and_value() {
    let mut r = Ropes::default();
    assert_eq!((r.final_error, r.anytime_auc), (0.3, 0.05));
    r.set("anytime-auc", 0.1).unwrap();
    assert_eq!(r.anytime_auc, 0.1);
    let e = r.set("dice", 0.1).unwrap_err().to_string();
    assert!(e.contains("\"final-error\", \"anytime-auc\""), "{e}");
    assert!(r.set("final-error", -1.0).is_err());
    assert!(r.set("final-error", f64::NAN).is_err());
}

#[test]
fn instances_of_a_function_are_one_unit_and_scopes_split_by_level() {
    // Five instances of one function better at budget 1000, worse at
    // 2000: one unit per scope, never significant.
    let mut o = Vec::new();
    for i in 0..5 {
        o.push(obs("X", "f", 1000, -1.0 - f64::from(i)));
        o.push(obs("X", "f", 2000, 1.0));
    }
    let rows = verdicts(
        &o,
        &[],
        Settings {
            alpha: 0.05,
            post_hoc: PostHoc::Holm,
            reference: None,
            ropes: Ropes::default(),
        },
    );
    let scopes: Vec<&str> = rows.iter().map(|r| r.scope.as_str()).collect();
    assert_eq!(scopes, ["all", "budget=1000", "budget=2000"]);
    assert!(rows.iter().all(|r| r.across.units == 1));
    assert_eq!(rows[0].problems, 10);
    // The unit's summary at scope all is the median of its ten values.
    assert_eq!(rows[0].across.effect_size, 0.0);
    assert_eq!(rows[1].across.effect_size, -3.0);
    assert!(rows.iter().all(|r| r.verdict == Verdict::Undecided));
}

use crate::families::STATE_OF_THE_ART_PAIRS;
use crate::optim::{ComparisonFamily, Optimisers};

#[test]
fn the_state_of_the_art_is_a_family_of_its_own_unless_it_is_the_reference() {
    let f = Families::default();
    assert_eq!(f.comparison_set("cmaes", "mhs"), STATE_OF_THE_ART);
    assert_eq!(f.comparison_set("lshade", "mhs"), STATE_OF_THE_ART);
    assert_eq!(f.comparison_set("random", "hs"), STATE_OF_THE_ART);
    assert_eq!(f.comparison_set("cmaes+lm", "mhs"), STATE_OF_THE_ART);
    assert_eq!(f.comparison_set("hs", "mhs"), "reference");
    assert_eq!(f.comparison_set("mhs+lm", "mhs"), "reference");
    assert_eq!(f.pair_set("hs", "mhs"), "method-pairs");
    assert_eq!(f.pair_set("mhs+lm", "lm"), "method-pairs");
    assert_eq!(f.pair_set("mhs", "cmaes+lm"), STATE_OF_THE_ART_PAIRS);
    assert_eq!(f.pair_set("lshade", "cmaes"), STATE_OF_THE_ART_PAIRS);
    assert_eq!(f.comparison_set("hs", "cmaes"), "reference");
    assert_eq!(f.comparison_set("lshade", "cmaes"), "reference");
    // An optimiser no registry knows (an external runs.csv's) is beyond
    // the thesis.
    assert_eq!(f.comparison_set("their-es", "mhs"), STATE_OF_THE_ART);
}

#[test]
fn a_registered_optimiser_declares_its_family() {
    use crate::optim::{random, OptimiserDef, RandomSearch};
    let mut reg = Optimisers::with_builtins();
    let def = OptimiserDef::new("my-hs", &random::PARAMS, "", RandomSearch::from_params);
    reg.register(def.in_family(ComparisonFamily::Thesis))
        .unwrap();
    let f = Families::of(&reg);
    assert_eq!(f.comparison_set("my-hs", "mhs"), "reference");
    assert_eq!(
        Families::default().comparison_set("my-hs", "mhs"),
        STATE_OF_THE_ART
    );
}
