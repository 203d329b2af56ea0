//! Random variates drawn bit-exactly from any `RngCore`, and per-run seeds.
//!
//! The optimisers draw every random number through [`Draw`] and [`Words`],
//! whose methods are defined here from raw 64-bit outputs rather than by
//! `rand`'s distribution code. A run's results therefore depend only on the
//! generator and on this file, not on the sampling algorithms of a
//! particular `rand` release.
//!
//! A run's generator is [`LaneRng`]: Xoshiro256++ (Blackman & Vigna 2021,
//! "Scrambled linear pseudorandom number generators", ACM TOMS 47(4)) in
//! [`LANES`] lanes that are 2¹²⁸ steps apart, interleaved into one stream and
//! produced in bulk, so that the optimisers' inner loops read their random
//! numbers from memory instead of waiting on one generator's state chain.

use rand::RngCore;

use crate::simd::{dispatch_at, simd, Simd};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The generator every run uses.
pub type RunRng = LaneRng;

/// The generator's name and layout as recorded in `meta.toml`.
pub const RNG_NAME: &str =
    "LaneRng: Xoshiro256++ in 4 lanes, lane k = lane 0 after k jumps of 2^128 steps, \
     interleaved (word 4t + k of the stream is lane k's output t); lane 0's state from \
     SplitMix64(seed), as rand_xoshiro 0.7's Xoshiro256PlusPlus::seed_from_u64(seed)";

/// The generator for one run, from its derived seed.
pub fn run_rng(seed: u64) -> RunRng {
    LaneRng::new(seed)
}

/// The number of Xoshiro256++ lanes of a [`LaneRng`].
pub const LANES: usize = 4;

/// Words buffered by [`LaneRng`] for one-at-a-time draws: 32 steps of all lanes.
const BUFFERED: usize = 32 * LANES;

/// The jump polynomial of Xoshiro256 (Blackman & Vigna 2021): applying it is
/// equivalent to 2¹²⁸ calls of the generator.
const JUMP: [u64; 4] = [
    0x180e_c6d3_3cfd_0aba,
    0xd5a6_1266_f0c9_392c,
    0xa958_2618_e03f_c9aa,
    0x39ab_dc45_29b1_661c,
];

/// Xoshiro256++ in [`LANES`] interleaved lanes (Blackman & Vigna 2021).
///
/// Lane 0 starts from the state `SplitMix64(seed)` fills in, exactly as
/// `rand_xoshiro`'s `Xoshiro256PlusPlus::seed_from_u64(seed)`; lane `k`
/// starts `k` jumps (`k·2¹²⁸` steps) further, so the lanes never overlap.
/// Word `L·t + k` of the stream is lane `k`'s output number `t`. The stream
/// is a pure function of the seed, whether it is read a word at a time
/// ([`RngCore::next_u64`]) or in blocks ([`Words::words`]), and on every
/// machine: the wide paths used where the CPU has AVX2 or AVX-512 compute
/// the same integers as the portable one.
#[derive(Clone, Debug)]
pub struct LaneRng {
    /// `state[i][k]`: state word `i` of lane `k` (structure of arrays, so the
    /// lanes step together in vector registers).
    state: [[u64; LANES]; 4],
    buffer: [u64; BUFFERED],
    /// The next unread word of `buffer`; `BUFFERED` when it is empty.
    next: usize,
    simd: Simd,
}

/// One Xoshiro256++ output and state step, on a single lane's state.
#[inline]
fn xoshiro_step(s: &mut [u64; 4]) -> u64 {
    let out = s[0].wrapping_add(s[3]).rotate_left(23).wrapping_add(s[0]);
    let t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = s[3].rotate_left(45);
    out
}

/// The Xoshiro256 jump: advances `s` by 2¹²⁸ steps.
fn jump(s: &mut [u64; 4]) {
    let mut acc = [0u64; 4];
    for word in JUMP {
        for bit in 0..64 {
            if word & (1u64 << bit) != 0 {
                for (a, v) in acc.iter_mut().zip(s.iter()) {
                    *a ^= v;
                }
            }
            xoshiro_step(s);
        }
    }
    *s = acc;
}

/// Writes `out.len() / L` Xoshiro256++ steps of `L` lanes into `out` (whose
/// length is a multiple of `L`), lane outputs interleaved; `state[i][k]` is
/// state word `i` of lane `k`. A run's stream is `L =` [`LANES`]; the
/// benchmarks also time wider `L` to find the generator's ceiling.
#[inline(always)]
pub fn lane_steps<const L: usize>(state: &mut [[u64; L]; 4], out: &mut [u64]) {
    let [mut s0, mut s1, mut s2, mut s3] = *state;
    for chunk in out.chunks_exact_mut(L) {
        for k in 0..L {
            chunk[k] = s0[k]
                .wrapping_add(s3[k])
                .rotate_left(23)
                .wrapping_add(s0[k]);
            let t = s1[k] << 17;
            s2[k] ^= s0[k];
            s3[k] ^= s1[k];
            s1[k] ^= s2[k];
            s0[k] ^= s3[k];
            s2[k] ^= t;
            s3[k] = s3[k].rotate_left(45);
        }
    }
    *state = [s0, s1, s2, s3];
}

/// [`lane_steps`] in AVX2 registers: one register per state word, the four
/// lanes side by side, with the same integer operations, hence the same
/// words. A rotation is a pair of shifts and an or, which compiles to one
/// `vprolq` under AVX-512VL.
///
/// # Safety
/// The caller runs with AVX2 enabled.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
unsafe fn lane_steps_x86(state: &mut [[u64; LANES]; 4], out: &mut [u64]) {
    use std::arch::x86_64::{
        __m256i, _mm256_add_epi64, _mm256_loadu_si256, _mm256_or_si256, _mm256_slli_epi64,
        _mm256_srli_epi64, _mm256_storeu_si256, _mm256_xor_si256,
    };
    const _: () = assert!(LANES == 4);
    // SAFETY: every load and store is of four u64 (32 bytes) inside an
    // array or chunk of exactly four u64; the caller has AVX2 enabled.
    unsafe {
        let mut s0 = _mm256_loadu_si256(state[0].as_ptr().cast::<__m256i>());
        let mut s1 = _mm256_loadu_si256(state[1].as_ptr().cast::<__m256i>());
        let mut s2 = _mm256_loadu_si256(state[2].as_ptr().cast::<__m256i>());
        let mut s3 = _mm256_loadu_si256(state[3].as_ptr().cast::<__m256i>());
        for chunk in out.chunks_exact_mut(LANES) {
            let sum = _mm256_add_epi64(s0, s3);
            let rot = _mm256_or_si256(_mm256_slli_epi64::<23>(sum), _mm256_srli_epi64::<41>(sum));
            _mm256_storeu_si256(
                chunk.as_mut_ptr().cast::<__m256i>(),
                _mm256_add_epi64(rot, s0),
            );
            let t = _mm256_slli_epi64::<17>(s1);
            s2 = _mm256_xor_si256(s2, s0);
            s3 = _mm256_xor_si256(s3, s1);
            s1 = _mm256_xor_si256(s1, s2);
            s0 = _mm256_xor_si256(s0, s3);
            s2 = _mm256_xor_si256(s2, t);
            s3 = _mm256_or_si256(_mm256_slli_epi64::<45>(s3), _mm256_srli_epi64::<19>(s3));
        }
        _mm256_storeu_si256(state[0].as_mut_ptr().cast::<__m256i>(), s0);
        _mm256_storeu_si256(state[1].as_mut_ptr().cast::<__m256i>(), s1);
        _mm256_storeu_si256(state[2].as_mut_ptr().cast::<__m256i>(), s2);
        _mm256_storeu_si256(state[3].as_mut_ptr().cast::<__m256i>(), s3);
    }
}

impl LaneRng {
    /// The generator of a run with derived seed `seed`.
    pub fn new(seed: u64) -> Self {
        let mut lane = [0u64; 4];
        for (i, w) in lane.iter_mut().enumerate() {
            *w = splitmix64(seed.wrapping_add((i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)));
        }
        let mut state = [[0u64; LANES]; 4];
        for k in 0..LANES {
            for (column, &word) in state.iter_mut().zip(&lane) {
                column[k] = word;
            }
            jump(&mut lane);
        }
        Self {
            state,
            buffer: [0; BUFFERED],
            next: BUFFERED,
            simd: simd(),
        }
    }

    /// Fills `out` (a multiple of [`LANES`] long) with the next steps.
    #[inline]
    fn steps(&mut self, out: &mut [u64]) {
        Self::advance(&mut self.state, self.simd, out)
    }

    #[inline]
    fn advance(state: &mut [[u64; LANES]; 4], simd: Simd, out: &mut [u64]) {
        dispatch_at(
            simd,
            #[inline(always)]
            |level| {
                #[cfg(target_arch = "x86_64")]
                if level >= Simd::Avx2 {
                    // SAFETY: `dispatch_at` runs this with AVX2 enabled.
                    return unsafe { lane_steps_x86(state, out) };
                }
                let _ = level;
                lane_steps(state, out)
            },
        )
    }

    #[cold]
    #[inline(never)]
    fn refill(&mut self) {
        Self::advance(&mut self.state, self.simd, &mut self.buffer);
        self.next = 0;
    }
}

impl RngCore for LaneRng {
    #[inline]
    fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    #[inline]
    fn next_u64(&mut self) -> u64 {
        if self.next == BUFFERED {
            self.refill();
        }
        let w = self.buffer[self.next];
        self.next += 1;
        w
    }

    fn fill_bytes(&mut self, dst: &mut [u8]) {
        for chunk in dst.chunks_mut(8) {
            let w = self.next_u64().to_le_bytes();
            chunk.copy_from_slice(&w[..chunk.len()]);
        }
    }
}

/// `u ~ U[0, 1)` with 52 random bits from one word, `(w >> 12) · 2⁻⁵²`, made
/// by setting the exponent of 1.0 and subtracting 1 (exact), which vector
/// units do without an integer-to-float conversion.
#[inline(always)]
pub fn unit52_of(w: u64) -> f64 {
    f64::from_bits(0x3FF0_0000_0000_0000 | (w >> 12)) - 1.0
}

/// `u ~ U[0, 1)` from one word: `(w >> 11) · 2⁻⁵³` ([`Draw::unit`]).
#[inline(always)]
pub fn unit_of(w: u64) -> f64 {
    (w >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A generator that hands out many words at once. The words are the same
/// as that many calls of [`RngCore::next_u64`], so code may mix both.
pub trait Words: RngCore {
    /// Fills `out` with the next `out.len()` words of the stream.
    #[inline]
    fn words(&mut self, out: &mut [u64]) {
        for w in out.iter_mut() {
            *w = self.next_u64();
        }
    }

    /// Fills `out` with the next `out.len()` uniform variates, each
    /// [`unit_of`] one word (the values of as many [`Draw::unit`] calls).
    #[inline]
    fn units(&mut self, out: &mut [f64]) {
        for u in out.iter_mut() {
            *u = unit_of(self.next_u64());
        }
    }
}

impl Words for Xoshiro256PlusPlus {}

impl Words for LaneRng {
    fn words(&mut self, out: &mut [u64]) {
        let take = (BUFFERED - self.next).min(out.len());
        out[..take].copy_from_slice(&self.buffer[self.next..self.next + take]);
        self.next += take;
        let rest = &mut out[take..];
        if rest.is_empty() {
            return;
        }
        // The buffer is empty, so the stream stands at a whole step.
        let whole = rest.len() / LANES * LANES;
        let (body, tail) = rest.split_at_mut(whole);
        self.steps(body);
        if !tail.is_empty() {
            self.refill();
            tail.copy_from_slice(&self.buffer[..tail.len()]);
            self.next = tail.len();
        }
    }

    fn units(&mut self, mut out: &mut [f64]) {
        while !out.is_empty() {
            if self.next == BUFFERED {
                self.refill();
            }
            let take = (BUFFERED - self.next).min(out.len());
            let (head, rest) = out.split_at_mut(take);
            units_of(self.simd, &self.buffer[self.next..self.next + take], head);
            self.next += take;
            out = rest;
        }
    }
}

/// `out[i] = unit_of(words[i])`, eight at a time where the CPU has
/// AVX-512DQ (an exact `vcvtuqq2pd` of the 53-bit integers, so the same
/// values as the scalar conversion). It keeps its own AVX-512 function
/// rather than [`dispatch_at`]: that measured 3–5 % slower on MHS, whose
/// steps convert a few uniforms at a time.
#[inline]
fn units_of(simd: Simd, words: &[u64], out: &mut [f64]) {
    #[inline(always)]
    fn each(words: &[u64], out: &mut [f64]) {
        for (u, &w) in out.iter_mut().zip(words) {
            *u = unit_of(w);
        }
    }
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,avx512f,avx512vl,avx512dq")]
    fn each_avx512(words: &[u64], out: &mut [f64]) {
        each(words, out)
    }
    #[cfg(target_arch = "x86_64")]
    if simd == Simd::Avx512 {
        // SAFETY: `simd` is at most the CPU's level.
        unsafe { each_avx512(words, out) };
        return;
    }
    let _ = simd;
    each(words, out)
}

/// SplitMix64's output function (Steele, Lea & Flood 2014, "Fast splittable
/// pseudorandom number generators", OOPSLA): a bijective 64-bit mixer.
#[inline]
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// FNV-1a 64-bit hash of a string (Fowler, Noll & Vo), stable across
/// platforms and Rust releases, unlike `std`'s hasher.
pub fn fnv1a64(text: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in text.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The seed of one run: `splitmix64` folded over (master seed, algorithm cell
/// key, problem key, run index).
///
/// Keys are the canonical texts of the cell and the problem (for example
/// `hs[hms=5;hmcr=0.9;...]` and `sphere-30`), so adding a cell or problem to a
/// spec never changes the seeds of the others.
///
/// ```
/// use metabezier_core::rng::derive_seed;
///
/// let a = derive_seed(2026, "HS:hs[hms=5]", "sphere-30", 0);
/// assert_eq!(a, derive_seed(2026, "HS:hs[hms=5]", "sphere-30", 0));
/// assert_ne!(a, derive_seed(2026, "HS:hs[hms=5]", "sphere-30", 1));
/// assert_ne!(a, derive_seed(2026, "HS:hs[hms=5]", "rastrigin-30", 0));
/// ```
pub fn derive_seed(master: u64, cell_key: &str, problem_key: &str, run: u32) -> u64 {
    let mut s = splitmix64(master);
    s = splitmix64(s ^ fnv1a64(cell_key));
    s = splitmix64(s ^ fnv1a64(problem_key));
    splitmix64(s ^ u64::from(run))
}

const MASK21: u64 = (1 << 21) - 1;

/// Decisions made from one 21-bit random field `f ~ U{0, …, 2²¹ − 1}`:
/// a Bernoulli trial with probability `p` is `f < ⌊p·2²¹⌋`, and an index in
/// `0..n` is `⌊f·n/2²¹⌋`. Rates are thus quantised to 2⁻²¹ ≈ 4.8·10⁻⁷ and
/// indices carry a relative bias below `n/2²¹`, in exchange for three
/// decisions per generator call in the optimisers' inner loops.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Field21;

impl Field21 {
    /// The mask of one field, `2²¹ − 1`.
    pub const MASK: u64 = MASK21;

    /// The threshold of a Bernoulli trial with probability `p ∈ [0, 1]`.
    #[inline]
    pub fn threshold(p: f64) -> u64 {
        (p.clamp(0.0, 1.0) * (1u64 << 21) as f64) as u64
    }

    /// The three fields of one word: bits 0–20, 21–41 and 42–62.
    #[inline(always)]
    pub fn split(w: u64) -> [u64; 3] {
        [w & MASK21, (w >> 21) & MASK21, (w >> 42) & MASK21]
    }

    /// An index in `0..n` from a field.
    #[inline]
    pub fn index(field: u64, n: usize) -> usize {
        ((field * n as u64) >> 21) as usize
    }
}

/// Bit-exact random variates on top of any [`RngCore`].
pub trait Draw: RngCore {
    /// `u ~ U[0, 1)` with 53 random bits: `(next_u64 >> 11) · 2⁻⁵³`.
    #[inline]
    fn unit(&mut self) -> f64 {
        unit_of(self.next_u64())
    }

    /// `true` with probability `p` (`unit() < p`).
    #[inline]
    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    /// A uniform index in `0..n` (`n ≥ 1`) by Lemire's unbiased
    /// multiply-and-reject method (Lemire 2019, ACM TOMACS 29(1)).
    #[inline]
    fn index(&mut self, n: usize) -> usize {
        debug_assert!(n > 0);
        let n = n as u64;
        let mut m = u128::from(self.next_u64()) * u128::from(n);
        if (m as u64) < n {
            let threshold = n.wrapping_neg() % n;
            while (m as u64) < threshold {
                m = u128::from(self.next_u64()) * u128::from(n);
            }
        }
        (m >> 64) as usize
    }

    /// `u ~ U[lo, hi)`.
    #[inline]
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + self.unit() * (hi - lo)
    }

    /// A standard normal variate by the Box–Muller transform (Box & Muller
    /// 1958): `√(−2 ln(1 − u₁)) · cos(2π u₂)`; the sine partner is discarded
    /// so the method keeps no state.
    #[inline]
    fn gaussian(&mut self) -> f64 {
        let u1 = self.unit();
        let u2 = self.unit();
        (-2.0 * (1.0 - u1).ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
}

impl<R: RngCore + ?Sized> Draw for R {}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;

    #[test]
    fn lanes_are_the_reference_generator_jumped() {
        // Lane k must be rand_xoshiro's Xoshiro256PlusPlus, seeded the same
        // way, after k jumps; the stream interleaves the lanes.
        for seed in [0, 1, 42, u64::MAX] {
            let mut lanes: Vec<Xoshiro256PlusPlus> = Vec::new();
            let mut r = Xoshiro256PlusPlus::seed_from_u64(seed);
            for _ in 0..LANES {
                lanes.push(r.clone());
                r.jump();
            }
            let mut ours = LaneRng::new(seed);
            for t in 0..100 {
                for (k, lane) in lanes.iter_mut().enumerate() {
                    assert_eq!(
                        ours.next_u64(),
                        lane.next_u64(),
                        "seed {seed}, step {t}, lane {k}"
                    );
                }
            }
        }
    }

    #[test]
    fn bulk_and_single_reads_give_one_stream() {
        let mut single = LaneRng::new(7);
        let want: Vec<u64> = (0..1000).map(|_| single.next_u64()).collect();
        // Reads of every length, including ones that straddle the buffer.
        let mut bulk = LaneRng::new(7);
        let mut got = Vec::new();
        let mut len = 0;
        while got.len() < want.len() {
            let n = (len % 71).min(want.len() - got.len());
            let mut w = vec![0; n];
            if len % 3 == 0 {
                w.iter_mut().for_each(|x| *x = bulk.next_u64());
            } else {
                bulk.words(&mut w);
            }
            got.extend(w);
            len += 1;
        }
        assert_eq!(got, want);
        let mut u = vec![0.0; 300];
        LaneRng::new(7).units(&mut u);
        for (u, w) in u.iter().zip(&want) {
            assert_eq!(*u, unit_of(*w));
        }
    }

    #[test]
    fn the_portable_and_wide_paths_agree() {
        let mut portable = LaneRng::new(11);
        portable.simd = Simd::Portable;
        let mut want = vec![0; 4096];
        portable.words(&mut want);
        for level in [Simd::Avx2, Simd::Avx512] {
            if level > simd() {
                continue;
            }
            let mut wide = LaneRng::new(11);
            wide.simd = level;
            let mut got = vec![0; 4096];
            wide.words(&mut got);
            assert_eq!(got, want, "{level:?}");
        }
    }

    #[test]
    fn seeds_differ_by_every_component() {
        let base = derive_seed(1, "hs", "sphere-10", 0);
        assert_ne!(base, derive_seed(2, "hs", "sphere-10", 0));
        assert_ne!(base, derive_seed(1, "ghs", "sphere-10", 0));
        assert_ne!(base, derive_seed(1, "hs", "sphere-30", 0));
        assert_ne!(base, derive_seed(1, "hs", "sphere-10", 1));
        assert_eq!(base, derive_seed(1, "hs", "sphere-10", 0));
    }

    #[test]
    fn fnv_matches_published_vectors() {
        // Test vectors from the FNV reference (isthe.com/chongo/tech/comp/fnv).
        assert_eq!(fnv1a64(""), 0xcbf29ce484222325);
        assert_eq!(fnv1a64("a"), 0xaf63dc4c8601ec8c);
        assert_eq!(fnv1a64("foobar"), 0x85944171f73967e8);
    }

    #[test]
    fn field21_decisions_have_the_right_frequencies() {
        assert_eq!(Field21::threshold(0.0), 0);
        assert_eq!(Field21::threshold(1.0), 1 << 21);
        assert_eq!(Field21::index(MASK21, 5), 4);
        assert_eq!(Field21::index(0, 5), 0);
        let mut rng = run_rng(9);
        let t = Field21::threshold(0.3);
        let (mut hits, mut counts) = (0usize, [0usize; 5]);
        let n = 100_000;
        for _ in 0..n {
            let [a, b, c] = Field21::split(rng.next_u64());
            assert!(a <= MASK21 && b <= MASK21 && c <= MASK21);
            hits += usize::from(a < t);
            counts[Field21::index(b, 5)] += 1;
        }
        assert!((hits as f64 / n as f64 - 0.3).abs() < 0.01);
        for c in counts {
            assert!((c as f64 / n as f64 - 0.2).abs() < 0.01);
        }
    }

    #[test]
    fn variates_have_the_right_ranges_and_moments() {
        let mut rng = run_rng(42);
        let n = 200_000;
        let (mut s, mut s2, mut counts) = (0.0, 0.0, [0usize; 7]);
        for _ in 0..n {
            let u = rng.unit();
            assert!((0.0..1.0).contains(&u));
            counts[rng.index(7)] += 1;
            let g = rng.gaussian();
            s += g;
            s2 += g * g;
        }
        let mean = s / n as f64;
        let var = s2 / n as f64 - mean * mean;
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "var {var}");
        for c in counts {
            let p = c as f64 / n as f64;
            assert!((p - 1.0 / 7.0).abs() < 0.005, "index frequency {p}");
        }
    }
}
