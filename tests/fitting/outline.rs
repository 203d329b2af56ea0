//! Outline input on the vendored real data (data/outlines/, see PROVENANCE.md)
//! and the user-facing errors.

use crate::common;

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

// ------------------------------------------- hardening (issue 31, round 2)

/// `metabezier score` used to panic (exit 101) on a transform whose ')'
/// comes before its '(' (3 of 1,000 SVG mutants), and on a number that
/// starts with a multi-byte space (U+2003): both sliced inside the text.
#[test]
fn svg_tokenizer_slices_never_panic() {
    let file = Path::new("t.svg");
    let e = svg_from_str(
        "<svg>\n<g transform=\"a)b(\"><path d=\"M0 0 L1 1\"/></g></svg>",
        file,
    )
    .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.svg:2:15: unsupported transform \"a)b(\"; supported: translate(x [y]), scale(x [y]), matrix(a b c d e f)"
    );
    let e = svg_from_str(
        "<svg><path transform=\")scale(2)\" d=\"M0 0 L1 1\"/></svg>",
        file,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("unsupported transform \")scale(2)\""),
        "{e}"
    );
    let e = svg_from_str("<svg><path d=\"M\u{2003}0 0 L1 1\"/></svg>", file).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.svg:1:16: expected a number, found \"\u{2003}\""
    );
    let e = svg_from_str("<svg><path d=\"M0 0 L1\u{a0}1\"/></svg>", file).unwrap_err();
    assert!(e.to_string().contains("expected a number"), "{e}");
    // A long word is quoted in part only.
    let long = "x".repeat(10_000);
    let e = svg_from_str(&format!("<svg><path d=\"M0 {long}\"/></svg>"), file).unwrap_err();
    assert!(e.to_string().len() < 200, "{e}");
}

/// An SVG that draws nothing, or whose coordinates overflow, used to be
/// scored as `inf` with exit 0.
#[test]
fn svg_without_a_segment_or_with_huge_coordinates_is_refused() {
    let file = Path::new("t.svg");
    let e = svg_from_str("<svg>\n<path d=\"M0 0\"/>\n<path d=\"\"/></svg>", file).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.svg: no drawable segment: 2 rendered <path> element(s) draw no line or curve; expected at least one segment to score"
    );
    let e = svg_from_str("<svg>\n<path d=\"M 0 0 L 1e308 0\"/></svg>", file).unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.svg:2:16: a coordinate (after the transforms) 1e308 is beyond ±1e15, the range of coordinates this tool scores (distances and their squares must stay finite)"
    );
    // In range in the file, out of range after a transform or a relative move.
    let e = svg_from_str(
        "<svg><g transform=\"scale(1e300)\"><path d=\"M0 0 L 1 1\"/></g></svg>",
        file,
    )
    .unwrap_err();
    assert!(e.to_string().contains("t.svg:1:48: a coordinate"), "{e}");
    let e = svg_from_str("<svg><path d=\"m 0 0 l 1e15 0 1e15 0\"/></svg>", file).unwrap_err();
    assert!(
        e.to_string()
            .contains("t.svg:1:30: a coordinate (after the transforms) 2e15 is beyond"),
        "{e}"
    );
    let e = svg_from_str(
        "<svg><g transform=\"scale(1e200) scale(1e200) scale(0)\"><path d=\"M0 0 L 1 1\"/></g></svg>",
        file,
    )
    .unwrap_err();
    assert!(e.to_string().contains("NaN is beyond"), "{e}");
    let e = svg_from_str(
        "<svg viewBox=\"0 0 1e300 1\"><path d=\"M0 0 L 1 1\"/></svg>",
        file,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("t.svg:1:15: the viewBox value 1e300 is beyond ±1e15"),
        "{e}"
    );
    let e = svg_from_str(
        "<svg height=\"1e300pt\"><path d=\"M0 0 L 1 1\"/></svg>",
        file,
    )
    .unwrap_err();
    assert!(e.to_string().contains("the height 1e300 is beyond"), "{e}");
    // 1e15 itself is accepted.
    assert!(svg_from_str("<svg><path d=\"M-1e15 0 L 1e15 1\"/></svg>", file).is_ok());
}

/// Paths in containers that are never rendered (`<defs>` and its kin, or
/// `display="none"`) used to be scored as curves.
#[test]
fn svg_paths_that_are_not_rendered_are_skipped() {
    let file = Path::new("t.svg");
    let svg = r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:svg="http://www.w3.org/2000/svg">
<defs><path id="a" d="M0 0 L 5 5"/><g><path d="M0 0 L 6 6"/></g></defs>
<symbol id="s"><path d="M0 0 L 7 7"/></symbol>
<clipPath id="c"><path d="M0 0 L 8 8"/></clipPath>
<mask id="m"><path d="M0 0 L 9 9"/></mask>
<pattern id="p"><path d="M0 0 L 9 9"/></pattern>
<marker id="k"><path d="M0 0 L 9 9"/></marker>
<svg:defs><path d="M0 0 L 9 9"/></svg:defs>
<g display="none"><path d="M0 0 L 9 9"/></g>
<path style="fill:red; display : none" d="M0 0 L 9 9"/>
<g transform="translate(1,0)"><path d="M0 0 L 1 0"/></g>
<path d="M0 2 L 1 2"/>
</svg>"#;
    let p = svg_from_str(svg, file).unwrap();
    assert_eq!(p.segment_count(), 2);
    assert_eq!(p.skipped, 10);
    assert_eq!(
        p.subpaths[0][0],
        Segment::Line(Point::new(1.0, 0.0), Point::new(2.0, 0.0))
    );
    // Only skipped paths: nothing to score, and the message says why.
    let e = svg_from_str("<svg><defs><path d=\"M0 0 L 1 1\"/></defs></svg>", file).unwrap_err();
    assert!(
        e.to_string().starts_with(
            "t.svg: no drawable segment: 0 rendered <path> element(s) draw no line or curve, and 1 <path> element(s) inside non-rendered containers"
        ),
        "{e}"
    );
    // A transform inside a skipped container is not read, so not refused.
    assert!(svg_from_str(
        "<svg><defs transform=\"rotate(3)\"><path d=\"M0 0 A 1 1 0 0 1 1 1\"/></defs><path d=\"M0 0 L1 1\"/></svg>",
        file
    )
    .is_ok());
    // <use> draws by reference, which this reader cannot follow.
    let e = svg_from_str(
        "<svg><defs><path id=\"a\" d=\"M0 0 L 1 1\"/></defs>\n<use href=\"#a\"/><path d=\"M0 0 L1 1\"/></svg>",
        file,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("t.svg:2:1: unsupported element <use>"),
        "{e}"
    );
}

/// The byte range of table `tag` in a font file.
fn table_range(font: &[u8], tag: &[u8; 4]) -> (usize, usize) {
    let n = u16::from_be_bytes([font[4], font[5]]) as usize;
    (0..n)
        .map(|i| &font[12 + 16 * i..28 + 16 * i])
        .find(|r| &r[..4] == tag)
        .map(|r| {
            let be = |k: usize| u32::from_be_bytes([r[k], r[k + 1], r[k + 2], r[k + 3]]) as usize;
            (be(8), be(8) + be(12))
        })
        .unwrap()
}

/// The byte range of the TrueType glyph for `c` in the font file.
fn glyph_slot(font: &[u8], c: char) -> (usize, usize) {
    let face = ttf_parser::Face::parse(font, 0).unwrap();
    let id = face.glyph_index(c).unwrap().0 as usize;
    let (head, _) = table_range(font, b"head");
    let long = font[head + 51] == 1;
    let (loca, _) = table_range(font, b"loca");
    let (glyf, _) = table_range(font, b"glyf");
    let at = |i: usize| {
        if long {
            let k = loca + 4 * i;
            u32::from_be_bytes([font[k], font[k + 1], font[k + 2], font[k + 3]]) as usize
        } else {
            let k = loca + 2 * i;
            2 * u16::from_be_bytes([font[k], font[k + 1]]) as usize
        }
    };
    (glyf + at(id), glyf + at(id + 1))
}

/// A truncated font used to say "the glyph has no outline" (the parser
/// treats a table beyond the end of the file as absent).
#[test]
fn truncated_and_malformed_fonts_say_so() {
    let dir = tempfile::tempdir().unwrap();
    for (name, table) in [
        ("Cantarell-Regular.otf", "CFF "),
        ("DejaVuSans.ttf", "glyf"),
    ] {
        let font = std::fs::read(data(name)).unwrap();
        let cut = &font[..font.len() * 3 / 10];
        let path = dir.path().join(name);
        std::fs::write(&path, cut).unwrap();
        let e = load_glyph(&path, 'g').unwrap_err();
        assert!(matches!(e, OutlineError::MalformedFont { .. }), "{e:?}");
        let (start, end) = table_range(&font, table.as_bytes().try_into().unwrap());
        assert_eq!(
            e.to_string(),
            format!(
                "{}: the font file is truncated: its table directory puts table '{table}' at bytes {start}..{end}, but the file has {} bytes",
                path.display(),
                cut.len()
            )
        );
        let e = glyph_from_bytes(&font[..100], &path, 'g').unwrap_err();
        assert!(
            e.to_string()
                .contains("the font file is truncated: its table directory lists"),
            "{e}"
        );
    }
    // A TrueType glyph whose contour count runs past its data.
    let mut font = std::fs::read(data("DejaVuSans.ttf")).unwrap();
    let (g, _) = glyph_slot(&font, 'g');
    font[g..g + 2].copy_from_slice(&0x7fffu16.to_be_bytes());
    let e = glyph_from_bytes(&font, Path::new("d.ttf"), 'g').unwrap_err();
    assert!(matches!(e, OutlineError::MalformedGlyph { .. }), "{e:?}");
    assert!(
        e.to_string().starts_with(
            "d.ttf: the font file is malformed: the outline of the glyph for 'g' (U+0067), glyph id 74 in table 'glyf', cannot be read: ttf-parser"
        ),
        "{e}"
    );
    // A CFF table shorter than its own offsets (inside the file).
    let mut font = std::fs::read(data("Cantarell-Regular.otf")).unwrap();
    let n = u16::from_be_bytes([font[4], font[5]]) as usize;
    let record = (0..n)
        .map(|i| 12 + 16 * i)
        .find(|&r| &font[r..r + 4] == b"CFF ")
        .unwrap();
    font[record + 12..record + 16].copy_from_slice(&64u32.to_be_bytes());
    let e = glyph_from_bytes(&font, Path::new("c.otf"), 'g').unwrap_err();
    assert_eq!(
        e.to_string(),
        "c.otf: the font file is malformed: ttf-parser cannot read its 'CFF ' table"
    );
    // A glyph that truly draws nothing still says so.
    let e = load_glyph(&data("DejaVuSans.ttf"), ' ').unwrap_err();
    assert!(matches!(e, OutlineError::NoOutline { .. }), "{e:?}");
}

/// Nested TrueType composites multiply their references: 12 components of
/// 12 components of … four deep make 22,621 references, beyond
/// `MAX_GLYPH_COMPONENTS` (counting stops at 11,311, past it), refused
/// before `ttf-parser` walks them; and a
/// composite containing itself is refused before `ttf-parser` follows the
/// cycle exponentially to its nesting limit.
#[test]
fn composite_glyph_bombs_are_refused_before_they_are_walked() {
    let original = std::fs::read(data("DejaVuSans.ttf")).unwrap();
    let face = ttf_parser::Face::parse(&original, 0).unwrap();
    let id = |c: char| face.glyph_index(c).unwrap().0;
    // Each level's glyph is a composite of 12 copies of the next one; the
    // last draws nothing (a glyph of 0 contours).
    let chain = ['m', 'w', 'M', 'W', 'B'];
    let mut font = original.clone();
    for (k, &c) in chain.iter().enumerate() {
        let (start, end) = glyph_slot(&original, c);
        let mut data = vec![0xff, 0xff, 0, 0, 0, 0, 0, 0, 0, 0];
        if k + 1 == chain.len() {
            data[..2].copy_from_slice(&[0, 0]);
        } else {
            for j in 0..12 {
                // ARGS_ARE_XY_VALUES, MORE_COMPONENTS but on the last.
                let flags: u16 = 0x0002 | if j < 11 { 0x0020 } else { 0 };
                data.extend_from_slice(&flags.to_be_bytes());
                data.extend_from_slice(&id(chain[k + 1]).to_be_bytes());
                data.extend_from_slice(&[0, 0]);
            }
        }
        assert!(data.len() <= end - start, "{c}: {} bytes", end - start);
        font[start..start + data.len()].copy_from_slice(&data);
    }
    let e = glyph_from_bytes(&font, Path::new("bomb.ttf"), 'm').unwrap_err();
    assert_eq!(
        e.to_string(),
        "bomb.ttf: the glyph for 'm' (U+006D) has at least 11311 component references, beyond this reader's limit of 10000 per glyph (the font is malformed, or far beyond any real glyph)"
    );
    // Three levels (1 + 12 + 12 · 13 · 12 = 1885 references) are within the limit.
    let e = glyph_from_bytes(&font, Path::new("bomb.ttf"), 'w').unwrap_err();
    assert!(matches!(e, OutlineError::NoOutline { .. }), "{e:?}");
    // A glyph made of 12 copies of itself.
    let mut font = original.clone();
    let (start, _) = glyph_slot(&original, 'm');
    let mut data = vec![0xff, 0xff, 0, 0, 0, 0, 0, 0, 0, 0];
    for j in 0..12 {
        let flags: u16 = 0x0002 | if j < 11 { 0x0020 } else { 0 };
        data.extend_from_slice(&flags.to_be_bytes());
        data.extend_from_slice(&id('m').to_be_bytes());
        data.extend_from_slice(&[0, 0]);
    }
    font[start..start + data.len()].copy_from_slice(&data);
    let e = glyph_from_bytes(&font, Path::new("cycle.ttf"), 'm').unwrap_err();
    assert!(
        e.to_string()
            .ends_with("cannot be read: its components refer back to one another (a cycle)"),
        "{e}"
    );
}

/// A glyph's sampling is bounded: a tiny spacing on a real glyph would
/// place more than `MAX_GLYPH_SAMPLES` points.
#[test]
fn glyph_sampling_is_bounded() {
    let g = load_glyph(&data("DejaVuSans.ttf"), 'g').unwrap();
    assert!(g.check_sample_count(Sampling::default(), 1).is_ok());
    let n = g.sample_count(Sampling::default(), 1);
    assert_eq!(
        n,
        g.sample(Sampling::default())
            .iter()
            .map(|s| s.outline.len())
            .sum::<usize>()
    );
    let e = g
        .check_sample_count(Sampling::Spacing(1e-3), 1)
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("sample points, beyond this reader's limit of 1000000 per glyph"),
        "{e}"
    );
}

/// `png` with its header's width, height and bit depth replaced (CRC fixed).
fn with_header(png: &[u8], width: u32, height: u32, depth: u8) -> Vec<u8> {
    let mut p = png.to_vec();
    p[16..20].copy_from_slice(&width.to_be_bytes());
    p[20..24].copy_from_slice(&height.to_be_bytes());
    p[24] = depth;
    common::fix_png_crcs(p)
}

/// A PNG header declaring more pixels than the file can hold used to make
/// the decoder allocate them all before finding the data missing.
#[test]
fn png_headers_are_checked_against_the_limits_and_the_file() {
    let coin = std::fs::read(data("coin.png")).unwrap();
    let file = Path::new("c.png");
    // 66 × 64 8-bit grey: 4224 bytes of pixels in 3131 bytes of file. As
    // 4096 × 4096 it would need 16 MiB: more than 1032 × 3098 bytes.
    let e = grey_from_bytes(&with_header(&coin, 4096, 4096, 8), file).unwrap_err();
    assert!(matches!(e, OutlineError::ImageData { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "c.png: the PNG header declares 4096×4096 pixels at 8 bits each, 16777216 bytes of pixel data, but the 3098 bytes after the header decompress to at most 3198168 (deflate expands at most 1032:1): the file is truncated or its header is corrupt"
    );
    let e = grey_from_bytes(&with_header(&coin, 70_000, 1, 8), file).unwrap_err();
    assert!(matches!(e, OutlineError::ImageTooLarge { .. }), "{e:?}");
    assert!(
        e.to_string().starts_with(
            "c.png: the PNG header declares 70000×1 pixels, beyond this reader's limits"
        ),
        "{e}"
    );
    let e = grey_from_bytes(&with_header(&coin, 5000, 5000, 1), file).unwrap_err();
    assert!(matches!(e, OutlineError::ImageTooLarge { .. }), "{e:?}");
    let e = grey_from_bytes(&with_header(&coin, 0, 64, 8), file).unwrap_err();
    assert!(
        matches!(e, OutlineError::EmptyImage { width: 0, .. }),
        "{e:?}"
    );
    // Within what the file could hold, the decoder finds the data short.
    let e = grey_from_bytes(&with_header(&coin, 660, 640, 8), file).unwrap_err();
    assert!(matches!(e, OutlineError::Image { .. }), "{e:?}");
    // The file itself reads as before.
    let g = grey_from_bytes(&coin, file).unwrap();
    assert_eq!((g.width, g.height), (66, 64));
    assert_eq!(g, load_grey(&data("coin.png")).unwrap());
}

/// A CSV outline is capped in points and in the length of a line.
#[test]
fn csv_points_and_lines_are_capped() {
    let file = Path::new("p.csv");
    let opts = CsvOptions::default();
    let line = format!("0,{}\n", "1".repeat(2000));
    let e = csv_from_bytes(format!("0,0\n1,0\n{line}").as_bytes(), file, &opts).unwrap_err();
    assert_eq!(
        e.to_string(),
        "p.csv:3: at least 2002 bytes on one line, beyond this reader's limit of 1024 (expected one \"x,y\" pair per line)"
    );
    // A long comment is fine.
    let text = format!("# {}\n0,0\n1,0\n0,1\n", "c".repeat(5000));
    assert_eq!(
        csv_from_bytes(text.as_bytes(), file, &opts).unwrap().len(),
        3
    );
    let mut text = String::with_capacity(4 * (MAX_CSV_POINTS + 1));
    for i in 0..=MAX_CSV_POINTS {
        text.push_str(if i % 2 == 0 { "0,0\n" } else { "1,1\n" });
    }
    let e = csv_from_bytes(text.as_bytes(), file, &opts).unwrap_err();
    assert_eq!(
        e.to_string(),
        "p.csv:10000001: at least 10000001 points, beyond this reader's limit of 10000000 (expected one \"x,y\" pair per line)"
    );
}

/// DejaVu Sans with each glyph of `chain` but the last made a composite of
/// `copies` copies of the next one (each offset by 10 units, so that no two
/// copies coincide); the last keeps its own outline.
fn composite_chain(chain: &[char], copies: usize) -> Vec<u8> {
    let original = std::fs::read(data("DejaVuSans.ttf")).unwrap();
    let face = ttf_parser::Face::parse(&original, 0).unwrap();
    let mut font = original.clone();
    for w in chain.windows(2) {
        let (start, end) = glyph_slot(&original, w[0]);
        let mut data = vec![0xff, 0xff, 0, 0, 0, 0, 0, 0, 0, 0];
        for j in 0..copies {
            // ARG_1_AND_2_ARE_WORDS | ARGS_ARE_XY_VALUES, MORE_COMPONENTS but on the last.
            let flags: u16 = 0x0003 | if j + 1 < copies { 0x0020 } else { 0 };
            data.extend_from_slice(&flags.to_be_bytes());
            data.extend_from_slice(&face.glyph_index(w[1]).unwrap().0.to_be_bytes());
            data.extend_from_slice(&(10 * j as i16).to_be_bytes());
            data.extend_from_slice(&(10 * j as i16).to_be_bytes());
        }
        assert!(data.len() <= end - start, "{}: {} bytes", w[0], end - start);
        font[start..start + data.len()].copy_from_slice(&data);
    }
    font
}

/// A composite that multiplies a drawing (within the reference limit) used
/// to be drawn, stored and oriented in full: 1,728 copies of 'o' draw about
/// 50,000 segments, and 1,728 copies of '.' make 1,728 contours, each
/// tested against all the others.
#[test]
fn glyphs_that_draw_too_much_are_stopped() {
    let font = composite_chain(&['m', 'w', 'M', 'o'], 12);
    let e = glyph_from_bytes(&font, Path::new("o.ttf"), 'm').unwrap_err();
    assert_eq!(
        e.to_string(),
        "o.ttf: the glyph for 'm' (U+006D) has at least 20001 segments, beyond this reader's limit of 20000 per glyph (the font is malformed, or far beyond any real glyph)"
    );
    // One level less (144 copies of 'o') is read.
    let g = glyph_from_bytes(&font, Path::new("o.ttf"), 'w').unwrap();
    assert_eq!(g.contours.len(), 288);
    let font = composite_chain(&['m', 'w', 'M', '.'], 12);
    let e = glyph_from_bytes(&font, Path::new("p.ttf"), 'm').unwrap_err();
    assert!(
        e.to_string()
            .contains("has at least 1728 contours, beyond this reader's limit of 1000 per glyph"),
        "{e}"
    );
}
