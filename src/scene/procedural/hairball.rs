//! The `hairball` scene: a dense ball of thin curved tubes, the stress test for fine
//! geometry (the thesis' Hairball, ~1M vertices there).
//!
//! Each curve is a smooth random walk inside a spherical shell (radii 0.55 to 1): its heading
//! turns by a low-pass-filtered random bend each step and is pulled back whenever it leaves
//! the shell, so the curves swirl around the ball instead of crossing it. The walk is swept
//! as a three-sided tube (smooth radial normals) whose radius is drawn per curve,
//! log-uniformly, so that at 1280x720 with the default camera the tubes are about 0.3 to 2
//! pixels wide, and tapers to a point at both ends. Curves are dealt round-robin onto five
//! meshes with muted blue-grey (and one copper) Blinn-Phong materials with a strong, tight
//! highlight (Ks 0.6, Ns 64), so that specular aliasing sparkles as the camera orbits.
//!
//! Every curve adds exactly `(POINTS - 1) * SIDES * 2` triangles, and the curve count is
//! `BASE_CURVES * density`, so the triangle count is linear in the density.

use glam::Vec3;

use super::SceneOptions;
use super::geometry::MeshBuilder;
use super::rng::Rng;
use crate::scene::{CameraRig, DirectionalLight, Material, Scene};

/// Sides of each tube's cross-section.
const SIDES: u32 = 3;
/// Points along each curve (segments + 1).
const POINTS: usize = 33;
/// Length of one walk step (world units; the ball has radius 1).
const STEP: f32 = 0.06;
/// Curves at density 1: 1563 * 32 * 3 * 2 = 300,096 triangles.
const BASE_CURVES: f64 = 1563.0;
/// Inner and outer radius of the shell the walks keep to.
const SHELL: (f32, f32) = (0.55, 0.95);
/// Tube radius range (world units): 0.3 to 1.7 px wide at the ball's centre at 720p.
const TUBE_RADIUS: (f32, f32) = (0.0006, 0.003);
/// Linear base colours of the five curve groups.
const PALETTE: [(&str, [f32; 3]); 5] = [
    ("slate", [0.16, 0.22, 0.33]),
    ("steel", [0.30, 0.35, 0.42]),
    ("mist", [0.50, 0.55, 0.62]),
    ("teal", [0.08, 0.21, 0.25]),
    ("copper", [0.48, 0.22, 0.10]),
];

/// Triangles one curve adds.
const TRIANGLES_PER_CURVE: usize = (POINTS - 1) * SIDES as usize * 2;
/// Vertices one curve adds (rings duplicate their seam vertex).
const VERTICES_PER_CURVE: usize = POINTS * (SIDES as usize + 1);

/// Number of curves for a density (already sanitised by [`SceneOptions::density`]).
fn curve_count(density: f32) -> usize {
    ((BASE_CURVES * f64::from(density)).round() as usize).max(1)
}

/// Fills `path` with one curve's walk.
fn walk(rng: &mut Rng, path: &mut Vec<Vec3>) {
    path.clear();
    // Uniform in the shell's volume.
    let (inner3, outer3) = (SHELL.0.powi(3), SHELL.1.powi(3));
    let mut p = rng.unit_vector() * rng.range(inner3, outer3).cbrt();
    // Start mostly tangential to the sphere, so the curve wraps around it.
    let radial = p.normalize();
    let mut heading = rng.unit_vector();
    heading = (heading - radial * heading.dot(radial) * 0.8)
        .normalize_or(radial.any_orthonormal_vector());
    let mut bend = Vec3::ZERO;
    for _ in 0..POINTS {
        path.push(p);
        // A slowly wandering bend: the heading turns about 6 degrees a step on average, in a
        // direction that persists for several steps, so curves sweep rather than zigzag.
        bend = bend * 0.88 + rng.unit_vector() * 0.12;
        let r = p.length();
        let radial = p / r.max(1e-6);
        let pull = if r > SHELL.1 {
            -radial * (r - SHELL.1) * 8.0
        } else if r < SHELL.0 {
            radial * (SHELL.0 - r) * 8.0
        } else {
            Vec3::ZERO
        };
        heading = (heading + bend * 0.5 + pull).normalize_or(heading);
        p += heading * STEP;
    }
}

/// Radius scale along a curve: closed points at both ends, full radius from the third point.
fn taper(i: usize) -> f32 {
    match i.min(POINTS - 1 - i) {
        0 => 0.0,
        1 => 0.6,
        _ => 1.0,
    }
}

/// The hairball scene (see the module docs).
pub fn hairball(options: &SceneOptions) -> Scene {
    let (density, warnings) = options.checked_density();
    let curves = curve_count(density);
    let groups = PALETTE.len();
    let per_group = curves.div_ceil(groups);
    let mut builders: Vec<MeshBuilder> = (0..groups)
        .map(|_| {
            MeshBuilder::with_capacity(
                per_group * VERTICES_PER_CURVE,
                per_group * TRIANGLES_PER_CURVE,
            )
        })
        .collect();
    let mut rng = Rng::new(options.seed, 0x4A1B);
    let mut path = Vec::with_capacity(POINTS);
    for curve in 0..curves {
        walk(&mut rng, &mut path);
        let (lo, hi) = (TUBE_RADIUS.0.ln(), TUBE_RADIUS.1.ln());
        let radius = rng.range(lo, hi).exp();
        builders[curve % groups].tube(&path, SIDES, false, 1.0, |i| radius * taper(i));
    }
    let materials = PALETTE
        .iter()
        .map(|(name, rgb)| Material {
            name: format!("hairball {name}"),
            base_color: Vec3::from(*rgb),
            specular: Vec3::splat(0.6),
            shininess: 64.0,
            double_sided: false,
            ..Material::default()
        })
        .collect();
    let meshes = builders
        .into_iter()
        .zip(PALETTE)
        .enumerate()
        .map(|(i, (b, (name, _)))| b.build(&format!("hairball {name}"), i, None))
        .collect();
    Scene {
        name: "hairball".to_owned(),
        meshes,
        materials,
        textures: Vec::new(),
        camera: CameraRig {
            target: Vec3::ZERO,
            // The ball (radius ~1) fills about 80% of the view height.
            distance: 3.1,
            yaw_degrees: 0.0,
            pitch_degrees: 15.0,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 20.0,
            orbit_degrees_per_frame: 0.5,
        },
        interior: false,
        light: DirectionalLight {
            direction: Vec3::new(0.45, -0.7, -0.55).normalize(),
            color: Vec3::splat(1.0),
            ambient: Vec3::splat(0.06),
        },
        clear_color: Vec3::new(0.012, 0.014, 0.02),
        views: Vec::new(),
        notes: Vec::new(),
        warnings,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn default_density_is_about_300k_triangles() {
        let scene = hairball(&SceneOptions::default());
        assert_scene_valid(&scene);
        let triangles = scene.triangle_count();
        assert!((280_000..=320_000).contains(&triangles), "{triangles}");
        assert_eq!(triangles, curve_count(1.0) * TRIANGLES_PER_CURVE);
    }

    #[test]
    fn density_seven_reaches_two_million() {
        let scene = hairball(&SceneOptions {
            density: 7.0,
            seed: 1,
        });
        assert!(
            scene.triangle_count() >= 2_000_000,
            "{}",
            scene.triangle_count()
        );
        assert!(scene.warnings.is_empty());
    }

    #[test]
    fn seed_changes_the_curves() {
        let options = SceneOptions {
            density: 0.05,
            seed: 1,
        };
        let a = hairball(&options);
        let b = hairball(&options);
        let c = hairball(&SceneOptions { seed: 2, ..options });
        assert_eq!(a.meshes[0].vertices, b.meshes[0].vertices);
        assert_ne!(a.meshes[0].vertices, c.meshes[0].vertices);
    }

    #[test]
    fn curves_stay_in_the_ball() {
        let scene = hairball(&SceneOptions {
            density: 0.2,
            seed: 9,
        });
        let (lo, hi) = scene.bounds().expect("vertices");
        assert!(
            lo.min_element() > -1.2 && hi.max_element() < 1.2,
            "{lo} {hi}"
        );
        assert!(
            lo.max_element() < -0.8 && hi.min_element() > 0.8,
            "{lo} {hi}"
        );
    }
}
