//! The fitted shape as a picture: one SVG path with every contour (the
//! even-odd fill rule makes holes holes) and its PNG rasterisation.
//!
//! **The SVG's frame.** The outline frame is y-up; SVG is y-down. The path
//! is written at `(x, Y₀ + Y₁ − y)` with the `viewBox` spanning
//! `[X₀, X₁] × [Y₀, Y₁]` (the data's bounding box with a margin), so that
//! reflecting about the view's mid-line, as `metabezier score` does, gives
//! the outline frame back exactly (no offset needed). Polynomial segments
//! are written exactly (`Q`, `C`); a rational segment, which SVG cannot
//! express, as cubic pieces (Hermite interpolation of position and
//! derivative at equal parameter steps) refined until they are within
//! `10⁻⁶` of the shape's size of it.

use std::path::{Path, PathBuf};

use super::ShapeFit;
use crate::files::{write_atomic, IoError};
use crate::fit::Segment;
use crate::geometry::{CubicBez, Curve, Point};

/// The pieces of a rational segment are refined until their distance from
/// it, at 5 parameters per piece, is at most this fraction of the shape's
/// size.
const TOLERANCE: f64 = 1e-6;

/// The cubic pieces of `segment`: the segment itself when it is a cubic
/// (or an elevated quadratic), else Hermite pieces at equal parameter
/// steps, doubled until every piece is within `tol` of the segment.
pub fn cubic_pieces(segment: &Segment, tol: f64) -> Vec<CubicBez> {
    match *segment {
        Segment::Cubic(c) => return vec![c],
        Segment::Quadratic(q) => {
            let (a, b, c) = (q.p0, q.p1, q.p2);
            return vec![CubicBez::new(
                a,
                a + (b - a) * (2.0 / 3.0),
                c + (b - c) * (2.0 / 3.0),
                c,
            )];
        }
        _ => {}
    }
    let mut k = 1usize;
    loop {
        let pieces: Vec<CubicBez> = (0..k)
            .map(|i| {
                let (t0, t1) = (i as f64 / k as f64, (i + 1) as f64 / k as f64);
                let h = t1 - t0;
                let (p0, p3) = (segment.eval(t0), segment.eval(t1));
                CubicBez::new(
                    p0,
                    p0 + segment.deriv(t0) * (h / 3.0),
                    p3 - segment.deriv(t1) * (h / 3.0),
                    p3,
                )
            })
            .collect();
        let err = pieces
            .iter()
            .enumerate()
            .flat_map(|(i, c)| {
                (1..=5).map(move |j| {
                    let u = j as f64 / 6.0;
                    let t = (i as f64 + u) / k as f64;
                    c.eval(u).distance(segment.eval(t))
                })
            })
            .fold(0.0, f64::max);
        if err <= tol || k >= 256 {
            return pieces;
        }
        k *= 2;
    }
}

/// The view: `(x₀, y₀, x₁, y₁)` around the data and the fitted curves.
fn view(fit: &ShapeFit, data: &[Point]) -> (f64, f64, f64, f64) {
    let curve = fit
        .segments()
        .flat_map(|(_, s)| (0..=16).map(move |j| s.segment.eval(j as f64 / 16.0)));
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in data.iter().copied().chain(curve).filter(|p| p.is_finite()) {
        (x0, y0, x1, y1) = (x0.min(p.x), y0.min(p.y), x1.max(p.x), y1.max(p.y));
    }
    if x0 > x1 {
        return (0.0, 0.0, 1.0, 1.0);
    }
    let m = 0.02 * (x1 - x0).max(y1 - y0).max(1e-9);
    (x0 - m, y0 - m, x1 + m, y1 + m)
}

/// The SVG document of `fit`: one path of every contour, filled with the
/// even-odd rule; `title` goes in its `<title>`.
pub fn shape_svg(fit: &ShapeFit, data: &[Point], title: &str) -> String {
    let (x0, y0, x1, y1) = view(fit, data);
    let tol = TOLERANCE * (x1 - x0).max(y1 - y0);
    let flip = |p: Point| format!("{} {}", p.x, y0 + y1 - p.y);
    let mut d = String::new();
    let (mut rational, mut pieces) = (0usize, 0usize);
    for c in &fit.contours {
        let Some(first) = c.fit.segments.first() else {
            continue;
        };
        d.push_str(&format!("M {}", flip(first.segment.start())));
        for s in &c.fit.segments {
            match s.segment {
                Segment::Quadratic(q) => d.push_str(&format!(" Q {} {}", flip(q.p1), flip(q.p2))),
                other => {
                    let cubics = cubic_pieces(&other, tol);
                    if other.function().is_rational() {
                        rational += 1;
                        pieces += cubics.len();
                    }
                    for p in cubics {
                        d.push_str(&format!(" C {} {} {}", flip(p.p1), flip(p.p2), flip(p.p3)));
                    }
                }
            }
        }
        d.push_str(" Z ");
    }
    let escaped = title.replace('&', "&amp;").replace('<', "&lt;");
    let approximation = if rational > 0 {
        format!(
            "<!-- SVG has no rational curves: the {rational} rational segment(s) of this fit are \
             drawn as {pieces} polynomial cubic pieces, each within {tol:e} of its segment \
             ({TOLERANCE:e} of the drawing's size, checked at 5 parameters per piece); fit.csv \
             holds the exact control points and weights. -->\n"
        )
    } else {
        String::new()
    };
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{x0} {y0} {w} {h}\">\n\
         <title>{escaped}</title>\n\
         <!-- metabezier fit: y here is Y0 + Y1 - y of the outline frame (the viewBox's \
         vertical extent); metabezier score reads it back with no offset. -->\n\
         {approximation}<path fill=\"#b4cdeb\" fill-rule=\"evenodd\" stroke=\"#1f4e8c\" \
         stroke-width=\"{sw}\" d=\"{d}\"/>\n</svg>\n",
        w = x1 - x0,
        h = y1 - y0,
        sw = 0.003 * (x1 - x0).max(y1 - y0),
        d = d.trim_end()
    )
}

/// An RGB raster of `fit`, `size` pixels on its longer side: the contours
/// filled with the even-odd rule, the curves drawn over them, the data
/// points as dots.
pub fn shape_raster(fit: &ShapeFit, data: &[Point], size: u32) -> (Vec<u8>, u32, u32) {
    let (x0, y0, x1, y1) = view(fit, data);
    let scale = f64::from(size) / (x1 - x0).max(y1 - y0);
    let (w, h) = (
        ((x1 - x0) * scale).ceil().max(1.0) as u32,
        ((y1 - y0) * scale).ceil().max(1.0) as u32,
    );
    let to_px = |p: Point| Point::new((p.x - x0) * scale, (y1 - p.y) * scale);
    let polygons: Vec<Vec<Point>> = fit
        .contours
        .iter()
        .map(|c| {
            c.fit
                .segments
                .iter()
                .flat_map(|s| (0..32).map(move |j| to_px(s.segment.eval(j as f64 / 32.0))))
                .collect()
        })
        .collect();
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    let mut put = |x: i64, y: i64, c: [u8; 3]| {
        if x >= 0 && y >= 0 && (x as u32) < w && (y as u32) < h {
            let i = ((y as u32 * w + x as u32) * 3) as usize;
            rgb[i..i + 3].copy_from_slice(&c);
        }
    };
    for (y, xs) in (0..h).map(|y| (y, crossings(&polygons, f64::from(y) + 0.5))) {
        for pair in xs.chunks_exact(2) {
            let (a, b) = (
                (pair[0] - 0.5).ceil() as i64,
                (pair[1] - 0.5).floor() as i64,
            );
            for x in a..=b {
                put(x, i64::from(y), [180, 205, 235]);
            }
        }
    }
    for poly in &polygons {
        for (i, &p) in poly.iter().enumerate() {
            let q = poly[(i + 1) % poly.len()];
            let n = (p.distance(q).ceil() as usize).max(1);
            for k in 0..=n {
                let r = p.lerp(q, k as f64 / n as f64);
                put(r.x.floor() as i64, r.y.floor() as i64, [31, 78, 140]);
            }
        }
    }
    for p in data.iter().map(|&p| to_px(p)) {
        for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            put(
                p.x.floor() as i64 + dx - 1,
                p.y.floor() as i64 + dy - 1,
                [200, 60, 40],
            );
        }
    }
    (rgb, w, h)
}

/// The x where the closed `polygons` cross the line `y`, sorted: pairs
/// bound the inside under the even-odd rule.
fn crossings(polygons: &[Vec<Point>], y: f64) -> Vec<f64> {
    let mut xs = Vec::new();
    for poly in polygons {
        for (i, &a) in poly.iter().enumerate() {
            let b = poly[(i + 1) % poly.len()];
            if (a.y > y) != (b.y > y) {
                xs.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
        }
    }
    xs.sort_by(f64::total_cmp);
    xs
}

/// Writes `<dir>/<stem>.svg` ([`shape_svg`]); returns its path.
pub fn save_shape_svg(
    fit: &ShapeFit,
    data: &[Point],
    title: &str,
    dir: &Path,
    stem: &str,
) -> Result<PathBuf, IoError> {
    let svg = dir.join(format!("{stem}.svg"));
    write_atomic(&svg, shape_svg(fit, data, title).as_bytes())?;
    Ok(svg)
}

/// Writes `<dir>/<stem>.png`, the fit's raster ([`shape_raster`], 800
/// pixels); returns its path.
pub fn save_shape_png(
    fit: &ShapeFit,
    data: &[Point],
    dir: &Path,
    stem: &str,
) -> Result<PathBuf, IoError> {
    let png = dir.join(format!("{stem}.png"));
    let (rgb, w, h) = shape_raster(fit, data, 800);
    let mut bytes = Vec::new();
    {
        use image::ImageEncoder;
        image::codecs::png::PngEncoder::new(&mut bytes)
            .write_image(&rgb, w, h, image::ColorType::Rgb8)
            .map_err(|e| IoError::new("encode", &png, std::io::Error::other(e)))?;
    }
    write_atomic(&png, &bytes)?;
    Ok(png)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::RationalQuadBez;

    #[test]
    fn rational_segments_become_close_cubic_pieces() {
        let arc = RationalQuadBez::circular_arc(Point::ZERO, 1.0, 0.0, std::f64::consts::FRAC_PI_2)
            .unwrap();
        let seg = Segment::RationalQuadratic(arc);
        let pieces = cubic_pieces(&seg, 1e-6);
        assert!(pieces.len() > 1);
        for p in &pieces {
            for j in 0..=10 {
                let q = p.eval(j as f64 / 10.0);
                assert!((q.hypot() - 1.0).abs() < 2e-6, "{q:?}");
            }
        }
        assert_eq!(pieces[0].p0, Point::new(1.0, 0.0));
    }

    #[test]
    fn even_odd_crossings_pair_up() {
        let square = |a: f64, b: f64| {
            vec![
                Point::new(a, a),
                Point::new(b, a),
                Point::new(b, b),
                Point::new(a, b),
            ]
        };
        let xs = crossings(&[square(0.0, 10.0), square(3.0, 6.0)], 5.0);
        assert_eq!(xs, vec![0.0, 3.0, 6.0, 10.0]);
    }
}
