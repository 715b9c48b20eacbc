//! The `glass` scene: transparency, which temporal antialiasing cannot reproject.
//!
//! A back wall covered by a lattice of thin light bars (about a pixel and a half wide at 720p,
//! a few pixels apart: fine geometry that every technique has to resolve), a floor with a
//! row of pillars, and in front of them three tinted glass panes at different depths and
//! angles (alpha 0.35 to 0.55, overlapping one another on screen) and a swarm of small glowing
//! particles (unlit, alpha 0.6) that circle about vertical axes of their own, fast enough to
//! cross several pixels a frame. Panes and particles are [`AlphaMode::Blend`] materials: the
//! renderer draws them last, back to front by mesh (each pane and each particle is a mesh of
//! its own), without depth or motion writes. So behind them the motion vectors are the
//! wall's: TAA reprojects the glass tint and the particles with the wrong motion, and the
//! particles, which move on their own, leave trails. The reactive mask (`reactive_mask` on
//! TAA and TAAU) is what that case is for.
//!
//! Positions, sizes, speeds and colours of the particles and the panes' tilts are drawn from
//! [`SceneOptions::seed`]; the density is ignored (about 8k triangles). The camera orbits
//! slowly (0.3 degrees a frame) so that the panes slide over the lattice with parallax.

use glam::Vec3;

use super::SceneOptions;
use super::geometry::MeshBuilder;
use super::rng::Rng;
use crate::scene::{AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, Spin};

/// Half the width of the wall and the floor; the wall's height.
const WALL_HALF_WIDTH: f32 = 4.0;
const WALL_HEIGHT: f32 = 3.2;
/// Depth (z) of the wall's face.
const WALL_Z: f32 = -2.0;
/// The lattice: bar width, and distance between bars (world units).
const BAR_WIDTH: f32 = 0.012;
const BAR_PITCH: f32 = 0.06;
/// Pillars standing between the wall and the panes.
const PILLARS: usize = 4;
/// Particles, their radius range and segments around each, and the range of their circling
/// speeds in radians per frame (either direction).
const PARTICLES: usize = 40;
const PARTICLE_RADIUS: (f32, f32) = (0.03, 0.06);
const PARTICLE_SEGMENTS: u32 = 12;
const PARTICLE_SPEED: (f32, f32) = (0.03, 0.07);

/// Material indices: wall, lattice, floor, then the panes', then the particles'.
const WALL: usize = 0;
const BARS: usize = WALL + 1;
const FLOOR: usize = WALL + 2;
const FIRST_PANE: usize = FLOOR + 1;
const FIRST_PARTICLE: usize = FIRST_PANE + PANES.len();

/// The panes: tint (linear) and alpha, centre, half size.
const PANES: [(Vec3, f32, Vec3, (f32, f32)); 3] = [
    (
        Vec3::new(0.25, 0.45, 0.9),
        0.35,
        Vec3::new(-0.9, 1.2, 0.2),
        (1.1, 0.9),
    ),
    (
        Vec3::new(0.3, 0.85, 0.4),
        0.45,
        Vec3::new(0.5, 1.0, 0.9),
        (0.9, 0.8),
    ),
    (
        Vec3::new(0.95, 0.6, 0.2),
        0.55,
        Vec3::new(1.2, 1.5, -0.6),
        (0.8, 0.7),
    ),
];

/// Particle colours (linear, unlit).
const PARTICLE_COLOURS: [Vec3; 3] = [
    Vec3::new(1.0, 0.55, 0.15),
    Vec3::new(0.3, 0.9, 1.0),
    Vec3::new(1.0, 0.95, 0.85),
];
const PARTICLE_ALPHA: f32 = 0.6;

fn materials() -> Vec<Material> {
    let opaque = |name: &str, base: Vec3, specular: f32| Material {
        name: format!("glass {name}"),
        base_color: base,
        specular: Vec3::splat(specular),
        shininess: 64.0,
        ..Material::default()
    };
    let mut materials = vec![
        opaque("wall", Vec3::new(0.05, 0.06, 0.08), 0.05),
        opaque("lattice", Vec3::new(0.85, 0.82, 0.75), 0.2),
        opaque("floor", Vec3::new(0.12, 0.11, 0.1), 0.1),
    ];
    materials.extend(
        PANES
            .iter()
            .enumerate()
            .map(|(i, &(tint, alpha, _, _))| Material {
                name: format!("glass pane {i}"),
                base_color: tint,
                opacity: alpha,
                specular: Vec3::splat(0.6),
                shininess: 400.0,
                alpha_mode: AlphaMode::Blend,
                ..Material::default()
            }),
    );
    materials.extend(
        PARTICLE_COLOURS
            .iter()
            .enumerate()
            .map(|(i, &colour)| Material {
                name: format!("glass particle {i}"),
                base_color: colour,
                opacity: PARTICLE_ALPHA,
                alpha_mode: AlphaMode::Blend,
                unlit: true,
                double_sided: false,
                ..Material::default()
            }),
    );
    materials
}

/// The wall with its lattice of bars, the floor and the pillars.
fn opaque_meshes() -> Vec<Mesh> {
    let mut wall = MeshBuilder::default();
    let mut bars = MeshBuilder::default();
    let mut floor = MeshBuilder::default();
    let h = WALL_HALF_WIDTH;
    wall.plane(
        Vec3::new(-h, 0.0, WALL_Z),
        Vec3::X * 2.0 * h,
        Vec3::Y * WALL_HEIGHT,
        1.0,
    );
    let half = 0.5 * BAR_WIDTH;
    let front = WALL_Z + BAR_WIDTH;
    let columns = (2.0 * h / BAR_PITCH) as u32;
    for i in 0..=columns {
        let x = -h + i as f32 * BAR_PITCH;
        bars.cuboid(
            Vec3::new(x - half, 0.0, WALL_Z),
            Vec3::new(x + half, WALL_HEIGHT, front),
            1.0,
        );
    }
    let rows = (WALL_HEIGHT / BAR_PITCH) as u32;
    for j in 1..=rows {
        let y = j as f32 * BAR_PITCH;
        bars.cuboid(
            Vec3::new(-h, y - half, front),
            Vec3::new(h, y + half, front + BAR_WIDTH),
            1.0,
        );
    }
    floor.plane(
        Vec3::new(-h, 0.0, 3.0),
        Vec3::X * 2.0 * h,
        Vec3::NEG_Z * (3.0 - WALL_Z),
        1.0,
    );
    for k in 0..PILLARS {
        let x = -1.8 + k as f32 * 1.2;
        floor.cuboid(
            Vec3::new(x - 0.08, 0.0, -1.1),
            Vec3::new(x + 0.08, 2.4, -0.94),
            1.0,
        );
    }
    vec![
        wall.build("glass wall", WALL, None),
        bars.build("glass lattice", BARS, None),
        floor.build("glass floor and pillars", FLOOR, None),
    ]
}

/// The panes, each a double-sided quad of its own, turned about the vertical by a random angle.
fn panes(rng: &mut Rng) -> Vec<Mesh> {
    PANES
        .iter()
        .enumerate()
        .map(|(i, &(_, _, centre, (half_width, half_height)))| {
            let turn = rng.range(-0.5, 0.5);
            let right = Vec3::new(turn.cos(), 0.0, -turn.sin()) * half_width;
            let up = Vec3::Y * half_height;
            let mut pane = MeshBuilder::default();
            pane.plane(centre - right - up, 2.0 * right, 2.0 * up, 1.0);
            pane.build(&format!("glass pane {i}"), FIRST_PANE + i, None)
        })
        .collect()
}

/// The particles, each a small sphere circling a vertical axis of its own.
fn particles(rng: &mut Rng) -> Vec<Mesh> {
    (0..PARTICLES)
        .map(|k| {
            let pivot = Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(0.4, 2.2),
                rng.range(-1.4, 1.8),
            );
            let orbit = rng.range(0.2, 0.8);
            let start = rng.range(0.0, std::f32::consts::TAU);
            let centre = pivot + Vec3::new(start.cos(), 0.0, start.sin()) * orbit;
            let speed = rng.range(PARTICLE_SPEED.0, PARTICLE_SPEED.1);
            let direction = if rng.below(2) == 0 { 1.0 } else { -1.0 };
            let colour = rng.below(PARTICLE_COLOURS.len());
            let mut particle = MeshBuilder::default();
            let radius = rng.range(PARTICLE_RADIUS.0, PARTICLE_RADIUS.1);
            particle.uv_sphere(centre, radius, PARTICLE_SEGMENTS);
            let spin = Spin {
                pivot,
                axis: Vec3::Y,
                radians_per_frame: speed * direction,
            };
            particle.build(
                &format!("glass particle {k}"),
                FIRST_PARTICLE + colour,
                Some(spin),
            )
        })
        .collect()
}

/// The glass scene (see the module docs).
pub fn glass(options: &SceneOptions) -> Scene {
    let mut rng = Rng::new(options.seed, 0x61A5);
    let mut meshes = opaque_meshes();
    meshes.extend(panes(&mut rng));
    meshes.extend(particles(&mut rng));
    Scene {
        meshes,
        materials: materials(),
        camera: CameraRig {
            target: Vec3::new(0.0, 1.2, -0.3),
            distance: 5.0,
            yaw_degrees: 0.0,
            pitch_degrees: 6.0,
            fov_y_degrees: 45.0,
            near: 0.05,
            far: 40.0,
            orbit_degrees_per_frame: 0.3,
        },
        light: DirectionalLight {
            direction: Vec3::new(-0.35, -0.8, -0.5).normalize(),
            color: Vec3::splat(0.9),
            ambient: Vec3::splat(0.2),
        },
        clear_color: Vec3::new(0.02, 0.02, 0.03),
        ..Scene::empty("glass")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn panes_and_particles_blend_and_particles_move() {
        let scene = glass(&SceneOptions::default());
        assert_scene_valid(&scene);
        let blended = |m: &Mesh| scene.materials[m.material].alpha_mode == AlphaMode::Blend;
        let panes = scene.meshes.iter().filter(|m| m.name.contains("pane"));
        assert!(panes.clone().count() == PANES.len() && panes.clone().all(blended));
        let particles: Vec<&Mesh> = scene.meshes.iter().filter(|m| m.spin.is_some()).collect();
        assert_eq!(particles.len(), PARTICLES);
        assert!(particles.iter().all(|m| blended(m)));
        // Single-sided and convex: one blended layer per particle.
        assert!(
            particles
                .iter()
                .all(|m| !scene.materials[m.material].double_sided)
        );
        let opaque = scene.meshes.iter().filter(|m| !blended(m)).count();
        assert_eq!(opaque, 3);
        let triangles = scene.triangle_count();
        assert!((5_000..=20_000).contains(&triangles), "{triangles}");
    }

    #[test]
    fn same_seed_same_scene_and_the_seed_moves_the_particles() {
        let options = SceneOptions::default();
        let (a, b) = (glass(&options), glass(&options));
        let c = glass(&SceneOptions { seed: 9, ..options });
        for (x, y) in a.meshes.iter().zip(&b.meshes) {
            assert_eq!(x.vertices, y.vertices, "{}", x.name);
            assert_eq!(x.spin, y.spin, "{}", x.name);
        }
        assert_eq!(
            a.meshes[1].vertices, c.meshes[1].vertices,
            "the lattice is fixed"
        );
        let last = a.meshes.len() - 1;
        assert_ne!(a.meshes[last].vertices, c.meshes[last].vertices);
    }
}
