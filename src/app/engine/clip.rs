//! The engine's side of clips: starting a recording on the render thread, taking its frames
//! as they arrive, its end and figures, and whether the clip or the live view is on screen
//! (the live view waits while a clip records or shows).

use super::*;

impl Engine {
    /// Records the clip of `recipe` along `cameras` (its warm-up first) through the
    /// techniques `ids`, with the complete reference per frame when the recipe has one.
    /// Frames arrive with [`Engine::poll`]; the clip is shown as they do, and no live frame
    /// renders until the user goes back to the live view.
    pub fn record_clip(
        &mut self,
        cameras: Vec<FrameCamera>,
        ids: &[&'static str],
        recipe: ClipRecipe,
        description: String,
    ) -> Result<(), EngineError> {
        if let Some(reason) = &self.stopped {
            return Err(EngineError::Stopped(reason.clone()));
        }
        let run: Vec<usize> = ids
            .iter()
            .filter_map(|id| self.entries.iter().position(|e| e.id == *id))
            .collect();
        let cancel = Arc::new(std::sync::atomic::AtomicBool::new(false));
        let job = ClipJob {
            cameras,
            warmup: recipe.warmup as usize,
            run,
            reference: recipe.reference_samples,
            cancel: Arc::clone(&cancel),
        };
        if !self.send(Command::Clip(job)) {
            return Err(EngineError::Stopped(String::new()));
        }
        self.clip = Some(Clip::recording(ids.to_vec(), recipe, description, cancel));
        self.clip_shown = true;
        self.after_clip = true;
        Ok(())
    }

    /// The clip, if one was recorded.
    pub fn clip(&self) -> Option<&Clip> {
        self.clip.as_ref()
    }

    /// The clip, to control its playback.
    pub fn clip_mut(&mut self) -> Option<&mut Clip> {
        self.clip.as_mut()
    }

    /// Whether live frames wait: a clip is on screen or being recorded.
    pub fn live_paused(&self) -> bool {
        self.clip_shown() || self.clip.as_ref().is_some_and(Clip::recording_now)
    }

    /// Whether the clip is on screen (every image lookup reads its shown frame).
    pub fn clip_shown(&self) -> bool {
        self.clip_shown && self.clip.is_some()
    }

    /// Shows the clip (`true`) or the live view.
    pub fn show_clip(&mut self, shown: bool) {
        self.clip_shown = shown && self.clip.is_some();
        if let Some(clip) = &mut self.clip {
            clip.player.pause_clock();
        }
    }

    /// Drops the clip (stopping its recording) and shows the live view.
    pub fn discard_clip(&mut self) {
        if let Some(clip) = &self.clip {
            clip.cancel();
        }
        self.clip = None;
        self.clip_shown = false;
    }

    pub(super) fn receive_clip_frame(
        &mut self,
        outputs: Vec<(usize, RenderedImage)>,
        reference: Option<RenderedImage>,
    ) {
        let Some(clip) = &mut self.clip else {
            return;
        };
        // Every clip frame is a view of its own: figures and heatmaps keyed on views follow
        // the frame shown.
        self.view_serial += 1;
        let view = self.view_serial;
        let mut slots: Vec<Option<Published>> = vec![None; clip.techniques.len()];
        for (index, image) in outputs {
            let entry = &self.entries[index];
            if let Some(slot) = clip.techniques.iter().position(|t| *t == entry.id) {
                self.publish_serial += 1;
                let stamp = ImageStamp {
                    view,
                    revision: entry.revision,
                    serial: self.publish_serial,
                };
                slots[slot] = Some(Published::new(image, stamp));
            }
        }
        let reference = reference.map(|image| {
            self.publish_serial += 1;
            let stamp = ImageStamp {
                view,
                revision: self.reference_revision,
                serial: self.publish_serial,
            };
            Published::new(image, stamp)
        });
        clip.push(ClipFrame {
            view,
            outputs: slots,
            reference,
        });
    }

    pub(super) fn end_clip(
        &mut self,
        end: Result<ClipSummary, crate::app::render_thread::RenderError>,
    ) {
        let Some(clip) = &mut self.clip else {
            return;
        };
        clip.status = match end {
            Ok(summary) => {
                clip.scores = summary.scores;
                clip.reference_change = summary.reference_change;
                clip.instability_maps = summary
                    .instability_maps
                    .map(|maps| maps.into_iter().map(Arc::new).collect());
                if summary.complete {
                    ClipStatus::Complete
                } else {
                    ClipStatus::Cancelled
                }
            }
            Err(err) => ClipStatus::Failed(err.to_string()),
        };
    }

    pub(super) fn shown_clip(&self) -> Option<&Clip> {
        self.clip.as_ref().filter(|_| self.clip_shown)
    }
}
