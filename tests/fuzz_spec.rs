//! Mutational fuzz of the spec readers (campaign and implant): no panic,
//! no hang, and no allocation beyond the limit on any mutant of the shipped
//! specs. See `tests/fuzz_common` for the loop and `make fuzz` for a longer
//! run.
mod fuzz_common;

use std::path::Path;

#[global_allocator]
static ALLOC: fuzz_common::CountingAlloc = fuzz_common::CountingAlloc;

/// The shipped specs' text, the inputs to mutate.
fn specs(names: &[&str]) -> Vec<Vec<u8>> {
    names
        .iter()
        .map(|n| {
            std::fs::read(
                Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join("experiments")
                    .join(n),
            )
            .unwrap()
        })
        .collect()
}

#[test]
fn campaign_specs_survive_mutation() {
    let inputs = specs(&[
        "quick.toml",
        "ch4_tuning.toml",
        "ch4_robustness.toml",
        "ch5_outlines.toml",
        "ch5_search_space.toml",
        "bbob.toml",
    ]);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/mutant.toml");
    let tally = fuzz_common::fuzz("spec", &inputs, 256 << 20, |bytes| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return false;
        };
        metabezier::experiment::Spec::parse(&path, text).is_ok()
    });
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}
