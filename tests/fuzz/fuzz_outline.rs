//! Mutational fuzz of the outline readers: SVG curves (then scored), PNG
//! images (then thresholded and border-followed), font glyphs (then
//! sampled) and CSV point lists. No panic, no hang, and no mutant may
//! allocate beyond its reader's limit (each justified at its call). See
//! `tests/fuzz_common` for the loop.
use crate::common;
use crate::fuzz_common;

use std::path::{Path, PathBuf};
use std::sync::Mutex;

use metabezier::geometry::Point;
use metabezier::outline::{
    csv_from_bytes, glyph_from_bytes, grey_from_bytes, grey_outlines, svg_from_str, CsvOptions,
    ImageOptions, Outline, Sampling, MAX_DEFLATE_RATIO, MAX_GLYPH_SAMPLES, MAX_GLYPH_SEGMENTS,
    MAX_IMAGE_PIXELS,
};
use metabezier::reconstruction::{score, Source};

/// The allocator's count is global: one test of this binary at a time, so
/// that no other test's allocations land inside a reader's limit.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const MIB: usize = 1 << 20;

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/outlines")
        .join(name)
}

/// The largest input, for limits that scale with the input.
fn largest(inputs: &[Vec<u8>]) -> usize {
    inputs.iter().map(Vec::len).max().unwrap_or(0)
}

#[test]
fn svg_curves_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let inputs: Vec<Vec<u8>> = vec![
        std::fs::read(data("horse-potrace.svg")).unwrap(),
        br#"<?xml version="1.0"?>
<!-- groups, transforms, comments -->
<svg xmlns="http://www.w3.org/2000/svg" width="20pt" height="10pt" viewBox="0 0 20 10">
<g transform="translate(0,10) scale(0.1,-0.1)">
  <g transform="matrix(1 0 0 1 5 5)"><path d="M10 20 l30 0 0 40 z m 5 5 h 10 v 10 h-10z"/></g>
  <path d="M0 0 C 10 0 10 10 0 10 S -10 20 0 20 Q 5 25 10 20 T 20 20"/>
</g>
<path transform="translate(1 1)" d="M 1 1 L 2 1 2 2 1 2 Z"/>
</svg>"#
            .to_vec(),
        br#"<svg viewBox="-5 -5 10 10"><defs><path id="a" d="M0 0 L 1 1"/></defs>
<g display="none"><path d="M0 0 L 2 2"/></g><symbol><path d="M0 0 L3 3"/></symbol>
<g style="stroke:black"><path d="m-1-1 2 0 0 2-2 0z"/></g></svg>"#
            .to_vec(),
        b"<svg><path d='M0,0 H1e15 V-1e15 h-.5e1 v.5 z'/></svg>".to_vec(),
        // Dense transform lists, and multi-byte text (U+2003, U+00A0, 馬)
        // for the mutator to move next to numbers.
        "<svg><title>horse\u{2003}馬\u{a0}</title><g transform=\"translate(1,2)scale(3)\">\
<g transform=\"matrix(1,0,0,1,0,0) translate(4) scale(1 -1)\"><path transform=\"scale(2)\" \
d=\"M0 0 L1\u{a0}1 2 2\"/><path d=\"M 0 0 Q 1 1 2 0\"/></g></g></svg>"
            .as_bytes()
            .to_vec(),
    ];
    // The points the curves are scored against.
    let square = Source::from_outline(
        "square",
        Outline::new(
            vec![
                Point::ZERO,
                Point::new(10.0, 0.0),
                Point::new(10.0, 10.0),
                Point::new(0.0, 10.0),
            ],
            true,
        ),
    );
    // A segment takes 72 bytes and can be written in 2 ("0 " after an H);
    // its subpath's vector may hold twice what it needs while growing (so
    // 72 bytes per input byte), the outline frame copies the segments (36),
    // and score boxes them (20): 128 bytes per input byte. The fixed 1 MiB
    // covers the tag and attribute lists and the error messages.
    let limit = 128 * largest(&inputs) + MIB;
    let file = Path::new("mutant.svg");
    let tally = fuzz_common::fuzz("svg", &inputs, limit, |bytes| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return false;
        };
        let Ok(paths) = svg_from_str(text, file) else {
            return false;
        };
        assert!(paths.segment_count() > 0, "an accepted SVG draws something");
        let Ok(s) = score(&square, &paths.to_frame(Point::new(-0.5, -0.5))) else {
            return false;
        };
        assert!(
            s.total.max_distance.is_finite() && s.total.rms_distance.is_finite(),
            "{s:?}"
        );
        true
    });
    eprintln!("{tally:?}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

/// A PNG file of `rows` of raw scanlines (filter byte 0 on each row):
/// `bits` per sample, colour type `colour`, with a 3-colour palette when
/// `plte`.
fn png(width: u32, height: u32, bits: u8, colour: u8, rows: &[Vec<u8>], plte: bool) -> Vec<u8> {
    use std::io::Write;
    let chunk = |out: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]| {
        out.extend_from_slice(&(data.len() as u32).to_be_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(data);
        let mut crc = flate2::Crc::new();
        crc.update(kind);
        crc.update(data);
        out.extend_from_slice(&crc.sum().to_be_bytes());
    };
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    let mut ihdr = Vec::new();
    ihdr.extend_from_slice(&width.to_be_bytes());
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[bits, colour, 0, 0, 0]);
    chunk(&mut out, b"IHDR", &ihdr);
    if plte {
        chunk(&mut out, b"PLTE", &[0, 0, 0, 255, 255, 255, 128, 0, 255]);
    }
    let mut raw = Vec::new();
    for r in rows {
        raw.push(0);
        raw.extend_from_slice(r);
    }
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(&raw).unwrap();
    chunk(&mut out, b"IDAT", &z.finish().unwrap());
    chunk(&mut out, b"IEND", &[]);
    out
}

#[test]
fn png_images_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    // The horse at a quarter of its size (100 × 82, RGBA): the full image
    // would make each accepted mutant take a millisecond.
    let horse = image::open(data("horse.png")).unwrap();
    let small = horse.resize_exact(100, 82, image::imageops::FilterType::Nearest);
    let mut horse_png = Vec::new();
    small
        .write_to(
            &mut std::io::Cursor::new(&mut horse_png),
            image::ImageFormat::Png,
        )
        .unwrap();
    // A disc in 1-bit grey, 2-bit palette and 16-bit grey + alpha.
    let disc = |x: u32, y: u32| (x as i32 - 8).pow(2) + (y as i32 - 8).pow(2) < 30;
    let one_bit: Vec<Vec<u8>> = (0..16)
        .map(|y| {
            (0..2)
                .map(|b| (0..8).fold(0u8, |acc, i| acc << 1 | u8::from(!disc(8 * b + i, y))))
                .collect()
        })
        .collect();
    let palette: Vec<Vec<u8>> = (0..16)
        .map(|y| {
            (0..4)
                .map(|b| {
                    (0..4).fold(0u8, |acc, i| {
                        acc << 2 | if disc(4 * b + i, y) { 0 } else { 1 }
                    })
                })
                .collect()
        })
        .collect();
    let wide: Vec<Vec<u8>> = (0..16)
        .map(|y| {
            (0..16)
                .flat_map(|x| {
                    let v: u16 = if disc(x, y) { 0x1000 } else { 0xf000 };
                    [v.to_be_bytes(), 0xffffu16.to_be_bytes()].concat()
                })
                .collect()
        })
        .collect();
    let inputs = vec![
        std::fs::read(data("coin.png")).unwrap(),
        horse_png,
        png(16, 16, 1, 0, &one_bit, false),
        png(16, 16, 2, 3, &palette, true),
        png(16, 16, 16, 4, &wide, false),
    ];
    // What a header alone can make the reader allocate is the decoded image
    // for the pixels it declares, before the data is read: at most
    // P = min(MAX_IMAGE_PIXELS, 8 · 1032 · len) pixels (the pixel data must
    // fit in deflate's 1032:1 of the file, and 1-bit pixels decode to a byte
    // each), at up to 8 bytes a pixel (16-bit RGBA). A mutant whose data does
    // decode is an image of about the seeds' size, whose grey, binary and
    // border data take well under the fixed 64 MiB.
    let len = largest(&inputs) as u64;
    let pixels = MAX_IMAGE_PIXELS.min(8 * MAX_DEFLATE_RATIO * len);
    let limit = 8 * pixels as usize + 64 * MIB;
    let file = Path::new("mutant.png");
    let options = ImageOptions {
        min_area: 4.0,
        ..ImageOptions::default()
    };
    let mut n = 0usize;
    let tally = fuzz_common::fuzz("png", &inputs, limit, |bytes| {
        // Every other mutant with its CRCs repaired.
        n += 1;
        let repaired;
        let bytes = if n.is_multiple_of(2) {
            repaired = common::fix_png_crcs(bytes.to_vec());
            &repaired[..]
        } else {
            bytes
        };
        let Ok(grey) = grey_from_bytes(bytes, file) else {
            return false;
        };
        grey_outlines(&grey, &options, file).is_ok()
    });
    eprintln!("{tally:?}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

#[test]
fn font_glyphs_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let inputs = vec![
        std::fs::read(data("DejaVuSans.ttf")).unwrap(),
        std::fs::read(data("Cantarell-Regular.otf")).unwrap(),
    ];
    // The reader copies nothing of the font; a glyph draws at most
    // MAX_GLYPH_SEGMENTS segments of 72 bytes (twice that while its vector
    // grows, and 8 sampled points of 16 bytes each to orient it), and its
    // sampling places at most MAX_GLYPH_SAMPLES points of 16 bytes with a
    // (segment, t) pair of 16 (twice that while growing).
    let limit = MAX_GLYPH_SEGMENTS * (2 * 72 + 8 * 16) + MAX_GLYPH_SAMPLES * 2 * 32 + 16 * MIB;
    let file = Path::new("mutant.ttf");
    let tally = fuzz_common::fuzz("glyph", &inputs, limit, |bytes| {
        let mut any = false;
        // 'é' is a composite in DejaVu Sans; ' ' draws nothing.
        for c in ['g', 'S', '&', 'é', ' '] {
            if let Ok(g) = glyph_from_bytes(bytes, file, c) {
                if g.check_sample_count(Sampling::default(), 3).is_ok() {
                    let sampled = g.sample_at_least(Sampling::default(), 3);
                    assert!(sampled
                        .iter()
                        .all(|s| s.outline.points.iter().all(|p| p.is_finite())));
                    any = true;
                }
            }
        }
        any
    });
    eprintln!("{tally:?}");
    assert!(tally.accepted > 0, "{tally:?}");
}

#[test]
fn csv_points_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let mut circle = String::from("x,y\n# a circle of 200 points\n");
    for i in 0..200 {
        let t = i as f64 * std::f64::consts::TAU / 200.0;
        circle.push_str(&format!("{:.6},{:.6}\n", 50.0 * t.cos(), 50.0 * t.sin()));
    }
    circle.push_str("50.000000,0.000000\n");
    let inputs = vec![
        circle.into_bytes(),
        b"# square\r\n0,0\r\n 10 , 0 \r\n10,10\r\n\r\n0,10\r\n0,0\r\n".to_vec(),
        b"1e-3,2.5E2\n-4,+5\n.5,6.\n7,-8e-1\n9,1e15\n".to_vec(),
    ];
    // A point takes 16 bytes and at least 4 of text ("0,0" and a newline),
    // twice that while the vector grows: 8 bytes per input byte; the CSV
    // reader's record buffers hold one line, and its 8 KiB input buffer and
    // the messages fit in the fixed 1 MiB.
    let limit = 8 * largest(&inputs) + MIB;
    let file = Path::new("mutant.csv");
    let tally = fuzz_common::fuzz("csv", &inputs, limit, |bytes| {
        csv_from_bytes(bytes, file, &CsvOptions::default()).is_ok()
    });
    eprintln!("{tally:?}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}
