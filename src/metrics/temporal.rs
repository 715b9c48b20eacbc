//! Temporal stability. A technique that shimmers changes its output between frames even when the
//! true image barely moves; the reference (64-sample SSAA) changes only as much as the scene
//! really does. [`ChangeMeter`] accumulates the mean absolute frame-to-frame change of BT.601
//! luma (0..255) over a sequence, and the flicker ratio divides a technique's change by the
//! reference's change over the same frames: 1 is as stable as the reference, 2 changes twice as
//! much as the true image does.
//!
//! Sequences for this are slow on purpose (sub-pixel camera motion per frame, [`SlowTrack`]):
//! with large motion every technique's change is dominated by the true change and the ratio
//! tends to 1.

use super::map::Plane;
use crate::scene::CameraRig;
use crate::scene::camera::{FrameCamera, OrbitPose};

/// A slow orbit for temporal measurements: the rig's frame-0 pose, turned about the vertical
/// axis by a fixed small yaw step per frame, chosen so that a point as far from the orbit axis
/// as the camera is from the target moves `step_px` pixels per frame (points nearer the axis
/// move less). Frame numbers advance by one per frame, so jitter sequences and object animation
/// run as usual.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlowTrack {
    base: OrbitPose,
    step_degrees: f32,
    size: (u32, u32),
}

impl SlowTrack {
    /// The track of `rig` at an image size, moving about `step_px` pixels per frame.
    pub fn new(rig: &CameraRig, size: (u32, u32), step_px: f32) -> Self {
        let base = OrbitPose::at_frame(rig, 0);
        // Pixels per radian of view angle at the image centre, vertically (square pixels).
        let pixels_per_radian =
            size.1.max(1) as f32 / (2.0 * (base.fov_y_degrees.to_radians() * 0.5).tan());
        Self {
            base,
            step_degrees: (step_px / pixels_per_radian).to_degrees(),
            size,
        }
    }

    /// Yaw per frame in degrees.
    pub fn step_degrees(&self) -> f32 {
        self.step_degrees
    }

    fn pose(&self, frame: u64) -> OrbitPose {
        OrbitPose {
            yaw_degrees: self.base.yaw_degrees + frame as f32 * self.step_degrees,
            ..self.base
        }
    }

    /// The camera of frame `frame` (the previous pose is frame - 1's, or the same at 0).
    pub fn camera(&self, frame: u64) -> FrameCamera {
        FrameCamera {
            pose: self.pose(frame),
            prev_pose: self.pose(frame.saturating_sub(1)),
            frame,
            size: self.size,
            render_size: None,
        }
    }
}

/// Accumulates frame-to-frame change over a sequence of images.
#[derive(Clone, Debug, Default)]
pub struct ChangeMeter {
    previous: Option<Plane>,
    sum: f64,
    steps: u32,
}

impl ChangeMeter {
    /// An empty meter.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the next frame of the sequence. A frame of a different size from the previous one
    /// restarts the sequence.
    pub fn push(&mut self, frame: &image::RgbaImage) {
        let luma = Plane::luma(frame);
        if let Some(previous) = self.previous.as_ref().filter(|p| p.size() == luma.size()) {
            let total: f64 = previous
                .data
                .iter()
                .zip(&luma.data)
                .map(|(a, b)| f64::from((a - b).abs()))
                .sum();
            self.sum += total / luma.data.len().max(1) as f64;
            self.steps += 1;
        }
        self.previous = Some(luma);
    }

    /// Frame-to-frame steps measured so far.
    pub fn steps(&self) -> u32 {
        self.steps
    }

    /// Mean absolute luma change per frame, `None` before two frames.
    pub fn mean_change(&self) -> Option<f64> {
        (self.steps > 0).then(|| self.sum / f64::from(self.steps))
    }
}

/// The flicker ratio: a technique's mean change over the reference's, `None` when either is
/// missing or the reference did not change at all.
pub fn flicker_ratio(technique: &ChangeMeter, reference: &ChangeMeter) -> Option<f64> {
    let t = technique.mean_change()?;
    let r = reference.mean_change()?;
    (r > 0.0).then(|| t / r)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(value: u8) -> image::RgbaImage {
        image::RgbaImage::from_pixel(4, 4, image::Rgba([value, value, value, 255]))
    }

    #[test]
    fn slow_track_moves_by_the_asked_pixels() {
        let rig = CameraRig {
            pitch_degrees: 0.0,
            fov_y_degrees: 90.0,
            ..CameraRig::default()
        };
        let track = SlowTrack::new(&rig, (200, 100), 0.5);
        // 100 px over a 90-degree view: 50 px per radian.
        assert!((track.step_degrees() - (0.01f32).to_degrees()).abs() < 1e-5);
        let c = track.camera(3);
        assert_eq!(c.frame, 3);
        assert!((c.pose.yaw_degrees - c.prev_pose.yaw_degrees - track.step_degrees()).abs() < 1e-5);
        assert_eq!(track.camera(0).pose, track.camera(0).prev_pose);
    }

    #[test]
    fn ratio_of_mean_changes() {
        let mut reference = ChangeMeter::new();
        let mut shaky = ChangeMeter::new();
        assert_eq!(reference.mean_change(), None);
        for (r, s) in [(100, 100), (101, 104), (102, 100)] {
            reference.push(&frame(r));
            shaky.push(&frame(s));
        }
        assert_eq!(reference.steps(), 2);
        assert!((reference.mean_change().unwrap() - 1.0).abs() < 1e-4);
        assert!((shaky.mean_change().unwrap() - 4.0).abs() < 1e-4);
        assert!((flicker_ratio(&shaky, &reference).unwrap() - 4.0).abs() < 1e-3);
        let mut still = ChangeMeter::new();
        still.push(&frame(5));
        still.push(&frame(5));
        assert_eq!(flicker_ratio(&shaky, &still), None);
    }
}
