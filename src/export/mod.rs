//! Writing results: clips (streamed animated PNG/GIF, MP4/WebM through ffmpeg), PNG images with their reproducibility record embedded, labelled comparison
//! sheets of zoomed crops, text rendering for them, error heatmaps with legends, bench reports
//! (JSON and Markdown) and charts.

pub mod animation;
pub mod apng;
pub mod charts;
pub mod clip;
pub mod clip_writer;
pub mod frame_change;
pub mod gif;
pub mod heatmap;
pub mod html;
pub mod png;
pub mod report;
pub mod report_markdown;
pub mod sheet;
pub mod text;
pub mod video;

pub use self::png::{ExportError, write_png};
