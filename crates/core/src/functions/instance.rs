//! Shifted and rotated instances of the benchmark functions, so that an
//! optimiser meets the optimum away from the centre of the box and in
//! coordinates that are not separable (the practice of the CEC and BBOB
//! suites: Suganthan et al. 2005, "Problem definitions and evaluation
//! criteria for the CEC 2005 special session", Nanyang Technological
//! University; Hansen et al. 2009, "Real-parameter black-box optimization
//! benchmarking 2009: noiseless functions definitions", INRIA RR-6829).
//!
//! Instance `k` of a function `f` at dimension `D` is
//! `F(x) = f(M_k (x − o_k) + x*)`, with `x*` the minimiser of `f`: it keeps
//! the minimum `f*` and moves the minimiser to `o_k`. The shift `o_k` is
//! uniform in ±80 % of the box around its centre; for
//! [`Transform::ShiftRotate`] the rotation `M_k` is Haar-distributed on the
//! orthogonal group (Mezzadri 2007, "How to generate random matrices from the
//! classical compact groups", Notices of the AMS 54(5):592–604): the Q factor,
//! with a positive diagonal of R, of a matrix of independent standard normal
//! variates. Both come from a stream seeded by the function, `D` and `k`
//! alone ([`instance_seed`]), so every algorithm, run and thread count meets
//! the same instances.

use std::fmt;

use super::panels::Panels;
use super::Function;
use crate::rng::{fnv1a64, run_rng, splitmix64, Draw};

/// How a benchmark function is moved away from its textbook position.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub enum Transform {
    /// The function as published (Yao, Liu & Lin 1999): one instance.
    #[default]
    None,
    /// `F(x) = f(x − o_k + x*)`: the optimum moves to `o_k`.
    Shift,
    /// `F(x) = f(M_k (x − o_k) + x*)`: shifted and rotated.
    ShiftRotate,
}

impl Transform {
    /// The names accepted in specs, in the order of the enum.
    pub const NAMES: [&'static str; 3] = ["none", "shift", "shift-rotate"];

    /// Parses a spec name.
    pub fn from_name(name: &str) -> Option<Transform> {
        match name {
            "none" => Some(Transform::None),
            "shift" => Some(Transform::Shift),
            "shift-rotate" => Some(Transform::ShiftRotate),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// What the transform does, for `metabezier list`.
    pub fn doc(self) -> &'static str {
        match self {
            Transform::None => "the function as published, optimum at its textbook place",
            Transform::Shift => {
                "F(x) = f(x − o_k + x*): optimum moved to o_k, uniform in ±80 % of the box"
            }
            Transform::ShiftRotate => {
                "F(x) = f(M_k(x − o_k) + x*): shifted and rotated by a Haar-random orthogonal M_k"
            }
        }
    }
}

impl fmt::Display for Transform {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The largest dimension a rotation is built for: `M_k` has `D²` entries
/// and costs `O(D³)` to draw.
pub const MAX_ROTATION_DIM: usize = 1000;

/// The seed of instance `k` of `function` at dimension `dim`: SplitMix64 of
/// the FNV-1a hash of `instance/<name>/<dim>/<k>`, independent of the spec,
/// the algorithm and the run.
pub fn instance_seed(function: Function, dim: usize, k: u32) -> u64 {
    splitmix64(fnv1a64(&format!("instance/{}/{dim}/{k}", function.name())))
}

/// One instance: the shift `o_k`, the rotation `M_k` (row-major `D × D`,
/// empty for a shift alone) and the function's minimiser `x*`.
#[derive(Clone, Debug, PartialEq)]
pub struct Instance {
    transform: Transform,
    index: u32,
    shift: Vec<f64>,
    rotation: Vec<f64>,
    /// `M_k` in panels of rows ([`Panels`]), which [`Instance::map_into`]
    /// runs through; empty without a rotation.
    panels: Panels,
    x_star: Vec<f64>,
}

impl Instance {
    /// Instance `k ≥ 1` of `function` at `dim` under `transform`
    /// (`Transform::None` is the identity). The caller has checked that the
    /// function admits transforms ([`Function::is_transformable`]) and, for
    /// a rotation, that `dim ≤ MAX_ROTATION_DIM`.
    pub fn new(function: Function, dim: usize, transform: Transform, k: u32) -> Instance {
        let mut rng = run_rng(instance_seed(function, dim, k));
        let bounds = function.domain();
        let (centre, half) = (
            0.5 * (bounds.lower + bounds.upper),
            0.5 * (bounds.upper - bounds.lower),
        );
        let (shift, rotation) = match transform {
            Transform::None => (vec![0.0; dim], Vec::new()),
            Transform::Shift | Transform::ShiftRotate => {
                let shift: Vec<f64> = (0..dim)
                    .map(|_| centre + (2.0 * rng.unit() - 1.0) * 0.8 * half)
                    .collect();
                let rotation = if transform == Transform::ShiftRotate {
                    haar_orthogonal(dim, &mut rng)
                } else {
                    Vec::new()
                };
                (shift, rotation)
            }
        };
        let panels = Panels::new(&rotation, dim);
        Instance {
            transform,
            index: k,
            shift,
            rotation,
            panels,
            x_star: function.optimum_location(dim),
        }
    }

    /// The transform.
    pub fn transform(&self) -> Transform {
        self.transform
    }

    /// The instance number `k` (from 1).
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The shift `o_k`: the minimiser of the instance.
    pub fn shift(&self) -> &[f64] {
        &self.shift
    }

    /// The rotation `M_k`, row-major, if the instance is rotated.
    pub fn rotation(&self) -> Option<&[f64]> {
        (!self.rotation.is_empty()).then_some(&self.rotation[..])
    }

    /// Maps `x` to the argument of the untransformed function,
    /// `y = M(x − o) + x*` (or `x − o + x*` without a rotation), into `y`;
    /// with a rotation `scratch` (at least D long; unused otherwise) holds
    /// `x − o`, computed once rather than once per row. Each sum
    /// `Σ_j M_ij (x_j − o_j)` runs left to right, `j = 0, 1, …`; the sums
    /// advance together in panels of rows held in registers (panels of `M`:
    /// the same bits as one row after the other).
    #[inline]
    pub fn map_into(&self, x: &[f64], scratch: &mut [f64], y: &mut [f64]) {
        let d = self.shift.len();
        let (x, o, star) = (&x[..d], &self.shift[..], &self.x_star[..d]);
        if self.panels.is_empty() {
            for (((yi, xi), oi), si) in y.iter_mut().zip(x).zip(o).zip(star) {
                *yi = (xi - oi) + si;
            }
        } else {
            let diff = &mut scratch[..d];
            for ((dj, xj), oj) in diff.iter_mut().zip(x).zip(o) {
                *dj = xj - oj;
            }
            let y = &mut y[..d];
            self.panels.apply(diff, y);
            for (yi, si) in y.iter_mut().zip(star) {
                *yi += si;
            }
        }
    }
}

/// A Haar-distributed orthogonal `d × d` matrix (row-major): the Q factor of
/// a matrix of standard normal variates with a positive diagonal of R
/// (Mezzadri 2007), computed by Gram–Schmidt run twice on every column
/// ("twice is enough": Giraud, Langou & Rozložník 2005, Comput. Math. Appl.
/// 50:1069–1075), so the columns are orthonormal to rounding.
fn haar_orthogonal<R: Draw + ?Sized>(d: usize, rng: &mut R) -> Vec<f64> {
    // Columns of the Gaussian matrix, drawn row by row.
    let mut g = vec![0.0; d * d];
    for v in g.iter_mut() {
        *v = rng.gaussian();
    }
    let mut cols: Vec<Vec<f64>> = (0..d)
        .map(|j| (0..d).map(|i| g[i * d + j]).collect())
        .collect();
    for j in 0..d {
        for _pass in 0..2 {
            for k in 0..j {
                let (done, rest) = cols.split_at_mut(j);
                let (qk, cj) = (&done[k], &mut rest[0]);
                let dot: f64 = qk.iter().zip(cj.iter()).map(|(a, b)| a * b).sum();
                for (c, q) in cj.iter_mut().zip(qk) {
                    *c -= dot * q;
                }
            }
        }
        // The norm is R_jj > 0, so Q needs no sign correction.
        let norm = cols[j].iter().map(|v| v * v).sum::<f64>().sqrt();
        for v in cols[j].iter_mut() {
            *v /= norm;
        }
    }
    let mut q = vec![0.0; d * d];
    for (j, col) in cols.iter().enumerate() {
        for i in 0..d {
            q[i * d + j] = col[i];
        }
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::{with_level, Simd};

    #[test]
    fn rotations_are_orthogonal() {
        for d in [1, 2, 10, 30, 100] {
            let inst = Instance::new(Function::Sphere, d, Transform::ShiftRotate, 3);
            let m = inst.rotation().unwrap();
            for a in 0..d {
                for b in 0..d {
                    let dot: f64 = (0..d).map(|i| m[i * d + a] * m[i * d + b]).sum();
                    let want = if a == b { 1.0 } else { 0.0 };
                    assert!((dot - want).abs() < 1e-12, "d {d}: ({a},{b}) {dot}");
                }
            }
        }
    }

    #[test]
    fn shifts_stay_in_eighty_percent_of_the_box_and_depend_on_the_instance() {
        let a = Instance::new(Function::Rastrigin, 30, Transform::Shift, 1);
        let b = Instance::new(Function::Rastrigin, 30, Transform::ShiftRotate, 1);
        let c = Instance::new(Function::Rastrigin, 30, Transform::Shift, 2);
        assert_eq!(a.shift(), b.shift(), "the rotation adds to the same shift");
        assert_ne!(a.shift(), c.shift());
        assert!(a.shift().iter().all(|o| o.abs() <= 0.8 * 5.12));
        assert!(a.rotation().is_none() && b.rotation().is_some());
        assert_eq!(
            a,
            Instance::new(Function::Rastrigin, 30, Transform::Shift, 1)
        );
    }

    /// The column-order map gives the bits of the sums row after row,
    /// `y_i = ((0 + M_i0 d_0) + M_i1 d_1) + … + x*_i`, on awkward values.
    #[test]
    fn map_is_the_row_by_row_sum_bit_for_bit() {
        // Every panel height (8, 16, 32), one and several panels, a padded
        // last panel, on every vector level this CPU runs.
        for (f, d) in [
            (Function::Rosenbrock, 1),
            (Function::Rastrigin, 7),
            (Function::Sphere, 8),
            (Function::Griewank, 9),
            (Function::Sphere, 16),
            (Function::Step, 17),
            (Function::Ackley, 30),
            (Function::Sphere, 32),
            (Function::Schwefel12, 33),
            (Function::Rastrigin, 100),
        ] {
            let inst = Instance::new(f, d, Transform::ShiftRotate, 2);
            let m = inst.rotation().unwrap();
            let x: Vec<f64> = (0..d)
                .map(|j| (j as f64 * 0.7311).sin() * 3.3e-3 + 1.0 / 3.0)
                .collect();
            let star = f.optimum_location(d);
            let want: Vec<f64> = (0..d)
                .map(|i| {
                    let mut s = 0.0;
                    for j in 0..d {
                        s += m[i * d + j] * (x[j] - inst.shift()[j]);
                    }
                    s + star[i]
                })
                .collect();
            let bits = |v: &[f64]| v.iter().map(|a| a.to_bits()).collect::<Vec<_>>();
            for level in [Simd::Portable, Simd::Avx2, Simd::Avx512] {
                let mut scratch = vec![0.0; d];
                let mut y = vec![f64::NAN; d];
                with_level(level, || inst.map_into(&x, &mut scratch, &mut y));
                assert_eq!(bits(&y), bits(&want), "{f:?}-{d} at {level:?}");
            }
        }
    }

    #[test]
    fn names_round_trip() {
        for name in Transform::NAMES {
            assert_eq!(Transform::from_name(name).unwrap().name(), name);
        }
        assert_eq!(Transform::from_name("rotate"), None);
    }
}
