//! Writing results: PNG images with their reproducibility record embedded, and (later) sheets,
//! reports and charts.

pub mod png;

pub use self::png::{ExportError, write_png};
