//! `aa-lab clip`'s captured panes: image sequences ([`crate::sequence`]) shown beside (or
//! instead of) rendered techniques, `--sequence LABEL=PATH` each, and `--reference-sequence
//! PATH`, the captured ground truth every pane is then scored against instead of the
//! 64-sample render.
//!
//! `--offset LABEL=N` starts sequence `LABEL` at its `N`th frame (0-based position, not the
//! number in the file name; `reference` names the reference sequence), so captures that start
//! on different frames line up: clip frame `t` shows frame `N + t` of each. The clip is as long
//! as the shortest sequence after its offset (a warning says so when another has frames left
//! over), and `--frames` may not ask for more. Every pane must have the clip's size; a
//! sequence of another size is an error naming it and both sizes.
//!
//! Frames are read when the clip reaches them, through each sequence's own cache of
//! [`CACHE_FRAMES`] frames, so a long capture is never held whole; the record
//! ([`SequenceRecord`]) states each sequence's folder or pattern, offset and the frame numbers
//! and files the clip used, which with the rest of the record reproduce the clip.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};

use crate::files::Overwrite;
use crate::scene::renderer::Tonemap;
use crate::sequence::Sequence;

/// The name `--offset` gives the reference sequence, and its folder in `--frames-dir`.
pub const REFERENCE_LABEL: &str = "reference";

/// Decoded frames each sequence keeps while the clip plays: the frame being scored and the
/// one before it.
const CACHE_FRAMES: usize = 2;

/// Frames of a clip without sequences and without `--frames`.
pub const DEFAULT_CLIP_FRAMES: u32 = 24;

/// One captured pane: its label, its frames and the first of them the clip shows.
pub struct CapturedPane {
    /// The pane's label (`reference` for the reference sequence).
    pub label: String,
    sequence: Sequence,
    offset: usize,
}

/// What the record says of a captured pane.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SequenceRecord {
    /// The pane's label.
    pub label: String,
    /// The folder or glob the frames were read from.
    pub path: PathBuf,
    /// Frames of the sequence skipped before the clip's first (`--offset`).
    pub offset: usize,
    /// Frames the sequence has.
    pub sequence_frames: usize,
    /// The frame numbers (from the file names) of the clip's first and last frames.
    pub first_number: Option<u64>,
    /// See `first_number`.
    pub last_number: Option<u64>,
    /// The files of the clip's first and last frames.
    pub first_file: Option<PathBuf>,
    /// See `first_file`.
    pub last_file: Option<PathBuf>,
}

impl CapturedPane {
    /// Width and height of every frame.
    pub fn size(&self) -> (u32, u32) {
        self.sequence.size()
    }

    /// Frames left from the offset on.
    fn available(&self) -> usize {
        self.sequence.len().saturating_sub(self.offset)
    }

    /// Clip frame `index` of this pane.
    pub fn frame(&self, index: usize) -> anyhow::Result<image::RgbaImage> {
        let frame = self.sequence.frame(self.offset + index)?;
        Ok(frame.as_ref().clone())
    }

    /// The record of this pane in a clip of `frames` frames.
    pub fn record(&self, frames: usize) -> SequenceRecord {
        let last = (self.offset + frames).saturating_sub(1);
        SequenceRecord {
            label: self.label.clone(),
            path: self.sequence.source().to_owned(),
            offset: self.offset,
            sequence_frames: self.sequence.len(),
            first_number: self.sequence.number(self.offset),
            last_number: self.sequence.number(last),
            first_file: self.sequence.path(self.offset).map(Path::to_owned),
            last_file: self.sequence.path(last).map(Path::to_owned),
        }
    }

    fn describe(&self) -> String {
        format!(
            "{} ({}, {} frames from offset {})",
            self.label,
            self.sequence.source().display(),
            self.available(),
            self.offset
        )
    }
}

/// Every captured pane of a clip.
#[derive(Default)]
pub struct ClipSequences {
    /// `--sequence` panes, in the order given.
    pub panes: Vec<CapturedPane>,
    /// `--reference-sequence`.
    pub reference: Option<CapturedPane>,
}

/// Splits `LABEL=VALUE` of `flag`.
fn split_label<'a>(flag: &str, text: &'a str) -> anyhow::Result<(&'a str, &'a str)> {
    match text.split_once('=') {
        Some((label, value)) if !label.trim().is_empty() && !value.is_empty() => {
            Ok((label.trim(), value))
        }
        _ => bail!("{flag} {text}: expected LABEL=VALUE, e.g. {flag} engine-taa=captures/taa/"),
    }
}

/// Opens one sequence with the clip's cache, by its absolute path (the record then
/// reproduces from any folder), its OpenEXR frames shown through `tonemap`.
fn open(label: &str, path: &Path, tonemap: Option<Tonemap>) -> anyhow::Result<CapturedPane> {
    let path = std::path::absolute(path).unwrap_or_else(|_| path.to_owned());
    let sequence = Sequence::open(&path)
        .with_context(|| format!("cannot open the sequence {label}"))?
        .with_tonemap(tonemap);
    let (width, height) = sequence.size();
    let frame_bytes = width as usize * height as usize * 4;
    Ok(CapturedPane {
        label: label.to_owned(),
        sequence: sequence.with_cache_bytes(CACHE_FRAMES * frame_bytes),
        offset: 0,
    })
}

impl ClipSequences {
    /// Opens `--sequence` (`LABEL=PATH` each), `--reference-sequence` and applies `--offset`
    /// (`LABEL=N` each): labels must be unique and not `reference`, and every offset must name
    /// a sequence and leave it a frame. OpenEXR frames are shown through `tonemap` (clamped
    /// without one).
    pub fn open(
        sequences: &[String],
        reference: Option<&Path>,
        offsets: &[String],
        tonemap: Option<Tonemap>,
    ) -> anyhow::Result<Self> {
        let mut panes: Vec<CapturedPane> = Vec::new();
        for text in sequences {
            let (label, path) = split_label("--sequence", text)?;
            if label.eq_ignore_ascii_case(REFERENCE_LABEL) {
                bail!(
                    "--sequence {text}: `{REFERENCE_LABEL}` names the reference; give the reference with --reference-sequence PATH"
                );
            }
            if panes.iter().any(|p| p.label == label) {
                bail!("--sequence {text}: two sequences are labelled {label}");
            }
            panes.push(open(label, Path::new(path), tonemap)?);
        }
        let mut clip = Self {
            panes,
            reference: reference
                .map(|path| open(REFERENCE_LABEL, path, tonemap))
                .transpose()?,
        };
        for text in offsets {
            let (label, value) = split_label("--offset", text)?;
            let offset: usize = value
                .parse()
                .with_context(|| format!("--offset {text}: {value} is not a frame count"))?;
            let pane = clip
                .all_mut()
                .find(|p| p.label == label)
                .with_context(|| {
                    format!(
                        "--offset {text}: no sequence is labelled {label} (--sequence LABEL=PATH, or `{REFERENCE_LABEL}` for --reference-sequence)"
                    )
                })?;
            if offset >= pane.sequence.len() {
                bail!(
                    "--offset {text}: {} has only {} frames",
                    pane.sequence.source().display(),
                    pane.sequence.len()
                );
            }
            pane.offset = offset;
        }
        Ok(clip)
    }

    /// Whether the clip has no captured pane.
    pub fn is_empty(&self) -> bool {
        self.panes.is_empty() && self.reference.is_none()
    }

    /// Every captured pane, the reference's last.
    pub fn all(&self) -> impl Iterator<Item = &CapturedPane> {
        self.panes.iter().chain(&self.reference)
    }

    fn all_mut(&mut self) -> impl Iterator<Item = &mut CapturedPane> {
        self.panes.iter_mut().chain(&mut self.reference)
    }

    /// Checks that every sequence has the clip's `size`, which `what` describes.
    pub fn check_size(&self, size: (u32, u32), what: &str) -> anyhow::Result<()> {
        for pane in self.all() {
            let (width, height) = pane.sequence.size();
            if (width, height) != size {
                bail!(
                    "the sequence {} ({}) is {width}x{height} but {what} is {}x{}: every pane of a clip has the same size",
                    pane.label,
                    pane.sequence.source().display(),
                    size.0,
                    size.1
                );
            }
        }
        Ok(())
    }

    /// The clip's frame count: `requested` (`--frames`) or, without it, the shortest
    /// sequence's frames after its offset (at most `max`; 24 without
    /// sequences). More than the shortest sequence has is an error; a sequence with frames
    /// left over gets a warning.
    pub fn clip_frames(&self, requested: Option<u32>, max: u32) -> anyhow::Result<u32> {
        let Some(shortest) = self.all().min_by_key(|p| p.available()) else {
            return Ok(requested.unwrap_or(DEFAULT_CLIP_FRAMES));
        };
        let available = u32::try_from(shortest.available()).unwrap_or(u32::MAX);
        let frames = match requested {
            Some(frames) if frames > available => bail!(
                "--frames {frames}: the clip plays every sequence in lockstep and the shortest, {}, has only {available}",
                shortest.describe()
            ),
            Some(frames) => frames,
            None => available.min(max),
        };
        let longer: Vec<String> = self
            .all()
            .filter(|p| p.available() > frames as usize)
            .map(CapturedPane::describe)
            .collect();
        if !longer.is_empty() {
            let why = match requested {
                Some(_) => "--frames".to_owned(),
                None if frames < available => format!("a clip has at most {max}"),
                None => format!("the shortest sequence is {}", shortest.describe()),
            };
            eprintln!(
                "warning: the clip has {frames} frames ({why}); the later frames of {} are left out",
                longer.join(", ")
            );
        }
        Ok(frames)
    }

    /// Every frame file: inputs a clip never writes over.
    pub fn protect(&self, policy: Overwrite) -> Overwrite {
        self.all()
            .flat_map(|p| p.sequence.paths())
            .fold(policy, Overwrite::with_input)
    }

    /// Clip frame `index` of every `--sequence` pane, in order.
    pub fn frames(&self, index: usize) -> anyhow::Result<Vec<image::RgbaImage>> {
        self.panes.iter().map(|p| p.frame(index)).collect()
    }
}
