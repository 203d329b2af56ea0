//! Helpers shared by the integration tests that include this module.
#![allow(dead_code)]

/// A right-handed oblique frame: the voxel axes turned 15° about z, then
/// 10° about x.
pub fn oblique_axes() -> [[f64; 3]; 3] {
    let (a, b) = (15f64.to_radians(), 10f64.to_radians());
    let rz = |v: [f64; 3]| {
        [
            a.cos() * v[0] - a.sin() * v[1],
            a.sin() * v[0] + a.cos() * v[1],
            v[2],
        ]
    };
    let rx = |v: [f64; 3]| {
        [
            v[0],
            b.cos() * v[1] - b.sin() * v[2],
            b.sin() * v[1] + b.cos() * v[2],
        ]
    };
    metabezier::ct::IDENTITY_AXES.map(|v| rx(rz(v)))
}

/// `png` with every complete chunk's CRC recomputed, so that a mutation of
/// a header or a length reaches the code behind the CRC check.
pub fn fix_png_crcs(mut png: Vec<u8>) -> Vec<u8> {
    let mut at = 8;
    while at + 12 <= png.len() {
        let len = u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
        let Some(end) = (at + 8).checked_add(len).filter(|e| e + 4 <= png.len()) else {
            break;
        };
        let mut crc = flate2::Crc::new();
        crc.update(&png[at + 4..end]);
        png[end..end + 4].copy_from_slice(&crc.sum().to_be_bytes());
        at = end + 4;
    }
    png
}

/// A TOML list of 1,000 reals from `from` in steps of 10⁻⁴.
pub fn thousand_reals(from: f64) -> String {
    let v: Vec<String> = (0..1000)
        .map(|i| format!("{}", from + i as f64 * 1e-4))
        .collect();
    format!("[{}]", v.join(", "))
}

/// The TOML list 1, 2, …, 1000.
pub fn thousand_counts() -> String {
    let v: Vec<String> = (1..=1000).map(|i| i.to_string()).collect();
    format!("[{}]", v.join(", "))
}

/// HS's `hmcr`, `par`, `bw` and `hms`, each a list of 1,000 values: a grid
/// of 10¹² cells in about 30 KB of spec.
pub fn thousand_value_hs_grid() -> String {
    format!(
        "hmcr = {}\npar = {}\nbw = {}\nhms = {}\n",
        thousand_reals(0.5),
        thousand_reals(0.2),
        thousand_reals(0.001),
        thousand_counts()
    )
}

/// Width and height of a PNG file, from its IHDR chunk.
pub fn png_size(path: &std::path::Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&b[1..4], b"PNG", "{}", path.display());
    let be = |i: usize| u32::from_be_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
    (be(16), be(20))
}

/// What makes the report in `dir` unreadable, one line each (empty when it
/// reads): `report.md` must open (after its title and preamble) with
/// `## Summary`, be under 300 lines, and every picture beside it or under
/// `plots/` must be at most 3,000 px on each side.
pub fn unreadable(dir: &std::path::Path) -> Vec<String> {
    let mut faults = Vec::new();
    let md = std::fs::read_to_string(dir.join("report.md"))
        .unwrap_or_else(|e| panic!("{}: {e}", dir.join("report.md").display()));
    let first = md.lines().find(|l| l.starts_with("## "));
    if first != Some("## Summary") {
        faults.push(format!("the first section is {first:?}, not ## Summary"));
    }
    let lines = md.lines().count();
    if lines >= 300 {
        faults.push(format!("report.md has {lines} lines"));
    }
    let mut pngs = Vec::new();
    for sub in [dir.to_path_buf(), dir.join("plots")] {
        if let Ok(entries) = std::fs::read_dir(&sub) {
            pngs.extend(
                entries
                    .map(|e| e.unwrap().path())
                    .filter(|p| p.extension().is_some_and(|e| e == "png")),
            );
        }
    }
    pngs.sort();
    for p in pngs {
        let (w, h) = png_size(&p);
        if w > 3000 || h > 3000 {
            faults.push(format!("{}: {w} × {h} px", p.display()));
        }
    }
    faults
}

/// Runs the spec `text`, written to `tmp/<name>.toml`, into `tmp/<name>` on
/// two threads and returns that results directory.
pub fn campaign(tmp: &std::path::Path, name: &str, text: &str) -> std::path::PathBuf {
    let out = campaign_runs(tmp, name, text, None);
    assert!(
        out.join("runs.csv").exists(),
        "{} is not complete",
        out.display()
    );
    out
}

/// [`campaign`] stopped after `max_runs` runs when given, so that a
/// journal remains.
pub fn campaign_runs(
    tmp: &std::path::Path,
    name: &str,
    text: &str,
    max_runs: Option<usize>,
) -> std::path::PathBuf {
    use metabezier::experiment::{run_campaign, RunOptions, Spec};
    let path = tmp.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    let spec = Spec::parse(&path, text).unwrap();
    let out = tmp.join(name);
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        max_runs,
        ..RunOptions::default()
    };
    run_campaign(&spec, &opts).unwrap();
    out
}

/// Writes `text` as `dir/spec.toml` and runs `metabezier implant` on it into
/// `dir/out`; returns (success, stderr).
pub fn implant(dir: &std::path::Path, text: &str) -> (bool, String) {
    let spec = dir.join("spec.toml");
    std::fs::write(&spec, text).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_metabezier"))
        .arg("implant")
        .arg(&spec)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The columns of a hand-made `runs.csv` (no instances).
pub const HEADER: &str = "algorithm,kind,params,problem,dim,budget,run,seed,best,error,evaluations,evaluations_to_target,success\n";

/// A runs.csv written by hand: `rows` of (algorithm, problem, run, error,
/// evaluations to target).
pub fn hand_made(rows: &[(&str, &str, u32, f64, Option<u64>)]) -> String {
    let mut s = HEADER.to_owned();
    for (alg, problem, run, error, ett) in rows {
        s.push_str(&format!(
            "{alg},hs,hms=5,{problem},2,1000,{run},{run},{error},{error},1000,{},{}\n",
            ett.map_or(String::new(), |e| e.to_string()),
            ett.is_some()
        ));
    }
    s
}

/// Every file and directory under `dir`, relative to it.
pub fn files_under(dir: &std::path::Path) -> std::collections::BTreeSet<std::path::PathBuf> {
    let mut out = std::collections::BTreeSet::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p.clone());
            }
            out.insert(p.strip_prefix(dir).unwrap().to_owned());
        }
    }
    out
}
