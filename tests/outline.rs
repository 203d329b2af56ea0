//! Outline input on the vendored real data (data/outlines/, see PROVENANCE.md)
//! and the user-facing errors.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use metabezier::fit::equal_arc_breaks;
use metabezier::geometry::{nearest, Point};
use metabezier::outline::*;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/outlines")
        .join(name)
}

// ---------------------------------------------------------------- images

#[test]
fn horse_is_one_counter_clockwise_loop() {
    let path = data("horse.png");
    let options = ImageOptions::default();
    let outlines = load_image(&path, &options).unwrap();
    assert_eq!(outlines.len(), 1, "min_area {} px²", options.min_area);
    let horse = &outlines[0];
    assert!(horse.closed);
    assert_eq!(horse.orientation(), Orientation::CounterClockwise);
    // Pinned: the number of mid-crack points of the horse's outer boundary.
    assert_eq!(horse.len(), 2644);
    // No consecutive duplicates, and unit steps between crack midpoints
    // (½√2 around a corner, 1 along a straight run).
    let n = horse.len();
    for i in 0..n {
        let d = horse.points[i].distance(horse.points[(i + 1) % n]);
        assert!(
            (d - 1.0).abs() < 1e-12 || (d - 0.5f64.sqrt()).abs() < 1e-12,
            "step {i}: {d}"
        );
    }
    // The enclosed area matches the shape's pixel count.
    let grey = load_grey(&path).unwrap();
    assert_eq!((grey.width, grey.height), (400, 328));
    let (binary, _) = binarize(&grey, &options).unwrap();
    let pixels = binary.count() as f64;
    let rel = (horse.area() - pixels).abs() / pixels;
    assert!(rel < 0.01, "area {} vs {pixels} pixels", horse.area());
    // y up: everything within the image's pixel-centre frame, ±½.
    let (lo, hi) = horse.bbox().unwrap();
    assert!(lo.x >= -0.5 && lo.y >= -0.5 && hi.x <= 399.5 && hi.y <= 327.5);
    // The same loop through pixel centres loses about half a pixel all round.
    let centres = load_image(
        &path,
        &ImageOptions {
            points: BoundaryPoints::PixelCentres,
            ..options
        },
    )
    .unwrap();
    assert_eq!(centres.len(), 1);
    // Pinned: the number of border pixels (after removing consecutive repeats).
    assert_eq!(centres[0].len(), 2054);
    let lost = pixels - centres[0].area();
    assert!(
        (lost - 0.5 * horse.length()).abs() < 0.1 * horse.length(),
        "{lost}"
    );
}

#[test]
fn horse_is_right_side_up() {
    // In the image the hooves are at the bottom rows; in the y-up frame they
    // must have the smallest y, so the lowest point of the outline lies in
    // the image's bottom rows.
    let horse = &load_image(&data("horse.png"), &ImageOptions::default()).unwrap()[0];
    let grey = load_grey(&data("horse.png")).unwrap();
    let (binary, _) = binarize(&grey, &ImageOptions::default()).unwrap();
    let lowest_row = (0..binary.height())
        .rev()
        .find(|&r| (0..binary.width()).any(|c| binary.get(c, r)))
        .unwrap();
    let (lo, _) = horse.bbox().unwrap();
    assert_eq!(lo.y, (binary.height() - 1 - lowest_row) as f64 - 0.5);
}

#[test]
fn coin_is_one_round_loop() {
    let outlines = load_image(&data("coin.png"), &ImageOptions::default()).unwrap();
    assert_eq!(outlines.len(), 1);
    let coin = &outlines[0];
    assert_eq!(coin.orientation(), Orientation::CounterClockwise);
    // Isoperimetric ratio 4πA/P² is 1 for a circle; the digitised, thresholded
    // coin edge is a little rough.
    let ratio = 4.0 * PI * coin.area() / coin.length().powi(2);
    assert!((ratio - 1.0).abs() < 0.15, "4πA/P² = {ratio}");
    // About 43 px across.
    let (lo, hi) = coin.bbox().unwrap();
    let (w, h) = (hi.x - lo.x, hi.y - lo.y);
    assert!((w - h).abs() < 4.0 && (38.0..48.0).contains(&w), "{w}×{h}");
    assert!(find_corners(coin, &CornerOptions::default()).is_empty());
}

#[test]
fn a_square_image_has_four_corners_and_a_disk_none() {
    let side = 40;
    let grey = GreyImage {
        width: 60,
        height: 60,
        pixels: (0..60 * 60)
            .map(|i| {
                let (c, r) = (i % 60, i / 60);
                if (10..10 + side).contains(&c) && (10..10 + side).contains(&r) {
                    0
                } else {
                    255
                }
            })
            .collect(),
    };
    let options = ImageOptions {
        points: BoundaryPoints::PixelCentres,
        ..ImageOptions::default()
    };
    let square = &grey_outlines(&grey, &options, Path::new("square")).unwrap()[0];
    let corners = find_corners(square, &CornerOptions::default());
    // The loop starts at the top-left pixel and runs counter-clockwise
    // (y up) through the 4 × 39 border pixels.
    assert_eq!(square.len(), 4 * (side - 1));
    assert_eq!(corners, vec![0, 39, 78, 117]);
    let at: Vec<Point> = corners.iter().map(|&i| square.points[i]).collect();
    assert_eq!(
        at,
        vec![
            Point::new(10.0, 49.0),
            Point::new(10.0, 10.0),
            Point::new(49.0, 10.0),
            Point::new(49.0, 49.0),
        ]
    );
    let pieces = split_at(square, &corners);
    assert_eq!(pieces.len(), 4);
    assert!(pieces.iter().all(|p| p.len() == 40));

    let disk = GreyImage {
        width: 80,
        height: 80,
        pixels: (0..80 * 80)
            .map(|i| {
                let (x, y) = ((i % 80) as f64 - 39.5, (i / 80) as f64 - 39.5);
                if x.hypot(y) < 30.0 {
                    200
                } else {
                    30
                }
            })
            .collect(),
    };
    let disk = &grey_outlines(&disk, &ImageOptions::default(), Path::new("disk")).unwrap()[0];
    assert!(find_corners(disk, &CornerOptions::default()).is_empty());
    let (breaks, _) = metabezier::fit::equal_arc_breaks(&disk.points, true, &[], 4).unwrap();
    assert_eq!(breaks.len(), 4);
}

#[test]
fn image_errors_name_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("missing.png");
    let e = load_image(&missing, &ImageOptions::default()).unwrap_err();
    assert!(matches!(e, OutlineError::Io { .. }));
    assert!(e.to_string().contains("missing.png: cannot read"), "{e}");

    let corrupt = dir.path().join("corrupt.png");
    std::fs::write(&corrupt, b"\x89PNG\r\n\x1a\nthis is not really a png").unwrap();
    let e = load_image(&corrupt, &ImageOptions::default()).unwrap_err();
    assert!(matches!(e, OutlineError::Image { .. }), "{e:?}");
    assert!(
        e.to_string()
            .contains("corrupt.png: cannot decode the image"),
        "{e}"
    );

    let text = dir.path().join("text.png");
    std::fs::write(&text, b"hello").unwrap();
    let e = load_image(&text, &ImageOptions::default()).unwrap_err();
    assert!(e.to_string().contains("text.png: cannot decode"), "{e}");

    let uniform = dir.path().join("uniform.png");
    image::GrayImage::from_pixel(16, 9, image::Luma([200]))
        .save(&uniform)
        .unwrap();
    let e = load_image(&uniform, &ImageOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: every pixel has grey level 200, so no threshold separates a shape from the background",
            uniform.display()
        )
    );

    let e = load_image(
        &data("coin.png"),
        &ImageOptions {
            min_area: 1e6,
            ..ImageOptions::default()
        },
    )
    .unwrap_err();
    assert!(matches!(e, OutlineError::NoShape { largest, .. } if largest > 1000.0));
    assert!(
        e.to_string()
            .contains("coin.png: no shape with an area of at least 1000000 px²"),
        "{e}"
    );
}

// ---------------------------------------------------------------- glyphs

/// Checks the sampling of every contour against the exact segments: the
/// break indices are the segment starts and every sample lies on its segment.
fn check_sampling(g: &Glyph, sampling: Sampling) {
    let sampled = g.sample(sampling);
    assert_eq!(sampled.len(), g.contours.len());
    for (contour, s) in g.contours.iter().zip(&sampled) {
        // The segments form a closed chain.
        for (j, seg) in contour.iter().enumerate() {
            assert_eq!(seg.end(), contour[(j + 1) % contour.len()].start());
        }
        assert_eq!(s.breaks.len(), contour.len());
        assert_eq!(s.breaks[0], 0);
        assert!(s.outline.closed);
        for (j, seg) in contour.iter().enumerate() {
            assert_eq!(s.outline.points[s.breaks[j]], seg.start());
            let end = s.breaks.get(j + 1).copied().unwrap_or(s.outline.len());
            assert!(end > s.breaks[j]);
            for &p in &s.outline.points[s.breaks[j]..end] {
                let d = match seg {
                    Segment::Line(a, b) => {
                        let t = ((p - *a).dot(*b - *a) / (*b - *a).hypot2()).clamp(0.0, 1.0);
                        p.distance(a.lerp(*b, t))
                    }
                    Segment::Quad(q) => nearest(q, p).1,
                    Segment::Cubic(c) => nearest(c, p).1,
                };
                assert!(d < 1e-9 * g.units_per_em as f64, "{d}");
            }
        }
        for (i, &(j, t)) in s.params.iter().enumerate() {
            assert_eq!(s.outline.points[i], contour[j].eval(t));
        }
    }
}

#[test]
fn dejavu_s_is_quadratic() {
    let g = load_glyph(&data("DejaVuSans.ttf"), 'S').unwrap();
    assert_eq!(g.units_per_em, 2048);
    assert_eq!(g.height(), 1549.0);
    assert_eq!(g.contours.len(), 1);
    let c = &g.contours[0];
    assert!(c.iter().all(|s| s.degree() <= 2));
    assert!(c.iter().any(|s| matches!(s, Segment::Quad(_))));
    assert!(c.iter().any(|s| matches!(s, Segment::Line(..))));
    check_sampling(&g, Sampling::default());
    check_sampling(&g, Sampling::PerSegment(7));
    let s = &g.sample(Sampling::PerSegment(7))[0];
    assert_eq!(s.outline.len(), 7 * c.len());
    assert_eq!(s.outline.orientation(), Orientation::CounterClockwise);
}

#[test]
fn cantarell_g_is_cubic_with_a_hole() {
    let g = load_glyph(&data("Cantarell-Regular.otf"), 'g').unwrap();
    assert_eq!(g.units_per_em, 1000);
    assert_eq!(g.height(), 719.0);
    assert!(g.contours.iter().flatten().any(|s| s.degree() == 3));
    assert!(g.contours.iter().flatten().all(|s| s.degree() != 2));
    check_sampling(&g, Sampling::default());
    let outlines = g.outlines(Sampling::default());
    assert_eq!(outlines.len(), 2);
    let ccw = outlines
        .iter()
        .filter(|o| o.orientation() == Orientation::CounterClockwise)
        .count();
    assert_eq!(ccw, 1, "one outer contour and one hole");
    // The hole lies inside the outer contour's box.
    let outer = outlines.iter().find(|o| o.signed_area() > 0.0).unwrap();
    let hole = outlines.iter().find(|o| o.signed_area() < 0.0).unwrap();
    let ((olo, ohi), (hlo, hhi)) = (outer.bbox().unwrap(), hole.bbox().unwrap());
    assert!(olo.x <= hlo.x && olo.y <= hlo.y && hhi.x <= ohi.x && hhi.y <= ohi.y);
}

#[test]
fn glyph_errors_name_the_glyph_and_font() {
    let font = data("Cantarell-Regular.otf");
    let e = load_glyph(&font, '漢').unwrap_err();
    assert!(matches!(e, OutlineError::MissingGlyph { glyph: '漢', .. }));
    assert_eq!(
        e.to_string(),
        format!(
            "{}: the font has no glyph for '漢' (U+6F22)",
            font.display()
        )
    );
    let e = load_glyph(&font, ' ').unwrap_err();
    assert!(matches!(e, OutlineError::NoOutline { .. }));
    assert!(
        e.to_string()
            .contains("the glyph for U+0020 has no outline"),
        "{e}"
    );
    let e = load_glyph(&data("horse.png"), 'a').unwrap_err();
    assert!(
        e.to_string().contains("horse.png: cannot read the font"),
        "{e}"
    );
    let e = load_glyph(Path::new("no/such/font.ttf"), 'a').unwrap_err();
    assert!(
        e.to_string().starts_with("no/such/font.ttf: cannot read"),
        "{e}"
    );
}

// ---------------------------------------------------------------- CSV

#[test]
fn csv_files_and_their_errors() {
    let dir = tempfile::tempdir().unwrap();
    let good = dir.path().join("good.csv");
    std::fs::write(&good, "# unit square\nx,y\n0,0\n1,0\n1,1\n0,1\n0,0\n").unwrap();
    let o = load_csv(&good, &CsvOptions::default()).unwrap();
    assert!(o.closed);
    assert_eq!(o.len(), 4);
    assert_eq!(o.signed_area(), 1.0);

    let short = dir.path().join("short.csv");
    std::fs::write(&short, "x,y\n0,0\n1,0\n").unwrap();
    let e = load_csv(&short, &CsvOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}: 2 point(s) found, but an outline needs at least 3",
            short.display()
        )
    );

    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "x,y\n0,0\n1,0\n# comment\n1.5,0..7\n").unwrap();
    let e = load_csv(&bad, &CsvOptions::default()).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:5: column 2 (y): expected a finite number, found \"0..7\"",
            bad.display()
        )
    );
}

// ---------------------------------------------------------------- inputs

#[test]
fn input_strings_load_all_three_kinds() {
    let options = Options::default();
    let horse = parse_input(data("horse.png").to_str().unwrap()).unwrap();
    assert_eq!(load(&horse, &options).unwrap()[0].len(), 2644);

    let spec = format!("font:{}:U+0067", data("Cantarell-Regular.otf").display());
    let g = parse_input(&spec).unwrap();
    assert!(matches!(g, Input::Glyph { glyph: 'g', .. }));
    assert_eq!(load(&g, &options).unwrap().len(), 2);

    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("tri.CSV");
    std::fs::write(&csv, "0,0\n3,0\n0,4\n").unwrap();
    let c = parse_input(csv.to_str().unwrap()).unwrap();
    let o = load(&c, &options).unwrap();
    assert_eq!(o.len(), 1);
    assert!(!o[0].closed);
    assert_eq!(o[0].length(), 8.0);
}

// ------------------------------------------------- corners and arc splits

/// A closed circle of radius 10 sampled at `n` points.
fn circle(n: usize) -> Outline {
    let pts = (0..n)
        .map(|i| {
            let a = 2.0 * PI * i as f64 / n as f64;
            Point::new(10.0 * a.cos(), 10.0 * a.sin())
        })
        .collect();
    Outline::new(pts, true)
}

#[test]
fn a_circle_has_none_and_is_split_by_arc_length() {
    let c = circle(100);
    assert!(find_corners(&c, &CornerOptions::default()).is_empty());
    // Without corners, the fit splits at equal arc length from index 0.
    let (b, _) = equal_arc_breaks(&c.points, true, &[], 4).unwrap();
    assert_eq!(b, vec![0, 25, 50, 75]);
}

#[test]
fn open_outlines_keep_their_ends_and_split_long_pieces() {
    // An L: 10 points along x, then 10 up.
    let mut pts: Vec<Point> = (0..10).map(|i| Point::new(i as f64, 0.0)).collect();
    pts.extend((1..=10).map(|j| Point::new(9.0, j as f64)));
    let l = Outline::new(pts, false);
    let opts = CornerOptions {
        k: 3,
        angle_deg: 60.0,
    };
    assert_eq!(find_corners(&l, &opts), vec![9]);
    let (b, corner) = equal_arc_breaks(&l.points, false, &[9], 3).unwrap();
    assert_eq!(b.len(), 3);
    assert!(b.contains(&9));
    assert!(corner[b.iter().position(|&i| i == 9).unwrap()]);
    let mut b = b;
    b.push(19);
    let pieces = split_at(&l, &b);
    assert_eq!(pieces.len(), 3);
    assert_eq!(pieces[0].points[0], Point::ZERO);
    assert_eq!(pieces[2].points.last(), Some(&Point::new(9.0, 10.0)));
}

#[test]
fn one_corner_on_a_closed_outline_gets_more_pieces() {
    // A teardrop: a circle with one sharp point.
    let mut c = circle(60);
    c.points[0] = Point::new(25.0, 0.0);
    let corners = find_corners(&c, &CornerOptions::default());
    assert_eq!(corners, vec![0]);
    let (b, _) = equal_arc_breaks(&c.points, true, &corners, 3).unwrap();
    assert_eq!(b.len(), 3);
    assert_eq!(b[0], 0);
    assert_eq!(split_at(&c, &b).len(), 3);
}
