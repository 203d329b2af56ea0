//! Random variates drawn bit-exactly from any `RngCore`, and per-run seeds.
//!
//! The optimisers draw every random number through [`Draw`], whose methods are
//! defined here from raw 64-bit outputs rather than by `rand`'s distribution
//! code. A run's results therefore depend only on the generator (Xoshiro256++,
//! Blackman & Vigna 2021, "Scrambled linear pseudorandom number generators",
//! ACM TOMS 47(4)) and on this file, not on the sampling algorithms of a
//! particular `rand` release.

use rand::{RngCore, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The generator every run uses.
pub type RunRng = Xoshiro256PlusPlus;

/// The generator's name as recorded in `meta.toml`.
pub const RNG_NAME: &str =
    "Xoshiro256PlusPlus (rand_xoshiro 0.7), state from SeedableRng::seed_from_u64(seed) (SplitMix64)";

/// The generator for one run, from its derived seed.
pub fn run_rng(seed: u64) -> RunRng {
    RunRng::seed_from_u64(seed)
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
    /// The threshold of a Bernoulli trial with probability `p ∈ [0, 1]`.
    #[inline]
    pub fn threshold(p: f64) -> u64 {
        (p.clamp(0.0, 1.0) * (1u64 << 21) as f64) as u64
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
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
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

    /// Three independent 21-bit fields of one 64-bit output, for hot loops
    /// that make several discrete decisions per variable (see [`Field21`]).
    #[inline]
    fn fields21(&mut self) -> [u64; 3] {
        let r = self.next_u64();
        [r & MASK21, (r >> 21) & MASK21, (r >> 42) & MASK21]
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
            let [a, b, c] = rng.fields21();
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
