//! DICOM CT series: a reader for uncompressed single-frame grey-scale images
//! (implicit or explicit VR little endian) and a minimal explicit-VR
//! little-endian CT writer, built on the pure-Rust `dicom-object` crate.
//!
//! Attributes used (DICOM PS3.3, C.7.6.2 Image Plane and C.7.6.3 Image Pixel
//! modules, C.11.1 Modality LUT): Rows, Columns, BitsAllocated (8 or 16),
//! BitsStored, PixelRepresentation, SamplesPerPixel (1), RescaleSlope and
//! RescaleIntercept (`HU = raw·slope + intercept`), PixelSpacing (row
//! spacing, column spacing), ImagePositionPatient and ImageOrientationPatient
//! (slice position along the normal `n = r × c`), else SliceLocation, else
//! InstanceNumber.

use std::path::{Path, PathBuf};

use dicom_core::value::{PrimitiveValue, Value};
use dicom_core::{DataElement, Tag, VR};
use dicom_dictionary_std::{tags, uids};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

use super::error::{CtError, DicomProblem};
use super::volume::{FrameSource, Spacing, Volume};
use crate::files::write_atomic;

/// One decoded DICOM image: HU samples and its geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct DicomSlice {
    /// The file it came from.
    pub path: PathBuf,
    /// Rows.
    pub rows: usize,
    /// Columns.
    pub cols: usize,
    /// Spacing between rows (y) in mm, PixelSpacing\[0\].
    pub row_spacing: f64,
    /// Spacing between columns (x) in mm, PixelSpacing\[1\].
    pub col_spacing: f64,
    /// ImagePositionPatient (x, y, z) of the first pixel in mm, if present.
    pub position: Option<[f64; 3]>,
    /// ImageOrientationPatient (row then column direction cosines), if present.
    pub orientation: Option<[f64; 6]>,
    /// Position along the slice normal in mm, used to sort a series.
    pub location: f64,
    /// SliceThickness in mm, if present.
    pub thickness: Option<f64>,
    /// Row-major HU samples (`raw·slope + intercept`, rounded, clamped to i16).
    pub hu: Vec<i16>,
}

fn get_f64s(obj: &InMemDicomObject, tag: Tag) -> Option<Vec<f64>> {
    obj.element_opt(tag)
        .ok()
        .flatten()
        .and_then(|e| e.to_multi_float64().ok())
}

fn get_int(obj: &InMemDicomObject, tag: Tag) -> Option<i64> {
    obj.element_opt(tag)
        .ok()
        .flatten()
        .and_then(|e| e.to_int::<i64>().ok())
}

/// The pixel format of a grey-scale image (Image Pixel module).
#[derive(Clone, Copy, Debug)]
struct PixelFormat {
    rows: usize,
    cols: usize,
    /// BitsAllocated: 8 or 16.
    bits: i64,
    /// BitsStored, `1..=bits`.
    stored: i64,
    /// PixelRepresentation 1: two's complement samples.
    signed: bool,
}

impl PixelFormat {
    /// Reads and checks Rows, Columns, BitsAllocated, BitsStored,
    /// PixelRepresentation, SamplesPerPixel and NumberOfFrames.
    fn read(obj: &InMemDicomObject, path: &Path) -> Result<PixelFormat, CtError> {
        let bad = |problem: DicomProblem| CtError::dicom(path, problem);
        let need = |tag: Tag, name: &'static str| {
            get_int(obj, tag).ok_or_else(|| bad(DicomProblem::Missing(name)))
        };
        let rows = need(tags::ROWS, "Rows")?;
        let cols = need(tags::COLUMNS, "Columns")?;
        if rows <= 0 || cols <= 0 {
            return Err(bad(DicomProblem::EmptyImage { rows, cols }));
        }
        let bits = need(tags::BITS_ALLOCATED, "BitsAllocated")?;
        if bits != 8 && bits != 16 {
            return Err(bad(DicomProblem::BitsAllocated(bits)));
        }
        let stored = get_int(obj, tags::BITS_STORED).unwrap_or(bits);
        if !(1..=bits).contains(&stored) {
            return Err(bad(DicomProblem::BitsStored { stored, bits }));
        }
        let signed = get_int(obj, tags::PIXEL_REPRESENTATION).unwrap_or(0) == 1;
        if get_int(obj, tags::SAMPLES_PER_PIXEL).unwrap_or(1) != 1 {
            return Err(bad(DicomProblem::SamplesPerPixel));
        }
        if get_int(obj, tags::NUMBER_OF_FRAMES).unwrap_or(1) != 1 {
            return Err(bad(DicomProblem::MultiFrame));
        }
        Ok(PixelFormat {
            rows: rows as usize,
            cols: cols as usize,
            bits,
            stored,
            signed,
        })
    }

    /// The raw stored words of `pixel` (PixelData), independent of the
    /// host's byte order; at least `rows·cols` of them. The value's length
    /// must be exactly `rows·cols·BitsAllocated/8` bytes, padded to even
    /// length (PS3.5 §7.1.1): a longer or shorter value is refused.
    fn words(&self, pixel: &Value<InMemDicomObject>, path: &Path) -> Result<Vec<u16>, CtError> {
        let bad = |problem: DicomProblem| CtError::dicom(path, problem);
        let found = match pixel {
            Value::Primitive(PrimitiveValue::U16(v)) => 2 * v.len(),
            Value::Primitive(PrimitiveValue::I16(v)) => 2 * v.len(),
            Value::Primitive(PrimitiveValue::U8(v)) => v.len(),
            _ => return Err(bad(DicomProblem::PixelDataType)),
        };
        let n = self.rows * self.cols;
        let bytes = n * (self.bits as usize / 8);
        let needed = bytes + bytes % 2;
        if found != needed {
            return Err(bad(DicomProblem::PixelDataLength {
                found,
                rows: self.rows,
                cols: self.cols,
                bits: self.bits,
                needed,
            }));
        }
        let words: Vec<u16> = match pixel {
            Value::Primitive(PrimitiveValue::U16(v)) if self.bits == 16 => v.to_vec(),
            Value::Primitive(PrimitiveValue::I16(v)) if self.bits == 16 => {
                v.iter().map(|&x| x as u16).collect()
            }
            Value::Primitive(PrimitiveValue::U8(v)) if self.bits == 16 => v
                .chunks_exact(2)
                .map(|c| u16::from_le_bytes([c[0], c[1]]))
                .collect(),
            Value::Primitive(PrimitiveValue::U8(v)) => v.iter().map(|&b| b as u16).collect(),
            Value::Primitive(PrimitiveValue::U16(v)) => v
                .iter()
                .flat_map(|w| w.to_le_bytes())
                .map(|b| b as u16)
                .collect(),
            _ => return Err(bad(DicomProblem::PixelDataType)),
        };
        Ok(words)
    }

    /// The first `rows·cols` stored words as HU: masked to BitsStored,
    /// sign-extended when signed, `raw·slope + intercept`, rounded and
    /// clamped to i16.
    fn hu(&self, words: &[u16], slope: f64, intercept: f64) -> Vec<i16> {
        let stored = self.stored;
        let mask: u32 = if stored >= 32 {
            u32::MAX
        } else {
            (1u32 << stored) - 1
        };
        words[..self.rows * self.cols]
            .iter()
            .map(|&w| {
                let u = (w as u32) & mask;
                let raw = if self.signed && stored > 0 && (u >> (stored - 1)) & 1 == 1 {
                    u as i64 - (1i64 << stored)
                } else {
                    u as i64
                };
                let v = (raw as f64 * slope + intercept).round();
                v.clamp(i16::MIN as f64, i16::MAX as f64) as i16
            })
            .collect()
    }
}

/// Opens a DICOM file and checks that its transfer syntax is uncompressed
/// little endian.
fn open_uncompressed(path: &Path) -> Result<dicom_object::DefaultDicomObject, CtError> {
    let bad = |problem: DicomProblem| CtError::dicom(path, problem);
    let file = dicom_object::open_file(path).map_err(|e| bad(DicomProblem::Open(Box::new(e))))?;
    let ts = file
        .meta()
        .transfer_syntax()
        .trim_end_matches('\0')
        .to_string();
    if ts != uids::IMPLICIT_VR_LITTLE_ENDIAN && ts != uids::EXPLICIT_VR_LITTLE_ENDIAN {
        return Err(bad(DicomProblem::TransferSyntax { syntax: ts }));
    }
    Ok(file)
}

/// The first value of a numeric attribute.
fn first_f64(obj: &InMemDicomObject, tag: Tag) -> Option<f64> {
    get_f64s(obj, tag).and_then(|v| v.first().copied())
}

/// The slice normal `n = r × c` of ImageOrientationPatient `o`.
fn normal(o: &[f64; 6]) -> [f64; 3] {
    [
        o[1] * o[5] - o[2] * o[4],
        o[2] * o[3] - o[0] * o[5],
        o[0] * o[4] - o[1] * o[3],
    ]
}

/// The slice's position along its normal `n = r × c` (from
/// ImagePositionPatient and ImageOrientationPatient), else the position's z,
/// else SliceLocation, else InstanceNumber, else 0.
fn slice_location(
    obj: &InMemDicomObject,
    position: Option<[f64; 3]>,
    orientation: Option<[f64; 6]>,
) -> f64 {
    match (position, orientation) {
        (Some(p), Some(o)) => {
            let n = normal(&o);
            p[0] * n[0] + p[1] * n[1] + p[2] * n[2]
        }
        (Some(p), None) => p[2],
        _ => first_f64(obj, tags::SLICE_LOCATION)
            .or_else(|| get_int(obj, tags::INSTANCE_NUMBER).map(|i| i as f64))
            .unwrap_or(0.0),
    }
}

/// Reads one DICOM file into HU. Errors (naming the file): unreadable or not
/// DICOM, compressed or big-endian transfer syntax, more than one frame or
/// sample per pixel, bits allocated other than 8/16, missing Rows, Columns,
/// PixelSpacing or PixelData, or pixel data of the wrong length.
pub fn read_dicom_file(path: &Path) -> Result<DicomSlice, CtError> {
    let bad = |problem: DicomProblem| CtError::dicom(path, problem);
    let file = open_uncompressed(path)?;
    let obj: &InMemDicomObject = &file;
    let format = PixelFormat::read(obj, path)?;
    let spacing = get_f64s(obj, tags::PIXEL_SPACING)
        .filter(|v| v.len() == 2 && v.iter().all(|s| s.is_finite() && *s > 0.0))
        .ok_or_else(|| bad(DicomProblem::Missing("PixelSpacing")))?;
    let slope = first_f64(obj, tags::RESCALE_SLOPE).unwrap_or(1.0);
    let intercept = first_f64(obj, tags::RESCALE_INTERCEPT).unwrap_or(0.0);
    let position = get_f64s(obj, tags::IMAGE_POSITION_PATIENT)
        .filter(|v| v.len() == 3)
        .map(|v| [v[0], v[1], v[2]]);
    let orientation = get_f64s(obj, tags::IMAGE_ORIENTATION_PATIENT)
        .filter(|v| v.len() == 6 && v.iter().all(|c| c.is_finite()))
        .map(|v| [v[0], v[1], v[2], v[3], v[4], v[5]]);
    let location = slice_location(obj, position, orientation);
    let thickness = first_f64(obj, tags::SLICE_THICKNESS);
    let pixel = obj
        .element_opt(tags::PIXEL_DATA)
        .map_err(|e| bad(DicomProblem::PixelDataAccess(Box::new(e))))?
        .ok_or_else(|| bad(DicomProblem::NoPixelData))?;
    let words = format.words(pixel.value(), path)?;
    Ok(DicomSlice {
        path: path.to_owned(),
        rows: format.rows,
        cols: format.cols,
        row_spacing: spacing[0],
        col_spacing: spacing[1],
        position,
        orientation,
        location,
        thickness,
        hu: format.hu(&words, slope, intercept),
    })
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-3 * a.abs().max(b.abs()).max(1.0)
}

/// Stacks DICOM files into a volume, sorted by position along the slice
/// normal (z increasing). Refuses (naming the first offending file) slices of
/// different sizes, different pixel spacing, or uneven gaps between slice
/// positions (relative tolerance 10⁻³); a single slice gets its
/// SliceThickness (or 1 mm) as z spacing.
pub fn read_dicom_series(paths: &[PathBuf]) -> Result<Volume, CtError> {
    if paths.is_empty() {
        return Err(CtError::EmptySeries);
    }
    let mut slices = paths
        .iter()
        .map(|p| read_dicom_file(p))
        .collect::<Result<Vec<_>, _>>()?;
    slices.sort_by(|a, b| a.location.total_cmp(&b.location));
    let first = &slices[0];
    for s in &slices[1..] {
        if (s.rows, s.cols) != (first.rows, first.cols) {
            return Err(CtError::SizeMismatch {
                path: s.path.clone(),
                expected: (first.rows, first.cols),
                found: (s.rows, s.cols),
            });
        }
        if let (Some(e), Some(f)) = (first.orientation, s.orientation) {
            if e.iter().zip(&f).any(|(a, b)| (a - b).abs() > 1e-4) {
                return Err(CtError::OrientationMismatch {
                    path: s.path.clone(),
                    expected: e,
                    found: f,
                });
            }
        }
        for (axis, e, f) in [
            ("row", first.row_spacing, s.row_spacing),
            ("column", first.col_spacing, s.col_spacing),
        ] {
            if !same(e, f) {
                return Err(CtError::SpacingMismatch {
                    path: s.path.clone(),
                    axis,
                    expected: e,
                    found: f,
                });
            }
        }
    }
    let sz = slice_step(&slices)?;
    let (origin, axes) = series_frame(&slices);
    let first = &slices[0];
    let (nx, ny, nz) = (first.cols, first.rows, slices.len());
    let spacing = Spacing {
        x: first.col_spacing,
        y: first.row_spacing,
        z: sz,
    };
    let mut data = Vec::with_capacity(nx * ny * nz);
    for s in slices {
        data.extend_from_slice(&s.hu);
    }
    Volume::new(nx, ny, nz, spacing, origin, data)?.with_frame(origin, axes, FrameSource::Dicom)
}

/// The slice spacing of a sorted series: the distance between the first
/// and last ImagePositionPatient over `n − 1` (the locations along the
/// normal when a position is missing), after checking that the gaps along
/// the normal are even; a single slice gets its SliceThickness (or 1 mm).
fn slice_step(slices: &[DicomSlice]) -> Result<f64, CtError> {
    let first = &slices[0];
    Ok(if slices.len() > 1 {
        let gap0 = slices[1].location - slices[0].location;
        for w in slices.windows(2) {
            let gap = w[1].location - w[0].location;
            if gap.is_nan() || gap <= 0.0 || !same(gap, gap0) {
                return Err(CtError::SpacingMismatch {
                    path: w[1].path.clone(),
                    axis: "slice gap",
                    expected: gap0,
                    found: gap,
                });
            }
        }
        let last = &slices[slices.len() - 1];
        match (first.position, last.position) {
            (Some(p), Some(q)) => {
                let d: f64 = (0..3).map(|i| (q[i] - p[i]).powi(2)).sum::<f64>().sqrt();
                d / (slices.len() - 1) as f64
            }
            _ => (last.location - first.location) / (slices.len() - 1) as f64,
        }
    } else {
        first.thickness.filter(|t| *t > 0.0).unwrap_or(1.0)
    })
}

/// The origin and axes of a sorted series: ImagePositionPatient of the
/// first slice (else `(0, 0, location)`), the row and column directions of
/// ImageOrientationPatient (else the identity), and the slice axis along
/// the positions from the first to the last slice (else the normal).
fn series_frame(slices: &[DicomSlice]) -> ([f64; 3], [[f64; 3]; 3]) {
    let first = &slices[0];
    let last = &slices[slices.len() - 1];
    let origin = first.position.unwrap_or([0.0, 0.0, first.location]);
    let Some(o) = first.orientation else {
        return (origin, crate::ct::volume::IDENTITY_AXES);
    };
    let n = normal(&o);
    let z = match (first.position, last.position) {
        (Some(p), Some(q)) if slices.len() > 1 => {
            let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            // The positions run along +n (sorted by location).
            if d.iter().map(|c| c * c).sum::<f64>() > 0.0 {
                d
            } else {
                n
            }
        }
        _ => n,
    };
    (origin, [[o[0], o[1], o[2]], [o[3], o[4], o[5]], z])
}

/// Reads every regular file of `dir` as one DICOM series (see
/// [`read_dicom_series`]); any file that is not valid DICOM is an error.
pub fn read_dicom_dir(dir: &Path) -> Result<Volume, CtError> {
    let mut paths = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(|e| CtError::io(dir, e))? {
        let entry = entry.map_err(|e| CtError::io(dir, e))?;
        let p = entry.path();
        if p.is_file() {
            paths.push(p);
        }
    }
    paths.sort();
    read_dicom_series(&paths)
}

/// A DICOM decimal string (≤ 16 characters, PS3.5 6.2) for `v`: the
/// shortest round-trip representation when it fits.
fn ds(v: f64) -> String {
    let s = format!("{v}");
    if s.len() <= 16 {
        return s;
    }
    for prec in (1..=15).rev() {
        let s = format!("{v:.prec$e}");
        if s.len() <= 16 {
            return s;
        }
    }
    format!("{v:.0}")
}

/// A deterministic UID under the `2.25` root (ITU-T X.667 UUID-derived) from
/// a text key (FNV-1a 64-bit, twice).
fn uid(key: &str) -> String {
    let fnv = |seed: u64| {
        key.bytes().fold(seed, |h, b| {
            (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
        })
    };
    let hi = fnv(0xcbf2_9ce4_8422_2325) as u128;
    let lo = fnv(0x8422_2325_cbf2_9ce4) as u128;
    format!("2.25.{}", (hi << 64 | lo) >> 1)
}

/// The HU samples of slice `z` as the writer's stored words
/// `raw = HU + 1024` (signed 16-bit).
fn stored_words(hu: &[i16], z: usize) -> Result<Vec<u16>, CtError> {
    let mut words = Vec::with_capacity(hu.len());
    for &hu in hu {
        let raw = hu as i32 + 1024;
        let raw = i16::try_from(raw).map_err(|_| CtError::HuOutOfRange { hu, slice: z })?;
        words.push(raw as u16);
    }
    Ok(words)
}

/// The identifying attributes of slice `z` of `series`: SOP class and
/// instance, modality, an anonymous patient, the deterministic study, series
/// and frame-of-reference UIDs, and InstanceNumber `z + 1`.
fn put_identity(obj: &mut InMemDicomObject, series: &str, z: usize) {
    let s = |t: Tag, vr: VR, v: String| DataElement::new(t, vr, PrimitiveValue::from(v));
    let sop = uid(&format!("{series}/{z}"));
    obj.put(s(
        tags::SOP_CLASS_UID,
        VR::UI,
        uids::CT_IMAGE_STORAGE.into(),
    ));
    obj.put(s(tags::SOP_INSTANCE_UID, VR::UI, sop));
    obj.put(s(tags::MODALITY, VR::CS, "CT".into()));
    obj.put(s(tags::PATIENT_NAME, VR::PN, "Anonymous".into()));
    obj.put(s(
        tags::STUDY_INSTANCE_UID,
        VR::UI,
        uid(&format!("{series}/study")),
    ));
    obj.put(s(
        tags::SERIES_INSTANCE_UID,
        VR::UI,
        uid(&format!("{series}/series")),
    ));
    obj.put(s(
        tags::FRAME_OF_REFERENCE_UID,
        VR::UI,
        uid(&format!("{series}/frame")),
    ));
    obj.put(s(tags::INSTANCE_NUMBER, VR::IS, format!("{}", z + 1)));
}

/// The bytes of slice `z` of `volume` as a single-frame CT Image Storage
/// DICOM file (explicit VR little endian; signed 16-bit samples
/// `raw = HU + 1024`, RescaleSlope 1, RescaleIntercept −1024;
/// ImageOrientationPatient = the volume's column and row axes,
/// ImagePositionPatient = the patient position of voxel (0, 0, z)).
/// `series` keys the deterministic study/series/instance UIDs.
pub fn dicom_slice_bytes(volume: &Volume, z: usize, series: &str) -> Result<Vec<u8>, CtError> {
    let sl = volume.slice(z);
    let words = stored_words(sl.data, z)?;
    let sp = volume.spacing;
    let frame = volume.frame();
    let pos = frame.to_patient([0.0, 0.0, z as f64 * sp.z]);
    let [r, c, _] = frame.axes;
    let iop: [f64; 6] = [r[0], r[1], r[2], c[0], c[1], c[2]];
    let n = normal(&iop);
    let location = pos[0] * n[0] + pos[1] * n[1] + pos[2] * n[2];
    let s = |t: Tag, vr: VR, v: String| DataElement::new(t, vr, PrimitiveValue::from(v));
    let u16e = |t: Tag, v: u16| DataElement::new(t, VR::US, PrimitiveValue::from(v));
    let mut obj = InMemDicomObject::new_empty();
    put_identity(&mut obj, series, z);
    obj.put(s(tags::SLICE_THICKNESS, VR::DS, ds(sp.z)));
    obj.put(s(
        tags::IMAGE_POSITION_PATIENT,
        VR::DS,
        format!("{}\\{}\\{}", ds(pos[0]), ds(pos[1]), ds(pos[2])),
    ));
    obj.put(s(
        tags::IMAGE_ORIENTATION_PATIENT,
        VR::DS,
        iop.map(ds).join("\\"),
    ));
    obj.put(s(tags::SLICE_LOCATION, VR::DS, ds(location)));
    obj.put(u16e(tags::SAMPLES_PER_PIXEL, 1));
    obj.put(s(
        tags::PHOTOMETRIC_INTERPRETATION,
        VR::CS,
        "MONOCHROME2".into(),
    ));
    obj.put(u16e(tags::ROWS, sl.ny as u16));
    obj.put(u16e(tags::COLUMNS, sl.nx as u16));
    obj.put(s(
        tags::PIXEL_SPACING,
        VR::DS,
        format!("{}\\{}", ds(sp.y), ds(sp.x)),
    ));
    obj.put(u16e(tags::BITS_ALLOCATED, 16));
    obj.put(u16e(tags::BITS_STORED, 16));
    obj.put(u16e(tags::HIGH_BIT, 15));
    obj.put(u16e(tags::PIXEL_REPRESENTATION, 1));
    obj.put(s(tags::RESCALE_INTERCEPT, VR::DS, "-1024".into()));
    obj.put(s(tags::RESCALE_SLOPE, VR::DS, "1".into()));
    obj.put(s(tags::RESCALE_TYPE, VR::LO, "HU".into()));
    obj.put(DataElement::new(
        tags::PIXEL_DATA,
        VR::OW,
        PrimitiveValue::U16(words.into()),
    ));
    if sl.nx > u16::MAX as usize || sl.ny > u16::MAX as usize {
        return Err(CtError::SliceTooLarge {
            nx: sl.nx,
            ny: sl.ny,
        });
    }
    let file = obj
        .with_meta(FileMetaTableBuilder::new().transfer_syntax(uids::EXPLICIT_VR_LITTLE_ENDIAN))
        .map_err(|e| CtError::DicomMeta {
            source: Box::new(e),
        })?;
    let mut bytes = Vec::new();
    file.write_all(&mut bytes)
        .map_err(|e| CtError::DicomEncode {
            source: Box::new(e),
        })?;
    Ok(bytes)
}

/// Writes slices `z_range` of `volume` into `dir` as `slice_NNNN.dcm`
/// (see [`dicom_slice_bytes`]), each atomically; returns the paths.
pub fn write_dicom_series(
    dir: &Path,
    volume: &Volume,
    z_range: std::ops::Range<usize>,
    series: &str,
) -> Result<Vec<PathBuf>, CtError> {
    let mut out = Vec::new();
    for z in z_range {
        let p = dir.join(format!("slice_{z:04}.dcm"));
        write_atomic(&p, &dicom_slice_bytes(volume, z, series)?)?;
        out.push(p);
    }
    Ok(out)
}
