//! Loaders stay near-linear: a 200,000-point CSV outline and a spec whose
//! algorithm grid has 10,000 cells (the figures of the hardening work;
//! both were quadratic once).

use std::path::Path;

use criterion::Criterion;
use metabezier::experiment::Spec;
use metabezier::outline::{csv_from_bytes, CsvOptions};

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
    c.final_summary();
}
