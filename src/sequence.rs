//! Image sequences: a folder or a glob of numbered frames (PNG, JPEG or OpenEXR) that play in
//! lockstep like a recorded clip, for `aa-lab compare` on two folders and anything else that
//! scores captures from an engine frame by frame.
//!
//! # Opening
//! [`Sequence::open`] takes a folder (every PNG, JPEG and OpenEXR file in it; hidden files,
//! sub-folders and files of other types are left out, so a capture's logs or sidecars may sit
//! beside its frames) or a glob whose wildcards (`*`, `?`, `[...]`) are in the file name only
//! (`captures/taa_*.png`), matched with the `glob` crate's patterns against one directory
//! listing. The frame number of a file is the last run of digits in its name without the
//! extension (`shot2_0017.exr` is frame 17), and frames play in numeric order, so `frame_9`
//! comes before `frame_10` whatever the padding. The numbers must run without gaps (from any
//! first number), every file must name its frame the same way (the same text around the
//! number, one format), and no number may appear twice: each of these is an error naming the
//! files at fault.
//!
//! Opening reads the directory listing and the first frame's header (its size), nothing more,
//! so a thousand-frame 1080p capture opens at once. A frame is read when asked for
//! ([`Sequence::frame`]): a bounded read of the whole file ([`files::read_bounded`]), its
//! header checked against the first frame's size before anything is decoded (a frame of
//! another size is an error naming it and both sizes), then decoded. Decoded frames stay in a
//! small least-recently-used cache under a byte cap ([`DEFAULT_CACHE_BYTES`], or
//! [`Sequence::with_cache_bytes`]); a frame larger than the cap is returned but not kept.
//!
//! # Colour
//! The metrics work on 8-bit sRGB-encoded RGBA, so every frame is delivered that way
//! ([`srgb::display_rgba8`]): PNG and JPEG frames as they are (8- or 16-bit, the latter
//! scaled), OpenEXR frames as linear light, clamped to 0..1 and sRGB-encoded: what an SDR
//! display shows of the frame without tonemapping, where highlights above 1 all become white.
//! An HDR capture whose highlights are compared goes through a tonemapper instead
//! ([`Sequence::with_tonemap`]: exposure and operator as the renders' own, `graph::hdr`), so
//! captured frames and rendered ones are displayed by the same curve.

use std::collections::VecDeque;
use std::io::Cursor;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use image::{ImageFormat, ImageReader, RgbaImage};

use crate::files::{self, FileError};
use crate::scene::renderer::Tonemap;
use crate::srgb;

/// Most frames a sequence may have.
pub const MAX_FRAMES: usize = 100_000;

/// Most directory entries listed when opening a sequence (files of other kinds included).
pub const MAX_LISTING_ENTRIES: usize = 1_000_000;

/// Most pixels a frame may have: 8K UHD (7680x4320) fits.
pub const MAX_FRAME_PIXELS: u64 = 1 << 25;

/// Decoded frames a sequence keeps by default, in bytes of RGBA8 (16 frames of 1920x1080).
pub const DEFAULT_CACHE_BYTES: usize = 16 * 1920 * 1080 * 4;

/// What [`files::read_bounded`] says a frame file was read as.
const FRAME_PURPOSE: &str = "a sequence frame";

/// Errors of opening a sequence or reading its frames.
#[derive(Debug, thiserror::Error)]
pub enum SequenceError {
    /// The folder could not be listed.
    #[error("cannot list {}: {source}", path.display())]
    List {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The glob is malformed, or has wildcards outside the file name.
    #[error("{pattern} is not a sequence pattern: {reason}")]
    Pattern {
        /// The pattern as given.
        pattern: String,
        /// Why.
        reason: String,
    },
    /// The folder has more entries, or the pattern more matches, than a sequence may.
    #[error("{} has more than {limit} {what}", path.display())]
    TooMany {
        /// The folder or pattern.
        path: PathBuf,
        /// The limit.
        limit: usize,
        /// `directory entries` or `frames`.
        what: &'static str,
    },
    /// Nothing matched.
    #[error(
        "{} holds no frames: a sequence is numbered PNG, JPEG or OpenEXR files (frame_0001.png, ...)",
        path.display()
    )]
    Empty {
        /// The folder or pattern.
        path: PathBuf,
    },
    /// A matched file is not PNG, JPEG or OpenEXR.
    #[error("{} is not a PNG, JPEG or OpenEXR file (by its extension)", path.display())]
    Format {
        /// The file.
        path: PathBuf,
    },
    /// A file has no digits in its name.
    #[error(
        "{} has no frame number: every file of a sequence has digits in its name (frame_0001.png)",
        path.display()
    )]
    Unnumbered {
        /// The file.
        path: PathBuf,
    },
    /// Two files name their frames differently (another prefix, suffix or format).
    #[error(
        "{} and {} do not belong to one sequence: their names differ around the frame number, or their formats differ",
        first.display(), second.display()
    )]
    Naming {
        /// A file of the sequence.
        first: PathBuf,
        /// A file named otherwise.
        second: PathBuf,
    },
    /// Two files have the same frame number.
    #[error("{} and {} are both frame {number}", first.display(), second.display())]
    Duplicate {
        /// The frame number.
        number: u64,
        /// One file.
        first: PathBuf,
        /// The other.
        second: PathBuf,
    },
    /// Frame numbers skip.
    #[error(
        "{} missing: {} is followed by {}",
        missing_frames(*first_missing, *last_missing), before.display(), after.display()
    )]
    Missing {
        /// The first number missing.
        first_missing: u64,
        /// The last number missing.
        last_missing: u64,
        /// The frame before the gap.
        before: PathBuf,
        /// The frame after it.
        after: PathBuf,
    },
    /// A frame file could not be read.
    #[error(transparent)]
    File(#[from] FileError),
    /// A frame file does not decode.
    #[error("cannot decode {}: {reason}", path.display())]
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        reason: String,
    },
    /// A frame has too many pixels.
    #[error(
        "{} is {}x{}, more than the {limit} pixels a sequence frame may have",
        path.display(), size.0, size.1
    )]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size.
        size: (u32, u32),
        /// The limit.
        limit: u64,
    },
    /// A frame has another size than the first.
    #[error(
        "{} is {}x{} but the sequence's first frame {} is {}x{}; every frame must have the same size",
        path.display(), size.0, size.1, first.display(), first_size.0, first_size.1
    )]
    FrameSize {
        /// The frame.
        path: PathBuf,
        /// Its size.
        size: (u32, u32),
        /// The first frame.
        first: PathBuf,
        /// The first frame's size.
        first_size: (u32, u32),
    },
    /// A frame index past the end.
    #[error("frame index {index} is past the end of a {frames}-frame sequence")]
    OutOfRange {
        /// The index asked for.
        index: usize,
        /// The sequence's length.
        frames: usize,
    },
    /// Two sequences compared differ in frame count or size.
    #[error("{0}")]
    Mismatch(String),
}

/// `frame 3 is` or `frames 3 to 5 are`, for [`SequenceError::Missing`].
fn missing_frames(first: u64, last: u64) -> String {
    if first == last {
        format!("frame {first} is")
    } else {
        format!("frames {first} to {last} are")
    }
}

/// One file of a sequence.
#[derive(Clone, Debug)]
struct FrameFile {
    path: PathBuf,
    number: u64,
}

/// A file name split around its frame number: the text before and after (with the
/// extension, lowercased) and the number.
struct FrameName {
    prefix: String,
    suffix: String,
    number: u64,
}

impl FrameName {
    /// Splits `name` at the last run of digits of its stem; `None` without one (or with more
    /// digits than a frame number holds).
    fn parse(name: &str) -> Option<Self> {
        let (stem, extension) = name.rsplit_once('.').unwrap_or((name, ""));
        let end = stem.rfind(|c: char| c.is_ascii_digit())? + 1;
        let start = stem[..end]
            .rfind(|c: char| !c.is_ascii_digit())
            .map_or(0, |i| i + 1);
        Some(Self {
            prefix: stem[..start].to_owned(),
            suffix: format!("{}.{}", &stem[end..], extension.to_ascii_lowercase()),
            number: stem[start..end].parse().ok()?,
        })
    }
}

/// The format of a frame file by its extension, `None` for anything but PNG, JPEG, OpenEXR.
fn frame_format(path: &Path) -> Option<ImageFormat> {
    let format = ImageFormat::from_path(path).ok()?;
    matches!(
        format,
        ImageFormat::Png | ImageFormat::Jpeg | ImageFormat::OpenExr
    )
    .then_some(format)
}

/// Decoded frames, most recently used last, under a byte cap.
#[derive(Debug)]
struct FrameCache {
    frames: VecDeque<(usize, Arc<RgbaImage>)>,
    bytes: usize,
    cap: usize,
    /// How linear (OpenEXR) frames reach display values; `None` clamps them. Kept with the
    /// frames it made, so a change and the frames it drops are one step.
    tonemap: Option<Tonemap>,
}

impl FrameCache {
    /// Drops every frame kept.
    fn forget(&mut self) {
        self.frames.clear();
        self.bytes = 0;
    }

    fn get(&mut self, index: usize) -> Option<Arc<RgbaImage>> {
        let position = self.frames.iter().position(|(i, _)| *i == index)?;
        let entry = self.frames.remove(position)?;
        let frame = Arc::clone(&entry.1);
        self.frames.push_back(entry);
        Some(frame)
    }

    fn insert(&mut self, index: usize, frame: &Arc<RgbaImage>) {
        let size = frame.as_raw().len();
        // Two threads may decode the same frame at once: keep one copy.
        if size > self.cap || self.frames.iter().any(|(i, _)| *i == index) {
            return;
        }
        while self.bytes + size > self.cap {
            match self.frames.pop_front() {
                Some((_, old)) => self.bytes -= old.as_raw().len(),
                None => break,
            }
        }
        self.bytes += size;
        self.frames.push_back((index, Arc::clone(frame)));
    }
}

/// A sequence of numbered frames on disk, read on demand (see the module docs).
#[derive(Debug)]
pub struct Sequence {
    source: PathBuf,
    frames: Vec<FrameFile>,
    format: ImageFormat,
    size: (u32, u32),
    cache: Mutex<FrameCache>,
    decoded: AtomicU64,
}

impl Sequence {
    /// Opens the sequence a folder or a glob names (see the module docs): reads the listing
    /// and the first frame's header.
    pub fn open(path: &Path) -> Result<Self, SequenceError> {
        let mut frames = list_frames(path)?;
        frames.sort_by_key(|f| f.number);
        check_numbering(&frames)?;
        let first = frames.first().ok_or_else(|| SequenceError::Empty {
            path: path.to_owned(),
        })?;
        let format = frame_format(&first.path).ok_or_else(|| SequenceError::Format {
            path: first.path.clone(),
        })?;
        files::check_regular(&first.path, files::MAX_IMAGE_FILE_BYTES, FRAME_PURPOSE)?;
        let mut reader =
            ImageReader::open(&first.path).map_err(|e| decode_error(&first.path, e))?;
        reader.set_format(format);
        let size = reader
            .into_dimensions()
            .map_err(|e| decode_error(&first.path, e))?;
        check_pixels(&first.path, size)?;
        Ok(Self {
            source: path.to_owned(),
            frames,
            format,
            size,
            cache: Mutex::new(FrameCache {
                frames: VecDeque::new(),
                bytes: 0,
                cap: DEFAULT_CACHE_BYTES,
                tonemap: None,
            }),
            decoded: AtomicU64::new(0),
        })
    }

    /// The same sequence with its linear (OpenEXR) frames shown through `tonemap` (see
    /// [`Sequence::set_tonemap`]).
    #[must_use]
    pub fn with_tonemap(self, tonemap: Option<Tonemap>) -> Self {
        self.set_tonemap(tonemap);
        self
    }

    /// Shows linear (OpenEXR) frames through `tonemap` (exposure and operator) from now on
    /// instead of clamping them; display-referred frames (PNG, JPEG) are unchanged. True when
    /// the sequence holds linear frames and the tonemap changed: frames read earlier look
    /// different now (the cache forgets them).
    pub fn set_tonemap(&self, tonemap: Option<Tonemap>) -> bool {
        let mut cache = self.cache.lock().unwrap_or_else(PoisonError::into_inner);
        if cache.tonemap == tonemap {
            return false;
        }
        cache.tonemap = tonemap;
        cache.forget();
        self.format == ImageFormat::OpenExr
    }

    /// The same sequence keeping at most `bytes` of decoded frames.
    #[must_use]
    pub fn with_cache_bytes(self, bytes: usize) -> Self {
        if let Ok(mut cache) = self.cache.lock() {
            cache.cap = bytes;
            cache.forget();
        }
        self
    }

    /// The folder or pattern the sequence was opened from.
    pub fn source(&self) -> &Path {
        &self.source
    }

    /// Number of frames.
    pub fn len(&self) -> usize {
        self.frames.len()
    }

    /// Whether the sequence has no frames (never true of an opened one).
    pub fn is_empty(&self) -> bool {
        self.frames.is_empty()
    }

    /// Width and height of every frame (the first frame's; others are checked when read).
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The file of frame `index` (0-based), if there is one.
    pub fn path(&self, index: usize) -> Option<&Path> {
        self.frames.get(index).map(|f| f.path.as_path())
    }

    /// The frame files, in playing order.
    pub fn paths(&self) -> impl Iterator<Item = &Path> {
        self.frames.iter().map(|f| f.path.as_path())
    }

    /// The frame number in the file name of frame `index` (0-based), if there is one.
    pub fn number(&self, index: usize) -> Option<u64> {
        self.frames.get(index).map(|f| f.number)
    }

    /// How many frames were decoded so far (cache hits are not decodes).
    pub fn decoded_frames(&self) -> u64 {
        self.decoded.load(Ordering::Relaxed)
    }

    /// Frame `index` (0-based) as sRGB-encoded RGBA8, from the cache or read and decoded.
    pub fn frame(&self, index: usize) -> Result<Arc<RgbaImage>, SequenceError> {
        let file = self.frames.get(index).ok_or(SequenceError::OutOfRange {
            index,
            frames: self.frames.len(),
        })?;
        let lock = || self.cache.lock().unwrap_or_else(PoisonError::into_inner);
        let tonemap = {
            let mut cache = lock();
            if let Some(frame) = cache.get(index) {
                return Ok(frame);
            }
            cache.tonemap
        };
        let frame = Arc::new(self.decode(&file.path, tonemap.as_ref())?);
        self.decoded.fetch_add(1, Ordering::Relaxed);
        let mut cache = lock();
        // (A frame decoded while the tonemap changed is returned but not kept.)
        if cache.tonemap == tonemap {
            cache.insert(index, &frame);
        }
        Ok(frame)
    }

    /// Reads and decodes one frame file, checking its size before decoding.
    fn decode(&self, path: &Path, tonemap: Option<&Tonemap>) -> Result<RgbaImage, SequenceError> {
        let bytes = files::read_bounded(path, files::MAX_IMAGE_FILE_BYTES, FRAME_PURPOSE)?;
        let reader = || ImageReader::with_format(Cursor::new(bytes.as_slice()), self.format);
        let size = reader()
            .into_dimensions()
            .map_err(|e| decode_error(path, e))?;
        if size != self.size {
            return Err(SequenceError::FrameSize {
                path: path.to_owned(),
                size,
                first: self.frames[0].path.clone(),
                first_size: self.size,
            });
        }
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(MAX_FRAME_PIXELS.saturating_mul(16));
        let mut reader = reader();
        reader.limits(limits);
        let image = reader.decode().map_err(|e| decode_error(path, e))?;
        Ok(match tonemap {
            Some(tonemap) => srgb::display_rgba8_mapped(image, |linear| {
                tonemap.apply(glam::Vec3::from(linear)).to_array()
            }),
            None => srgb::display_rgba8(image),
        })
    }
}

/// Checks that two sequences scored against each other have the same frame count and size;
/// the error names both and what differs.
pub fn check_same_shape(reference: &Sequence, test: &Sequence) -> Result<(), SequenceError> {
    let describe = |s: &Sequence| {
        format!(
            "{} has {} frames of {}x{}",
            s.source().display(),
            s.len(),
            s.size.0,
            s.size.1
        )
    };
    let what = if reference.len() != test.len() {
        "frame counts"
    } else if reference.size != test.size {
        "frame sizes"
    } else {
        return Ok(());
    };
    Err(SequenceError::Mismatch(format!(
        "the sequences' {what} differ: {} but {}",
        describe(reference),
        describe(test)
    )))
}

/// Whether `path` names a sequence rather than one image: a folder, or a path that is not a
/// file and has wildcards in its file name.
pub fn is_sequence_path(path: &Path) -> bool {
    path.is_dir() || (!path.exists() && path.file_name().is_some_and(has_wildcards))
}

fn has_wildcards(text: &std::ffi::OsStr) -> bool {
    text.to_string_lossy().contains(['*', '?', '['])
}

fn decode_error(path: &Path, error: impl std::fmt::Display) -> SequenceError {
    SequenceError::Decode {
        path: path.to_owned(),
        reason: error.to_string(),
    }
}

fn check_pixels(path: &Path, size: (u32, u32)) -> Result<(), SequenceError> {
    if u64::from(size.0) * u64::from(size.1) > MAX_FRAME_PIXELS {
        return Err(SequenceError::TooLarge {
            path: path.to_owned(),
            size,
            limit: MAX_FRAME_PIXELS,
        });
    }
    Ok(())
}

/// The numbered frame files of a folder or a glob, unsorted; every file named alike.
fn list_frames(path: &Path) -> Result<Vec<FrameFile>, SequenceError> {
    let (folder, pattern) = if path.is_dir() {
        (path, None)
    } else {
        let name = path.file_name().unwrap_or_default();
        let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
        let folder = parent.unwrap_or(Path::new("."));
        let pattern_error = |reason: String| SequenceError::Pattern {
            pattern: path.display().to_string(),
            reason,
        };
        if has_wildcards(folder.as_os_str()) {
            return Err(pattern_error(
                "wildcards may only be in the file name (frames/taa_*.png)".into(),
            ));
        }
        let pattern = glob::Pattern::new(&name.to_string_lossy())
            .map_err(|e| pattern_error(e.to_string()))?;
        (folder, Some(pattern))
    };
    let list_error = |source| SequenceError::List {
        path: folder.to_owned(),
        source,
    };
    let mut frames = Vec::new();
    let mut naming: Option<(String, String, PathBuf)> = None;
    for (count, entry) in std::fs::read_dir(folder).map_err(list_error)?.enumerate() {
        if count >= MAX_LISTING_ENTRIES {
            return Err(too_many(folder, MAX_LISTING_ENTRIES, "directory entries"));
        }
        let entry = entry.map_err(list_error)?;
        let file_path = entry.path();
        let name = entry.file_name().to_string_lossy().into_owned();
        let wanted = match &pattern {
            Some(pattern) => pattern.matches(&name),
            None => !name.starts_with('.') && frame_format(&file_path).is_some(),
        };
        if !wanted || !file_path.is_file() {
            continue;
        }
        if frame_format(&file_path).is_none() {
            return Err(SequenceError::Format { path: file_path });
        }
        let parsed = FrameName::parse(&name).ok_or_else(|| SequenceError::Unnumbered {
            path: file_path.clone(),
        })?;
        match &naming {
            Some((prefix, suffix, first))
                if *prefix != parsed.prefix || *suffix != parsed.suffix =>
            {
                return Err(SequenceError::Naming {
                    first: first.clone(),
                    second: file_path,
                });
            }
            Some(_) => {}
            None => naming = Some((parsed.prefix, parsed.suffix, file_path.clone())),
        }
        if frames.len() >= MAX_FRAMES {
            return Err(too_many(path, MAX_FRAMES, "frames"));
        }
        frames.push(FrameFile {
            path: file_path,
            number: parsed.number,
        });
    }
    Ok(frames)
}

fn too_many(path: &Path, limit: usize, what: &'static str) -> SequenceError {
    SequenceError::TooMany {
        path: path.to_owned(),
        limit,
        what,
    }
}

/// Checks sorted frames for duplicate and missing numbers.
fn check_numbering(frames: &[FrameFile]) -> Result<(), SequenceError> {
    for pair in frames.windows(2) {
        let (a, b) = (&pair[0], &pair[1]);
        if a.number == b.number {
            return Err(SequenceError::Duplicate {
                number: a.number,
                first: a.path.clone(),
                second: b.path.clone(),
            });
        }
        if b.number > a.number + 1 {
            return Err(SequenceError::Missing {
                first_missing: a.number + 1,
                last_missing: b.number - 1,
                before: a.path.clone(),
                after: b.path.clone(),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cache_evicts_the_least_recently_used_frame_and_keeps_one_copy() {
        let frame = || Arc::new(RgbaImage::new(4, 4));
        let mut cache = FrameCache {
            frames: VecDeque::new(),
            bytes: 0,
            cap: 2 * 64,
            tonemap: None,
        };
        cache.insert(0, &frame());
        cache.insert(1, &frame());
        cache.insert(1, &frame());
        assert_eq!(cache.bytes, 128);
        // Reading frame 0 makes frame 1 the least recently used: frame 2 evicts it.
        assert!(cache.get(0).is_some());
        cache.insert(2, &frame());
        assert!(cache.get(1).is_none());
        assert!(cache.get(0).is_some() && cache.get(2).is_some());
        assert_eq!(cache.bytes, 128);
        // A frame larger than the cap is not kept.
        cache.insert(3, &Arc::new(RgbaImage::new(8, 8)));
        assert!(cache.get(3).is_none());
    }

    #[test]
    fn frame_numbers_are_the_last_run_of_digits() {
        let name = FrameName::parse("shot2_0017.EXR").expect("numbered");
        assert_eq!(
            (name.prefix.as_str(), name.suffix.as_str(), name.number),
            ("shot2_", ".exr", 17)
        );
        let name = FrameName::parse("f9b.png").expect("numbered");
        assert_eq!((name.prefix.as_str(), name.suffix.as_str()), ("f", "b.png"));
        assert!(FrameName::parse("thumbnail.png").is_none());
        assert!(FrameName::parse("f123456789012345678901234.png").is_none());
    }
}
