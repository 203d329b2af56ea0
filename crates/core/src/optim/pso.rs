//! Particle Swarm Optimisation, PSO (Kennedy & Eberhart 1995, "Particle
//! swarm optimization", Proc. IEEE ICNN 4:1942–1948), with the inertia
//! weight of Shi & Eberhart (1998, "A modified particle swarm optimizer",
//! Proc. IEEE ICEC, 69–73).

use super::params::{Kind, ParamDef, ParamSet, Setting};
use super::{clamp, max_x86, min_x86, policy_param, select, Optimiser, ParamError, BOUNDS_PARAM};
use crate::optim::evaluator::Evaluator;
use crate::optim::params::Param;
use crate::problem::{BoundPolicy, Bounds, Problem};
use crate::rng::Words;
use crate::simd::dispatch;

/// How the inertia weight `ω` evolves over the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Inertia {
    /// A constant `ω = w`.
    Constant,
    /// Linearly decreasing `ω(t) = w_max − (w_max − w_min)·t/NI`
    /// (Shi & Eberhart 1998).
    Linear,
}

impl Inertia {
    /// Spec names, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["constant", "linear"];

    fn from_name(name: &str) -> Self {
        if name == "constant" {
            Self::Constant
        } else {
            Self::Linear
        }
    }
}

/// Global-best PSO with inertia weight and velocity clamping.
///
/// Each particle moves by
/// `v_j ← ω v_j + c1 φ1_j (p_j − x_j) + c2 φ2_j (g_j − x_j)`, then
/// `v_j ← clamp(v_j, ±vmax·(U_j − L_j))` and `x_j ← x_j + v_j`, where `p` is
/// its personal best, `g` the swarm's best and `φ1_j, φ2_j ~ U(0,1)` are drawn
/// per dimension (Kennedy & Eberhart 1995; Shi & Eberhart 1998); for each
/// move all `φ1` are drawn first, then all `φ2`.
///
/// Design choices, all documented so that runs can be compared:
/// * initial positions are uniform in the bounds and initial velocities
///   uniform in `±vmax·(U_j − L_j)`; every initial position is evaluated;
/// * the swarm best is updated asynchronously, right after each particle's
///   evaluation, so later particles of the same sweep already follow it;
/// * a personal (and so the swarm) best changes only on strict improvement,
///   which breaks ties towards the earlier point and the lower index;
/// * bound handling follows the "absorbing" and "reflecting" walls of
///   Robinson & Rahmat-Samii (2004, "Particle swarm optimization in
///   electromagnetics", IEEE Trans. Antennas Propag. 52(2):397–407): with
///   `clip` a coordinate that left the box is set on the violated bound and its
///   velocity component is zeroed; with `reflect` it is mirrored back inside
///   and its velocity component is negated;
/// * `ω(t)` uses `t/NI`, the fraction of the evaluation budget used, and is
///   recomputed before each particle moves.
#[derive(Clone, Debug, PartialEq)]
pub struct ParticleSwarm {
    /// Swarm size.
    pub swarm: usize,
    /// Constant or linearly decreasing inertia.
    pub inertia: Inertia,
    /// The constant inertia weight `ω` of [`Inertia::Constant`].
    pub w: f64,
    /// The initial inertia weight of [`Inertia::Linear`].
    pub w_max: f64,
    /// The final inertia weight of [`Inertia::Linear`].
    pub w_min: f64,
    /// The cognitive ("self-confidence") coefficient `c1`, `C_PSO1`.
    pub c1: f64,
    /// The social ("swarm confidence") coefficient `c2`, `C_PSO2`.
    pub c2: f64,
    /// The velocity clamp as a fraction of each variable's range.
    pub vmax: f64,
    /// Bound handling (see the type's docs).
    pub policy: BoundPolicy,
}

/// The key of the `swarm` parameter.
pub const SWARM_KEY: Param<u64> = Param::new("swarm");
/// The key of the `inertia` parameter.
pub const INERTIA_KEY: Param<&'static str> = Param::new("inertia");
/// The key of the `w` parameter.
pub const W_KEY: Param<f64> = Param::new("w");
/// The key of the `w_max` parameter.
pub const W_MAX_KEY: Param<f64> = Param::new("w_max");
/// The key of the `w_min` parameter.
pub const W_MIN_KEY: Param<f64> = Param::new("w_min");
/// The key of the `c1` parameter.
pub const C1_KEY: Param<f64> = Param::new("c1");
/// The key of the `c2` parameter.
pub const C2_KEY: Param<f64> = Param::new("c2");
/// The key of the `vmax` parameter.
pub const VMAX_KEY: Param<f64> = Param::new("vmax");

/// The parameters of [`ParticleSwarm`]. The defaults are the classical
/// setting of Shi & Eberhart (1998): `ω` falling linearly from 0.9 to 0.4 with
/// `c1 = c2 = 2`. The default constant `w = 0.7298` is the
/// constriction-equivalent inertia of Clerc & Kennedy (2002, "The particle
/// swarm — explosion, stability, and convergence in a multidimensional
/// complex space", IEEE TEC 6(1):58–73), to be paired with
/// `c1 = c2 = 1.49618` when `inertia = "constant"`.
pub static PARAMS: [ParamDef; 9] = [
    ParamDef {
        name: SWARM_KEY.name,
        doc: "swarm size (number of particles)",
        kind: Kind::Count {
            min: 1,
            max: 100_000,
        },
        default: Setting::Count(30),
        omit_at_default: false,
    },
    ParamDef {
        name: INERTIA_KEY.name,
        doc: "\"constant\" ω = w, or \"linear\" ω(t) = w_max − (w_max − w_min)·t/NI",
        kind: Kind::Choice(&Inertia::NAMES),
        default: Setting::Choice("linear"),
        omit_at_default: false,
    },
    ParamDef {
        name: W_KEY.name,
        doc: "constant inertia weight ω (inertia = \"constant\")",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.7298),
        omit_at_default: false,
    },
    ParamDef {
        name: W_MAX_KEY.name,
        doc: "initial inertia weight (inertia = \"linear\")",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.9),
        omit_at_default: false,
    },
    ParamDef {
        name: W_MIN_KEY.name,
        doc: "final inertia weight (inertia = \"linear\"), at most w_max",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: false,
        },
        default: Setting::Real(0.4),
        omit_at_default: false,
    },
    ParamDef {
        name: C1_KEY.name,
        doc: "cognitive (self-confidence) coefficient c1, C_PSO1",
        kind: Kind::Real {
            min: 0.0,
            max: 4.0,
            open_min: false,
        },
        default: Setting::Real(2.0),
        omit_at_default: false,
    },
    ParamDef {
        name: C2_KEY.name,
        doc: "social (swarm-confidence) coefficient c2, C_PSO2",
        kind: Kind::Real {
            min: 0.0,
            max: 4.0,
            open_min: false,
        },
        default: Setting::Real(2.0),
        omit_at_default: false,
    },
    ParamDef {
        name: VMAX_KEY.name,
        doc: "velocity clamp vmax, as a fraction of each variable's range",
        kind: Kind::Real {
            min: 0.0,
            max: 1.0,
            open_min: true,
        },
        default: Setting::Real(0.2),
        omit_at_default: false,
    },
    BOUNDS_PARAM,
];

impl Default for ParticleSwarm {
    fn default() -> Self {
        Self::from_params(&ParamSet::defaults(&PARAMS)).expect("defaults are valid")
    }
}

impl ParticleSwarm {
    /// Builds PSO from validated parameters; with `inertia = "linear"`,
    /// `w_min ≤ w_max` is required.
    pub fn from_params(p: &ParamSet) -> Result<Self, ParamError> {
        let s = Self {
            swarm: p.get(SWARM_KEY) as usize,
            inertia: Inertia::from_name(p.get(INERTIA_KEY)),
            w: p.get(W_KEY),
            w_max: p.get(W_MAX_KEY),
            w_min: p.get(W_MIN_KEY),
            c1: p.get(C1_KEY),
            c2: p.get(C2_KEY),
            vmax: p.get(VMAX_KEY),
            policy: policy_param(p),
        };
        if s.inertia == Inertia::Linear && s.w_min > s.w_max {
            return Err(ParamError::new(
                "w_min",
                format!("w_min ({}) must not exceed w_max ({})", s.w_min, s.w_max),
            ));
        }
        Ok(s)
    }

    /// The inertia weight `ω` at progress `t/NI`.
    #[inline]
    pub fn inertia_at(&self, progress: f64) -> f64 {
        match self.inertia {
            Inertia::Constant => self.w,
            Inertia::Linear => self.w_max - (self.w_max - self.w_min) * progress,
        }
    }
}

impl Optimiser for ParticleSwarm {
    /// Positions, velocities and personal bests (3 × swarm × D) and a few
    /// D-vectors.
    fn state_bytes(&self, dim: usize, _budget: u64) -> u128 {
        super::vectors_bytes(3 * self.swarm + 4, dim)
    }

    fn minimise<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        dispatch(
            #[inline(always)]
            |_| self.fly(eval, rng),
        )
    }
}

impl ParticleSwarm {
    /// The swarm's moves until the budget is spent: the body of
    /// [`Optimiser::minimise`], compiled for the CPU by [`dispatch`].
    #[inline(always)]
    fn fly<P: Problem + ?Sized, R: Words + ?Sized>(
        &self,
        eval: &mut Evaluator<'_, P>,
        rng: &mut R,
    ) {
        let n = self.swarm.max(1);
        let bounds = eval.bounds();
        let dim = bounds.len();
        if dim == 0 {
            // Nothing to move: spend the budget on the only point there is.
            while eval.remaining() > 0 {
                eval.evaluate(&[]);
            }
            return;
        }
        let vmax: Vec<f64> = bounds.iter().map(|b| self.vmax * b.width()).collect();
        let mut x = vec![0.0; n * dim];
        let mut v = vec![0.0; n * dim];
        let mut pbest = vec![0.0; n * dim];
        let mut pval = vec![f64::INFINITY; n];
        let mut phis = vec![0.0; 2 * dim];
        let lower: Vec<f64> = bounds.iter().map(|b| b.lower).collect();
        let upper: Vec<f64> = bounds.iter().map(|b| b.upper).collect();

        if !scatter(eval, rng, &vmax, (&mut x, &mut v), (&mut pbest, &mut pval)) {
            return;
        }
        // The swarm best is the personal best of particle `g`.
        let mut g = (0..n).fold(0, |g, i| if pval[i] < pval[g] { i } else { g });

        let (c1, c2, policy) = (self.c1, self.c2, self.policy);
        let walls = Walls {
            bounds,
            lower: &lower,
            upper: &upper,
            vmax: &vmax,
        };
        loop {
            for i in 0..n {
                if eval.remaining() == 0 {
                    return;
                }
                let w = self.inertia_at(eval.progress());
                let row = i * dim..(i + 1) * dim;
                let xi = &mut x[row.clone()];
                let vi = &mut v[row.clone()];
                let pi = &pbest[row.clone()];
                let gi = &pbest[g * dim..(g + 1) * dim];
                // Draw all φ first, in a tight loop that keeps the generator
                // in registers, then move the particle in a branch-free loop.
                rng.units(&mut phis);
                let (phi1, phi2) = phis.split_at(dim);
                let pull = Pull {
                    w,
                    c1,
                    c2,
                    phi1,
                    phi2,
                };
                match policy {
                    BoundPolicy::Clip => move_clipped(&pull, &walls, xi, vi, pi, gi),
                    BoundPolicy::Reflect => move_reflected(&pull, &walls, xi, vi, pi, gi),
                }
                let f = eval.evaluate(xi);
                if f < pval[i] {
                    pval[i] = f;
                    pbest[row].copy_from_slice(&x[i * dim..(i + 1) * dim]);
                    if f < pval[g] {
                        g = i;
                    }
                }
            }
        }
    }
}

/// Scatters the swarm: each particle at a uniform point of the box with a
/// uniform velocity in `[−v_max, v_max]`, evaluated, its personal best
/// itself. Returns `false` if the budget ran out first.
#[inline(always)]
fn scatter<P: Problem + ?Sized, R: Words + ?Sized>(
    eval: &mut Evaluator<'_, P>,
    rng: &mut R,
    vmax: &[f64],
    (x, v): (&mut [f64], &mut [f64]),
    (pbest, pval): (&mut [f64], &mut [f64]),
) -> bool {
    let bounds = eval.bounds();
    let dim = bounds.len();
    let mut phis = vec![0.0; 2 * dim];
    for (i, ((xi, vi), pi)) in x
        .chunks_exact_mut(dim)
        .zip(v.chunks_exact_mut(dim))
        .zip(pbest.chunks_exact_mut(dim))
        .enumerate()
    {
        if eval.remaining() == 0 {
            return false;
        }
        rng.units(&mut phis);
        for ((((xj, vj), b), &vm), u) in xi
            .iter_mut()
            .zip(vi.iter_mut())
            .zip(bounds)
            .zip(vmax)
            .zip(phis.chunks_exact(2))
        {
            *xj = b.lerp(u[0]);
            *vj = -vm + u[1] * (vm + vm);
        }
        eval.place_start(xi);
        pval[i] = eval.evaluate(xi);
        pi.copy_from_slice(xi);
    }
    true
}

/// What pulls a particle in one move: the inertia `w`, the acceleration
/// coefficients `c₁`, `c₂` and the particle's uniform draws `φ₁`, `φ₂`.
struct Pull<'a> {
    w: f64,
    c1: f64,
    c2: f64,
    phi1: &'a [f64],
    phi2: &'a [f64],
}

/// The box a particle moves in, also as columns, and the velocity clamp.
struct Walls<'a> {
    bounds: &'a [Bounds],
    lower: &'a [f64],
    upper: &'a [f64],
    vmax: &'a [f64],
}

/// One move (Shi & Eberhart 1998) `v ← clamp(w v + c₁φ₁(p − x) + c₂φ₂(g − x), ±v_max)`,
/// `x ← x + v` (0 within [`POSITION_FLOOR`] of 0), clipped into the box, a
/// clipped coordinate's velocity zeroed; branch-free, so that it vectorises.
#[inline(always)]
fn move_clipped(
    pull: &Pull<'_>,
    walls: &Walls<'_>,
    xi: &mut [f64],
    vi: &mut [f64],
    pi: &[f64],
    gi: &[f64],
) {
    let dim = xi.len();
    let (xi, vi, pi, gi) = (&mut xi[..dim], &mut vi[..dim], &pi[..dim], &gi[..dim]);
    let (lo, hi, vm) = (&walls.lower[..dim], &walls.upper[..dim], &walls.vmax[..dim]);
    let (f1, f2) = (&pull.phi1[..dim], &pull.phi2[..dim]);
    let (w, c1, c2) = (pull.w, pull.c1, pull.c2);
    for j in 0..dim {
        let here = xi[j];
        let vel = min_x86(
            max_x86(
                w * vi[j] + c1 * f1[j] * (pi[j] - here) + c2 * f2[j] * (gi[j] - here),
                -vm[j],
            ),
            vm[j],
        );
        let pos = off_the_floor(here + vel);
        let inside = clamp(Bounds::new(lo[j], hi[j]), pos);
        vi[j] = if inside == pos { vel } else { 0.0 };
        xi[j] = inside;
    }
}

/// The positions closer to 0 than `2⁻⁵¹¹` (≈ 1.5·10⁻¹⁵⁴) are taken as 0:
/// the square of such a coordinate is subnormal, and a swarm converging on
/// an optimum at 0 (Sphere as published) would otherwise spend its last
/// evaluations in the objective's gradual underflow, where x86 cores take a
/// microcode assist per subnormal result (Sphere-30 at 10⁻¹⁶⁰ evaluated 4×
/// slower than at 1; `make overhead`'s long run showed PSO's last tenth at
/// 1.46× its first). No target or box is finer than this floor: it changes
/// a run only once its points come within 10⁻¹⁵⁴ of 0.
pub const POSITION_FLOOR: f64 = 1.491_668_146_240_041_3e-154;

/// `x`, or 0 when `|x| <` [`POSITION_FLOOR`]: a compare and a bit mask, so
/// that the move stays branch-free.
#[inline(always)]
fn off_the_floor(x: f64) -> f64 {
    select(x.abs() >= POSITION_FLOOR, x, 0.0)
}

/// The move of [`move_clipped`], a position outside the box reflected back
/// into it and its velocity reversed.
#[inline(always)]
fn move_reflected(
    pull: &Pull<'_>,
    walls: &Walls<'_>,
    xi: &mut [f64],
    vi: &mut [f64],
    pi: &[f64],
    gi: &[f64],
) {
    let (w, c1, c2) = (pull.w, pull.c1, pull.c2);
    for (((((((xj, vj), &pj), &gj), b), &vm), &f1), &f2) in xi
        .iter_mut()
        .zip(vi.iter_mut())
        .zip(pi)
        .zip(gi)
        .zip(walls.bounds)
        .zip(walls.vmax)
        .zip(pull.phi1)
        .zip(pull.phi2)
    {
        let here = *xj;
        let mut vel = (w * *vj + c1 * f1 * (pj - here) + c2 * f2 * (gj - here))
            .max(-vm)
            .min(vm);
        let mut pos = off_the_floor(here + vel);
        if !b.contains(pos) {
            pos = b.reflect(pos);
            vel = -vel;
        }
        *xj = pos;
        *vj = vel;
    }
}

#[cfg(test)]
mod tests {
    use crate::optim::bowl::{assert_solves_sphere_10, Bowl};

    use super::*;
    use crate::optim::params::Raw;
    use crate::rng::run_rng;

    fn build(settings: &[(&str, Raw)]) -> Result<ParticleSwarm, ParamError> {
        let mut p = ParamSet::defaults(&PARAMS);
        for (name, raw) in settings {
            p.set(name, raw).unwrap();
        }
        ParticleSwarm::from_params(&p)
    }

    /// The default PSO drives Sphere-10 below 1e-6 in 100 000 evaluations,
    /// for each of five seeds.
    #[test]
    fn solves_sphere_10() {
        assert_solves_sphere_10(&ParticleSwarm::default(), 100_000, 1e-6);
    }

    /// A swarm converging on Sphere's optimum at 0 reaches it exactly and
    /// never evaluates a coordinate within 2⁻⁵¹¹ of 0 (whose square would
    /// be subnormal), under either bound policy.
    #[test]
    fn keeps_its_points_off_the_subnormal_floor() {
        assert_eq!(POSITION_FLOOR, f64::MIN_POSITIVE.sqrt(), "2^-511");
        for bounds in ["clip", "reflect"] {
            let algo = build(&[("bounds", Raw::Text(bounds.into()))]).unwrap();
            let p = Bowl::sphere(5);
            let out = algo.run(&p, 400_000, &mut run_rng(3));
            assert_eq!(out.best_value, 0.0, "{bounds}");
            assert_eq!(p.tiny.get(), 0, "{bounds}: points within 2^-511 of 0");
        }
    }

    #[test]
    fn inertia_follows_the_schedule() {
        let pso = ParticleSwarm::default();
        assert_eq!(pso.inertia_at(0.0), 0.9);
        assert!((pso.inertia_at(0.5) - 0.65).abs() < 1e-15);
        assert!((pso.inertia_at(1.0) - 0.4).abs() < 1e-15);
        let constant = build(&[("inertia", Raw::Text("constant".into()))]).unwrap();
        assert_eq!(constant.inertia_at(0.7), 0.7298);
    }

    #[test]
    fn rejects_invalid_combinations() {
        let e = build(&[("w_max", Raw::Float(0.3))]).unwrap_err();
        assert_eq!(e.param, "w_min");
        assert!(build(&[
            ("w_max", Raw::Float(0.3)),
            ("inertia", Raw::Text("constant".into()))
        ])
        .is_ok());
        let mut p = ParamSet::defaults(&PARAMS);
        assert!(p.set("swarm", &Raw::Int(0)).is_err());
        assert!(p.set("vmax", &Raw::Float(0.0)).is_err());
        assert_eq!(ParticleSwarm::default().swarm, 30);
    }
}
