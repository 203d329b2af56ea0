//! `metabezier archive`: a results directory as a reproducible `.tar.gz`
//! with SHA256SUMS, CITATION.cff and .zenodo.json, checked by `--verify`;
//! and the directories it refuses.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common;

use metabezier::experiment::archive::{
    verify_archive_capped, write_archive_capped, ArchiveError, SOFTWARE,
};
use metabezier::experiment::runner::DirLock;
use metabezier::report::{write_report, ReportOptions};
use sha2::{Digest, Sha256};

/// Held by every test of this file: a campaign's lock is an `flock`, and
/// a child that another test thread forks (to run the binary) holds a copy
/// of every open descriptor until it execs, so a lock just released by one
/// test could still look held to the next. One test at a time, none does.
fn serial() -> std::sync::MutexGuard<'static, ()> {
    static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());
    SERIAL.lock().unwrap_or_else(|e| e.into_inner())
}

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_metabezier"))
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A campaign `name` of HS and MHS on Sphere-2 in `dir/name`, with
/// `max_runs` of its 8 runs (all when `None`) and a report when `report`.
fn campaign(dir: &Path, name: &str, max_runs: Option<usize>, report: bool) -> PathBuf {
    let text = format!(
        "[experiment]\nname = \"{name}\"\nseed = 7\nruns = 4\nbudget = 300\n\n\
         [[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"hs\"\n\n\
         [[algorithm]]\nname = \"mhs\"\n"
    );
    let out = common::campaign_runs(dir, name, &text, max_runs);
    assert_eq!(out.join("runs.csv").exists(), max_runs.is_none());
    if report {
        write_report(&out, &ReportOptions::default()).unwrap();
    }
    out
}

fn archive(dir: &Path, out: &Path) -> Output {
    bin()
        .arg("archive")
        .arg(dir)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

/// Archives `dir` into `out`, which must succeed and say `says`.
fn archived(dir: &Path, out: &Path, says: &str) {
    let o = archive(dir, out);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains(says), "{}", stdout(&o));
}

/// A finished campaign `name` in a new temporary directory, archived into
/// `name.tar.gz` beside it: the directory, the campaign and the archive.
fn archived_campaign(name: &str, report: bool) -> (tempfile::TempDir, PathBuf, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), name, None, report);
    let file = tmp.path().join(format!("{name}.tar.gz"));
    archived(&dir, &file, &format!("1 campaign(s) ({name})"));
    (tmp, dir, file)
}

/// Archives `dir` into `out`, which must fail, say `says` and write
/// nothing.
fn refused(dir: &Path, out: &Path, says: &str) {
    let o = archive(dir, out);
    assert!(!o.status.success(), "{}", stdout(&o));
    assert!(stderr(&o).contains(says), "{says} not in {}", stderr(&o));
    assert!(!out.exists(), "{}", out.display());
}

fn verify(file: &Path) -> Output {
    bin()
        .arg("archive")
        .arg("--verify")
        .arg(file)
        .output()
        .unwrap()
}

fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// One entry of a `.tar.gz` as its header and data give it.
struct Entry {
    mode: u32,
    mtime: u64,
    uid: u64,
    gid: u64,
    user: String,
    data: Vec<u8>,
}

/// The entries of a `.tar.gz` by path, directories with a trailing `/`.
fn entries(file: &Path) -> BTreeMap<String, Entry> {
    let gz = flate2::read::GzDecoder::new(std::fs::File::open(file).unwrap());
    let mut out = BTreeMap::new();
    for entry in tar::Archive::new(gz).entries().unwrap() {
        let mut e = entry.unwrap();
        let path = String::from_utf8(e.path_bytes().into_owned()).unwrap();
        let h = e.header().clone();
        let mut data = Vec::new();
        e.read_to_end(&mut data).unwrap();
        let row = Entry {
            mode: h.mode().unwrap(),
            mtime: h.mtime().unwrap(),
            uid: h.uid().unwrap(),
            gid: h.gid().unwrap(),
            user: h.username().unwrap().unwrap_or("").to_owned(),
            data,
        };
        out.insert(path, row);
    }
    out
}

#[test]
fn an_archive_round_trips_and_its_sums_check() {
    let _serial = serial();
    let (tmp, dir, file) = archived_campaign("trip", true);
    let o = verify(&file);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains(": OK, "), "{}", stdout(&o));

    // The gzip header: no mtime, no file name, the "unknown" system.
    let gz = std::fs::read(&file).unwrap();
    assert_eq!(gz[..4], [0x1f, 0x8b, 8, 0]);
    assert_eq!(gz[4..8], [0, 0, 0, 0]);
    assert_eq!(gz[9], 255);

    let all = entries(&file);
    for (path, e) in &all {
        let want = if path.ends_with('/') { 0o755 } else { 0o644 };
        assert_eq!((e.mode, e.mtime, e.uid, e.gid), (want, 0, 0, 0), "{path}");
        assert_eq!(e.user, "", "{path}");
    }
    // Sorted, under one top directory named as the campaign's.
    let paths: Vec<&String> = all.keys().collect();
    assert_eq!(paths[0], "trip/");
    // Every campaign file is there, byte for byte, except the lock.
    let originals = common::files_under(&dir);
    assert!(originals.contains(Path::new(".lock")));
    for rel in originals.iter().filter(|r| dir.join(r).is_file()) {
        let rel = rel.to_str().unwrap();
        if rel != ".lock" {
            let bytes = std::fs::read(dir.join(rel)).unwrap();
            assert_eq!(all[&format!("trip/{rel}")].data, bytes, "{rel}");
        }
    }
    assert!(!all.contains_key("trip/.lock"));
    for rel in [
        "runs.csv",
        "spec.toml",
        "meta.toml",
        "provenance.toml",
        "report.md",
    ] {
        assert!(all.contains_key(&format!("trip/{rel}")), "{rel}");
    }
    assert!(all.keys().any(|k| k.starts_with("trip/plots/")));
    // CITATION.cff is the repository's.
    let cff = std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("CITATION.cff")).unwrap();
    assert_eq!(all["trip/CITATION.cff"].data, cff);
    // SHA256SUMS lists every other file, sorted, with its digest.
    let sums = String::from_utf8(all["trip/SHA256SUMS"].data.clone()).unwrap();
    let listed: Vec<(&str, &str)> = sums.lines().map(|l| (&l[66..], &l[..64])).collect();
    let mut sorted = listed.clone();
    sorted.sort();
    assert_eq!(listed, sorted);
    let files: Vec<&str> = all
        .keys()
        .filter(|k| !k.ends_with('/') && *k != "trip/SHA256SUMS")
        .map(|k| &k["trip/".len()..])
        .collect();
    assert_eq!(listed.iter().map(|l| l.0).collect::<Vec<_>>(), files);
    for (path, hex) in &listed {
        assert_eq!(sha256(&all[&format!("trip/{path}")].data), *hex, "{path}");
    }
    // .zenodo.json: what CITATION.cff and the crate say, nothing made up.
    let zenodo = String::from_utf8(all["trip/.zenodo.json"].data.clone()).unwrap();
    // CITATION.cff names no repository: no related identifier is made up.
    assert!(!zenodo.contains("related_identifiers"), "{zenodo}");
    for part in [
        "\"title\": \"trip: results of a metabezier ".to_owned(),
        "\"upload_type\": \"dataset\"".to_owned(),
        "\"creators\": [{\"name\": \"The metabezier developers\"}]".to_owned(),
        format!("\"version\": \"{}\"", env!("CARGO_PKG_VERSION")),
        "\"license\": \"MIT\"".to_owned(),
        "\"keywords\": [\"Bézier curves\"".to_owned(),
        "\"access_right\": \"open\"".to_owned(),
        "trip (8 runs)".to_owned(),
    ] {
        assert!(zenodo.contains(&part), "{part} not in {zenodo}");
    }

    // `sha256sum -c` agrees, where coreutils are installed.
    let x = tmp.path().join("x");
    std::fs::create_dir(&x).unwrap();
    tar::Archive::new(flate2::read::GzDecoder::new(
        std::fs::File::open(&file).unwrap(),
    ))
    .unpack(&x)
    .unwrap();
    if let Ok(o) = Command::new("sha256sum")
        .args(["-c", "--quiet", "SHA256SUMS"])
        .current_dir(x.join("trip"))
        .output()
    {
        assert!(o.status.success(), "{}", stdout(&o));
    }
}

#[test]
fn the_same_directory_gives_the_same_bytes() {
    let _serial = serial();
    let (tmp, dir, a) = archived_campaign("twice", false);
    let b = tmp.path().join("b.tar.gz");
    // A later modification time changes nothing.
    let runs = std::fs::File::options()
        .append(true)
        .open(dir.join("runs.csv"))
        .unwrap();
    runs.set_modified(std::time::SystemTime::now() + std::time::Duration::from_secs(3600))
        .unwrap();
    drop(runs);
    archived(&dir, &b, "twice");
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
}

#[test]
fn a_flipped_byte_is_refused_with_its_file_named() {
    let _serial = serial();
    let (tmp, _, file) = archived_campaign("flip", false);
    // Flip one byte of runs.csv's data in the tar stream, and recompress.
    let mut tar_bytes = Vec::new();
    flate2::read::GzDecoder::new(std::fs::File::open(&file).unwrap())
        .read_to_end(&mut tar_bytes)
        .unwrap();
    let at = tar::Archive::new(&tar_bytes[..])
        .entries()
        .unwrap()
        .map(Result::unwrap)
        .find(|e| e.path_bytes().as_ref() == b"flip/runs.csv")
        .map(|e| e.raw_file_position() as usize)
        .unwrap();
    tar_bytes[at + 10] ^= 0x01;
    let bad = tmp.path().join("bad.tar.gz");
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut gz, &tar_bytes).unwrap();
    std::fs::write(&bad, gz.finish().unwrap()).unwrap();
    let o = verify(&bad);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains(&format!(
            "{}: flip/runs.csv: differs from SHA256SUMS: its SHA-256 is ",
            bad.display()
        )),
        "{}",
        stderr(&o)
    );
}

#[test]
fn an_unfinished_or_running_campaign_is_refused_and_nothing_is_written() {
    let _serial = serial();
    let tmp = tempfile::tempdir().unwrap();
    let half = campaign(tmp.path(), "half", Some(3), false);
    let out_dir = tmp.path().join("out");
    std::fs::create_dir(&out_dir).unwrap();
    let file = out_dir.join("half.tar.gz");
    let says = format!(
        "{}: the campaign did not finish (its journal remains); finish it with `metabezier run SPEC --out DIR --resume`",
        half.join("journal.csv").display()
    );
    refused(&half, &file, &says);
    // A campaign running (its lock held by this process) is refused too.
    let done = campaign(tmp.path(), "done", None, false);
    let lock = DirLock::take(&done).unwrap();
    let says = format!(
        "{}: a campaign is running in it (another process holds {}); wait for it to finish, then archive",
        done.display(),
        done.join(".lock").display()
    );
    refused(&done, &file, &says);
    assert_eq!(std::fs::read_dir(&out_dir).unwrap().count(), 0);
    drop(lock);
    assert!(archive(&done, &file).status.success());
}

#[test]
fn other_directories_are_refused_with_the_file_named() {
    let _serial = serial();
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("x.tar.gz");
    // No runs.csv.
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    refused(
        &empty,
        &file,
        &format!("{}: holds no runs.csv", empty.display()),
    );
    // A symbolic link is refused, not followed.
    let dir = campaign(tmp.path(), "linked", None, false);
    let link = dir.join("elsewhere.csv");
    std::os::unix::fs::symlink("/etc/hostname", &link).unwrap();
    refused(
        &dir,
        &file,
        &format!(
            "{}: is a symbolic link (to /etc/hostname), which an archive does not follow",
            link.display()
        ),
    );
    std::fs::remove_file(&link).unwrap();
    // The archive inside the directory it archives.
    refused(
        &dir,
        &dir.join("self.tar.gz"),
        "so the archive would hold itself",
    );
    // A file with the name of one the archive adds.
    std::fs::write(dir.join("SHA256SUMS"), "").unwrap();
    refused(
        &dir,
        &file,
        "SHA256SUMS: has the name of a file the archive adds",
    );
    assert!(!file.exists());
}

#[test]
fn the_size_cap_is_stated_and_refuses_with_the_size_named() {
    let _serial = serial();
    let tmp = tempfile::tempdir().unwrap();
    let dir = campaign(tmp.path(), "capped", None, false);
    let file = tmp.path().join("capped.tar.gz");
    let e = write_archive_capped(&dir, &file, &SOFTWARE, 10 << 10).unwrap_err();
    assert!(matches!(e, ArchiveError::TooLarge { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.starts_with(&format!("{}: its archive would hold ", dir.display()))
            && text.contains("bytes (0.00 GiB), over the cap of 10 KiB (MAX_ARCHIVE_BYTES)"),
        "{text}"
    );
    assert!(!file.exists());
    // Under a cap it fits, and --verify stops reading at a lower one.
    let w = write_archive_capped(&dir, &file, &SOFTWARE, 1 << 20).unwrap();
    assert_eq!(
        verify_archive_capped(&file, 1 << 20).unwrap().files,
        w.files
    );
    let e = verify_archive_capped(&file, 10 << 10)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "it is larger than the 10 KiB an archive (uncompressed, MAX_ARCHIVE_BYTES) may be"
        ),
        "{e}"
    );
    assert_eq!(metabezier::experiment::archive::MAX_ARCHIVE_BYTES, 4 << 30);
}

#[test]
fn a_results_directory_of_two_campaigns_is_one_archive() {
    let _serial = serial();
    let tmp = tempfile::tempdir().unwrap();
    let results = tmp.path().join("results");
    std::fs::create_dir(&results).unwrap();
    campaign(&results, "first", None, false);
    campaign(&results, "second", None, false);
    for spec in ["first.toml", "second.toml"] {
        std::fs::remove_file(results.join(spec)).unwrap();
    }
    std::fs::write(results.join("README.md"), "two campaigns\n").unwrap();
    let file = tmp.path().join("results.tar.gz");
    archived(&results, &file, "2 campaign(s) (first, second)");
    assert!(verify(&file).status.success());
    let all = entries(&file);
    for path in [
        "results/first/runs.csv",
        "results/second/runs.csv",
        "results/README.md",
    ] {
        assert!(all.contains_key(path), "{path}");
    }
    let zenodo = String::from_utf8(all["results/.zenodo.json"].data.clone()).unwrap();
    assert!(
        zenodo.contains("\"title\": \"first, second: results of metabezier"),
        "{zenodo}"
    );
    // A subdirectory that is no campaign is named.
    let stray = results.join("stray");
    std::fs::create_dir(&stray).unwrap();
    refused(
        &results,
        &tmp.path().join("y.tar.gz"),
        &format!(
            "{}: holds no runs.csv, so {} is not a directory of campaigns only",
            stray.display(),
            results.display()
        ),
    );
}
