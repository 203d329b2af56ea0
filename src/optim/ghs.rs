//! Global-best Harmony Search, GHS (Omran & Mahdavi 2008, "Global-best
//! harmony search", Applied Mathematics and Computation 198:643–656).

use super::harmony::{HarmonyMemory, CHUNK};
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{clamp, select, Optimiser, ParamError};
use crate::optim::evaluator::Evaluator;
use crate::problem::Problem;
use crate::rng::{unit_of, Field21, Words};

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
/// evaluation budget used. Each variable reads two words of the stream: the
/// first gives the HMCR trial, memory index and PAR trial
/// ([`crate::rng::Field21`]), the second either the uniform draw or, when
/// the value is adjusted, the dimension `k` (the two uses exclude each
/// other); the outcome is chosen by masks, without branches.
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

/// The parameters of [`GlobalBestHarmonySearch`], with the paper's defaults.
pub static PARAMS: [ParamDef; 4] = [
    ParamDef {
        name: "hms",
        doc: "harmony memory size HMS",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(5),
        omit_at_default: false,
    },
    ParamDef {
        name: "hmcr",
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
        name: "par_min",
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
        name: "par_max",
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
            hms: p.count("hms") as usize,
            hmcr: p.real("hmcr"),
            par_min: p.real("par_min"),
            par_max: p.real("par_max"),
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
        let mut x = vec![0.0; dim];
        // The best harmony in normalised coordinates, refreshed when it changes.
        let mut best_unit = vec![0.0; dim];
        let refresh = |hm: &HarmonyMemory, best_unit: &mut [f64]| {
            for ((u, b), v) in best_unit.iter_mut().zip(bounds).zip(hm.harmony(hm.best())) {
                *u = b.normalise(*v);
            }
        };
        refresh(&hm, &mut best_unit);
        let hms = hm.len();
        let hmcr = Field21::threshold(self.hmcr);
        let mut words = [0u64; 2 * CHUNK];
        while eval.remaining() > 0 {
            let par =
                Field21::threshold(self.par_min + (self.par_max - self.par_min) * eval.progress());
            for start in (0..dim).step_by(CHUNK) {
                let end = (start + CHUNK).min(dim);
                let words = &mut words[..2 * (end - start)];
                rng.words(words);
                for ((w, xj), (j, b)) in words
                    .chunks_exact(2)
                    .zip(&mut x[start..end])
                    .zip(bounds[start..end].iter().enumerate())
                {
                    let [consider, pick, adjust] = Field21::split(w[0]);
                    let held = hm.get(Field21::index(pick, hms), start + j);
                    let unit = best_unit[Field21::index(w[1] & Field21::MASK, dim)];
                    let copied = clamp(*b, b.lower + unit * b.width());
                    let fresh = clamp(*b, b.lower + unit_of(w[1]) * b.width());
                    *xj = select(consider < hmcr, select(adjust < par, copied, held), fresh);
                }
            }
            let v = eval.evaluate(&x);
            if hm.consider(&x, v) && v <= hm.value(hm.best()) {
                refresh(&hm, &mut best_unit);
            }
        }
    }
}
