//! Image sequences as panes: File > Open sequences (or folders dropped on the window) opens up
//! to five sequences of one frame size ([`crate::sequence::Sequence`]: a folder or a glob of
//! numbered PNG, JPEG or OpenEXR frames), one of them the reference, and plays them in
//! lockstep as a recorded clip plays. With five, the four others are the panes and the
//! reference is shown as a technique view's reference is (`image_set.rs`); it is read, played
//! and measured against like the rest.
//!
//! **Why it is an image set.** A sequence set is shown exactly as an open image set is: the
//! frames of the playhead are the set's images, so the panes, layouts, magnifier, wipe and
//! flip, heatmaps, quality figures and labels work on them unchanged, and the image set's
//! reference choice and swap apply as they are. This module owns only what is particular to
//! sequences, and the image set (`image_set.rs`) holds a [`SequenceSet`] beside its images:
//! each time a new frame is read, the set's images are replaced and stamped with a new view,
//! so the figures of the previous frame go stale and the quality worker measures the new one,
//! as it does when another reference is chosen. The transport is the clip's: a
//! [`ClipPlayer`] (play, pause, steps, scrubbing, rate, ping-pong) driven by the clip bar's
//! controls, rather than a second player.
//!
//! **Streaming.** Nothing is decoded up front: opening reads each sequence's listing and first
//! frame (`Sequence::open`, then frame 0 to show). A frame reader ([`Worker`], one thread)
//! reads the frames of the playhead (`Sequence::frame`, from the sequence's cache or read and
//! decoded), uploads them to eframe's device and hands them back; then, while no other frame
//! is asked for, it reads the next frames into the cache, so playback rarely waits for a
//! decode. Each sequence keeps at most [`CACHE_FRAMES`] decoded frames, so the memory held is
//! about `(CACHE_FRAMES + 2) x frame bytes` per sequence (the cache, the shown frame's pixels
//! and its texture) whatever the length: figures in `docs/sequences.md`.
//!
//! **Lockstep.** All panes change together: a frame is shown once every sequence's frame of
//! that instant has been read, and the player advances only once the frame it asked for is
//! on screen, so when reading is slower than the playback rate every frame is still shown,
//! more slowly (the clip bar says at which rate), as a clip plays on a slow window.
//!
//! **Temporal figures.** The reader measures the frames it reads in a row (consecutive instants
//! of every sequence, the same reference) with the clip's [`ClipMetrics`]: temporal
//! instability and ghosting of every pane against the reference over the run so far, handed
//! back with the frames ([`PlayedRun`]). It costs one luma plane per pane and frame on the
//! reader's thread; a jump, a wrap, another offset or reference starts a new run.
//!
//! **Offsets.** Sequence `k` with offset `o_k` shows its frame `t + o_k` at instant `t`, so
//! captures that start on different frames line up; the set plays `min_k(len_k - o_k)`
//! instants. A frame that cannot be read (another size, a corrupt file) stops playback with a
//! notice naming the file, and the frames shown stay.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use super::blit::Uploader;
use super::engine::ClipPlayer;
use super::render_thread::RenderedImage;
use super::worker::{Reporter, Worker};
use crate::metrics::stability::{ClipMetrics, TemporalScores};
use crate::scene::renderer::Tonemap;
use crate::sequence::Sequence;

/// Decoded frames each sequence of the viewer keeps (the shown one and the ones read ahead).
pub const CACHE_FRAMES: usize = 3;

/// Frames read ahead of the playhead while the reader is otherwise idle.
const READ_AHEAD: usize = CACHE_FRAMES - 1;

/// Playback rates from which the UI repaints continuously (below, once per frame): the
/// clip's rule.
const REPAINT_EVERY_FRAME_FPS: f64 = 30.0;

/// The frames of one instant to read, the frames to read ahead after them, and the pane of
/// the reference (the temporal figures are measured against it).
struct FrameJob {
    /// The arrangement it was asked for (see [`SequenceSet::arrangement`]).
    arrangement: u64,
    instant: usize,
    frames: Vec<(Arc<Sequence>, usize)>,
    ahead: Vec<(Arc<Sequence>, usize)>,
    reference: usize,
}

/// The frames of an instant on eframe's device with the temporal figures of the run they
/// end, or why one could not be read.
type FrameAnswer = (u64, usize, Result<(Vec<RenderedImage>, PlayedRun), String>);

/// The temporal figures of the frames played in a row: every pane but the reference's, in
/// pane order, over `frames` consecutive instants.
#[derive(Clone, Debug)]
pub struct PlayedRun {
    /// Instants in the run (the figures need at least two).
    pub frames: usize,
    /// The reference's pane.
    pub reference: usize,
    /// Per pane but the reference's, in order.
    pub scores: Vec<TemporalScores>,
}

/// The figures of the run of consecutive instants the reader has read: what identifies the
/// run (its last instant, the frames it read, the reference) and the clip figures so far.
#[derive(Default)]
struct RunMetrics {
    last: Option<(usize, Vec<usize>, usize)>,
    frames: usize,
    metrics: ClipMetrics,
}

impl RunMetrics {
    /// Adds the frames of `job` (their pixels `images`): to the run when they follow its last
    /// instant in every sequence, else as the first of a new run.
    fn push(&mut self, job: &FrameJob, images: &[RenderedImage]) -> Result<PlayedRun, String> {
        let indices: Vec<usize> = job.frames.iter().map(|(_, index)| *index).collect();
        let follows = self
            .last
            .as_ref()
            .is_some_and(|(last, previous, reference)| {
                *reference == job.reference
                    && job.instant == last + 1
                    && previous.iter().zip(&indices).all(|(p, i)| p + 1 == *i)
            });
        if !follows {
            self.metrics = ClipMetrics::new(images.len().saturating_sub(1));
            self.frames = 0;
        }
        let reference = images
            .get(job.reference)
            .ok_or("the reference has no frame")?;
        let others: Vec<&image::RgbaImage> = images
            .iter()
            .enumerate()
            .filter(|(pane, _)| *pane != job.reference)
            .map(|(_, image)| &image.pixels)
            .collect();
        self.metrics
            .push(&reference.pixels, &others)
            .map_err(|e| e.to_string())?;
        self.frames += 1;
        self.last = Some((job.instant, indices, job.reference));
        Ok(PlayedRun {
            frames: self.frames,
            reference: job.reference,
            scores: self.metrics.scores(),
        })
    }
}

/// What the frame reader produced since the last poll.
pub enum FrameNews {
    /// The frames of an instant, one per sequence in pane order.
    Frames(Vec<RenderedImage>),
    /// A frame could not be read: playback stopped.
    Failed(String),
}

/// Opens the sequences at `paths` and checks that they can play together: at least one, all
/// of one frame size (the error names the sequence that differs). Each keeps at most
/// [`CACHE_FRAMES`] decoded frames.
pub fn open_all(paths: &[PathBuf]) -> Result<Vec<Arc<Sequence>>, String> {
    let mut sequences = Vec::with_capacity(paths.len());
    for path in paths {
        let sequence = Sequence::open(path).map_err(|e| e.to_string())?;
        let (w, h) = sequence.size();
        let frame_bytes = w as usize * h as usize * 4;
        sequences.push(Arc::new(
            sequence.with_cache_bytes(CACHE_FRAMES * frame_bytes),
        ));
    }
    let Some(first) = sequences.first() else {
        return Err("no sequences were given".to_owned());
    };
    if let Some(other) = sequences.iter().find(|s| s.size() != first.size()) {
        let (w, h) = other.size();
        let (fw, fh) = first.size();
        return Err(format!(
            "the sequences differ in size: {} has frames of {w}x{h} but {} has {fw}x{fh}; open sequences of one size",
            other.source().display(),
            first.source().display()
        ));
    }
    Ok(sequences)
}

/// Reads the frames of `frames` and uploads them, in order.
fn read_frames(
    frames: &[(Arc<Sequence>, usize)],
    uploader: &Uploader,
) -> Result<Vec<RenderedImage>, String> {
    let images = frames
        .iter()
        .map(|(sequence, index)| {
            let pixels = sequence.frame(*index).map_err(|e| e.to_string())?;
            let pixels = image::RgbaImage::clone(&pixels);
            let texture = uploader.upload(&pixels);
            Ok(RenderedImage { pixels, texture })
        })
        .collect();
    uploader.flush();
    images
}

/// The first frames of `sequences` (frame 0 of each), read on the calling thread.
pub fn first_frames(
    sequences: &[Arc<Sequence>],
    uploader: &Uploader,
) -> Result<Vec<RenderedImage>, String> {
    let frames: Vec<_> = sequences.iter().map(|s| (Arc::clone(s), 0)).collect();
    read_frames(&frames, uploader)
}

/// The open sequences, their offsets, the player and the frame reader (see the module docs).
pub struct SequenceSet {
    sequences: Vec<Arc<Sequence>>,
    offsets: Vec<usize>,
    /// Playback, as a clip's.
    pub player: ClipPlayer,
    /// The instant shown (`None` when the frames shown are no longer those of the offsets).
    shown: Option<usize>,
    /// Counts changes of which frames the panes show at an instant (offsets, order): an
    /// answer read for an earlier arrangement is dropped.
    arrangement: u64,
    /// The instant being read.
    asked: Option<usize>,
    /// The temporal figures of the frames played in a row up to the one shown.
    played: Option<PlayedRun>,
    reader: Worker<FrameJob, FrameAnswer>,
}

impl SequenceSet {
    /// The set of `sequences` showing their first frames, with a frame reader thread that
    /// uploads with `uploader` and wakes `ctx`.
    pub fn new(
        sequences: Vec<Arc<Sequence>>,
        uploader: Uploader,
        ctx: &egui::Context,
    ) -> std::io::Result<Self> {
        let mut run = RunMetrics::default();
        let reader = Worker::spawn(
            "aa-lab sequence reader",
            ctx,
            move |job: FrameJob, reporter: &Reporter<FrameAnswer>| {
                let read = read_frames(&job.frames, &uploader).and_then(|images| {
                    let played = run.push(&job, &images)?;
                    Ok((images, played))
                });
                if read.is_err() {
                    run = RunMetrics::default();
                }
                reporter.send((job.arrangement, job.instant, read));
                for (sequence, index) in job.ahead {
                    // Into the cache; an error shows when the frame is asked for.
                    let _ = sequence.frame(index);
                }
            },
        )?;
        let offsets = vec![0; sequences.len()];
        let mut player = ClipPlayer::default();
        player.playing = false;
        Ok(Self {
            sequences,
            offsets,
            player,
            shown: Some(0),
            arrangement: 0,
            asked: None,
            played: None,
            reader,
        })
    }

    /// The sequences, in pane order.
    pub fn sequences(&self) -> &[Arc<Sequence>] {
        &self.sequences
    }

    /// The frame offset of sequence `index`.
    pub fn offset(&self, index: usize) -> usize {
        self.offsets.get(index).copied().unwrap_or(0)
    }

    /// The largest offset sequence `index` may have (its last frame).
    pub fn max_offset(&self, index: usize) -> usize {
        self.sequences
            .get(index)
            .map_or(0, |s| s.len().saturating_sub(1))
    }

    /// Shows sequence `index` from its frame `offset` on (clamped to its frames); the frames
    /// are read again.
    pub fn set_offset(&mut self, index: usize, offset: usize) {
        let offset = offset.min(self.max_offset(index));
        if let Some(slot) = self.offsets.get_mut(index)
            && *slot != offset
        {
            *slot = offset;
            self.rearranged();
        }
    }

    /// Swaps sequences `a` and `b` (with their offsets), as the image set swaps their
    /// images.
    pub fn swap(&mut self, a: usize, b: usize) {
        if a != b && a.max(b) < self.sequences.len() {
            self.sequences.swap(a, b);
            self.offsets.swap(a, b);
            self.rearranged();
        }
    }

    /// Shows the sequences' linear (OpenEXR) frames through `tonemap` (clamped without one);
    /// what is shown is read again when that changes how it looks.
    pub fn set_tonemap(&mut self, tonemap: Option<Tonemap>) {
        let mut changed = false;
        for sequence in &self.sequences {
            changed |= sequence.set_tonemap(tonemap);
        }
        if changed {
            self.rearranged();
        }
    }

    /// The panes show other frames at an instant: what is shown is read again, what is being
    /// read is dropped when it comes.
    fn rearranged(&mut self) {
        self.shown = None;
        self.arrangement += 1;
    }

    /// Instants the set plays: the frames every sequence has after its offset.
    pub fn len(&self) -> usize {
        self.sequences
            .iter()
            .zip(&self.offsets)
            .map(|(s, o)| s.len().saturating_sub(*o))
            .min()
            .unwrap_or(0)
    }

    /// Whether there is nothing to play (never true of an opened set).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The instant on screen (`None` while the frames of new offsets are being read).
    pub fn shown(&self) -> Option<usize> {
        self.shown
    }

    /// The frame number (from its file name) each sequence shows, in pane order.
    pub fn shown_numbers(&self) -> Vec<Option<u64>> {
        let instant = self.shown.unwrap_or_else(|| self.player.frame(self.len()));
        self.sequences
            .iter()
            .zip(&self.offsets)
            .map(|(s, o)| s.number(instant + o))
            .collect()
    }

    /// The frame file each sequence shows, in pane order.
    pub fn shown_path(&self, index: usize) -> Option<&Path> {
        let instant = self.shown?;
        self.sequences
            .get(index)?
            .path(instant + self.offset(index))
    }

    /// The temporal figures of the consecutive frames read up to the one shown (reset by a
    /// jump, a wrap, another offset or reference).
    pub fn played(&self) -> Option<&PlayedRun> {
        self.played.as_ref()
    }

    /// Whether it plays.
    pub fn playing(&self) -> bool {
        self.player.playing && self.len() > 1
    }

    /// The frames of the `count` instants after `instant`, one per sequence each.
    fn frames_after(&self, instant: usize, count: usize) -> Vec<(Arc<Sequence>, usize)> {
        let len = self.len();
        (1..=count)
            .filter(|step| *step < len)
            .flat_map(|step| {
                let at = (instant + step) % len;
                self.sequences
                    .iter()
                    .zip(&self.offsets)
                    .map(move |(s, o)| (Arc::clone(s), at + o))
            })
            .collect()
    }

    /// Takes what the reader finished, advances the player once the frame it asked for is on
    /// screen, asks for the next frame when the player moved on, and schedules the next UI
    /// frame while it plays.
    /// `reference` is the reference's pane.
    pub fn tick(&mut self, ctx: &egui::Context, reference: usize) -> Option<FrameNews> {
        let mut news = None;
        for (arrangement, instant, answer) in self.reader.poll() {
            self.asked = None;
            if arrangement != self.arrangement {
                continue;
            }
            news = Some(match answer {
                Ok((images, played)) => {
                    self.shown = Some(instant);
                    self.played = Some(played);
                    FrameNews::Frames(images)
                }
                Err(err) => {
                    self.played = None;
                    self.player.playing = false;
                    // Stay on the frame shown rather than ask for the bad one again.
                    self.player.seek(self.shown.unwrap_or(instant));
                    self.shown = Some(self.player.frame(self.len()));
                    FrameNews::Failed(err)
                }
            });
        }
        let len = self.len();
        if self.shown == Some(self.player.frame(len)) {
            self.player.tick(Instant::now(), len);
        }
        let wanted = self.player.frame(len);
        if self.shown != Some(wanted) {
            if self.asked.is_some() || self.reader.busy() {
                return news;
            }
            let here = self
                .sequences
                .iter()
                .zip(&self.offsets)
                .map(|(s, o)| (Arc::clone(s), wanted + o))
                .collect();
            let job = FrameJob {
                arrangement: self.arrangement,
                instant: wanted,
                frames: here,
                reference,
                ahead: self.frames_after(wanted, READ_AHEAD),
            };
            if self.reader.submit(job) {
                self.asked = Some(wanted);
            }
        } else if self.playing() {
            if self.player.rate.fps() >= REPAINT_EVERY_FRAME_FPS {
                super::repaint::request_one_frame(ctx);
            } else {
                let due = std::time::Duration::from_secs_f64(self.player.until_next_frame());
                ctx.request_repaint_after(due);
            }
        }
        news
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write_frames(dir: &Path, name: &str, size: (u32, u32), frames: u32) -> PathBuf {
        let folder = dir.join(name);
        std::fs::create_dir_all(&folder).unwrap();
        for index in 0..frames {
            image::RgbaImage::from_pixel(size.0, size.1, image::Rgba([index as u8, 0, 0, 255]))
                .save(folder.join(format!("f{index:03}.png")))
                .unwrap();
        }
        folder
    }

    #[test]
    fn sequences_of_one_size_open_with_a_small_cache_and_others_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let a = write_frames(dir.path(), "a", (8, 6), 5);
        let b = write_frames(dir.path(), "b", (8, 6), 3);
        let opened = open_all(&[a.clone(), b]).unwrap();
        assert_eq!(opened.len(), 2);
        assert_eq!(opened[0].len(), 5);
        // The cache keeps CACHE_FRAMES frames: reading them all decodes each once, and the
        // oldest is decoded again after one more.
        for index in 0..=CACHE_FRAMES {
            opened[0].frame(index).unwrap();
        }
        opened[0].frame(1).unwrap();
        assert_eq!(opened[0].decoded_frames(), CACHE_FRAMES as u64 + 1);
        opened[0].frame(0).unwrap();
        assert_eq!(opened[0].decoded_frames(), CACHE_FRAMES as u64 + 2);

        let other = write_frames(dir.path(), "other", (8, 5), 5);
        let err = open_all(&[a, other]).err().unwrap();
        assert!(
            err.contains("other has frames of 8x5") && err.contains("a has 8x6"),
            "{err}"
        );
        assert!(open_all(&[]).is_err());
        let empty = dir.path().join("empty");
        std::fs::create_dir_all(&empty).unwrap();
        assert!(
            open_all(&[empty])
                .err()
                .unwrap()
                .contains("holds no frames")
        );
    }
}
