//! The shape `metabezier fit` traces in a PNG, as a PBM for potrace (`make
//! peer-potrace`): the luminance, Otsu's threshold and the foreground class
//! of the default image options, the shape's pixels black (1).
//!
//! ```text
//! cargo run --release --example shape_pbm -- data/outlines/horse.png horse.pbm
//! potrace -s -o horse-potrace.svg horse.pbm
//! metabezier score data/outlines/horse.png horse-potrace.svg --offset -0.5,-0.5
//! ```
//!
//! potrace puts pixel corners at integer coordinates with y up from the
//! bottom edge, `metabezier` pixel centres: hence `--offset -0.5,-0.5`.

use std::error::Error;
use std::path::Path;

use metabezier::outline::{binarize, load_grey, ImageOptions};

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [input, output] = &args[..] else {
        return Err("usage: shape_pbm INPUT.png OUTPUT.pbm".into());
    };
    let grey = load_grey(Path::new(input))?;
    let (binary, threshold) =
        binarize(&grey, &ImageOptions::default()).ok_or("one grey level: no threshold")?;
    let (w, h) = (binary.width(), binary.height());
    // P4: rows of bits, most significant first, each row padded to a byte.
    let mut pbm = format!("P4\n{w} {h}\n").into_bytes();
    for row in 0..h {
        for byte in 0..w.div_ceil(8) {
            let mut b = 0u8;
            for bit in 0..8 {
                let col = byte * 8 + bit;
                if col < w && binary.get(col, row) {
                    b |= 0x80 >> bit;
                }
            }
            pbm.push(b);
        }
    }
    std::fs::write(output, pbm)?;
    eprintln!("{input}: {w} x {h}, threshold {threshold}");
    Ok(())
}
