//! The context's clip commands: recording the compared techniques along the chosen camera
//! path within the memory cap, showing the clip or the live view, ticking the player, and the
//! recorded clip's progress, scores and instability maps as the panels and the magnifier read
//! them.

use std::sync::Arc;
use std::time::Instant;

use super::{Context, Level};
use crate::app::engine::{ClipPath, ClipRecipe};
use crate::metrics::stability::TemporalScores;
use crate::scene::camera::OrbitPose;

/// Playback rates from which the UI repaints continuously (below, once per clip frame).
const REPAINT_EVERY_FRAME_FPS: f64 = 30.0;

impl Context {
    /// Shows the clip or the live view.
    pub(in crate::app) fn show_clip(&mut self, shown: bool) {
        if let Some(engine) = &mut self.engine {
            engine.show_clip(shown);
        }
    }

    /// Records a clip of the compared techniques along the chosen path from the current view.
    pub(in crate::app) fn record_clip(&mut self) {
        let ids = self.compared();
        let size = self.render_size;
        let settings = self.settings.clip;
        if ids.is_empty() {
            self.notify(
                Level::Warning,
                "Switch on a technique to record a clip of it.",
            );
            return;
        }
        if size.0 == 0 || size.1 == 0 {
            self.notify(Level::Warning, "The viewport has no size to record at.");
            return;
        }
        let bytes = settings.bytes(ids.len() + usize::from(settings.reference), size);
        let cap = u64::from(settings.budget_mib) << 20;
        if bytes > cap {
            self.notify(
                Level::Error,
                format!(
                    "A clip of {} frames of {} images at {}x{} would hold {}; the cap is {} MiB. Record fewer frames, at a smaller resolution or with fewer techniques.",
                    settings.frames,
                    ids.len() + usize::from(settings.reference),
                    size.0,
                    size.1,
                    crate::app::style::whole_mib(bytes),
                    settings.budget_mib
                ),
            );
            return;
        }
        let bookmarks: Vec<OrbitPose> = self.scene_bookmarks().iter().map(|b| b.pose).collect();
        let Some(cameras) =
            settings.cameras(self.camera.rig(), self.camera.pose(), &bookmarks, size)
        else {
            self.notify(
                Level::Warning,
                "The bookmark path needs at least two camera bookmarks of this scene (Camera > Add bookmark).",
            );
            return;
        };
        let Some(engine) = &self.engine else {
            return;
        };
        let recipe = ClipRecipe {
            scene: self
                .scene
                .as_ref()
                .map_or_else(String::new, |s| s.spec.clone()),
            path: settings.path,
            speed_px: settings.speed_px,
            warmup: settings.warmup,
            frames: settings.frames,
            size,
            start: self.camera.pose(),
            bookmarks: if settings.path == ClipPath::Bookmarks {
                bookmarks
            } else {
                Vec::new()
            },
            techniques: ids.iter().map(|id| engine.technique_spec(id)).collect(),
            reference_samples: settings.reference.then_some(settings.reference_samples),
            adapter: format!("{} ({})", engine.caps().adapter_name, engine.caps().backend),
            build: crate::spec::build_id(),
        };
        let description = recipe.describe(self.scene.as_ref().map_or("scene", |s| s.name.as_str()));
        let Some(engine) = &mut self.engine else {
            return;
        };
        if let Err(err) = engine.record_clip(cameras, &ids, recipe, description) {
            self.notify(Level::Error, err.to_string());
        }
    }

    /// The clip's progress: frames recorded, and whether it is still recording (`None`: no
    /// clip).
    pub(in crate::app) fn clip_progress(&self) -> Option<(usize, bool)> {
        let clip = self.engine.as_ref()?.clip()?;
        Some((clip.frames.len(), clip.recording_now()))
    }

    /// The clip's temporal figures per technique, once recorded with the reference.
    pub(in crate::app) fn clip_scores(&self) -> Option<Vec<TemporalScores>> {
        self.engine.as_ref()?.clip()?.scores.clone()
    }

    /// The instability map of technique `id` in the shown clip.
    pub(in crate::app) fn instability_map(&self, id: &str) -> Option<Arc<crate::metrics::Plane>> {
        let engine = self.engine.as_ref()?;
        let clip = engine.clip().filter(|_| engine.clip_shown())?;
        let slot = clip.techniques.iter().position(|t| *t == id)?;
        clip.instability_maps.as_ref()?.get(slot).cloned()
    }

    /// The index of the clip frame on screen (`None` when the live view is).
    pub(in crate::app) fn shown_clip_frame(&self) -> Option<usize> {
        let engine = self.engine.as_ref()?;
        let clip = engine.clip().filter(|_| engine.clip_shown())?;
        Some(clip.player.frame(clip.frames.len()))
    }

    /// Advances the shown clip's playback; asks for the next UI frame when it plays.
    pub(in crate::app) fn tick_clip(&mut self, ctx: &egui::Context) {
        let Some(engine) = &mut self.engine else {
            return;
        };
        if !engine.clip_shown() {
            return;
        }
        let Some(clip) = engine.clip_mut() else {
            return;
        };
        let frames = clip.frames.len();
        if clip.recording_now() {
            // While it records, the clip shows its newest frame; each recorded frame wakes the
            // UI. (Looping over the frames so far would repaint without pause and, on a
            // software rasteriser, take the CPU the recording needs, doubling its time; see
            // docs/viewer.md.) Playback starts when the recording ends.
            clip.player.show_newest(frames);
            return;
        }
        clip.player.tick(Instant::now(), frames);
        if clip.player.playing && frames > 1 {
            if clip.player.rate.fps() >= REPAINT_EVERY_FRAME_FPS {
                // Real time: paint as often as the display (or the rasteriser) allows, so a
                // frame that takes most of a clip period still lands on every clip frame.
                crate::app::repaint::request_one_frame(ctx);
            } else {
                // Slow motion: the next UI frame when the next clip frame is due.
                let due = std::time::Duration::from_secs_f64(clip.player.until_next_frame());
                ctx.request_repaint_after(due);
            }
        }
    }
}
