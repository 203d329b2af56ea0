//! The house's own rules: the crates' layering, rooms that stay small, and
//! documents that quote the registry.

mod code_blocks;
mod documents;
mod layering;
mod links;
mod rooms;
