//! Bone segmentation: a Hounsfield threshold (cortical bone ≥ 300 HU by
//! default) followed by keeping the largest connected component.
//!
//! Two variants: per slice with 8-connectivity ([`largest_component_2d`]),
//! used by the slice pipeline, and over the volume with 26-connectivity
//! ([`largest_component_3d`]). On ProMED CT 0051 both drop the head holder
//! and the table (separate components in every vault slice), which the tests
//! check on the vendored slices.

use std::collections::VecDeque;

use super::error::CtError;
use super::mask::{Mask2, Mask3};
use super::volume::{Slice, Volume};

/// The default bone threshold in HU.
pub const BONE_THRESHOLD_HU: i16 = 300;

/// `HU ≥ threshold` per pixel.
pub fn threshold_slice(slice: &Slice, threshold: i16) -> Mask2 {
    Mask2 {
        nx: slice.nx,
        ny: slice.ny,
        data: slice.data.iter().map(|&v| v >= threshold).collect(),
    }
}

/// The largest 8-connected component of `mask` (ties: the one met first in
/// row-major order); an empty mask stays empty.
pub fn largest_component_2d(mask: &Mask2) -> Mask2 {
    Mask2 {
        nx: mask.nx,
        ny: mask.ny,
        data: largest_component(&mask.data, mask.nx, mask.ny, 1),
    }
}

/// The largest 26-connected component of `mask` (ties: first met in z/y/x
/// order); an empty mask stays empty.
pub fn largest_component_3d(mask: &Mask3) -> Mask3 {
    Mask3 {
        data: largest_component(&mask.data, mask.nx, mask.ny, mask.nz),
        ..mask.clone()
    }
}

/// The largest component of a `nz × ny × nx` grid under 26-connectivity
/// (8-connectivity when `nz = 1`), by breadth-first labelling; ties go to
/// the component met first in z/y/x order.
fn largest_component(data: &[bool], nx: usize, ny: usize, nz: usize) -> Vec<bool> {
    let mut label = vec![0u32; data.len()];
    let mut best = (0usize, 0u32);
    let mut next = 0u32;
    let mut queue = VecDeque::new();
    for start in 0..data.len() {
        if !data[start] || label[start] != 0 {
            continue;
        }
        next += 1;
        label[start] = next;
        queue.push_back(start);
        let mut size = 0;
        while let Some(i) = queue.pop_front() {
            size += 1;
            let (z, y, x) = (i / (nx * ny), (i / nx) % ny, i % nx);
            for zz in z.saturating_sub(1)..=(z + 1).min(nz - 1) {
                for yy in y.saturating_sub(1)..=(y + 1).min(ny - 1) {
                    for xx in x.saturating_sub(1)..=(x + 1).min(nx - 1) {
                        let j = (zz * ny + yy) * nx + xx;
                        if data[j] && label[j] == 0 {
                            label[j] = next;
                            queue.push_back(j);
                        }
                    }
                }
            }
        }
        if size > best.0 {
            best = (size, next);
        }
    }
    label.iter().map(|&l| l != 0 && l == best.1).collect()
}

/// The bone of one slice: threshold, then the largest 8-connected
/// component. Error [`CtError::NoBone`] when no pixel reaches `threshold`.
pub fn bone_mask_slice(slice: &Slice, threshold: i16) -> Result<Mask2, CtError> {
    let t = threshold_slice(slice, threshold);
    if t.count() == 0 {
        return Err(CtError::NoBone {
            slice: slice.z,
            threshold,
        });
    }
    Ok(largest_component_2d(&t))
}

/// The bone of a volume: threshold, then the largest 26-connected
/// component. Error [`CtError::NoBone`] (naming the first empty slice) when
/// any slice has no pixel at or above `threshold`.
pub fn bone_mask_volume(volume: &Volume, threshold: i16) -> Result<Mask3, CtError> {
    let n = volume.nx * volume.ny;
    for z in 0..volume.nz {
        if !volume.data()[z * n..(z + 1) * n]
            .iter()
            .any(|&v| v >= threshold)
        {
            return Err(CtError::NoBone {
                slice: z,
                threshold,
            });
        }
    }
    let m = Mask3 {
        nx: volume.nx,
        ny: volume.ny,
        nz: volume.nz,
        spacing: volume.spacing,
        data: volume.data().iter().map(|&v| v >= threshold).collect(),
    };
    Ok(largest_component_3d(&m))
}
