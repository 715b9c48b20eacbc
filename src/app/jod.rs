//! ColorVideoVDP in the viewer ([`crate::metrics::jod`]): every technique of the recorded clip,
//! or every sequence of an open sequence set, scored against the reference in JOD, as watched at
//! the playback rate on the display of the settings (a standard display model, its pixels per
//! degree replaced when a viewing distance is set), and when asked the per-pixel distortion map
//! of each (the magnifier's "JOD distortion" heatmap, `difference.rs`).
//!
//! One worker thread ([`Worker`]) scores one job at a time, keeping the scorer of the last
//! display (a technique takes seconds, and its memory is reused), and reports each figure as it
//! comes, so the metrics panel shows them with progress. A job stops between techniques and
//! between the frames it reads when the user cancels it, when what is shown changes, or when
//! the viewer closes.
//! - A recorded clip is scored once it is complete and has the reference: its frames are the
//!   clip's own (shared, not copied).
//! - Sequences are scored when asked (the metrics panel's button, or choosing the distortion
//!   heatmap): the worker reads their frames itself, every instant the set plays (through each
//!   sequence's small cache), so the UI thread never waits for a decode; the reference's frames
//!   are read once for all sequences. Sets whose scoring would hold more than
//!   [`jod::MAX_SCORED_BYTES`] are refused, with the reason as each sequence's figure.
//! - The distortion map costs one more plane per frame while scoring, so it is computed only
//!   while that heatmap is chosen: choosing it scores again with the map, and figures with the
//!   map serve a later request without it.
//!
//! A new clip, other sequences, offsets or reference, another display or rate start again. The
//! figures and maps are published to the context ([`JodMaps`]) for the magnifier and the blind
//! comparison, which never see this feature.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::context::{Context, JodMaps, Level};
use super::difference::DiffMetric;
use super::engine::PlayRate;
use super::image_set::IMAGE_IDS;
use super::worker::{Reporter, Worker};
use crate::metrics::Plane;
use crate::metrics::jod::{self, JodDisplay, JodScorer};
use crate::sequence::Sequence;

/// What is scored.
#[derive(Clone, Debug, PartialEq)]
enum Subject {
    /// The recorded clip, by when its recording started.
    Clip(Instant),
    /// The open sequences: their sources in pane order, their offsets, the reference's pane
    /// and the instants the set plays.
    Sequences {
        sources: Vec<PathBuf>,
        offsets: Vec<usize>,
        reference: usize,
        instants: usize,
    },
}

/// What figures describe: the subject, the display, the frame rate, and whether they come
/// with the distortion maps.
#[derive(Clone, Debug, PartialEq)]
struct Key {
    subject: Subject,
    display: JodDisplay,
    fps: u32,
    mapped: bool,
}

impl Key {
    /// Whether figures of this key answer a request for `wanted` (maps serve a request
    /// without them).
    fn covers(&self, wanted: &Key) -> bool {
        self.subject == wanted.subject
            && self.display == wanted.display
            && self.fps == wanted.fps
            && (self.mapped || !wanted.mapped)
    }
}

/// A pane's JOD, or why it has none.
pub type Figure = Result<f64, String>;

/// What a pane's figure said when its job was cancelled before it.
const CANCELLED: &str = "cancelled";

/// Where a job's frames come from.
enum Frames {
    /// Already in memory (a recorded clip's frames, shared).
    Shared(Vec<Arc<image::RgbaImage>>),
    /// Read on the worker: `count` frames of `sequence` from frame `first` on.
    Sequence {
        sequence: Arc<Sequence>,
        first: usize,
        count: usize,
    },
}

impl Frames {
    /// The frames, read when they are a sequence's; `None` when `cancel` was set meanwhile.
    fn load(&self, cancel: &AtomicBool) -> Option<Result<Vec<Arc<image::RgbaImage>>, String>> {
        let (sequence, first, count) = match self {
            Frames::Shared(frames) => return Some(Ok(frames.clone())),
            Frames::Sequence {
                sequence,
                first,
                count,
            } => (sequence, *first, *count),
        };
        let mut frames = Vec::with_capacity(count);
        for index in first..first + count {
            if cancel.load(Ordering::Relaxed) {
                return None;
            }
            match sequence.frame(index) {
                Ok(frame) => frames.push(frame),
                Err(err) => return Some(Err(err.to_string())),
            }
        }
        Some(Ok(frames))
    }
}

/// Panes to score (by slot) and the reference.
struct Job {
    key: Key,
    tests: Vec<(usize, Frames)>,
    reference: Frames,
    /// Set when the job is moot (checked between techniques and frames read).
    cancel: Arc<AtomicBool>,
}

/// One pane's figure, and its map when the job asked for maps.
struct Scored {
    key: Key,
    slot: usize,
    figure: Figure,
    map: Option<Arc<Plane>>,
}

/// Scores jobs one after the other on the worker's thread, keeping the scorer of the last
/// display and map choice.
fn score(scorer: &mut Option<JodScorer>, job: Job, reporter: &Reporter<Scored>) {
    let key = &job.key;
    let fail_all = |reason: String| {
        for (slot, _) in &job.tests {
            reporter.send(Scored {
                key: key.clone(),
                slot: *slot,
                figure: Err(reason.clone()),
                map: None,
            });
        }
    };
    let fits = |s: &JodScorer| *s.display() == key.display && s.mapped() == key.mapped;
    let scorer = match scorer {
        Some(s) if fits(s) => s,
        _ => {
            *scorer = None;
            match JodScorer::for_display(&key.display, key.mapped) {
                Ok(built) => scorer.insert(built),
                Err(err) => return fail_all(err.to_string()),
            }
        }
    };
    // Sequences of any length can be open; their scoring holds every frame.
    if let Frames::Sequence {
        sequence, count, ..
    } = &job.reference
        && let Err(err) = jod::check_memory(sequence.size(), *count)
    {
        return fail_all(err.to_string());
    }
    let reference = match job.reference.load(&job.cancel) {
        None => return,
        Some(Err(err)) => return fail_all(format!("the reference: {err}")),
        Some(Ok(frames)) => frames,
    };
    let fps = key.fps as f32;
    for (slot, test) in &job.tests {
        if job.cancel.load(Ordering::Relaxed) {
            return;
        }
        let Some(test) = test.load(&job.cancel) else {
            return;
        };
        let scored = test.and_then(|test| {
            let scored = match key.mapped {
                true => scorer
                    .score_with_map(&test, &reference, fps)
                    .map(|(value, map)| (value, Some(Arc::new(map)))),
                false => scorer.score(&test, &reference, fps).map(|v| (v, None)),
            };
            scored.map_err(|e| e.to_string())
        });
        let (figure, map) = match scored {
            Ok((value, map)) => (Ok(value), map),
            Err(err) => (Err(err), None),
        };
        reporter.send(Scored {
            key: key.clone(),
            slot: *slot,
            figure,
            map,
        });
    }
}

/// The frame rate a player's rate scores at (the slow rate is the 30 fps clip slowed down).
fn scored_fps(rate: PlayRate) -> u32 {
    match rate {
        PlayRate::Fps60 => 60,
        PlayRate::Fps30 | PlayRate::Slow => 30,
    }
}

/// The JOD figures and maps of what is shown (see the module docs).
#[derive(Default)]
pub struct JodScores {
    worker: Option<Worker<Job, Scored>>,
    /// The job handed to the worker, with its cancel flag.
    running: Option<(Key, Arc<AtomicBool>)>,
    /// What `figures` and `maps` describe.
    scored: Option<Key>,
    /// The panes of `scored`, by slot, in order.
    slots: Vec<usize>,
    /// Per slot, as they come.
    figures: BTreeMap<usize, Figure>,
    maps: BTreeMap<usize, Arc<Plane>>,
    /// With maps of sequences, the reference pane's: all zero, as the reference has no
    /// visible difference from itself (ColorVideoVDP scores identical clips 10 JOD).
    reference_map: Option<(usize, Arc<Plane>)>,
    /// The sequences the user asked to score: scored again (with the map, on another display)
    /// while they stay as they are.
    asked: Option<Subject>,
    /// Counts changes of the figures and maps (the magnifier computes its heatmaps again).
    generation: u64,
}

impl Drop for JodScores {
    /// Closing the viewer stops a job after its technique; the worker's drop waits for that.
    fn drop(&mut self) {
        self.stop_running();
    }
}

impl JodScores {
    /// Takes finished figures, and starts scoring what is shown when it should be scored and
    /// has no figures for the settings yet: a complete clip with the reference always,
    /// sequences when asked or when the distortion heatmap is chosen.
    pub fn update(&mut self, cx: &mut Context, ctx: &egui::Context) {
        self.collect();
        let current = Self::current(cx);
        // A job for what is no longer shown is moot: it stops after its technique.
        if let Some((running, _)) = &self.running
            && current
                .as_ref()
                .is_none_or(|c| c.subject != running.subject)
        {
            self.stop_running();
        }
        let Some(mut key) = current else {
            return;
        };
        key.mapped = cx.settings.show_magnifier
            && cx.settings.magnifier.difference
            && cx.settings.magnifier.metric == DiffMetric::JodDistortion;
        let wanted = match &key.subject {
            Subject::Clip(_) => true,
            Subject::Sequences { .. } => key.mapped || self.asked.as_ref() == Some(&key.subject),
        };
        if !wanted || self.scored.as_ref().is_some_and(|s| s.covers(&key)) {
            return;
        }
        // A job for something else is moot: it stops after its technique.
        self.stop_running();
        if self.worker.is_none() {
            let mut scorer = None;
            match Worker::spawn("aa-lab JOD", ctx, move |job, reporter| {
                score(&mut scorer, job, reporter)
            }) {
                Ok(worker) => self.worker = Some(worker),
                Err(err) => {
                    cx.notify(
                        Level::Error,
                        format!("no thread to score with ColorVideoVDP: {err}"),
                    );
                    self.scored = Some(key);
                    return;
                }
            }
        }
        // The worker takes one job at a time: a newer one waits for the moot one to stop.
        if self.worker.as_ref().is_none_or(Worker::busy) {
            return;
        }
        let Some((tests, reference)) = Self::frames(cx, &key) else {
            return;
        };
        let cancel = Arc::new(AtomicBool::new(false));
        self.slots = tests.iter().map(|(slot, _)| *slot).collect();
        let job = Job {
            key: key.clone(),
            tests,
            reference,
            cancel: Arc::clone(&cancel),
        };
        if self.worker.as_mut().is_some_and(|w| w.submit(job)) {
            self.figures.clear();
            self.maps.clear();
            self.reference_map = match (&key.subject, key.mapped, cx.images.open()) {
                (Subject::Sequences { reference, .. }, true, Some(set)) => {
                    let (width, height) = set.size();
                    let zero = Plane::from_fn(width, height, |_, _| 0.0);
                    Some((*reference, Arc::new(zero)))
                }
                _ => None,
            };
            self.generation += 1;
            self.scored = Some(key.clone());
            self.running = Some((key, cancel));
        }
    }

    /// What is shown that can be scored, as the settings would score it (without maps): the
    /// open sequences when there are at least two, else the complete clip recorded with the
    /// reference.
    fn current(cx: &Context) -> Option<Key> {
        let display = JodDisplay {
            name: cx.settings.jod_display.clone(),
            pixels_per_degree: cx.settings.jod_pixels_per_degree,
        };
        if let Some(set) = cx.images.open() {
            let sequences = set.sequences().filter(|s| s.sequences().len() > 1)?;
            return Some(Key {
                subject: Subject::Sequences {
                    sources: sequences
                        .sequences()
                        .iter()
                        .map(|s| s.source().to_owned())
                        .collect(),
                    offsets: (0..sequences.sequences().len())
                        .map(|i| sequences.offset(i))
                        .collect(),
                    reference: set.reference_index(),
                    instants: sequences.len(),
                },
                display,
                fps: scored_fps(sequences.player.rate),
                mapped: false,
            });
        }
        let clip = cx.engine.as_ref()?.clip()?;
        let has_reference = clip.frames.iter().all(|f| f.reference.is_some());
        (!clip.recording_now() && clip.frames.len() > 1 && has_reference).then(|| Key {
            subject: Subject::Clip(clip.started()),
            display,
            fps: scored_fps(clip.player.rate),
            mapped: false,
        })
    }

    /// The frames of `key`'s subject: every pane but the reference's by slot, and the
    /// reference's.
    fn frames(cx: &Context, key: &Key) -> Option<(Vec<(usize, Frames)>, Frames)> {
        if let Subject::Sequences {
            reference,
            instants,
            ..
        } = &key.subject
        {
            let set = cx.images.open()?.sequences()?;
            let frames = |slot: usize| Frames::Sequence {
                sequence: Arc::clone(&set.sequences()[slot]),
                first: set.offset(slot),
                count: *instants,
            };
            let tests = (0..set.sequences().len())
                .filter(|slot| slot != reference)
                .map(|slot| (slot, frames(slot)))
                .collect();
            return Some((tests, frames(*reference)));
        }
        let clip = cx.engine.as_ref()?.clip()?;
        let reference = clip
            .frames
            .iter()
            .map(|f| f.reference.as_ref()?.pixels.clone())
            .collect::<Option<Vec<_>>>()?;
        let tests = (0..clip.techniques.len())
            .map(|slot| {
                let frames = clip
                    .frames
                    .iter()
                    .filter_map(|f| f.outputs.get(slot)?.as_ref()?.pixels.clone())
                    .collect();
                (slot, Frames::Shared(frames))
            })
            .collect();
        Some((tests, Frames::Shared(reference)))
    }

    /// Takes the figures that finished.
    fn collect(&mut self) {
        let Some(worker) = &mut self.worker else {
            return;
        };
        for scored in worker.poll() {
            if self.scored.as_ref() == Some(&scored.key) {
                self.figures.insert(scored.slot, scored.figure);
                if let Some(map) = scored.map {
                    self.maps.insert(scored.slot, map);
                }
                self.generation += 1;
            }
        }
        if !worker.busy() {
            self.running = None;
        }
    }

    /// Tells the running job to stop after its technique.
    fn stop_running(&mut self) {
        if let Some((_, cancel)) = &self.running {
            cancel.store(true, Ordering::Relaxed);
        }
    }

    /// Scores what is shown (again): the sequences of the open set are scored from now on
    /// while they stay as they are.
    pub fn start(&mut self, cx: &Context) {
        if let Some(key) = Self::current(cx) {
            self.asked = Some(key.subject);
            self.scored = None;
        }
    }

    /// Cancels the running job: the panes not scored yet say so, and nothing starts again
    /// until asked ([`JodScores::start`]).
    pub fn cancel(&mut self) {
        if self.running.is_none() {
            return;
        }
        self.stop_running();
        self.asked = None;
        for slot in &self.slots {
            self.figures
                .entry(*slot)
                .or_insert_with(|| Err(CANCELLED.to_owned()));
        }
        self.generation += 1;
    }

    /// Whether the figures describe what is shown on the settings' display and rate.
    fn describes(&self, cx: &Context) -> bool {
        let (Some(scored), Some(current)) = (&self.scored, Self::current(cx)) else {
            return false;
        };
        scored.covers(&current)
    }

    /// The JOD of the technique or sequence in pane `slot` of what is shown, if scored for
    /// the settings' display and rate.
    pub fn figure(&self, cx: &Context, slot: usize) -> Option<&Figure> {
        self.describes(cx)
            .then(|| self.figures.get(&slot))
            .flatten()
    }

    /// Whether what is shown can be scored (a complete clip with the reference, or two
    /// sequences or more).
    pub fn scorable(cx: &Context) -> bool {
        Self::current(cx).is_some()
    }

    /// Whether figures for what is shown exist or are being computed.
    pub fn started(&self, cx: &Context) -> bool {
        self.describes(cx)
    }

    /// The shown clip's figures by technique id, those scored so far (the blind comparison
    /// records them).
    pub fn published(&self, cx: &Context) -> BTreeMap<&'static str, f64> {
        let Some(clip) = cx.engine.as_ref().and_then(|e| e.clip()) else {
            return BTreeMap::new();
        };
        if cx.images.is_open() {
            return BTreeMap::new();
        }
        clip.techniques
            .iter()
            .enumerate()
            .filter_map(|(slot, id)| Some((*id, *self.figure(cx, slot)?.as_ref().ok()?)))
            .collect()
    }

    /// The distortion maps of what is shown by pane id, or why a pane has none yet.
    pub fn maps(&self, cx: &Context) -> JodMaps {
        let mut published = JodMaps {
            generation: self.generation,
            panes: BTreeMap::new(),
        };
        if !self.describes(cx) || !self.scored.as_ref().is_some_and(|k| k.mapped) {
            return published;
        }
        let ids: Vec<&'static str> = match cx.images.open() {
            Some(_) => IMAGE_IDS.to_vec(),
            None => match cx.engine.as_ref().and_then(|e| e.clip()) {
                Some(clip) => clip.techniques.clone(),
                None => return published,
            },
        };
        for slot in &self.slots {
            let Some(id) = ids.get(*slot) else { continue };
            let pane = match (self.maps.get(slot), self.figures.get(slot)) {
                (Some(map), _) => Ok(Arc::clone(map)),
                (None, Some(Err(why))) => Err(format!("no JOD distortion map: {why}")),
                (None, Some(Ok(_))) => Err("no JOD distortion map".to_owned()),
                (None, None) => Err("ColorVideoVDP: computing the distortion map…".to_owned()),
            };
            published.panes.insert(id, pane);
        }
        if let Some((slot, zero)) = &self.reference_map
            && let Some(id) = ids.get(*slot)
        {
            published.panes.insert(id, Ok(Arc::clone(zero)));
        }
        published
    }

    /// Panes scored and to score while a job runs.
    pub fn progress(&self) -> Option<(usize, usize)> {
        self.running.as_ref()?;
        Some((self.figures.len(), self.slots.len()))
    }
}
