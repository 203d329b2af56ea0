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
//! | [`wall_input`] | what a wall is given: its kind, options and the contours around a defect |
//! | [`polar`] | the contours about the polar centre: envelope, mirror, local table, thickness |
//! | [`continuation`] | the template across the midline: both sides continued, G² (beyond the thesis) |
//! | [`wall`] | one slice's outer and inner wall ([`design_outer`], [`finish_wall`], [`reconstruct_wall`]) |
//! | [`delivered`] | the STL's ring of each slice measured like the design: kinks at the seats, thickness |
//! | [`seats`] | the seats A′ and B′ of a stack of slices, chosen jointly (Viterbi) |
//! | [`smooth`] | thickness and outer-wall smoothing across slices |
//! | [`pipeline`] | the real defect: slices → mesh → voxels ([`reconstruct_defect`]) |
//! | [`regions`] | where the method works: validation cases by region (front, back, vertex, skull base) |
//! | [`validation`] | artificial defects on intact bone, one slice each, AutoImplant metrics |
//! | [`validation3d`] | patches across slices through the whole pipeline, 3D metrics |
//! | [`spec`], [`run`] | the TOML experiment and its driver (`metabezier implant`) |
//! | [`checks`] | the spec checked against its volume before anything is computed or written |
//! | [`plausibility`] | each designed slice checked before anything is written (width jump, hull, wrap, volume, fit) |
//! | [`units`] | the independent units of the validation verdicts (slice clusters × positions) |
//! | [`tables`], [`tables3d`] | its tables: report sections and CSV files |
//! | [`rim_fill`] | the rim fill: a sphere and a thin-plate spline through the bone around a defect, in 3D |
//! | [`ray_template`], [`template_source`] | a template as a radius per ray; which template a wall used |
//! | [`surface_template`] | the 3D templates (`mirror3d`, `rim`) sliced to one outer-wall curve per defect slice |
//! | [`template_comparison`] | the slice-wise, 3D-mirror, rim-fill and straight templates compared by region as tested verdicts |
//! | [`render`] | its pictures: slice overlays and the 3D preview |

pub mod check_limits;
pub mod checks;
pub mod continuation;
pub mod delivered;
pub mod pipeline;
pub mod plausibility;
pub mod polar;
pub mod ray_template;
pub mod refusal;
pub mod regions;
pub mod rim_fill;
pub mod seats;
pub mod slice_error;
pub mod smooth;
pub mod surface_template;
pub mod template_source;
pub mod wall;
pub mod wall_input;

pub use continuation::TemplateSource;
pub use pipeline::{
    build_mesh, build_mesh_through, build_mesh_with, check_distinct_ends, index_of,
    reconstruct_defect, reconstruct_defect_with, reconstruct_from, resolve_midline, slice_context,
    slice_index, slice_mask, DefectConfig, Ends, Implant, ImplantError, MidlineSpec, SliceContext,
    SliceResult, SliceSpec, Smoothing, Templates, MIN_MIDLINE_DICE,
};
pub use plausibility::{Check, CheckValues, Finding, PlausibilityLimits};
pub use seats::{choose_seats, SeatProfile, SeatRule};
pub use slice_error::SliceError;
pub use smooth::{lipschitz_envelope, roughness, smooth_outer_walls};
pub use wall::{
    angle_deg, design_outer, envelope_radius, finish_wall, reconstruct_wall, refit_outer,
    seat_profiles, seat_rule, OuterDesign, Wall, WallInput, WallKind, WallOptions,
};
pub use wall_input::{TemplateChoice, ThicknessProfile};
pub mod render;
pub mod run;
pub mod spec;
pub mod tables;
pub mod tables2d;
pub mod tables3d;
pub mod template;
pub mod template_comparison;
pub mod units;
pub mod validation;
pub mod validation3d;
pub mod verdict_tables;

pub use run::{load_volume, run_implant, run_implant_with, RunOptions, RunSummary, PARTIAL_STL};
pub use spec::{ImplantSpec, Validation3dSpec, ValidationSpec};
pub use template::{read_templates, templates_csv};
pub use validation::{
    case_metrics, evaluate, prepare_case, reconstruct_case, reconstruct_case_with, Case, CaseError,
    CaseMetrics, PreparedCase, ValidationRow,
};
pub use validation3d::{
    evaluate_3d, prepare_case_3d, score_3d, Case3d, Metrics3d, Prepared3d, Row3d,
};
