//! Campaigns through the binary: specs and their errors, bad input, resume, run
//! identity, clusters and shards, hardening, reader caps, archives, citation
//! and the command line.

#[path = "../common/mod.rs"]
mod common;

mod archive;
mod bad_input;
mod campaign_tests;
mod citation;
mod cli;
mod cluster;
mod hardening;
mod properties;
mod reader_caps;
mod resume_checks;
mod run_identity;
mod spec_errors;
