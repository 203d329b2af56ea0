//! The memory guard's model, held to measurement: a global allocator that
//! counts the heap as glibc's malloc takes it (each block's chunk, by
//! `malloc_usable_size`) measures the records the runner keeps and the peak
//! of whole campaigns, and the tests require the model of
//! `runner::estimated_bytes` (its constants and `records::record_heap`) to
//! match: they fail when records grow and the guard is not updated.
//! `make memory` (ci/measure-memory.sh) holds the same estimate to the peak
//! resident set size of real campaigns.
#![cfg(all(target_os = "linux", target_env = "gnu"))]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;

use metabezier::experiment::records::{
    heap_block, read_results, record_heap, RecordShape, RunRecord, SEGMENT_ROW_HEAP,
};
use metabezier::experiment::runner::{self, check_limits, estimated_bytes};
use metabezier::experiment::spec::Benchmark;
use metabezier::experiment::{RunOptions, Shard, Spec};

extern "C" {
    fn malloc_usable_size(ptr: *mut u8) -> usize;
}

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

/// Counts every block as the chunk glibc takes for it: its usable size
/// and its 8-byte header.
struct Chunks;

fn chunk(ptr: *mut u8) -> usize {
    unsafe { malloc_usable_size(ptr) + 8 }
}

fn gained(ptr: *mut u8) {
    if !ptr.is_null() {
        let n = chunk(ptr);
        let live = LIVE.fetch_add(n, Ordering::Relaxed) + n;
        PEAK.fetch_max(live, Ordering::Relaxed);
    }
}

unsafe impl GlobalAlloc for Chunks {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        gained(p);
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        gained(p);
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(chunk(ptr), Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, size: usize) -> *mut u8 {
        let old = chunk(ptr);
        let p = unsafe { System.realloc(ptr, layout, size) };
        if !p.is_null() {
            LIVE.fetch_sub(old, Ordering::Relaxed);
            gained(p);
        }
        p
    }
}

#[global_allocator]
static ALLOC: Chunks = Chunks;

/// One measurement at a time: the counters are global.
static SERIAL: Mutex<()> = Mutex::new(());

/// The live heap now.
fn live() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// `f`'s result and the peak of the live heap above its start.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let start = live();
    PEAK.store(start, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed) - start)
}

const ROOT: &str = env!("CARGO_MANIFEST_DIR");

/// Benchmark runs of quick.toml's problems and optimisers.
fn benchmark_spec(runs: u32, budget: u64) -> String {
    format!(
        r#"
[experiment]
name = "memory_benchmark"
seed = 20261122
runs = {runs}
budget = {budget}
threshold = 1e-8

[[problem]]
function = ["sphere", "rastrigin"]
dim = 10

[[problem]]
function = "six_hump_camel"

[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "ghs"
label = "GHS"

[[algorithm]]
name = "ga"
label = "GA"

[[algorithm]]
name = "pso"
label = "PSO"

[[algorithm]]
name = "mhs"
label = "MHS"
"#
    )
}

/// Fitting runs of ch5_outlines's coin (8 segments) and horse (30), the
/// four fitting functions, C1 and G1, at `budget` evaluations a segment.
fn fitting_spec(runs: u32, budget: u64, horse: bool) -> String {
    let mut s = format!(
        r#"
[experiment]
name = "memory_fitting"
seed = 2012
runs = {runs}
budget = {budget}
threshold = 0

[[fit]]
input = "{ROOT}/data/outlines/coin.png"
function = ["quadratic", "cubic", "rational-quadratic", "rational-cubic"]
continuity = ["c1", "g1"]
closing = "smooth"
segments = 8
"#
    );
    if horse {
        s.push_str(&format!(
            r#"
[[fit]]
input = "{ROOT}/data/outlines/horse.png"
function = ["quadratic", "cubic", "rational-quadratic", "rational-cubic"]
continuity = ["c1", "g1"]
closing = "smooth"
segments = 30
"#
        ));
    }
    s.push_str(
        r#"
[[algorithm]]
name = "hs"
label = "HS"

[[algorithm]]
name = "pso"
label = "PSO"

[[algorithm]]
name = "lm"
label = "LM"
"#,
    );
    s
}

fn parse(dir: &Path, text: &str) -> Spec {
    let path = dir.join("spec.toml");
    std::fs::write(&path, text).unwrap();
    Spec::load(&path).unwrap()
}

/// The shape of a record, as `record_heap` reads it.
fn shape(r: &RunRecord) -> RecordShape {
    RecordShape {
        strings: [
            r.algorithm.len(),
            r.kind.len(),
            r.params.len(),
            r.problem.len(),
        ],
        trace_points: r.trace.len(),
        hits: r.hits.len(),
        segments: r.fit.as_ref().map_or(0, |f| f.segments.len()),
    }
}

/// The chunk of a vector's or string's block, if it has one.
fn block<T>(ptr: *const T, capacity: usize) -> usize {
    if capacity == 0 || std::mem::size_of::<T>() == 0 {
        0
    } else {
        chunk(ptr as *mut u8)
    }
}

/// The heap `r` holds, block by block, as glibc took it.
fn heap_of(r: &RunRecord) -> usize {
    let string = |s: &String| block(s.as_ptr(), s.capacity());
    let mut heap = string(&r.algorithm) + string(&r.kind) + string(&r.params) + string(&r.problem);
    heap += block(r.trace.as_ptr(), r.trace.capacity());
    heap += block(r.hits.as_ptr(), r.hits.capacity());
    if let Some(f) = &r.fit {
        heap += block(f.segments.as_ptr(), f.segments.capacity());
        for row in &f.segments {
            heap += block(row.as_ptr(), row.capacity()) + row.iter().map(string).sum::<usize>();
        }
    }
    heap
}

/// Every run of `spec` executed and kept as the runner keeps it (trace and
/// hits at their exact length), with the heap it holds.
fn kept(spec: &Spec) -> Vec<(RunRecord, usize)> {
    (0..spec.run_count() as usize)
        .map(|i| {
            let mut r = runner::execute(spec, spec.run_id(i));
            r.trace.shrink_to_fit();
            r.hits.shrink_to_fit();
            let heap = heap_of(&r);
            (r, heap)
        })
        .collect()
}

#[test]
fn record_heap_is_the_heap_of_the_records_the_runner_keeps() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().unwrap();
    let spec = parse(tmp.path(), &benchmark_spec(2, 3000));
    let runs = kept(&spec);
    let measured: usize = runs.iter().map(|(_, h)| h).sum();
    let modelled: u64 = runs.iter().map(|(r, _)| record_heap(&shape(r))).sum();
    assert!(runs.iter().any(|(r, _)| !r.hits.is_empty()));
    let ratio = modelled as f64 / measured as f64;
    assert!(
        (0.97..=1.03).contains(&ratio),
        "benchmark records: modelled {modelled} B, measured {measured} B"
    );
}

#[test]
fn segment_rows_take_the_heap_the_guard_counts() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().unwrap();
    let spec = parse(tmp.path(), &fitting_spec(1, 20, true));
    let runs = kept(&spec);
    let mut rows = 0u64;
    let mut row_heap = 0f64;
    for (r, heap) in &runs {
        let s = shape(r);
        let without_rows =
            record_heap(&RecordShape { segments: 0, ..s }) + heap_block(24 * s.segments as u64);
        rows += s.segments as u64;
        row_heap += *heap as f64 - without_rows as f64;
    }
    let per_row = row_heap / rows as f64;
    assert!(
        (per_row - SEGMENT_ROW_HEAP as f64).abs() <= 0.05 * per_row,
        "a segment row takes {per_row:.0} B on the heap; records::SEGMENT_ROW_HEAP says {SEGMENT_ROW_HEAP}"
    );
}

/// The estimate of `spec` with the hits its runs in `dir` reached in place
/// of the bound it counts (every target), and the number of those runs.
fn with_reached_hits(spec: &Spec, dir: &Path) -> u128 {
    let bound: usize = metabezier::experiment::records::default_targets().len();
    let excess: u64 = read_results(dir)
        .unwrap()
        .iter()
        .filter(|r| r.fit.is_none())
        .map(|r| heap_block(16 * bound as u64) - heap_block(16 * r.hits.len() as u64))
        .sum();
    estimated_bytes(spec) - u128::from(excess)
}

/// The peak heap of a campaign of `text` and its estimate, each less those
/// of the campaign with one run per cell (the program, the spec and the
/// runs in flight), and the estimate with the hits reached.
fn campaign_peak(text: impl Fn(u32) -> String, runs: u32) -> (f64, f64, f64) {
    let one = |runs: u32| {
        let tmp = tempfile::tempdir().unwrap();
        let spec = parse(tmp.path(), &text(runs));
        let out = tmp.path().join("out");
        let opts = RunOptions {
            out: Some(out.clone()),
            threads: Some(2),
            ..RunOptions::default()
        };
        let (s, peak) = peak_of(|| runner::run_campaign(&spec, &opts).unwrap());
        assert!(s.complete);
        (
            peak as f64,
            estimated_bytes(&spec) as f64,
            with_reached_hits(&spec, &out) as f64,
        )
    };
    let (p1, e1, h1) = one(1);
    let (p, e, h) = one(runs);
    (p - p1, e - e1, h - h1)
}

fn check_peak(name: &str, text: impl Fn(u32) -> String, runs: u32) {
    let (measured, estimate, reached) = campaign_peak(text, runs);
    let mib = |b: f64| b / f64::from(1u32 << 20);
    eprintln!(
        "{name}: measured {:.2} MiB, estimate {:.2} MiB, with the hits reached {:.2} MiB",
        mib(measured),
        mib(estimate),
        mib(reached)
    );
    assert!(
        (0.9..=1.1).contains(&(reached / measured)),
        "{name}: the model with the hits reached gives {:.2} MiB for a measured peak of {:.2} MiB",
        mib(reached),
        mib(measured)
    );
    assert!(
        estimate >= 0.95 * measured,
        "{name}: the estimate {:.2} MiB is below the measured peak {:.2} MiB",
        mib(estimate),
        mib(measured)
    );
}

#[test]
fn the_estimate_holds_the_peak_of_benchmark_campaigns() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    // Long runs that reach most targets, and short ones that reach few.
    check_peak("benchmark, budget 20000", |r| benchmark_spec(r, 20000), 40);
    check_peak("benchmark, budget 10", |r| benchmark_spec(r, 10), 800);
}

#[test]
fn the_estimate_holds_the_peak_of_a_fitting_campaign() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    check_peak("fitting", |r| fitting_spec(r, 20, true), 6);
}

/// quick.toml's problems and optimisers, 1.62 million runs: the base's
/// guard counted 2,635 bytes a run (3.98 GiB, admitted) where the records
/// take about 2,900 and the whole text of convergence.csv, 6.7 kB a run,
/// was held besides (about 18 GiB in all).
#[test]
fn a_campaign_whose_records_exceed_the_limit_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let spec = parse(tmp.path(), &benchmark_spec(108_000, 20000));
    let err = check_limits(&spec, &RunOptions::default())
        .unwrap_err()
        .to_string();
    // Only the memory is over its limit, and only it is named.
    assert!(
        err.contains("an estimated 4.2 GiB of results in memory exceed the limit of 4 GiB")
            && !err.contains("runs exceed"),
        "{err}"
    );
    // As 2 shards, each is held to its own runs and admitted.
    for k in 1..=2 {
        let shard = RunOptions {
            shard: Some(Shard { k, n: 2 }),
            ..RunOptions::default()
        };
        check_limits(&spec, &shard).unwrap();
    }
    assert!(spec.problems[0].kind_as::<Benchmark>().is_some());
}

#[test]
fn a_resume_reads_its_journal_a_line_at_a_time() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let tmp = tempfile::tempdir().unwrap();
    let spec = parse(tmp.path(), &benchmark_spec(200, 2000));
    let out = tmp.path().join("out");
    let opts = RunOptions {
        out: Some(out.clone()),
        threads: Some(2),
        max_runs: Some(2999),
        ..RunOptions::default()
    };
    assert!(!runner::run_campaign(&spec, &opts).unwrap().complete);
    let journal = out.join("journal.csv");
    let size = std::fs::metadata(&journal).unwrap().len() as usize;
    let start = live();
    let (records, peak) =
        peak_of(|| metabezier::experiment::journal::read_journal(&journal).unwrap());
    let kept = live() - start;
    assert_eq!(records.len(), 2999);
    // Beyond the records it returns, a line and the reader's buffers: the
    // journal's text is never held whole.
    assert!(
        peak - kept < size / 20,
        "reading a {size}-byte journal took {} bytes beyond its {kept} bytes of records",
        peak - kept
    );
}
