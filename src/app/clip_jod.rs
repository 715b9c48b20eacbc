//! The recorded clip's ColorVideoVDP figures ([`crate::metrics::jod`]): once a clip recorded
//! with the reference is complete, every technique's JOD against the reference, as watched at
//! the clip's real-time rate on the display model of the settings, computed on a thread of its
//! own (a technique takes seconds) and shown in the metrics panel as they come, with progress.
//! A new clip, another display model or another real-time rate starts again; the frames are
//! the clip's own (shared, not copied).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Instant;

use super::context::Context;
use super::engine::PlayRate;
use crate::metrics::jod::JodScorer;

/// What the figures describe: the clip (when its recording started), the display model and the
/// frame rate.
type Key = (Instant, String, u32);

/// A technique's JOD, or why it has none.
pub type Figure = Result<f64, String>;

/// The scoring of one clip.
struct Job {
    key: Key,
    results: mpsc::Receiver<(usize, Figure)>,
    cancel: Arc<AtomicBool>,
}

/// The figures of the shown clip (see the module docs).
#[derive(Default)]
pub struct ClipJod {
    job: Option<Job>,
    /// What `figures` describe.
    scored: Option<Key>,
    /// Per technique in pane order, once scored.
    figures: Vec<Option<Figure>>,
}

impl Drop for ClipJod {
    fn drop(&mut self) {
        self.stop();
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
        if self.scored.as_ref() == Some(&key) || self.job.as_ref().is_some_and(|j| j.key == key) {
            return;
        }
        let tests: Vec<Vec<Arc<image::RgbaImage>>> = (0..clip.techniques.len())
            .map(|slot| {
                clip.frames
                    .iter()
                    .filter_map(|f| f.outputs.get(slot)?.as_ref()?.pixels.clone())
                    .collect()
            })
            .collect();
        self.stop();
        self.figures = vec![None; tests.len()];
        self.scored = Some(key.clone());
        let scorer = match JodScorer::new(&key.1) {
            Ok(scorer) => scorer,
            Err(err) => {
                self.figures = vec![Some(Err(err.to_string())); tests.len()];
                return;
            }
        };
        let (sender, results) = mpsc::channel();
        let cancel = Arc::new(AtomicBool::new(false));
        let stop = Arc::clone(&cancel);
        let wake = ctx.clone();
        let spawned = std::thread::Builder::new()
            .name("aa-lab clip JOD".to_owned())
            .spawn(move || {
                super::worker::lower_priority();
                for (slot, test) in tests.iter().enumerate() {
                    if stop.load(Ordering::Relaxed) {
                        return;
                    }
                    let figure = scorer
                        .score(test, &reference, fps as f32)
                        .map_err(|e| e.to_string());
                    let _ = sender.send((slot, figure));
                    super::request_one_frame(&wake);
                }
            });
        match spawned {
            Ok(_) => {
                self.job = Some(Job {
                    key,
                    results,
                    cancel,
                })
            }
            Err(err) => {
                let text = format!("no thread to score the clip: {err}");
                self.figures = vec![Some(Err(text)); self.figures.len()];
            }
        }
    }

    /// Takes the figures that finished.
    fn collect(&mut self) {
        let Some(job) = &self.job else { return };
        loop {
            match job.results.try_recv() {
                Ok((slot, figure)) => {
                    if let Some(place) = self.figures.get_mut(slot) {
                        *place = Some(figure);
                    }
                }
                Err(mpsc::TryRecvError::Empty) => return,
                Err(mpsc::TryRecvError::Disconnected) => {
                    self.job = None;
                    return;
                }
            }
        }
    }

    /// Stops the scoring in progress (after the technique being scored).
    fn stop(&mut self) {
        if let Some(job) = self.job.take() {
            job.cancel.store(true, Ordering::Relaxed);
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

    /// Techniques scored and to score while a scoring runs.
    pub fn progress(&self) -> Option<(usize, usize)> {
        self.job.as_ref()?;
        let done = self.figures.iter().filter(|f| f.is_some()).count();
        Some((done, self.figures.len()))
    }
}
