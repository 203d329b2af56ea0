//! A DICOM series stacked into a volume: sorted along the slice normal,
//! every slice checked to share the size, spacing and orientation, and the
//! gaps between slice positions checked to be even.

use std::path::{Path, PathBuf};

use super::slice::read_dicom_file;
use super::{normal, DicomSlice};
use crate::ct::error::CtError;
use crate::ct::volume::{FrameSource, Spacing, Volume};

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-3 * a.abs().max(b.abs()).max(1.0)
}

/// Stacks DICOM files into a volume, sorted by position along the slice
/// normal (z increasing). Refuses (naming the first offending file) slices of
/// different sizes, different pixel spacing, a slice without a position
/// when the series has more than one (ImagePositionPatient on every slice,
/// or SliceLocation on every slice when none has a position), two slices at
/// one position, or uneven gaps between slice positions (relative tolerance
/// 10⁻³); a single slice gets its SliceThickness (or 1 mm) as z spacing.
pub fn read_dicom_series(paths: &[PathBuf]) -> Result<Volume, CtError> {
    if paths.is_empty() {
        return Err(CtError::EmptySeries);
    }
    let mut slices = paths
        .iter()
        .map(|p| read_dicom_file(p))
        .collect::<Result<Vec<_>, _>>()?;
    check_positions(&slices)?;
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
    if let Some(o) = slices[0].orientation {
        check_orthogonal(&slices[0].path, o)?;
    }
    let z_known = slices.len() > 1 || slices[0].thickness.is_some_and(|t| t > 0.0);
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
    let mut v = Volume::new(nx, ny, nz, spacing, origin, data)?.with_frame(
        origin,
        axes,
        FrameSource::Dicom,
    )?;
    v.z_spacing_known = z_known;
    Ok(v)
}

/// ImageOrientationPatient `o` of the slice at `path` must be two
/// orthogonal unit vectors (within 10⁻³, DICOM PS3.3 C.7.6.2.1.1).
fn check_orthogonal(path: &Path, o: [f64; 6]) -> Result<(), CtError> {
    let (r, c) = ([o[0], o[1], o[2]], [o[3], o[4], o[5]]);
    let dot = r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
    let len = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let (row_len, col_len) = (len(r), len(c));
    if dot.abs() > 1e-3 || (row_len - 1.0).abs() > 1e-3 || (col_len - 1.0).abs() > 1e-3 {
        return Err(CtError::OrientationNotOrthogonal {
            path: path.to_path_buf(),
            orientation: o,
            dot,
            row_len,
            col_len,
        });
    }
    Ok(())
}

/// Checks that every slice of a series of more than one says where it lies:
/// ImagePositionPatient on every slice when any slice has it, else
/// SliceLocation on every slice (InstanceNumber orders slices but does not
/// space them). The error names the first slice without it.
fn check_positions(slices: &[DicomSlice]) -> Result<(), CtError> {
    if slices.len() < 2 {
        return Ok(());
    }
    let positioned = slices.iter().any(|s| s.position.is_some());
    let missing = slices.iter().find(|s| {
        if positioned {
            s.position.is_none()
        } else {
            s.slice_location.is_none()
        }
    });
    match missing {
        Some(s) => Err(CtError::MissingPosition {
            path: s.path.clone(),
            tags: if positioned {
                "ImagePositionPatient (0020,0032)"
            } else {
                "ImagePositionPatient (0020,0032) or SliceLocation (0020,1041)"
            },
            slices: slices.len(),
        }),
        None => Ok(()),
    }
}

/// The slice spacing of a sorted series: the distance between the first
/// and last ImagePositionPatient over `n − 1` (the locations along the
/// normal when a position is missing), after checking that no two slices
/// share a position and that the gaps along the normal are even; a single
/// slice gets its SliceThickness (or 1 mm).
fn slice_step(slices: &[DicomSlice]) -> Result<f64, CtError> {
    let first = &slices[0];
    Ok(if slices.len() > 1 {
        for w in slices.windows(2) {
            if w[1].location == w[0].location {
                return Err(CtError::DuplicatePosition {
                    path: w[1].path.clone(),
                    other: w[0].path.clone(),
                    location: w[1].location,
                });
            }
        }
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
