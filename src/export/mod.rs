//! Writing results: animated PNG/GIF clips, PNG images with their reproducibility record embedded, labelled comparison
//! sheets of zoomed crops, text rendering for them, error heatmaps with legends, bench reports
//! (JSON and Markdown) and charts.

pub mod animation;
pub mod charts;
pub mod clip;
pub mod heatmap;
pub mod png;
pub mod report;
pub mod sheet;
pub mod text;

pub use self::png::{ExportError, write_png};
