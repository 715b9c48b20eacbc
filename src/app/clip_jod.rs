//! The recorded clip's ColorVideoVDP figures ([`crate::metrics::jod`]): once a clip recorded
//! with the reference is complete, every technique's JOD against the reference, as watched at
//! the clip's real-time rate on the display model of the settings, computed on a thread of its
//! own (a technique takes seconds; one worker thread for every clip, so its memory is reused)
//! and shown in the metrics panel as they come, with progress.
//! A new clip, another display model or another real-time rate starts again; the frames are
//! the clip's own (shared, not copied).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use super::context::{Context, Level};
use super::engine::PlayRate;
use super::worker::{Reporter, Worker};
use crate::metrics::jod::JodScorer;

/// What the figures describe: the clip (when its recording started), the display model and the
/// frame rate.
type Key = (Instant, String, u32);

/// A technique's JOD, or why it has none.
pub type Figure = Result<f64, String>;

/// A clip to score: each technique's frames and the reference's.
struct Job {
    key: Key,
    tests: Vec<Vec<Arc<image::RgbaImage>>>,
    reference: Vec<Arc<image::RgbaImage>>,
    /// Set when a newer clip or display makes the job moot (checked between techniques).
    cancel: Arc<AtomicBool>,
}

/// One technique's figure, for the clip of `key`.
struct Scored {
    key: Key,
    slot: usize,
    figure: Figure,
}

/// Scores jobs one after the other on the worker's thread, keeping the scorer of the last
/// display model (one thread for every clip, so its memory is reused).
fn score(scorer: &mut Option<JodScorer>, job: Job, reporter: &Reporter<Scored>) {
    let display = &job.key.1;
    if scorer.as_ref().is_none_or(|s| s.display() != display) {
        *scorer = JodScorer::new(display).ok();
    }
    for (slot, test) in job.tests.iter().enumerate() {
        if job.cancel.load(Ordering::Relaxed) {
            return;
        }
        let figure = match scorer {
            Some(scorer) => scorer
                .score(test, &job.reference, job.key.2 as f32)
                .map_err(|e| e.to_string()),
            None => Err(format!("ColorVideoVDP has no display model `{display}`")),
        };
        reporter.send(Scored {
            key: job.key.clone(),
            slot,
            figure,
        });
    }
}

/// The figures of the shown clip (see the module docs).
#[derive(Default)]
pub struct ClipJod {
    worker: Option<Worker<Job, Scored>>,
    /// The job handed to the worker, with its cancel flag.
    running: Option<(Key, Arc<AtomicBool>)>,
    /// What `figures` describe.
    scored: Option<Key>,
    /// Per technique in pane order, as they come.
    figures: Vec<Option<Figure>>,
}

impl Drop for ClipJod {
    /// Closing the viewer stops a job after its technique; the worker's drop waits for that.
    fn drop(&mut self) {
        if let Some((_, cancel)) = &self.running {
            cancel.store(true, Ordering::Relaxed);
        }
    }
}

impl ClipJod {
    /// Starts scoring the clip the context shows when it is complete, has the reference and
    /// has no figures for the display model and rate yet; takes finished figures.
    pub fn update(&mut self, cx: &mut Context, ctx: &egui::Context) {
        self.collect();
        let Some(clip) = cx.engine.as_ref().and_then(|e| e.clip()) else {
            return;
        };
        let complete = !clip.recording_now() && clip.frames.len() > 1;
        let reference: Option<Vec<_>> = clip
            .frames
            .iter()
            .map(|f| f.reference.as_ref()?.pixels.clone())
            .collect();
        let (Some(reference), true) = (reference, complete) else {
            return;
        };
        let fps = match clip.player.rate {
            PlayRate::Fps60 => 60,
            PlayRate::Fps30 | PlayRate::Slow => 30,
        };
        let key = (clip.started(), cx.settings.jod_display.clone(), fps);
        if self.scored.as_ref() == Some(&key) {
            return;
        }
        // A job for another clip or display is moot: it stops after its technique.
        if let Some((_, cancel)) = &self.running {
            cancel.store(true, Ordering::Relaxed);
        }
        let tests: Vec<Vec<Arc<image::RgbaImage>>> = (0..clip.techniques.len())
            .map(|slot| {
                clip.frames
                    .iter()
                    .filter_map(|f| f.outputs.get(slot)?.as_ref()?.pixels.clone())
                    .collect()
            })
            .collect();
        if self.worker.is_none() {
            let mut scorer = None;
            match Worker::spawn("aa-lab clip JOD", ctx, move |job, reporter| {
                score(&mut scorer, job, reporter)
            }) {
                Ok(worker) => self.worker = Some(worker),
                Err(err) => {
                    cx.notify(
                        Level::Error,
                        format!("no thread to score clips with ColorVideoVDP: {err}"),
                    );
                    self.scored = Some(key);
                    return;
                }
            }
        }
        let Some(worker) = &mut self.worker else {
            return;
        };
        let cancel = Arc::new(AtomicBool::new(false));
        let job = Job {
            key: key.clone(),
            tests,
            reference,
            cancel: Arc::clone(&cancel),
        };
        // The worker takes one job at a time: a newer clip waits for the moot one to stop.
        if worker.submit(job) {
            self.figures = vec![None; clip.techniques.len()];
            self.scored = Some(key.clone());
            self.running = Some((key, cancel));
        }
    }

    /// Takes the figures that finished.
    fn collect(&mut self) {
        let Some(worker) = &mut self.worker else {
            return;
        };
        for scored in worker.poll() {
            if self.scored.as_ref() == Some(&scored.key)
                && let Some(place) = self.figures.get_mut(scored.slot)
            {
                *place = Some(scored.figure);
            }
        }
        if !worker.busy() {
            self.running = None;
        }
    }

    /// The JOD of the technique in pane `slot` of the shown clip, if scored for the settings'
    /// display model.
    pub fn figure(&self, cx: &Context, slot: usize) -> Option<&Figure> {
        let clip = cx.engine.as_ref()?.clip()?;
        let (started, display, _) = self.scored.as_ref()?;
        (*started == clip.started() && *display == cx.settings.jod_display)
            .then(|| self.figures.get(slot)?.as_ref())
            .flatten()
    }

    /// The shown clip's figures by technique id, those scored so far.
    pub fn published(&self, cx: &Context) -> std::collections::BTreeMap<&'static str, f64> {
        let Some(clip) = cx.engine.as_ref().and_then(|e| e.clip()) else {
            return Default::default();
        };
        clip.techniques
            .iter()
            .enumerate()
            .filter_map(|(slot, id)| Some((*id, *self.figure(cx, slot)?.as_ref().ok()?)))
            .collect()
    }

    /// Techniques scored and to score while a scoring runs.
    pub fn progress(&self) -> Option<(usize, usize)> {
        self.running.as_ref()?;
        let done = self.figures.iter().filter(|f| f.is_some()).count();
        Some((done, self.figures.len()))
    }
}
