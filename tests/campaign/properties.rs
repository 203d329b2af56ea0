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

/// A small real `.inv3`: a 48×48×3 block of CT 0051 (columns 104–151, rows
/// 200–247, extract slices 20–22), written as InVesalius writes it.
fn small_inv3() -> (Vec<u8>, metabezier::ct::Volume) {
    let full = metabezier::ct::read_inv3(&repo("data/ct0051/ct0051_z040-100.inv3")).unwrap();
    let (x0, y0, z0, n) = (104, 200, 20, 48);
    let mut data = Vec::with_capacity(n * n * 3);
    for z in z0..z0 + 3 {
        for y in y0..y0 + n {
            for x in x0..x0 + n {
                data.push(full.get(z, y, x));
            }
        }
    }
    let v = metabezier::ct::Volume::new(n, n, 3, full.spacing, [0.0; 3], data).unwrap();
    (metabezier::ct::inv3::inv3_bytes(&v, "block"), v)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// A mutated `.inv3` is refused with its file named, or it reads back to
    /// the very same voxels and spacing: the gzip CRC-32 and length are
    /// checked, so a changed byte can never reach an implant.
    #[test]
    fn inv3_projects_are_read_exactly_or_refused(m in mutation()) {
        static SMALL: std::sync::OnceLock<(Vec<u8>, metabezier::ct::Volume)> = std::sync::OnceLock::new();
        let (bytes, original) = SMALL.get_or_init(small_inv3);
        let (_dir, path) = temp_file("block.inv3", &apply(bytes, &m));
        match metabezier::ct::read_inv3(&path) {
            Ok(v) => {
                prop_assert_eq!((v.nx, v.ny, v.nz), (original.nx, original.ny, original.nz));
                prop_assert_eq!(v.spacing, original.spacing);
                prop_assert!(v.data() == original.data());
            }
            Err(e) => prop_assert!(e.to_string().contains("block.inv3"), "{}", e),
        }
    }
}

/// Single-bit flips in the compressed body of the real CT extract are all
/// refused (before the CRC-32 check some were read as a different volume
/// and an implant was built from it).
#[test]
fn a_flipped_bit_in_the_real_ct_is_refused() {
    let bytes = std::fs::read(repo("data/ct0051/ct0051_z040-100.inv3")).unwrap();
    let body = 10..bytes.len();
    for k in 1..=8 {
        let at = body.start + (body.end - body.start) * k / 9 + k;
        let mut flipped = bytes.clone();
        flipped[at] ^= 1 << (k % 8);
        let (_dir, path) = temp_file("flipped.inv3", &flipped);
        let err = metabezier::ct::read_inv3(&path).expect_err("a flipped bit must be refused");
        let text = err.to_string();
        assert!(text.contains("flipped.inv3"), "{text}");
    }
}

/// A tar header that declares a 1 TiB member is refused before anything is
/// allocated, naming the member and the bound.
#[test]
fn a_member_declaring_a_tebibyte_is_refused() {
    let mut header = tar::Header::new_ustar();
    header.set_size(1 << 40);
    header.set_mode(0o644);
    header.set_entry_type(tar::EntryType::Regular);
    header.set_path("matrix.dat").unwrap();
    header.set_cksum();
    let mut tar_bytes = header.as_bytes().to_vec();
    tar_bytes.extend_from_slice(&[0u8; 2048]);
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    std::io::Write::write_all(&mut gz, &tar_bytes).unwrap();
    let (_dir, path) = temp_file("huge.inv3", &gz.finish().unwrap());
    let text = metabezier::ct::read_inv3(&path).unwrap_err().to_string();
    assert!(
        text.contains("huge.inv3") && text.contains("matrix.dat declares 1099511627776 bytes"),
        "{text}"
    );
}
