//! A peer on the same outlines: kurbo's curve fitting (Levien 2022, "Fitting
//! cubic Bézier curves", the area-and-moment quartic solver of
//! `kurbo::fit_to_bezpath`; with `--optimal`, `kurbo::fit_to_bezpath_opt`,
//! which also searches optimal subdivision points) run on the outline that
//! `metabezier fit` fits, written as an SVG that `metabezier score` reads
//! back in the same frame as our own `fit.svg`.
//!
//! ```text
//! cargo run --release --example kurbo_fit -- data/outlines/horse.png kurbo.svg 1.0
//! metabezier score data/outlines/horse.png kurbo.svg
//! ```
//!
//! `--optimal` did not finish within 120 s on the coin's 172 points
//! (kurbo 0.13.1), where `fit_to_bezpath` takes milliseconds; `make
//! peer-kurbo` runs the plain fit.
//!
//! The source is each closed contour's points, interpolated by the uniform
//! Catmull–Rom spline (a `C¹` curve through every outline point; the bare
//! polyline, with a corner at every vertex, makes kurbo subdivide without
//! end). No cusps are reported. `metabezier score` then measures the curves
//! against the outline points, as it measures ours and potrace's.

use std::error::Error;
use std::ops::Range;
use std::path::Path;

use kurbo::{fit_to_bezpath, fit_to_bezpath_opt, CurveFitSample, ParamCurveFit, PathEl, Vec2};
use metabezier::geometry::Point;
use metabezier::reconstruction::{LoadOptions, Source};

/// A closed outline as a curve-fitting source: the uniform Catmull–Rom
/// spline through its points (Catmull & Rom 1974, "A class of local
/// interpolating splines"), `C¹`, the cubic Hermite interpolant with the
/// tangent `(R_{i+1} − R_{i−1})/2` at point `i`; `t ∈ [0, 1]` covers the
/// `n` spans. The polyline itself, with a corner at every vertex, is no
/// source for a fitter that imposes G¹ at its subdivisions: `kurbo`
/// subdivides it without end.
struct Outline {
    points: Vec<Point>,
}

impl Outline {
    /// The span of `t` and the local parameter in it (the span after a
    /// knot for `sign ≥ 0`, before it otherwise).
    fn span(&self, t: f64, sign: f64) -> (usize, f64) {
        let n = self.points.len();
        let u = t.clamp(0.0, 1.0) * n as f64;
        let mut i = u.floor() as usize;
        if (u == i as f64 && sign < 0.0 && i > 0) || i >= n {
            i -= 1;
        }
        (i, u - i as f64)
    }

    /// `P` and `dP/dt` in span `i` at local parameter `f`.
    fn at(&self, i: usize, f: f64) -> (kurbo::Point, Vec2) {
        let n = self.points.len();
        let r = |k: isize| self.points[k.rem_euclid(n as isize) as usize];
        let i = i as isize;
        let (p0, p1) = (r(i), r(i + 1));
        let (m0, m1) = ((r(i + 1) - r(i - 1)) * 0.5, (r(i + 2) - r(i)) * 0.5);
        let (f2, f3) = (f * f, f * f * f);
        let p = p0 * (2.0 * f3 - 3.0 * f2 + 1.0)
            + m0 * (f3 - 2.0 * f2 + f)
            + p1 * (-2.0 * f3 + 3.0 * f2)
            + m1 * (f3 - f2);
        let d = p0 * (6.0 * f2 - 6.0 * f)
            + m0 * (3.0 * f2 - 4.0 * f + 1.0)
            + p1 * (-6.0 * f2 + 6.0 * f)
            + m1 * (3.0 * f2 - 2.0 * f);
        let d = d * n as f64;
        (kurbo::Point::new(p.x, p.y), Vec2::new(d.x, d.y))
    }
}

impl ParamCurveFit for Outline {
    fn sample_pt_tangent(&self, t: f64, sign: f64) -> CurveFitSample {
        let (i, f) = self.span(t, sign);
        let (p, tangent) = self.at(i, f);
        CurveFitSample { p, tangent }
    }

    fn sample_pt_deriv(&self, t: f64) -> (kurbo::Point, Vec2) {
        let (i, f) = self.span(t, 1.0);
        self.at(i, f)
    }

    fn break_cusp(&self, _: Range<f64>) -> Option<f64> {
        None
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(input), Some(out)) = (args.get(1), args.get(2)) else {
        return Err("usage: kurbo_fit INPUT OUT.svg [ACCURACY] [--optimal]".into());
    };
    let optimal = args.iter().skip(3).any(|a| a == "--optimal");
    let accuracy: f64 = match args.get(3).filter(|a| *a != "--optimal") {
        Some(a) => a.parse().map_err(|e| format!("ACCURACY {a:?}: {e}"))?,
        None => 1.0,
    };
    if !(accuracy.is_finite() && accuracy > 0.0) {
        return Err(format!("ACCURACY {accuracy}: expected a finite distance > 0").into());
    }
    let source = Source::load(input, Path::new(""), &LoadOptions::default())?;
    let all: Vec<Point> = source.points();
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in &all {
        (x0, y0, x1, y1) = (x0.min(p.x), y0.min(p.y), x1.max(p.x), y1.max(p.y));
    }
    let margin = 0.05 * (x1 - x0).max(y1 - y0);
    let (x0, y0, x1, y1) = (x0 - margin, y0 - margin, x1 + margin, y1 + margin);
    // The frame of metabezier's fit.svg: y written as Y0 + Y1 − y.
    let flip = |p: kurbo::Point| format!("{} {}", p.x, y0 + y1 - p.y);
    let mut d = String::new();
    let mut segments = 0;
    for contour in &source.contours {
        let fit = if optimal {
            fit_to_bezpath_opt
        } else {
            fit_to_bezpath
        };
        let path = fit(
            &Outline {
                points: contour.outline.points.clone(),
            },
            accuracy,
        );
        for el in path.elements() {
            match el {
                PathEl::MoveTo(p) => d.push_str(&format!("M {} ", flip(*p))),
                PathEl::LineTo(p) => {
                    segments += 1;
                    d.push_str(&format!("L {} ", flip(*p)));
                }
                PathEl::QuadTo(a, b) => {
                    segments += 1;
                    d.push_str(&format!("Q {} {} ", flip(*a), flip(*b)));
                }
                PathEl::CurveTo(a, b, c) => {
                    segments += 1;
                    d.push_str(&format!("C {} {} {} ", flip(*a), flip(*b), flip(*c)));
                }
                PathEl::ClosePath => d.push_str("Z "),
            }
        }
    }
    let svg = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{x0} {y0} {} {}\">\n\
         <!-- kurbo {} {} of {input} at accuracy {accuracy}; y is Y0 + Y1 - y \
         of the outline frame, as in metabezier's fit.svg -->\n\
         <path fill=\"none\" stroke=\"black\" d=\"{}\"/>\n</svg>\n",
        x1 - x0,
        y1 - y0,
        "0.13",
        if optimal {
            "fit_to_bezpath_opt"
        } else {
            "fit_to_bezpath"
        },
        d.trim_end()
    );
    std::fs::write(out, svg).map_err(|e| format!("{out}: {e}"))?;
    println!("{input}: {segments} segments at accuracy {accuracy} -> {out}");
    Ok(())
}
