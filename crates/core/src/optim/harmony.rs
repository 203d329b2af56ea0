//! The harmony memory and the classical improvisation, shared by HS, GHS and
//! MHS (Geem, Kim & Loganathan 2001, "A new heuristic optimization algorithm:
//! harmony search", Simulation 76(2):60–68).

use crate::optim::params::Param;
use crate::rng::Words;

use super::evaluator::Evaluator;
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::ParamError;
use super::{clamp, select};
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::{unit52_of, Field21};
use crate::simd::Simd;

/// The harmony memory HM: `HMS` harmony vectors and their objective values,
/// stored row-major in one buffer, with the indices of the best and the worst.
#[derive(Clone, Debug)]
pub struct HarmonyMemory {
    dim: usize,
    harmonies: Vec<f64>,
    values: Vec<f64>,
    best: usize,
    worst: usize,
}

impl HarmonyMemory {
    /// Fills a memory of up to `hms` harmonies drawn uniformly in the bounds,
    /// evaluating each; it holds fewer if the budget runs out first.
    pub fn random<P: Problem + ?Sized, R: Words + ?Sized>(
        hms: usize,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) -> Self {
        let dim = eval.dim();
        let bounds = eval.bounds();
        let size = hms.min(usize::try_from(eval.remaining()).unwrap_or(usize::MAX));
        let mut harmonies = Vec::with_capacity(size * dim);
        let mut values = Vec::with_capacity(size);
        let mut u = vec![0.0; dim];
        for _ in 0..size {
            let start = harmonies.len();
            rng.units(&mut u);
            harmonies.extend(bounds.iter().zip(&u).map(|(b, &u)| b.lerp(u)));
            eval.place_start(&mut harmonies[start..]);
            values.push(eval.evaluate(&harmonies[start..]));
        }
        let mut hm = Self {
            dim,
            harmonies,
            values,
            best: 0,
            worst: 0,
        };
        hm.rescan();
        hm
    }

    fn rescan(&mut self) {
        let (mut best, mut worst) = (0, 0);
        for (i, &v) in self.values.iter().enumerate() {
            if v < self.values[best] {
                best = i;
            }
            if v > self.values[worst] {
                worst = i;
            }
        }
        self.best = best;
        self.worst = worst;
    }

    /// The number of harmonies held.
    #[inline]
    pub fn len(&self) -> usize {
        self.values.len()
    }

    /// Whether the memory is empty (only when the budget was zero).
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.values.is_empty()
    }

    /// Harmony `i`.
    #[inline]
    pub fn harmony(&self, i: usize) -> &[f64] {
        &self.harmonies[i * self.dim..(i + 1) * self.dim]
    }

    /// All harmonies, row-major (`len() × dim` values).
    #[inline]
    pub(crate) fn rows(&self) -> &[f64] {
        &self.harmonies
    }

    /// Variable `j` of harmony `i`.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        self.harmonies[i * self.dim + j]
    }

    /// The objective value of harmony `i`.
    #[inline]
    pub fn value(&self, i: usize) -> f64 {
        self.values[i]
    }

    /// The index of the best harmony (smallest value; the first on ties).
    #[inline]
    pub fn best(&self) -> usize {
        self.best
    }

    /// The index of the worst harmony (largest value; the first on ties).
    #[inline]
    pub fn worst(&self) -> usize {
        self.worst
    }

    /// The HS memory update: `x` replaces the worst harmony if its value is
    /// strictly smaller. Returns whether it did.
    #[inline]
    pub fn consider(&mut self, x: &[f64], value: f64) -> bool {
        // A NaN never enters the memory.
        if self.is_empty() || value.is_nan() || value >= self.values[self.worst] {
            return false;
        }
        let w = self.worst;
        self.harmonies[w * self.dim..(w + 1) * self.dim].copy_from_slice(x);
        // The best moves only to the new harmony (first index on ties); the
        // worst must be found again, among the values alone.
        let best_value = self.values[self.best];
        self.values[w] = value;
        if value < best_value || (value == best_value && w < self.best) || w == self.best {
            self.best = w;
        }
        let mut worst = 0;
        for (i, &v) in self.values.iter().enumerate() {
            if v > self.values[worst] {
                worst = i;
            }
        }
        self.worst = worst;
        true
    }
}

/// The classical HS improvisation of a new harmony `x′` (Geem et al. 2001).
///
/// For each variable: with probability HMCR take `x′_j` from a random
/// harmony in memory and then, with probability PAR, adjust it to
/// `x′_j ± u·bw_j` with `u ~ U(0,1)` (drawn as `bw_j·(2u − 1)`); otherwise
/// draw `x′_j` uniformly in its bounds. `bw_j` is absolute (already scaled
/// by the variable's range).
#[derive(Clone, Copy, Debug)]
pub struct Improvisation {
    /// Harmony memory considering rate HMCR.
    pub hmcr: f64,
    /// Pitch adjusting rate PAR.
    pub par: f64,
    /// How adjusted values are brought back inside the bounds.
    pub policy: BoundPolicy,
}

/// Variables improvised per block of random words.
pub(crate) const CHUNK: usize = 32;

/// The bounds of a problem as three columns, `L_j`, `U_j` and `U_j − L_j`,
/// the layout the vectorised improvisation reads.
#[derive(Clone, Debug)]
pub struct BoundColumns {
    pub(crate) lower: Vec<f64>,
    pub(crate) upper: Vec<f64>,
    pub(crate) width: Vec<f64>,
}

impl BoundColumns {
    /// The columns of `bounds`.
    pub fn new(bounds: &[Bounds]) -> Self {
        Self {
            lower: bounds.iter().map(|b| b.lower).collect(),
            upper: bounds.iter().map(|b| b.upper).collect(),
            width: bounds.iter().map(|b| b.width()).collect(),
        }
    }

    /// The number of variables.
    pub fn len(&self) -> usize {
        self.lower.len()
    }

    /// Whether there are no variables.
    pub fn is_empty(&self) -> bool {
        self.lower.is_empty()
    }
}

impl Improvisation {
    /// Writes a new harmony into `x`; `bw[j]` is the absolute bandwidth of
    /// variable `j`, and `words` is scratch space for the random words.
    ///
    /// Variables are improvised in blocks of up to 32. A block of `n`
    /// variables reads `2n` words of the stream: word `i` gives variable
    /// `i`'s HMCR trial, memory index and PAR trial
    /// ([`crate::rng::Field21`]), and word `n + i` its `u`
    /// ([`crate::rng::unit52_of`]), used by the pitch adjustment or, when the
    /// memory is not considered, by the uniform draw (the two uses exclude
    /// each other). All outcomes are computed and one is kept by masks, so
    /// there is no data-dependent branch; with `bounds = "clip"` on a CPU
    /// with AVX2 four variables are improvised at a time, with the same
    /// floating-point operations as the portable loop and so the same values.
    /// `simd` is the level the caller runs with ([`crate::simd::dispatch`]);
    /// below [`Simd::Avx2`] the portable rule does every variable.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    pub fn improvise<R: Words + ?Sized>(
        &self,
        hm: &HarmonyMemory,
        cols: &BoundColumns,
        bw: &[f64],
        rng: &mut R,
        words: &mut [u64; 2 * CHUNK],
        x: &mut [f64],
        simd: Simd,
    ) {
        let rates = [Field21::threshold(self.hmcr), Field21::threshold(self.par)];
        improvise_blocks(
            rng,
            words,
            x,
            simd,
            #[inline(always)]
            |start, fields, units, x| {
                #[cfg(target_arch = "x86_64")]
                if self.policy == BoundPolicy::Clip {
                    // SAFETY: `improvise_blocks` calls this only at
                    // `Simd::Avx2` or above, which the CPU has.
                    return unsafe { self.clip_block_avx2(hm, start, fields, units, cols, bw, x) };
                }
                let _ = (start, fields, units, x);
                0
            },
            #[inline(always)]
            |j, field, unit| self.variable(hm, j, field, unit, cols, bw, rates),
        );
    }

    /// Variable `j` improvised from its two words (the portable rule);
    /// `[hmcr, par]` are the rates as 21-bit thresholds.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn variable(
        &self,
        hm: &HarmonyMemory,
        j: usize,
        field: u64,
        unit: u64,
        cols: &BoundColumns,
        bw: &[f64],
        rates: [u64; 2],
    ) -> f64 {
        choose(hm, j, field, unit, cols, rates, |held, u| {
            let moved = held + bw[j] * (2.0 * u - 1.0);
            let b = Bounds::new(cols.lower[j], cols.upper[j]);
            match self.policy {
                BoundPolicy::Clip => clamp(b, moved),
                BoundPolicy::Reflect => b.reflect(moved),
            }
        })
    }

    /// [`Improvisation::variable`] for `bounds = "clip"`, four variables
    /// per AVX2 register; returns how many of the block's variables it did
    /// (a multiple of four, the rest are left to the portable rule).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn clip_block_avx2(
        &self,
        hm: &HarmonyMemory,
        start: usize,
        fields: &[u64],
        units: &[u64],
        cols: &BoundColumns,
        bw: &[f64],
        x: &mut [f64],
    ) -> usize {
        use std::arch::x86_64::*;
        let rates = [Field21::threshold(self.hmcr), Field21::threshold(self.par)];
        assert!(start + fields.len() / 4 * 4 <= bw.len());
        // SAFETY: AVX2 is enabled on this function; the rule reads
        // `bw[j..j + 4]` for blocks inside `start..start + n`, inside `bw`
        // by the assert.
        unsafe {
            let (one, two) = (_mm256_set1_pd(1.0), _mm256_set1_pd(2.0));
            choose_block_avx2(hm, start, fields, units, cols, rates, x, |v: &Lanes| {
                let step = _mm256_loadu_pd(bw.as_ptr().add(v.j));
                let moved = _mm256_add_pd(
                    v.held,
                    _mm256_mul_pd(step, _mm256_sub_pd(_mm256_mul_pd(two, v.u), one)),
                );
                clamp4(moved, v.lo, v.hi)
            })
        }
    }
}

/// Improvises `x` block by block from the stream, the layout HS, GHS and
/// the HS step of MHS share: a block of `n ≤` [`CHUNK`] variables starting
/// at `start` reads `2n` words, the first `n` (`fields`) giving each
/// variable's HMCR trial, memory index and PAR trial and the next `n`
/// (`units`) its second word. Where `simd` is at least [`Simd::Avx2`] (at
/// most the CPU's level) and `n ≥ 4`, `block(start, fields, units, x)`
/// improvises the leading variables of the block four at a time and
/// returns how many it did; `variable(j, field, unit)` gives each of the
/// rest.
#[inline(always)]
pub(crate) fn improvise_blocks<R: Words + ?Sized>(
    rng: &mut R,
    words: &mut [u64; 2 * CHUNK],
    x: &mut [f64],
    simd: Simd,
    mut block: impl FnMut(usize, &[u64], &[u64], &mut [f64]) -> usize,
    mut variable: impl FnMut(usize, u64, u64) -> f64,
) {
    let dim = x.len();
    for start in (0..dim).step_by(CHUNK) {
        let n = (start + CHUNK).min(dim) - start;
        let words = &mut words[..2 * n];
        rng.words(words);
        let (fields, units) = words.split_at(n);
        let done = if simd >= Simd::Avx2 && n >= 4 {
            block(start, fields, units, x)
        } else {
            0
        };
        for i in done..n {
            x[start + i] = variable(start + i, fields[i], units[i]);
        }
    }
}

/// The HS-family choice for variable `j` (HS, GHS and the HS step of MHS),
/// from its two words: the first gives the HMCR trial, the memory index and
/// the PAR trial ([`crate::rng::Field21`]), the second `u`
/// ([`crate::rng::unit52_of`]). With probability HMCR the value of a random
/// harmony is taken and, with probability PAR, replaced by
/// `adjusted(held, u)`; otherwise the variable is `L + u·(U − L)`. All
/// outcomes are computed and one is kept by masks.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn choose(
    hm: &HarmonyMemory,
    j: usize,
    field: u64,
    unit: u64,
    cols: &BoundColumns,
    [hmcr, par]: [u64; 2],
    adjusted: impl FnOnce(f64, f64) -> f64,
) -> f64 {
    let [consider, pick, adjust] = Field21::split(field);
    let u = unit52_of(unit);
    let b = Bounds::new(cols.lower[j], cols.upper[j]);
    let held = hm.harmonies[Field21::index(pick, hm.len()) * hm.dim + j];
    let adjusted = adjusted(held, u);
    let fresh = clamp(b, b.lower + u * cols.width[j]);
    select(consider < hmcr, select(adjust < par, adjusted, held), fresh)
}

/// The largest memory whose values [`choose_block_avx2`] selects by
/// comparing every harmony's four variables with the drawn indices, rather
/// than by four scalar loads.
const ROW_SELECT_MAX: i64 = 8;

/// Four variables `j..j + 4` of [`choose_block_avx2`], in AVX2 registers:
/// the held values, the second words, their `u`, and the bounds.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(crate) struct Lanes {
    pub(crate) j: usize,
    pub(crate) held: std::arch::x86_64::__m256d,
    pub(crate) words: std::arch::x86_64::__m256i,
    pub(crate) u: std::arch::x86_64::__m256d,
    pub(crate) lo: std::arch::x86_64::__m256d,
    pub(crate) hi: std::arch::x86_64::__m256d,
    pub(crate) width: std::arch::x86_64::__m256d,
}

/// `v` clipped into `[lo, hi]` by `maxpd` and `minpd`: [`clamp`] on four lanes.
///
/// # Safety
/// The caller runs with AVX2 enabled.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
pub(crate) unsafe fn clamp4(
    v: std::arch::x86_64::__m256d,
    lo: std::arch::x86_64::__m256d,
    hi: std::arch::x86_64::__m256d,
) -> std::arch::x86_64::__m256d {
    use std::arch::x86_64::{_mm256_max_pd, _mm256_min_pd};
    // SAFETY: AVX2 (and so AVX) is enabled in the caller.
    unsafe { _mm256_min_pd(_mm256_max_pd(v, lo), hi) }
}

/// [`choose`] for the variables `start..start + n` of a block, four per
/// AVX2 register with the same floating-point operations, where `n` is the
/// block's length rounded down to a multiple of four; returns `n`.
/// `adjusted` gives the adjusted values of four variables.
///
/// # Safety
/// The caller runs with AVX2 enabled, and `adjusted` reads only memory it
/// has checked.
#[cfg(target_arch = "x86_64")]
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) unsafe fn choose_block_avx2(
    hm: &HarmonyMemory,
    start: usize,
    fields: &[u64],
    units: &[u64],
    cols: &BoundColumns,
    [hmcr, par]: [u64; 2],
    x: &mut [f64],
    adjusted: impl Fn(&Lanes) -> std::arch::x86_64::__m256d,
) -> usize {
    use std::arch::x86_64::*;
    let n = fields.len() / 4 * 4;
    let (hms, dim) = (hm.len() as i64, hm.dim as i64);
    assert!(units.len() >= n && start + n <= x.len() && start + n <= cols.len());
    assert!(hm.harmonies.len() == hm.len() * hm.dim);
    // SAFETY: the loads and stores below read lanes `start + i ..
    // start + i + 4` with `i + 4 ≤ n`, inside every slice by the asserts;
    // the scalar loads read `index·dim + j` with `index < hms` (a 21-bit
    // field times hms, shifted down by 21) and `j < dim`, inside the
    // memory; the caller has AVX2 enabled.
    unsafe {
        let mask = _mm256_set1_epi64x(Field21::MASK as i64);
        let hmcr = _mm256_set1_epi64x(hmcr as i64);
        let par = _mm256_set1_epi64x(par as i64);
        let hms_v = _mm256_set1_epi64x(hms);
        let dim_v = _mm256_set1_epi64x(dim);
        let one_bits = _mm256_set1_epi64x(0x3FF0_0000_0000_0000);
        let one = _mm256_set1_pd(1.0);
        let lanes = _mm256_set_epi64x(3, 2, 1, 0);
        let base = hm.harmonies.as_ptr();
        for i in (0..n).step_by(4) {
            let j = start + i;
            let f = _mm256_loadu_si256(fields.as_ptr().add(i).cast());
            let consider = _mm256_cmpgt_epi64(hmcr, _mm256_and_si256(f, mask));
            let adjust =
                _mm256_cmpgt_epi64(par, _mm256_and_si256(_mm256_srli_epi64::<42>(f), mask));
            let pick = _mm256_and_si256(_mm256_srli_epi64::<21>(f), mask);
            let index = _mm256_srli_epi64::<21>(_mm256_mul_epu32(pick, hms_v));
            let held = if hms <= ROW_SELECT_MAX {
                // A small memory: load the four variables of every harmony
                // and keep, lane by lane, the one whose index was drawn.
                let mut held = _mm256_loadu_pd(base.add(j));
                for r in 1..hms {
                    let row = _mm256_loadu_pd(base.add(r as usize * hm.dim + j));
                    let hit = _mm256_cmpeq_epi64(index, _mm256_set1_epi64x(r));
                    held = _mm256_blendv_pd(held, row, _mm256_castsi256_pd(hit));
                }
                held
            } else {
                let at = _mm256_add_epi64(
                    _mm256_mul_epu32(index, dim_v),
                    _mm256_add_epi64(_mm256_set1_epi64x(j as i64), lanes),
                );
                // Four scalar loads: no slower than `vgatherqpd` on the AMD
                // EPYC measured, and not subject to the slow microcoded
                // gathers of Intel parts with the GDS mitigation.
                let mut k = [0i64; 4];
                _mm256_storeu_si256(k.as_mut_ptr().cast(), at);
                _mm256_set_pd(
                    *base.offset(k[3] as isize),
                    *base.offset(k[2] as isize),
                    *base.offset(k[1] as isize),
                    *base.offset(k[0] as isize),
                )
            };
            let words = _mm256_loadu_si256(units.as_ptr().add(i).cast());
            let u = _mm256_sub_pd(
                _mm256_castsi256_pd(_mm256_or_si256(_mm256_srli_epi64::<12>(words), one_bits)),
                one,
            );
            let lo = _mm256_loadu_pd(cols.lower.as_ptr().add(j));
            let hi = _mm256_loadu_pd(cols.upper.as_ptr().add(j));
            let width = _mm256_loadu_pd(cols.width.as_ptr().add(j));
            let adjusted = adjusted(&Lanes {
                j,
                held,
                words,
                u,
                lo,
                hi,
                width,
            });
            let fresh = clamp4(_mm256_add_pd(lo, _mm256_mul_pd(u, width)), lo, hi);
            let kept = _mm256_blendv_pd(held, adjusted, _mm256_castsi256_pd(adjust));
            let out = _mm256_blendv_pd(fresh, kept, _mm256_castsi256_pd(consider));
            _mm256_storeu_pd(x.as_mut_ptr().add(j), out);
        }
    }
    n
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::rng::{run_rng, Words};

    /// `Σ|x_j|` in the given bounds: a memory filler for the tests.
    struct Abs(Vec<Bounds>);
    impl Problem for Abs {
        fn dim(&self) -> usize {
            self.0.len()
        }
        fn bounds(&self) -> &[Bounds] {
            &self.0
        }
        fn objective(&self, x: &[f64]) -> f64 {
            x.iter().map(|v| v.abs()).sum()
        }
    }

    /// A memory of `hms` random harmonies in `bounds`, for the tests here
    /// and in GHS.
    pub(crate) fn memory_in(bounds: &[Bounds], hms: usize, rng: &mut impl Words) -> HarmonyMemory {
        let p = Abs(bounds.to_vec());
        HarmonyMemory::random(hms, &mut Evaluator::new(&p, 100), rng)
    }

    #[test]
    fn memory_replaces_only_the_worst_and_only_when_better() {
        let p = Abs(vec![Bounds::new(-1.0, 1.0); 2]);
        let mut ev = Evaluator::new(&p, 100);
        let mut rng = run_rng(7);
        let mut hm = HarmonyMemory::random(4, &mut ev, &mut rng);
        assert_eq!(hm.len(), 4);
        assert_eq!(ev.used(), 4);
        let worst = hm.value(hm.worst());
        assert!(
            !hm.consider(&[1.0, 1.0], 2.0),
            "worse than the worst is refused"
        );
        assert!(!hm.consider(&[0.0, 0.0], worst), "a tie is refused");
        let w = hm.worst();
        assert!(hm.consider(&[0.0, 0.0], 0.0));
        assert_eq!(hm.harmony(w), &[0.0, 0.0]);
        assert_eq!(hm.best(), w);
        for i in 0..hm.len() {
            assert!(hm.value(i) <= hm.value(hm.worst()));
        }
    }

    #[test]
    fn memory_is_truncated_by_a_small_budget() {
        let p = Abs(vec![Bounds::new(-1.0, 1.0); 3]);
        let mut ev = Evaluator::new(&p, 2);
        let hm = HarmonyMemory::random(10, &mut ev, &mut run_rng(1));
        assert_eq!(hm.len(), 2);
        assert_eq!(ev.remaining(), 0);
    }

    #[test]
    fn the_avx2_block_improvises_exactly_as_the_portable_rule() {
        if crate::simd::simd() < crate::simd::Simd::Avx2 {
            return;
        }
        let mut rng = run_rng(5);
        for dim in [1, 3, 4, 7, 30, 33] {
            let bounds: Vec<Bounds> = (0..dim)
                .map(|j| Bounds::new(-1.0 - j as f64, 2.0 + 0.5 * j as f64))
                .collect();
            let hm = memory_in(&bounds, 7, &mut rng);
            let cols = BoundColumns::new(&bounds);
            let bw: Vec<f64> = (0..dim).map(|j| 0.3 + j as f64).collect();
            for (hmcr, par) in [(0.9, 0.3), (0.5, 0.9), (1.0, 0.0), (0.0, 1.0)] {
                let imp = Improvisation {
                    hmcr,
                    par,
                    policy: BoundPolicy::Clip,
                };
                let n = dim.min(CHUNK);
                let mut words = vec![0u64; 2 * n];
                rng.words(&mut words);
                let (fields, units) = words.split_at(n);
                let mut wide = vec![f64::NAN; dim];
                // SAFETY: the CPU has AVX2 (checked above).
                let done =
                    unsafe { imp.clip_block_avx2(&hm, 0, fields, units, &cols, &bw, &mut wide) };
                assert_eq!(done, n / 4 * 4);
                for i in 0..done {
                    let rates = [Field21::threshold(hmcr), Field21::threshold(par)];
                    let want = imp.variable(&hm, i, fields[i], units[i], &cols, &bw, rates);
                    assert_eq!(wide[i].to_bits(), want.to_bits(), "dim {dim}, variable {i}");
                }
            }
        }
    }

    #[test]
    fn hmcr_one_par_zero_only_copies_memory_values() {
        let p = Abs(vec![Bounds::new(-5.0, 5.0); 3]);
        let mut ev = Evaluator::new(&p, 100);
        let mut rng = run_rng(3);
        let hm = HarmonyMemory::random(3, &mut ev, &mut rng);
        let imp = Improvisation {
            hmcr: 1.0,
            par: 0.0,
            policy: BoundPolicy::Clip,
        };
        let mut x = [0.0; 3];
        for _ in 0..50 {
            imp.improvise(
                &hm,
                &BoundColumns::new(p.bounds()),
                &[1.0; 3],
                &mut rng,
                &mut [0; 2 * CHUNK],
                &mut x,
                crate::simd::simd(),
            );
            for (j, xj) in x.iter().enumerate() {
                assert!((0..3).any(|i| hm.harmony(i)[j] == *xj));
            }
        }
    }
}

/// The pitch-adjustment bandwidth of HS and MHS, as a fraction of each
/// variable's range, `bw_j = bw·(U_j − L_j)`, so that one setting serves
/// variables of different scales.
///
/// With `decay` the bandwidth falls exponentially over the budget,
/// `bw(t) = bw·(bw_min/bw)^(t/NI)` (Mahdavi, Fesanghary & Damangir 2007,
/// "An improved harmony search algorithm", Appl. Math. Comput.
/// 188:1567–1579); without it, it is the classical constant bandwidth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bandwidth {
    /// The bandwidth fraction at the start of the run.
    pub bw: f64,
    /// Whether the bandwidth decays exponentially to `bw_min`.
    pub decay: bool,
    /// The final bandwidth fraction when `decay` is set.
    pub bw_min: f64,
}

/// The key of the `bw` parameter.
pub const BW_KEY: Param<f64> = Param::new("bw");
/// The key of the `bw_decay` parameter.
pub const BW_DECAY_KEY: Param<&'static str> = Param::new("bw_decay");
/// The key of the `bw_min` parameter.
pub const BW_MIN_KEY: Param<f64> = Param::new("bw_min");

/// The `bw` parameter: the initial bandwidth fraction.
pub const BW_PARAM: ParamDef = ParamDef {
    name: BW_KEY.name,
    doc: "bandwidth bw, as a fraction of each variable's range",
    kind: Kind::Real {
        min: 0.0,
        max: 1.0,
        open_min: false,
    },
    default: Setting::Real(0.01),
    omit_at_default: false,
};

/// The `bw_decay` parameter: `"none"` or `"exponential"` (IHS).
pub const BW_DECAY_PARAM: ParamDef = ParamDef {
    name: BW_DECAY_KEY.name,
    doc: "\"none\" (classical HS) or \"exponential\" decay of bw to bw_min (IHS)",
    kind: Kind::Choice(&["none", "exponential"]),
    default: Setting::Choice("none"),
    omit_at_default: false,
};

/// The `bw_min` parameter: the final fraction of an exponential decay.
pub const BW_MIN_PARAM: ParamDef = ParamDef {
    name: BW_MIN_KEY.name,
    doc: "final bandwidth fraction for bw_decay = \"exponential\"",
    kind: Kind::Real {
        min: 0.0,
        max: 1.0,
        open_min: true,
    },
    default: Setting::Real(1e-6),
    omit_at_default: false,
};

impl Bandwidth {
    /// Reads [`BW_PARAM`], [`BW_DECAY_PARAM`] and [`BW_MIN_PARAM`], and
    /// checks that a decaying bandwidth does not grow.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let s = Self {
            bw: p.get(BW_KEY),
            decay: p.get(BW_DECAY_KEY) == "exponential",
            bw_min: p.get(BW_MIN_KEY),
        };
        if s.decay && s.bw_min > s.bw {
            return Err(ParamError::new(
                "bw_min",
                format!("bw_min ({}) must not exceed bw ({})", s.bw_min, s.bw),
            ));
        }
        Ok(s)
    }

    /// The bandwidth fraction at progress `t/NI ∈ [0, 1]`.
    #[inline]
    pub fn fraction(&self, progress: f64) -> f64 {
        if self.decay {
            self.bw * (self.bw_min / self.bw).powf(progress)
        } else {
            self.bw
        }
    }

    /// Writes the absolute bandwidths `bw_j = fraction(t)·(U_j − L_j)` for
    /// progress `t/NI` into `out`.
    pub fn scale(&self, progress: f64, widths: &[f64], out: &mut [f64]) {
        let f = self.fraction(progress);
        for (o, w) in out.iter_mut().zip(widths) {
            *o = f * w;
        }
    }
}
