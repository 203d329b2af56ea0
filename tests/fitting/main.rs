//! Curve fitting (chapter 5): outlines, fits and their guarantees, exact fits,
//! the joint chain, tolerances, fitting campaigns and the reconstruction
//! pipeline.

#[path = "../common/mod.rs"]
mod common;

mod coarse_trials;
mod exact_fit;
mod fit;
mod fit_campaign_tolerance;
mod fit_corpus;
mod fit_guarantees;
mod joint_chain;
mod outline;
mod reconstruction;
mod tolerance;
