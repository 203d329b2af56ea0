//! The house's own rules: the crates' layering, rooms that stay small, and
//! documents that quote the registry.

mod documents;
mod layering;
mod rooms;
