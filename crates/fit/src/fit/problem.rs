//! One segment's fitting problem: the decision variables, their box and the
//! objective `E = Σᵢ |Rᵢ − P(sᵢ)|²`, at fixed `sᵢ` or at each candidate's
//! foot points ([`ErrorMeasure`]).
//!
//! The problem knows nothing of the algorithm that solves it (argmin's split):
//! it implements [`Problem`] for the metaheuristics and [`LeastSquares`] for
//! Levenberg–Marquardt.

use super::controls::{cubic, quad, rcubic, rquad, sum_sq, Controls};
use super::search_space::{guesses, point_box};
use super::{ErrorMeasure, FitError, FunctionType, SearchSpaceOptions, Segment};
use crate::geometry::{bounding_box, Continuity, Curve, Parameterisation, Point, SegmentEnd};
use crate::optim::lm::LeastSquares;
use crate::problem::{Bounds, Problem};

/// How a segment starts: its start point `C′₀` is always the first data
/// point; the join with the previous segment decides `C′₁`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Start {
    /// The first segment of an open outline, or a C⁰ join: `C′₁` is free.
    Free,
    /// A C¹ join after a segment with end derivative `D = Q′(1)`:
    /// `C′₁ = C′₀ + D/(m w′₁)` (`w′₁ = 1` for polynomial segments), i.e.
    /// `C′₁ = C₃ + (w₂w′₀)/(w₃w′₁)(C₃ − C₂)` for rational cubics and
    /// `C′₁ = C₂ + (h₁/h′₁)(C₂ − C₁)` for rational quadratics in standard
    /// form (Farin 2002, eq. 13.10).
    C1 {
        /// The previous segment's end derivative `Q′(1)`.
        derivative: Point,
    },
    /// A G¹ join after a segment whose last control leg is
    /// `L = C_m − C_{m−1}`: `C′₁ = C′₀ + T·L` with a free `T > 0`
    /// (Farin 2002, §10.2; the thesis's "T: parameter to locate new
    /// position of CP1").
    G1 {
        /// The previous segment's last leg `C_m − C_{m−1}`.
        leg: Point,
    },
}

impl Start {
    /// The start of a segment that follows `previous` with `continuity`.
    pub fn after<L: SegmentEnd + ?Sized>(previous: &L, continuity: Continuity) -> Start {
        match continuity {
            Continuity::C0 => Start::Free,
            Continuity::C1 => Start::C1 {
                derivative: previous.end_derivative(),
            },
            Continuity::G1 => {
                let (a, b) = previous.end_leg();
                Start::G1 { leg: b - a }
            }
        }
    }

    /// The start tangent direction this join imposes, if any.
    pub fn tangent(self) -> Option<Point> {
        match self {
            Start::Free => None,
            Start::C1 { derivative } => Some(derivative),
            Start::G1 { leg } => Some(leg),
        }
    }
}

/// How a segment ends: its end point `C_m` is always the last data point;
/// an optional join with a known curve *after* it decides `C_{m−1}`.
///
/// Used when a segment must fit between two fixed neighbours, as the
/// cranial-implant outer wall does between the intact contour at A and at B
/// (thesis chapter 6). The formulas mirror [`Start`] (Farin 2002, §10.2 and
/// eq. 13.10, read from the end): the end derivative of a (rational) Bézier
/// segment of degree `m` in standard form is `Q′(1) = m (w_{m−1}/w_m)(C_m − C_{m−1})`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum End {
    /// No constraint: `C_{m−1}` is free (or set by [`Start`] for a quadratic).
    #[default]
    Free,
    /// A C¹ join before a curve with start derivative `D`:
    /// `C_{m−1} = C_m − D/(m w_{m−1})` (`w_{m−1} = 1` for polynomial segments).
    C1 {
        /// The next curve's start derivative `Q′(0)`.
        derivative: Point,
    },
    /// A G¹ join before a curve whose start tangent (direction of travel) is
    /// `dir`: `C_{m−1} = C_m − T_end·dir` with a free `T_end > 0`.
    G1 {
        /// The next curve's start tangent direction (need not be unit).
        dir: Point,
    },
}

impl End {
    /// The end tangent direction (direction of travel) this join imposes.
    pub fn tangent(self) -> Option<Point> {
        match self {
            End::Free => None,
            End::C1 { derivative } => Some(derivative),
            End::G1 { dir } => Some(dir),
        }
    }
}

/// How an inner control point (`C₁`, or `C_{m−1}` for an end join) is
/// obtained from the decision vector.
#[derive(Clone, Copy, Debug, PartialEq)]
enum C1Var {
    /// `C_k = (x[i], x[i+1])`.
    Free(usize),
    /// `C₁ = C₀ + D/(m w₁)` (C¹ join).
    Derived(Point),
    /// `C₁ = C₀ + x[i]·L` (G¹ join).
    Ratio(usize, Point),
    /// `C_{m−1} = C_m − D/(m w_{m−1})` (C¹ join at the end).
    EndDerived(Point),
    /// `C_{m−1} = C_m − x[i]·dir` (G¹ join at the end).
    EndRatio(usize, Point),
    /// A fixed point: the inner control point of a quadratic joined G¹ at
    /// both ends, where the two tangent lines meet.
    Fixed(Point),
}

/// Where each quantity sits in the decision vector.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Layout {
    c1: C1Var,
    c2: Option<C1Var>,
    w1: Option<usize>,
    w2: Option<usize>,
    dim: usize,
}

impl Layout {
    /// The layout; a quadratic with an end join must start [`Start::Free`],
    /// and its `C₁` then comes from the end, or [`Start::G1`] with a G¹ end,
    /// and its `C₁` is then `meet`, where the two tangent lines cross
    /// (checked by the caller).
    fn new(function: FunctionType, start: Start, end: End, meet: Option<Point>) -> Layout {
        let mut dim = 0;
        let mut take = |k: usize| {
            let i = dim;
            dim += k;
            i
        };
        let end_var = |take: &mut dyn FnMut(usize) -> usize| match end {
            End::Free => C1Var::Free(take(2)),
            End::C1 { derivative } => C1Var::EndDerived(derivative),
            End::G1 { dir } => C1Var::EndRatio(take(1), dir),
        };
        let c1 = match (start, meet) {
            (_, Some(p)) => C1Var::Fixed(p),
            (start, None) => match start {
                Start::Free if function.degree() == 2 => end_var(&mut take),
                Start::Free => C1Var::Free(take(2)),
                Start::C1 { derivative } => C1Var::Derived(derivative),
                Start::G1 { leg } => C1Var::Ratio(take(1), leg),
            },
        };
        let c2 = (function.degree() == 3).then(|| end_var(&mut take));
        let w1 = function.is_rational().then(|| take(1));
        let w2 = (function == FunctionType::RationalCubic).then(|| take(1));
        Layout {
            c1,
            c2,
            w1,
            w2,
            dim,
        }
    }
}

/// Where the start tangent line `C₀ + t·leg` meets the end tangent line
/// `C_m − u·dir`, if it does so in front of both ends (`t, u > 0`): the
/// inner control point of a quadratic joined G¹ at both ends (Farin 2002,
/// §10.2). `None` for (nearly) parallel lines.
pub fn tangent_meet(c0: Point, leg: Point, cn: Point, dir: Point) -> Option<Point> {
    let det = leg.cross(dir);
    let d = cn - c0;
    if det.abs() <= 1e-12 * leg.hypot() * dir.hypot() || !det.is_finite() {
        return None;
    }
    let t = d.cross(dir) / det;
    let u = leg.cross(d) / det;
    (t > 0.0 && u > 0.0).then(|| c0 + leg * t)
}

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

    /// Writes the residuals `Rᵢ − P(sᵢ)` as `(x, y)` pairs into `out`
    /// (`out.len() == 2(n + 1)`), without allocation; under
    /// [`ErrorMeasure::Orthogonal`] the `sᵢ` are the foot points.
    pub fn residuals(&self, x: &[f64], out: &mut [f64]) {
        let k = self.controls(x);
        debug_assert_eq!(out.len(), 2 * self.points.len());
        if self.error == ErrorMeasure::Orthogonal {
            for (i, (o, &r)) in out.chunks_exact_mut(2).zip(&self.points).enumerate() {
                let p = self.measured(&k, i).1;
                o[0] = r.x - p.x;
                o[1] = r.y - p.y;
            }
            return;
        }
        let pairs = out.chunks_exact_mut(2).zip(&self.points).zip(&self.params);
        macro_rules! fill {
            ($eval:expr) => {
                for ((o, &r), &s) in pairs {
                    let p = $eval(s);
                    o[0] = r.x - p.x;
                    o[1] = r.y - p.y;
                }
            };
        }
        match self.function {
            FunctionType::Quadratic => fill!(|s| quad(&k, s)),
            FunctionType::Cubic => fill!(|s| cubic(&k, s)),
            FunctionType::RationalQuadratic => fill!(|s| rquad(&k, s)),
            FunctionType::RationalCubic => fill!(|s| rcubic(&k, s)),
        }
    }

    /// Writes the Jacobian `∂rₖ/∂x_j` of [`SegmentProblem::residuals`]
    /// row-major (`2(n + 1)` rows, `dim` columns) into `jac`.
    ///
    /// With `P = Σ w_k B_k C_k / W`, `W = Σ w_k B_k`:
    /// `∂P/∂C_k = w_k B_k / W` (times the identity), `∂P/∂w_k = B_k (C_k − P)/W`,
    /// and through the joins `∂C₁/∂T = L` (G¹), `∂C₁/∂w₁ = −D/(m w₁²)` (C¹);
    /// the residual's derivative is minus that of `P`.
    ///
    /// Under [`ErrorMeasure::Orthogonal`] the rows are taken at the foot
    /// points and projected onto the normal, `−(I − t tᵀ) ∂P/∂x` with `t` the
    /// unit tangent there: the foot point moves along the curve to first
    /// order, `∂s/∂x = −t·∂P/∂x / |P′|` (Kaufman's 1975 variable-projection
    /// Jacobian; exact where the residual is zero).
    pub fn jacobian(&self, x: &[f64], jac: &mut [f64]) {
        let dim = self.layout.dim;
        debug_assert_eq!(jac.len(), 2 * self.points.len() * dim);
        if dim == 0 {
            return;
        }
        let k = self.controls(x);
        let m = self.function.degree();
        let orthogonal = self.error == ErrorMeasure::Orthogonal;
        for i in 0..self.params.len() {
            let (s, tangent) = if orthogonal {
                let (s, _, d1) = self.measured(&k, i);
                let len = d1.hypot();
                (s, (len > 0.0 && len.is_finite()).then(|| d1 / len))
            } else {
                (self.params[i], None)
            };
            let q = k.partials(m, s);
            let (a1, a2) = (q.c1, q.c2);
            let (rx, ry) = jac[2 * i * dim..2 * (i + 1) * dim].split_at_mut(dim);
            let mut put = |j: usize, d: Point| {
                rx[j] = -d.x;
                ry[j] = -d.y;
            };
            let mut lin = |var: C1Var, a: f64| match var {
                C1Var::Free(j) => {
                    put(j, Point::new(a, 0.0));
                    put(j + 1, Point::new(0.0, a));
                }
                C1Var::Derived(_) | C1Var::EndDerived(_) | C1Var::Fixed(_) => {}
                C1Var::Ratio(j, leg) => put(j, leg * a),
                C1Var::EndRatio(j, dir) => put(j, dir * -a),
            };
            lin(self.layout.c1, a1);
            if let Some(var) = self.layout.c2 {
                lin(var, a2);
            }
            // ∂C/∂w of a derived control point: −D/(m w²) from the start,
            // +D/(m w²) from the end.
            let derived = |var: C1Var, wk: f64, a: f64| match var {
                C1Var::Derived(dv) => dv * (-a / (m as f64 * wk * wk)),
                C1Var::EndDerived(dv) => dv * (a / (m as f64 * wk * wk)),
                _ => Point::ZERO,
            };
            if let Some(j) = self.layout.w1 {
                put(j, q.w1 + derived(self.layout.c1, k.w1, a1));
            }
            if let Some(j) = self.layout.w2 {
                let var = self.layout.c2.unwrap_or(C1Var::Free(0));
                put(j, q.w2 + derived(var, k.w2, a2));
            }
            if let Some(t) = tangent {
                for (x, y) in rx.iter_mut().zip(ry.iter_mut()) {
                    let along = *x * t.x + *y * t.y;
                    *x -= along * t.x;
                    *y -= along * t.y;
                }
            }
        }
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

impl LeastSquares for SegmentProblem {
    fn residual_count(&self) -> usize {
        2 * self.points.len()
    }

    fn residuals(&self, x: &[f64], out: &mut [f64]) {
        SegmentProblem::residuals(self, x, out)
    }

    fn jacobian(&self, x: &[f64], jac: &mut [f64]) -> bool {
        SegmentProblem::jacobian(self, x, jac);
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{CubicBez, QuadBez, RationalCubicBez};

    fn sample<C: Curve>(c: &C, n: usize) -> (Vec<Point>, Vec<f64>) {
        let params: Vec<f64> = (0..=n).map(|k| k as f64 / n as f64).collect();
        (params.iter().map(|&s| c.eval(s)).collect(), params)
    }

    fn starts() -> [Start; 3] {
        [
            Start::Free,
            Start::C1 {
                derivative: Point::new(3.0, 1.0),
            },
            Start::G1 {
                leg: Point::new(1.0, 0.5),
            },
        ]
    }

    #[test]
    fn dimensions_follow_the_joins() {
        let c = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (pts, ps) = sample(&c, 20);
        let o = SearchSpaceOptions::default();
        let expect = [[2, 0, 1], [4, 2, 3], [3, 1, 2], [6, 4, 5]];
        for (f, dims) in FunctionType::ALL.iter().zip(expect) {
            let continuities = [Continuity::C0, Continuity::C1, Continuity::G1];
            for ((start, d), continuity) in starts().into_iter().zip(dims).zip(continuities) {
                let p = SegmentProblem::new(*f, pts.clone(), ps.clone(), start, &o).unwrap();
                assert_eq!(p.dim(), d, "{f} {start:?}");
                // What a segment adds to a chain is the dimension of a
                // segment whose start is joined.
                assert_eq!(f.chain_dim(continuity), d, "{f} {continuity:?}");
                assert_eq!(p.bounds().len(), d);
                assert_eq!(p.variable_names().len(), d);
                assert!(p.variable_names().iter().all(|n| !n.is_empty()));
                assert!(p
                    .guess()
                    .iter()
                    .zip(p.bounds())
                    .all(|(&g, b)| b.contains(g)));
            }
        }
    }

    #[test]
    fn objective_matches_the_geometry_and_residuals() {
        let c = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (mut pts, ps) = sample(&c, 30);
        for (i, p) in pts.iter_mut().enumerate().skip(1) {
            p.y += 0.01 * ((i * 7 % 5) as f64 - 2.0);
        }
        let o = SearchSpaceOptions::default();
        for f in FunctionType::ALL {
            for start in starts() {
                let p = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o).unwrap();
                let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.37)).collect();
                let seg = p.segment(&x);
                let e = p.objective(&x);
                let e_geom = seg.sse(&pts, &ps);
                assert!(
                    (e - e_geom).abs() <= 1e-12 * e_geom.max(1.0),
                    "{f} {start:?}"
                );
                let mut r = vec![0.0; p.residual_count()];
                p.residuals(&x, &mut r);
                let e_r: f64 = r.iter().map(|v| v * v).sum();
                assert!((e - e_r).abs() <= 1e-12 * e.max(1.0));
                assert_eq!(seg.start(), pts[0]);
                assert_eq!(seg.end(), pts[30]);
            }
        }
    }

    /// Checks the analytic Jacobian of `p` against central differences
    /// (step 10⁻⁶) at a point inside its box; `what` names the case.
    fn assert_jacobian(p: &SegmentProblem, what: &str) {
        let (d, m) = (p.dim(), p.residual_count());
        let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.41)).collect();
        let mut jac = vec![0.0; m * d];
        p.jacobian(&x, &mut jac);
        let (mut rp, mut rm) = (vec![0.0; m], vec![0.0; m]);
        let h = 1e-6;
        for j in 0..d {
            let mut xp = x.clone();
            xp[j] += h;
            p.residuals(&xp, &mut rp);
            xp[j] -= 2.0 * h;
            p.residuals(&xp, &mut rm);
            for k in 0..m {
                let fd = (rp[k] - rm[k]) / (2.0 * h);
                let an = jac[k * d + j];
                assert!(
                    (fd - an).abs() < 1e-6 * (1.0 + fd.abs()),
                    "{what} var {j} row {k}: fd {fd} an {an}"
                );
            }
        }
    }

    #[test]
    fn analytic_jacobian_matches_finite_differences() {
        let c = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (pts, ps) = sample(&c, 12);
        let o = SearchSpaceOptions::default();
        for f in FunctionType::ALL {
            for start in starts() {
                let p = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o).unwrap();
                assert_jacobian(&p, &format!("{f} {start:?}"));
            }
        }
    }

    #[test]
    fn joins_are_built_in() {
        let prev = RationalCubicBez::new(
            Point::new(-4.0, 1.0),
            Point::new(-3.0, 2.0),
            Point::new(-1.0, -1.0),
            Point::ZERO,
            0.7,
            1.8,
        )
        .unwrap();
        let next = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (pts, ps) = sample(&next, 20);
        let o = SearchSpaceOptions::default();
        for f in FunctionType::ALL {
            for cont in [Continuity::C1, Continuity::G1] {
                let p =
                    SegmentProblem::new(f, pts.clone(), ps.clone(), Start::after(&prev, cont), &o)
                        .unwrap();
                let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(0.8)).collect();
                let seg = p.segment(&x);
                assert!(
                    crate::geometry::check_join(&prev, &seg, cont, 1e-12),
                    "{f} {cont:?}"
                );
            }
        }
    }

    #[test]
    fn errors_are_explained() {
        let o = SearchSpaceOptions::default();
        let pts = vec![
            Point::ZERO,
            Point::new(1.0, 1.0),
            Point::new(2.0, 0.0),
            Point::new(3.0, 0.0),
        ];
        let e = SegmentProblem::with_parameterisation(
            FunctionType::RationalCubic,
            pts.clone(),
            Parameterisation::ChordLength,
            Start::Free,
            &o,
        )
        .unwrap_err();
        assert!(matches!(
            e,
            FitError::TooFewPoints {
                found: 4,
                needed: 5,
                ..
            }
        ));
        let msg = e.to_string();
        assert!(
            msg.contains("4 data point") && msg.contains("at least 5"),
            "{msg}"
        );
        let bad = SearchSpaceOptions {
            weight_range: (-1.0, 1.0),
            ..o
        };
        let e = SegmentProblem::with_parameterisation(
            FunctionType::Cubic,
            pts,
            Parameterisation::ChordLength,
            Start::Free,
            &bad,
        )
        .unwrap_err();
        assert!(e.to_string().contains("strictly positive"), "{e}");
    }

    /// Every function with a start join and an end join (where allowed):
    /// the joins hold to 1e-9 at both ends for arbitrary decision vectors,
    /// the analytic Jacobian matches finite differences, and LM recovers a
    /// curve that satisfies both joins exactly.
    #[test]
    fn end_joins_are_built_in() {
        let prev = RationalCubicBez::new(
            Point::new(-4.0, 1.0),
            Point::new(-3.0, 2.0),
            Point::new(-1.0, -1.0),
            Point::ZERO,
            0.7,
            1.8,
        )
        .unwrap();
        let next = RationalCubicBez::new(
            Point::new(4.0, 0.0),
            Point::new(5.0, -2.0),
            Point::new(7.0, 1.0),
            Point::new(9.0, 0.5),
            1.3,
            0.6,
        )
        .unwrap();
        let mid = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (pts, ps) = sample(&mid, 20);
        let o = SearchSpaceOptions::default();
        let ends = [
            (
                Continuity::C1,
                End::C1 {
                    derivative: next.deriv(0.0),
                },
            ),
            (
                Continuity::G1,
                End::G1 {
                    dir: next.deriv(0.0) * 0.1,
                },
            ),
        ];
        for f in FunctionType::ALL {
            for start_cont in [Continuity::C0, Continuity::C1, Continuity::G1] {
                for (end_cont, end) in ends {
                    let start = Start::after(&prev, start_cont);
                    let built = SegmentProblem::new(f, pts.clone(), ps.clone(), start, &o)
                        .unwrap()
                        .with_end(end);
                    let both_g1 = start_cont == Continuity::G1 && end_cont == Continuity::G1;
                    if f.degree() == 2 && start != Start::Free && !both_g1 {
                        let e = built.unwrap_err();
                        assert!(e.to_string().contains("free start"), "{e}");
                        continue;
                    }
                    let p = match built {
                        Ok(p) => p,
                        Err(e) => {
                            // G¹ at both ends of a quadratic: only when the
                            // tangent lines meet in front of both ends.
                            assert!(f.degree() == 2 && both_g1, "{f}: {e}");
                            assert!(e.to_string().contains("meet in front"), "{e}");
                            continue;
                        }
                    };
                    assert_eq!(p.end(), end);
                    assert_eq!(p.variable_names().len(), p.dim());
                    assert!(p.variable_names().iter().all(|n| !n.is_empty()));
                    for frac in [0.2, 0.8] {
                        let x: Vec<f64> = p.bounds().iter().map(|b| b.lerp(frac)).collect();
                        let seg = p.segment(&x);
                        assert_eq!(seg.start(), pts[0]);
                        assert_eq!(seg.end(), pts[20]);
                        assert!(
                            crate::geometry::check_join(&seg, &next, end_cont, 1e-9),
                            "end {f} {start_cont:?} {end_cont:?}: {:?} vs {:?}",
                            seg.deriv(1.0),
                            next.deriv(0.0)
                        );
                        if start_cont != Continuity::C0 {
                            assert!(
                                crate::geometry::check_join(&prev, &seg, start_cont, 1e-9),
                                "start {f} {start_cont:?} {end_cont:?}"
                            );
                        }
                    }
                    // Jacobian against central differences.
                    assert_jacobian(&p, &format!("{f} {start_cont:?} {end_cont:?}"));
                }
            }
        }
    }

    #[test]
    fn a_quadratic_joined_g1_at_both_ends_meets_its_tangent_lines() {
        // The quadratic (0,0)-(1,1)-(2,0): start tangent (1,1), end tangent (1,−1).
        let q = QuadBez::new(Point::ZERO, Point::new(1.0, 1.0), Point::new(2.0, 0.0));
        let (pts, ps) = sample(&q, 10);
        assert_eq!(
            tangent_meet(
                Point::ZERO,
                Point::new(0.5, 0.5),
                Point::new(2.0, 0.0),
                Point::new(3.0, -3.0)
            ),
            Some(Point::new(1.0, 1.0))
        );
        // Behind an end, or parallel: no meeting point.
        assert_eq!(
            tangent_meet(
                Point::ZERO,
                Point::new(-1.0, -1.0),
                Point::new(2.0, 0.0),
                Point::new(1.0, -1.0)
            ),
            None
        );
        assert_eq!(
            tangent_meet(
                Point::ZERO,
                Point::new(1.0, 0.0),
                Point::new(2.0, 1.0),
                Point::new(1.0, 0.0)
            ),
            None
        );
        let o = SearchSpaceOptions::default();
        for (f, dim) in [
            (FunctionType::Quadratic, 0),
            (FunctionType::RationalQuadratic, 1),
        ] {
            let p = SegmentProblem::new(
                f,
                pts.clone(),
                ps.clone(),
                Start::G1 {
                    leg: Point::new(2.0, 2.0),
                },
                &o,
            )
            .unwrap()
            .with_end(End::G1 {
                dir: Point::new(1.0, -1.0),
            })
            .unwrap();
            assert_eq!(p.dim(), dim, "{f}");
            let x = vec![1.0; dim];
            assert!(p.objective(&x) < 1e-24, "{f}");
        }
    }

    #[test]
    fn end_g1_dimensions_and_exact_recovery() {
        // A cubic whose end leg points along (1, −2): with End::G1 along that
        // direction (C₂ = C₃ − T·dir, T = 1) LM recovers it exactly.
        let c = CubicBez::new(
            Point::ZERO,
            Point::new(1.0, 2.0),
            Point::new(3.0, 2.0),
            Point::new(4.0, 0.0),
        );
        let (pts, ps) = sample(&c, 30);
        let o = SearchSpaceOptions::default();
        let expect = [1, 3, 2, 5];
        for (f, dim) in FunctionType::ALL.into_iter().zip(expect) {
            let p = SegmentProblem::new(f, pts.clone(), ps.clone(), Start::Free, &o)
                .unwrap()
                .with_end(End::G1 {
                    dir: Point::new(1.0, -2.0),
                })
                .unwrap();
            assert_eq!(p.dim(), dim, "{f}");
        }
        let p = SegmentProblem::new(FunctionType::Cubic, pts, ps, Start::Free, &o)
            .unwrap()
            .with_end(End::G1 {
                dir: Point::new(1.0, -2.0),
            })
            .unwrap();
        let x = crate::fit::linear_fit(&p);
        assert!(p.objective(&x) < 1e-20, "{x:?}");
        let seg = p.segment(&x);
        assert!((seg.control_points()[2] - Point::new(3.0, 2.0)).hypot() < 1e-9);
        let e = SegmentProblem::new(
            FunctionType::Cubic,
            p.points().to_vec(),
            p.params().to_vec(),
            Start::Free,
            &o,
        )
        .unwrap()
        .with_end(End::G1 { dir: Point::ZERO })
        .unwrap_err();
        assert!(e.to_string().contains("non-zero end tangent"), "{e}");
    }
}
