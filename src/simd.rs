//! The vector instruction sets the hot loops run with, detected at run
//! time. Every wide path computes the same numbers as the portable one (no
//! reassociation, no fused multiply-add), so results do not depend on the
//! machine; only the speed does.

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

/// The widest [`Simd`] level this CPU runs (detected once, then cached by
/// the standard library).
#[inline]
pub fn simd() -> Simd {
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

/// Whether this CPU runs the AVX2 paths (the generator's steps and the
/// harmony improvisation); they give the same numbers as the portable paths.
#[inline]
pub fn has_avx2() -> bool {
    simd() >= Simd::Avx2
}

/// Runs `body` compiled for this CPU's [`simd`] level, which it is given:
/// `body` (a closure marked `#[inline(always)]`, with `#[inline(always)]`
/// callees) is inlined into a function with that level's target features,
/// so its loops are vectorised for the CPU and its intrinsic calls are
/// inlined without a call per block.
#[inline(always)]
pub fn dispatch<T>(body: impl FnOnce(Simd) -> T) -> T {
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
        match simd() {
            // SAFETY: the CPU has the features of the level `simd` reports.
            Simd::Avx512 => return unsafe { avx512(body) },
            // SAFETY: as above.
            Simd::Avx2 => return unsafe { avx2(body) },
            Simd::Portable => {}
        }
    }
    body(Simd::Portable)
}
