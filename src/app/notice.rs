//! Notices: messages for the user in the status bar, with their severity and how long they
//! stay. Every part of the viewer raises them (through the context); this file imports
//! nothing of the viewer.

use std::time::Instant;

/// How long a notice stays in the status bar.
pub const NOTICE_SECONDS: f64 = 12.0;

/// Severity of a notice.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// Something finished.
    Info,
    /// Something is off but work continues.
    Warning,
    /// Something failed.
    Error,
}

/// A message for the user in the status bar (and the notices list).
#[derive(Clone, Debug)]
pub struct Notice {
    /// Severity.
    pub level: Level,
    /// Text.
    pub text: String,
    /// When it was raised.
    pub at: Instant,
}
