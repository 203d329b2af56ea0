//! One segment's fitting problem: the decision variables, their box and the
//! objective `E = Σᵢ |Rᵢ − P(sᵢ)|²`, at fixed `sᵢ` or at each candidate's
//! foot points ([`ErrorMeasure`]).
//!
//! The problem knows nothing of the algorithm that solves it (argmin's split):
//! it implements [`Problem`] for the metaheuristics and [`LeastSquares`] for
//! Levenberg–Marquardt.

mod joins;
mod layout;
mod least_squares;
#[cfg(test)]
mod tests;

pub use joins::{tangent_meet, End, Start};
use layout::{C1Var, Layout};

use super::controls::{cubic, quad, rcubic, rquad, sum_sq, Controls};
use super::search_space::{guesses, point_box};
use super::{ErrorMeasure, FitError, FunctionType, SearchSpaceOptions, Segment};
use crate::geometry::{bounding_box, Curve, Parameterisation, Point};
use crate::problem::{Bounds, Problem};

/// The segment fitting problem of the thesis: data points `R₀..R_n` with
/// parameters `s₀ = 0 < … < s_n = 1`, end control points fixed at `R₀` and
/// `R_n`, and the objective `E(x) = Σᵢ |Rᵢ − P(sᵢ)|²`; with
/// [`SegmentProblem::with_error`]`(`[`ErrorMeasure::Orthogonal`]`)` the
/// `sᵢ` of each candidate are its foot points, found from the stored ones.
///
/// **Decision vector** (in this order; `m` the degree):
///
/// | start | `C₁` part | then |
/// |---|---|---|
/// | [`Start::Free`] (first segment, C⁰) | `C₁.x, C₁.y` | |
/// | [`Start::C1`] | none (`C₁` derived) | |
/// | [`Start::G1`] | `T` (its range: [`SearchSpaceOptions::scale_t_range`]) | |
/// | | | cubics: `C₂.x, C₂.y`; rationals: `w₁` (`h₁`), rational cubic: `w₂` |
///
/// so the dimensions are, for Free / C¹ / G¹: quadratic 2 / 0 / 1, rational
/// quadratic 3 / 1 / 2, cubic 4 / 2 / 3, rational cubic 6 / 4 / 5. A
/// quadratic with a C¹ join is fully determined (dimension 0).
///
/// **Evaluation.** The objective and the residuals evaluate the curve with
/// the explicit Bernstein form of the fixed degree (no allocation, no de
/// Casteljau), so one evaluation of `E` costs about as much as evaluating
/// the curve at the `n + 1` parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentProblem {
    function: FunctionType,
    start: Start,
    end: End,
    points: Vec<Point>,
    params: Vec<f64>,
    layout: Layout,
    bounds: Vec<Bounds>,
    guess: Vec<f64>,
    search: SearchSpaceOptions,
    error: ErrorMeasure,
}

impl SegmentProblem {
    /// The problem of fitting `function` to `points` at the local parameters
    /// `params` (same length, `s₀ = 0`, `s_n = 1` expected), starting as
    /// `start` says, with the search box of `search`.
    ///
    /// Fails if the options are invalid, the lengths differ, a point is not
    /// finite or there are fewer than [`FunctionType::min_points`] points.
    pub fn new(
        function: FunctionType,
        points: Vec<Point>,
        params: Vec<f64>,
        start: Start,
        search: &SearchSpaceOptions,
    ) -> Result<SegmentProblem, FitError> {
        search.validate()?;
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(FitError::NonFinitePoint { index });
        }
        let needed = function.min_points();
        if points.len() < needed {
            return Err(FitError::TooFewPoints {
                segment: 0,
                first: 0,
                last: points.len().saturating_sub(1),
                found: points.len(),
                needed,
                function,
            });
        }
        if params.len() != points.len() {
            return Err(FitError::DimensionMismatch {
                expected: points.len(),
                found: params.len(),
            });
        }
        let layout = Layout::new(function, start, End::Free, None);
        let mut problem = SegmentProblem {
            function,
            start,
            end: End::Free,
            points,
            params,
            layout,
            bounds: Vec::new(),
            guess: Vec::new(),
            search: *search,
            error: ErrorMeasure::Fixed,
        };
        problem.build_search_space();
        Ok(problem)
    }

    /// As [`SegmentProblem::new`], with the parameters of `points` computed
    /// by `parameterisation` (on the segment's own points, which equals
    /// `sᵢ = (tᵢ − t_a)/(t_b − t_a)` of the whole outline's parameters).
    pub fn with_parameterisation(
        function: FunctionType,
        points: Vec<Point>,
        parameterisation: Parameterisation,
        start: Start,
        search: &SearchSpaceOptions,
    ) -> Result<SegmentProblem, FitError> {
        let params = parameterisation.params(&points);
        SegmentProblem::new(function, points, params, start, search)
    }

    /// The same problem with the end joined as `end` says (see [`End`]): for
    /// a cubic `C₂` becomes `C₃ − T_end·dir` (G¹, one variable `T_end`
    /// instead of two) or `C₃ − D/(3w₂)` (C¹, none); for a quadratic with a
    /// free start `C₁` comes from the end instead; for a quadratic joined G¹
    /// at both ends `C₁` is where the two tangent lines meet (no variable
    /// left but `h₁`). The box and the guess are rebuilt; `T_end` gets the
    /// same range as the start's `T`.
    ///
    /// Fails ([`FitError::InvalidOption`] named `"end"`) for a quadratic
    /// joined C¹ at one end and at the other (its only inner control point
    /// cannot satisfy both), for a quadratic joined G¹ at both ends whose
    /// tangent lines do not meet in front of both ends, or for a zero or
    /// non-finite end direction.
    pub fn with_end(mut self, end: End) -> Result<SegmentProblem, FitError> {
        if let Some(d) = end.tangent() {
            if !(d.is_finite() && d.hypot() > 0.0) {
                return Err(FitError::InvalidOption {
                    name: "end",
                    value: d.hypot(),
                    expected: "a finite, non-zero end tangent",
                });
            }
        }
        let mut meet = None;
        if self.function.degree() == 2 && end != End::Free {
            let (c0, cn) = (self.points[0], self.points[self.points.len() - 1]);
            match (self.start, end) {
                (Start::Free, _) => {}
                (Start::G1 { leg }, End::G1 { dir }) => {
                    meet = Some(
                        tangent_meet(c0, leg, cn, dir).ok_or(FitError::InvalidOption {
                            name: "end",
                            value: leg.cross(dir),
                            expected: "tangent lines that meet in front of both ends \
                                       (a quadratic joined G1 at both ends)",
                        })?,
                    );
                }
                _ => {
                    return Err(FitError::InvalidOption {
                        name: "end",
                        value: 2.0,
                        expected: "a free start, or G1 at both ends, for a quadratic \
                                   joined at its end (C₁ is shared)",
                    })
                }
            }
        }
        self.end = end;
        self.layout = Layout::new(self.function, self.start, end, meet);
        self.build_search_space();
        Ok(self)
    }

    /// How the segment ends.
    pub fn end(&self) -> End {
        self.end
    }

    /// The same problem measuring `E` as `error` says: at the fixed data
    /// parameters (the thesis's E) or orthogonally, each candidate's
    /// parameters being the foot points of the data on its curve, found from
    /// the stored parameters (see [`ErrorMeasure::Orthogonal`]). The box and
    /// the guess do not change.
    pub fn with_error(mut self, error: ErrorMeasure) -> SegmentProblem {
        self.error = error;
        self
    }

    /// What `E` measures.
    pub fn error(&self) -> ErrorMeasure {
        self.error
    }

    /// The box a local solver (Levenberg–Marquardt) searches: the search
    /// box under [`ErrorMeasure::Fixed`] (the thesis's method), and under
    /// [`ErrorMeasure::Orthogonal`] the search box with every free control
    /// point coordinate widened to `10³` times the data's extent about the
    /// box's centre, so that a curve of the family whose control points lie
    /// outside the thesis's box (a wide conic arc) is reached. The weights
    /// keep `weight_range` and the G¹ ratios `T` their range: a leg shrunk
    /// towards zero would make a G¹ joint a cusp in all but name (which the
    /// orthogonal error, hugging a pixel staircase, would otherwise reach).
    /// It contains the search box.
    pub fn local_bounds(&self) -> Vec<Bounds> {
        if self.error == ErrorMeasure::Fixed {
            return self.bounds.clone();
        }
        let n = self.points.len() - 1;
        let (lo, hi) = bounding_box(&self.points).expect("segment data are never empty");
        let extent = (hi - lo)
            .hypot()
            .max(self.points[0].distance(self.points[n]));
        let reach = 1e3 * if extent > 0.0 { extent } else { 1.0 };
        let mut out = self.bounds.clone();
        for var in [Some(self.layout.c1), self.layout.c2].into_iter().flatten() {
            if let C1Var::Free(i) = var {
                for b in &mut out[i..i + 2] {
                    let c = 0.5 * (b.lower + b.upper);
                    *b = Bounds::new(c - reach, c + reach);
                }
            }
        }
        out
    }

    /// The parameters at which `E(x)` is measured: the stored `sᵢ` for
    /// [`ErrorMeasure::Fixed`], the foot points of the data on the curve of
    /// `x` for [`ErrorMeasure::Orthogonal`] (the ends stay at 0 and 1).
    pub fn measured_params(&self, x: &[f64]) -> Vec<f64> {
        if self.error == ErrorMeasure::Fixed {
            return self.params.clone();
        }
        let k = self.controls(x);
        (0..self.params.len())
            .map(|i| self.measured(&k, i).0)
            .collect()
    }

    /// `(sᵢ, P(sᵢ), P′(sᵢ))` of data point `i` under the error measure: the
    /// stored parameter, or the foot point (ends fixed).
    #[inline(always)]
    fn measured(&self, k: &Controls, i: usize) -> (f64, Point, Point) {
        let s = self.params[i];
        let m = self.function.degree();
        if i == 0 || i + 1 == self.params.len() {
            let (p, d1, _) = k.eval_d2(m, s);
            (s, p, d1)
        } else {
            k.foot(m, self.points[i], s)
        }
    }

    /// The same problem with new parameters (same box); used by parameter
    /// correction.
    pub fn with_params(&self, params: Vec<f64>) -> Result<SegmentProblem, FitError> {
        if params.len() != self.points.len() {
            return Err(FitError::DimensionMismatch {
                expected: self.points.len(),
                found: params.len(),
            });
        }
        Ok(SegmentProblem {
            params,
            ..self.clone()
        })
    }

    /// Computes the box and the centre guess from the search options.
    fn build_search_space(&mut self) {
        let g = guesses(
            self.function,
            &self.points,
            &self.params,
            self.start.tangent(),
            &self.search,
        );
        let dim = self.layout.dim;
        let mut bounds = vec![Bounds::new(0.0, 0.0); dim];
        let mut guess = vec![0.0; dim];
        let c0 = self.points[0];
        let cn = self.points[self.points.len() - 1];
        let chord = c0.distance(cn);
        let degree = self.function.degree() as f64;
        let (search, points) = (&self.search, &self.points);
        // Fills the box and guess of one inner control point guessed at `a`.
        let set = |bounds: &mut [Bounds], guess: &mut [f64], var: C1Var, a: Point| {
            let ratio =
                |bounds: &mut [Bounds], guess: &mut [f64], i: usize, from: Point, dir: Point| {
                    let (lo, hi) = search.t_range;
                    let rho = chord / degree / dir.hypot();
                    let rho = if search.scale_t_range && rho.is_finite() && rho > 0.0 {
                        rho
                    } else {
                        1.0
                    };
                    bounds[i] = Bounds::new(lo * rho, hi * rho);
                    let l2 = dir.hypot2();
                    let t = if l2 > 0.0 {
                        (a - from).dot(dir) / l2
                    } else {
                        1.0
                    };
                    guess[i] = bounds[i].clip(t);
                };
            match var {
                C1Var::Free(i) => {
                    let b = point_box(a, points, search);
                    bounds[i] = Bounds::new(b.lower.x, b.upper.x);
                    bounds[i + 1] = Bounds::new(b.lower.y, b.upper.y);
                    guess[i] = bounds[i].clip(a.x);
                    guess[i + 1] = bounds[i + 1].clip(a.y);
                }
                C1Var::Derived(_) | C1Var::EndDerived(_) | C1Var::Fixed(_) => {}
                C1Var::Ratio(i, leg) => ratio(bounds, guess, i, c0, leg),
                // C_{m−1} = C_m − T·dir: T = (C_m − A)·dir/|dir|².
                C1Var::EndRatio(i, dir) => ratio(bounds, guess, i, cn, -dir),
            }
        };
        set(&mut bounds, &mut guess, self.layout.c1, g.a1);
        if let (Some(var), Some(a2)) = (self.layout.c2, g.a2) {
            set(&mut bounds, &mut guess, var, a2);
        }
        let (wlo, whi) = self.search.weight_range;
        for i in [self.layout.w1, self.layout.w2].into_iter().flatten() {
            bounds[i] = Bounds::new(wlo, whi);
            guess[i] = bounds[i].clip(1.0);
        }
        self.bounds = bounds;
        self.guess = guess;
    }

    /// The function fitted.
    pub fn function(&self) -> FunctionType {
        self.function
    }

    /// How the segment starts.
    pub fn start(&self) -> Start {
        self.start
    }

    /// The data points `R₀..R_n`.
    pub fn points(&self) -> &[Point] {
        &self.points
    }

    /// The parameters `s₀..s_n`.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The search options the box was built with.
    pub fn search(&self) -> &SearchSpaceOptions {
        &self.search
    }

    /// The centre of the search space as a decision vector: the first guesses
    /// `A₁′, A₂′` (or the `T` that best matches `A₁′`) and unit weights, all
    /// clipped into the box.
    pub fn guess(&self) -> &[f64] {
        &self.guess
    }

    /// The name of each decision variable (`"C1.x"`, `"T"`, `"w2"`, …).
    pub fn variable_names(&self) -> Vec<&'static str> {
        let mut names = vec![""; self.layout.dim];
        match self.layout.c1 {
            C1Var::Free(i) => {
                names[i] = "C1.x";
                names[i + 1] = "C1.y";
            }
            C1Var::Derived(_) | C1Var::EndDerived(_) | C1Var::Fixed(_) => {}
            C1Var::Ratio(i, _) => names[i] = "T",
            C1Var::EndRatio(i, _) => names[i] = "T_end",
        }
        match self.layout.c2 {
            Some(C1Var::Free(i)) => {
                names[i] = "C2.x";
                names[i + 1] = "C2.y";
            }
            Some(C1Var::EndRatio(i, _)) => names[i] = "T_end",
            _ => {}
        }
        if let Some(i) = self.layout.w1 {
            names[i] = if self.function.degree() == 2 {
                "h1"
            } else {
                "w1"
            };
        }
        if let Some(i) = self.layout.w2 {
            names[i] = "w2";
        }
        names
    }

    /// Whether `x` is a weight (`w₁`, `w₂`, `h₁`) position; the rest enter
    /// the curve linearly once the weights are fixed.
    pub fn is_weight(&self, index: usize) -> bool {
        self.layout.w1 == Some(index) || self.layout.w2 == Some(index)
    }

    #[inline]
    fn controls(&self, x: &[f64]) -> Controls {
        debug_assert_eq!(x.len(), self.layout.dim);
        let n = self.points.len() - 1;
        let c0 = self.points[0];
        let cn = self.points[n];
        let m = self.function.degree();
        let w1 = self.layout.w1.map_or(1.0, |i| x[i]);
        let w2 = self.layout.w2.map_or(1.0, |i| x[i]);
        // `w` is the weight of the control point being derived.
        let inner = |var: C1Var, w: f64| match var {
            C1Var::Free(i) => Point::new(x[i], x[i + 1]),
            C1Var::Derived(d) => c0 + d / (m as f64 * w),
            C1Var::Ratio(i, leg) => c0 + leg * x[i],
            C1Var::EndDerived(d) => cn - d / (m as f64 * w),
            C1Var::EndRatio(i, dir) => cn - dir * x[i],
            C1Var::Fixed(p) => p,
        };
        let c1 = inner(self.layout.c1, w1);
        let c = if m == 3 {
            let var = self.layout.c2.expect("cubic layouts have C2");
            [c0, c1, inner(var, w2), cn]
        } else {
            [c0, c1, cn, Point::ZERO]
        };
        Controls { c, w1, w2 }
    }

    /// The fitted geometry for the decision vector `x`, clipped into the
    /// local box first ([`SegmentProblem::local_bounds`], which contains the
    /// search box; so the weights are positive). Panics if `x.len() != dim`.
    pub fn segment(&self, x: &[f64]) -> Segment {
        assert_eq!(x.len(), self.layout.dim, "decision vector length");
        let clipped: Vec<f64> = x
            .iter()
            .zip(&self.local_bounds())
            .map(|(&v, b)| b.clip(v))
            .collect();
        self.controls(&clipped)
            .segment(self.function)
            .expect("weights clipped into a positive range and finite points")
    }

    /// One Newton step of every interior parameter towards the foot of its
    /// data point on `curve`: `s ← s − g/g′` with `g = (Q(s) − R)·Q′(s)`,
    /// `g′ = |Q′|² + (Q − R)·Q″` (Schneider 1990, "NewtonRaphsonRootFind"),
    /// clamped to `[0, 1]`; a step with `g′ ≤ 0` is skipped. The ends stay
    /// at 0 and 1.
    pub fn corrected_params<C: Curve + ?Sized>(&self, curve: &C) -> Vec<f64> {
        let n = self.params.len() - 1;
        let mut out = self.params.clone();
        for (i, o) in out.iter_mut().enumerate().take(n).skip(1) {
            let (r, s) = (self.points[i], self.params[i]);
            let q = curve.eval(s);
            let d1 = curve.deriv(s);
            let d2 = curve.deriv2(s);
            let g = (q - r).dot(d1);
            let gp = d1.hypot2() + (q - r).dot(d2);
            if gp > 0.0 && gp.is_finite() {
                let next = s - g / gp;
                if next.is_finite() {
                    *o = next.clamp(0.0, 1.0);
                }
            }
        }
        out
    }
}

impl Problem for SegmentProblem {
    fn dim(&self) -> usize {
        self.layout.dim
    }

    fn bounds(&self) -> &[Bounds] {
        &self.bounds
    }

    /// `E(x) = Σᵢ |Rᵢ − P(sᵢ)|²`, allocation-free; under
    /// [`ErrorMeasure::Orthogonal`] at the foot points, `Σᵢ min_s |Rᵢ − P(s)|²`
    /// (one foot-point projection per point: several curve evaluations,
    /// still counted as one evaluation of `E`).
    fn objective(&self, x: &[f64]) -> f64 {
        let k = self.controls(x);
        if self.error == ErrorMeasure::Orthogonal {
            return (0..self.points.len())
                .map(|i| self.measured(&k, i).1.distance_squared(self.points[i]))
                .sum();
        }
        let (pts, ps) = (&self.points[..], &self.params[..]);
        match self.function {
            FunctionType::Quadratic => sum_sq(pts, ps, |s| quad(&k, s)),
            FunctionType::Cubic => sum_sq(pts, ps, |s| cubic(&k, s)),
            FunctionType::RationalQuadratic => sum_sq(pts, ps, |s| rquad(&k, s)),
            FunctionType::RationalCubic => sum_sq(pts, ps, |s| rcubic(&k, s)),
        }
    }
}
