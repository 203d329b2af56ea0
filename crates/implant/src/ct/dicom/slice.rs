//! One DICOM slice from its bytes: the attributes the reader uses (PS3.3
//! C.7.6.2 Image Plane, C.7.6.3 Image Pixel, C.11.1 Modality LUT), the
//! pixel format and the HU samples `raw·slope + intercept`.

use std::io::Read;
use std::path::Path;

use dicom_core::{Tag, VR};
use dicom_dictionary_std::tags;

use super::walk::{file_meta, numbers, u16_at, walk, Element};
use super::{normal, DicomSlice, MAX_DICOM_FILE_BYTES};
use crate::ct::error::{CtError, DicomProblem};

/// The top-level elements the reader uses, borrowed from the file.
#[derive(Default)]
struct Attributes<'a> {
    found: Vec<(Tag, Element<'a>)>,
}

/// The tags [`Attributes`] keeps.
const USED_TAGS: [Tag; 16] = [
    tags::SAMPLES_PER_PIXEL,
    tags::NUMBER_OF_FRAMES,
    tags::ROWS,
    tags::COLUMNS,
    tags::PIXEL_SPACING,
    tags::BITS_ALLOCATED,
    tags::BITS_STORED,
    tags::PIXEL_REPRESENTATION,
    tags::RESCALE_INTERCEPT,
    tags::RESCALE_SLOPE,
    tags::SLICE_THICKNESS,
    tags::IMAGE_POSITION_PATIENT,
    tags::IMAGE_ORIENTATION_PATIENT,
    tags::SLICE_LOCATION,
    tags::INSTANCE_NUMBER,
    tags::PIXEL_DATA,
];

impl<'a> Attributes<'a> {
    /// The element `tag` (the last one, if the file repeats it).
    fn get(&self, tag: Tag) -> Option<&Element<'a>> {
        self.found
            .iter()
            .rev()
            .find(|(t, _)| *t == tag)
            .map(|(_, e)| e)
    }

    /// The first value of `tag` as an integer, if present and integral.
    fn int(&self, tag: Tag) -> Option<i64> {
        let v = *numbers(self.get(tag)?)?.first()?;
        (v.fract() == 0.0 && v.abs() < 9e15).then_some(v as i64)
    }

    /// The values of `tag`: `Ok(None)` when absent or empty, an error
    /// naming the tag when present but not `n` finite numbers passing `ok`.
    fn finite(
        &self,
        tag: Tag,
        name: &'static str,
        n: usize,
        expected: &'static str,
        ok: impl Fn(f64) -> bool,
    ) -> Result<Option<Vec<f64>>, DicomProblem> {
        let Some(e) = self.get(tag) else {
            return Ok(None);
        };
        match numbers(e) {
            Some(v) if v.is_empty() => Ok(None),
            Some(v) if v.len() == n && v.iter().all(|&x| x.is_finite() && ok(x)) => Ok(Some(v)),
            _ => Err(DicomProblem::BadValue {
                name,
                tag,
                offset: e.offset,
                found: String::from_utf8_lossy(&e.value[..e.value.len().min(64)]).into_owned(),
                expected,
            }),
        }
    }
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
    fn read(attrs: &Attributes) -> Result<PixelFormat, DicomProblem> {
        let need = |tag: Tag, name: &'static str| attrs.int(tag).ok_or(DicomProblem::Missing(name));
        let rows = need(tags::ROWS, "Rows")?;
        let cols = need(tags::COLUMNS, "Columns")?;
        if rows <= 0 || cols <= 0 {
            return Err(DicomProblem::EmptyImage { rows, cols });
        }
        let bits = need(tags::BITS_ALLOCATED, "BitsAllocated")?;
        if bits != 8 && bits != 16 {
            return Err(DicomProblem::BitsAllocated(bits));
        }
        let stored = attrs.int(tags::BITS_STORED).unwrap_or(bits);
        if !(1..=bits).contains(&stored) {
            return Err(DicomProblem::BitsStored { stored, bits });
        }
        let signed = attrs.int(tags::PIXEL_REPRESENTATION).unwrap_or(0) == 1;
        if attrs.int(tags::SAMPLES_PER_PIXEL).unwrap_or(1) != 1 {
            return Err(DicomProblem::SamplesPerPixel);
        }
        if attrs.int(tags::NUMBER_OF_FRAMES).unwrap_or(1) != 1 {
            return Err(DicomProblem::MultiFrame);
        }
        Ok(PixelFormat {
            rows: rows as usize,
            cols: cols as usize,
            bits,
            stored,
            signed,
        })
    }

    /// The pixel bytes of PixelData, after checking its VR (OB, OW, or UN)
    /// and that its length is exactly `rows·cols·BitsAllocated/8·samples`
    /// bytes (samples = 1), padded to even length (PS3.5 §7.1.1).
    fn pixels<'a>(&self, attrs: &Attributes<'a>) -> Result<&'a [u8], DicomProblem> {
        let e = attrs
            .get(tags::PIXEL_DATA)
            .ok_or(DicomProblem::NoPixelData)?;
        if !matches!(e.vr, VR::OB | VR::OW | VR::UN) {
            return Err(DicomProblem::PixelDataType {
                offset: e.offset,
                vr: e.vr.to_string().into(),
            });
        }
        let bytes = (self.rows as u64)
            .saturating_mul(self.cols as u64)
            .saturating_mul(self.bits as u64 / 8);
        let needed = bytes.saturating_add(bytes % 2);
        if e.value.len() as u64 != needed {
            return Err(DicomProblem::PixelDataLength {
                offset: e.offset,
                found: e.value.len() as u64,
                rows: self.rows,
                cols: self.cols,
                bits: self.bits,
                samples: 1,
                needed,
            });
        }
        Ok(e.value)
    }

    /// The first `rows·cols` stored samples of `pixels` (little endian, at
    /// least `rows·cols` of them: see [`PixelFormat::pixels`]) as
    /// HU: masked to BitsStored, sign-extended when signed,
    /// `raw·slope + intercept`, rounded and clamped to i16.
    fn hu(&self, pixels: &[u8], slope: f64, intercept: f64) -> Vec<i16> {
        let stored = self.stored;
        let mask: u32 = (1u32 << stored) - 1;
        let convert = |w: u16| {
            let u = (w as u32) & mask;
            let raw = if self.signed && (u >> (stored - 1)) & 1 == 1 {
                u as i64 - (1i64 << stored)
            } else {
                u as i64
            };
            let v = (raw as f64 * slope + intercept).round();
            v.clamp(i16::MIN as f64, i16::MAX as f64) as i16
        };
        let n = self.rows * self.cols;
        if self.bits == 16 {
            pixels
                .chunks_exact(2)
                .take(n)
                .map(|c| convert(u16_at(c, 0)))
                .collect()
        } else {
            pixels.iter().take(n).map(|&b| convert(b as u16)).collect()
        }
    }
}

/// The slice's position along its normal `n = r × c` (from
/// ImagePositionPatient and ImageOrientationPatient), else the position's z,
/// else SliceLocation, else InstanceNumber, else 0.
fn slice_location(
    attrs: &Attributes,
    position: Option<[f64; 3]>,
    orientation: Option<[f64; 6]>,
    slice_location: Option<f64>,
) -> f64 {
    match (position, orientation) {
        (Some(p), Some(o)) => {
            let n = normal(&o);
            p[0] * n[0] + p[1] * n[1] + p[2] * n[2]
        }
        (Some(p), None) => p[2],
        _ => slice_location
            .or_else(|| attrs.int(tags::INSTANCE_NUMBER).map(|i| i as f64))
            .unwrap_or(0.0),
    }
}

/// Reads one DICOM file into HU (see [`dicom_slice_from_bytes`]); a file
/// above [`MAX_DICOM_FILE_BYTES`] is refused before it is read.
pub fn read_dicom_file(path: &Path) -> Result<DicomSlice, CtError> {
    let file = std::fs::File::open(path).map_err(|e| CtError::io(path, e))?;
    let len = file.metadata().map_err(|e| CtError::io(path, e))?.len();
    let too_large = |len: u64| {
        CtError::dicom(
            path,
            DicomProblem::TooLarge {
                len,
                limit: MAX_DICOM_FILE_BYTES,
            },
        )
    };
    if len > MAX_DICOM_FILE_BYTES {
        return Err(too_large(len));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    file.take(MAX_DICOM_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| CtError::io(path, e))?;
    if bytes.len() as u64 > MAX_DICOM_FILE_BYTES {
        return Err(too_large(bytes.len() as u64));
    }
    dicom_slice_from_bytes(path, &bytes)
}

/// Reads one DICOM image from the bytes of its file (`path` only names it
/// in errors). Every element header of the file meta information and the
/// data set is checked before any value is used: declared lengths against
/// the bytes that remain (in the file and in the enclosing sequence or
/// item), the transfer syntax (implicit or explicit VR little endian only),
/// sequence nesting ([`super::MAX_DICOM_NESTING`]) and the PixelData length
/// against `rows·cols·BitsAllocated/8`. Other errors: more than one frame
/// or sample per pixel, bits allocated other than 8/16, missing Rows,
/// Columns, PixelSpacing or PixelData, a RescaleSlope that is zero or not
/// finite, and a position, orientation, location or intercept that is not
/// finite. Errors name the file, the element's tag and its byte offset.
pub fn dicom_slice_from_bytes(path: &Path, bytes: &[u8]) -> Result<DicomSlice, CtError> {
    slice_from_bytes(path, bytes).map_err(|problem| CtError::dicom(path, problem))
}

fn slice_from_bytes(path: &Path, bytes: &[u8]) -> Result<DicomSlice, DicomProblem> {
    let (syntax, start) = file_meta(bytes)?;
    let mut attrs = Attributes::default();
    walk(bytes, (start, bytes.len()), syntax, "file", |tag, e| {
        if USED_TAGS.contains(&tag) {
            attrs.found.push((tag, e));
        }
        Ok(())
    })?;
    let format = PixelFormat::read(&attrs)?;
    let spacing = attrs
        .get(tags::PIXEL_SPACING)
        .and_then(numbers)
        .filter(|v| v.len() == 2 && v.iter().all(|s| s.is_finite() && *s > 0.0))
        .ok_or(DicomProblem::Missing("PixelSpacing"))?;
    let slope = attrs
        .finite(
            tags::RESCALE_SLOPE,
            "RescaleSlope",
            1,
            "a finite, non-zero number",
            |s| s != 0.0,
        )?
        .map_or(1.0, |v| v[0]);
    let intercept = attrs
        .finite(
            tags::RESCALE_INTERCEPT,
            "RescaleIntercept",
            1,
            "a finite number",
            |_| true,
        )?
        .map_or(0.0, |v| v[0]);
    let position = attrs
        .finite(
            tags::IMAGE_POSITION_PATIENT,
            "ImagePositionPatient",
            3,
            "three finite numbers (x, y, z in mm)",
            |_| true,
        )?
        .map(|v| [v[0], v[1], v[2]]);
    let orientation = attrs
        .finite(
            tags::IMAGE_ORIENTATION_PATIENT,
            "ImageOrientationPatient",
            6,
            "six finite direction cosines",
            |_| true,
        )?
        .map(|v| [v[0], v[1], v[2], v[3], v[4], v[5]]);
    let located = attrs
        .finite(
            tags::SLICE_LOCATION,
            "SliceLocation",
            1,
            "a finite number (mm)",
            |_| true,
        )?
        .map(|v| v[0]);
    let location = slice_location(&attrs, position, orientation, located);
    let thickness = attrs
        .get(tags::SLICE_THICKNESS)
        .and_then(numbers)
        .and_then(|v| v.first().copied());
    let pixels = format.pixels(&attrs)?;
    Ok(DicomSlice {
        path: path.to_owned(),
        rows: format.rows,
        cols: format.cols,
        row_spacing: spacing[0],
        col_spacing: spacing[1],
        position,
        orientation,
        slice_location: located,
        location,
        thickness,
        hu: format.hu(pixels, slope, intercept),
    })
}
