//! Global-best Harmony Search, GHS (Omran & Mahdavi 2008, "Global-best
//! harmony search", Applied Mathematics and Computation 198:643–656).

use super::harmony::{choose, improvise_blocks, BoundColumns, HarmonyMemory, CHUNK};
#[cfg(target_arch = "x86_64")]
use super::harmony::{choose_block_avx2, clamp4, Lanes};
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{clamp, Optimiser, ParamError};
use crate::optim::evaluator::Evaluator;
use crate::optim::params::Param;
use crate::problem::{Bounds, Problem};
use crate::rng::{Field21, Words};
use crate::simd::dispatch;

/// GHS: HS without a bandwidth, whose pitch adjustment copies a random
/// dimension of the best harmony.
///
/// For each variable `j`: with probability HMCR, `x′_j` is taken from a random
/// harmony; then with probability `PAR(t) = PARmin + (PARmax − PARmin)·t/NI`
/// it is replaced by `x^best_k` for a random dimension `k`. Otherwise `x′_j`
/// is uniform in its bounds. Because variables may have different bounds,
/// the copy is made in normalised coordinates:
/// `x′_j = L_j + (x^best_k − L_k)/(U_k − L_k)·(U_j − L_j)`; on a common box this
/// is exactly the paper's `x′_j = x^best_k`. `t/NI` is the fraction of the
/// evaluation budget used. Variables are improvised in blocks of up to 32;
/// a block of `n` reads `2n` words, word `i` and word `n + i` for variable
/// `i` (the HMCR, index and PAR fields, then the uniform draw or the copied
/// dimension), and chooses by masks, without branches
/// (four variables at a time on a CPU with AVX2, with the same values).
#[derive(Clone, Debug, PartialEq)]
pub struct GlobalBestHarmonySearch {
    /// Harmony memory size HMS.
    pub hms: usize,
    /// Harmony memory considering rate HMCR.
    pub hmcr: f64,
    /// PAR at the start of the run.
    pub par_min: f64,
    /// PAR at the end of the run.
    pub par_max: f64,
}

/// The key of the `hms` parameter.
pub const HMS_KEY: Param<u64> = Param::new("hms");
/// The key of the `hmcr` parameter.
pub const HMCR_KEY: Param<f64> = Param::new("hmcr");
/// The key of the `par_min` parameter.
pub const PAR_MIN_KEY: Param<f64> = Param::new("par_min");
/// The key of the `par_max` parameter.
pub const PAR_MAX_KEY: Param<f64> = Param::new("par_max");

/// The parameters of [`GlobalBestHarmonySearch`], with the paper's defaults.
pub static PARAMS: [ParamDef; 4] = [
    ParamDef {
        name: HMS_KEY.name,
        doc: "harmony memory size HMS",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(5),
        omit_at_default: false,
    },
    ParamDef {
        name: HMCR_KEY.name,
        doc: "harmony memory considering rate HMCR",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.9),
        omit_at_default: false,
    },
    ParamDef {
        name: PAR_MIN_KEY.name,
        doc: "pitch adjusting rate at the start, PARmin",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.01),
        omit_at_default: false,
    },
    ParamDef {
        name: PAR_MAX_KEY.name,
        doc: "pitch adjusting rate at the end, PARmax",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.99),
        omit_at_default: false,
    },
];

impl Default for GlobalBestHarmonySearch {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl GlobalBestHarmonySearch {
    /// Builds GHS from validated parameters.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let s = Self {
            hms: p.get(HMS_KEY) as usize,
            hmcr: p.get(HMCR_KEY),
            par_min: p.get(PAR_MIN_KEY),
            par_max: p.get(PAR_MAX_KEY),
        };
        if s.par_min > s.par_max {
            return Err(ParamError::new(
                "par_min",
                format!(
                    "par_min ({}) must not exceed par_max ({})",
                    s.par_min, s.par_max
                ),
            ));
        }
        Ok(s)
    }
}

impl Optimiser for GlobalBestHarmonySearch {
    /// The harmony memory (HMS × D) and a few D-vectors.
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        super::vectors_bytes(self.hms + 4, dim)
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let mut hm = HarmonyMemory::random(self.hms, eval, rng);
        if hm.is_empty() {
            return;
        }
        let bounds = eval.bounds();
        let dim = bounds.len();
        let cols = BoundColumns::new(bounds);
        let mut x = vec![0.0; dim];
        // The best harmony in normalised coordinates, refreshed when it changes.
        let mut best_unit = vec![0.0; dim];
        let refresh = |hm: &HarmonyMemory, best_unit: &mut [f64]| {
            for ((u, b), v) in best_unit.iter_mut().zip(bounds).zip(hm.harmony(hm.best())) {
                *u = b.normalise(*v);
            }
        };
        refresh(&hm, &mut best_unit);
        let mut words = [0u64; 2 * CHUNK];
        dispatch(
            #[inline(always)]
            |simd| {
                while eval.remaining() > 0 {
                    let rule = Rule {
                        hmcr: Field21::threshold(self.hmcr),
                        par: Field21::threshold(
                            self.par_min + (self.par_max - self.par_min) * eval.progress(),
                        ),
                    };
                    improvise_blocks(
                        rng,
                        &mut words,
                        &mut x,
                        simd,
                        #[inline(always)]
                        |start, fields, units, x| {
                            // SAFETY: `improvise_blocks` calls this only at
                            // `Simd::Avx2` or above, which the CPU has.
                            #[cfg(target_arch = "x86_64")]
                            return unsafe {
                                rule.block_avx2(&hm, &best_unit, start, fields, units, &cols, x)
                            };
                            #[cfg(not(target_arch = "x86_64"))]
                            {
                                let _ = (start, fields, units, x);
                                0
                            }
                        },
                        #[inline(always)]
                        |j, field, unit| rule.variable(&hm, &best_unit, j, field, unit, &cols),
                    );
                    let v = eval.evaluate(&x);
                    if hm.consider(&x, v) && v <= hm.value(hm.best()) {
                        refresh(&hm, &mut best_unit);
                    }
                }
            },
        );
    }
}

/// The GHS improvisation with the rates of one step: HMCR and `PAR(t)` as
/// 21-bit thresholds ([`crate::rng::Field21`]).
#[derive(Clone, Copy, Debug)]
struct Rule {
    hmcr: u64,
    par: u64,
}

impl Rule {
    /// Variable `j` from its two words ([`choose`]); an adjusted value is
    /// the best harmony's variable `k`, mapped into `j`'s bounds, where `k`
    /// comes from the low 21 bits of the second word (whose `u` is used only
    /// by the uniform draw, so the two uses exclude each other).
    #[inline(always)]
    fn variable(
        self,
        hm: &HarmonyMemory,
        best_unit: &[f64],
        j: usize,
        field: u64,
        unit: u64,
        cols: &BoundColumns,
    ) -> f64 {
        choose(hm, j, field, unit, cols, [self.hmcr, self.par], |_, _| {
            let copied = best_unit[Field21::index(unit & Field21::MASK, best_unit.len())];
            let b = Bounds::new(cols.lower[j], cols.upper[j]);
            clamp(b, b.lower + copied * cols.width[j])
        })
    }

    /// [`Rule::variable`] for four variables per AVX2 register, with the
    /// same floating-point operations; returns how many of the block's
    /// variables it did (a multiple of four).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn block_avx2(
        self,
        hm: &HarmonyMemory,
        best_unit: &[f64],
        start: usize,
        fields: &[u64],
        units: &[u64],
        cols: &BoundColumns,
        x: &mut [f64],
    ) -> usize {
        use std::arch::x86_64::*;
        let dim = best_unit.len();
        assert!(hm.rows().len() == hm.len() * dim);
        // SAFETY: AVX2 is enabled on this function; the rule reads
        // `best_unit[k]` with `k < dim` (a 21-bit field times the length,
        // shifted down by 21).
        unsafe {
            let mask = _mm256_set1_epi64x(Field21::MASK as i64);
            let dim_v = _mm256_set1_epi64x(dim as i64);
            let best = best_unit.as_ptr();
            let rates = [self.hmcr, self.par];
            choose_block_avx2(hm, start, fields, units, cols, rates, x, |v: &Lanes| {
                let k = _mm256_srli_epi64::<21>(_mm256_mul_epu32(
                    _mm256_and_si256(v.words, mask),
                    dim_v,
                ));
                let mut b = [0i64; 4];
                _mm256_storeu_si256(b.as_mut_ptr().cast(), k);
                let copied = _mm256_set_pd(
                    *best.offset(b[3] as isize),
                    *best.offset(b[2] as isize),
                    *best.offset(b[1] as isize),
                    *best.offset(b[0] as isize),
                );
                clamp4(
                    _mm256_add_pd(v.lo, _mm256_mul_pd(copied, v.width)),
                    v.lo,
                    v.hi,
                )
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::harmony::tests::memory_in;
    use crate::rng::run_rng;

    #[test]
    fn the_avx2_block_improvises_exactly_as_the_portable_rule() {
        if crate::simd::simd() < crate::simd::Simd::Avx2 {
            return;
        }
        let mut rng = run_rng(8);
        for dim in [1, 4, 6, 30, 35] {
            let bounds: Vec<Bounds> = (0..dim)
                .map(|j| Bounds::new(-2.0 + j as f64, 3.0 + 2.0 * j as f64))
                .collect();
            let hm = memory_in(&bounds, 5, &mut rng);
            let cols = BoundColumns::new(&bounds);
            let best_unit: Vec<f64> = (0..dim).map(|j| (j as f64 * 0.37) % 1.0).collect();
            for (hmcr, par) in [(0.9, 0.3), (0.5, 0.99), (1.0, 0.0), (0.0, 1.0)] {
                let rule = Rule {
                    hmcr: Field21::threshold(hmcr),
                    par: Field21::threshold(par),
                };
                let n = dim.min(CHUNK);
                let mut words = vec![0u64; 2 * n];
                rng.words(&mut words);
                let (fields, units) = words.split_at(n);
                let mut wide = vec![f64::NAN; dim];
                // SAFETY: the CPU has AVX2 (checked above).
                let done =
                    unsafe { rule.block_avx2(&hm, &best_unit, 0, fields, units, &cols, &mut wide) };
                assert_eq!(done, n / 4 * 4);
                for i in 0..done {
                    let want = rule.variable(&hm, &best_unit, i, fields[i], units[i], &cols);
                    assert_eq!(wide[i].to_bits(), want.to_bits(), "dim {dim}, variable {i}");
                }
            }
        }
    }
}
