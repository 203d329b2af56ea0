//! CT data layer for the cranial-implant chapter (thesis chapter 6): volumes
//! and their readers (`.inv3`, DICOM), bone segmentation, contours, defect
//! detection, the mirror technique, meshes and STL, voxel metrics
//! (AutoImplant, Li & Egger et al. 2021) and preview rendering.
//!
//! Frames: voxel `(z, y, x)` = (slice, row, column). In a slice, points are
//! in millimetres `x = col·sx`, `y = row·sy` (see [`volume`]); in 3D,
//! `z = slice·sz`: the *voxel millimetres* every computation uses. A
//! volume's [`Frame`] maps them to the scanner's patient coordinates (from
//! DICOM ImagePositionPatient / ImageOrientationPatient; the identity for an
//! `.inv3`), the frame of written meshes.

pub mod bone;
pub mod clip;
pub mod contour;
pub mod defect;
pub mod dicom;
pub mod edt;
pub mod error;
pub mod hull;
pub mod inv3;
pub mod mask;
pub mod mesh;
pub mod metrics;
pub mod mirror;
pub mod plist;
pub mod render;
pub mod stl;
pub mod symmetry3d;
pub mod triangulate;
pub mod volume;
pub mod voxelise;

pub use crate::geometry::{Nearest, Polyline};
pub use bone::{
    bone_mask_slice, bone_mask_slice_holding, bone_mask_volume, largest_component_2d,
    largest_component_3d, threshold_slice, BONE_THRESHOLD_HU,
};
pub use clip::{clip_to_tissue, clip_to_tissue_keeping, Clipped};
pub use contour::{bone_loops, marching_squares, table_contours, TableContours};
pub use defect::{detect_defect, Defect, DefectParams};
pub use dicom::{
    read_dicom_dir, read_dicom_file, read_dicom_series, write_dicom_series, DicomSlice,
};
pub use edt::edt_squared;
pub use error::{CtError, DicomProblem, Inv3Problem};
pub use hull::ConvexHull;
pub use inv3::{read_inv3, write_inv3};
pub use mask::{Mask2, Mask3};
pub use mesh::{
    loft, loft_rings, loft_rings_through, mesh_of_rings, resample_through, slice_mesh, Mesh,
};
pub use metrics::{
    boundary_dice, contour_deviation, dice, hd95, percentile, surface, surface_distances,
    ContourDeviation,
};
pub use mirror::{
    estimate_midline, estimate_tilted_midline, mirror_template, reflect, MidLine, Midline,
    MirrorTemplate, TiltedMidline,
};
pub use render::{
    encode_png, mesh_view, mesh_view_rgb, slice_overlay_png, slice_view_rgb, write_png, Canvas,
    MeshView, Overlay, SliceView, View, Window,
};
pub use stl::{parse_stl, stl_bytes, write_stl};
pub use symmetry3d::{
    bone_surface_points, estimate_symmetry_plane, mid_sagittal_plane, IcpOptions, Plane3,
    SurfacePoints, SymmetryPlane,
};
pub use triangulate::ear_clip;
pub use volume::{
    Anatomy, Frame, FrameSource, PatientDirection, Slice, Spacing, Volume, IDENTITY_AXES,
    INV3_ANATOMY,
};
pub use voxelise::{voxelise, voxelise_mesh};

/// Index in the original 108-slice ProMED CT 0051 volume of slice 0 of the
/// vendored extract `data/ct0051/ct0051_z040-100.inv3` (see its PROVENANCE.md).
pub const CT0051_FIRST_Z: usize = 40;

/// A pixel position `(row, col)` in a slice.
pub type Pixel = (usize, usize);

/// The bone-gap end points A and B of the real defect of ProMED CT 0051,
/// measured by hand on three slices: `(z, (row, col) of A, (row, col) of B)`
/// with `z` in the full volume's slice index. The reference for
/// [`detect_defect`] and the ends given to the chapter-6 pipeline.
pub const CT0051_MEASURED_ENDS: [(usize, Pixel, Pixel); 3] = [
    (64, (196, 111), (188, 86)),
    (72, (194, 107), (184, 86)),
    (80, (185, 104), (179, 93)),
];

/// Path of the vendored ProMED CT 0051 extract, relative to the crate root.
pub const CT0051_PATH: &str = "data/ct0051/ct0051_z040-100.inv3";
