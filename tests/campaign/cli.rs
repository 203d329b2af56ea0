//! The command line: exit codes, messages and the files a run leaves.

use std::path::Path;
use std::process::Command;

fn metabezier() -> Command {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
}

/// `metabezier ARGS` run in `dir`, its output.
fn in_dir(dir: &std::path::Path, args: &[&str]) -> std::process::Output {
    metabezier().current_dir(dir).args(args).output().unwrap()
}

#[test]
fn a_bad_spec_fails_with_its_message_and_writes_nothing() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = tmp.path().join("bad.toml");
    std::fs::write(
        &spec,
        "[experiment]\nname = \"bad\"\nseed = 1\nruns = 1\nbudget = 10\n\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\nhmcr = 2\n",
    )
    .unwrap();
    let out = in_dir(tmp.path(), &["run", "bad.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(
        stderr,
        "metabezier: error: bad.toml:13:8: algorithm[1].hmcr: expected a real number in [0, 1], found 2\n"
    );
    assert!(
        !tmp.path().join("results").exists(),
        "nothing is written for a bad spec"
    );
}

#[test]
fn run_writes_the_result_files_and_check_describes_the_plan() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("small.toml"),
        "[experiment]\nname = \"small\"\nseed = 7\nruns = 2\nbudget = 300\n\n[[problem]]\nfunction = \"sphere\"\ndim = 3\n\n[[algorithm]]\nname = \"mhs\"\nhmcr = [0.8, 0.9]\n",
    )
    .unwrap();
    let check = in_dir(tmp.path(), &["check", "small.toml"]);
    assert!(check.status.success());
    let text = String::from_utf8(check.stdout).unwrap();
    assert!(
        text.contains("1 problems × 2 algorithm cells × 2 runs = 4 runs, 1200 evaluations"),
        "{text}"
    );

    let out = in_dir(
        tmp.path(),
        &["run", "small.toml", "--threads", "2", "--quiet"],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stderr.is_empty(),
        "no progress bar when stderr is not a terminal"
    );
    let dir = tmp.path().join("results/small");
    for f in [
        "runs.csv",
        "convergence.csv",
        "timing.csv",
        "spec.toml",
        "meta.toml",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    is_finished_and_records_its_provenance(&dir);
    // A second run without --resume refuses to touch the finished campaign.
    let again = in_dir(tmp.path(), &["run", "small.toml"]);
    assert_eq!(again.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&again.stderr).contains("pass --resume"));

    // `report` turns the directory into report.md, tables and plots.
    let report = in_dir(tmp.path(), &["report", "results/small"]);
    assert!(
        report.status.success(),
        "{}",
        String::from_utf8_lossy(&report.stderr)
    );
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("## Statistical tests"), "{md}");
    for f in [
        "tables/descriptive.csv",
        "plots/convergence.svg",
        "plots/convergence.png",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    reports_refuse_bad_references_ropes_and_claims(tmp.path(), &dir);
}

/// A finished campaign leaves no temporary file or journal, and records its generator and seed (meta.toml) and where and with what build it ran (deterministically apart).
fn is_finished_and_records_its_provenance(dir: &Path) {
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp") || n == "journal.csv")
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    let meta = std::fs::read_to_string(dir.join("meta.toml")).unwrap();
    assert!(
        meta.contains("rng = \"LaneRng: Xoshiro256++ in 4 lanes"),
        "{meta}"
    );
    assert!(meta.contains("master_seed = 7"), "{meta}");
    // Where and with what build the runs were made: beside meta.toml,
    // which stays deterministic.
    assert!(!meta.contains("commit") && !meta.contains("date"), "{meta}");
    let sessions = metabezier::experiment::provenance::read(dir);
    assert_eq!(sessions.len(), 1, "{sessions:?}");
    let s = &sessions[0];
    assert_eq!(s.version, env!("CARGO_PKG_VERSION"));
    assert_eq!(s.commit, metabezier::experiment::provenance::GIT_COMMIT);
    assert!(s.date.len() == 20 && s.date.ends_with('Z') && s.date.starts_with("20"));
    assert!(s.threads == 2 && !s.cpu.is_empty() && s.runs > 0, "{s:?}");
}

/// `report` names the algorithms for an unknown reference, parses `--rope` once (a usage error names the measures) and stops at a missing claim's row with the claims file's line.
fn reports_refuse_bad_references_ropes_and_claims(tmp: &Path, dir: &Path) {
    // An unknown reference names the algorithms that exist.
    let bad = in_dir(tmp, &["report", "results/small", "--reference", "XYZ"]);
    assert_eq!(bad.status.code(), Some(1));
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(
        err.contains("XYZ") && err.contains("mhs (hmcr=0.8)"),
        "{err}"
    );
    // --rope: a measure's rope, parsed once; an unknown measure or a bad
    // value is a usage error naming the measures.
    let rope = in_dir(
        tmp,
        &["report", "results/small", "--rope", "final-error=0.2"],
    );
    assert!(
        rope.status.success(),
        "{}",
        String::from_utf8_lossy(&rope.stderr)
    );
    let verdicts = std::fs::read_to_string(dir.join("tables/verdicts.csv")).unwrap();
    assert!(verdicts
        .lines()
        .any(|l| l.contains(",final-error,") && l.contains(",0.2,")));
    for bad in ["dice=0.1", "final-error=-1", "final-error"] {
        let out = in_dir(tmp, &["report", "results/small", "--rope", bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("--rope") && err.contains("final-error"),
            "{bad}: {err}"
        );
    }
    // --claims: a claim of this campaign whose row is missing stops the
    // report with the claims file's line.
    let claims = tmp.join("claims.toml");
    std::fs::write(
        &claims,
        "[[claim]]\nid = \"x\"\nclaim = \"x\"\nsource = \"x\"\ncampaign = \"small\"\n\
         table = \"reference\"\nmeasure = \"final-error\"\nalgorithm = \"nobody\"\n\
         reference = \"mhs\"\nscope = \"all\"\nholds_if = \"worse\"\n",
    )
    .unwrap();
    let out = metabezier()
        .current_dir(tmp)
        .args(["report", "results/small", "--claims"])
        .arg(&claims)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("claims.toml:1: claim \"x\"") && err.contains("algorithm=nobody"),
        "{err}"
    );
}

#[test]
fn report_of_a_missing_directory_names_the_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = in_dir(tmp.path(), &["report", "nowhere"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("nowhere/runs.csv"), "{err}");
}

#[test]
fn a_report_whose_figures_cannot_be_drawn_says_so_and_fails_unless_told_to_go_on() {
    // A runs.csv alone (another tool's) whose every error is infinite: the
    // report is written, its summary names the figures the runs should have
    // allowed, and the command fails unless given --keep-going.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("broken");
    std::fs::create_dir(&dir).unwrap();
    let mut csv = String::from(
        "algorithm,kind,params,problem,dim,budget,run,seed,best,error,evaluations,evaluations_to_target,success\n",
    );
    for (alg, kind) in [("HS", "hs"), ("MHS", "mhs")] {
        for run in 0..3 {
            csv.push_str(&format!(
                "{alg},{kind},,sphere,2,100,{run},{run},inf,inf,100,,false\n"
            ));
        }
    }
    std::fs::write(dir.join("runs.csv"), csv).unwrap();
    let out = metabezier().args(["report"]).arg(&dir).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("report.md: written, but 1 figure(s)"), "{err}");
    assert!(
        err.contains("box plots skipped: no finite final error"),
        "{err}"
    );
    assert!(err.contains("--keep-going"), "{err}");
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    let summary = &md[md.find("## Summary").unwrap()..md.find("## Plots").unwrap()];
    assert!(
        summary.contains("Warning: 1 figure(s) could not be drawn"),
        "{summary}"
    );
    let out = metabezier()
        .args(["report", "--keep-going"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn list_shows_every_algorithm_and_function() {
    let out = metabezier().arg("list").output().unwrap();
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    for name in [
        "hs",
        "ghs",
        "ga",
        "pso",
        "mhs",
        "cmaes",
        "hmcr",
        "par_min",
        "inc_popsize",
        "sigma0",
        "lshade",
        "random",
        "r_n_init",
        "arc_rate",
        "p_best",
        "sphere",
        "six_hump_camel",
        "lm ",
        "<name>+lm",
        "rational-cubic",
        "rational-quadratic",
        "f24  lunacek",
        "attractive-sector",
    ] {
        assert!(text.contains(name), "{name} missing from:\n{text}");
    }
}

#[test]
fn check_refuses_a_cmaes_whose_state_does_not_fit_and_runs_a_large_hs() {
    // Issue 49: the optimiser's state is sized before it is allocated, in
    // `check` as in `run`: CMA-ES at D = 30,000 is refused with the cell,
    // the algorithm, D and the bytes; HS at D = 10⁶ is linear and passes.
    let tmp = tempfile::tempdir().unwrap();
    let spec = |name: &str, dim: u64| {
        format!(
            "[experiment]\nname = \"big\"\nseed = 1\nruns = 1\nbudget = 1000\n\n\
             [[problem]]\nfunction = \"sphere\"\ndim = {dim}\n\n[[algorithm]]\nname = \"{name}\"\n"
        )
    };
    std::fs::write(tmp.path().join("cmaes.toml"), spec("cmaes", 30_000)).unwrap();
    let out = in_dir(tmp.path(), &["check", "cmaes.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cmaes.toml: algorithm \"cmaes\" (cmaes) at D = 30000 needs an estimated")
            && err.contains("GiB of optimiser state for one run, over the limit of 4 GiB"),
        "{err}"
    );
    let run = in_dir(tmp.path(), &["run", "cmaes.toml"]);
    assert_eq!(run.status.code(), Some(1));
    assert!(!tmp.path().join("results/big/runs.csv").exists());
    std::fs::write(tmp.path().join("hs.toml"), spec("hs", 1_000_000)).unwrap();
    let out = in_dir(tmp.path(), &["check", "hs.toml"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn usage_errors_exit_with_two() {
    let out = metabezier()
        .args(["run", "x.toml", "--shard", "5/3"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected a shard as K/N"));
}

#[test]
fn check_of_a_campaign_over_the_limits_refuses_it_as_run_does() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("huge.toml"),
        "[experiment]\nname = \"huge\"\nseed = 1\nruns = 4294967295\nbudget = 100\n\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\n",
    )
    .unwrap();
    let out = in_dir(tmp.path(), &["check", "huge.toml"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("huge.toml:11:1: algorithm[1]: with its cell the campaign has 1 problems × 1 cells × 4294967295 runs = 4294967295 runs, over the limit of 10000000 runs"),
        "{stderr}"
    );
    // Under --allow-large, check describes it.
    let out = in_dir(tmp.path(), &["check", "huge.toml", "--allow-large"]);
    assert_eq!(out.status.code(), Some(0));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains("= 4294967295 runs, 429496729500 evaluations"),
        "{stdout}"
    );
    assert!(!tmp.path().join("results").exists());
}

#[test]
fn a_failed_journal_write_stops_the_campaign_and_keeps_every_finished_run() {
    // A file-size limit (ulimit -f, with SIGXFSZ ignored so that the write
    // fails with EFBIG instead of killing the process) stands in for a full
    // disk: the journal's appends fail once it passes 2 KiB.
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(
        tmp.path().join("s.toml"),
        "[experiment]\nname = \"s\"\nseed = 3\nruns = 60\nbudget = 200\n\n[[problem]]\nfunction = \"sphere\"\ndim = 3\n\n[[algorithm]]\nname = \"hs\"\n",
    )
    .unwrap();
    let bin = env!("CARGO_BIN_EXE_metabezier");
    let out = Command::new("sh")
        .current_dir(tmp.path())
        .arg("-c")
        .arg(format!(
            "trap '' XFSZ; ulimit -f 4; exec '{bin}' run s.toml --out limited --threads 1 -q"
        ))
        .output()
        .unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("limited/journal.csv: cannot append to"),
        "{stderr}"
    );
    let journal = std::fs::read_to_string(tmp.path().join("limited/journal.csv")).unwrap();
    let kept = journal.lines().count();
    assert!(kept > 1 && kept < 60, "{kept} journal lines");
    assert!(!tmp.path().join("limited/runs.csv").exists());
    // Without the limit the campaign resumes from the kept runs and ends
    // with the files of an uninterrupted run.
    for (dir, resume) in [("limited", true), ("whole", false)] {
        let mut cmd = metabezier();
        cmd.current_dir(tmp.path())
            .args(["run", "s.toml", "--out", dir, "-q"]);
        if resume {
            cmd.arg("--resume");
        }
        assert!(cmd.status().unwrap().success());
    }
    for f in ["runs.csv", "convergence.csv", "hits.csv"] {
        assert_eq!(
            std::fs::read(tmp.path().join("limited").join(f)).unwrap(),
            std::fs::read(tmp.path().join("whole").join(f)).unwrap(),
            "{f}"
        );
    }
}
