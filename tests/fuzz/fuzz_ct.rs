//! Mutational fuzz of the CT readers (DICOM slices and series, `.inv3`
//! projects at the gzip and at the tar level, property lists): no panic, no
//! hang, and no allocation beyond the limit on any mutant. Also the
//! allocation cases of issue 31, each read under the counting allocator.
//! See `tests/fuzz_common` for the loop and `make fuzz` for a longer run.
//!
//! The limits, per reader (the mutant's own bytes are held by the loop
//! before the limit is armed, so they are not counted):
//!
//! * DICOM slice, `4 × file + 1 MiB`: the reader borrows every value from
//!   the file's bytes and holds only the list of the 16 attributes it uses
//!   and the HU samples, 2 bytes a pixel: at most the PixelData's length
//!   for 16-bit images and twice it for 8-bit ones (whose length is checked
//!   against rows·cols before anything is decoded), so at most 2 × the
//!   file; 1 MiB covers the error text and the allocator's rounding.
//! * DICOM series, `4 × files + 1 MiB`: as above, plus each file's bytes
//!   read from disk (1 × each) while its slice is decoded.
//! * `.inv3`, `4 × tar + 1 MiB`: the reader holds the volume's samples
//!   (at most the matrix member, which is at most the tar), the plist text
//!   and its tree (at most the tar, and about ten times a plist of a few
//!   kilobytes), a 64 KiB sample buffer and the inflater's state (about
//!   50 KiB). For tar-level mutants the stored gzip stream built in the
//!   loop (1 × the tar) is counted too.
//! * plist, `16 × text + 1 MiB`: a parsed value costs 32 bytes (56 for a
//!   dict entry) and the shortest element that makes one is 7 bytes of
//!   text (`<true/>`), so with vector doubling the tree is at most about
//!   ten times the text.
use crate::ct_inputs;
use crate::fuzz_common;

use std::io::Read;
use std::path::{Path, PathBuf};

use ct_inputs::{element, item, long_element, short_element, with_value};
use metabezier::ct::dicom::{dicom_slice_bytes, dicom_slice_from_bytes};
use metabezier::ct::inv3::{inv3_bytes, inv3_plist, read_inv3_bytes};
use metabezier::ct::plist::parse_plist;
use metabezier::ct::{read_dicom_series, read_inv3, Volume, CT0051_PATH};

const MIB: usize = 1 << 20;

/// The allocator's count is global: while one test reads under a limit, no
/// other test of this binary may allocate (even to build its inputs), so
/// each test holds this lock from start to end.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner())
}

/// The largest input.
fn largest(inputs: &[Vec<u8>]) -> usize {
    inputs.iter().map(Vec::len).max().unwrap()
}

/// Builds the DICOM data dictionary (a process-wide table of some 300 KB
/// that error messages consult for keywords) before a limit is armed.
fn warm_up_the_dictionary() {
    let _ = metabezier::ct::error::tag_label(dicom_core::Tag(0x7FE0, 0x0010));
}

/// Slice `z` of the 7×5×3 test volume as DICOM bytes.
fn small_slice(z: usize) -> Vec<u8> {
    dicom_slice_bytes(&ct_inputs::small_volume(), z, "fuzz").unwrap()
}

/// Slice 0 of the 7×5×3 test volume as an unsigned 8-bit image.
fn eight_bit_slice() -> Vec<u8> {
    let mut b = small_slice(0);
    for (tag, value) in [
        ((0x0028, 0x0100), 8u16),
        ((0x0028, 0x0101), 8),
        ((0x0028, 0x0102), 7),
        ((0x0028, 0x0103), 0),
    ] {
        b = with_value(&b, tag, &value.to_le_bytes());
    }
    let pixels: Vec<u8> = (0..36).map(|i| (i * 7) as u8).collect();
    with_value(&b, (0x7FE0, 0x0010), &pixels)
}

/// CT_small.dcm with a sequence of undefined length (one item of undefined
/// and one of defined length) before its PixelData.
fn ct_small_with_sequence() -> Vec<u8> {
    let inner = short_element((0x0008, 0x1150), b"UI", b"1.2.3\0");
    let seq = [
        long_element((0x0008, 0x1140), b"SQ", u32::MAX, &[]),
        item(0xE000, u32::MAX),
        inner.clone(),
        item(0xE00D, 0),
        item(0xE000, inner.len() as u32),
        inner,
        item(0xE0DD, 0),
    ]
    .concat();
    ct_inputs::insert_before(&ct_inputs::ct_small(), (0x7FE0, 0x0010), &seq)
}

#[test]
fn dicom_slices_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    let inputs = vec![
        ct_inputs::ct_small(),
        ct_inputs::ct_small_implicit(),
        ct_small_with_sequence(),
        small_slice(1),
        eight_bit_slice(),
    ];
    for i in &inputs {
        dicom_slice_from_bytes(Path::new("seed.dcm"), i).expect("the seeds are valid");
    }
    warm_up_the_dictionary();
    let limit = 4 * largest(&inputs) + MIB;
    let path = Path::new("mutant.dcm");
    let tally = fuzz_common::fuzz(
        "dicom",
        &inputs,
        limit,
        |bytes| match dicom_slice_from_bytes(path, bytes) {
            Ok(s) => {
                assert_eq!(s.hu.len(), s.rows * s.cols);
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with("mutant.dcm: "), "{e}");
                false
            }
        },
    );
    eprintln!("dicom: {tally:?}, limit {limit}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

#[test]
fn dicom_series_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    let dir = tempfile::tempdir().unwrap();
    let slices: Vec<Vec<u8>> = (0..3).map(small_slice).collect();
    let paths: Vec<PathBuf> = (0..3)
        .map(|z| {
            let p = dir.path().join(format!("s{z}.dcm"));
            std::fs::write(&p, &slices[z]).unwrap();
            p
        })
        .collect();
    read_dicom_series(&paths).expect("the seed series is valid");
    warm_up_the_dictionary();
    let limit = 4 * slices.iter().map(Vec::len).sum::<usize>() + MIB;
    // Each mutant replaces the middle slice (a splice may bring in the others).
    let tally = fuzz_common::fuzz("dicom-series", &slices, limit, |bytes| {
        std::fs::write(&paths[1], bytes).unwrap();
        match read_dicom_series(&paths) {
            Ok(v) => {
                assert_eq!(v.data().len(), v.nx * v.ny * v.nz);
                true
            }
            Err(e) => {
                let text = e.to_string();
                assert!(text.contains(dir.path().to_str().unwrap()), "{text}");
                false
            }
        }
    });
    eprintln!("dicom-series: {tally:?}, limit {limit}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

/// The tar of `volume` in InVesalius's own member order: a pax header
/// (Python's `tarfile` writes one with the fractional mtime), the matrix
/// under a directory, a mask, and the plist last.
fn invesalius_tar(volume: &Volume) -> Vec<u8> {
    let plist = inv3_plist(volume, "fuzz");
    let matrix = ct_inputs::matrix_bytes(volume);
    let pax = ct_inputs::pax(&[("mtime", "1700000000.25")]);
    ct_inputs::tar(&[
        ("././@PaxHeader", b'x', &pax),
        ("tmp1/matrix.dat", b'0', &matrix),
        ("tmp1/mask_0.dat", b'0', &[1u8; 700]),
        ("tmp1/main.plist", b'0', plist.as_bytes()),
    ])
}

/// The tar of `volume` with the plist first and the matrix as `m.raw`.
fn renamed_tar(volume: &Volume) -> Vec<u8> {
    let plist = inv3_plist(volume, "fuzz").replace("matrix.dat", "m.raw");
    let matrix = ct_inputs::matrix_bytes(volume);
    ct_inputs::tar(&[
        ("m.raw", b'0', &matrix),
        ("main.plist", b'0', plist.as_bytes()),
    ])
}

#[test]
fn inv3_projects_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    let block = ct_inputs::ct_block();
    let small = ct_inputs::small_volume();
    let inputs = vec![
        inv3_bytes(&block, "block"),
        ct_inputs::gzip(&invesalius_tar(&block)),
        inv3_bytes(&small, "small"),
        ct_inputs::gzip(&renamed_tar(&small)),
    ];
    for i in &inputs {
        read_inv3_bytes(Path::new("seed.inv3"), i).expect("the seeds are valid");
    }
    // The largest tar any seed decompresses to.
    let tar = invesalius_tar(&block)
        .len()
        .max(2 * block.data().len() + 4096);
    let limit = 4 * tar + MIB;
    let path = Path::new("mutant.inv3");
    let tally = fuzz_common::fuzz("inv3", &inputs, limit, |bytes| {
        match read_inv3_bytes(path, bytes) {
            // The CRC-32 is checked: a read volume is one of the seeds'.
            Ok(v) => {
                assert!(v.data() == block.data() || v.data() == small.data());
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with("mutant.inv3: "), "{e}");
                false
            }
        }
    });
    eprintln!("inv3: {tally:?}, limit {limit}");
    // Only mutants of the gzip header's free fields (mtime, OS) pass the CRC.
    assert!(tally.accepted < tally.mutants, "{tally:?}");
}

#[test]
fn inv3_tars_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    let small = ct_inputs::small_volume();
    let block = ct_inputs::ct_block();
    let plain = |v: &Volume| {
        let plist = inv3_plist(v, "fuzz");
        let matrix = ct_inputs::matrix_bytes(v);
        ct_inputs::tar(&[
            ("main.plist", b'0', plist.as_bytes()),
            ("matrix.dat", b'0', &matrix),
        ])
    };
    let inputs = vec![
        plain(&small),
        invesalius_tar(&small),
        renamed_tar(&small),
        invesalius_tar(&block),
    ];
    for i in &inputs {
        read_inv3_bytes(Path::new("seed.inv3"), &ct_inputs::gzip_stored(i))
            .expect("the seeds are valid");
    }
    let limit = 4 * largest(&inputs) + MIB;
    let path = Path::new("mutant.inv3");
    let tally = fuzz_common::fuzz("inv3-tar", &inputs, limit, |tar| {
        match read_inv3_bytes(path, &ct_inputs::gzip_stored(tar)) {
            Ok(v) => {
                assert_eq!(v.data().len(), v.nx * v.ny * v.nz);
                true
            }
            Err(e) => {
                assert!(e.to_string().starts_with("mutant.inv3: "), "{e}");
                false
            }
        }
    });
    eprintln!("inv3-tar: {tally:?}, limit {limit}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

/// The vendored extract's `main.plist`.
fn vendored_plist() -> Vec<u8> {
    let file = std::fs::File::open(ct_inputs::root().join(CT0051_PATH)).unwrap();
    let mut archive = tar::Archive::new(flate2::read::GzDecoder::new(file));
    for entry in archive.entries().unwrap() {
        let mut entry = entry.unwrap();
        if entry.path().unwrap().ends_with("main.plist") {
            let mut text = Vec::new();
            entry.read_to_end(&mut text).unwrap();
            return text;
        }
    }
    panic!("no main.plist in the vendored extract");
}

#[test]
fn plists_survive_mutation() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    let inputs = vec![
        vendored_plist(),
        inv3_plist(&ct_inputs::small_volume(), "a & <b>").into_bytes(),
        b"<plist><array><array><dict><key>k</key><array><true/><false/><real>1e3</real></array></dict></array><string/></array></plist>".to_vec(),
    ];
    for i in &inputs {
        parse_plist(std::str::from_utf8(i).unwrap()).expect("the seeds are valid");
    }
    let limit = 16 * largest(&inputs) + MIB;
    let tally = fuzz_common::fuzz("plist", &inputs, limit, |bytes| {
        std::str::from_utf8(bytes).is_ok_and(|t| parse_plist(t).is_ok())
    });
    eprintln!("plist: {tally:?}, limit {limit}");
    assert!(
        tally.accepted > 0 && tally.accepted < tally.mutants,
        "{tally:?}"
    );
}

// ------------------------------------------------ the allocation cases of issue 31

#[test]
fn a_pixel_data_length_of_4_gib_is_refused_without_allocating_it() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    // A 39 KB slice whose PixelData length says 0xFFFFFFF0 took 4.1 GB
    // before failing.
    let b = ct_inputs::ct_small();
    let px = element(&b, (0x7FE0, 0x0010));
    let mut m = b.clone();
    m[px.at + 8..px.at + 12].copy_from_slice(&0xFFFF_FFF0u32.to_le_bytes());
    let limit = 4 * m.len() + MIB;
    let (result, peak) =
        fuzz_common::with_limit(limit, || dicom_slice_from_bytes(Path::new("long.dcm"), &m));
    let e = result.unwrap_err().to_string();
    assert!(
        e.contains("(7FE0,0010) PixelData") && e.contains("declares 4294967280 bytes, but only"),
        "{e}"
    );
    assert!(peak < 64 << 10, "peak {peak}");
}

#[test]
fn a_big_endian_slice_is_refused_before_its_data_set_is_read() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    // A big-endian transfer syntax took 1.3 GB.
    let m = ct_inputs::with_syntax(&ct_inputs::ct_small(), "1.2.840.10008.1.2.2");
    let (result, peak) = fuzz_common::with_limit(4 * m.len() + MIB, || {
        dicom_slice_from_bytes(Path::new("be.dcm"), &m)
    });
    let e = result.unwrap_err().to_string();
    assert!(
        e.contains("1.2.840.10008.1.2.2 (Explicit VR Big Endian) is not supported"),
        "{e}"
    );
    assert!(peak < 64 << 10, "peak {peak}");
}

#[test]
fn junk_members_are_skipped_without_being_held() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    // A 6 MB .inv3 with two 1 GiB junk members peaked at 2.07 GB; here two
    // 64 MiB members of zeros (a 600 KB file) must not be held.
    let v = ct_inputs::small_volume();
    let plist = inv3_plist(&v, "junk");
    let matrix = ct_inputs::matrix_bytes(&v);
    let gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    let mut builder = tar::Builder::new(gz);
    let junk = 64u64 << 20;
    for (name, size) in [
        ("junk_a.bin", junk),
        ("main.plist", plist.len() as u64),
        ("junk_b.bin", junk),
        ("matrix.dat", matrix.len() as u64),
    ] {
        let mut h = tar::Header::new_ustar();
        h.set_size(size);
        h.set_mode(0o644);
        let data: Box<dyn std::io::Read> = match name {
            "main.plist" => Box::new(plist.as_bytes()),
            "matrix.dat" => Box::new(&matrix[..]),
            _ => Box::new(std::io::repeat(0).take(size)),
        };
        builder.append_data(&mut h, name, data).unwrap();
    }
    let file = builder.into_inner().unwrap().finish().unwrap();
    let limit = 4 * file.len() + MIB;
    let (result, peak) =
        fuzz_common::with_limit(limit, || read_inv3_bytes(Path::new("junk.inv3"), &file));
    assert_eq!(result.unwrap().data(), v.data());
    eprintln!("junk: peak {peak} for a {}-byte file", file.len());
    assert!(
        peak < 512 << 10,
        "peak {peak} for a {}-byte file",
        file.len()
    );
}

#[test]
fn the_vendored_ct_is_read_holding_its_volume_and_fixed_buffers() {
    let _one = fuzz_common::one_test_at_a_time();
    let _one = one_at_a_time();
    // Before, the matrix's bytes and its samples were held together (twice
    // the volume).
    let path = ct_inputs::root().join(CT0051_PATH);
    let volume_bytes = 2 * 256 * 256 * 61;
    let (result, peak) = fuzz_common::with_limit(volume_bytes + MIB, || read_inv3(&path));
    assert_eq!(result.unwrap().data().len() * 2, volume_bytes);
    eprintln!("vendored: peak {peak} for a {volume_bytes}-byte volume");
    assert!(peak < volume_bytes + (512 << 10), "peak {peak}");
}
