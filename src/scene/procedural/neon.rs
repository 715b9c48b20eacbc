//! The `neon` scene: an HDR stress case, thin edges far brighter than the display's white.
//!
//! A dark alley wall at night with neon signs on it: tubes a pixel or two thick at 720p
//! (straight strokes at shallow angles, zig-zags, rings and frames) whose emitted radiance is 3
//! to 12 times the display's white, a string of small bulbs brighter still (about 40), a fence
//! of thin dark bars between the camera and the signs, and a neon ring spinning in front of
//! them (object motion). Everything else is dark and matte under a dim moonlight. This is the
//! case where the tonemapping order decides the antialiasing: averaged as radiance, an edge
//! pixel a quarter covered by a tube of radiance 16 holds 4, which every tonemapper shows as
//! nearly white, so the edge is as wide and as stair-stepped as without antialiasing; averaged
//! after the tonemapper (or with Karis' 1 / (1 + luma) weights) it is a quarter grey.
//!
//! Radiance lives in [`Material::emissive`], so the scene is HDR ([`Scene::is_hdr`]) and is
//! shown through a tonemapper by default (`graph::hdr`). Rendered on the LDR path, every tube
//! clamps to its colour at full brightness. Positions, shapes and colours are drawn from
//! [`SceneOptions::seed`]; the density is ignored (about 40k triangles). The camera orbits
//! slowly (0.4 degrees a frame) and the ring turns about 1.7 degrees a frame.

use glam::Vec3;

use super::SceneOptions;
use super::geometry::MeshBuilder;
use super::rng::Rng;
use crate::scene::{CameraRig, DirectionalLight, Material, Scene, Spin};

/// Half the width of the wall and the floor (world units).
const HALF_WIDTH: f32 = 4.0;
/// Height of the wall.
const WALL_HEIGHT: f32 = 3.0;
/// The wall's plane (z) and the signs' plane just in front of it.
const WALL_Z: f32 = -2.0;
const SIGN_Z: f32 = -1.95;
/// The fence of dark bars: its plane, bar width, spacing and height.
const FENCE_Z: f32 = -0.9;
const BAR_WIDTH: f32 = 0.022;
const BAR_SPACING: f32 = 0.33;
const BAR_HEIGHT: f32 = 1.5;
/// Neon tube radius range (about 1 to 2.5 px across at 720p from the default camera).
const TUBE_RADIUS: (f32, f32) = (0.004, 0.01);
/// Emitted radiance range of the tubes, in multiples of the display's white.
const TUBE_RADIANCE: (f32, f32) = (3.0, 12.0);
/// Radiance and half-size of the bulbs.
const BULB_RADIANCE: f32 = 40.0;
const BULB_HALF: f32 = 0.018;
const BULBS: usize = 14;
/// Sides of every tube.
const TUBE_SIDES: u32 = 8;
/// The neon hues (normalised to a maximum of 1 before the radiance scale).
const HUES: [Vec3; 4] = [
    Vec3::new(1.0, 0.08, 0.45),
    Vec3::new(0.1, 0.75, 1.0),
    Vec3::new(1.0, 0.45, 0.05),
    Vec3::new(0.35, 1.0, 0.2),
];

/// An unlit, black-bodied material that only emits `radiance`.
fn emitter(name: String, radiance: Vec3) -> Material {
    Material {
        name,
        base_color: Vec3::ZERO,
        unlit: true,
        emissive: radiance,
        ..Material::default()
    }
}

/// A straight stroke from `a` to `b`, subdivided so the tube follows it exactly.
fn stroke(a: Vec3, b: Vec3) -> Vec<Vec3> {
    (0..=8).map(|k| a.lerp(b, k as f32 / 8.0)).collect()
}

/// One sign centred at `at` on the sign plane: a shape of `kind` about `size` across.
fn sign_path(rng: &mut Rng, kind: usize, at: Vec3, size: f32) -> (Vec<Vec3>, bool) {
    match kind {
        // A ring.
        0 => (
            (0..48)
                .map(|k| {
                    let (sin, cos) = (k as f32 / 48.0 * std::f32::consts::TAU).sin_cos();
                    at + Vec3::new(cos, sin, 0.0) * size * 0.5
                })
                .collect(),
            true,
        ),
        // A zig-zag.
        1 => (
            (0..7)
                .map(|k| {
                    let x = (k as f32 / 6.0 - 0.5) * size;
                    let y = if k % 2 == 0 { -0.18 } else { 0.18 } * size;
                    at + Vec3::new(x, y, 0.0)
                })
                .collect(),
            false,
        ),
        // A frame (a closed rectangle, corners subdivided so they stay sharp).
        2 => {
            let (w, h) = (size * 0.5, size * rng.range(0.2, 0.35));
            let corners = [
                Vec3::new(-w, -h, 0.0),
                Vec3::new(w, -h, 0.0),
                Vec3::new(w, h, 0.0),
                Vec3::new(-w, h, 0.0),
            ];
            let mut path = Vec::new();
            for (i, corner) in corners.iter().enumerate() {
                let next = corners[(i + 1) % 4];
                path.extend((0..6).map(|k| at + corner.lerp(next, k as f32 / 6.0)));
            }
            (path, true)
        }
        // A long stroke at a shallow angle (the staircase every AA method is judged on).
        _ => {
            let angle =
                rng.range(2.0, 12.0).to_radians() * if rng.unit() < 0.5 { -1.0 } else { 1.0 };
            let half = Vec3::new(angle.cos(), angle.sin(), 0.0) * size * 0.7;
            (stroke(at - half, at + half), false)
        }
    }
}

/// The neon scene (see the module docs).
pub fn neon(options: &SceneOptions) -> Scene {
    let mut rng = Rng::new(options.seed, 0x4E30);
    let mut materials = vec![
        Material {
            name: "neon wall".to_owned(),
            base_color: Vec3::new(0.03, 0.028, 0.032),
            specular: Vec3::splat(0.04),
            shininess: 40.0,
            ..Material::default()
        },
        Material {
            name: "neon fence".to_owned(),
            base_color: Vec3::splat(0.01),
            specular: Vec3::splat(0.3),
            shininess: 80.0,
            ..Material::default()
        },
    ];
    let mut meshes = Vec::new();
    let mut wall = MeshBuilder::default();
    wall.plane(
        Vec3::new(-HALF_WIDTH, 0.0, WALL_Z),
        Vec3::X * 2.0 * HALF_WIDTH,
        Vec3::Y * WALL_HEIGHT,
        1.0,
    );
    wall.plane(
        Vec3::new(-HALF_WIDTH, 0.0, 2.0 * HALF_WIDTH + WALL_Z),
        Vec3::X * 2.0 * HALF_WIDTH,
        Vec3::NEG_Z * 2.0 * HALF_WIDTH,
        1.0,
    );
    meshes.push(wall.build("neon wall and ground", 0, None));

    let mut fence = MeshBuilder::default();
    let bars = (2.0 * HALF_WIDTH / BAR_SPACING) as i32;
    for k in 0..bars {
        let x = -HALF_WIDTH + (k as f32 + 0.5) * BAR_SPACING;
        let half = BAR_WIDTH * 0.5;
        fence.cuboid(
            Vec3::new(x - half, 0.0, FENCE_Z - half),
            Vec3::new(x + half, BAR_HEIGHT, FENCE_Z + half),
            1.0,
        );
    }
    fence.cuboid(
        Vec3::new(-HALF_WIDTH, BAR_HEIGHT - 0.03, FENCE_Z - 0.015),
        Vec3::new(HALF_WIDTH, BAR_HEIGHT, FENCE_Z + 0.015),
        1.0,
    );
    meshes.push(fence.build("neon fence", 1, None));

    // Signs: a grid of slots on the wall, one shape of one hue each.
    for (row, y) in [0.55, 1.25, 1.95].into_iter().enumerate() {
        for column in 0..5 {
            let x = (column as f32 - 2.0) * 1.25 + rng.range(-0.15, 0.15);
            let at = Vec3::new(x, y + rng.range(-0.08, 0.08), SIGN_Z);
            let kind = rng.below(4);
            let size = rng.range(0.55, 0.9);
            let (path, closed) = sign_path(&mut rng, kind, at, size);
            let hue = HUES[rng.below(HUES.len())];
            let radiance = hue * rng.range(TUBE_RADIANCE.0, TUBE_RADIANCE.1);
            let radius = rng.range(TUBE_RADIUS.0, TUBE_RADIUS.1);
            let mut tube = MeshBuilder::default();
            tube.tube(&path, TUBE_SIDES, closed, 1.0, |_| radius);
            materials.push(emitter(format!("neon sign {row}.{column}"), radiance));
            meshes.push(tube.build(
                &format!("neon sign {row}.{column}"),
                materials.len() - 1,
                None,
            ));
        }
    }

    // A string of bulbs sagging across the top of the wall, and its wire.
    let mut bulbs = MeshBuilder::default();
    let mut wire = MeshBuilder::default();
    let sag = |t: f32| 2.7 - 0.25 * (1.0 - (2.0 * t - 1.0).powi(2));
    let wire_path: Vec<Vec3> = (0..=32)
        .map(|k| {
            let t = k as f32 / 32.0;
            Vec3::new((t - 0.5) * 2.0 * (HALF_WIDTH - 0.4), sag(t), -1.4)
        })
        .collect();
    wire.tube(&wire_path, 6, false, 1.0, |_| 0.003);
    for k in 0..BULBS {
        let t = (k as f32 + 0.5) / BULBS as f32;
        let at = Vec3::new((t - 0.5) * 2.0 * (HALF_WIDTH - 0.4), sag(t) - 0.04, -1.4);
        bulbs.cuboid(
            at - Vec3::splat(BULB_HALF),
            at + Vec3::splat(BULB_HALF),
            1.0,
        );
    }
    meshes.push(wire.build("neon bulb wire", 1, None));
    materials.push(emitter(
        "neon bulbs".to_owned(),
        Vec3::new(1.0, 0.85, 0.6) * BULB_RADIANCE,
    ));
    meshes.push(bulbs.build("neon bulbs", materials.len() - 1, None));

    // The spinning ring in front of the fence.
    let centre = Vec3::new(1.4, 0.75, 0.2);
    let axis = Vec3::new(0.3, 0.2, 1.0).normalize();
    let (u, v) = (
        axis.any_orthonormal_vector(),
        axis.cross(axis.any_orthonormal_vector()),
    );
    let ring: Vec<Vec3> = (0..96)
        .map(|k| {
            let (sin, cos) = (k as f32 / 96.0 * std::f32::consts::TAU).sin_cos();
            centre + (u * cos + v * sin) * 0.45
        })
        .collect();
    let mut spinner = MeshBuilder::default();
    spinner.tube(&ring, TUBE_SIDES, true, 1.0, |_| 0.008);
    materials.push(emitter("neon ring".to_owned(), HUES[1] * 16.0));
    let spin = Spin {
        pivot: centre,
        axis: Vec3::Y,
        radians_per_frame: 0.03,
    };
    meshes.push(spinner.build("neon ring", materials.len() - 1, Some(spin)));

    Scene {
        meshes,
        materials,
        camera: CameraRig {
            target: Vec3::new(0.0, 1.2, -1.0),
            distance: 5.5,
            yaw_degrees: 0.0,
            pitch_degrees: 6.0,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 40.0,
            orbit_degrees_per_frame: 0.4,
        },
        light: DirectionalLight {
            direction: Vec3::new(-0.4, -0.8, -0.45).normalize(),
            color: Vec3::new(0.12, 0.14, 0.2),
            ambient: Vec3::splat(0.02),
        },
        clear_color: Vec3::new(0.002, 0.003, 0.008),
        ..Scene::empty("neon")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn the_scene_is_hdr_with_thin_bright_emitters_on_dark_matte_surfaces() {
        let scene = neon(&SceneOptions::default());
        assert_scene_valid(&scene);
        assert!(scene.is_hdr());
        let emitters: Vec<&Material> = scene
            .materials
            .iter()
            .filter(|m| m.emissive.max_element() > 0.0)
            .collect();
        assert!(emitters.len() >= 10);
        for m in &emitters {
            assert!(m.emissive.max_element() >= TUBE_RADIANCE.0, "{}", m.name);
            assert!(m.unlit && m.base_color == Vec3::ZERO, "{}", m.name);
        }
        for m in scene.materials.iter().filter(|m| m.emissive == Vec3::ZERO) {
            assert!(m.base_color.max_element() < 0.05, "{}", m.name);
        }
        assert!(scene.meshes.iter().any(|m| m.spin.is_some()));
        let triangles = scene.triangle_count();
        assert!((5_000..=80_000).contains(&triangles), "{triangles}");
    }

    #[test]
    fn the_seed_moves_the_signs_and_the_same_seed_builds_the_same_scene() {
        let options = SceneOptions::default();
        let (a, b) = (neon(&options), neon(&options));
        let c = neon(&SceneOptions { seed: 9, ..options });
        for (x, y) in a.meshes.iter().zip(&b.meshes) {
            assert_eq!(x.vertices, y.vertices, "{}", x.name);
        }
        let signs = |s: &Scene| -> Vec<Vec<crate::scene::Vertex>> {
            (s.meshes.iter())
                .filter(|m| m.name.starts_with("neon sign"))
                .map(|m| m.vertices.clone())
                .collect()
        };
        assert_ne!(signs(&a), signs(&c));
    }
}
