//! The harmony memory and the classical improvisation, shared by HS, GHS and
//! MHS (Geem, Kim & Loganathan 2001, "A new heuristic optimization algorithm:
//! harmony search", Simulation 76(2):60–68).

use rand::RngCore;

use super::evaluator::Evaluator;
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::ParamError;
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::{Draw, Field21};

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
    pub fn random<P: Problem + ?Sized, R: RngCore + ?Sized>(
        hms: usize,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) -> Self {
        let dim = eval.dim();
        let bounds = eval.bounds();
        let size = hms.min(usize::try_from(eval.remaining()).unwrap_or(usize::MAX));
        let mut harmonies = Vec::with_capacity(size * dim);
        let mut values = Vec::with_capacity(size);
        for _ in 0..size {
            let start = harmonies.len();
            harmonies.extend(bounds.iter().map(|b| b.lerp(rng.unit())));
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

impl Improvisation {
    /// Writes a new harmony into `x`; `bw[j]` is the absolute bandwidth of variable `j`.
    ///
    /// The HMCR trial, the memory index and the PAR trial of a variable
    /// come from one generator call ([`crate::rng::Field21`]).
    #[inline]
    pub fn improvise<R: RngCore + ?Sized>(
        &self,
        hm: &HarmonyMemory,
        bounds: &[Bounds],
        bw: &[f64],
        rng: &mut R,
        x: &mut [f64],
    ) {
        let hms = hm.len();
        let hmcr = Field21::threshold(self.hmcr);
        let par = Field21::threshold(self.par);
        for (j, ((xj, b), bwj)) in x.iter_mut().zip(bounds).zip(bw).enumerate() {
            let [consider, pick, adjust] = rng.fields21();
            if consider < hmcr {
                let mut v = hm.harmonies[Field21::index(pick, hms) * hm.dim + j];
                if adjust < par {
                    v = b.repair(v + bwj * (2.0 * rng.unit() - 1.0), self.policy);
                }
                *xj = v;
            } else {
                *xj = b.lerp(rng.unit());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::run_rng;

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
            imp.improvise(&hm, p.bounds(), &[1.0; 3], &mut rng, &mut x);
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

/// The `bw` parameter: the initial bandwidth fraction.
pub const BW_PARAM: ParamDef = ParamDef {
    name: "bw",
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
    name: "bw_decay",
    doc: "\"none\" (classical HS) or \"exponential\" decay of bw to bw_min (IHS)",
    kind: Kind::Choice(&["none", "exponential"]),
    default: Setting::Choice("none"),
    omit_at_default: false,
};

/// The `bw_min` parameter: the final fraction of an exponential decay.
pub const BW_MIN_PARAM: ParamDef = ParamDef {
    name: "bw_min",
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
            bw: p.real("bw"),
            decay: p.choice("bw_decay") == "exponential",
            bw_min: p.real("bw_min"),
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
