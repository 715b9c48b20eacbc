//! What can go wrong reading an OBJ or MTL file ([`ObjError`], every message naming the file
//! and, for a malformed record, the line), the size limits, and the bounded reading of either
//! file as UTF-8 text that every other part of the loader starts from.

use std::io;
use std::path::{Path, PathBuf};

use crate::files::{self, FileError};

/// Largest OBJ file read.
pub const MAX_OBJ_BYTES: u64 = 2 << 30;
/// Largest MTL file read.
pub const MAX_MTL_BYTES: u64 = 64 << 20;

/// Why an OBJ file could not be loaded. Every message names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file is not a regular file or is too large to read.
    #[error(transparent)]
    File(FileError),
    /// The file could not be read (missing, a directory, no permission, ...).
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// File that was read.
        path: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// The file is binary data or not UTF-8 text.
    #[error("{} is not a text OBJ/MTL file: {reason}", path.display())]
    NotText {
        /// File that was read.
        path: PathBuf,
        /// What gave it away.
        reason: String,
    },
    /// The file has no faces to draw (it is empty, or holds only vertices or comments).
    #[error("{} has no faces: nothing to draw", path.display())]
    NoFaces {
        /// The OBJ file.
        path: PathBuf,
    },
    /// A record of the OBJ or MTL file is malformed.
    #[error("{}, line {line}: {message}", path.display())]
    Syntax {
        /// File with the record.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A face refers to a vertex, texture coordinate or normal that does not exist.
    #[error(
        "{}, line {line}: face refers to {kind} {index}, but only {count} are defined before it",
        path.display()
    )]
    IndexOutOfRange {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number of the face.
        line: usize,
        /// `vertex`, `texture coordinate` or `normal`.
        kind: &'static str,
        /// The index as written (negative indices count back from the last element).
        index: i64,
        /// How many elements of that kind precede the face.
        count: usize,
    },
    /// A vertex, texture coordinate or normal has a NaN or infinite component.
    #[error("{}, line {line}: {kind} {index} has a non-finite component ({value})", path.display())]
    NonFinite {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// `vertex`, `texture coordinate` or `normal`.
        kind: &'static str,
        /// 1-based OBJ index of the element.
        index: usize,
        /// The offending value as written (or as computed, after a `w` division).
        value: String,
    },
    /// A material library named by `mtllib` could not be read.
    #[error(
        "cannot read material library {} (named by {}): {source}",
        mtl.display(),
        obj.display()
    )]
    MissingMtl {
        /// The OBJ file that names the library.
        obj: PathBuf,
        /// The path the library was looked for at.
        mtl: PathBuf,
        /// The operating system's error.
        #[source]
        source: io::Error,
    },
    /// `tobj` rejected a file the validation pass let through.
    #[error("{} could not be parsed: {source}", path.display())]
    Parse {
        /// The OBJ or MTL file.
        path: PathBuf,
        /// `tobj`'s error.
        #[source]
        source: tobj::LoadError,
    },
}

/// Why a file could not be turned into text.
pub(super) enum ReadFailure {
    Io(io::Error),
    File(FileError),
    NotText(String),
}

impl ReadFailure {
    pub(super) fn into_error(self, path: &Path) -> ObjError {
        let path = path.to_owned();
        match self {
            Self::Io(source) => ObjError::Io { path, source },
            Self::File(error) => ObjError::File(error),
            Self::NotText(reason) => ObjError::NotText { path, reason },
        }
    }
}

/// Reads a whole regular file of at most `limit` bytes as UTF-8 text, rejecting binary data
/// and skipping a byte-order mark.
pub(super) fn read_text(
    path: &Path,
    limit: u64,
    what: &'static str,
) -> Result<String, ReadFailure> {
    let bytes = files::read_bounded(path, limit, what).map_err(|error| match error {
        FileError::Read { source, .. } => ReadFailure::Io(source),
        other => ReadFailure::File(other),
    })?;
    if let Some(at) = bytes.iter().position(|&b| b == 0) {
        return Err(ReadFailure::NotText(format!(
            "NUL byte at offset {at} (binary data)"
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        ReadFailure::NotText(format!(
            "invalid UTF-8 at byte offset {}",
            e.utf8_error().valid_up_to()
        ))
    })?;
    Ok(match text.strip_prefix('\u{feff}') {
        Some(rest) => rest.to_owned(),
        None => text,
    })
}

pub(super) fn syntax(path: &Path, line: usize, message: String) -> ObjError {
    ObjError::Syntax {
        path: path.to_owned(),
        line,
        message,
    }
}

/// Parses a number of an OBJ/MTL record, naming the record in the error.
pub(super) fn parse_number(
    path: &Path,
    line: usize,
    record: &str,
    word: &str,
) -> Result<f32, ObjError> {
    word.parse()
        .map_err(|_| syntax(path, line, format!("{record}: '{word}' is not a number")))
}
