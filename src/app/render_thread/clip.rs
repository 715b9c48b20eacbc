//! Clip recording on the render thread: a [`ClipJob`] runs through the library's
//! [`ClipRecorder`] with this thread's graph, readback belt and uploads, each recorded frame
//! going to the UI as it comes ([`Event::ClipFrame`]) and the figures at the end
//! ([`ClipSummary`]).

use super::*;
use crate::clip_recorder::{ClipFrames, ClipRecorder, FrameImages, ScoredFrame};

/// A clip to record: every camera in turn through the same techniques (temporal ones with
/// their real history), each frame read back and uploaded for display. The thread renders it
/// in one go, answering [`Event::ClipFrame`] per recorded frame and [`Event::ClipEnd`] at the
/// end; commands sent meanwhile wait.
pub struct ClipJob {
    /// Warm-up cameras first (rendered for the history only), then the clip's.
    pub cameras: Vec<FrameCamera>,
    /// How many of `cameras` are warm-up.
    pub warmup: usize,
    /// Registry indices of the techniques.
    pub run: Vec<usize>,
    /// Render the reference, complete, with every recorded frame, at this many samples per
    /// pixel.
    pub reference: Option<u32>,
    /// Set by the UI to stop after the frame being rendered.
    pub cancel: Arc<AtomicBool>,
}

/// How a clip ended.
pub struct ClipSummary {
    /// Every frame was recorded (not cancelled).
    pub complete: bool,
    /// Temporal figures per technique of the job, when it rendered the reference.
    pub scores: Option<Vec<TemporalScores>>,
    /// The reference's mean luma change per pixel and frame.
    pub reference_change: Option<f64>,
    /// Per technique of the job, with the reference: each pixel's mean luma change over the
    /// reference's mean change of the whole frame (the instability map).
    pub instability_maps: Option<Vec<Plane>>,
}

impl RenderState {
    /// Renders `job`, sending each recorded frame through `send`, and scores it (the viewer's
    /// reference comes back afterwards).
    pub(super) fn record_clip(
        &mut self,
        job: &ClipJob,
        send: &dyn Fn(Event),
    ) -> Result<ClipSummary, RenderError> {
        let live_samples = self.reference_samples;
        if let Some(samples) = job.reference {
            self.set_reference_samples(samples);
        }
        let recorded = self.record_clip_frames(job, send);
        self.set_reference_samples(live_samples);
        recorded
    }

    /// Renders `job` with the library's [`ClipRecorder`], sending each recorded frame through
    /// `send`, and scores it.
    fn record_clip_frames(
        &mut self,
        job: &ClipJob,
        send: &dyn Fn(Event),
    ) -> Result<ClipSummary, RenderError> {
        let recorder = ClipRecorder::new(
            job.cameras.clone(),
            job.warmup,
            job.run.len(),
            job.reference.is_some(),
        );
        let clip = recorder.record(&mut ViewerClipFrames {
            state: self,
            job,
            send,
        })?;
        Ok(ClipSummary {
            complete: clip.complete,
            reference_change: clip.reference_change(),
            instability_maps: clip.instability_maps(),
            scores: clip.scores(),
        })
    }
}

/// A clip frame as the viewer shows it: the techniques' images and the reference's.
struct ShownClipFrame {
    outputs: Vec<(usize, RenderedImage)>,
    reference: Option<RenderedImage>,
}

impl ScoredFrame for ShownClipFrame {
    fn whole(&self) -> FrameImages<'_> {
        FrameImages {
            techniques: self
                .outputs
                .iter()
                .map(|(_, image)| &image.pixels)
                .collect(),
            reference: self.reference.as_ref().map(|image| &image.pixels),
        }
    }
}

/// The render thread's side of the recorder: renders a job's frames through the thread's
/// graph and readback belt, and sends every recorded frame to the UI.
struct ViewerClipFrames<'a> {
    state: &'a mut RenderState,
    job: &'a ClipJob,
    send: &'a dyn Fn(Event),
}

impl ClipFrames for ViewerClipFrames<'_> {
    type Frame = ShownClipFrame;
    type Error = RenderError;

    fn cancelled(&self) -> bool {
        self.job.cancel.load(Ordering::Relaxed)
    }

    fn warm_up(&mut self, frame: &FrameInfo) -> Result<(), RenderError> {
        let run = &self.job.run;
        self.state.enable(run, run, false);
        self.state.graph.render(frame, FrameScope::TemporalOnly)?;
        self.state.graph.finish();
        Ok(())
    }

    fn capture(&mut self, frame: &FrameInfo) -> Result<ShownClipFrame, RenderError> {
        let job = self.job;
        let plan = FramePlan {
            frame: *frame,
            run: job.run.clone(),
            read: job.run.clone(),
            // Every frame needs textures of its own: the outputs' are overwritten.
            textures: false,
            debug: Vec::new(),
            reference: job.reference.map(|_| ReferenceRequest {
                restart: true,
                budget: self.state.reference_samples,
            }),
            on: job.run.clone(),
            report_memory: false,
            delay: Duration::ZERO,
        };
        let result = self.state.render(&plan)?;
        Ok(ShownClipFrame {
            outputs: result
                .outputs
                .into_iter()
                .filter_map(|(index, output)| {
                    let texture = output.display?;
                    let pixels = output.pixels?;
                    Some((index, RenderedImage { pixels, texture }))
                })
                .collect(),
            reference: result.reference.map(|(_, image)| image),
        })
    }

    fn deliver(&mut self, _number: usize, frame: ShownClipFrame) -> Result<(), RenderError> {
        (self.send)(Event::ClipFrame {
            outputs: frame.outputs,
            reference: frame.reference,
        });
        Ok(())
    }
}
