//! The `sparkle` scene: specular aliasing, the flicker no geometric antialiasing removes.
//!
//! Shiny curved surfaces under one low sun, each with procedural normal detail finer than a
//! pixel at 720p ([`NormalDetail`], evaluated by the scene shader): a ring of metallic-flake
//! spheres (one random tilt per cubic flake cell, cells about 0.7 px across at the ring),
//! a hammered-chrome sphere in the middle and tori between the spheres (smooth ripples of
//! about 1.5 px period) on a wet, flaked floor. Every exponent is high (Blinn-Phong 900 to
//! 2500, lobes of one to two degrees), so each flake or ripple that happens to face the half
//! vector is a sub-pixel glint and its neighbours are dark: as the camera moves, the glints
//! jump from pixel to pixel. Edges are few and large, so MSAA, FXAA and SMAA have little to
//! do here, while the 64-sample reference averages the glints into a soft sheen; geometric
//! specular antialiasing (`--specular-aa`) widens each lobe by the normal's change across the
//! pixel instead.
//!
//! Sizes, positions and tori orientations are drawn from [`SceneOptions::seed`]; the density
//! is ignored (the scene is small: about 100k triangles). The sun is low behind the ring, a little
//! to the left, so its reflection in the floor glitters in the lower half of the view and
//! the spheres' highlights sit near their tops; the camera orbits slowly (0.5 degrees a
//! frame), as the hairball's does.

use glam::Vec3;

use super::SceneOptions;
use super::geometry::MeshBuilder;
use super::rng::Rng;
use crate::scene::{CameraRig, DirectionalLight, Material, NormalDetail, Scene};

/// Spheres on the ring around the middle.
const RING_SPHERES: usize = 6;
/// Radius of the ring the spheres stand on (world units).
const RING_RADIUS: f32 = 1.5;
/// Radius range of the ring's spheres.
const SPHERE_RADIUS: (f32, f32) = (0.3, 0.5);
/// Radius of the middle sphere.
const MIDDLE_RADIUS: f32 = 0.7;
/// Tube (minor) and ring (major) radius of the tori.
const TORUS_RADII: (f32, f32) = (0.1, 0.32);
/// Half the side of the square floor.
const FLOOR_HALF: f32 = 8.0;
/// Segments around (and half as many along) every sphere; around every torus.
const SEGMENTS: u32 = 96;
/// Sides of every torus's tube.
const TORUS_SIDES: u32 = 32;

/// The scene's three materials: flake paint, hammered chrome, wet floor.
fn materials() -> Vec<Material> {
    let shiny =
        |name: &str, base: Vec3, specular: f32, shininess: f32, detail: NormalDetail| Material {
            name: format!("sparkle {name}"),
            base_color: base,
            specular: Vec3::splat(specular),
            shininess,
            double_sided: false,
            normal_detail: Some(detail),
            ..Material::default()
        };
    vec![
        shiny(
            "flake paint",
            Vec3::new(0.03, 0.06, 0.2),
            0.9,
            1500.0,
            NormalDetail {
                frequency: 250.0,
                ripple: 0.0,
                flakes: 0.35,
            },
        ),
        shiny(
            "hammered chrome",
            Vec3::splat(0.05),
            1.0,
            900.0,
            NormalDetail {
                frequency: 110.0,
                ripple: 0.4,
                flakes: 0.0,
            },
        ),
        shiny(
            "wet floor",
            Vec3::new(0.025, 0.022, 0.02),
            0.7,
            2500.0,
            NormalDetail {
                frequency: 160.0,
                ripple: 0.15,
                flakes: 0.2,
            },
        ),
    ]
}

/// A UV sphere standing on the floor at `foot`.
fn sphere(builder: &mut MeshBuilder, foot: Vec3, radius: f32) {
    builder.uv_sphere(foot + Vec3::Y * radius, radius, SEGMENTS);
}

/// A torus about `center` whose ring lies in the plane with unit normal `axis`.
fn torus(builder: &mut MeshBuilder, center: Vec3, axis: Vec3) {
    let (minor, major) = TORUS_RADII;
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let path: Vec<Vec3> = (0..SEGMENTS)
        .map(|k| {
            let (sin, cos) = (k as f32 / SEGMENTS as f32 * std::f32::consts::TAU).sin_cos();
            center + (u * cos + v * sin) * major
        })
        .collect();
    builder.tube(&path, TORUS_SIDES, true, 1.0, |_| minor);
}

/// The sparkle scene (see the module docs).
pub fn sparkle(options: &SceneOptions) -> Scene {
    let mut rng = Rng::new(options.seed, 0x5BA4);
    let mut flakes = MeshBuilder::default();
    let mut chrome = MeshBuilder::default();
    let mut floor = MeshBuilder::default();
    sphere(&mut chrome, Vec3::ZERO, MIDDLE_RADIUS);
    for k in 0..RING_SPHERES {
        let angle = (k as f32 + rng.range(-0.15, 0.15)) / RING_SPHERES as f32;
        let (sin, cos) = (angle * std::f32::consts::TAU).sin_cos();
        let radius = rng.range(SPHERE_RADIUS.0, SPHERE_RADIUS.1);
        sphere(&mut flakes, Vec3::new(sin, 0.0, cos) * RING_RADIUS, radius);
        // A torus between this sphere and the next, standing on its rim at a random lean.
        let (sin, cos) = ((angle + 0.5 / RING_SPHERES as f32) * std::f32::consts::TAU).sin_cos();
        let lean = rng.range(-0.6, 0.6);
        let facing = Vec3::new(cos, lean, -sin).normalize();
        let center =
            Vec3::new(sin, 0.0, cos) * RING_RADIUS + Vec3::Y * (TORUS_RADII.0 + TORUS_RADII.1);
        torus(&mut chrome, center, facing);
    }
    let corner = Vec3::new(-FLOOR_HALF, 0.0, FLOOR_HALF);
    floor.plane(
        corner,
        Vec3::X * 2.0 * FLOOR_HALF,
        Vec3::NEG_Z * 2.0 * FLOOR_HALF,
        1.0,
    );
    Scene {
        name: "sparkle".to_owned(),
        meshes: vec![
            flakes.build("sparkle flake spheres", 0, None),
            chrome.build("sparkle chrome", 1, None),
            floor.build("sparkle floor", 2, None),
        ],
        materials: materials(),
        textures: Vec::new(),
        camera: CameraRig {
            target: Vec3::new(0.0, 0.35, 0.0),
            distance: 5.2,
            yaw_degrees: 0.0,
            pitch_degrees: 18.0,
            fov_y_degrees: 42.0,
            near: 0.05,
            far: 40.0,
            orbit_degrees_per_frame: 0.5,
        },
        interior: false,
        light: DirectionalLight {
            direction: Vec3::new(0.3, -0.45, 1.0).normalize(),
            color: Vec3::splat(1.0),
            ambient: Vec3::splat(0.08),
        },
        clear_color: Vec3::new(0.01, 0.012, 0.02),
        views: Vec::new(),
        warnings: Vec::new(),
        notes: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn every_surface_is_shiny_and_normal_detailed() {
        let scene = sparkle(&SceneOptions::default());
        assert_scene_valid(&scene);
        for mesh in &scene.meshes {
            let material = &scene.materials[mesh.material];
            let detail = material.normal_detail.expect("normal detail");
            assert!(detail.ripple > 0.0 || detail.flakes > 0.0, "{}", mesh.name);
            assert!(material.shininess >= 500.0, "{}", material.name);
            assert!(
                mesh.spin.is_none(),
                "world-space detail needs static meshes"
            );
        }
        let triangles = scene.triangle_count();
        assert!((50_000..=150_000).contains(&triangles), "{triangles}");
    }

    #[test]
    fn seed_moves_the_ring_and_nothing_else_changes() {
        let options = SceneOptions::default();
        let (a, b) = (sparkle(&options), sparkle(&options));
        let c = sparkle(&SceneOptions { seed: 2, ..options });
        for ((x, y), z) in a.meshes.iter().zip(&b.meshes).zip(&c.meshes) {
            assert_eq!(x.vertices, y.vertices, "{}", x.name);
            assert_eq!(x.indices, y.indices, "{}", x.name);
            assert_eq!(x.indices.len(), z.indices.len(), "{}", x.name);
        }
        assert_ne!(a.meshes[0].vertices, c.meshes[0].vertices);
        // The floor does not depend on the seed.
        assert_eq!(a.meshes[2].vertices, c.meshes[2].vertices);
    }

    #[test]
    fn sphere_normals_point_away_from_the_centre() {
        let mut builder = MeshBuilder::default();
        sphere(&mut builder, Vec3::new(1.0, 0.0, -2.0), 0.5);
        let center = Vec3::new(1.0, 0.5, -2.0);
        for v in &builder.vertices {
            let outward = (Vec3::from(v.position) - center) / 0.5;
            assert!(outward.distance(Vec3::from(v.normal)) < 1e-4, "{v:?}");
        }
        // Counter-clockwise seen from outside: every face normal points outwards.
        for t in builder.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(builder.vertices[t[k] as usize].position));
            let face = (b - a).cross(c - a);
            assert!(face.dot((a + b + c) / 3.0 - center) >= 0.0);
        }
    }
}
