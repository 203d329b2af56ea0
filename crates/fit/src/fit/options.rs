//! The options of a fit, all with defaults and all validated in one place.

use super::{FitError, FunctionType};
use crate::geometry::{Continuity, Parameterisation};

/// A real-valued fitting option's one home: its name, the interval it
/// must lie in and its default, read by [`SearchSpaceOptions`], the spec
/// parser and the report alike.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RealOption {
    /// The option's name, as in specs.
    pub name: &'static str,
    /// The lower end of the interval.
    pub min: f64,
    /// Whether `min` itself is admissible.
    pub min_inclusive: bool,
    /// The upper end of the interval (admissible; `∞` for none).
    pub max: f64,
    /// The default value.
    pub default: f64,
    /// The interval in words, for error messages.
    pub expected: &'static str,
}

impl RealOption {
    /// Whether `x` is finite and in the option's interval.
    pub fn contains(&self, x: f64) -> bool {
        let above = if self.min_inclusive {
            x >= self.min
        } else {
            x > self.min
        };
        x.is_finite() && above && x <= self.max
    }

    /// `x` if the option admits it, else the error naming the option.
    pub fn check(&self, x: f64) -> Result<f64, FitError> {
        if self.contains(x) {
            Ok(x)
        } else {
            Err(FitError::InvalidOption {
                name: self.name,
                value: x,
                expected: self.expected,
            })
        }
    }
}

/// `α_size`: the technique's box has half-width `α_size·|C_m − C₀|` per
/// coordinate; in `(0, 10⁶]`, default 0.5 (our choice; the thesis's value is
/// lost).
pub const ALPHA_SIZE: RealOption = RealOption {
    name: "alpha_size",
    min: 0.0,
    min_inclusive: false,
    max: 1e6,
    default: 0.5,
    expected: "a real number in (0, 1000000]",
};

/// `pt`: how far the first guesses move towards the data's end tangent
/// lines; in `[0, 1]`, default 0 (not at all).
pub const PT: RealOption = RealOption {
    name: "pt",
    min: 0.0,
    min_inclusive: true,
    max: 1.0,
    default: 0.0,
    expected: "a real number in [0, 1]",
};

/// The bounding box's enlargement on each side, as a fraction of its
/// larger side; `≥ 0`, default 0.5.
pub const MARGIN: RealOption = RealOption {
    name: "margin",
    min: 0.0,
    min_inclusive: true,
    max: f64::INFINITY,
    default: 0.5,
    expected: "a real number ≥ 0",
};

/// How the box the optimisers search is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SearchSpace {
    /// The thesis's search-space technique (chapter 5, **reconstructed**;
    /// see [`crate::fit::search_space`]): a box of half-width
    /// `α_size·|C_m − C₀|` per coordinate around first guesses of the inner
    /// control points.
    #[default]
    Technique,
    /// The naive alternative: every control point coordinate may lie anywhere
    /// in the bounding box of the segment's data, enlarged on each side by
    /// `margin` times its larger side.
    BoundingBox,
}

impl SearchSpace {
    /// The names accepted in experiment specs, in the order of the enum.
    pub const NAMES: [&'static str; 2] = ["technique", "bounding-box"];

    /// Parses a spec name.
    pub fn from_name(name: &str) -> Option<SearchSpace> {
        match name {
            "technique" => Some(SearchSpace::Technique),
            "bounding-box" | "bounding_box" | "bbox" => Some(SearchSpace::BoundingBox),
            _ => None,
        }
    }

    /// The spec name.
    pub fn name(self) -> &'static str {
        match self {
            SearchSpace::Technique => "technique",
            SearchSpace::BoundingBox => "bounding-box",
        }
    }
}

/// Where the first guesses `A₁′, A₂′` of the technique come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GuessRule {
    /// The thesis's quarter points: the cubic passes through `R_Q1` at
    /// `s = 1/4` and `R_Q3` at `s = 3/4` (the quadratic through `R_mid` at
    /// `s = 1/2`), whatever the data's own parameters are.
    #[default]
    QuarterPoints,
    /// The same interpolation at the actual parameters `s_Q1`, `s_Q3`
    /// (`s_mid`) of those points, a 2×2 solve.
    ActualParams,
}

/// The options of the search box (see [`crate::fit::search_space`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SearchSpaceOptions {
    /// Technique or bounding box.
    pub kind: SearchSpace,
    /// Where the technique's first guesses come from.
    pub guess: GuessRule,
    /// `α_size`: the box's half-width per coordinate is `α_size·|C_m − C₀|`
    /// ([`ALPHA_SIZE`]: in `(0, 10⁶]`, default 0.5).
    pub alpha_size: f64,
    /// `pt ∈ [0, 1]`: how far the guesses move towards the end tangent lines
    /// estimated from the data ([`PT`]: 0 = not at all, the default).
    pub pt: f64,
    /// `[T_min, T_max]`, the range of the G¹ ratio `T`; default `[0.05, 5]`.
    pub t_range: (f64, f64),
    /// Whether `t_range` is scaled by `ρ = (|C′_m − C′₀|/m)/|C_m − C_{m−1}|`,
    /// the new segment's chord per degree over the previous segment's last
    /// leg, so that it bounds the new first leg relative to the new segment
    /// rather than to the previous one (our choice, default `true`; with
    /// `false`, `T ∈ [T_min, T_max]` as given, which keeps neighbouring
    /// segments within a length ratio of about `T_max`).
    pub scale_t_range: bool,
    /// `[w_min, w_max]`, the range of every free rational weight; default
    /// `[0.01, 10]`. Must satisfy `0 < w_min < w_max`.
    pub weight_range: (f64, f64),
    /// The bounding box's enlargement on each side, as a fraction of its
    /// larger side ([`MARGIN`]: `≥ 0`, default 0.5).
    pub margin: f64,
    /// How many data points, counted from each end, estimate an end tangent
    /// for `pt` (the chord from the end point to the `k`-th point); default 3.
    pub tangent_points: usize,
}

impl Default for SearchSpaceOptions {
    fn default() -> Self {
        Self {
            kind: SearchSpace::Technique,
            guess: GuessRule::QuarterPoints,
            alpha_size: ALPHA_SIZE.default,
            pt: PT.default,
            t_range: (0.05, 5.0),
            scale_t_range: true,
            weight_range: (0.01, 10.0),
            margin: MARGIN.default,
            tangent_points: 3,
        }
    }
}

impl SearchSpaceOptions {
    /// Checks every option, naming the first invalid one.
    pub fn validate(&self) -> Result<(), FitError> {
        let (wmin, wmax) = self.weight_range;
        if !(wmin.is_finite() && wmax.is_finite() && wmin > 0.0 && wmin < wmax) {
            return Err(FitError::InvalidWeightRange {
                min: wmin,
                max: wmax,
            });
        }
        let (tmin, tmax) = self.t_range;
        if !(tmin.is_finite() && tmax.is_finite() && tmin > 0.0 && tmin < tmax) {
            return Err(FitError::InvalidTRange {
                min: tmin,
                max: tmax,
            });
        }
        ALPHA_SIZE.check(self.alpha_size)?;
        PT.check(self.pt)?;
        MARGIN.check(self.margin)?;
        if self.tangent_points == 0 {
            return Err(FitError::InvalidOption {
                name: "tangent_points",
                value: 0.0,
                expected: "an integer ≥ 1",
            });
        }
        Ok(())
    }
}

/// What the fit's error `E` measures: the thesis's distance at fixed data
/// parameters, or the orthogonal distance to the curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ErrorMeasure {
    /// `E = Σᵢ |Rᵢ − P(sᵢ)|²` at the data parameters `sᵢ`, fixed during the
    /// solve (the thesis's E; the `sᵢ` come from the parameterisation).
    #[default]
    Fixed,
    /// `E = Σᵢ min_s |Rᵢ − P(s)|²`, the orthogonal distance regression of
    /// Borges & Pastva (2002, "Total least squares fitting of Bézier and
    /// B-spline curves to ordered data"): every candidate's `sᵢ` are its
    /// foot points, found by a safeguarded Newton projection started from
    /// the parameterisation's `sᵢ` (an inner solve), so the data parameters
    /// are unknowns of the fit without widening the search space. For
    /// Levenberg–Marquardt the `sᵢ` are eliminated by variable projection
    /// (Golub & Pereyra 1973, with Kaufman's 1975 Jacobian): each residual
    /// row is projected onto the curve's normal, which is Gauss–Newton on
    /// the orthogonal distances ("tangent distance minimisation", Wang,
    /// Pottmann & Liu 2006), exact at zero residual, and costs O(n) per
    /// iteration in the number of points.
    Orthogonal,
}

impl ErrorMeasure {
    /// The names accepted in specs (`error = "…"`) and on the command line.
    pub const NAMES: [&'static str; 2] = ["fixed", "orthogonal"];

    /// Parses a name.
    pub fn from_name(name: &str) -> Option<ErrorMeasure> {
        match name {
            "fixed" => Some(ErrorMeasure::Fixed),
            "orthogonal" => Some(ErrorMeasure::Orthogonal),
            _ => None,
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            ErrorMeasure::Fixed => "fixed",
            ErrorMeasure::Orthogonal => "orthogonal",
        }
    }
}

/// How the chain of segments closes on a closed outline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Closing {
    /// The closing joint gets the requested continuity unless it lies at a
    /// corner: the chain starts at a corner when the outline has one (so it
    /// also closes there, where C⁰ is right); otherwise the last segment is
    /// fitted with an end join to the first segment's start tangent
    /// ([`crate::fit::End`]), so the closing joint is G¹ or C¹ by construction.
    #[default]
    Smooth,
    /// The chain starts at the first break and the closing joint is only C⁰
    /// (sequential fitting as the thesis describes it; the behaviour of
    /// specs written before the smooth closing existed).
    C0,
}

impl Closing {
    /// The names accepted in specs and on the command line.
    pub const NAMES: [&'static str; 2] = ["smooth", "c0"];

    /// Parses a name.
    pub fn from_name(name: &str) -> Option<Closing> {
        match name {
            "smooth" => Some(Closing::Smooth),
            "c0" | "C0" => Some(Closing::C0),
            _ => None,
        }
    }

    /// The name.
    pub fn name(self) -> &'static str {
        match self {
            Closing::Smooth => "smooth",
            Closing::C0 => "c0",
        }
    }
}

/// How the segments of a piecewise fit are solved: one after another (the
/// thesis's sequential fitting), or all at once.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Chain {
    /// Segment after segment, each inheriting its start join from the
    /// previous one (the default in specs).
    #[default]
    Sequential,
    /// The sequential chain, then every segment's variables solved together
    /// by Levenberg–Marquardt with shared joins (beyond the thesis; see
    /// [`crate::fit`]'s joint-chain notes).
    Joint,
}

impl Chain {
    /// The names [`Chain::from_name`] accepts.
    pub const NAMES: [&'static str; 2] = ["sequential", "joint"];

    /// The chain called `name`.
    pub fn from_name(name: &str) -> Option<Chain> {
        match name {
            "sequential" => Some(Chain::Sequential),
            "joint" => Some(Chain::Joint),
            _ => None,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Chain::Sequential => "sequential",
            Chain::Joint => "joint",
        }
    }
}

/// Everything a piecewise fit needs besides the data, the breaks and the solver.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitOptions {
    /// The function fitted to each segment; default rational cubic (the
    /// thesis's title function).
    pub function: FunctionType,
    /// The continuity at interior joints; default C¹.
    pub continuity: Continuity,
    /// How data parameters are assigned; default chord length. Under
    /// [`ErrorMeasure::Orthogonal`] they are the foot-point projection's start.
    pub parameterisation: Parameterisation,
    /// What `E` measures; default [`ErrorMeasure::Fixed`] (the thesis's E).
    pub error: ErrorMeasure,
    /// The search box.
    pub search: SearchSpaceOptions,
    /// Objective evaluations per segment (per solve); default 10 000.
    pub budget_per_segment: u64,
    /// Rounds of Newton parameter correction after each segment's solve
    /// (Schneider 1990, "Reparameterize"): each round moves every interior
    /// `s_i` one Newton step towards the foot of `R_i` on the curve and
    /// solves again, with a fresh `budget_per_segment`. Default 0 (the
    /// thesis keeps the parameters fixed).
    pub reparameterise: u32,
    /// How a closed outline's chain closes; default [`Closing::Smooth`].
    pub closing: Closing,
    /// How the chain of segments is solved; default [`Chain::Sequential`]
    /// (the thesis's).
    pub chain: Chain,
}

impl Default for FitOptions {
    fn default() -> Self {
        Self {
            function: FunctionType::RationalCubic,
            continuity: Continuity::C1,
            parameterisation: Parameterisation::ChordLength,
            error: ErrorMeasure::Fixed,
            search: SearchSpaceOptions::default(),
            budget_per_segment: 10_000,
            reparameterise: 0,
            closing: Closing::Smooth,
            chain: Chain::Sequential,
        }
    }
}

impl FitOptions {
    /// Default options for `function` joined with `continuity`.
    pub fn new(function: FunctionType, continuity: Continuity) -> FitOptions {
        FitOptions {
            function,
            continuity,
            ..FitOptions::default()
        }
    }

    /// Checks every option.
    pub fn validate(&self) -> Result<(), FitError> {
        self.search.validate()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid_and_bad_values_are_named() {
        assert!(FitOptions::default().validate().is_ok());
        let mut s = SearchSpaceOptions {
            weight_range: (0.0, 10.0),
            ..Default::default()
        };
        assert!(matches!(
            s.validate(),
            Err(FitError::InvalidWeightRange { .. })
        ));
        for bad in [(-1.0, 2.0), (3.0, 3.0), (5.0, 1.0), (0.1, f64::INFINITY)] {
            s.weight_range = bad;
            assert!(s.validate().is_err(), "{bad:?}");
        }
        s.weight_range = (0.01, 10.0);
        s.t_range = (0.0, 1.0);
        assert!(matches!(s.validate(), Err(FitError::InvalidTRange { .. })));
        s.t_range = (0.05, 5.0);
        s.pt = 1.5;
        let e = s.validate().unwrap_err();
        assert!(e.to_string().contains("pt"), "{e}");
        s.pt = 0.5;
        s.alpha_size = 0.0;
        assert!(s.validate().is_err());
        for n in SearchSpace::NAMES {
            assert_eq!(SearchSpace::from_name(n).unwrap().name(), n);
        }
    }

    #[test]
    fn each_real_option_has_one_range_read_by_validate() {
        let d = SearchSpaceOptions::default();
        assert_eq!(d.alpha_size, ALPHA_SIZE.default);
        assert_eq!(d.pt, PT.default);
        assert_eq!(d.margin, MARGIN.default);
        type Setter = fn(&mut SearchSpaceOptions, f64);
        let cases: [(&RealOption, Setter); 3] = [
            (&ALPHA_SIZE, |s, x| s.alpha_size = x),
            (&PT, |s, x| s.pt = x),
            (&MARGIN, |s, x| s.margin = x),
        ];
        for (option, set) in cases {
            assert!(option.contains(option.default), "{}", option.name);
            for x in [-1.0, 0.0, 0.5, 1.0, 1e6, 1.5e6, f64::NAN, f64::INFINITY] {
                let mut s = SearchSpaceOptions::default();
                set(&mut s, x);
                assert_eq!(
                    s.validate().is_ok(),
                    option.contains(x),
                    "{} = {x}",
                    option.name
                );
                if let Err(e) = s.validate() {
                    let text = e.to_string();
                    assert!(
                        text.contains(option.name) && text.contains(option.expected),
                        "{text}"
                    );
                }
            }
        }
        assert!(
            !ALPHA_SIZE.contains(0.0) && ALPHA_SIZE.contains(1e6) && !ALPHA_SIZE.contains(1.5e6)
        );
        assert!(PT.contains(0.0) && PT.contains(1.0) && !PT.contains(1.0 + 1e-12));
    }
}
