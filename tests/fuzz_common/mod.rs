//! A seeded mutational fuzz loop for the file readers, shared by the
//! `tests/fuzz_*.rs` binaries.
//!
//! Each binary declares the counting allocator as its global allocator:
//!
//! ```ignore
//! mod fuzz_common;
//! #[global_allocator]
//! static ALLOC: fuzz_common::CountingAlloc = fuzz_common::CountingAlloc;
//! ```
//!
//! and calls [`fuzz`] with a reader, a few valid inputs to mutate and a
//! limit of bytes. Every mutant is read under `catch_unwind` (a panic fails
//! the test and names the mutant), a watchdog aborts the binary when one
//! mutant takes longer than [`HANG_SECONDS`], and while a mutant is read the
//! allocator refuses (prints, then aborts) any request that would take the
//! live heap more than the limit above what it held before, so a length a
//! file declares but cannot back fails here instead of taking the machine's
//! memory.
//!
//! `METABEZIER_FUZZ_MUTANTS` sets the mutants per reader (default
//! [`DEFAULT_MUTANTS`]; `make fuzz` runs many more) and
//! `METABEZIER_FUZZ_SEED` the first seed; a failure prints both, and
//! `METABEZIER_FUZZ_KEEP=dir` writes the failing mutant there.
#![allow(dead_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// Mutants per reader in `make test`.
pub const DEFAULT_MUTANTS: usize = 2000;
/// A mutant read for longer than this aborts the binary as a hang.
pub const HANG_SECONDS: u64 = 20;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
/// The live heap a reader may reach while armed (usize::MAX = unarmed).
static CEILING: AtomicUsize = AtomicUsize::new(usize::MAX);
static REFUSED: AtomicBool = AtomicBool::new(false);

/// A global allocator that counts the live heap and its peak, and refuses
/// requests above the armed ceiling.
pub struct CountingAlloc;

unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !admit(layout.size()) {
            return std::ptr::null_mut();
        }
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !admit(layout.size()) {
            return std::ptr::null_mut();
        }
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if new_size > layout.size() {
            if !admit(new_size - layout.size()) {
                return std::ptr::null_mut();
            }
        } else {
            LIVE.fetch_sub(layout.size() - new_size, Ordering::Relaxed);
        }
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            // The old block is still live; undo the change.
            if new_size > layout.size() {
                LIVE.fetch_sub(new_size - layout.size(), Ordering::Relaxed);
            } else {
                LIVE.fetch_add(layout.size() - new_size, Ordering::Relaxed);
            }
        }
        p
    }
}

/// Counts `size` more live bytes, unless that passes the ceiling.
fn admit(size: usize) -> bool {
    let live = LIVE.fetch_add(size, Ordering::Relaxed) + size;
    if live > CEILING.load(Ordering::Relaxed) {
        LIVE.fetch_sub(size, Ordering::Relaxed);
        if !REFUSED.swap(true, Ordering::Relaxed) {
            // No allocation here: write a fixed message straight to stderr.
            let msg = b"\nfuzz: an allocation passed the reader's memory limit (the mutant is named below)\n";
            unsafe { libc_write(2, msg.as_ptr(), msg.len()) };
            report_current();
        }
        return false;
    }
    PEAK.fetch_max(live, Ordering::Relaxed);
    true
}

extern "C" {
    #[link_name = "write"]
    fn libc_write(fd: i32, buf: *const u8, count: usize) -> isize;
}

/// The reader, seed and mutant being read, for the refusal and hang
/// messages (fixed-size, written without allocating).
static CURRENT: Mutex<[u8; 160]> = Mutex::new([0; 160]);
static CURRENT_LEN: AtomicUsize = AtomicUsize::new(0);

fn set_current(text: &str) {
    let mut buf = CURRENT.lock().unwrap_or_else(|e| e.into_inner());
    let n = text.len().min(buf.len());
    buf[..n].copy_from_slice(&text.as_bytes()[..n]);
    CURRENT_LEN.store(n, Ordering::Relaxed);
}

fn report_current() {
    if let Ok(buf) = CURRENT.try_lock() {
        let n = CURRENT_LEN.load(Ordering::Relaxed);
        unsafe {
            libc_write(2, buf.as_ptr(), n);
            libc_write(2, b"\n".as_ptr(), 1);
        }
    }
}

/// The live heap now, in bytes.
pub fn live_bytes() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// Runs `f` with the live heap capped at what it holds now plus `limit`
/// bytes and returns its result and the peak it reached above that start.
pub fn with_limit<T>(limit: usize, f: impl FnOnce() -> T) -> (T, usize) {
    let start = LIVE.load(Ordering::Relaxed);
    PEAK.store(start, Ordering::Relaxed);
    CEILING.store(start.saturating_add(limit), Ordering::Relaxed);
    let out = f();
    CEILING.store(usize::MAX, Ordering::Relaxed);
    (out, PEAK.load(Ordering::Relaxed).saturating_sub(start))
}

/// A splitmix64 stream: the mutator's only source of choices.
pub struct Stream(u64);

impl Stream {
    /// A stream from `seed`.
    pub fn new(seed: u64) -> Self {
        Stream(seed)
    }

    /// The next 64 bits.
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Byte values and little- and big-endian words that readers treat
/// specially: lengths of zero, one, all ones, just below a power of two.
const INTERESTING: [u32; 12] = [
    0,
    1,
    0x7F,
    0x80,
    0xFF,
    0x7FFF,
    0xFFFF,
    0x1_0000,
    0x7FFF_FFFF,
    0xFFFF_FFF0,
    0xFFFF_FFFF,
    0x8000_0000,
];

/// A mutant of `seed_input` (or a splice of two inputs): one to four edits
/// among bit flips, random and interesting bytes or words, deletions,
/// duplications and insertions of chunks, and truncation.
pub fn mutate(inputs: &[Vec<u8>], s: &mut Stream) -> Vec<u8> {
    let mut m = inputs[s.below(inputs.len())].clone();
    let edits = 1 + s.below(4);
    for _ in 0..edits {
        let len = m.len();
        match s.below(10) {
            0 if len > 0 => {
                let i = s.below(len);
                m[i] ^= 1 << s.below(8);
            }
            1 if len > 0 => {
                let i = s.below(len);
                m[i] = s.next() as u8;
            }
            2 if len >= 4 => {
                let i = s.below(len - 3);
                let v = INTERESTING[s.below(INTERESTING.len())];
                let bytes = if s.below(2) == 0 {
                    v.to_le_bytes()
                } else {
                    v.to_be_bytes()
                };
                m[i..i + 4].copy_from_slice(&bytes);
            }
            3 if len > 0 => {
                let i = s.below(len);
                let n = 1 + s.below((len - i).min(64));
                m.drain(i..i + n);
            }
            4 if len > 0 => {
                let i = s.below(len);
                let n = 1 + s.below((len - i).min(256));
                let chunk = m[i..i + n].to_vec();
                let at = s.below(len + 1);
                for _ in 0..1 + s.below(3) {
                    m.splice(at..at, chunk.iter().copied());
                }
            }
            5 => {
                let at = s.below(len + 1);
                let n = 1 + s.below(16);
                let bytes: Vec<u8> = (0..n).map(|_| s.next() as u8).collect();
                m.splice(at..at, bytes);
            }
            6 if len > 0 => {
                m.truncate(s.below(len));
            }
            7 if len > 0 => {
                // A byte that means something in text formats.
                const TEXT: &[u8] = b"\"'=[](){}<>,;:.-+eE0123456789 \n\r\t#\\/";
                let i = s.below(len);
                m[i] = TEXT[s.below(TEXT.len())];
            }
            8 if inputs.len() > 1 && len > 0 => {
                let other = &inputs[s.below(inputs.len())];
                if !other.is_empty() {
                    let i = s.below(len);
                    let j = s.below(other.len());
                    m.truncate(i);
                    m.extend_from_slice(&other[j..]);
                }
            }
            _ if len > 0 => {
                let i = s.below(len);
                m[i] = m[i].wrapping_add(1 + s.below(4) as u8);
            }
            _ => m.push(s.next() as u8),
        }
    }
    m
}

/// The mutants per reader: `METABEZIER_FUZZ_MUTANTS` or the default.
pub fn mutant_count() -> usize {
    std::env::var("METABEZIER_FUZZ_MUTANTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(DEFAULT_MUTANTS)
}

fn first_seed() -> u64 {
    std::env::var("METABEZIER_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0x6d65_7461_6265_7a69)
}

/// One fuzz binary reads one mutant at a time (the allocator's ceiling is
/// global).
static SERIAL: Mutex<()> = Mutex::new(());

/// The fuzz tests share one binary and so one allocator: a test that
/// prepares its inputs while another's ceiling is armed would be refused.
static ONE_TEST: Mutex<()> = Mutex::new(());

/// Runs the tests of the binary one at a time: every fuzz test holds this
/// guard for its whole body.
pub fn one_test_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_TEST.lock().unwrap_or_else(|e| e.into_inner())
}

/// What one run of [`fuzz`] saw.
#[derive(Debug, Default)]
pub struct Tally {
    /// Mutants read.
    pub mutants: usize,
    /// Mutants the reader accepted.
    pub accepted: usize,
    /// The largest live-heap rise of one mutant, in bytes.
    pub peak: usize,
}

/// Reads `mutant_count()` mutants of `inputs` with `read` (which returns
/// whether the reader accepted it; any error must come back as `false`,
/// never a panic), each under a ceiling of `limit` bytes of heap above the
/// start. Panics, naming the seed and mutant, when `read` panics.
pub fn fuzz(
    name: &str,
    inputs: &[Vec<u8>],
    limit: usize,
    mut read: impl FnMut(&[u8]) -> bool,
) -> Tally {
    assert!(!inputs.is_empty(), "{name}: no inputs to mutate");
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    lift_ceiling_on_panic();
    let count = mutant_count();
    let seed = first_seed() ^ fnv(name.as_bytes());
    let mut stream = Stream::new(seed);
    let started = std::sync::Arc::new(AtomicU64::new(0));
    let done = std::sync::Arc::new(AtomicBool::new(false));
    let epoch = Instant::now();
    let watchdog = {
        let (started, done) = (started.clone(), done.clone());
        std::thread::spawn(move || {
            while !done.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(200));
                let s = started.load(Ordering::Relaxed);
                if s != 0 && epoch.elapsed().as_millis() as u64 - s > HANG_SECONDS * 1000 {
                    let msg = b"\nfuzz: a mutant hung (named below)\n";
                    unsafe { libc_write(2, msg.as_ptr(), msg.len()) };
                    report_current();
                    std::process::abort();
                }
            }
        })
    };
    let mut tally = Tally::default();
    for i in 0..count {
        let mutant = mutate(inputs, &mut stream);
        set_current(&format!(
            "fuzz {name}: mutant {i} of METABEZIER_FUZZ_SEED={} ({} bytes)",
            first_seed(),
            mutant.len()
        ));
        if let Ok(dir) = std::env::var("METABEZIER_FUZZ_KEEP") {
            let _ = std::fs::create_dir_all(&dir);
            let _ = std::fs::write(
                std::path::Path::new(&dir).join(format!("{name}-current")),
                &mutant,
            );
        }
        started.store(
            (epoch.elapsed().as_millis() as u64).max(1),
            Ordering::Relaxed,
        );
        let (outcome, peak) =
            with_limit(limit, || catch_unwind(AssertUnwindSafe(|| read(&mutant))));
        started.store(0, Ordering::Relaxed);
        match outcome {
            Ok(accepted) => tally.accepted += usize::from(accepted),
            Err(_) => {
                done.store(true, Ordering::Relaxed);
                panic!(
                    "fuzz {name}: mutant {i} of METABEZIER_FUZZ_SEED={} panicked (rerun with METABEZIER_FUZZ_KEEP=dir to keep it)",
                    first_seed()
                );
            }
        }
        tally.mutants += 1;
        tally.peak = tally.peak.max(peak);
    }
    done.store(true, Ordering::Relaxed);
    let _ = watchdog.join();
    tally
}

/// Installs (once) a panic hook that lifts the ceiling before the default
/// hook runs: a reader's panic is reported with its message and backtrace
/// (which allocate), not as an allocation failure.
fn lift_ceiling_on_panic() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            CEILING.store(usize::MAX, Ordering::Relaxed);
            previous(info);
        }));
    });
}

/// FNV-1a of `bytes`: a reader's name becomes its own seed offset.
fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x100_0000_01b3)
    })
}
