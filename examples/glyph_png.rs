//! A font's glyph drawn as a black-on-white PNG, so that `make
//! peer-potrace` gives potrace and `metabezier fit` the same pixels of an
//! unseen shape: the glyph's outline (its TrueType or CFF segments, read by
//! `metabezier::outline::load_glyph`) scaled to `HEIGHT` pixels plus a
//! 16-pixel margin, y up, and filled by the nonzero winding rule at each
//! pixel's centre (the rule of both font formats; TrueType reference
//! manual, "Glyf table"; Adobe Type 2 charstrings, 5177).
//!
//! ```text
//! cargo run --release --example glyph_png -- data/outlines/DejaVuSans.ttf g 200 g.png
//! ```

use std::error::Error;
use std::path::Path;

use metabezier::geometry::Point;
use metabezier::outline::load_glyph;

/// Blank pixels around the glyph.
const MARGIN: f64 = 16.0;

/// Points per segment of the polygon the fill reads: far finer than a
/// pixel at the heights the peer run uses.
const STEPS: usize = 64;

/// Whether `p` is inside the closed polygons `rings` by the nonzero rule:
/// the winding number of the edges around `p` (Hormann & Agathos 2001).
fn inside(rings: &[Vec<Point>], p: Point) -> bool {
    let mut winding = 0i32;
    for ring in rings {
        for (a, b) in ring.iter().zip(ring.iter().cycle().skip(1)) {
            let cross = (b.x - a.x) * (p.y - a.y) - (p.x - a.x) * (b.y - a.y);
            if a.y <= p.y && b.y > p.y && cross > 0.0 {
                winding += 1;
            } else if a.y > p.y && b.y <= p.y && cross < 0.0 {
                winding -= 1;
            }
        }
    }
    winding != 0
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [font, glyph, height, output] = &args[..] else {
        return Err("usage: glyph_png FONT GLYPH HEIGHT_PX OUTPUT.png".into());
    };
    let mut chars = glyph.chars();
    let (Some(c), None) = (chars.next(), chars.next()) else {
        return Err(format!("GLYPH: expected one character, found \"{glyph}\"").into());
    };
    let height: f64 = height
        .parse()
        .ok()
        .filter(|h: &f64| (8.0..=4000.0).contains(h))
        .ok_or_else(|| {
            format!("HEIGHT_PX: expected a height in [8, 4000] px, found \"{height}\"")
        })?;
    let g = load_glyph(Path::new(font), c)?;
    let scale = height / g.height();
    let (lo, hi) = g.bbox;
    let to_px = |q: Point| Point::new(MARGIN + (q.x - lo.x) * scale, MARGIN + (hi.y - q.y) * scale);
    let rings: Vec<Vec<Point>> = g
        .contours
        .iter()
        .map(|contour| {
            contour
                .iter()
                .flat_map(|s| (0..STEPS).map(move |k| s.eval(k as f64 / STEPS as f64)))
                .map(to_px)
                .collect()
        })
        .collect();
    let w = (g.width() * scale + 2.0 * MARGIN).ceil() as u32;
    let h = (height + 2.0 * MARGIN).ceil() as u32;
    let img = image::GrayImage::from_fn(w, h, |x, y| {
        let centre = Point::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
        image::Luma([if inside(&rings, centre) { 0 } else { 255 }])
    });
    img.save(output)?;
    eprintln!("{font}:{c}: {w} x {h} px");
    Ok(())
}
