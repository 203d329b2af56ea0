//! The house's own rules: the crates' layering, and rooms that stay small.

mod layering;
mod rooms;
