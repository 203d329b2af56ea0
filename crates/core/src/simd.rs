//! The vector instruction sets the hot loops run with, detected at run
//! time. Every wide path computes the same numbers as the portable one (no
//! reassociation, no fused multiply-add), so results do not depend on the
//! machine; only the speed does.

use std::cell::Cell;
use std::sync::atomic::{AtomicU8, Ordering};

/// The vector instruction set a wide path runs with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Simd {
    /// Plain Rust, on every machine.
    Portable,
    /// x86-64 with AVX2.
    Avx2,
    /// x86-64 with AVX2, AVX-512F, AVX-512VL and AVX-512DQ.
    Avx512,
}

thread_local! {
    /// The cap set by [`with_level`] on this thread, if any.
    static CAP: Cell<Option<Simd>> = const { Cell::new(None) };
}

/// The widest [`Simd`] level this CPU runs (detected once, then cached),
/// lowered to the cap of [`with_level`] while one is
/// set on this thread.
#[inline]
pub fn simd() -> Simd {
    let cpu = detected();
    match CAP.with(Cell::get) {
        Some(cap) => cpu.min(cap),
        None => cpu,
    }
}

/// The CPU's widest level, detected on first use and then read with one
/// relaxed load (0 means not yet detected).
#[inline]
fn detected() -> Simd {
    static LEVEL: AtomicU8 = AtomicU8::new(0);
    match LEVEL.load(Ordering::Relaxed) {
        1 => Simd::Portable,
        2 => Simd::Avx2,
        3 => Simd::Avx512,
        _ => {
            let level = detect();
            LEVEL.store(level as u8 + 1, Ordering::Relaxed);
            level
        }
    }
}

/// Asks the CPU which level it runs.
#[cold]
fn detect() -> Simd {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        if has!("avx2") && has!("avx512f") && has!("avx512vl") && has!("avx512dq") {
            return Simd::Avx512;
        }
        if has!("avx2") {
            return Simd::Avx2;
        }
    }
    Simd::Portable
}

/// Runs `f` on this thread with [`simd`] capped at `cap` (the CPU's own
/// level if that is lower), then restores the previous cap: how the tests
/// run one computation on every level and compare the results bit for bit.
pub fn with_level<T>(cap: Simd, f: impl FnOnce() -> T) -> T {
    struct Restore(Option<Simd>);
    impl Drop for Restore {
        fn drop(&mut self) {
            CAP.with(|c| c.set(self.0));
        }
    }
    let _restore = Restore(CAP.with(|c| c.replace(Some(cap))));
    f()
}

/// Runs `body` compiled for this CPU's [`simd`] level, which it is given:
/// `body` (a closure marked `#[inline(always)]`, with `#[inline(always)]`
/// callees) is inlined into a function with that level's target features,
/// so its loops are vectorised for the CPU and its intrinsic calls are
/// inlined without a call per block.
#[inline(always)]
pub fn dispatch<T>(body: impl FnOnce(Simd) -> T) -> T {
    dispatch_at(simd(), body)
}

/// [`dispatch`] at `level`, lowered to the CPU's own level if that is lower
/// (so it is always safe): for code that keeps the level it was made with,
/// such as a generator.
#[inline(always)]
pub fn dispatch_at<T>(level: Simd, body: impl FnOnce(Simd) -> T) -> T {
    #[cfg(target_arch = "x86_64")]
    {
        #[target_feature(enable = "avx2,avx512f,avx512vl,avx512dq")]
        fn avx512<T>(body: impl FnOnce(Simd) -> T) -> T {
            body(Simd::Avx512)
        }
        #[target_feature(enable = "avx2")]
        fn avx2<T>(body: impl FnOnce(Simd) -> T) -> T {
            body(Simd::Avx2)
        }
        match level.min(detected()) {
            // SAFETY: the CPU has the features of every level up to
            // `detected()`.
            Simd::Avx512 => return unsafe { avx512(body) },
            // SAFETY: as above.
            Simd::Avx2 => return unsafe { avx2(body) },
            Simd::Portable => {}
        }
    }
    let _ = level;
    body(Simd::Portable)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cap_lowers_the_level_and_is_restored() {
        let cpu = simd();
        assert_eq!(with_level(Simd::Portable, simd), Simd::Portable);
        assert_eq!(with_level(Simd::Avx512, simd), cpu, "a cap never raises");
        let nested = with_level(Simd::Avx2, || {
            (simd(), with_level(Simd::Portable, simd), simd())
        });
        assert_eq!(
            nested,
            (cpu.min(Simd::Avx2), Simd::Portable, cpu.min(Simd::Avx2))
        );
        assert_eq!(simd(), cpu);
        assert_eq!(dispatch(|level| level), cpu);
        assert_eq!(
            with_level(Simd::Portable, || dispatch(|level| level)),
            Simd::Portable
        );
    }
}
