//! The viewer's camera: the scene's orbit rig as a starting point, mouse orbit, pan and zoom on
//! top, the thesis' auto-rotation (the rig's degrees per frame), pause and single-frame steps,
//! and cut detection so temporal techniques drop their history when the view jumps.
//!
//! Two modes share one [`OrbitPose`], so bookmarks, exports and render records work in both:
//! *orbit* turns the eye about the target; *fly* (for interiors) keeps the eye where it is and
//! turns the view about it (mouse look), and WASD/QE move eye and target together, at a speed
//! scaled to the scene (a quarter of the framing distance per second, four times that with
//! Shift). A loaded scene opens in the mode its default view suits: fly for an interior
//! (whose default view is an inside one, `scene::interior`), orbit otherwise.
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
/// Fly speed in framing distances (the rig's distance) per second.
const FLY_SPEED: f32 = 0.25;
/// Fly speed factor with Shift held.
const FLY_FAST: f32 = 4.0;

/// How mouse and keys move the camera.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CameraMode {
    /// Dragging orbits about the target.
    #[default]
    Orbit,
    /// First person: dragging looks around from the eye; WASD/QE move.
    Fly,
}

/// Fly movement asked for this frame, each axis -1, 0 or 1.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FlyInput {
    /// D minus A.
    pub right: f32,
    /// E minus Q (world up).
    pub up: f32,
    /// W minus S.
    pub forward: f32,
    /// Shift held.
    pub fast: bool,
}

impl FlyInput {
    /// Whether any movement is asked for.
    pub fn moving(&self) -> bool {
        self.right != 0.0 || self.up != 0.0 || self.forward != 0.0
    }
}

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
    /// Orbit or fly.
    pub mode: CameraMode,
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
            mode: CameraMode::Orbit,
        }
    }

    /// Switches to another scene's rig: back to its first frame, with a cut.
    pub fn set_rig(&mut self, rig: CameraRig) {
        *self = Self {
            auto_rotate: self.auto_rotate,
            playing: self.playing,
            mode: self.mode,
            ..Self::new(rig)
        };
    }

    /// The scene's camera rig.
    pub fn rig(&self) -> &CameraRig {
        &self.rig
    }

    /// The current pose.
    pub fn pose(&self) -> OrbitPose {
        self.pose
    }

    /// The current frame number.
    pub fn frame(&self) -> u64 {
        self.frame
    }

    /// A primary-button drag of `delta` points: orbits in orbit mode (right drags the scene
    /// to the right), looks around in fly mode (right turns the view right).
    pub fn orbit(&mut self, delta: Vec2) {
        let eye = self.pose.eye();
        self.pose.yaw_degrees =
            (self.pose.yaw_degrees - delta.x * ORBIT_DEGREES_PER_PIXEL).rem_euclid(360.0);
        self.pose.pitch_degrees = (self.pose.pitch_degrees + delta.y * ORBIT_DEGREES_PER_PIXEL)
            .clamp(-MAX_PITCH, MAX_PITCH);
        if self.mode == CameraMode::Fly {
            // The same angles about the eye instead of the target: the eye stays put.
            self.pose.target += eye - self.pose.eye();
        }
    }

    /// Moves the eye (and the target with it) in fly mode for `seconds` of `input`; the
    /// horizontal axes follow the view direction, up is world +Y.
    pub fn fly(&mut self, input: FlyInput, seconds: f32) {
        if self.mode != CameraMode::Fly || !input.moving() {
            return;
        }
        let forward = (self.pose.target - self.pose.eye()).normalize_or_zero();
        let right = forward.cross(Vec3::Y).normalize_or_zero();
        let speed = self.rig.distance
            * FLY_SPEED
            * if input.fast { FLY_FAST } else { 1.0 }
            * seconds.clamp(0.0, 0.25);
        let step = (forward * input.forward + right * input.right + Vec3::Y * input.up) * speed;
        if step.is_finite() {
            self.pose.target += step;
        }
    }

    /// Switches between orbit and fly. Entering fly mode puts the point the view turns about
    /// close in front of the eye, so looking around feels like turning one's head.
    pub fn toggle_mode(&mut self) {
        self.mode = match self.mode {
            CameraMode::Orbit => {
                let eye = self.pose.eye();
                let forward = (self.pose.target - eye).normalize_or_zero();
                let distance = (self.rig.distance * 0.05).max(self.pose.near * 4.0);
                self.pose.target = eye + forward * distance;
                self.pose.distance = distance;
                CameraMode::Fly
            }
            CameraMode::Fly => CameraMode::Orbit,
        };
    }

    /// Switches to `mode` as [`CameraController::toggle_mode`] does, unless already in it.
    pub fn set_mode(&mut self, mode: CameraMode) {
        if self.mode != mode {
            self.toggle_mode();
        }
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
            render_size: None,
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
    fn fly_mode_looks_about_the_eye_and_moves_it() {
        let mut cam = CameraController::new(CameraRig::default());
        let start_eye = cam.pose().eye();
        cam.toggle_mode();
        assert_eq!(cam.mode, CameraMode::Fly);
        assert!((cam.pose().eye() - start_eye).length() < 1e-4);
        cam.orbit(Vec2::new(40.0, -20.0));
        assert!(
            (cam.pose().eye() - start_eye).length() < 1e-4,
            "looking moved the eye"
        );
        let forward = (cam.pose().target - cam.pose().eye()).normalize();
        let input = FlyInput {
            forward: 1.0,
            ..FlyInput::default()
        };
        cam.fly(input, 0.1);
        let moved = cam.pose().eye() - start_eye;
        let expected = CameraRig::default().distance * FLY_SPEED * 0.1;
        assert!((moved - forward * expected).length() < 1e-4, "{moved}");
        let fast = FlyInput {
            fast: true,
            ..input
        };
        let before = cam.pose().eye();
        cam.fly(fast, 0.1);
        assert!(((cam.pose().eye() - before).length() - expected * FLY_FAST).abs() < 1e-4);
        cam.toggle_mode();
        let eye = cam.pose().eye();
        cam.fly(input, 0.1);
        assert_eq!(cam.pose().eye(), eye, "orbit mode ignores fly keys");
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
