//! A template for defects the mirror technique cannot serve (defects across
//! the mid-sagittal line): the outer contour **continued** from both sides
//! of the defect, curvature-continuous at A′ and B′
//! (**BEYOND THE THESIS**: the thesis's chapter 6 only mirrors).
//!
//! The missing outer table is described, as the mirrored template is, in
//! polar form about the polar centre `O` on the midline: a radius function
//! `r(θ)` from θ_A (at A′) to θ_B (at B′). Next to each end, the intact
//! table (the outer envelope walked away from the gap, `Gap::table` in [`super::polar`]) is
//! read as samples `(θ_k, r_k)` and a least-squares quadratic in
//! `φ = θ − θ_end` gives the end's slope `r′` and second derivative `r″`;
//! `r` itself is the end's own radius. In a polar parameterisation the
//! three numbers `r, r′, r″` fix the position, the tangent direction and the
//! curvature `κ = (r² + 2r′² − r r″)/(r² + r′²)^{3/2}` of the curve, so the
//! **quintic Hermite interpolant** of `(r, r′, r″)` at both ends
//!
//! `r(θ_A + tΔ) = H₀(t) r_A + H₁(t) Δ r′_A + H₂(t) Δ² r″_A + H₃(t) Δ² r″_B + H₄(t) Δ r′_B + H₅(t) r_B`
//!
//! (`Δ = θ_B − θ_A`, `t ∈ [0, 1]`, the quintic Hermite basis
//! `H₀ = 1 − 10t³ + 15t⁴ − 6t⁵`, `H₁ = t − 6t³ + 8t⁴ − 3t⁵`,
//! `H₂ = (t² − 3t³ + 3t⁴ − t⁵)/2`, `H₃ = (t³ − 2t⁴ + t⁵)/2`,
//! `H₄ = −4t³ + 7t⁴ − 3t⁵`, `H₅ = 10t³ − 15t⁴ + 6t⁵`) is a curve that joins
//! the bone on both sides with G² continuity (position, tangent and
//! curvature; Farin, *Curves and Surfaces for CAGD*, 5th ed. 2002, §7.3 on
//! quintic Hermite interpolation; G² Hermite data as in de Boor, Höllig &
//! Sabin, "High accuracy geometric Hermite interpolation", CAGD 4(4):269–278,
//! 1987). It is the lowest-degree polynomial radius with that end data, so
//! it adds no oscillation of its own, and a circle about `O` (constant `r`)
//! is continued exactly.
//!
//! Why polar rather than a Cartesian quintic: the Cartesian G² Hermite
//! quintic needs two free tangent lengths per end (Yong & Cheng, "Geometric
//! Hermite curves with minimum strain energy", CAGD 21(3):281–301, 2004),
//! which must be chosen; with θ as the parameter they are fixed by the
//! geometry, the curve is a ray function like the outer envelope it
//! replaces (so the template stays star-shaped about `O`), and it is sampled
//! on the same rays as the mirrored template.
//!
//! The derivatives are read over [`window_mm`] = 2 × `tangent_mm` (12 mm by
//! default) of table: long enough that the quadratic's curvature is not the
//! pixel staircase's, short compared with the skull's radius of curvature
//! (≈ 60–100 mm on the vault). The template is then fitted by the same
//! chapter-5 curve fit as the mirrored one ([`super::wall::design_outer`]),
//! so the wall kinds keep their meaning: `template` is the bare
//! continuation, `curve` its fit with the G¹ joins, `straight` the chord.

use super::polar::{angle, least_squares_quadratic, wrap, Gap, Side, WallEnds};
pub use super::template_source::TemplateSource;
use super::wall_input::{TemplateChoice, WallInput, WallOptions};
use super::SliceError;
use crate::ct::{CtError, MidLine};
use crate::geometry::Point;

/// Whether the defect ends `a` and `b` lie on opposite sides of (or on)
/// the mid-sagittal line, so that the mirror image of the gap falls into
/// the gap itself.
pub fn crosses_midline(a: Point, b: Point, line: &MidLine) -> bool {
    line.side(a) * line.side(b) <= 0.0
}

/// The template a wall across the defect `a`–`b` is fitted to, as far as
/// it can be told before the design: the explicit file when there is one,
/// else the continuation when `options.template` forces it or (`Auto`) the
/// defect crosses the midline ([`crosses_midline`]), else the mirror. Under
/// `Auto` a mirror that then cannot serve the defect (its mirrored end C
/// or D falls into the gap, which happens next to the midline when a seat
/// moves across it) still gives way to the continuation (`template_for`);
/// [`super::wall::OuterDesign::template_source`] says what was used.
pub fn source_for(
    a: Point,
    b: Point,
    line: &MidLine,
    has_file: bool,
    options: &WallOptions,
) -> TemplateSource {
    match options.template {
        _ if has_file => TemplateSource::File,
        TemplateChoice::Continuation => TemplateSource::Continuation,
        TemplateChoice::Auto | TemplateChoice::Auto3d if crosses_midline(a, b, line) => {
            TemplateSource::Continuation
        }
        _ => TemplateSource::Mirror,
    }
}

/// [`source_for`] of a wall input under `options`, or the kind of its 3D
/// template ([`WallInput::surface`]) when it has one.
pub fn template_source(input: &WallInput<'_>, options: &WallOptions) -> TemplateSource {
    if let Some(s) = input.surface {
        return s.kind;
    }
    source_for(
        input.a,
        input.b,
        &input.midline,
        input.template.is_some(),
        options,
    )
}

/// The arc length (mm) of outer table next to each end read for the
/// continuation's derivatives: twice the join tangent's window.
pub fn window_mm(options: &WallOptions) -> f64 {
    2.0 * options.tangent_mm.max(1.0)
}

/// The quintic Hermite basis at `t` in the order of the end data
/// `(p₀, p₀′, p₀″, p₁″, p₁′, p₁)` (Farin 2002, §7.3).
pub fn quintic_hermite_basis(t: f64) -> [f64; 6] {
    let (t2, t3) = (t * t, t * t * t);
    let (t4, t5) = (t3 * t, t3 * t2);
    [
        1.0 - 10.0 * t3 + 15.0 * t4 - 6.0 * t5,
        t - 6.0 * t3 + 8.0 * t4 - 3.0 * t5,
        0.5 * (t2 - 3.0 * t3 + 3.0 * t4 - t5),
        0.5 * (t3 - 2.0 * t4 + t5),
        -4.0 * t3 + 7.0 * t4 - 3.0 * t5,
        10.0 * t3 - 15.0 * t4 + 6.0 * t5,
    ]
}

/// A polar radius function's value and first two derivatives in θ at an
/// end of the gap.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolarJet {
    /// `r` (mm).
    pub r: f64,
    /// `dr/dθ` (mm per radian).
    pub dr: f64,
    /// `d²r/dθ²` (mm per radian²).
    pub ddr: f64,
}

impl PolarJet {
    /// The curvature (1/mm) of the polar curve `r(θ)` at this point:
    /// `κ = (r² + 2r′² − r r″)/(r² + r′²)^{3/2}` (positive when it turns
    /// towards the centre).
    pub fn curvature(&self) -> f64 {
        let (r, d, dd) = (self.r, self.dr, self.ddr);
        (r * r + 2.0 * d * d - r * dd) / (r * r + d * d).powf(1.5)
    }
}

/// The quintic Hermite radius from `a` (at `t = 0`) to `b` (at `t = 1`)
/// over the signed angular width `span` (radians): `r(θ_A + t·span)`.
pub fn quintic_radius(a: &PolarJet, b: &PolarJet, span: f64, t: f64) -> f64 {
    let h = quintic_hermite_basis(t);
    let s2 = span * span;
    h[0] * a.r
        + h[1] * span * a.dr
        + h[2] * s2 * a.ddr
        + h[3] * s2 * b.ddr
        + h[4] * span * b.dr
        + h[5] * b.r
}

/// The least-squares quadratic `r ≈ c₀ + c₁φ + c₂φ²` through `(φ_k, r_k)`
/// ([`least_squares_quadratic`]): `(c₁, 2c₂)`, its slope and second
/// derivative at `φ = 0`.
fn quadratic_derivatives(samples: &[(f64, f64)]) -> Option<(f64, f64)> {
    let c = least_squares_quadratic(samples.iter().copied())?;
    Some((c[1], 2.0 * c[2])).filter(|(d, dd)| d.is_finite() && dd.is_finite())
}

/// The polar jet of the outer envelope at one end of `gap`: `r` of the end
/// point itself, `r′` and `r″` of a least-squares quadratic in `θ` through
/// 25 points of the table over `window` mm next to the end.
fn end_jet(gap: &Gap<'_>, side: Side, window: f64) -> Option<PolarJet> {
    let o = gap.input.centre;
    let theta0 = match side {
        Side::A => gap.th_a,
        Side::B => gap.th_a + gap.span,
    };
    let walk = gap.table(side, window)?;
    let end = walk.at(0.0);
    let samples: Vec<(f64, f64)> = (0..=24)
        .map(|k| {
            let p = walk.at(window * k as f64 / 24.0);
            (wrap(angle(p, o) - theta0), p.distance(o))
        })
        .collect();
    let (dr, ddr) = quadratic_derivatives(&samples)?;
    Some(PolarJet {
        r: end.distance(o),
        dr,
        ddr,
    })
}

/// The continuation template of the gap (its ends at the seats): A′ and B′
/// on the envelope, and the quintic Hermite radius ([`quintic_radius`])
/// sampled on `template_points` rays from θ_A to θ_B, from A′ to B′. C and
/// D are A′ and B′ themselves (no mirror image is used).
///
/// Errors: [`CtError::NotOnContour`] when the ray of A′ or B′ misses the
/// contour, [`SliceError::TooLittleIntactContour`] when the table next to an
/// end is too short to read its derivatives, and
/// [`SliceError::TemplateNotCovered`] when the continued radius is not
/// positive on every ray.
pub(crate) fn continuation_template(
    gap: &Gap<'_>,
    options: &WallOptions,
) -> Result<(WallEnds, Vec<Point>), SliceError> {
    let o = gap.input.centre;
    let missing = |what| CtError::NotOnContour {
        what,
        distance_mm: f64::INFINITY,
        tolerance_mm: options.mirror_tolerance_mm,
    };
    let th_b = gap.th_a + gap.span;
    let a = gap.env(gap.th_a).ok_or_else(|| missing("A"))?;
    let b = gap.env(th_b).ok_or_else(|| missing("B"))?;
    let window = window_mm(options);
    let jet_a = end_jet(gap, Side::A, window).ok_or(SliceError::TooLittleIntactContour {
        before: 0,
        after: 1,
    })?;
    let jet_b = end_jet(gap, Side::B, window).ok_or(SliceError::TooLittleIntactContour {
        before: 1,
        after: 0,
    })?;
    let needed = options.function.min_points();
    let n = options.template_points.max(needed + 2);
    let mut data: Vec<Point> = (0..n)
        .map(|k| {
            let t = k as f64 / (n - 1) as f64;
            let theta = gap.th_a + gap.span * t;
            let r = quintic_radius(&jet_a, &jet_b, gap.span, t);
            (r.is_finite() && r > 0.0).then(|| o + Point::new(theta.cos(), theta.sin()) * r)
        })
        .collect::<Option<Vec<Point>>>()
        .ok_or(SliceError::TemplateNotCovered { points: 0, needed })?;
    data[0] = a;
    data[n - 1] = b;
    Ok((WallEnds { a, b, c: a, d: b }, data))
}

/// The wall's ends and fit data (A′ first, B′ last) and where they came
/// from: the continuation when [`template_source`] says so; otherwise the
/// mirror (or the explicit file) — and under [`TemplateChoice::Auto`], when
/// the mirror cannot serve the gap because a mirrored end (C or D) is not
/// on the contour or too few mirrored rays meet it, the continuation.
pub(crate) fn template_for(
    gap: &Gap<'_>,
    input: &WallInput<'_>,
    options: &WallOptions,
) -> Result<(WallEnds, Vec<Point>, TemplateSource), SliceError> {
    let source = template_source(input, options);
    if source == TemplateSource::Continuation {
        let (ends, data) = continuation_template(gap, options)?;
        return Ok((ends, data, source));
    }
    let mirrored = gap
        .ends(options.mirror_tolerance_mm)
        .map_err(SliceError::from)
        .and_then(|ends| Ok((ends, gap.template(&ends, options)?)));
    let mirror_failed = |e: &SliceError| match e {
        SliceError::Ct(CtError::NotOnContour { what, .. }) => {
            what.starts_with('C') || what.starts_with('D')
        }
        SliceError::TemplateNotCovered { .. } => true,
        _ => false,
    };
    match mirrored {
        Ok((ends, data)) => Ok((ends, data, source)),
        Err(e)
            if matches!(
                options.template,
                TemplateChoice::Auto | TemplateChoice::Auto3d
            ) && source == TemplateSource::Mirror
                && mirror_failed(&e) =>
        {
            let (ends, data) = continuation_template(gap, options)?;
            Ok((ends, data, TemplateSource::Continuation))
        }
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ct::Polyline;

    #[test]
    fn the_basis_interpolates_values_slopes_and_second_derivatives() {
        let h = 1e-4;
        let d1 = |i: usize, t: f64| {
            (quintic_hermite_basis(t + h)[i] - quintic_hermite_basis(t - h)[i]) / (2.0 * h)
        };
        let d2 = |i: usize, t: f64| {
            (quintic_hermite_basis(t + h)[i] - 2.0 * quintic_hermite_basis(t)[i]
                + quintic_hermite_basis(t - h)[i])
                / (h * h)
        };
        // Index i carries: value at 0, slope at 0, second at 0, second at
        // 1, slope at 1, value at 1.
        let want = |i: usize, what: usize, end: usize| -> f64 {
            let idx = [[0, 1, 2], [5, 4, 3]][end][what];
            f64::from(u8::from(i == idx))
        };
        for i in 0..6 {
            for (end, t) in [(0, 0.0), (1, 1.0)] {
                assert!((quintic_hermite_basis(t)[i] - want(i, 0, end)).abs() < 1e-12);
                assert!((d1(i, t) - want(i, 1, end)).abs() < 1e-6, "H{i}' at {t}");
                assert!((d2(i, t) - want(i, 2, end)).abs() < 1e-3, "H{i}'' at {t}");
            }
        }
    }

    /// A closed polygon of `n` points on the ellipse with centre `c` and
    /// semi-axes `ax`, `ay`.
    fn ellipse(c: Point, ax: f64, ay: f64, n: usize) -> Polyline {
        Polyline::closed(
            (0..n)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / n as f64;
                    c + Point::new(ax * t.cos(), ay * t.sin())
                })
                .collect(),
        )
    }

    #[test]
    fn an_ellipse_is_continued_across_a_gap_on_its_midline() {
        // A skull-like ellipse (semi-axes 70 × 90 mm) whose polar centre O is
        // 10 mm off its centre: r(θ) is not constant, and the gap (40°
        // about the posterior midline) crosses the midline x = 100.
        let c = Point::new(100.0, 110.0);
        let outer = ellipse(c, 70.0, 90.0, 4000);
        let polys = [&outer];
        let no_bone = |_: Point| false;
        let o = Point::new(100.0, 100.0);
        let line = MidLine::vertical(100.0);
        let at = |deg: f64| {
            let t = deg.to_radians();
            o + Point::new(t.cos(), t.sin())
                * super::super::polar::envelope_radius(&polys, o, t).unwrap()
        };
        let input = WallInput {
            outer: &polys,
            is_bone: &no_bone,
            centre: o,
            midline: line,
            a: at(250.0),
            b: at(290.0),
            template: None,
            surface: None,
            tissue: None,
        };
        let options = WallOptions {
            template: TemplateChoice::Auto,
            ..WallOptions::default()
        };
        assert_eq!(
            template_source(&input, &options),
            TemplateSource::Continuation
        );
        assert_eq!(
            template_source(&input, &WallOptions::default()),
            TemplateSource::Mirror
        );
        let gap = Gap::new(input);
        let (ends, data) = continuation_template(&gap, &options).unwrap();
        assert_eq!((ends.c, ends.d), (ends.a, ends.b));
        // Every template point lies on the true ellipse within 0.2 mm (0.13
        // mm: the end derivatives come from quadratics over 12 mm of table).
        let worst = data
            .iter()
            .map(|&p| outer.distance_to(p))
            .fold(0.0, f64::max);
        assert!(worst < 0.2, "worst {worst} mm");
        // A straight chord misses it by millimetres (the test can fail).
        let sag = outer.distance_to(ends.a.lerp(ends.b, 0.5));
        assert!(sag > 1.0, "sag {sag}");
    }
}
