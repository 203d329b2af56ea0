//! CT data layer for the cranial-implant chapter (thesis chapter 6): volumes
//! and their readers (`.inv3`, DICOM), bone segmentation, contours, defect
//! detection, the mirror technique, meshes and STL, voxel metrics
//! (AutoImplant, Li & Egger et al. 2021) and preview rendering.
//!
//! Frames: voxel `(z, y, x)` = (slice, row, column). In a slice, points are
//! in millimetres `x = col·sx`, `y = row·sy` (see [`volume`]); in 3D,
//! `z = slice·sz`. The volume origin is never added.

pub mod bone;
pub mod contour;
pub mod defect;
pub mod dicom;
pub mod error;
pub mod inv3;
pub mod mask;
pub mod plist;
pub mod polyline;
pub mod volume;

pub use bone::{
    bone_mask_slice, bone_mask_volume, largest_component_2d, largest_component_3d, threshold_slice,
    BONE_THRESHOLD_HU,
};
pub use contour::{bone_loops, marching_squares, table_contours, TableContours};
pub use defect::{detect_defect, Defect, DefectParams};
pub use dicom::{
    read_dicom_dir, read_dicom_file, read_dicom_series, write_dicom_series, DicomSlice,
};
pub use error::CtError;
pub use inv3::{read_inv3, write_inv3};
pub use mask::{Mask2, Mask3};
pub use polyline::{Nearest, Polyline};
pub use volume::{Slice, Spacing, Volume};

/// Index in the original 108-slice ProMED CT 0051 volume of slice 0 of the
/// vendored extract `data/ct0051/ct0051_z040-100.inv3` (see its PROVENANCE.md).
pub const CT0051_FIRST_Z: usize = 40;

/// Path of the vendored ProMED CT 0051 extract, relative to the crate root.
pub const CT0051_PATH: &str = "data/ct0051/ct0051_z040-100.inv3";
