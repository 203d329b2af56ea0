//! The cranial implant (chapter 6): CT readers, the implant pipeline, its
//! continuation, CQ500, figures, inner wall, orientation, plausibility and the
//! rim template.

#[path = "../common/mod.rs"]
mod common;
#[path = "../ct_inputs/mod.rs"]
mod ct_inputs;

mod ct;
mod implant_continuation;
mod implant_cq500;
mod implant_figures;
mod implant_inner_wall;
mod implant_orientation;
mod implant_plausibility;
mod implant_rim;
mod implant_tests;
