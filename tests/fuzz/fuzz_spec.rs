//! Mutational fuzz of the spec readers (campaign and implant): no panic,
//! no hang, and no allocation beyond the limit on any mutant of the shipped
//! specs. See `tests/fuzz_common` for the loop and `make fuzz` for a longer
//! run.
use crate::common;
use crate::fuzz_common;

use std::path::Path;

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
    let _one = fuzz_common::one_test_at_a_time();
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

/// A 30 KB spec with four lists of 1,000 values is refused with at most a
/// few MiB of heap: the grid is counted, not expanded (before, it took
/// 4.7 GB and aborted).
#[test]
fn a_huge_grid_is_refused_within_a_small_heap() {
    let _one = fuzz_common::one_test_at_a_time();
    let text = format!(
        "[experiment]\nname = \"g\"\nseed = 1\nruns = 1\nbudget = 100\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n[[algorithm]]\nname = \"hs\"\n{}",
        common::thousand_value_hs_grid()
    );
    let (result, peak) = fuzz_common::with_limit(64 << 20, || {
        metabezier::experiment::Spec::parse(Path::new("grid.toml"), &text)
    });
    let e = result.unwrap_err();
    assert!(
        e.message
            .contains("pass the limit of 1000000 algorithm cells"),
        "{e}"
    );
    assert!(peak < 16 << 20, "{peak} bytes");
    // At the run limit without the cell limit: 10⁴ cells × 10³ runs.
    let text = text
        .replace("runs = 1\n", "runs = 1000\n")
        .replace(&format!("par = {}\n", common::thousand_reals(0.2)), "")
        .replace(&format!("bw = {}\n", common::thousand_reals(0.001)), "")
        .replace(
            &format!("hms = {}\n", common::thousand_counts()),
            "hms = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10]\n",
        );
    let (result, peak) = fuzz_common::with_limit(64 << 20, || {
        metabezier::experiment::Spec::parse(Path::new("grid.toml"), &text)
    });
    let spec = result.unwrap();
    assert_eq!(spec.run_count(), 10_000_000);
    assert!(peak < 48 << 20, "{peak} bytes for 10,000 cells");
}

#[test]
fn implant_specs_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let inputs = specs(&["ch6_cranial.toml"]);
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments/mutant.toml");
    let tally = fuzz_common::fuzz("implant-spec", &inputs, 64 << 20, |bytes| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return false;
        };
        metabezier::implant::ImplantSpec::parse(&path, text).is_ok()
    });
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

/// The loop itself: a reader's panic fails the test and names the mutant,
/// and an allocation above the limit aborts the binary with the mutant
/// named (checked in a child process of this test binary).
#[test]
fn the_loop_catches_panics_and_oversized_allocations() {
    let _one = fuzz_common::one_test_at_a_time();
    if std::env::var_os("METABEZIER_FUZZ_SELFTEST").is_some() {
        fuzz_common::fuzz("selftest", &[b"abc".to_vec()], 1 << 20, |bytes| {
            let v = vec![1u8; 64 << 20];
            v.len() > bytes.len()
        });
        return;
    }
    let caught = std::panic::catch_unwind(|| {
        fuzz_common::fuzz("panics", &[b"abcdef".to_vec()], 1 << 20, |bytes| {
            assert!(bytes.len() < 6, "a long mutant");
            true
        })
    });
    let message = caught.unwrap_err();
    let message = message.downcast_ref::<String>().unwrap();
    assert!(message.starts_with("fuzz panics: mutant "), "{message}");
    let child = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "fuzz_spec::the_loop_catches_panics_and_oversized_allocations",
            "--nocapture",
        ])
        .env("METABEZIER_FUZZ_SELFTEST", "1")
        .output()
        .unwrap();
    assert!(!child.status.success());
    let stderr = String::from_utf8_lossy(&child.stderr);
    assert!(
        stderr.contains("an allocation passed the reader's memory limit")
            && stderr.contains("fuzz selftest: mutant 0 of METABEZIER_FUZZ_SEED="),
        "{stderr}"
    );
}
