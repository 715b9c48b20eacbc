//! Writing results: PNG images with their reproducibility record embedded, labelled comparison
//! sheets of zoomed crops, and text rendering for them.

pub mod png;
pub mod sheet;
pub mod text;

pub use self::png::{ExportError, write_png};
