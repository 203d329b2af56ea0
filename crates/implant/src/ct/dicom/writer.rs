//! A minimal explicit-VR little-endian CT Image Storage writer, built on
//! the pure-Rust `dicom-object` crate.

use std::path::{Path, PathBuf};

use dicom_core::value::PrimitiveValue;
use dicom_core::{DataElement, Tag, VR};
use dicom_dictionary_std::{tags, uids};
use dicom_object::{FileMetaTableBuilder, InMemDicomObject};

use super::normal;
use crate::ct::error::CtError;
use crate::ct::volume::Volume;
use crate::files::write_atomic;

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
