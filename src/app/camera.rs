//! The viewer's camera: the scene's orbit rig as a starting point, mouse orbit, pan and zoom on
//! top, the thesis' auto-rotation (the rig's degrees per frame), pause and single-frame steps,
//! and cut detection so temporal techniques drop their history when the view jumps.
//!
//! The frame number is the scene's animation clock and the temporal techniques' jitter index:
//! it advances by one per rendered frame while playing and stands still while paused. The
//! pose of the previous rendered frame is kept so that motion vectors describe what the user
//! did with the mouse, except after a cut, where the previous pose equals the current one.

use glam::{Vec2, Vec3};

use crate::scene::CameraRig;
use crate::scene::camera::{FrameCamera, OrbitPose};

/// Degrees of orbit per pixel dragged.
const ORBIT_DEGREES_PER_PIXEL: f32 = 0.3;
/// Pitch limit, short of the poles where the view would flip.
const MAX_PITCH: f32 = 89.0;
/// Distance factor per scroll point.
const ZOOM_PER_POINT: f32 = 0.002;

/// See the module docs.
#[derive(Clone, Debug)]
pub struct CameraController {
    rig: CameraRig,
    pose: OrbitPose,
    prev_pose: OrbitPose,
    frame: u64,
    /// The camera follows the rig's orbit while playing.
    pub auto_rotate: bool,
    /// Time advances (animation and temporal jitter).
    pub playing: bool,
    step_requested: bool,
    cut: bool,
}

impl CameraController {
    /// A camera at frame 0 of `rig`.
    pub fn new(rig: CameraRig) -> Self {
        let pose = OrbitPose::at_frame(&rig, 0);
        Self {
            rig,
            pose,
            prev_pose: pose,
            frame: 0,
            auto_rotate: false,
            playing: true,
            step_requested: false,
            cut: true,
        }
    }

    /// Switches to another scene's rig: back to its first frame, with a cut.
    pub fn set_rig(&mut self, rig: CameraRig) {
        *self = Self {
            auto_rotate: self.auto_rotate,
            playing: self.playing,
            ..Self::new(rig)
        };
    }

    /// The current pose.
    pub fn pose(&self) -> OrbitPose {
        self.pose
    }

    /// The current frame number.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// Orbits by a mouse drag of `delta` points (right drags the scene to the right).
    pub fn orbit(&mut self, delta: Vec2) {
        self.pose.yaw_degrees =
            (self.pose.yaw_degrees - delta.x * ORBIT_DEGREES_PER_PIXEL).rem_euclid(360.0);
        self.pose.pitch_degrees = (self.pose.pitch_degrees + delta.y * ORBIT_DEGREES_PER_PIXEL)
            .clamp(-MAX_PITCH, MAX_PITCH);
    }

    /// Pans by a drag of `delta` points in a viewport `height` points tall: the point under the
    /// cursor stays under it (at the target's depth).
    pub fn pan(&mut self, delta: Vec2, height: f32) {
        let eye = self.pose.eye();
        let forward = (self.pose.target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let up = right.cross(forward);
        let world_per_point =
            2.0 * self.pose.distance * (self.pose.fov_y_degrees.to_radians() * 0.5).tan()
                / height.max(1.0);
        self.pose.target += (-right * delta.x + up * delta.y) * world_per_point;
    }

    /// Zooms by a scroll of `points` (positive moves closer).
    pub fn zoom(&mut self, points: f32) {
        let factor = (-points * ZOOM_PER_POINT).exp();
        let min = self.pose.near * 2.0;
        let max = (self.rig.distance * 20.0).max(min * 2.0);
        self.pose.distance = (self.pose.distance * factor).clamp(min, max);
    }

    /// Back to the rig's pose at the current frame (with a cut).
    pub fn reset(&mut self) {
        let frame_pose =
            OrbitPose::at_frame(&self.rig, if self.auto_rotate { self.frame } else { 0 });
        self.jump_to(frame_pose);
    }

    /// Moves to a pose (a bookmark) with a cut.
    pub fn jump_to(&mut self, pose: OrbitPose) {
        self.pose = pose;
        self.cut = true;
    }

    /// Asks for a history reset without moving (scene change, resize).
    pub fn cut(&mut self) {
        self.cut = true;
    }

    /// Advances one frame on the next [`CameraController::next_frame`] even while paused.
    pub fn step(&mut self) {
        self.step_requested = true;
    }

    /// Whether the view moves by itself (playing with auto-rotation).
    pub fn moving_by_itself(&self) -> bool {
        self.playing && self.auto_rotate
    }

    /// Whether time advances on the next frame.
    pub fn advancing(&self) -> bool {
        self.playing || self.step_requested
    }

    /// The camera of the next frame to render at `size`, and whether it is a cut. Advances the
    /// clock (and the auto-rotation) when playing or stepping.
    pub fn next_frame(&mut self, size: (u32, u32)) -> (FrameCamera, bool) {
        if self.advancing() {
            self.frame += 1;
            if self.auto_rotate {
                self.pose.yaw_degrees =
                    (self.pose.yaw_degrees + self.rig.orbit_degrees_per_frame).rem_euclid(360.0);
            }
            self.step_requested = false;
        }
        let cut = std::mem::take(&mut self.cut);
        if cut {
            self.prev_pose = self.pose;
        }
        let camera = FrameCamera {
            pose: self.pose,
            prev_pose: self.prev_pose,
            frame: self.frame,
            size,
        };
        self.prev_pose = self.pose;
        (camera, cut)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_rotation_follows_the_rig_and_pause_freezes_time() {
        let rig = CameraRig::default();
        let mut cam = CameraController::new(rig);
        cam.auto_rotate = true;
        let (first, cut) = cam.next_frame((64, 64));
        assert!(cut);
        assert_eq!(first.prev_pose, first.pose);
        let (second, cut) = cam.next_frame((64, 64));
        assert!(!cut);
        assert!(
            (second.pose.yaw_degrees - first.pose.yaw_degrees - rig.orbit_degrees_per_frame).abs()
                < 1e-4
        );
        assert_eq!(second.prev_pose, first.pose);
        cam.playing = false;
        let (third, _) = cam.next_frame((64, 64));
        assert_eq!(third.frame, second.frame);
        assert_eq!(third.pose, second.pose);
        cam.step();
        let (fourth, _) = cam.next_frame((64, 64));
        assert_eq!(fourth.frame, second.frame + 1);
        let (fifth, _) = cam.next_frame((64, 64));
        assert_eq!(fifth.frame, fourth.frame);
    }

    #[test]
    fn mouse_moves_and_reset_cuts() {
        let mut cam = CameraController::new(CameraRig::default());
        cam.playing = false;
        let (start, _) = cam.next_frame((64, 64));
        cam.orbit(Vec2::new(10.0, 1000.0));
        assert!(cam.pose().pitch_degrees <= MAX_PITCH);
        cam.zoom(100.0);
        assert!(cam.pose().distance < start.pose.distance);
        cam.pan(Vec2::new(5.0, 0.0), 100.0);
        assert_ne!(cam.pose().target, start.pose.target);
        let (moved, cut) = cam.next_frame((64, 64));
        assert!(!cut);
        assert_eq!(moved.prev_pose, start.pose);
        cam.reset();
        let (reset, cut) = cam.next_frame((64, 64));
        assert!(cut);
        assert_eq!(reset.pose, start.pose);
        assert_eq!(reset.prev_pose, reset.pose);
    }
}
