//! The "did you mean" suggester counts a transposition of two adjacent
//! letters as one edit (Damerau–Levenshtein), so a swapped pair of letters
//! is suggested back rather than a shorter name at the same distance.

use std::path::Path;

use metabezier::experiment::Spec;

const BASE: &str = r#"[experiment]
name = "t"
seed = 1
runs = 2
budget = 100

[[problem]]
function = "sphere"
dim = 2

[[algorithm]]
name = "hs"
"#;

fn hint_for(name: &str) -> String {
    let text = BASE.replace("name = \"hs\"", &format!("name = \"{name}\""));
    match Spec::parse(Path::new("spec.toml"), &text) {
        Ok(_) => panic!("{name} was accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn transposed_letters_suggest_the_name_they_come_from() {
    for (typo, meant) in [
        ("msh", "mhs"),
        ("pos", "pso"),
        ("cmase", "cmaes"),
        ("lshaed", "lshade"),
    ] {
        let e = hint_for(typo);
        assert!(
            e.contains(&format!("did you mean \"{meant}\"?")),
            "{typo}: {e}"
        );
    }
}

#[test]
fn a_name_far_from_every_choice_gets_no_suggestion() {
    let e = hint_for("simplex");
    assert!(!e.contains("did you mean"), "{e}");
}
