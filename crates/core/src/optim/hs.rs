//! Harmony Search, HS (Geem, Kim & Loganathan 2001, "A new heuristic
//! optimization algorithm: harmony search", Simulation 76(2):60–68).

use crate::optim::params::Param;
use crate::rng::Words;

use super::harmony::{
    Bandwidth, BoundColumns, HarmonyMemory, Improvisation, BW_DECAY_PARAM, BW_MIN_PARAM, BW_PARAM,
    CHUNK,
};
use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{policy_param, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::problem::{BoundPolicy, Problem};
use crate::simd::dispatch;

/// Classical Harmony Search: improvise one harmony per evaluation and let it
/// replace the worst harmony in memory if it is better.
///
/// The bandwidth is a fraction of each variable's range ([`Bandwidth`]); the
/// default is the classical constant bandwidth, and `bw_decay =
/// "exponential"` gives the IHS schedule of Mahdavi et al. (2007).
#[derive(Clone, Debug, PartialEq)]
pub struct HarmonySearch {
    /// Harmony memory size HMS.
    pub hms: usize,
    /// Harmony memory considering rate HMCR.
    pub hmcr: f64,
    /// Pitch adjusting rate PAR.
    pub par: f64,
    /// The pitch-adjustment bandwidth and its schedule.
    pub bandwidth: Bandwidth,
    /// Bound handling for pitch-adjusted values.
    pub policy: BoundPolicy,
}

/// The key of the `hms` parameter.
pub const HMS_KEY: Param<u64> = Param::new("hms");
/// The key of the `hmcr` parameter.
pub const HMCR_KEY: Param<f64> = Param::new("hmcr");
/// The key of the `par` parameter.
pub const PAR_KEY: Param<f64> = Param::new("par");

/// The parameters of [`HarmonySearch`]; defaults follow the HS settings of
/// Omran & Mahdavi (2008).
pub static PARAMS: [ParamDef; 7] = [
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
        name: PAR_KEY.name,
        doc: "pitch adjusting rate PAR",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.3),
        omit_at_default: false,
    },
    BW_PARAM,
    BW_DECAY_PARAM,
    BW_MIN_PARAM,
    BOUNDS_PARAM,
];

impl Default for HarmonySearch {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl HarmonySearch {
    /// Builds HS from validated parameters.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        Ok(Self {
            hms: p.get(HMS_KEY) as usize,
            hmcr: p.get(HMCR_KEY),
            par: p.get(PAR_KEY),
            bandwidth: Bandwidth::from_params(p)?,
            policy: policy_param(p),
        })
    }
}

impl Optimiser for HarmonySearch {
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
        let widths: Vec<f64> = bounds.iter().map(|b| b.width()).collect();
        let mut bw = vec![0.0; bounds.len()];
        self.bandwidth.scale(0.0, &widths, &mut bw);
        let cols = BoundColumns::new(bounds);
        let imp = Improvisation {
            hmcr: self.hmcr,
            par: self.par,
            policy: self.policy,
        };
        let mut x = vec![0.0; bounds.len()];
        let mut words = [0; 2 * CHUNK];
        dispatch(
            #[inline(always)]
            |simd| {
                while eval.remaining() > 0 {
                    if self.bandwidth.decay {
                        self.bandwidth.scale(eval.progress(), &widths, &mut bw);
                    }
                    imp.improvise(&hm, &cols, &bw, rng, &mut words, &mut x, simd);
                    let v = eval.evaluate(&x);
                    hm.consider(&x, v);
                }
            },
        );
    }
}
