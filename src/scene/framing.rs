//! The opening camera of a loaded model: an orbit about the centre of its bounding box,
//! slightly from above, at a distance at which no orbit angle clips the model. The OBJ and
//! glTF loaders share it.

use glam::Vec3;

use super::{CameraRig, Scene};

/// Vertical field of view of OBJ scenes, in degrees.
const FOV_Y_DEGREES: f32 = 45.0;
/// How much larger than the bounding sphere the framed view is.
const FRAME_MARGIN: f32 = 1.1;
/// Camera elevation above the target, in degrees.
const PITCH_DEGREES: f32 = 15.0;
/// Auto-rotation speed, in degrees per frame.
const ORBIT_DEGREES_PER_FRAME: f32 = 0.5;

/// The sphere about the centre of the scene's bounding box through its farthest vertex
/// (tighter than the box's own bounding sphere), or `None` without vertices.
pub fn bounding_sphere(scene: &Scene) -> Option<(Vec3, f32)> {
    let (lo, hi) = scene.bounds()?;
    let center = (lo + hi) * 0.5;
    let radius = scene
        .meshes
        .iter()
        .flat_map(|m| &m.vertices)
        .map(|v| Vec3::from(v.position).distance(center))
        .fold(0.0, f32::max);
    Some((center, radius))
}

/// A camera rig orbiting `target` that keeps a sphere of `radius` about it in view.
pub fn framed_camera(target: Vec3, radius: f32) -> CameraRig {
    // A model of zero size still needs a camera that is not inside it.
    let radius = radius.max(1e-6);
    let distance = radius * FRAME_MARGIN / (FOV_Y_DEGREES.to_radians() * 0.5).sin();
    CameraRig {
        target,
        distance,
        yaw_degrees: 0.0,
        pitch_degrees: PITCH_DEGREES,
        fov_y_degrees: FOV_Y_DEGREES,
        near: radius * 0.01,
        far: distance + radius * 100.0,
        orbit_degrees_per_frame: ORBIT_DEGREES_PER_FRAME,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn framing_fits_the_bounding_sphere() {
        let target = Vec3::new(1.0, 1.0, 0.0);
        let radius = 2.5;
        let rig = framed_camera(target, radius);
        assert_eq!(rig.target, target);
        let half_fov = (rig.fov_y_degrees.to_radians() * 0.5).sin();
        assert!(rig.distance * half_fov > radius);
        assert!(rig.distance * half_fov < radius * 1.2);
        assert!(rig.near > 0.0 && rig.near < rig.distance - radius);
        assert!(rig.far > rig.distance + radius);

        let point = framed_camera(Vec3::ONE, 0.0);
        assert!(point.distance.is_finite() && point.distance > 0.0 && point.near > 0.0);
    }
}
