//! The campaign runner: spec → seeded runs in parallel → records on disk.
//!
//! Runs execute in parallel with rayon, but the output does not depend on
//! the thread count: each run's seed is derived from the spec alone
//! ([`crate::rng::derive_seed`]), and the rows are written in the
//! campaign's fixed order (problem, cell, run) once all runs are done.
//! Finished runs are journalled as they complete, so `--resume` continues
//! an interrupted campaign without redoing them, and `--shard K/N` runs one
//! slice of a campaign, in its own directory, for
//! [`merge`](super::shards::merge) to join.

use std::collections::HashMap;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::Instant;

use rayon::prelude::*;

use super::records::{self, RunKey, RunRecord};
use super::spec::{FitCase, RunId, Spec};
use super::{journal, journal_check};
use super::{CampaignAction, CampaignError, ExperimentError};
use crate::files::{
    create_dir, csv_bytes, fmt_real, read_text_limited, remove_stale_temporaries, write_atomic,
    IoError, MAX_TEXT_BYTES,
};
use crate::optim::{interrupt, MAX_STATE_BYTES};
use crate::reconstruction::Method;
use crate::rng::{derive_seed, fnv1a64, RNG_NAME};

/// One slice `K/N` of a campaign: the runs whose index `i` has `i mod N = K − 1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// This slice, from 1.
    pub k: usize,
    /// The number of slices.
    pub n: usize,
}

impl Shard {
    /// Parses `K/N` with `1 ≤ K ≤ N`.
    pub fn parse(text: &str) -> Result<Shard, ShardError> {
        let bad = |problem| ShardError {
            text: text.to_owned(),
            problem,
        };
        let (k, n) = text
            .split_once('/')
            .ok_or_else(|| bad(ShardProblem::NoSlash))?;
        let k: usize = k.trim().parse().map_err(|_| bad(ShardProblem::K))?;
        let n: usize = n.trim().parse().map_err(|_| bad(ShardProblem::N))?;
        if n == 0 {
            return Err(bad(ShardProblem::N));
        }
        if k == 0 || k > n {
            return Err(bad(ShardProblem::OutOfRange { k, n }));
        }
        Ok(Shard { k, n })
    }

    /// Whether run `index` belongs to this slice.
    pub fn contains(self, index: usize) -> bool {
        index % self.n == self.k - 1
    }

    /// The name of this shard's own directory, `shard-K-of-N`.
    pub fn dir_name(self) -> String {
        format!("shard-{}-of-{}", self.k, self.n)
    }

    /// The shard a directory named `shard-K-of-N` holds, if it is so named.
    pub fn from_dir_name(name: &str) -> Option<Shard> {
        let (k, n) = name.strip_prefix("shard-")?.split_once("-of-")?;
        let (k, n) = (k.parse().ok()?, n.parse().ok()?);
        (k >= 1 && k <= n && name == Shard { k, n }.dir_name()).then_some(Shard { k, n })
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

/// A shard that is not `K/N` with `1 ≤ K ≤ N`: the text given and what is
/// wrong with it.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("expected a shard as K/N with 1 ≤ K ≤ N, such as 2/8, found \"{text}\": {problem}")]
pub struct ShardError {
    /// The text given.
    pub text: String,
    /// What is wrong with it.
    pub problem: ShardProblem,
}

/// What is wrong with a shard's text.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
pub enum ShardProblem {
    /// No `/` between K and N.
    #[error("there is no '/' between K and N")]
    NoSlash,
    /// K is not a whole number.
    #[error("K is not a whole number")]
    K,
    /// N is not a whole number of at least 1.
    #[error("N is not a whole number of at least 1")]
    N,
    /// K is 0 or more than N.
    #[error("shard {k} does not exist; the shards of {n} are 1 to {n}")]
    OutOfRange {
        /// The K given.
        k: usize,
        /// The N given.
        n: usize,
    },
}

/// How to run a campaign.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output directory; default `results/<name>`. A shard writes into its
    /// own `shard-K-of-N/` beneath it (see [`shard_dir`]).
    pub out: Option<PathBuf>,
    /// Worker threads; default all cores.
    pub threads: Option<usize>,
    /// Continue a campaign whose output directory already holds runs.
    pub resume: bool,
    /// Run only this slice.
    pub shard: Option<Shard>,
    /// Stop after this many new runs (the rest can be resumed later).
    pub max_runs: Option<usize>,
    /// Show a progress bar (only ever drawn when stderr is a terminal).
    pub progress: bool,
    /// Lift the limits on the number of runs and the estimated memory.
    pub allow_large: bool,
}

/// An estimate of the memory a campaign of `spec` takes at its peak, once
/// every run is finished and before the result files are streamed out;
/// see [`estimated_shard_bytes`].
pub fn estimated_bytes(spec: &Spec) -> u128 {
    estimated_shard_bytes(spec, None)
}

/// The memory the runs of `shard` (all runs if `None`) take at their peak.
///
/// Each run's record takes `size_of::<RunRecord>()` bytes and the heap of
/// [`records::record_heap`]: its four strings, its trace (the spec's
/// checkpoints), its target hits (counted as every target reached: the
/// number of targets a run reaches is known only once it ran, so this is an
/// upper bound, exact for runs that converge) and a fitting run's segment
/// rows. The campaign holds the records twice at its peak: in the vector
/// the runs fill and in the table they are moved into, at the moment that
/// table doubles (both tables then live); plus two positions per run. Tests
/// (`tests/memory.rs`) hold the model to the heap measured by a counting
/// allocator, and `make memory` to the peak resident set size.
pub fn estimated_shard_bytes(spec: &Spec, shard: Option<Shard>) -> u128 {
    let cells: Vec<[usize; 3]> = spec
        .cells
        .iter()
        .map(|c| {
            [
                c.label.len(),
                c.method.name().len(),
                c.params.canonical().len(),
            ]
        })
        .collect();
    let runs = u128::from(spec.runs);
    let mut heap = 0u128;
    let mut count = 0u128;
    for (p, entry) in spec.problems.iter().enumerate() {
        let (trace_points, hits, segments) = entry.kind.record_shape(spec, entry);
        let problem = entry.name().len();
        for (c, [label, kind, params]) in cells.iter().enumerate() {
            let first = (p as u128 * cells.len() as u128 + c as u128) * runs;
            let n = runs_in(first, runs, shard);
            let shape = records::RecordShape {
                strings: [*label, *kind, *params, problem],
                trace_points,
                hits,
                segments,
            };
            heap += n * u128::from(records::record_heap(&shape));
            count += n;
        }
    }
    heap + held_twice(count)
}

/// The runs among positions `first..first + n` that `shard` holds.
fn runs_in(first: u128, n: u128, shard: Option<Shard>) -> u128 {
    let Some(s) = shard else {
        return n;
    };
    let (k, big_n) = (s.k as u128 - 1, s.n as u128);
    let below = |x: u128| x / big_n + u128::from(x % big_n > k);
    below(first + n) - below(first)
}

/// The containers of `n` finished runs at the campaign's peak: the vector
/// the runs fill (one record each), the table they move into while it
/// doubles to its final size (its old half and its new whole, a record, a
/// position and a control byte per bucket; buckets a power of two at most
/// 7/8 full), and the positions of the runs to do and done.
fn held_twice(n: u128) -> u128 {
    let record = std::mem::size_of::<RunRecord>() as u128;
    let bucket = record + 8 + 1;
    let buckets = if n == 0 {
        0
    } else {
        ((n * 8).div_ceil(7)).next_power_of_two().max(4)
    };
    n * (record + 16) + buckets * bucket + buckets / 2 * bucket
}

/// The most memory a campaign's results may take, by
/// [`estimated_shard_bytes`], without `--allow-large`: 4 GiB.
pub const MAX_RESULT_BYTES: u128 = 4 << 30;

/// Refuses, before anything is allocated, a campaign (or shard) over
/// [`super::MAX_RUNS`] runs or [`MAX_RESULT_BYTES`] of estimated memory,
/// unless `allow_large`; and more worker threads than 4 × the cores. A
/// shard is held to the limits by its own runs, so a campaign too large
/// for one machine runs as shards.
pub fn check_limits(spec: &Spec, opts: &RunOptions) -> Result<(), CampaignError> {
    let runs = match opts.shard {
        Some(s) => runs_in(0, spec.run_count(), Some(s)),
        None => spec.run_count(),
    };
    let bytes = estimated_shard_bytes(spec, opts.shard);
    if !opts.allow_large && (runs > super::MAX_RUNS || bytes > MAX_RESULT_BYTES) {
        return Err(CampaignError::TooLarge {
            spec: spec.path.clone(),
            runs,
            gib: bytes as f64 / f64::from(1u32 << 30),
        });
    }
    if !opts.allow_large {
        state_within_limit(spec)?;
    }
    if let Some(asked) = opts.threads {
        let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
        if asked > 4 * cores {
            return Err(CampaignError::TooManyThreads {
                asked,
                max: 4 * cores,
                cores,
            });
        }
    }
    Ok(())
}

/// Refuses a campaign one of whose runs would allocate more than
/// [`MAX_STATE_BYTES`] of optimiser state ([`crate::optim::Algorithm::state_bytes`]: CMA-ES's
/// covariance at D = 30,000 is 7.2 GB), naming the cell, its algorithm, D
/// and the bytes. Fitting problems are left out: their optimisers search
/// one segment's few parameters.
fn state_within_limit(spec: &Spec) -> Result<(), CampaignError> {
    // Each distinct (D, budget) once, in spec order: the functions,
    // transforms and instances of one D and budget size a state alike.
    let mut sizes: Vec<(usize, u64)> = Vec::new();
    for p in spec.problems.iter().filter(|p| !p.kind.least_squares()) {
        if !sizes.contains(&(p.dim, p.budget)) {
            sizes.push((p.dim, p.budget));
        }
    }
    for cell in &spec.cells {
        let algorithm = match &cell.method {
            Method::Metaheuristic(a) | Method::Hybrid(a) => a,
            Method::Exact => continue,
        };
        for &(dim, budget) in &sizes {
            let bytes = algorithm.state_bytes(dim, budget);
            if bytes > MAX_STATE_BYTES {
                return Err(CampaignError::StateTooLarge {
                    spec: spec.path.clone(),
                    cell: cell.label.clone(),
                    algorithm: algorithm.name().to_owned(),
                    dim,
                    bytes,
                });
            }
        }
    }
    Ok(())
}

/// An exclusive lock on a campaign directory (`.lock`, an advisory `flock`
/// that the operating system releases when the process ends, so a killed
/// or requeued run never leaves a stale lock); held while it lives.
///
/// A lock just released can look held for a moment: a thread of the same
/// process that forks to start a program copies the descriptor into the
/// child until the child's `exec` closes it. So a refused lock is tried
/// again for [`LOCK_PATIENCE`] before it is reported.
pub struct DirLock {
    _file: std::fs::File,
}

/// How long a held campaign lock is tried again before it is reported
/// (see [`DirLock`]).
pub const LOCK_PATIENCE: std::time::Duration = std::time::Duration::from_millis(500);

impl DirLock {
    /// Takes the lock of `dir` (created if missing), or says who has it.
    pub fn take(dir: &Path) -> Result<DirLock, ExperimentError> {
        create_dir(dir)?;
        let path = dir.join(".lock");
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| IoError::new("open", &path, e))?;
        let started = std::time::Instant::now();
        let mut attempt = file.try_lock();
        while matches!(attempt, Err(std::fs::TryLockError::WouldBlock))
            && started.elapsed() < LOCK_PATIENCE
        {
            std::thread::sleep(std::time::Duration::from_millis(10));
            attempt = file.try_lock();
        }
        match attempt {
            Ok(()) => Ok(DirLock { _file: file }),
            Err(std::fs::TryLockError::WouldBlock) => Err(CampaignError::Locked {
                dir: dir.to_owned(),
                lock: path,
            }
            .into()),
            Err(std::fs::TryLockError::Error(e)) => Err(IoError::new("lock", &path, e).into()),
        }
    }
}

/// What a campaign did.
#[derive(Clone, Debug)]
pub struct Summary {
    /// The output directory.
    pub out: PathBuf,
    /// Runs in this campaign (or shard).
    pub total: usize,
    /// Runs found already finished.
    pub reused: usize,
    /// Runs executed now.
    pub executed: usize,
    /// Whether every run is finished and the result files are written.
    pub complete: bool,
    /// The journal rows a resume dropped because they disagree with
    /// themselves or with the spec ([`crate::journal_check`]), each a
    /// message naming the journal, the line and the field; their runs were
    /// redone.
    pub dropped: Vec<String>,
}

/// The seed of run `id`: derived from the master seed, the cell key, the
/// problem's seed key (its key without the spec's `paired` factors) and the
/// run number.
pub fn run_seed(spec: &Spec, id: RunId) -> u64 {
    let entry = &spec.problems[id.problem];
    let cell = &spec.cells[id.cell];
    derive_seed(
        spec.seed,
        &cell.key(),
        &entry.seed_key(&spec.paired),
        id.run,
    )
}

/// Executes one run: derives its seed, minimises, and records the outcome.
pub fn execute(spec: &Spec, id: RunId) -> RunRecord {
    let entry = &spec.problems[id.problem];
    let cell = &spec.cells[id.cell];
    let seed = run_seed(spec, id);
    let start = Instant::now();
    let (outcome, fit) = entry.kind.execute(spec, entry, &cell.method, seed);
    let wall_seconds = start.elapsed().as_secs_f64();
    RunRecord {
        algorithm: cell.label.clone(),
        kind: cell.method.name(),
        params: cell.params.canonical(),
        problem: entry.name(),
        dim: entry.dim,
        budget: entry.budget,
        transform: entry.transform,
        instance: entry.instance,
        run: id.run,
        seed,
        best: outcome.best_value,
        error: outcome.best_value - entry.optimum_value(),
        evaluations: outcome.evaluations,
        evaluations_to_target: outcome.evaluations_to_target,
        success: outcome.evaluations_to_target.is_some(),
        trace: outcome.trace,
        hits: outcome.hits,
        fit,
        wall_seconds,
    }
}

/// The `meta.toml` of a campaign directory.
pub(super) fn meta_toml(spec: &Spec, shard: Option<Shard>, runs: usize) -> String {
    let mut s = String::new();
    s.push_str("# Written by metabezier; see the README for the file formats.\n");
    s.push_str(&format!(
        "tool = \"metabezier\"\nversion = \"{}\"\n",
        env!("CARGO_PKG_VERSION")
    ));
    s.push_str(&format!("experiment = \"{}\"\n", spec.name));
    s.push_str(&format!("master_seed = {}\n", spec.seed));
    s.push_str(&format!("rng = \"{RNG_NAME}\"\n"));
    s.push_str(
        if spec.problems.iter().all(|p| p.key() == format!("{}-{}", p.name(), p.dim)) {
            "seed_derivation = \"seed = splitmix64 folded over (master_seed, fnv1a64(cell key), fnv1a64(problem key), run); cell key = label:kind[params], problem key = problem-dim\"\n"
        } else {
            "seed_derivation = \"seed = splitmix64 folded over (master_seed, fnv1a64(cell key), fnv1a64(problem key), run); cell key = label:kind[params], problem key = problem-dim and |factor=value for each non-default factor not in paired\"\n"
        },
    );
    if !spec.paired.is_empty() {
        let names: Vec<String> = spec
            .paired
            .iter()
            .map(|f| format!("\"{}\"", f.name()))
            .collect();
        s.push_str(&format!("paired = [{}]\n", names.join(", ")));
    }
    s.push_str(&format!(
        "spec_fnv1a64 = \"{:016x}\"\n",
        fnv1a64(&spec.text)
    ));
    s.push_str(&format!("runs = {runs}\n"));
    if let Some(sh) = shard {
        s.push_str(&format!("shard = \"{sh}\"\n"));
    }
    s
}

/// The directory a campaign writes into: `out`, by default
/// `results/<name>`; a shard writes into its own directory beneath it
/// ([`shard_dir`]), so shards never share a file.
pub fn campaign_dir(spec: &Spec, out: Option<&Path>, shard: Option<Shard>) -> PathBuf {
    let parent = out.map_or_else(|| default_out(spec), Path::to_owned);
    match shard {
        Some(s) => shard_dir(&parent, s),
        None => parent,
    }
}

/// The directory of shard `s` under `parent`: `parent/shard-K-of-N`, or
/// `parent` itself when it already is that shard's directory: so named, or
/// started as that shard by a version that wrote shards straight into
/// `--out` (its `meta.toml` says so), which thus still resumes.
pub fn shard_dir(parent: &Path, s: Shard) -> PathBuf {
    let named = parent
        .file_name()
        .is_some_and(|n| n.to_str() == Some(s.dir_name().as_str()));
    if named || recorded_shard(parent) == Some(s.to_string()) {
        parent.to_owned()
    } else {
        parent.join(s.dir_name())
    }
}

/// The shard (`K/N`) that `dir/meta.toml` says the directory holds, if any.
pub(super) fn recorded_shard(dir: &Path) -> Option<String> {
    let meta = read_text_limited(&dir.join("meta.toml"), MAX_TEXT_BYTES, "a meta.toml").ok()?;
    meta.lines()
        .find_map(|l| l.strip_prefix("shard = \""))
        .map(|s| s.trim_end_matches('"').to_owned())
}

/// `results/<name>`, the default output directory of a campaign.
pub(super) fn default_out(spec: &Spec) -> PathBuf {
    Path::new("results").join(&spec.name)
}

/// The position of every run of a spec in its fixed order (problem, cell,
/// run), found from a run's key by arithmetic: it holds one entry per cell
/// and per problem, not per run, so its memory does not grow with `runs`.
#[derive(Clone, Debug)]
pub struct RunIndex {
    /// Cell key → cell number.
    cells: HashMap<String, usize>,
    /// (problem match key, budget) → problem number.
    problems: HashMap<(String, u64), usize>,
    /// The cell keys in order.
    cell_keys: Vec<String>,
    /// The problems' (match key, budget) in order.
    problem_keys: Vec<(String, u64)>,
    /// Runs per (problem, cell).
    runs: u32,
}

impl RunIndex {
    /// The index of `spec`'s runs.
    pub fn of(spec: &Spec) -> Self {
        let cell_keys: Vec<String> = spec.cells.iter().map(|c| c.key()).collect();
        let problem_keys: Vec<(String, u64)> = spec
            .problems
            .iter()
            .map(|p| (p.match_key(), p.budget))
            .collect();
        RunIndex {
            cells: cell_keys.iter().cloned().zip(0..).collect(),
            problems: problem_keys.iter().cloned().zip(0..).collect(),
            cell_keys,
            problem_keys,
            runs: spec.runs,
        }
    }

    /// The position of the run with `key`, if the spec defines it:
    /// `(problem · cells + cell) · runs + run`, as [`Spec::run_ids`].
    pub fn get(&self, key: &RunKey) -> Option<usize> {
        let (cell, problem, budget, run) = key;
        let c = *self.cells.get(cell)?;
        let p = *self.problems.get(&(problem.clone(), *budget))?;
        (*run < self.runs)
            .then(|| (p * self.cell_keys.len() + c) * self.runs as usize + *run as usize)
    }

    /// The number of runs.
    pub fn len(&self) -> usize {
        self.problem_keys.len() * self.cell_keys.len() * self.runs as usize
    }

    /// Whether the spec defines no run.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The key of run `id` (of the spec this index was made from; see
    /// [`Spec::run_id`]).
    pub fn key(&self, id: RunId) -> RunKey {
        let (problem, budget) = &self.problem_keys[id.problem];
        (
            self.cell_keys[id.cell].clone(),
            problem.clone(),
            *budget,
            id.run,
        )
    }
}

/// Writes the three result files of `records` (already in final order).
pub(super) fn write_results(spec: &Spec, out: &Path, records: &[RunRecord]) -> Result<(), IoError> {
    let optimum: HashMap<String, f64> = spec
        .problems
        .iter()
        .map(|p| (p.name(), p.optimum_value()))
        .collect();
    let hits = spec.problems.iter().any(|p| p.kind.has_targets());
    records::write_files(
        spec,
        out,
        records,
        |r| optimum.get(&r.problem).copied().unwrap_or(0.0),
        hits,
    )?;
    if records.iter().any(|r| r.fit.is_some()) {
        write_atomic(&out.join("outlines.csv"), &outlines_csv(spec))?;
    }
    Ok(())
}

/// The data points of every fitted source, `source,x,y` in outline order,
/// so that reports can draw fits over their data without the inputs.
fn outlines_csv(spec: &Spec) -> Vec<u8> {
    let mut seen = std::collections::HashSet::new();
    let rows = spec
        .problems
        .iter()
        .filter_map(|p| match p.kind_as::<FitCase>() {
            Some(c) if seen.insert(c.source_name.clone()) => Some(c),
            _ => None,
        })
        .flat_map(|c| {
            c.source
                .points()
                .into_iter()
                .map(move |q| vec![c.source_name.clone(), fmt_real(q.x), fmt_real(q.y)])
        });
    csv_bytes(&["source", "x", "y"], rows)
}

/// Runs (or resumes) a campaign and writes `runs.csv`, `convergence.csv`,
/// `timing.csv`, a copy of the spec, `meta.toml` and `provenance.toml` (one
/// session appended per invocation that ran something) into the output
/// directory.
pub fn run_campaign(spec: &Spec, opts: &RunOptions) -> Result<Summary, ExperimentError> {
    run_campaign_built(spec, opts, super::provenance::UNKNOWN_COMMIT)
}

/// [`run_campaign`] by a build of git commit `commit`, which
/// `provenance.toml` records (the `metabezier` crate passes the commit it
/// was built from; this crate never sees it, so a commit rebuilds only the
/// binary).
pub fn run_campaign_built(
    spec: &Spec,
    opts: &RunOptions,
    commit: &str,
) -> Result<Summary, ExperimentError> {
    check_limits(spec, opts)?;
    let out = campaign_dir(spec, opts.out.as_deref(), opts.shard);
    let _lock = DirLock::take(&out)?;
    let journal_path = out.join("journal.csv");
    let has_state = journal_path.exists() || out.join("runs.csv").exists();
    if has_state && !opts.resume {
        return Err(CampaignError::AlreadyHoldsRuns { out }.into());
    }

    if opts.resume {
        // Under the lock: no other writer of `out` runs.
        remove_stale_temporaries(&out)?;
    }
    let index = RunIndex::of(spec);
    let (mut done, dropped) = if has_state {
        recover(spec, opts.shard, &out, &index)?
    } else {
        (HashMap::new(), Vec::new())
    };
    // Positions, not run ids or keys: 8 bytes per run of the shard before
    // the first run starts.
    let ids: Vec<usize> = (0..index.len())
        .filter(|&i| opts.shard.is_none_or(|s| s.contains(i)))
        .collect();
    let total = ids.len();
    write_atomic(&out.join("spec.toml"), spec.text.as_bytes())?;
    write_atomic(
        &out.join("meta.toml"),
        meta_toml(spec, opts.shard, total).as_bytes(),
    )?;
    rewrite_journal(&journal_path, &done, &index)?;
    let reused = done.len();

    let mut todo: Vec<usize> = ids
        .iter()
        .copied()
        .filter(|i| !done.contains_key(i))
        .collect();
    if let Some(m) = opts.max_runs {
        todo.truncate(m);
    }
    // Longest runs first, so that no core idles at the end; the results
    // are stored by position, so the order of execution changes nothing.
    todo.sort_by_key(|&i| {
        let p = &spec.problems[spec.run_id(i).problem];
        std::cmp::Reverse(p.budget.saturating_mul(p.dim as u64))
    });
    let threads = opts
        .threads
        .filter(|&t| t > 0)
        .unwrap_or_else(rayon::current_num_threads);
    let mut session = super::provenance::Session::now(commit, threads, 0);
    let new = execute_journalled(spec, &todo, &journal_path, opts)?;
    let executed = new.len();
    // Where and with what build the runs were made, beside (not in) the
    // deterministic meta.toml.
    if executed > 0 || !out.join(super::provenance::PROVENANCE_FILE).exists() {
        session.runs = executed;
        super::provenance::append(&out, &session)?;
    }
    for (&i, rec) in todo.iter().zip(new) {
        done.insert(i, rec);
    }

    let complete = ids.iter().all(|i| done.contains_key(i));
    if complete {
        let ordered: Vec<RunRecord> = ids
            .iter()
            .map(|i| done.remove(i).expect("complete"))
            .collect();
        write_results(spec, &out, &ordered)?;
        std::fs::remove_file(&journal_path)
            .map_err(|e| IoError::new("remove", &journal_path, e))?;
    }
    Ok(Summary {
        out,
        total,
        reused,
        executed,
        complete,
        dropped,
    })
}

/// The finished runs of an interrupted campaign in `out`, by position in
/// the fixed order, after checking that it was started from the same spec
/// and as the same `shard`; with the journal rows dropped as untrustworthy
/// ([`journal_check::trusted_rows`]).
fn recover(
    spec: &Spec,
    shard: Option<Shard>,
    out: &Path,
    index: &RunIndex,
) -> Result<journal_check::Recovered, ExperimentError> {
    let spec_copy = out.join("spec.toml");
    if let Ok(old) = read_text_limited(&spec_copy, MAX_TEXT_BYTES, "a spec") {
        if old != spec.text {
            return Err(CampaignError::SpecChanged {
                spec: spec.path.clone(),
                copy: spec_copy,
            }
            .into());
        }
    }
    check_spec_hash(spec, out)?;
    if out.join("meta.toml").exists() {
        let old_shard = recorded_shard(out);
        let new_shard = shard.map(|s| s.to_string());
        if old_shard != new_shard {
            return Err(CampaignError::ShardChanged {
                out: out.to_owned(),
                started: old_shard,
                asked: new_shard,
            }
            .into());
        }
    }
    // The journal is the truth while it exists: it holds every finished
    // run, and the result files beside it may be partial (a campaign killed,
    // or a disk full, while it wrote them). It is removed only once every
    // result file is written.
    let journal_path = out.join("journal.csv");
    if journal_path.exists() {
        let rows = journal::read_journal_rows(&journal_path)?;
        let expected = |i: usize| {
            let id = spec.run_id(i);
            let optimum = spec.problems[id.problem].optimum_value();
            (run_seed(spec, id), optimum)
        };
        return journal_check::trusted_rows(rows, &journal_path, |r| index.get(&r.key()), expected)
            .map_err(|r| foreign_run(CampaignAction::Resume, out, &r).into());
    }
    let mut done = HashMap::new();
    for r in records::read_results(out)? {
        let i = index
            .get(&r.key())
            .ok_or_else(|| foreign_run(CampaignAction::Resume, out, &r))?;
        done.insert(i, r);
    }
    Ok((done, Vec::new()))
}

/// Refuses to resume a campaign whose `meta.toml` records the hash of
/// another spec (the check that still holds when `spec.toml` is gone).
fn check_spec_hash(spec: &Spec, out: &Path) -> Result<(), CampaignError> {
    let meta = out.join("meta.toml");
    let Ok(text) = read_text_limited(&meta, MAX_TEXT_BYTES, "a meta.toml") else {
        return Ok(());
    };
    let recorded = text
        .lines()
        .find_map(|l| l.strip_prefix("spec_fnv1a64 = \""))
        .map(|s| s.trim_end_matches('"').to_owned());
    let found = format!("{:016x}", fnv1a64(&spec.text));
    match recorded {
        Some(recorded) if recorded != found => Err(CampaignError::SpecHashChanged {
            meta,
            spec: spec.path.clone(),
            recorded,
            found,
        }),
        _ => Ok(()),
    }
}

/// Rewrites the journal with the runs already finished, in the fixed order
/// (which drops a torn last line), for new runs to be appended to.
fn rewrite_journal(
    path: &Path,
    done: &HashMap<usize, RunRecord>,
    index: &RunIndex,
) -> Result<(), IoError> {
    let mut bytes = Vec::new();
    let mut reused: Vec<&RunRecord> = done.values().collect();
    reused.sort_by_key(|r| index.get(&r.key()));
    for r in &reused {
        bytes.extend(journal::journal_line(r));
    }
    write_atomic(path, &bytes)
}

/// Executes the runs at positions `todo` in parallel, one run per task, appending each finished
/// run to the journal at `journal_path`; the records come back in `todo`
/// order. The first journal line that cannot be written stops the campaign
/// (no new run starts; the journal keeps the finished ones).
fn execute_journalled(
    spec: &Spec,
    todo: &[usize],
    journal_path: &Path,
    opts: &RunOptions,
) -> Result<Vec<RunRecord>, ExperimentError> {
    let journal = std::fs::OpenOptions::new()
        .append(true)
        .open(journal_path)
        .map_err(|e| IoError::new("open", journal_path, e))?;
    let journal = Mutex::new(journal);
    let bar = progress_bar(spec, todo.len(), opts.progress);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(CampaignError::Threads)?;
    // An indexed collect writes each record straight into its slot of one
    // vector (`None` = not run, once a journal line failed): no per-task
    // vectors, so the records' memory is what `estimated_bytes` counts.
    let stop = std::sync::atomic::AtomicBool::new(false);
    let failed: Mutex<Option<ExperimentError>> = Mutex::new(None);
    let interrupted = || {
        CampaignError::Interrupted {
            journal: journal_path.to_owned(),
        }
        .into()
    };
    let fail = |e: ExperimentError| {
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        let mut first = failed.lock().unwrap_or_else(|p| p.into_inner());
        first.get_or_insert(e);
    };
    let new: Vec<Option<RunRecord>> = pool.install(|| {
        todo.par_iter()
            .with_max_len(1)
            .map(|&i| {
                if stop.load(std::sync::atomic::Ordering::Relaxed) {
                    return None;
                }
                if interrupt::requested() {
                    fail(interrupted());
                    return None;
                }
                // A panic in an optimiser's or a problem's code (a library
                // user's own, say) stops the campaign with the run named;
                // the finished runs stay in the journal.
                let id = spec.run_id(i);
                let run =
                    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| execute(spec, id)));
                // A run the host interrupted ended early (or unwound from a
                // Python objective): it is not a result, and is redone on
                // resume.
                if interrupt::requested() {
                    fail(interrupted());
                    return None;
                }
                let mut rec = match run {
                    Ok(rec) => rec,
                    Err(payload) => {
                        let message = payload
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| payload.downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "(no message)".into());
                        fail(
                            CampaignError::RunPanicked {
                                run: id.run,
                                cell: spec.cells[id.cell].label.clone(),
                                problem: spec.problems[id.problem].key(),
                                message,
                                journal: journal_path.to_owned(),
                            }
                            .into(),
                        );
                        return None;
                    }
                };
                // Held until the end: no spare capacity.
                rec.trace.shrink_to_fit();
                rec.hits.shrink_to_fit();
                let line = journal::journal_line(&rec);
                let mut j = journal.lock().unwrap_or_else(|p| p.into_inner());
                if let Err(e) = j.write_all(&line).and_then(|_| j.flush()) {
                    drop(j);
                    fail(IoError::new("append to", journal_path, e).into());
                    return None;
                }
                drop(j);
                bar.inc(1);
                Some(rec)
            })
            .collect()
    });
    bar.finish_and_clear();
    if let Some(e) = failed.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    // Every slot is filled when no line failed; the vector is reused in place.
    Ok(new.into_iter().map(|r| r.expect("every run ran")).collect())
}

/// A progress bar over `runs` runs, drawn only if asked and stderr is a
/// terminal.
fn progress_bar(spec: &Spec, runs: usize, progress: bool) -> indicatif::ProgressBar {
    if !(progress && std::io::stderr().is_terminal()) {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(runs as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix} [{elapsed_precise}] {wide_bar} {pos}/{len} runs (eta {eta})",
        )
        .expect("valid template"),
    );
    bar.set_prefix(spec.name.clone());
    bar
}

/// The error for run `r` of `dir`, which the spec does not define.
pub(super) fn foreign_run(action: CampaignAction, dir: &Path, r: &RunRecord) -> CampaignError {
    CampaignError::ForeignRun {
        action,
        dir: dir.to_owned(),
        run: r.run,
        cell: r.cell_key(),
        problem: r.match_key(),
    }
}
