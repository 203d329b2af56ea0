//! Property tests on mutated real inputs: the spec parser and the readers of
//! CSV outlines, PNG images, fonts, `.inv3` projects and DICOM files never
//! panic on a flipped bit, a truncation or appended garbage; they either
//! return a typed error or data that passes the checks an unmutated file
//! passes (finite coordinates, consistent sizes).

use std::path::{Path, PathBuf};

use proptest::prelude::*;

use metabezier::experiment::Spec;
use metabezier::outline::{csv_from_bytes, load_glyph, load_image, CsvOptions, ImageOptions};

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// A mutation of a byte string.
#[derive(Clone, Debug)]
enum Mutation {
    /// Flip bit `bit` of the byte at `at` (a fraction of the length).
    Flip { at: f64, bit: u8 },
    /// Keep the first fraction of the bytes.
    Truncate { keep: f64 },
    /// Append these bytes.
    Append(Vec<u8>),
    /// Replace the byte at `at` with `byte`.
    Replace { at: f64, byte: u8 },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0.0..1.0f64, 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        (0.0..1.0f64).prop_map(|keep| Mutation::Truncate { keep }),
        proptest::collection::vec(any::<u8>(), 1..64).prop_map(Mutation::Append),
        (0.0..1.0f64, any::<u8>()).prop_map(|(at, byte)| Mutation::Replace { at, byte }),
    ]
}

fn apply(bytes: &[u8], m: &Mutation) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let at = |f: f64| ((f * out.len() as f64) as usize).min(out.len().saturating_sub(1));
    match m {
        Mutation::Flip { at: f, bit } => {
            let i = at(*f);
            if let Some(b) = out.get_mut(i) {
                *b ^= 1 << bit;
            }
        }
        Mutation::Truncate { keep } => out.truncate((keep * bytes.len() as f64) as usize),
        Mutation::Append(extra) => out.extend(extra),
        Mutation::Replace { at: f, byte } => {
            let i = at(*f);
            if let Some(b) = out.get_mut(i) {
                *b = *byte;
            }
        }
    }
    out
}

/// Writes `bytes` to a fresh temporary file named `name`.
fn temp_file(name: &str, bytes: &[u8]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, bytes).unwrap();
    (dir, path)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn the_spec_parser_never_panics(ms in proptest::collection::vec(mutation(), 1..4)) {
        let mut text = std::fs::read(repo("experiments/quick.toml")).unwrap();
        for m in &ms {
            text = apply(&text, m);
        }
        let text = String::from_utf8_lossy(&text);
        if let Ok(spec) = Spec::parse(Path::new("spec.toml"), &text) {
            prop_assert!(!spec.problems.is_empty() && !spec.cells.is_empty());
        }
    }

    #[test]
    fn csv_outlines_are_read_or_refused(ms in proptest::collection::vec(mutation(), 1..4)) {
        let mut bytes = b"x,y\n0,0\n10,0\n10,10\n0,10\n5,2.5e0\n".to_vec();
        for m in &ms {
            bytes = apply(&bytes, m);
        }
        match csv_from_bytes(&bytes, Path::new("pts.csv"), &CsvOptions::default()) {
            Ok(o) => prop_assert!(o.points.iter().all(|p| p.x.is_finite() && p.y.is_finite())),
            Err(e) => prop_assert!(e.to_string().contains("pts.csv"), "{}", e),
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

    #[test]
    fn png_images_are_read_or_refused(m in mutation()) {
        let bytes = apply(&std::fs::read(repo("data/outlines/coin.png")).unwrap(), &m);
        let (_dir, path) = temp_file("coin.png", &bytes);
        match load_image(&path, &ImageOptions::default()) {
            Ok(shapes) => prop_assert!(shapes
                .iter()
                .all(|o| o.points.iter().all(|p| p.x.is_finite() && p.y.is_finite()))),
            Err(e) => prop_assert!(e.to_string().contains("coin.png"), "{}", e),
        }
    }

    #[test]
    fn fonts_are_read_or_refused(m in mutation()) {
        let bytes = apply(&std::fs::read(repo("data/outlines/DejaVuSans.ttf")).unwrap(), &m);
        let (_dir, path) = temp_file("font.ttf", &bytes);
        match load_glyph(&path, 'B') {
            Ok(g) => prop_assert!(g.height().is_finite()),
            Err(e) => prop_assert!(e.to_string().contains("font.ttf"), "{}", e),
        }
    }

    #[test]
    fn dicom_files_are_read_or_refused(m in mutation()) {
        let bytes = apply(&std::fs::read(repo("data/dicom/CT_small.dcm")).unwrap(), &m);
        let (_dir, path) = temp_file("slice.dcm", &bytes);
        match metabezier::ct::read_dicom_file(&path) {
            Ok(s) => prop_assert!(s.rows > 0 && s.cols > 0 && s.hu.len() == s.rows * s.cols),
            Err(e) => prop_assert!(e.to_string().contains("slice.dcm"), "{}", e),
        }
    }
}
