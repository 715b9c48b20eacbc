//! The context's blind-comparison commands: starting a session over the compared techniques
//! (its answers file in the export folder), the session's keys and pane clicks, acting on an
//! answer, and the record of what was on screen for each answer.

use std::time::{SystemTime, UNIX_EPOCH};

use super::{Context, Level};
use crate::app::blind::{BlindAction, Choice, Lens, OnScreen, TrialContext};

impl Context {
    /// Starts a blind session over the compared techniques (two to four), writing its answers
    /// into the export folder.
    pub(in crate::app) fn start_blind(&mut self, ctx: &egui::Context) {
        let ids = self.compared();
        if ids.len() < 2 {
            self.notify(
                Level::Warning,
                "A blind comparison needs at least two compared techniques: switch on another.",
            );
            return;
        }
        let techniques = ids.iter().map(|id| (*id, self.shown_label(id))).collect();
        let seed = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos() as u64);
        let scene = if self.images.is_open() {
            "images"
        } else {
            self.scene.as_ref().map_or("scene", |s| s.name.as_str())
        };
        let dir = self.settings.export_dir.clone();
        let stem = crate::files::free_stem(&dir, &format!("{scene}-blind"), &[".json".to_owned()]);
        let path = dir.join(format!("{stem}.json"));
        let adapter = format!("{} ({})", self.gpu.caps.adapter_name, self.gpu.caps.backend);
        match self.blind.start(techniques, seed, path, adapter, ctx) {
            Ok(()) => self.notify(
                Level::Info,
                "Blind comparison: the panes are numbered and shuffled; answer with 1–4 or 0.",
            ),
            Err(err) => self.notify(
                Level::Error,
                format!("cannot start the blind comparison: {err}"),
            ),
        }
    }

    /// The session's keys, taken out of `events` (before the shortcuts, which they take
    /// precedence over).
    pub(in crate::app) fn blind_keys(&mut self, events: &mut Vec<egui::Event>) {
        if let Some(action) = self.blind.take_keys(events) {
            self.blind_act(action);
        }
    }

    /// A click on the pane of `slot` (viewport or magnifier) answers during a session.
    pub(in crate::app) fn blind_click(&mut self, slot: usize) {
        if self.blind.active() {
            self.blind_act(BlindAction::Answer(Choice::Pane(slot)));
        }
    }

    pub(in crate::app) fn blind_act(&mut self, action: BlindAction) {
        match action {
            BlindAction::Answer(choice) => {
                let context = self.trial_context();
                self.blind.answer(choice, context);
            }
            BlindAction::Next => self.blind.next_trial(),
            BlindAction::End => {
                if let Some(line) = self.blind.end() {
                    self.notify(Level::Info, line);
                }
            }
        }
    }

    /// What is on screen now, for an answer's record.
    pub(in crate::app) fn trial_context(&self) -> TrialContext {
        let engine = self.engine.as_ref();
        let clip = engine
            .filter(|e| e.clip_shown())
            .and_then(|e| e.clip())
            .filter(|_| !self.images.is_open());
        let (shown, in_motion) = if let Some(set) = self.images.open() {
            let paths = set.images().iter().map(|i| i.path.clone()).collect();
            (OnScreen::Images { paths }, false)
        } else if let Some(clip) = clip {
            let frames = clip.frames.len();
            let playing = clip.player.playing && frames > 1;
            let shown = OnScreen::Clip {
                frame: clip.player.frame(frames),
                frames,
                playing,
                fps: clip.player.rate.fps(),
                ping_pong: clip.player.ping_pong,
                recipe: clip.recipe.clone(),
            };
            (shown, playing)
        } else {
            let moving = self.camera.moving_by_itself();
            let settings = self
                .compared()
                .into_iter()
                .filter_map(|id| Some((id, engine?.param_map(id))))
                .collect();
            let shown = OnScreen::Live {
                frame: self.camera.frame(),
                camera: self.camera.pose(),
                camera_moving: moving,
                settings,
            };
            (shown, moving)
        };
        let region = self
            .settings
            .show_magnifier
            .then(|| self.lens())
            .flatten()
            .map(|lens| Lens {
                x: lens.x,
                y: lens.y,
                width: lens.width,
                height: lens.height,
                zoom: self.settings.magnifier.zoom,
            });
        TrialContext {
            scene: self
                .scene
                .as_ref()
                .filter(|_| !self.images.is_open())
                .map_or_else(|| "images".to_owned(), |s| s.spec.clone()),
            in_motion,
            shown,
            layout: self.settings.layout,
            jod: clip
                .is_some()
                .then(|| self.clip_jod.clone())
                .filter(|jod| !jod.is_empty()),
            region,
            render_size: self.render_size,
        }
    }
}
