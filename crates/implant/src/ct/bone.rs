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
use crate::geometry::Point;

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
/// (8-connectivity when `nz = 1`); ties go to the component met first in
/// z/y/x order.
fn largest_component(data: &[bool], nx: usize, ny: usize, nz: usize) -> Vec<bool> {
    let (label, sizes) = components(data, nx, ny, nz);
    let mut best = (0usize, 0u32);
    for (k, &size) in sizes.iter().enumerate() {
        if size > best.0 {
            best = (size, k as u32 + 1);
        }
    }
    label.iter().map(|&l| l != 0 && l == best.1).collect()
}

/// The components of a `nz × ny × nx` grid under 26-connectivity
/// (8-connectivity when `nz = 1`) by breadth-first labelling: each
/// sample's label (0 outside, labels from 1 in z/y/x order of the first
/// sample met) and each label's size.
fn components(data: &[bool], nx: usize, ny: usize, nz: usize) -> (Vec<u32>, Vec<usize>) {
    let mut label = vec![0u32; data.len()];
    let mut sizes = Vec::new();
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
        sizes.push(size);
    }
    (label, sizes)
}

/// The bone of one slice around a defect whose ends are `ends` (mm): as
/// [`bone_mask_slice`], the largest component, and where an end lies
/// farther than `radius_mm` from it, also the components with a pixel
/// within `radius_mm` of that end. A ring broken twice (an artificial cut
/// on a slice that has a real defect as well) is two pieces, each holding
/// one end; the largest alone would lose the other.
pub fn bone_mask_slice_holding(
    slice: &Slice,
    threshold: i16,
    ends: &[Point],
    radius_mm: f64,
) -> Result<Mask2, CtError> {
    let largest = bone_mask_slice(slice, threshold)?;
    let (sx, sy) = (slice.sx, slice.sy);
    // The pixels of `keep` within `radius_mm` of `p`.
    let near = |p: Point, keep: &dyn Fn(usize) -> bool| -> Vec<usize> {
        let (rr, rc) = (
            (radius_mm / sy).ceil() as i64,
            (radius_mm / sx).ceil() as i64,
        );
        let (r0, c0) = ((p.y / sy).round() as i64, (p.x / sx).round() as i64);
        let mut out = Vec::new();
        for r in (r0 - rr).max(0)..=(r0 + rr).min(slice.ny as i64 - 1) {
            for c in (c0 - rc).max(0)..=(c0 + rc).min(slice.nx as i64 - 1) {
                let i = r as usize * slice.nx + c as usize;
                let d = Point::new(c as f64 * sx, r as f64 * sy).distance(p);
                if d <= radius_mm && keep(i) {
                    out.push(i);
                }
            }
        }
        out
    };
    let far: Vec<Point> = ends
        .iter()
        .copied()
        .filter(|&p| near(p, &|i| largest.data[i]).is_empty())
        .collect();
    if far.is_empty() {
        return Ok(largest);
    }
    let t = threshold_slice(slice, threshold);
    let (label, _) = components(&t.data, t.nx, t.ny, 1);
    let mut wanted = std::collections::BTreeSet::new();
    for p in far {
        for i in near(p, &|i| t.data[i]) {
            wanted.insert(label[i]);
        }
    }
    Ok(Mask2 {
        nx: t.nx,
        ny: t.ny,
        data: largest
            .data
            .iter()
            .zip(&label)
            .map(|(&l, k)| l || wanted.contains(k))
            .collect(),
    })
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
