//! Chapter 6 of the thesis: a cranial implant from CT slices.
//!
//! The user marks the ends A and B of the bone defect on each slice (or
//! they are detected); reflecting them across the mid-sagittal line `M_x`
//! gives C and D, and the intact outer contour between C and D reflected
//! back is the template of the missing contour (the mirror technique). The
//! missing outer contour is fitted with the chapter-5 Bézier scheme between
//! the fixed ends, joined G¹ or C¹ to the intact contour; the inner wall is
//! the offset `PO(u) = C(u) + Dis(u)·N(u)`; the slices are lofted into a
//! closed mesh written as STL. The validation follows the AutoImplant
//! challenge (Li & Egger et al., "AutoImplant 2020 — first MICCAI challenge
//! on automatic cranial implant design", IEEE TMI 40(9), 2021): artificial
//! defects cut out of intact bone, compared with the removed bone by Dice,
//! boundary Dice and HD95.
//!
//! | module | concept |
//! |---|---|
//! | [`wall`] | one slice's outer and inner wall ([`reconstruct_wall`]) |
//! | [`pipeline`] | the real defect: slices → mesh → voxels ([`reconstruct_defect`]) |
//! | [`validation`] | artificial defects on intact bone, AutoImplant metrics |
//! | [`spec`], [`run`] | the TOML experiment and its driver (`metabezier implant`) |
//! | [`render`] | its outputs: report sections, CSV tables, overlay and preview PNGs |

pub mod pipeline;
pub mod wall;

pub use pipeline::{
    build_mesh, reconstruct_defect, reconstruct_slice, resolve_midline, slice_mask, DefectConfig,
    Ends, Implant, ImplantError, MidlineSpec, SliceResult, SliceSpec,
};
pub use wall::{envelope_radius, reconstruct_wall, Wall, WallInput, WallKind, WallOptions};
pub mod render;
pub mod run;
pub mod spec;
pub mod validation;

pub use run::{load_volume, run_implant, RunSummary};
pub use spec::{ImplantSpec, ValidationSpec};
pub use validation::{
    case_metrics, evaluate, prepare_case, reconstruct_case, Case, CaseError, CaseMetrics,
    PreparedCase, ValidationRow,
};
