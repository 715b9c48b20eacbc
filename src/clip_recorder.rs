//! The clip recorder: the one loop that records a clip, driven by `aa-lab clip` and by the
//! viewer's render thread alike.
//!
//! A clip is a list of cameras, the first `warmup` of which only fill the temporal techniques'
//! history. The recorder walks them in order: the first frame drops every history, a warm-up
//! frame renders the temporal techniques and reads nothing, a clip frame renders every
//! technique (and the reference, when the clip is scored) and is read back. Every clip frame is
//! scored against the reference as it comes ([`ClipMetrics`]: temporal instability, ghosting),
//! over the whole frame and, when the front end marks one, over a region, and then handed to
//! the front end, which encodes it (the command line) or shows it (the viewer).
//!
//! What differs between the front ends (how a frame is rendered and read back, where it goes)
//! is theirs, behind [`ClipFrames`]; the order of the frames, the history resets, cancelling
//! and the figures are here, once. A clip that nothing renders (every pane read from captured
//! image sequences) has no cameras: its front end adds each frame to
//! [`RecordedClip::scored`] with [`RecordedClip::add`], which scores it the same way.

use crate::graph::FrameInfo;
use crate::metrics::stability::{ClipMetrics, TemporalScores};
use crate::metrics::{MetricsError, Plane};
use crate::scene::camera::FrameCamera;

/// The images of a recorded frame the recorder scores: each technique's, in the clip's order,
/// and the reference's (none when the clip is not scored). sRGB-encoded RGBA8, one size.
pub struct FrameImages<'a> {
    /// The techniques' images.
    pub techniques: Vec<&'a image::RgbaImage>,
    /// The reference's image.
    pub reference: Option<&'a image::RgbaImage>,
}

/// A recorded frame as a front end keeps it, with the images the recorder scores.
pub trait ScoredFrame {
    /// The whole frame's images.
    fn whole(&self) -> FrameImages<'_>;

    /// The images of the region the clip is also scored over, when it has one.
    fn region(&self) -> Option<FrameImages<'_>> {
        None
    }
}

/// What a front end does for the recorder: render and read back frames, and take the
/// recorded ones.
pub trait ClipFrames {
    /// A recorded frame, as the front end keeps it.
    type Frame: ScoredFrame;
    /// The front end's error.
    type Error;

    /// Whether the recording should stop before the next frame.
    fn cancelled(&self) -> bool {
        false
    }

    /// Renders a warm-up frame: the temporal techniques only, nothing read back.
    fn warm_up(&mut self, frame: &FrameInfo) -> Result<(), Self::Error>;

    /// Renders a clip frame, every technique and the reference, and reads it back.
    fn capture(&mut self, frame: &FrameInfo) -> Result<Self::Frame, Self::Error>;

    /// Takes clip frame `number` (0 is the first after the warm-up), once it is scored.
    fn deliver(&mut self, number: usize, frame: Self::Frame) -> Result<(), Self::Error>;
}

/// A clip to record: its cameras, how many of them warm up, how many techniques it shows and
/// whether it is scored against a reference.
pub struct ClipRecorder {
    cameras: Vec<FrameCamera>,
    warmup: usize,
    techniques: usize,
    scored: bool,
}

/// What a recording leaves: whether it ran to the end, and its figures.
#[derive(Debug, Default)]
pub struct RecordedClip {
    /// Every frame was recorded (not cancelled).
    pub complete: bool,
    /// Clip frames recorded (warm-up not counted).
    pub frames: usize,
    /// The figures over the whole frame, when the clip was scored and every frame could be.
    pub metrics: Option<ClipMetrics>,
    /// The figures over the region, when the frames had one.
    pub region_metrics: Option<ClipMetrics>,
    /// Why a scored clip has no figures (a frame whose images did not fit the reference).
    pub score_error: Option<MetricsError>,
}

impl ClipRecorder {
    /// A clip over `cameras`, of which the first `warmup` only warm up, showing `techniques`
    /// techniques, scored against a reference when `scored`.
    pub fn new(cameras: Vec<FrameCamera>, warmup: usize, techniques: usize, scored: bool) -> Self {
        Self {
            cameras,
            warmup,
            techniques,
            scored,
        }
    }

    /// Records the clip through `frames` (see the module docs). A front end's error ends the
    /// recording and is returned; a frame that cannot be scored only leaves the clip without
    /// figures ([`RecordedClip::score_error`]).
    pub fn record<F: ClipFrames>(self, frames: &mut F) -> Result<RecordedClip, F::Error> {
        let mut recorded = RecordedClip {
            complete: true,
            metrics: self.scored.then(|| ClipMetrics::new(self.techniques)),
            ..RecordedClip::default()
        };
        for (index, camera) in self.cameras.iter().enumerate() {
            if frames.cancelled() {
                recorded.complete = false;
                break;
            }
            let info = FrameInfo {
                camera: *camera,
                reset_history: index == 0,
            };
            if index < self.warmup {
                frames.warm_up(&info)?;
                continue;
            }
            let frame = frames.capture(&info)?;
            recorded.add(&frame);
            frames.deliver(index - self.warmup, frame)?;
        }
        Ok(recorded)
    }
}

impl RecordedClip {
    /// A complete clip of no frames yet, scored against a reference, of `techniques` panes
    /// besides the reference's: the start of a clip whose frames are not rendered.
    pub fn scored(techniques: usize) -> Self {
        Self {
            complete: true,
            metrics: Some(ClipMetrics::new(techniques)),
            ..Self::default()
        }
    }

    /// Counts a recorded frame and adds it to the figures (over its region too when it is the
    /// first frame and has one); the first frame that cannot be scored drops them.
    pub fn add(&mut self, frame: &impl ScoredFrame) {
        if self.frames == 0
            && frame.region().is_some()
            && let Some(metrics) = &self.metrics
        {
            self.region_metrics = Some(ClipMetrics::new(metrics.scores().len()));
        }
        self.frames += 1;
        let whole = score(&mut self.metrics, &frame.whole());
        let region = match frame.region() {
            Some(images) => score(&mut self.region_metrics, &images),
            None => {
                self.region_metrics = None;
                Ok(())
            }
        };
        if let Err(err) = whole.and(region) {
            self.metrics = None;
            self.region_metrics = None;
            self.score_error.get_or_insert(err);
        }
    }

    /// Every technique's figures over the whole frame, in the clip's order.
    pub fn scores(&self) -> Option<Vec<TemporalScores>> {
        self.metrics.as_ref().map(ClipMetrics::scores)
    }

    /// Every technique's figures over the region.
    pub fn region_scores(&self) -> Option<Vec<TemporalScores>> {
        self.region_metrics.as_ref().map(ClipMetrics::scores)
    }

    /// The reference's mean luma change per pixel and frame, over the whole frame.
    pub fn reference_change(&self) -> Option<f64> {
        self.metrics.as_ref()?.reference().mean_change()
    }

    /// Per technique: each pixel's mean luma change over the reference's mean change of the
    /// whole frame (the instability map), when the reference moved at all.
    pub fn instability_maps(&self) -> Option<Vec<Plane>> {
        let metrics = self.metrics.as_ref()?;
        let change = self.reference_change().filter(|&change| change > 0.0)? as f32;
        (0..metrics.scores().len())
            .map(|i| {
                let mut map = metrics.technique(i)?.change_map()?;
                map.data.iter_mut().for_each(|v| *v /= change);
                Some(map)
            })
            .collect()
    }
}

/// Adds `images` to `metrics` (nothing when the clip is not scored or has lost its figures).
fn score(metrics: &mut Option<ClipMetrics>, images: &FrameImages) -> Result<(), MetricsError> {
    match (metrics, images.reference) {
        (Some(metrics), Some(reference)) => metrics.push(reference, &images.techniques),
        (Some(_), None) => Err(MetricsError::NoReference),
        (None, _) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::CameraRig;

    /// A front end that records what it is asked for: a grey frame per clip frame, brighter
    /// each frame for the technique, constant for the reference.
    #[derive(Default)]
    struct Log {
        warmed: Vec<(u64, bool)>,
        captured: Vec<(u64, bool)>,
        delivered: Vec<usize>,
        cancel_after: Option<usize>,
        region: bool,
    }

    struct Frame {
        technique: image::RgbaImage,
        reference: image::RgbaImage,
        region: bool,
    }

    impl ScoredFrame for Frame {
        fn whole(&self) -> FrameImages<'_> {
            FrameImages {
                techniques: vec![&self.technique],
                reference: Some(&self.reference),
            }
        }

        fn region(&self) -> Option<FrameImages<'_>> {
            self.region.then(|| self.whole())
        }
    }

    impl ClipFrames for Log {
        type Frame = Frame;
        type Error = String;

        fn cancelled(&self) -> bool {
            self.cancel_after
                .is_some_and(|n| self.warmed.len() + self.captured.len() >= n)
        }

        fn warm_up(&mut self, frame: &FrameInfo) -> Result<(), String> {
            self.warmed.push((frame.camera.frame, frame.reset_history));
            Ok(())
        }

        fn capture(&mut self, frame: &FrameInfo) -> Result<Frame, String> {
            self.captured
                .push((frame.camera.frame, frame.reset_history));
            let level = 40 * self.captured.len() as u8;
            Ok(Frame {
                technique: image::RgbaImage::from_pixel(
                    4,
                    4,
                    image::Rgba([level, level, level, 255]),
                ),
                reference: image::RgbaImage::from_pixel(4, 4, image::Rgba([9, 9, 9, 255])),
                region: self.region,
            })
        }

        fn deliver(&mut self, number: usize, _frame: Frame) -> Result<(), String> {
            self.delivered.push(number);
            Ok(())
        }
    }

    fn cameras(count: u64) -> Vec<FrameCamera> {
        (0..count)
            .map(|frame| FrameCamera::from_rig(&CameraRig::default(), frame, (4, 4)))
            .collect()
    }

    #[test]
    fn warm_up_frames_are_rendered_first_and_only_the_first_frame_resets_history() {
        let mut log = Log::default();
        let recorded = ClipRecorder::new(cameras(5), 2, 1, true)
            .record(&mut log)
            .expect("records");
        assert_eq!(log.warmed, vec![(0, true), (1, false)]);
        assert_eq!(log.captured, vec![(2, false), (3, false), (4, false)]);
        assert_eq!(log.delivered, vec![0, 1, 2]);
        assert!(recorded.complete);
        assert_eq!(recorded.frames, 3);
        let scores = recorded.scores().expect("scored");
        // The technique brightens by 40 levels a frame while the reference stands still.
        assert!(scores[0].mean_change.expect("a change") > 0.1);
        assert_eq!(recorded.reference_change(), Some(0.0));
        assert!(
            recorded.instability_maps().is_none(),
            "a still reference has no maps"
        );
        assert!(recorded.region_scores().is_none());
    }

    #[test]
    fn a_cancelled_clip_stops_before_the_next_frame_and_says_so() {
        let mut log = Log {
            cancel_after: Some(3),
            region: true,
            ..Log::default()
        };
        let recorded = ClipRecorder::new(cameras(6), 1, 1, true)
            .record(&mut log)
            .expect("records");
        assert!(!recorded.complete);
        assert_eq!(log.delivered, vec![0, 1]);
        assert_eq!(recorded.frames, 2);
        assert!(recorded.region_scores().is_some());
    }

    #[test]
    fn a_frame_with_the_wrong_number_of_images_leaves_the_clip_without_figures() {
        let mut log = Log::default();
        let recorded = ClipRecorder::new(cameras(3), 0, 2, true)
            .record(&mut log)
            .expect("records");
        assert_eq!(log.delivered, vec![0, 1, 2], "the frames still arrive");
        assert!(recorded.scores().is_none());
        assert!(matches!(
            recorded.score_error,
            Some(MetricsError::FrameCount {
                expected: 2,
                got: 1
            })
        ));
    }
}
