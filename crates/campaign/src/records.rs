//! Run records and the tidy CSV files they are written to.
//!
//! * `runs.csv`: one row per run (the columns of [`RUNS_HEADER`], with
//!   `transform` and `instance` when the campaign has benchmark instances,
//!   see [`Schema`]);
//! * `convergence.csv`: long format, the best-so-far of each run at
//!   log-spaced evaluation counts;
//! * `timing.csv`: wall time per run, kept apart so that `runs.csv` and
//!   `convergence.csv` are byte-identical whatever the thread count;
//! * `hits.csv`: long format, the first evaluation at which each run
//!   reached each target precision ([`default_targets`]);
//! * `journal.csv`: while a campaign runs, each finished run is appended
//!   here as one self-checking line, so an interrupted campaign resumes
//!   without losing finished runs.
//!
//! Reals are written in Rust's shortest round-trip form, so reading a file
//! back gives bit-identical values.

use std::path::Path;

pub use super::outcome::{default_targets, FitDetail};
use super::spec::factor_suffix;
use crate::files::fmt_real;
use crate::functions::Transform;
use crate::optim::{TargetHit, TracePoint};

mod data;
mod read;
mod schema;
mod write;

pub(crate) use data::parse;
pub(crate) use data::{data, parse_real, Real};
pub use data::{DataError, DataProblem, ReadError};
pub(crate) use read::{parse_transform, record_from_fields};
pub use read::{read_results, read_runs};
pub use schema::Schema;
pub(crate) use write::write_files;
pub use write::{
    convergence_csv, fits_csv, hits_csv, runs_csv, segments_csv, timing_csv, write_convergence,
    write_fits, write_hits, write_runs, write_segments, write_timing,
};

/// The result of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunRecord {
    /// The cell's label.
    pub algorithm: String,
    /// The optimiser's spec name (`hs`, `ghs`, `ga`, `pso`, `mhs`).
    pub kind: String,
    /// The canonical parameter text `name=value;...`.
    pub params: String,
    /// The problem's name.
    pub problem: String,
    /// The problem's dimension.
    pub dim: usize,
    /// The run's evaluation budget.
    pub budget: u64,
    /// The benchmark transform (`none` for untransformed and fitting runs).
    pub transform: Transform,
    /// The benchmark instance (1 unless transformed).
    pub instance: u32,
    /// The run number, from 0.
    pub run: u32,
    /// The run's derived seed.
    pub seed: u64,
    /// The best objective value found.
    pub best: f64,
    /// `best − f*`.
    pub error: f64,
    /// Evaluations used.
    pub evaluations: u64,
    /// First evaluation count at which `f ≤ f* + threshold`, if reached.
    pub evaluations_to_target: Option<u64>,
    /// Whether the threshold was reached.
    pub success: bool,
    /// The best-so-far at the convergence checkpoints.
    pub trace: Vec<TracePoint>,
    /// The first evaluation at which each target precision was reached
    /// (`hits.csv`; unreached targets are absent).
    pub hits: Vec<TargetHit>,
    /// For a fitting problem, the fitted outline (`fits.csv`, `segments.csv`).
    pub fit: Option<FitDetail>,
    /// Wall time of the run in seconds (not part of the reproducible output).
    pub wall_seconds: f64,
}

impl FitDetail {
    /// The run-level columns of `fits.csv` after the run key: those of
    /// [`FIT_FIELDS_CURRENT`] with `rms_distance` (the two-sided columns
    /// empty for a run journalled before they existed), else of
    /// [`FIT_FIELDS`].
    pub(super) fn fields(&self) -> Vec<String> {
        let opt = |x: Option<f64>| x.map_or(String::new(), fmt_real);
        let mut out = vec![fmt_real(self.rms), fmt_real(self.max_distance)];
        if let Some(d) = self.rms_distance {
            out.push(fmt_real(d));
            out.push(opt(self.two_sided.map(|t| t.0)));
            out.push(opt(self.two_sided.map(|t| t.1)));
        }
        out.push(opt(self.closing_angle_degrees));
        out.push(opt(self.closing_relative_derivative_gap));
        out
    }

    /// Reads [`FitDetail::fields`] back (segments empty), in either layout.
    pub(super) fn from_fields(path: &Path, line: u64, f: &[&str]) -> Result<FitDetail, ReadError> {
        let opt = |name: &str, t: &str| -> Result<Option<f64>, ReadError> {
            if t.is_empty() {
                Ok(None)
            } else {
                parse(path, line, name, t).map(Some)
            }
        };
        // 4 fields (legacy), 5 (with rms_distance) or 7 (and the two sides).
        let with_rms = f.len() >= FIT_FIELDS_RMS.len();
        let two_sided = f.len() == FIT_FIELDS_CURRENT.len();
        let at = usize::from(with_rms) + 2 * usize::from(two_sided);
        let two = if two_sided {
            match (opt("curve_distance", f[3])?, opt("hausdorff", f[4])?) {
                (Some(c), Some(h)) => Some((c, h)),
                _ => None,
            }
        } else {
            None
        };
        Ok(FitDetail {
            rms: parse(path, line, "rms", f[0])?,
            max_distance: parse(path, line, "max_distance", f[1])?,
            rms_distance: if with_rms {
                Some(parse(path, line, "rms_distance", f[2])?)
            } else {
                None
            },
            two_sided: two,
            closing_angle_degrees: opt("closing_angle_degrees", f[2 + at])?,
            closing_relative_derivative_gap: opt("closing_relative_derivative_gap", f[3 + at])?,
            segments: Vec::new(),
        })
    }
}

/// The bytes the system allocator takes for a block of `n` requested
/// bytes: glibc's chunk, `n` plus its 8-byte header rounded up to 16, at
/// least 32; nothing for an empty block (an empty `String` or `Vec`
/// allocates nothing).
pub const fn heap_block(n: u64) -> u64 {
    if n == 0 {
        return 0;
    }
    let chunk = (n + 8 + 15) & !15;
    if chunk < 32 {
        32
    } else {
        chunk
    }
}

/// The heap one segment row of a fitting run's record takes (its vector of
/// [`FIT_SEGMENT_HEADER`](crate::segments::FIT_SEGMENT_HEADER) strings and each string's block), measured by
/// `tests/memory.rs` over the four fitting functions: the one figure of
/// [`record_heap`] that depends on the values (the length of each real's
/// shortest round-trip form), so the test fails when it drifts.
pub const SEGMENT_ROW_HEAP: u64 = 1336;

/// What a run's record holds beyond its fixed fields, for [`record_heap`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RecordShape {
    /// The lengths of the label, the optimiser's name, the canonical
    /// parameters and the problem's name.
    pub strings: [usize; 4],
    /// Convergence checkpoints in the trace.
    pub trace_points: usize,
    /// Target hits.
    pub hits: usize,
    /// Segments of a fitting run (0 for a benchmark run).
    pub segments: usize,
}

/// The heap one record of `shape` takes beyond `size_of::<RunRecord>()`:
/// its four strings, its trace and hits (16 bytes a point, vectors at
/// their exact length, as the runner keeps them) and a fitting run's
/// segment rows ([`SEGMENT_ROW_HEAP`] each, in a vector of 24-byte rows).
pub fn record_heap(shape: &RecordShape) -> u64 {
    let strings: u64 = shape.strings.iter().map(|&n| heap_block(n as u64)).sum();
    let point = std::mem::size_of::<TracePoint>() as u64;
    let hit = std::mem::size_of::<TargetHit>() as u64;
    let rows = std::mem::size_of::<Vec<String>>() as u64;
    let segments = shape.segments as u64;
    strings
        + heap_block(point * shape.trace_points as u64)
        + heap_block(hit * shape.hits as u64)
        + heap_block(rows * segments)
        + segments * SEGMENT_ROW_HEAP
}

/// The run-level columns of a legacy `fits.csv` after the run key.
pub(crate) const FIT_FIELDS: [&str; 4] = [
    "rms",
    "max_distance",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The run-level columns of `fits.csv` written before the two-sided
/// distances: the orthogonal `rms_distance` next to `max_distance` (read,
/// no longer written).
pub(crate) const FIT_FIELDS_RMS: [&str; 5] = [
    "rms",
    "max_distance",
    "rms_distance",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// The run-level columns of `fits.csv` with the current fitting records:
/// the orthogonal `rms_distance` next to `max_distance` (data → curve),
/// then `curve_distance` (curve → data) and `hausdorff` (the larger).
pub(crate) const FIT_FIELDS_CURRENT: [&str; 7] = [
    "rms",
    "max_distance",
    "rms_distance",
    "curve_distance",
    "hausdorff",
    "closing_angle_degrees",
    "closing_relative_derivative_gap",
];

/// Identifies a run within a campaign: (cell key, problem match key,
/// budget, run); see [`crate::spec::ProblemEntry::match_key`].
pub type RunKey = (String, String, u64, u32);

impl RunRecord {
    /// The cell key `label:kind[params]`, as [`crate::spec::Cell::key`].
    pub fn cell_key(&self) -> String {
        format!("{}:{}[{}]", self.algorithm, self.kind, self.params)
    }

    /// The problem key without the budget: `problem-dim` and the transform
    /// and instance of a transformed benchmark, as
    /// [`crate::spec::ProblemEntry::match_key`].
    pub fn match_key(&self) -> String {
        format!(
            "{}-{}{}",
            self.problem,
            self.dim,
            factor_suffix(self.transform, self.instance, true, true)
        )
    }

    /// `run R of CELL on PROBLEM`, for messages.
    pub fn describe(&self) -> String {
        format!(
            "run {} of {} on {}",
            self.run,
            self.cell_key(),
            self.match_key()
        )
    }

    /// The run's key.
    pub fn key(&self) -> RunKey {
        (self.cell_key(), self.match_key(), self.budget, self.run)
    }
}

/// The columns of `runs.csv` of a campaign without instances (see
/// [`Schema::runs_header`]).
pub const RUNS_HEADER: [&str; 13] = [
    "algorithm",
    "kind",
    "params",
    "problem",
    "dim",
    "budget",
    "run",
    "seed",
    "best",
    "error",
    "evaluations",
    "evaluations_to_target",
    "success",
];

/// The columns of `convergence.csv` after the run key.
pub(crate) const CONVERGENCE_FIELDS: [&str; 3] = ["evaluations", "best", "error"];

/// The columns of `timing.csv` after the run key.
pub(crate) const TIMING_FIELDS: [&str; 1] = ["wall_seconds"];

/// The fields of `runs.csv` of a campaign without instances: the layout the
/// journal keeps for every run.
pub(crate) fn run_fields(r: &RunRecord) -> Vec<String> {
    vec![
        r.algorithm.clone(),
        r.kind.clone(),
        r.params.clone(),
        r.problem.clone(),
        r.dim.to_string(),
        r.budget.to_string(),
        r.run.to_string(),
        r.seed.to_string(),
        fmt_real(r.best),
        fmt_real(r.error),
        r.evaluations.to_string(),
        r.evaluations_to_target
            .map_or(String::new(), |e| e.to_string()),
        r.success.to_string(),
    ]
}

/// The fields of `r` in `runs.csv` under `schema`.
pub(crate) fn runs_row(schema: Schema, r: &RunRecord) -> Vec<String> {
    let mut row = run_fields(r);
    if schema.instances {
        row.splice(
            6..6,
            [r.transform.name().to_owned(), r.instance.to_string()],
        );
    }
    row
}

/// A run record with awkward values (quotes, extreme reals, an infinite
/// trace point) for round-trip tests.
#[cfg(test)]
pub(crate) fn sample_record(run: u32) -> RunRecord {
    RunRecord {
        algorithm: "HS, tuned".into(),
        kind: "hs".into(),
        params: "hms=5;hmcr=0.9".into(),
        problem: "sphere".into(),
        dim: 10,
        budget: 1000,
        transform: Transform::ShiftRotate,
        instance: 3,
        run,
        seed: u64::MAX - 3,
        best: 1.234_567_890_123_456_7e-13,
        error: 1.234_567_890_123_456_7e-13,
        evaluations: 1000,
        evaluations_to_target: if run == 0 { None } else { Some(17) },
        success: run != 0,
        trace: vec![
            TracePoint {
                evaluations: 1,
                best: f64::INFINITY,
            },
            TracePoint {
                evaluations: 10,
                best: 0.1 + 0.2,
            },
        ],
        hits: vec![
            TargetHit {
                precision: 100.0,
                evaluations: 1,
            },
            TargetHit {
                precision: 1e-8,
                evaluations: 10,
            },
        ],
        fit: None,
        wall_seconds: 0.0125,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn result_files_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let recs = vec![sample_record(0), sample_record(1)];
        std::fs::write(dir.path().join("runs.csv"), runs_csv(&recs)).unwrap();
        std::fs::write(
            dir.path().join("convergence.csv"),
            convergence_csv(&recs, |_| 0.0),
        )
        .unwrap();
        std::fs::write(dir.path().join("timing.csv"), timing_csv(&recs)).unwrap();
        std::fs::write(dir.path().join("hits.csv"), hits_csv(&recs)).unwrap();
        assert_eq!(read_results(dir.path()).unwrap(), recs);
        let runs = std::fs::read_to_string(dir.path().join("runs.csv")).unwrap();
        assert!(
            runs.starts_with("algorithm,kind,params,problem,dim,budget,transform,instance,run,")
        );
        // A budget grid adds the budget to the keyed files.
        let mut grid = recs.clone();
        grid.extend(recs.iter().cloned().map(|mut r| {
            r.budget *= 10;
            r
        }));
        std::fs::write(dir.path().join("runs.csv"), runs_csv(&grid)).unwrap();
        std::fs::write(
            dir.path().join("convergence.csv"),
            convergence_csv(&grid, |_| 0.0),
        )
        .unwrap();
        std::fs::write(dir.path().join("timing.csv"), timing_csv(&grid)).unwrap();
        std::fs::write(dir.path().join("hits.csv"), hits_csv(&grid)).unwrap();
        let timing = std::fs::read_to_string(dir.path().join("timing.csv")).unwrap();
        assert!(timing.starts_with(
            "algorithm,kind,params,problem,dim,budget,transform,instance,run,wall_seconds"
        ));
        assert_eq!(read_results(dir.path()).unwrap(), grid);
    }
}
