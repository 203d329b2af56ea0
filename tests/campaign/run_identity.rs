//! Run identity: every design factor is part of a run's key and seed unless
//! it is at its default or declared `paired`, so that specs written before
//! the factors existed keep their files bit for bit, and paired factors
//! share their random numbers exactly where declared.

use std::path::{Path, PathBuf};

use metabezier::experiment::runner::run_seed;
use metabezier::experiment::spec::RunId;
use metabezier::experiment::{run_campaign, RunOptions, Spec};
use metabezier::rng::fnv1a64;

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn run(spec: &Spec, out: &Path, threads: usize) {
    let opts = RunOptions {
        out: Some(out.to_owned()),
        threads: Some(threads),
        ..RunOptions::default()
    };
    run_campaign(spec, &opts).unwrap();
}

fn hash(path: &Path) -> u64 {
    fnv1a64(&std::fs::read_to_string(path).unwrap())
}

/// A fitting spec with both search spaces, as written before factors existed.
const LEGACY_FIT: &str = r#"[experiment]
name = "fit_test"
seed = 5
runs = 2
budget = 400

[[fit]]
input = "coin.png"
function = ["cubic", "rational-cubic"]
continuity = ["c1", "g1"]
search_space = ["technique", "bounding-box"]
segments = 4

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "mhs+lm"
label = "MHS+LM"
"#;

#[test]
fn specs_without_new_factors_keep_their_files_bit_for_bit() {
    // FNV-1a hashes of the files these specs give. They matched the files of
    // metabezier at commit dbab234 (before transforms, instances, budget
    // grids, pairing and the MHS readings existed) until the bulk generator
    // (`LaneRng`) changed every run's random numbers; they were re-pinned
    // then, with keys and seeds unchanged, and must not move again unless
    // the generator or an operator changes on purpose.
    let tmp = tempfile::tempdir().unwrap();
    let quick = Spec::load(&repo("experiments/quick.toml")).unwrap();
    let out = tmp.path().join("quick");
    run(&quick, &out, 2);
    assert_eq!(hash(&out.join("runs.csv")), 0x6612c30e1c42f278);
    assert_eq!(hash(&out.join("convergence.csv")), 0x02613f64c13ec025);

    std::fs::copy(repo("data/outlines/coin.png"), tmp.path().join("coin.png")).unwrap();
    let path = tmp.path().join("fit.toml");
    std::fs::write(&path, LEGACY_FIT).unwrap();
    let fit = Spec::load(&path).unwrap();
    let out = tmp.path().join("fit");
    run(&fit, &out, 2);
    for (file, want) in [
        ("runs.csv", 0xbff898bb67d6132c),
        ("convergence.csv", 0x6e1f1111121036d7),
        ("fits.csv", 0xd1d20913a559f416),
        ("segments.csv", 0xc34066194ca0785c),
    ] {
        assert_eq!(hash(&out.join(file)), want, "{file} changed");
    }
}

const FACTORS: &str = r#"[experiment]
name = "factors"
seed = 3
runs = 3
budget = [300, 600]
PAIRED

[[problem]]
function = ["sphere", "rastrigin"]
dim = 4
transform = ["none", "shift", "shift-rotate"]
instances = 2

[[algorithm]]
name = "pso"

[[algorithm]]
name = "mhs"
scheme = "per-variable"

[[algorithm]]
name = "lshade"

[[algorithm]]
name = "random"
"#;

fn factors(paired: &str) -> Spec {
    Spec::parse(Path::new("spec.toml"), &FACTORS.replace("PAIRED", paired)).unwrap()
}

/// The seed of every run.
fn seeds(spec: &Spec) -> Vec<(RunId, u64)> {
    spec.run_ids()
        .into_iter()
        .map(|id| (id, run_seed(spec, id)))
        .collect()
}

#[test]
fn paired_factors_share_seeds_exactly_where_declared() {
    let unpaired = factors("");
    let all = seeds(&unpaired);
    let mut distinct: Vec<u64> = all.iter().map(|(_, s)| *s).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert_eq!(
        distinct.len(),
        all.len(),
        "without pairing every run has its own seed"
    );

    let by_budget = factors("paired = [\"budget\"]");
    let p = &by_budget.problems;
    for (id, seed) in seeds(&by_budget) {
        for (jd, other) in seeds(&by_budget) {
            let (a, b) = (&p[id.problem], &p[jd.problem]);
            let same_but_budget = a.name() == b.name()
                && a.transform == b.transform
                && a.instance == b.instance
                && id.cell == jd.cell
                && id.run == jd.run;
            assert_eq!(
                seed == other,
                same_but_budget,
                "{} / {} run {}",
                a.key(),
                b.key(),
                id.run
            );
        }
    }
    // Pairing the transform: `none`, `shift` #1 and `shift-rotate` #1 share
    // their seeds; instance 2 keeps its own.
    let by_transform = factors("paired = \"transform\"");
    let seed_of = |key: &str, cell: usize, run: u32| {
        let problem = by_transform
            .problems
            .iter()
            .position(|p| p.key() == key)
            .unwrap_or_else(|| panic!("{key}"));
        run_seed(
            &by_transform,
            RunId {
                index: 0,
                problem,
                cell,
                run,
            },
        )
    };
    let none = seed_of("sphere-4|budget=300", 1, 2);
    assert_eq!(none, seed_of("sphere-4|budget=300|transform=shift", 1, 2));
    assert_eq!(
        none,
        seed_of("sphere-4|budget=300|transform=shift-rotate", 1, 2)
    );
    assert_ne!(
        none,
        seed_of("sphere-4|budget=300|transform=shift|instance=2", 1, 2)
    );
    assert_eq!(
        seed_of("sphere-4|budget=300|transform=shift|instance=2", 1, 2),
        seed_of(
            "sphere-4|budget=300|transform=shift-rotate|instance=2",
            1,
            2
        )
    );
    // An untransformed problem keeps the seed it has without pairing.
    let problem = unpaired
        .problems
        .iter()
        .position(|p| p.key() == "sphere-4|budget=300")
        .unwrap();
    let id = RunId {
        index: 0,
        problem,
        cell: 1,
        run: 2,
    };
    assert_eq!(none, run_seed(&unpaired, id));
}

#[test]
fn instances_are_identical_across_algorithms_and_thread_counts() {
    let spec = factors("paired = [\"budget\"]");
    let tmp = tempfile::tempdir().unwrap();
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    run(&spec, &one, 1);
    run(&spec, &two, 2);
    for f in ["runs.csv", "convergence.csv", "hits.csv"] {
        assert_eq!(
            std::fs::read(one.join(f)).unwrap(),
            std::fs::read(two.join(f)).unwrap(),
            "{f} differs between 1 and 2 threads"
        );
    }
    let runs = std::fs::read_to_string(one.join("runs.csv")).unwrap();
    assert!(
        runs.starts_with("algorithm,kind,params,problem,dim,budget,transform,instance,run,seed,")
    );
    assert_eq!(runs.lines().count(), 1 + 2 * 5 * 2 * 4 * 3);
    // The keyed files carry the budget, since runs of one problem differ in it.
    let hits = std::fs::read_to_string(one.join("hits.csv")).unwrap();
    assert!(hits.starts_with(
        "algorithm,kind,params,problem,dim,budget,transform,instance,run,target,evaluations\n"
    ));
    // With the budget paired, the 300-evaluation run is the first 300
    // evaluations of the 600-evaluation one, so its hits are a prefix.
    let records = metabezier::experiment::records::read_results(&one).unwrap();
    for r in records
        .iter()
        .filter(|r| r.budget == 300 && r.kind == "mhs")
    {
        let long = records
            .iter()
            .find(|q| {
                q.budget == 600
                    && q.match_key() == r.match_key()
                    && q.run == r.run
                    && q.kind == r.kind
            })
            .unwrap();
        assert_eq!(r.seed, long.seed);
        let early: Vec<_> = long
            .hits
            .iter()
            .filter(|h| h.evaluations <= 300)
            .copied()
            .collect();
        assert_eq!(r.hits, early, "{}", r.match_key());
    }
}
