//! COCO's bbob suite through its own C code: ids, boxes, optima and values
//! equal those of COCO's Python package (tests/data/bbob_reference.csv,
//! made by tools/bbob_reference.py with coco-experiment 2.8.2), and
//! COCO's evaluation counter equals ours.

use std::path::Path;

use metabezier::functions::BbobProblem;
use metabezier::problem::Problem;

/// `|a − b| ≤ 1e-12·max(1, |b|)`.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * b.abs().max(1.0)
}

#[test]
fn values_equal_cocos_python_package() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/bbob_reference.csv");
    let mut reader = csv::Reader::from_path(&path).unwrap();
    let mut rows = 0;
    for row in reader.records() {
        let row = row.unwrap();
        let num = |i: usize| -> usize { row[i].parse().unwrap() };
        let real = |i: usize| -> f64 { row[i].parse().unwrap() };
        let (f, d, k) = (num(0), num(1), num(2));
        let p = BbobProblem::new(f, d, k).unwrap();
        assert_eq!(p.id(), &row[3]);
        assert_eq!(p.bounds()[0].lower, real(4));
        assert_eq!(p.bounds()[d - 1].upper, real(5));
        assert!(
            close(p.fopt(), real(6)),
            "{}: f* {} against COCO's f(x*) {}",
            &row[3],
            p.fopt(),
            real(6)
        );
        let x: Vec<f64> = row[8].split(' ').map(|v| v.parse().unwrap()).collect();
        let y = p.objective(&x);
        assert!(
            close(y, real(9)),
            "{} at point {}: {y} against {}",
            &row[3],
            &row[7],
            real(9)
        );
        assert_eq!(p.coco_evaluations(), 1);
        rows += 1;
    }
    assert_eq!(rows, 24 * 3 * 3 * 3);
}
