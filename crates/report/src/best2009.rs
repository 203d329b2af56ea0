//! COCO's reference algorithms on the bbob suite: for every function,
//! dimension and target precision, the smallest average runtime aRT that any
//! algorithm of a set of archived data sets reached. *best 2009* is the
//! virtual best of the 31 algorithms of the BBOB-2009 workshop (Hansen,
//! Auger, Ros, Finck & Pošík 2010, "Comparing results of 31 algorithms from
//! the black-box optimization benchmarking BBOB-2009", GECCO '10 companion,
//! 1689–1696); *best 2009–16* that of the data sets of the BBOB workshops
//! 2009 to 2016, cocopp's default reference since 2017 (Hansen et al. 2021,
//! "COCO: a platform for comparing continuous optimizers in a black-box
//! setting", Optim. Methods Softw. 36(1):114–144).
//!
//! The data are cocopp's own reference files `refalgs/best2009-bbob.tar.gz`
//! and `refalgs/best09-16-bbob.tar.gz`, vendored unchanged in `vendor/coco/`
//! (cocopp 2.9.1, BSD-3; provenance and sha256 in
//! `vendor/coco/PROVENANCE.md`) and compiled into the binary. Each
//! `bbob-bestalg_fFF_dDD.dat` of the archive lists lines `aRT Δf Δf algorithm
//! successes runs` in increasing aRT, written by cocopp's
//! `bestalg.create_data_files`: one line per distinct rounded aRT, with the
//! smallest target that has it. The aRT to a target `t` is therefore the aRT
//! of the first line whose target is at most `t`; a target below every line's
//! was reached by no algorithm of 2009.
//!
//! The archive's gzip CRC-32 and length and every tar header checksum are
//! checked while it is read (by `flate2` and `tar`); a line that does not
//! parse, or an aRT that decreases, is an error, not a skipped line.

use std::collections::BTreeMap;
use std::io::Read;

/// cocopp's `best2009-bbob.tar.gz`, unchanged.
static ARCHIVE: &[u8] = include_bytes!("../../../vendor/coco/best2009-bbob.tar.gz");

/// cocopp's `best09-16-bbob.tar.gz`, unchanged.
static ARCHIVE_0916: &[u8] = include_bytes!("../../../vendor/coco/best09-16-bbob.tar.gz");

/// A vendored reference: its archive, length, name and description.
struct Vendored {
    archive: &'static [u8],
    /// The archive's length in bytes, as recorded in
    /// `vendor/coco/PROVENANCE.md`.
    len: usize,
    label: &'static str,
    source: &'static str,
    what: &'static str,
}

/// The references, oldest first.
static REFERENCES: [Vendored; 2] = [
    Vendored {
        archive: ARCHIVE,
        len: 54_603,
        label: "best 2009",
        source: "cocopp 2.9.1 refalgs/best2009-bbob.tar.gz",
        what: "COCO's virtual best of the 31 algorithms of BBOB-2009",
    },
    Vendored {
        archive: ARCHIVE_0916,
        len: 63_907,
        label: "best 2009–16",
        source: "cocopp 2.9.1 refalgs/best09-16-bbob.tar.gz",
        what: "COCO's virtual best of the data sets of the BBOB workshops 2009–2016 (cocopp's default reference)",
    },
];

/// One line of a `.dat` file: the aRT of the best 2009 algorithm to `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Step {
    /// The average runtime, in evaluations.
    pub art: f64,
    /// The target precision Δf.
    pub target: f64,
    /// The runs of the best algorithm for this target that reached it.
    pub successes: u32,
    /// Its runs in all.
    pub runs: u32,
}

/// A reference: the steps of every (function, dimension) of its archive.
#[derive(Clone, Debug, Default)]
pub(crate) struct Best2009 {
    steps: BTreeMap<(usize, usize), Vec<Step>>,
    /// How it is named in tables and plots ("best 2009").
    pub label: &'static str,
    /// Its provenance, for the `params` column of the tables.
    pub source: &'static str,
    /// What it is, for the captions.
    pub what: &'static str,
}

impl Best2009 {
    /// Reads the vendored best 2009 archive, checking its length, the gzip
    /// checksum and the tar headers, and parsing every `.dat` file.
    #[cfg(test)]
    pub(crate) fn load() -> Result<Self, String> {
        Self::load_vendored(&REFERENCES[0])
    }

    /// Both references, best 2009 and best 2009–16, each read as
    /// [`Best2009::load`] reads best 2009.
    pub(crate) fn load_all() -> Result<Vec<Self>, String> {
        REFERENCES.iter().map(Self::load_vendored).collect()
    }

    fn load_vendored(v: &Vendored) -> Result<Self, String> {
        if v.archive.len() != v.len {
            return Err(format!(
                "the vendored {} has {} bytes, expected {}",
                v.source,
                v.archive.len(),
                v.len
            ));
        }
        let mut b = Self::from_archive(v.archive)?;
        b.label = v.label;
        b.source = v.source;
        b.what = v.what;
        Ok(b)
    }

    /// Parses a gzip-compressed tar archive in cocopp's `bestalg` layout.
    fn from_archive(bytes: &[u8]) -> Result<Self, String> {
        let mut archive = tar::Archive::new(flate2::read::GzDecoder::new(bytes));
        let mut steps = BTreeMap::new();
        let entries = archive
            .entries()
            .map_err(|e| format!("best2009-bbob.tar.gz: {e}"))?;
        for entry in entries {
            let mut entry = entry.map_err(|e| format!("best2009-bbob.tar.gz: {e}"))?;
            let path = entry
                .path()
                .map_err(|e| format!("best2009-bbob.tar.gz: {e}"))?
                .to_string_lossy()
                .into_owned();
            let Some(key) = dat_key(&path) else {
                continue;
            };
            let mut text = String::new();
            entry
                .read_to_string(&mut text)
                .map_err(|e| format!("best2009-bbob.tar.gz, {path}: {e}"))?;
            steps.insert(key, parse_dat(&text).map_err(|e| format!("{path}: {e}"))?);
        }
        // Reading to the end checks the gzip trailer (CRC-32 and length).
        let mut rest = Vec::new();
        archive
            .into_inner()
            .read_to_end(&mut rest)
            .map_err(|e| format!("best2009-bbob.tar.gz: {e}"))?;
        if steps.is_empty() {
            return Err("best2009-bbob.tar.gz holds no .dat file".into());
        }
        Ok(Self {
            steps,
            ..Self::default()
        })
    }

    /// Whether the reference has data for bbob function `function` at `dim`.
    pub(crate) fn covers(&self, function: usize, dim: usize) -> bool {
        self.steps.contains_key(&(function, dim))
    }

    /// The reference's line for `target` on `function` at `dim`: the first
    /// line whose target is at most `target` (within a relative 1e-9, for
    /// targets printed with 16 digits), `None` when the reference has no
    /// data there or no algorithm of 2009 reached the target.
    pub(crate) fn step(&self, function: usize, dim: usize, target: f64) -> Option<Step> {
        self.steps
            .get(&(function, dim))?
            .iter()
            .find(|s| s.target <= target * (1.0 + 1e-9))
            .copied()
    }

    /// The aRT to `target`, `None` when unreached or not covered.
    pub(crate) fn art(&self, function: usize, dim: usize, target: f64) -> Option<f64> {
        self.step(function, dim, target).map(|s| s.art)
    }
}

/// `(function, dim)` of an archive path `…/bbob-bestalg_f01_d02.dat`.
fn dat_key(path: &str) -> Option<(usize, usize)> {
    let name = path.rsplit('/').next()?;
    let rest = name.strip_prefix("bbob-bestalg_f")?.strip_suffix(".dat")?;
    let (f, d) = rest.split_once("_d")?;
    Some((f.parse().ok()?, d.parse().ok()?))
}

/// The steps of one `.dat` file, in increasing aRT.
fn parse_dat(text: &str) -> Result<Vec<Step>, String> {
    let mut steps: Vec<Step> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('%') {
            continue;
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        let bad = || {
            format!(
                "line {}: expected `aRT Δf Δf algorithm successes runs`, found `{line}`",
                i + 1
            )
        };
        if fields.len() != 6 {
            return Err(bad());
        }
        let art: f64 = fields[0].parse().map_err(|_| bad())?;
        let target: f64 = fields[1].parse().map_err(|_| bad())?;
        let successes: u32 = fields[4].parse().map_err(|_| bad())?;
        let runs: u32 = fields[5].parse().map_err(|_| bad())?;
        if !(art >= 1.0 && art.is_finite() && target > 0.0 && successes <= runs && runs > 0) {
            return Err(bad());
        }
        if let Some(prev) = steps.last() {
            if art < prev.art || target > prev.target {
                return Err(format!(
                    "line {}: aRT {art} or target {target} out of order after aRT {} at {}",
                    i + 1,
                    prev.art,
                    prev.target
                ));
            }
        }
        steps.push(Step {
            art,
            target,
            successes,
            runs,
        });
    }
    if steps.is_empty() {
        return Err("no data line".into());
    }
    Ok(steps)
}

/// `(function, dim)` of a bbob problem named as the runner names it,
/// `bbob_f010_d05` (the report's function key) or `bbob_f010_i01_d05`.
pub(crate) fn bbob_key(name: &str) -> Option<(usize, usize)> {
    let rest = name.strip_prefix("bbob_f")?;
    let mut parts = rest.split('_');
    let f: usize = parts.next()?.parse().ok()?;
    let d = parts.find_map(|p| p.strip_prefix('d'))?.parse().ok()?;
    Some((f, d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_vendored_reference_reads_and_answers_known_values() {
        let b = Best2009::load().unwrap();
        // 24 functions at D = 2, 3, 5, 10, 20, 40.
        assert_eq!(b.steps.len(), 24 * 6);
        for f in 1..=24 {
            for d in [2, 3, 5, 10, 20, 40] {
                assert!(b.covers(f, d), "f{f} D{d}");
            }
        }
        // Lines of bbob-bestalg_f10_d10.dat: "1 1.584893192461114e+07 …" and
        // "1498 3.981071705534973e+01 … BFGS_ros_noiseless.tgz 15 15".
        assert_eq!(b.art(10, 10, 1.584893192461114e7), Some(1.0));
        assert_eq!(b.art(10, 10, 1e9), Some(1.0));
        let s = b.step(10, 10, 3.981071705534973e1).unwrap();
        assert_eq!((s.art, s.successes, s.runs), (1498.0, 15, 15));
        // A target between two lines takes the next line with a smaller
        // target (the aRT of 50 is at least that of 63.1 and at most that
        // of 39.8, and cocopp keeps one line per aRT).
        assert_eq!(b.art(10, 10, 50.0), Some(1498.0));
        // The sphere is solved to 1e-8 in every dimension.
        for d in [2, 5, 10, 20] {
            assert!(b.art(1, d, 1e-8).is_some(), "f1 D{d}");
        }
        assert_eq!(b.art(1, 7, 1e-8), None);
    }

    #[test]
    fn best_2009_16_reads_and_is_at_least_as_good_as_best_2009() {
        let all = Best2009::load_all().unwrap();
        assert_eq!(all.len(), 2);
        let (old, new) = (&all[0], &all[1]);
        assert_eq!((old.label, new.label), ("best 2009", "best 2009–16"));
        assert_eq!(new.steps.len(), 24 * 6);
        // bbob-bestalg_f10_d10.dat of best09-16: "1 1.000000000000000e+07 …"
        // and "236 3.981071705534973e+03 … fmincon_pal_noiseless.tgz 15 15".
        assert_eq!(new.art(10, 10, 1e7), Some(1.0));
        let s = new.step(10, 10, 3.981071705534973e3).unwrap();
        assert_eq!((s.art, s.successes, s.runs), (236.0, 15, 15));
        // Wherever best 2009 reaches 1e-8, so does best 2009–16 (its data
        // sets include 2009's), never slower by more than rounding.
        let mut solved = (0, 0);
        for f in 1..=24 {
            let (a, b) = (old.art(f, 10, 1e-8), new.art(f, 10, 1e-8));
            solved.0 += usize::from(a.is_some());
            solved.1 += usize::from(b.is_some());
            if let (Some(a), Some(b)) = (a, b) {
                assert!(b <= a * 1.01, "f{f}: {b} against {a}");
            }
        }
        assert!(solved.1 >= solved.0, "{solved:?}");
    }

    #[test]
    fn names_and_lines_that_do_not_add_up_are_rejected() {
        assert_eq!(bbob_key("bbob_f010_d05"), Some((10, 5)));
        assert_eq!(bbob_key("bbob_f010_i01_d05"), Some((10, 5)));
        assert_eq!(bbob_key("sphere"), None);
        assert_eq!(
            dat_key("best2009-bbob/bbob-bestalg_f03_d20.dat"),
            Some((3, 20))
        );
        assert_eq!(dat_key("best2009-bbob/bbob-bestalg_f03_d20.tdat"), None);
        assert!(parse_dat("% only a comment\n").is_err());
        assert!(parse_dat("1 1e2 1e2 A 15\n").is_err());
        assert!(parse_dat("5 1e2 1e2 A 15 15\n3 1e1 1e1 A 15 15\n").is_err());
        assert!(parse_dat("1 1e2 1e2 A 16 15\n").is_err());
        // A corrupted archive fails its checksum instead of yielding data.
        let mut bytes = ARCHIVE.to_vec();
        let mid = bytes.len() / 2;
        bytes[mid] ^= 0x55;
        assert!(Best2009::from_archive(&bytes).is_err());
    }
}
