//! Bad input, second round: limits counted before anything is expanded or
//! read, `check` refusing what `run` refuses, job scripts that carry any
//! path safely, lost writes that fail the command, and results that appear
//! whole or not at all.

use crate::common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::hand_made;
use metabezier::report::{write_report, ReportOptions};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
}

fn crate_path(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A spec of two runs of HS on Sphere-2, with `extra` lines in
/// `[experiment]` and `algorithm` lines after `name = "hs"`.
fn small_spec(extra: &str, algorithm: &str) -> String {
    format!(
        "[experiment]\nname = \"small\"\nseed = 1\nruns = 2\nbudget = 500\n{extra}\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\n{algorithm}\n"
    )
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `check` and `run` of `spec`: both must fail, with the same message.
fn refused_alike(spec: &Path, out: &Path) -> String {
    let check = bin().arg("check").arg(spec).output().unwrap();
    let run = bin()
        .arg("run")
        .arg(spec)
        .arg("--out")
        .arg(out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(
        !check.status.success(),
        "check accepted it: {}",
        stderr(&check)
    );
    assert!(!run.status.success(), "run accepted it");
    assert_eq!(stderr(&check), stderr(&run));
    assert!(!out.exists(), "run wrote {}", out.display());
    stderr(&check)
}

#[test]
fn a_spec_is_read_only_up_to_its_size_limit() {
    // An endless stream: read up to the limit, then refused.
    let o = bin().args(["check", "/dev/zero"]).output().unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains(
            "/dev/zero: cannot read the spec: it is larger than the 16 MiB a spec may be"
        ),
        "{}",
        stderr(&o)
    );
    // A spec that is not UTF-8 is named with the offset of its first bad byte.
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("latin1.toml");
    std::fs::write(&p, b"[experiment]\nname = \"caf\xe9\"\n").unwrap();
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert!(
        stderr(&o).contains("it is not UTF-8 text (invalid byte at offset 24)"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn check_refuses_what_run_refuses_with_the_same_message() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 9·10⁷ runs: over the run limit, counted before any run is listed.
    let many = write(
        d,
        "many.toml",
        &small_spec("", "").replace("runs = 2", "runs = 90000000"),
    );
    let e = refused_alike(&many, &d.join("o1"));
    assert!(
        e.contains(
            "1 problems × 1 cells × 90000000 runs = 90000000 runs, over the limit of 10000000 runs"
        ) && e.contains("--allow-large"),
        "{e}"
    );
    // A name too long for a directory.
    let long = format!("name = \"{}\"", "a".repeat(300));
    let name = write(
        d,
        "name.toml",
        &small_spec("", "").replace("name = \"small\"", &long),
    );
    let e = refused_alike(&name, &d.join("o2"));
    assert!(
        e.contains("name.toml:2:8: experiment.name: expected a name of at most 100 characters"),
        "{e}"
    );
    // A budget over the per-run limit, and one per dimension that passes it.
    let budget = write(
        d,
        "budget.toml",
        &small_spec("", "").replace("budget = 500", "budget = 20000000000"),
    );
    let e = refused_alike(&budget, &d.join("o3"));
    assert!(
        e.contains("budget.toml:5:10: experiment.budget: 20000000000 evaluations per run pass the limit of 10000000000"),
        "{e}"
    );
    let per_dim = write(
        d,
        "per_dim.toml",
        &small_spec("", "").replace("budget = 500", "budget_per_dim = 6000000000"),
    );
    let e = refused_alike(&per_dim, &d.join("o4"));
    assert!(
        e.contains("budget_per_dim × dim = 12000000000 evaluations per run at D = 2"),
        "{e}"
    );
    // --allow-large lifts the run and budget limits for check as for run.
    let o = bin()
        .arg("check")
        .arg(&budget)
        .arg("--allow-large")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = bin()
        .arg("check")
        .arg(&many)
        .arg("--allow-large")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn grids_are_counted_before_they_are_expanded() {
    let dir = tempfile::tempdir().unwrap();
    let grid = common::thousand_value_hs_grid();
    let p = write(dir.path(), "grid.toml", &small_spec("", &grid));
    let e = refused_alike(&p, &dir.path().join("o"));
    assert!(
        e.contains("grid.toml:11:1: algorithm[1]: its grid of 1000 × 1000 × 1000 × 1000 = 1000000000000 cells pass the limit of 1000000 algorithm cells"),
        "{e}"
    );
    // The same for problems: 1,000 dimensions × 2,000 instances.
    let dims: Vec<String> = (2..1002).map(|i| i.to_string()).collect();
    let text = small_spec("", "").replace(
        "dim = 2",
        &format!(
            "dim = [{}]\ntransform = \"shift\"\ninstances = 2000",
            dims.join(", ")
        ),
    );
    let p = write(dir.path(), "problems.toml", &text);
    let e = refused_alike(&p, &dir.path().join("o"));
    assert!(
        e.contains("problems.toml:7:1: problem[1]: this section makes 2000000 problems, over the limit of 1000000 problems of a spec"),
        "{e}"
    );
}

#[test]
fn messages_name_the_type_and_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        dir.path(),
        "float.toml",
        &small_spec("", "").replace("budget = 500", "budget = 1e3"),
    );
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert!(
        stderr(&o).contains("experiment.budget: expected an integer ≥ 1, found the float 1000.0 (write an integer without a decimal point or exponent: 1000)"),
        "{}",
        stderr(&o)
    );
    let p = write(dir.path(), "hms.toml", &small_spec("", "hms = 5.0"));
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert!(stderr(&o).contains("found the float 5.0"), "{}", stderr(&o));
    let p = write(dir.path(), "dup.toml", &small_spec("runs = 3", ""));
    let o = bin().arg("check").arg(&p).output().unwrap();
    assert!(
        stderr(&o).contains(
            "dup.toml:6:1: invalid TOML: duplicate key runs: a key is set once in its table"
        ),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_dangling_symlink_as_out_is_named_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write(dir.path(), "s.toml", &small_spec("", ""));
    let link = dir.path().join("link");
    std::os::unix::fs::symlink(dir.path().join("nowhere"), &link).unwrap();
    let o = bin()
        .arg("run")
        .arg(&spec)
        .arg("--out")
        .arg(&link)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("is a symbolic link to")
            && stderr(&o).contains("nowhere, which does not exist"),
        "{}",
        stderr(&o)
    );
    assert!(!stderr(&o).contains("File exists"), "{}", stderr(&o));
}

#[test]
fn fit_budgets_have_a_limit() {
    let o = bin()
        .arg("fit")
        .arg(crate_path("data/outlines/coin.png"))
        .args(["--budget", "18446744073709551615"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--budget 18446744073709551615: more than the limit of 10000000000 evaluations per segment; pass --allow-large"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_lost_write_to_standard_output_fails_the_command() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let spec = write(dir.path(), "s.toml", &small_spec("", ""));
    let full = || {
        std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap()
    };
    let cases: [Vec<&std::ffi::OsStr>; 3] = [
        vec!["check".as_ref(), spec.as_os_str()],
        vec!["list".as_ref()],
        vec![
            "slurm".as_ref(),
            spec.as_os_str(),
            "--tasks".as_ref(),
            "2".as_ref(),
        ],
    ];
    for args in cases {
        let o = bin().args(&args).stdout(full()).output().unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert!(
            stderr(&o).contains("cannot write the output: No space left on device"),
            "{args:?}: {}",
            stderr(&o)
        );
    }
    // A reader that stops early is not an error.
    let mut child = bin()
        .arg("list")
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    assert!(child.wait().unwrap().success());
}

#[test]
fn job_scripts_refuse_control_characters_and_quote_everything_else() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let spec = write(d, "s.toml", &small_spec("", ""));
    // A newline in --out, or an escape in the spec's file name, is refused.
    let o = bin()
        .arg("slurm")
        .arg(&spec)
        .args(["--tasks", "2", "--out"])
        .arg(d.join("x\nrm -rf y"))
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("--out \"")
            && stderr(&o).contains("x\\nrm -rf y\": the path holds a control character (U+000A)"),
        "{}",
        stderr(&o)
    );
    assert!(o.stdout.is_empty());
    let odd_spec = d.join("s\u{1b}.toml");
    std::fs::copy(&spec, &odd_spec).unwrap();
    let o = bin()
        .arg("slurm")
        .arg(&odd_spec)
        .args(["--tasks", "2"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("control character (U+001B)"),
        "{}",
        stderr(&o)
    );

    // Quotes, spaces, $(…) and backquotes are carried verbatim: the script,
    // run by bash as task 0, writes its shard into exactly that directory
    // and runs nothing else.
    let out = d.join("it's a $(touch pwned) `touch pwned2` \"dir\"");
    let o = bin()
        .arg("slurm")
        .arg(&spec)
        .args(["--tasks", "2", "--time", "00:10:00", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let script = String::from_utf8(o.stdout).unwrap();
    assert!(script.contains("#SBATCH --time=00:10:00"), "{script}");
    assert!(script.contains("#SBATCH --array=0-1"), "{script}");
    let job = write(d, "job.sh", &script);
    let run = Command::new("bash")
        .arg(&job)
        .current_dir(d)
        .env("SLURM_ARRAY_TASK_ID", "0")
        .output()
        .unwrap();
    assert!(run.status.success(), "{}", stderr(&run));
    assert!(out.join("shard-1-of-2").join("runs.csv").is_file());
    assert!(!d.join("pwned").exists() && !d.join("pwned2").exists());
}

/// Runs `args` with files limited to `kib` KiB (SIGXFSZ ignored, so a write
/// past it fails with EFBIG as a full disk would).
fn with_file_limit(kib: u32, args: &[&std::ffi::OsStr]) -> Output {
    Command::new("bash")
        .arg("-c")
        .arg(format!("trap '' XFSZ; ulimit -f {kib}; exec \"$@\""))
        .arg("_")
        .arg(env!("CARGO_BIN_EXE_metabezier"))
        .args(args)
        .output()
        .unwrap()
}

/// The files of `dir` (name → bytes).
fn files(dir: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let e = e.unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                std::fs::read(e.path()).unwrap(),
            )
        })
        .collect()
}

#[test]
fn fit_results_appear_whole_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("fit");
    let coin = crate_path("data/outlines/coin.png");
    let fit = |seed: &str, limit: Option<u32>| {
        let args: Vec<&std::ffi::OsStr> = vec![
            "fit".as_ref(),
            coin.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
            "--seed".as_ref(),
            seed.as_ref(),
            "--budget".as_ref(),
            "200".as_ref(),
            // A seeded method, so that another seed gives another fit.
            "--algorithm".as_ref(),
            "mhs".as_ref(),
            "--outputs".as_ref(),
            "all".as_ref(),
        ];
        match limit {
            Some(kib) => with_file_limit(kib, &args),
            None => bin().args(&args).output().unwrap(),
        }
    };
    // On a "disk" that takes no file over 100 KiB the overlay PNG fails:
    // nothing is left, not even the directory.
    let o = fit("1", Some(100));
    assert!(!o.status.success());
    assert!(stderr(&o).contains("File too large"), "{}", stderr(&o));
    assert!(
        !out.exists(),
        "{:?}",
        std::fs::read_dir(&out).map(|d| d.count())
    );
    // A complete fit, then a failing refit: the first fit's files stay as
    // they were, with no file of the second beside them.
    let o = fit("1", None);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = files(&out);
    assert!(before.contains_key("overlay.png") && before.contains_key("fit.csv"));
    let o = fit("2", Some(100));
    assert!(!o.status.success());
    assert_eq!(files(&out), before);
    // A staging directory left by a killed process is removed by the next
    // fit, once that process is gone.
    let mut gone = Command::new("true").spawn().unwrap();
    let pid = gone.id();
    gone.wait().unwrap();
    let stale = out.join(format!(".staging-{pid}-0123456789abcdef"));
    std::fs::create_dir(&stale).unwrap();
    std::fs::write(stale.join(".fit.csv.1.2.tmp"), b"half").unwrap();
    let o = fit("2", None);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists());
    let after = files(&out);
    assert_eq!(
        after.keys().collect::<Vec<_>>(),
        before.keys().collect::<Vec<_>>()
    );
    assert_ne!(after["fit.csv"], before["fit.csv"]);
}

#[test]
fn implant_results_appear_whole_or_not_at_all() {
    let dir = tempfile::tempdir().unwrap();
    let spec = write(
        dir.path(),
        "implant.toml",
        &format!(
            "[implant]\nvolume = \"{}\"\nfirst_z = 40\nmidline_slices = [86, 92]\nmethod = \"mhs\"\nbudget = 2000\nseed = 7\n\n[defect]\nslices = [70, 72]\noverlays = [72]\n",
            crate_path("data/ct0051/ct0051_z040-100.inv3").display()
        ),
    );
    let out = dir.path().join("implant");
    let args: Vec<&std::ffi::OsStr> = vec![
        "implant".as_ref(),
        spec.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ];
    // The STL (47 KB) and metrics.csv are written, the overlay (140 KB) is
    // not: neither is left without report.md.
    let o = with_file_limit(100, &args);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("File too large"), "{}", stderr(&o));
    assert!(!out.exists());
    let o = bin().args(&args).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let names: Vec<String> = files(&out).into_keys().collect();
    assert!(
        names.contains(&"implant.stl".to_owned()) && names.contains(&"report.md".to_owned()),
        "{names:?}"
    );
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");
}

#[test]
fn external_runs_are_checked_like_our_own() {
    // Issue 49: `report --external` refuses what the campaign's reader
    // would, naming the file and line, and the directory's own runs.csv.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("base");
    std::fs::create_dir_all(&dir).unwrap();
    let ours: Vec<(&str, &str, u32, f64, Option<u64>)> =
        (0..5).map(|r| ("MHS", "sphere", r, 1e-3, None)).collect();
    std::fs::write(dir.join("runs.csv"), hand_made(&ours)).unwrap();
    let good: Vec<(&str, &str, u32, f64, Option<u64>)> =
        (0..5).map(|r| ("ES", "sphere", r, 1e-4, None)).collect();
    let good = hand_made(&good);
    let report = |name: &str, text: &str| {
        let ext = tmp.path().join(name);
        std::fs::write(&ext, text).unwrap();
        write_report(
            &dir,
            &ReportOptions {
                external: Some(ext),
                ..ReportOptions::default()
            },
        )
        .map(|_| ())
        .map_err(|e| e.to_string())
    };
    report("good.csv", &good).unwrap();
    let third = |from: &str, to: &str| {
        let mut lines: Vec<String> = good.lines().map(str::to_owned).collect();
        lines[3] = lines[3].replacen(from, to, 1);
        lines.join("\n") + "\n"
    };
    for (text, want) in [
        (
            third(",0.0001,0.0001,", ",NaN,NaN,"),
            "nan.csv:4: error NaN of run 2 of ES",
        ),
        (third(",0.0001,0.0001,", ",-1,-1,"), "error -1 of run 2"),
        (
            third(",2,1000,", ",2,2000,"),
            "problem sphere-2 at budget 2000 is not one of",
        ),
        (
            third(",1000,,false", ",5000,,false"),
            "used 5000 evaluations, over its budget of 1000",
        ),
        (
            third("ES,", "=1+1,"),
            "label \"=1+1\" starts like a spreadsheet formula",
        ),
        (
            good.clone() + good.lines().nth(1).unwrap() + "\n",
            "appears twice",
        ),
    ] {
        let name = if want.starts_with("nan") {
            "nan.csv"
        } else {
            "bad.csv"
        };
        let e = report(name, &text).unwrap_err();
        assert!(e.contains("--external") && e.contains(want), "{want}: {e}");
    }
    let e = write_report(
        &dir,
        &ReportOptions {
            external: Some(dir.join("runs.csv")),
            ..ReportOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("is the results directory's own runs.csv"), "{e}");
}

#[cfg(unix)]
#[test]
fn a_report_never_writes_through_a_link_out_of_its_directory() {
    // Issue 49: `tables/` or `plots/` linked elsewhere is refused before
    // anything is computed, and nothing lands at the link's target; a link
    // within the directory is followed.
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("base");
    std::fs::create_dir_all(&dir).unwrap();
    let rows: Vec<(&str, &str, u32, f64, Option<u64>)> = (0..5)
        .flat_map(|r| {
            [
                ("MHS", "sphere", r, 1e-3, None),
                ("HS", "sphere", r, 1e-2, None),
            ]
        })
        .collect();
    std::fs::write(dir.join("runs.csv"), hand_made(&rows)).unwrap();
    let outside = tmp.path().join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    for name in ["tables", "plots"] {
        std::os::unix::fs::symlink(&outside, dir.join(name)).unwrap();
        let e = write_report(&dir, &ReportOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains(&format!("{name} is a symbolic link to"))
                && e.contains("outside the results directory"),
            "{e}"
        );
        assert_eq!(std::fs::read_dir(&outside).unwrap().count(), 0);
        assert!(!dir.join("report.md").exists());
        std::fs::remove_file(dir.join(name)).unwrap();
    }
    // Within the directory: followed.
    std::fs::create_dir_all(dir.join("mine")).unwrap();
    std::os::unix::fs::symlink(dir.join("mine"), dir.join("tables")).unwrap();
    write_report(&dir, &ReportOptions::default()).unwrap();
    assert!(dir.join("mine/verdicts.csv").exists() || dir.join("mine/descriptive.csv").exists());
}
