//! aa-lab: compare real-time antialiasing techniques on the same frame.
//!
//! The crate is one engine with two front ends: a headless command line (`render`, `compare`,
//! `bench`) and an egui viewer. See `README.md` for the tour and `shaders/` for the WGSL.

pub mod gpu;
pub mod scene;
