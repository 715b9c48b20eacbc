//! Camera motions for clips: deterministic camera paths that reveal temporal aliasing.
//!
//! A [`Motion`] plus a scene's [`CameraRig`], the image size and a frame number fixes the
//! camera completely, so the same clip is the same on every run. Every motion starts from the
//! rig's frame-0 pose; frame numbers advance by one per frame in every motion (so the jitter
//! sequences of temporal techniques and object animation run as usual):
//!
//! - `orbit`: the rig's own path (frame N turns `N * orbit_degrees_per_frame` about the
//!   target), exactly what `render --frame N` shows.
//! - `pan`: the camera stays where it is and turns about the vertical axis through its eye by
//!   `speed_px` pixels per frame at the image centre: the whole image slides sideways at a slow,
//!   sub-pixel rate, which makes stair steps crawl and sub-pixel geometry shimmer.
//! - `dolly`: the camera moves straight toward the target; a point at the target's depth half
//!   an image height above the centre moves `speed_px` pixels per frame (the distance shrinks
//!   geometrically, never below four near-plane distances).
//! - `still`: the camera never moves; only the jitter of temporal techniques (and animated
//!   objects) change between frames.

use super::CameraRig;
use super::camera::{FrameCamera, OrbitPose};

/// Default speed of `pan` and `dolly`, pixels per frame: slow enough that every technique's
/// change is mostly its own, not the scene's.
pub const DEFAULT_SPEED_PX: f32 = 0.25;

/// A deterministic camera motion (see the module docs).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Motion {
    /// The scene's orbit about its target (the camera path of `render --frame N`).
    #[default]
    Orbit,
    /// The camera turns in place: the image slides sideways by the speed per frame.
    Pan,
    /// The camera moves slowly toward its target.
    Dolly,
    /// The camera is fixed; only temporal techniques' jitter moves.
    Still,
}

impl Motion {
    /// Every motion, in documentation order.
    pub const ALL: [Motion; 4] = [Motion::Orbit, Motion::Pan, Motion::Dolly, Motion::Still];

    /// The name on the command line and in records.
    pub fn name(self) -> &'static str {
        match self {
            Motion::Orbit => "orbit",
            Motion::Pan => "pan",
            Motion::Dolly => "dolly",
            Motion::Still => "still",
        }
    }

    /// Whether `speed_px` affects this motion.
    pub fn uses_speed(self) -> bool {
        matches!(self, Motion::Pan | Motion::Dolly)
    }

    /// The pose of frame `frame`.
    pub fn pose(self, rig: &CameraRig, size: (u32, u32), speed_px: f32, frame: u64) -> OrbitPose {
        let base = OrbitPose::at_frame(rig, 0);
        // Pixels per radian of view angle at the image centre (square pixels).
        let pixels_per_radian =
            size.1.max(1) as f32 / (2.0 * (base.fov_y_degrees.to_radians() * 0.5).tan());
        match self {
            Motion::Orbit => OrbitPose::at_frame(rig, frame),
            Motion::Still => base,
            Motion::Pan => {
                // A turn by d about the vertical axis moves the centre ray by d * cos(pitch)
                // radians of view angle.
                let cos_pitch = base.pitch_degrees.to_radians().cos().abs().max(1e-3);
                let step = speed_px / (pixels_per_radian * cos_pitch);
                let yaw = (f64::from(base.yaw_degrees)
                    + frame as f64 * f64::from(step.to_degrees()))
                .rem_euclid(360.0) as f32;
                let eye = base.eye();
                let turned = OrbitPose {
                    yaw_degrees: yaw,
                    target: glam::Vec3::ZERO,
                    ..base
                };
                // Same eye, looking in the turned direction.
                OrbitPose {
                    target: eye - turned.eye(),
                    ..turned
                }
            }
            Motion::Dolly => {
                let half = size.1.max(1) as f64 * 0.5;
                let ratio = half / (half + f64::from(speed_px.max(0.0)));
                let exponent = i32::try_from(frame).unwrap_or(i32::MAX);
                let distance = f64::from(base.distance) * ratio.powi(exponent);
                OrbitPose {
                    distance: (distance as f32).max(base.near * 4.0).min(base.distance),
                    ..base
                }
            }
        }
    }

    /// The camera of frame `frame` (the previous pose is frame - 1's, or the same at 0).
    pub fn camera(
        self,
        rig: &CameraRig,
        size: (u32, u32),
        speed_px: f32,
        frame: u64,
    ) -> FrameCamera {
        FrameCamera {
            pose: self.pose(rig, size, speed_px, frame),
            prev_pose: self.pose(rig, size, speed_px, frame.saturating_sub(1)),
            frame,
            size,
            render_size: None,
        }
    }
}

/// The pose a fraction `t` (0..=1) along the path through `poses`, each leg taking the same
/// time: target, distance, pitch, field of view and near plane interpolate linearly, yaw along
/// the shorter way round. `None` with fewer than two poses.
pub fn along_path(poses: &[OrbitPose], t: f32) -> Option<OrbitPose> {
    if poses.len() < 2 {
        return None;
    }
    let legs = (poses.len() - 1) as f32;
    let at = t.clamp(0.0, 1.0) * legs;
    let leg = (at.floor() as usize).min(poses.len() - 2);
    let (a, b) = (poses[leg], poses[leg + 1]);
    let f = at - leg as f32;
    let mix = |x: f32, y: f32| x + (y - x) * f;
    let turn = (b.yaw_degrees - a.yaw_degrees + 180.0).rem_euclid(360.0) - 180.0;
    Some(OrbitPose {
        target: a.target.lerp(b.target, f),
        distance: mix(a.distance, b.distance),
        yaw_degrees: (a.yaw_degrees + turn * f).rem_euclid(360.0),
        pitch_degrees: mix(a.pitch_degrees, b.pitch_degrees),
        fov_y_degrees: mix(a.fov_y_degrees, b.fov_y_degrees),
        near: mix(a.near, b.near),
    })
}

impl std::fmt::Display for Motion {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};

    fn project(camera: &FrameCamera, p: Vec3) -> Vec2 {
        let size = Vec2::new(camera.size.0 as f32, camera.size.1 as f32);
        let clip = camera.view_proj() * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        Vec2::new((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y)
    }

    const SIZE: (u32, u32) = (320, 180);

    #[test]
    fn paths_pass_through_every_pose_at_an_even_pace_and_turn_the_short_way() {
        let pose = |yaw: f32, distance: f32| OrbitPose {
            yaw_degrees: yaw,
            distance,
            ..OrbitPose::default()
        };
        let poses = [pose(350.0, 2.0), pose(10.0, 4.0), pose(10.0, 8.0)];
        assert!(along_path(&poses[..1], 0.5).is_none());
        assert_eq!(along_path(&poses, 0.0), Some(poses[0]));
        assert_eq!(along_path(&poses, 0.5), Some(poses[1]));
        assert_eq!(along_path(&poses, 1.0), Some(poses[2]));
        let quarter = along_path(&poses, 0.25).unwrap();
        assert!(quarter.yaw_degrees.abs() < 1e-3 || (quarter.yaw_degrees - 360.0).abs() < 1e-3);
        assert!((quarter.distance - 3.0).abs() < 1e-6);
    }

    #[test]
    fn orbit_is_the_rig_path() {
        let rig = CameraRig::default();
        for frame in [0, 1, 17] {
            assert_eq!(
                Motion::Orbit.camera(&rig, SIZE, 0.25, frame),
                FrameCamera::from_rig(&rig, frame, SIZE)
            );
        }
    }

    #[test]
    fn still_never_moves_but_frames_advance() {
        let rig = CameraRig::default();
        let a = Motion::Still.camera(&rig, SIZE, 0.25, 0);
        let b = Motion::Still.camera(&rig, SIZE, 0.25, 9);
        assert_eq!(a.pose, b.pose);
        assert_eq!(b.pose, b.prev_pose);
        assert_eq!(b.frame, 9);
    }

    #[test]
    fn pan_keeps_the_eye_and_slides_the_centre_by_the_speed() {
        let rig = CameraRig::default();
        let speed = 0.5;
        let c0 = Motion::Pan.camera(&rig, SIZE, speed, 0);
        assert_eq!(c0.pose, OrbitPose::at_frame(&rig, 0));
        let c4 = Motion::Pan.camera(&rig, SIZE, speed, 4);
        assert!((c4.pose.eye() - c0.pose.eye()).length() < 1e-4);
        // The point at the centre of frame 0 moves 4 * speed pixels sideways by frame 4.
        let centre = c0.pose.target;
        let before = project(&c0, centre);
        let after = project(&c4, centre);
        assert!(
            (before - Vec2::new(160.0, 90.0)).length() < 1e-2,
            "{before}"
        );
        let moved = after - before;
        assert!((moved.x.abs() - 4.0 * speed).abs() < 0.02, "{moved}");
        assert!(moved.y.abs() < 0.05, "{moved}");
        assert_eq!(c4.prev_pose, Motion::Pan.pose(&rig, SIZE, speed, 3));
    }

    #[test]
    fn dolly_moves_toward_the_target_by_the_speed() {
        let rig = CameraRig::default();
        let speed = 0.25;
        let c0 = Motion::Dolly.camera(&rig, SIZE, speed, 0);
        let c1 = Motion::Dolly.camera(&rig, SIZE, speed, 1);
        assert!(c1.pose.distance < c0.pose.distance);
        assert_eq!(c1.pose.target, c0.pose.target);
        // A point at the target's depth, half an image height above the centre, moves by the
        // speed (to first order).
        let half_angle = (rig.fov_y_degrees.to_radians() * 0.5).tan();
        let up = c0.pose.view().inverse().transform_vector3(Vec3::Y);
        let p = c0.pose.target + up * c0.pose.distance * half_angle * 0.999;
        let moved = project(&c1, p) - project(&c0, p);
        assert!((moved.length() - speed).abs() < 0.01, "{moved}");
        // Never through the target.
        let far = Motion::Dolly.camera(&rig, SIZE, speed, 1_000_000);
        assert!(far.pose.distance >= rig.near * 4.0 - 1e-6);
    }

    #[test]
    fn names_round_trip_through_serde() {
        for motion in Motion::ALL {
            let text = serde_json::to_string(&motion).unwrap();
            assert_eq!(text, format!("\"{}\"", motion.name()));
            assert_eq!(serde_json::from_str::<Motion>(&text).unwrap(), motion);
        }
    }
}
