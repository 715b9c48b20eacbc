//! aa-lab: compare real-time antialiasing techniques on the same frame.
//!
//! The crate is one engine with two front ends: a headless command line (`render`, `compare`,
//! `bench`) and an egui viewer. Modules:
//! - [`gpu`]: device creation, capabilities, readback, shader loading, fullscreen passes;
//! - [`scene`]: scene data, procedural scenes, OBJ loading, camera, forward renderer;
//! - [`graph`]: the technique trait and the frame graph that shares scene renders between
//!   techniques, with timings and memory reports;
//! - [`aa`]: the registry and one folder per technique, with what they share in `aa::common`;
//! - [`spec`]: reproducible render descriptions and the headless runner;
//! - [`bench`]: the measurements `bench` takes, as library types;
//! - [`clip_recorder`]: the loop that records a clip, for `clip` and the viewer alike;
//! - [`metrics`]: SSIM, PSNR, MAE, FLIP (CPU and GPU), flicker, chart ground truth, timing
//!   summaries;
//! - [`export`]: PNG files with their render record;
//! - [`files`]: bounded reads of user files, atomic writes and the overwrite policy;
//! - [`sequence`]: image sequences (folders or globs of numbered PNG/JPEG/OpenEXR frames), read
//!   on demand through a bounded cache;
//! - [`srgb`]: the sRGB transfer function, once for the crate;
//! - [`text`]: text drawn into images with egui's bundled fonts (sheet labels, the UI overlay);
//! - [`cli`]: the command-line subcommands;
//! - [`app`]: the viewer (eframe/egui on the same frame graph);
//! - `profile` (cargo feature `profile`): the CPU profile of the viewer's UI frame.

pub mod aa;
pub mod app;
pub mod bench;
pub mod cli;
pub mod clip_recorder;
pub mod export;
pub mod files;
pub mod gpu;
pub mod graph;
pub mod metrics;
#[cfg(feature = "profile")]
pub mod profile;
pub mod scene;
pub mod sequence;
pub mod spec;
pub mod srgb;
pub mod text;
