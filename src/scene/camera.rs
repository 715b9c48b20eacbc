//! The deterministic orbit camera and the matrices a frame is rendered with.
//!
//! A [`CameraRig`] (from the scene) plus a frame number fixes the camera completely: frame N
//! orbits `yaw + N * orbit_degrees_per_frame` about the vertical axis, so the same frame is
//! identical on every run and every machine. The viewer adds the user's orbit/pan/zoom on top
//! by editing an [`OrbitPose`] directly.
//!
//! Projection is reverse-Z with an infinite far plane (depth 1 at the near plane, 0 at
//! infinity, compare `Greater`), which keeps depth precise across the hairball's thin tubes.
//! Sub-pixel jitter and supersampling tiles are applied to the projection matrix only, so
//! motion vectors computed from the un-jittered matrices carry no jitter.

use glam::{Mat4, Vec2, Vec3};

/// The deterministic camera path of a scene: an orbit about the vertical axis through `target`.
///
/// In a render record every field may be left out and takes its [`Default`] value.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct CameraRig {
    /// Point the camera looks at and orbits around.
    pub target: Vec3,
    /// Distance from the target.
    pub distance: f32,
    /// Azimuth at frame 0, in degrees (0 looks down -Z).
    pub yaw_degrees: f32,
    /// Elevation in degrees (positive looks down on the target).
    pub pitch_degrees: f32,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Near clip distance.
    pub near: f32,
    /// Far clip distance.
    pub far: f32,
    /// Auto-rotation speed about the vertical axis, degrees per frame (0 for a still camera).
    pub orbit_degrees_per_frame: f32,
}

impl Default for CameraRig {
    fn default() -> Self {
        Self {
            target: Vec3::ZERO,
            distance: 5.0,
            yaw_degrees: 0.0,
            pitch_degrees: 15.0,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 100.0,
            orbit_degrees_per_frame: 0.5,
        }
    }
}

impl CameraRig {
    /// This rig with its frame-0 pose replaced by `pose` (the far plane and the orbit speed
    /// stay): motions then start where the camera is now.
    pub fn starting_at(&self, pose: OrbitPose) -> Self {
        Self {
            target: pose.target,
            distance: pose.distance,
            yaw_degrees: pose.yaw_degrees,
            pitch_degrees: pose.pitch_degrees,
            fov_y_degrees: pose.fov_y_degrees,
            near: pose.near,
            ..*self
        }
    }

    /// A rig whose frame 0 looks from `eye` at `look_at` (turning about `look_at` at
    /// `orbit_degrees_per_frame`); `None` when the two points coincide or are not finite.
    pub fn looking_at(
        eye: Vec3,
        look_at: Vec3,
        fov_y_degrees: f32,
        near: f32,
        orbit_degrees_per_frame: f32,
    ) -> Option<Self> {
        let (distance, yaw_degrees, pitch_degrees) = orbit_angles(eye, look_at)?;
        Some(Self {
            target: look_at,
            distance,
            yaw_degrees,
            pitch_degrees,
            fov_y_degrees,
            near,
            far: Self::default().far.max(distance * 100.0),
            orbit_degrees_per_frame,
        })
    }
}

/// Distance, yaw and pitch (degrees) of an orbit about `target` that puts the camera at
/// `eye`; pitch is kept within ±89.9° so the view never looks straight up or down (where the
/// orbit's up vector is undefined). `None` when the points coincide or are not finite.
pub fn orbit_angles(eye: Vec3, target: Vec3) -> Option<(f32, f32, f32)> {
    let offset = eye - target;
    let distance = offset.length();
    if !distance.is_finite() || distance <= f32::EPSILON * target.abs().max_element().max(1.0) {
        return None;
    }
    let dir = offset / distance;
    let pitch = dir
        .y
        .clamp(-1.0, 1.0)
        .asin()
        .to_degrees()
        .clamp(-89.9, 89.9);
    let yaw = dir.x.atan2(dir.z).to_degrees();
    Some((distance, yaw, pitch))
}

/// Where the camera is: an orbit about a target.
///
/// In a render record (`"camera": {...}`) every field may be left out and takes the value of
/// [`OrbitPose::default`] (frame 0 of the default [`CameraRig`]: target at the origin, 5 units
/// away, yaw 0, 15 degrees above, 45 degree vertical field of view, near plane 0.05).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct OrbitPose {
    /// Point looked at.
    pub target: Vec3,
    /// Distance from the target.
    pub distance: f32,
    /// Azimuth in degrees (0 looks down -Z).
    pub yaw_degrees: f32,
    /// Elevation in degrees (positive looks down).
    pub pitch_degrees: f32,
    /// Vertical field of view in degrees.
    pub fov_y_degrees: f32,
    /// Near plane distance.
    pub near: f32,
}

impl Default for OrbitPose {
    fn default() -> Self {
        Self::at_frame(&CameraRig::default(), 0)
    }
}

impl OrbitPose {
    /// A pose at `eye` looking at `target`; `None` when the points coincide or are not
    /// finite.
    pub fn looking_at(eye: Vec3, target: Vec3, fov_y_degrees: f32, near: f32) -> Option<Self> {
        let (distance, yaw_degrees, pitch_degrees) = orbit_angles(eye, target)?;
        Some(Self {
            target,
            distance,
            yaw_degrees,
            pitch_degrees,
            fov_y_degrees,
            near,
        })
    }

    /// The pose of `rig` at a frame of its auto-rotation.
    pub fn at_frame(rig: &CameraRig, frame: u64) -> Self {
        // f64 keeps the angle exact for long runs; the result is reduced before narrowing.
        let yaw = (f64::from(rig.yaw_degrees)
            + frame as f64 * f64::from(rig.orbit_degrees_per_frame))
        .rem_euclid(360.0);
        Self {
            target: rig.target,
            distance: rig.distance,
            yaw_degrees: yaw as f32,
            pitch_degrees: rig.pitch_degrees,
            fov_y_degrees: rig.fov_y_degrees,
            near: rig.near,
        }
    }

    /// Camera position in world space.
    pub fn eye(&self) -> Vec3 {
        let (yaw, pitch) = (
            self.yaw_degrees.to_radians(),
            self.pitch_degrees.to_radians(),
        );
        // Yaw 0 puts the camera on +Z looking down -Z; positive pitch lifts it above the target.
        let offset = Vec3::new(
            yaw.sin() * pitch.cos(),
            pitch.sin(),
            yaw.cos() * pitch.cos(),
        );
        self.target + offset * self.distance
    }

    /// World-to-view matrix.
    pub fn view(&self) -> Mat4 {
        glam::camera::rh::view::look_at_mat4(self.eye(), self.target, Vec3::Y)
    }

    /// Reverse-Z infinite perspective for an aspect ratio (width / height).
    pub fn projection(&self, aspect: f32) -> Mat4 {
        glam::camera::rh::proj::directx::perspective_infinite_reverse(
            self.fov_y_degrees.to_radians(),
            aspect,
            self.near,
        )
    }
}

/// A rectangle of the image in pixels, used to render part of a larger image (supersampling
/// tiles) with the projection of the whole.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PixelRect {
    /// Left edge.
    pub x: u32,
    /// Top edge.
    pub y: u32,
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
}

/// Shifts a projection by a sub-pixel offset (in pixels, +x right, +y down) for an image of
/// `size` pixels. The offset moves the image content, i.e. the sample position inside each
/// pixel moves by `-offset`.
pub fn jitter_projection(projection: Mat4, offset_px: Vec2, size: Vec2) -> Mat4 {
    let ndc = Vec2::new(2.0 * offset_px.x / size.x, -2.0 * offset_px.y / size.y);
    Mat4::from_translation(ndc.extend(0.0)) * projection
}

/// Restricts a projection for an image of `full` pixels to the sub-rectangle `tile`, so that
/// rendering into a `tile`-sized target produces exactly those pixels of the full image.
pub fn tile_projection(projection: Mat4, tile: PixelRect, full: (u32, u32)) -> Mat4 {
    let (fw, fh) = (full.0 as f32, full.1 as f32);
    let (tw, th) = (tile.width as f32, tile.height as f32);
    let scale = Vec3::new(fw / tw, fh / th, 1.0);
    // Centre of the tile in full-image NDC, moved to the origin before scaling.
    let center = Vec2::new(
        (tile.x as f32 + tw * 0.5) / fw * 2.0 - 1.0,
        1.0 - (tile.y as f32 + th * 0.5) / fh * 2.0,
    );
    Mat4::from_scale(scale) * Mat4::from_translation(-center.extend(0.0)) * projection
}

/// The matrices and parameters one scene render uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewParams {
    /// Matrix used to rasterise (jitter and tile applied).
    pub view_proj: Mat4,
    /// This frame's un-jittered matrix (motion vectors).
    pub unjittered_view_proj: Mat4,
    /// Previous frame's un-jittered matrix (motion vectors).
    pub prev_view_proj: Mat4,
    /// Camera position.
    pub eye: Vec3,
    /// Frame number, possibly fractional, for object animation.
    pub frame: f32,
    /// Previous frame number, for the previous object transforms.
    pub prev_frame: f32,
    /// Texture LOD bias (negative sharpens; TAA and jittered supersampling use it).
    pub mip_bias: f32,
}

/// The camera of one frame: this frame's pose, the previous frame's pose and the image size.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCamera {
    /// Pose of this frame.
    pub pose: OrbitPose,
    /// Pose of the previous frame (equal to `pose` on the first frame or after a cut).
    pub prev_pose: OrbitPose,
    /// Frame number (object animation time).
    pub frame: u64,
    /// Output image size in pixels (its aspect ratio shapes the projection).
    pub size: (u32, u32),
    /// The size the scene is rendered at when a technique runs below the output size (a render
    /// scale, see `aa::scaled`); `None` renders at `size`. The projection keeps the output's
    /// aspect ratio, so a render at any scale covers exactly the output's view and its pixels
    /// map onto the output's by one scale factor per axis.
    pub render_size: Option<(u32, u32)>,
}

impl FrameCamera {
    /// Frame `frame` of a rig's auto-rotation at an image size.
    pub fn from_rig(rig: &CameraRig, frame: u64, size: (u32, u32)) -> Self {
        Self {
            pose: OrbitPose::at_frame(rig, frame),
            prev_pose: OrbitPose::at_frame(rig, frame.saturating_sub(1)),
            frame,
            size,
            render_size: None,
        }
    }

    /// This camera seen at a render size (the output size itself leaves it unscaled).
    pub fn at_render_size(self, render_size: (u32, u32)) -> Self {
        Self {
            render_size: (render_size != self.size).then_some(render_size),
            ..self
        }
    }

    /// The size of the image this camera renders: the render size, else the output size.
    pub fn image_size(&self) -> (u32, u32) {
        self.render_size.unwrap_or(self.size)
    }

    /// The texture mip bias a render below the output size adds, log2(render / output) (the
    /// mean of both axes), so textures are sampled at the detail of the output's pixels; zero
    /// at the output size.
    pub fn scale_mip_bias(&self) -> f32 {
        match self.render_size {
            None => 0.0,
            Some((w, h)) => {
                0.5 * ((w as f32 / self.size.0.max(1) as f32).log2()
                    + (h as f32 / self.size.1.max(1) as f32).log2())
            }
        }
    }

    fn aspect(&self) -> f32 {
        self.size.0 as f32 / self.size.1.max(1) as f32
    }

    /// Un-jittered view-projection of this frame.
    pub fn view_proj(&self) -> Mat4 {
        self.pose.projection(self.aspect()) * self.pose.view()
    }

    /// Un-jittered view-projection of the previous frame.
    pub fn prev_view_proj(&self) -> Mat4 {
        self.prev_pose.projection(self.aspect()) * self.prev_pose.view()
    }

    /// View parameters for a render with a sub-pixel jitter (pixels of the rendered image,
    /// [`FrameCamera::image_size`]); `mip_bias` is added to the render scale's
    /// ([`FrameCamera::scale_mip_bias`]).
    pub fn params(&self, jitter_px: Vec2, mip_bias: f32) -> ViewParams {
        let (width, height) = self.image_size();
        let size = Vec2::new(width as f32, height as f32);
        let projection = jitter_projection(self.pose.projection(self.aspect()), jitter_px, size);
        ViewParams {
            view_proj: projection * self.pose.view(),
            unjittered_view_proj: self.view_proj(),
            prev_view_proj: self.prev_view_proj(),
            eye: self.pose.eye(),
            frame: self.frame as f32,
            prev_frame: self.frame.saturating_sub(1) as f32,
            mip_bias: mip_bias + self.scale_mip_bias(),
        }
    }

    /// View parameters for one tile of a supersampled image `factor` times larger than the
    /// rendered image, optionally jittered in pixels of the supersampled image.
    pub fn tile_params(
        &self,
        factor: u32,
        tile: PixelRect,
        jitter_px: Vec2,
        mip_bias: f32,
    ) -> ViewParams {
        let (width, height) = self.image_size();
        let full = (width * factor, height * factor);
        let full_size = Vec2::new(full.0 as f32, full.1 as f32);
        let projection =
            jitter_projection(self.pose.projection(self.aspect()), jitter_px, full_size);
        let projection = tile_projection(projection, tile, full);
        ViewParams {
            view_proj: projection * self.pose.view(),
            ..self.params(Vec2::ZERO, mip_bias)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn looking_at_reproduces_eye_and_target() {
        let eye = Vec3::new(3.0, 2.0, -1.0);
        let look_at = Vec3::new(-1.0, 0.5, 2.0);
        let rig = CameraRig::looking_at(eye, look_at, 60.0, 0.01, 0.0).expect("distinct points");
        let pose = OrbitPose::at_frame(&rig, 0);
        assert!((pose.eye() - eye).length() < 1e-4, "{}", pose.eye());
        assert_eq!(pose.target, look_at);
        assert!(CameraRig::looking_at(eye, eye, 60.0, 0.01, 0.0).is_none());
        assert!(CameraRig::looking_at(Vec3::NAN, eye, 60.0, 0.01, 0.0).is_none());
    }

    fn project(m: Mat4, p: Vec3, size: Vec2) -> Vec2 {
        let clip = m * p.extend(1.0);
        let ndc = clip.truncate() / clip.w;
        Vec2::new((ndc.x * 0.5 + 0.5) * size.x, (0.5 - ndc.y * 0.5) * size.y)
    }

    #[test]
    fn frame_determines_pose() {
        let rig = CameraRig::default();
        assert_eq!(OrbitPose::at_frame(&rig, 17), OrbitPose::at_frame(&rig, 17));
        let a = OrbitPose::at_frame(&rig, 0);
        let b = OrbitPose::at_frame(&rig, 1);
        assert!((b.yaw_degrees - a.yaw_degrees - rig.orbit_degrees_per_frame).abs() < 1e-4);
    }

    #[test]
    fn yaw_zero_looks_down_negative_z() {
        let pose = OrbitPose {
            pitch_degrees: 0.0,
            ..OrbitPose::at_frame(&CameraRig::default(), 0)
        };
        let dir = (pose.target - pose.eye()).normalize();
        assert!((dir - Vec3::NEG_Z).length() < 1e-5, "{dir}");
    }

    #[test]
    fn jitter_moves_content_by_pixels() {
        let cam = FrameCamera::from_rig(&CameraRig::default(), 3, (640, 360));
        let size = Vec2::new(640.0, 360.0);
        let p = Vec3::new(0.3, 0.2, 0.1);
        let base = project(cam.params(Vec2::ZERO, 0.0).view_proj, p, size);
        let moved = project(cam.params(Vec2::new(0.25, -0.5), 0.0).view_proj, p, size);
        assert!(
            (moved - base - Vec2::new(0.25, -0.5)).length() < 1e-3,
            "{base} {moved}"
        );
    }

    #[test]
    fn tile_projection_maps_tile_pixels() {
        let cam = FrameCamera::from_rig(&CameraRig::default(), 0, (100, 50));
        let factor = 4;
        let full = Vec2::new(400.0, 200.0);
        let tile = PixelRect {
            x: 128,
            y: 64,
            width: 128,
            height: 96,
        };
        let p = Vec3::new(0.1, 0.05, 0.0);
        let whole = project(cam.params(Vec2::ZERO, 0.0).view_proj, p, full);
        let tiled = project(
            cam.tile_params(factor, tile, Vec2::ZERO, 0.0).view_proj,
            p,
            Vec2::new(128.0, 96.0),
        );
        assert!(
            (whole - Vec2::new(128.0, 64.0) - tiled).length() < 1e-3,
            "{whole} {tiled}"
        );
    }

    #[test]
    fn reverse_z_puts_near_plane_at_one() {
        let pose = OrbitPose::at_frame(&CameraRig::default(), 0);
        let clip = pose.projection(1.0) * Vec3::new(0.0, 0.0, -pose.near).extend(1.0);
        assert!((clip.z / clip.w - 1.0).abs() < 1e-5);
    }
}
