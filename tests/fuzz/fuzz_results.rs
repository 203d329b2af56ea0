//! Mutational fuzz of the results readers: every file that `report` and a
//! resume or merge read (runs.csv, convergence.csv, timing.csv, hits.csv,
//! fits.csv, segments.csv, journal.csv) of two small campaigns run here, one
//! file mutated at a time, read the way `report` reads a directory
//! (`report::load_results`) and the way a resume and a merge do
//! (`records::read_results`, `journal::read_journal`): no panic, no hang,
//! and no allocation beyond a small multiple of the files' size.
use crate::common;
use crate::fuzz_common;

use std::path::Path;

use metabezier::experiment::journal::read_journal;
use metabezier::experiment::records::read_results;
use metabezier::report::load_results;

use common::campaign_runs as campaign;

const BENCHMARK: &str = r#"
[experiment]
name = "fuzz_results"
seed = 7
runs = 2
budget = 300
threshold = 1e-8

[[problem]]
function = ["sphere", "rastrigin"]
dim = 3

[[problem]]
function = "six_hump_camel"

[[problem]]
function = "sphere"
dim = 3
transform = "shift-rotate"
instances = [2]

[[algorithm]]
name = "hs"
label = "HS, tuned"

[[algorithm]]
name = "pso"
swarm = 10
"#;

fn fitting() -> String {
    let coin = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines/coin.png");
    format!(
        "[experiment]\nname = \"fuzz_fit\"\nseed = 3\nruns = 2\nbudget = 8\nthreshold = 0\n\n\
         [[fit]]\ninput = \"{}\"\nfunction = [\"cubic\", \"rational-quadratic\"]\ncontinuity = \"g1\"\nclosing = \"smooth\"\nsegments = 4\n\n\
         [[algorithm]]\nname = \"hs\"\n",
        coin.display()
    )
}

/// The bytes of the files of `dir`, and their total.
fn size_of_files(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().metadata().unwrap().len() as usize)
        .sum()
}

/// Fuzzes `file` of `dir` with `read` (the directory, with the mutant in
/// place of the file), then puts the file back; the limit is 4 × the
/// files' size and 1 MiB.
fn fuzz_file(dir: &Path, file: &str, read: impl Fn(&Path) -> bool) {
    let path = dir.join(file);
    let original = std::fs::read(&path).unwrap();
    let limit = 4 * size_of_files(dir) + (1 << 20);
    let name = format!("{}/{file}", dir.file_name().unwrap().to_string_lossy());
    let tally = fuzz_common::fuzz(&name, std::slice::from_ref(&original), limit, |bytes| {
        std::fs::write(&path, bytes).unwrap();
        read(dir)
    });
    std::fs::write(&path, &original).unwrap();
    assert!(read(dir), "{name}: the original is refused");
    assert!(
        tally.accepted < tally.mutants,
        "{name}: every mutant accepted: {tally:?}"
    );
    eprintln!("{name}: {tally:?}, limit {limit}");
}

/// Read as `report` and as a resume or a merge do: true if both accept.
fn as_report_and_resume(dir: &Path) -> bool {
    let report = load_results(dir, None).is_ok();
    let resume = read_results(dir).is_ok();
    report && resume
}

/// A scratch directory in memory where there is one: each mutant rewrites
/// a file in place, which ext4 (auto_da_alloc) flushes to disk on close,
/// seven times slower on a busy disk.
fn scratch() -> tempfile::TempDir {
    let shm = Path::new("/dev/shm");
    if shm.is_dir() {
        if let Ok(dir) = tempfile::tempdir_in(shm) {
            return dir;
        }
    }
    tempfile::tempdir().unwrap()
}

#[test]
fn results_directories_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let tmp = scratch();
    let bench = campaign(tmp.path(), "bench", BENCHMARK, None);
    for file in ["runs.csv", "convergence.csv", "hits.csv", "timing.csv"] {
        fuzz_file(&bench, file, as_report_and_resume);
    }
    // A fitting campaign; without its spec copy, whose check would fit the
    // outline once per mutant.
    let fit = campaign(tmp.path(), "fit", &fitting(), None);
    std::fs::remove_file(fit.join("spec.toml")).unwrap();
    for file in ["runs.csv", "fits.csv", "segments.csv"] {
        fuzz_file(&fit, file, as_report_and_resume);
    }
}

#[test]
fn journals_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let tmp = scratch();
    let bench = campaign(tmp.path(), "bench", BENCHMARK, Some(7));
    let fit = campaign(tmp.path(), "fit", &fitting(), Some(3));
    for dir in [bench, fit] {
        let journal = dir.join("journal.csv");
        fuzz_file(&dir, "journal.csv", |_| read_journal(&journal).is_ok());
    }
}
