//! Loaders stay near-linear: a 200,000-point CSV outline and a spec whose
//! algorithm grid has 10,000 cells (the figures of the hardening work;
//! both were quadratic once); and the outline readers on the vendored
//! files (PNG, SVG, TrueType and CFF glyphs), whose limit checks must cost
//! nothing measurable.

use std::path::Path;

use criterion::Criterion;
use metabezier::experiment::Spec;
use metabezier::outline::{
    csv_from_bytes, load_glyph, load_image, load_svg, CsvOptions, ImageOptions, Sampling,
};

fn main() {
    let mut c = Criterion::default().configure_from_args().sample_size(10);
    let mut csv = String::from("x,y\n# a comment\n");
    for i in 0..200_000 {
        let t = i as f64 * 1e-4;
        csv.push_str(&format!("{},{}\n", 100.0 * t.cos(), 100.0 * t.sin()));
    }
    c.bench_function("load_csv_200k_points", |b| {
        b.iter(|| {
            csv_from_bytes(csv.as_bytes(), Path::new("pts.csv"), &CsvOptions::default())
                .unwrap()
                .points
                .len()
        })
    });
    let values = |n: usize, scale: f64| -> String {
        (1..=n)
            .map(|i| format!("{}", i as f64 * scale))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let spec = format!(
        "[experiment]\nname = \"grid\"\nseed = 1\nruns = 1\nbudget = 10\n\n[[problem]]\nfunction = \"sphere\"\ndim = 2\n\n[[algorithm]]\nname = \"mhs\"\nhms = [{}]\nhmcr = [{}]\nbw = [{}]\nl = [{}]\n",
        values(10, 1.0),
        values(10, 0.09),
        values(10, 0.01),
        values(10, 1.0)
    );
    c.bench_function("check_10000_cell_grid", |b| {
        b.iter(|| {
            Spec::parse(Path::new("grid.toml"), &spec)
                .unwrap()
                .cells
                .len()
        })
    });
    // The outline readers on the vendored files: PNG (decode, threshold,
    // border following), SVG (potrace's horse), glyphs (TrueType and CFF,
    // read and sampled as `fit` samples them).
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/outlines");
    c.bench_function("load_png_horse", |b| {
        b.iter(|| {
            load_image(&data.join("horse.png"), &ImageOptions::default())
                .unwrap()
                .len()
        })
    });
    c.bench_function("load_svg_horse_potrace", |b| {
        b.iter(|| {
            load_svg(&data.join("horse-potrace.svg"))
                .unwrap()
                .segment_count()
        })
    });
    for (font, name) in [
        ("DejaVuSans.ttf", "load_glyph_dejavu_g"),
        ("Cantarell-Regular.otf", "load_glyph_cantarell_g"),
    ] {
        c.bench_function(name, |b| {
            b.iter(|| {
                load_glyph(&data.join(font), 'g')
                    .unwrap()
                    .sample(Sampling::default())
                    .len()
            })
        });
    }
    c.final_summary();
}
