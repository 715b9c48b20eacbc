//! The camera flags every command shares (`--camera-eye`, `--camera-look-at`, `--fov`,
//! `--camera-motion`): an explicit camera instead of the scene's own, turned into the orbit
//! rig the renderer uses and recorded in the render record.

use anyhow::{Context, bail};
use glam::Vec3;

use crate::scene::CameraRig;
use crate::spec::RenderSpec;

/// Whether the camera given on the command line moves with the frame number.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum CameraMotion {
    /// Frame N turns the camera N times the scene's orbit step about the look-at point.
    #[default]
    Orbit,
    /// Every frame is seen from the same place.
    Still,
}

/// A camera given on the command line; shared by `render`, `sheet` and `bench`.
#[derive(Clone, Debug, Default, clap::Args)]
pub struct CameraArgs {
    /// Camera position X,Y,Z in scene units (with --camera-look-at), e.g. to look around
    /// inside a building; replaces the scene's default view.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, requires = "camera_look_at", allow_hyphen_values = true)]
    pub camera_eye: Option<Vec3>,
    /// Point the camera looks at, X,Y,Z; frame N of the orbit turns about it.
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_vec3, requires = "camera_eye", allow_hyphen_values = true)]
    pub camera_look_at: Option<Vec3>,
    /// Vertical field of view in degrees (default: the scene's).
    #[arg(long, value_name = "DEG")]
    pub fov: Option<f32>,
    /// `orbit` (frame N turns about the look-at point) or `still` (no camera motion).
    #[arg(long, value_enum, default_value_t)]
    pub camera_motion: CameraMotion,
}

impl CameraArgs {
    /// The camera path these flags make of a scene's default one; `None` when no flag
    /// changes it.
    pub fn rig(&self, scene: &CameraRig) -> anyhow::Result<Option<CameraRig>> {
        if let Some(fov) = self.fov
            && !(fov.is_finite() && fov > 0.0 && fov < 180.0)
        {
            bail!("--fov {fov} is not a vertical field of view between 0 and 180 degrees");
        }
        let mut rig = match (self.camera_eye, self.camera_look_at) {
            (Some(eye), Some(look_at)) => CameraRig::looking_at(
                eye,
                look_at,
                scene.fov_y_degrees,
                scene.near,
                scene.orbit_degrees_per_frame,
            )
            .with_context(|| {
                format!("--camera-eye {eye} and --camera-look-at {look_at} must be different finite points")
            })?,
            _ if self.fov.is_none() && self.camera_motion == CameraMotion::Orbit => return Ok(None),
            _ => *scene,
        };
        if let Some(fov) = self.fov {
            rig.fov_y_degrees = fov;
        }
        if self.camera_motion == CameraMotion::Still {
            rig.orbit_degrees_per_frame = 0.0;
        }
        Ok(Some(rig))
    }

    /// Applies these flags to a loaded scene and records the result in its spec.
    pub fn apply(
        &self,
        spec: &mut RenderSpec,
        scene: &mut crate::scene::Scene,
    ) -> anyhow::Result<()> {
        if let Some(rig) = self.rig(&scene.camera)? {
            scene.camera = rig;
            spec.rig = Some(rig);
        }
        Ok(())
    }
}

/// Parses `X,Y,Z` (three finite numbers).
pub fn parse_vec3(text: &str) -> Result<Vec3, String> {
    let values: Vec<f32> = text
        .split(',')
        .map(|v| v.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|e| format!("expected X,Y,Z, e.g. 1.5,2,-3 ({e})"))?;
    match values.as_slice() {
        [x, y, z] if values.iter().all(|v| v.is_finite()) => Ok(Vec3::new(*x, *y, *z)),
        _ => Err(format!("expected three finite numbers X,Y,Z, got `{text}`")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vectors_parse_and_reject_garbage() {
        assert_eq!(parse_vec3("1,-2.5, 3"), Ok(Vec3::new(1.0, -2.5, 3.0)));
        assert!(parse_vec3("1,2").is_err());
        assert!(parse_vec3("1,2,nan").is_err());
        assert!(parse_vec3("a,b,c").is_err());
    }

    #[test]
    fn camera_flags_make_a_rig() {
        let scene = CameraRig::default();
        assert_eq!(CameraArgs::default().rig(&scene).ok(), Some(None));
        let args = CameraArgs {
            camera_eye: Some(Vec3::new(0.0, 1.0, 4.0)),
            camera_look_at: Some(Vec3::new(0.0, 1.0, 0.0)),
            fov: Some(70.0),
            camera_motion: CameraMotion::Still,
        };
        let rig = args.rig(&scene).ok().flatten().expect("a rig");
        assert_eq!(rig.fov_y_degrees, 70.0);
        assert_eq!(rig.orbit_degrees_per_frame, 0.0);
        assert!((rig.distance - 4.0).abs() < 1e-5);
        assert!(rig.pitch_degrees.abs() < 1e-4 && rig.yaw_degrees.abs() < 1e-4);
        let same = CameraArgs {
            camera_look_at: args.camera_eye,
            ..args.clone()
        };
        assert!(same.rig(&scene).is_err());
        let bad_fov = CameraArgs {
            fov: Some(180.0),
            ..CameraArgs::default()
        };
        assert!(bad_fov.rig(&scene).is_err());
    }
}
