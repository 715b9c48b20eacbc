//! The `atrium` scene: a two-storey arcaded courtyard in the spirit of Crytek Sponza, seen
//! from inside by a camera that orbits its centre.
//!
//! # Plan (metres, +Y up)
//! A 12 x 12 m court paved with polished marble (glossy: Ks 0.5, Ns 200) is ringed by
//! arcades: columns every 2 m on the lines |x| = 6 and |z| = 6, carrying semicircular arches
//! (a true arch: spandrel faces triangulated against the curve, and a curved soffit), a
//! frieze with a carved inscription, a cornice, and above them a gallery storey with smaller
//! columns, wrought-iron balustrades (balusters ~2 cm thick, handrails) and lattice screens
//! in the arch heads. Aisles 2.25 m deep run behind the arcades to brick walls at 8.5 m
//! with noticeboards of small print. Over the court hang catenary cables (6 mm) with strings
//! of glowing bulbs; stone urns with alpha-tested foliage cards stand in the corners and
//! along the arcades; in the middle a chain-link fence rings a pedestal carrying a brass
//! armillary sphere that turns about its tilted axis (the scene's [`Spin`]: object motion
//! besides the camera's).
//!
//! # Construction
//! One side of the cloister (the +Z side, in local coordinates where the court lies towards
//! -Z) is built and then copied three times rotated by 90 degrees. Pieces that meet at the
//! corners are assigned pinwheel-fashion: a strip at depth w0..w1 from the centre spans
//! -w1..w0 along its side, so the four copies tile the ring without overlapping coplanar
//! faces. Stone is single-sided, so the hidden faces where pieces touch are culled rather
//! than z-fighting.
//!
//! Every mesh gathers one material, so the scene has one draw per material plus the
//! spinning sculpture. The seed varies the foliage, the textures' noise and the glyphs;
//! the architecture is fixed.

mod architecture;
mod furniture;
mod textures;

use architecture::{
    arcade, balustrades, fanlights, gallery_entablature, ground_entablature, outer_wall,
};
use furniture::{SCULPTURE_AXIS, SCULPTURE_CENTER, cables, fence, planters, sculpture};

use glam::{Vec2, Vec3};

use super::SceneOptions;
use super::geometry::{MeshBuilder, ProfilePoint};
use super::rng::Rng;
use crate::scene::{AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, Spin};

/// Distance from the centre to the arcade's column line.
const COURT: f32 = 6.0;
/// Half the thickness of the arcade walls.
const WALL_HALF: f32 = 0.25;
/// Distance from the centre to the inner face of the outer brick walls.
const OUTER: f32 = 8.5;
/// Column spacing along a side.
const BAY: f32 = 2.0;
/// Radius of the arches' soffit.
const ARCH_RADIUS: f32 = 0.7;
/// Columns per side (the side owns the corner column at its start).
const COLUMNS_PER_SIDE: usize = 6;
/// Height of the whole building (top of the cornices and roof slabs).
const ROOF_TOP: f32 = 8.66;

/// One storey of the arcade.
struct Storey {
    /// Floor level the columns stand on.
    floor: f32,
    /// Springing line of the arches (top of the capitals).
    spring: f32,
    /// Top of the arched wall.
    top: f32,
    /// Column radius scale (1 = 0.2 m shaft).
    scale: f32,
}

const GROUND: Storey = Storey {
    floor: 0.0,
    spring: 3.0,
    top: 4.0,
    scale: 1.0,
};

const GALLERY: Storey = Storey {
    floor: 4.75,
    spring: 7.2,
    top: 8.2,
    scale: 0.82,
};

/// The meshes of the scene, one per material, in material order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    Floor,
    Brick,
    Stone,
    Frieze,
    Notice,
    Iron,
    Cable,
    Foliage,
    Fence,
    Lattice,
    Brass,
    Bulbs,
}

impl Part {
    /// Name of the part's mesh and material (after "atrium ").
    fn name(self) -> &'static str {
        match self {
            Part::Floor => "marble floor",
            Part::Brick => "bricks",
            Part::Stone => "sandstone",
            Part::Frieze => "inscription",
            Part::Notice => "noticeboard",
            Part::Iron => "wrought iron",
            Part::Cable => "cable",
            Part::Foliage => "foliage",
            Part::Fence => "chain link",
            Part::Lattice => "lattice",
            Part::Brass => "brass",
            Part::Bulbs => "bulbs",
        }
    }
}

/// Every part, in material order.
const PARTS: [Part; 12] = [
    Part::Floor,
    Part::Brick,
    Part::Stone,
    Part::Frieze,
    Part::Notice,
    Part::Iron,
    Part::Cable,
    Part::Foliage,
    Part::Fence,
    Part::Lattice,
    Part::Brass,
    Part::Bulbs,
];

/// World size of one texture repeat, per textured part.
const STONE_TILE: f32 = 2.0;
const BRICK_TILE: f32 = 1.2;
const FLOOR_TILE: f32 = 2.4;
const CHAIN_LINK_TILE: f32 = 3.0;
const LATTICE_TILE: f32 = 4.3;

/// The builders of every part.
struct Parts([MeshBuilder; PARTS.len()]);

impl Parts {
    fn get(&mut self, part: Part) -> &mut MeshBuilder {
        &mut self.0[part as usize]
    }

    fn marks(&self) -> [(usize, usize); PARTS.len()] {
        std::array::from_fn(|i| self.0[i].mark())
    }

    /// Copies everything built since `marks` three more times, rotated about the centre.
    fn replicate_sides(&mut self, marks: [(usize, usize); PARTS.len()]) {
        for (builder, (vertex, index)) in self.0.iter_mut().zip(marks) {
            builder.rotated_copies(vertex, index, Vec3::ZERO, 4);
        }
    }
}

/// The atrium scene (see the module docs). Only the seed is used; the design is fixed.
pub fn atrium(options: &SceneOptions) -> Scene {
    let materials: Vec<Material> = PARTS.iter().map(|&part| material(part)).collect();
    Scene {
        name: "atrium".to_owned(),
        meshes: meshes(options.seed),
        materials,
        textures: textures::all(options.seed),
        camera: camera(),
        interior: false,
        light: DirectionalLight {
            direction: Vec3::new(0.3, -0.85, 0.45).normalize(),
            color: Vec3::new(1.0, 0.93, 0.82),
            ambient: Vec3::new(0.28, 0.29, 0.32),
        },
        clear_color: Vec3::new(0.50, 0.66, 0.85),
        views: Vec::new(),
        notes: Vec::new(),
        warnings: Vec::new(),
    }
}

/// Every mesh: one per part (material), then the spinning armillary sphere.
fn meshes(seed: u64) -> Vec<Mesh> {
    let mut parts = Parts(std::array::from_fn(|_| MeshBuilder::default()));
    let marks = parts.marks();
    arcade(&mut parts, &GROUND);
    arcade(&mut parts, &GALLERY);
    ground_entablature(&mut parts);
    gallery_entablature(&mut parts);
    balustrades(&mut parts);
    fanlights(&mut parts);
    outer_wall(&mut parts);
    let mut rng = Rng::new(seed, 0xA7);
    planters(&mut parts, &mut rng);
    parts.replicate_sides(marks);
    parts.get(Part::Floor).plane(
        Vec3::new(-OUTER, 0.0, OUTER),
        Vec3::X * 2.0 * OUTER,
        Vec3::NEG_Z * 2.0 * OUTER,
        FLOOR_TILE,
    );
    fence(&mut parts);
    cables(&mut parts);
    let armillary = sculpture(&mut parts);
    let mut meshes: Vec<Mesh> = parts
        .0
        .into_iter()
        .zip(PARTS)
        .map(|(builder, part)| {
            builder.build(&format!("atrium {}", part.name()), part as usize, None)
        })
        .collect();
    meshes.push(armillary.build(
        "atrium armillary sphere",
        Part::Brass as usize,
        Some(Spin {
            pivot: SCULPTURE_CENTER,
            axis: SCULPTURE_AXIS,
            radians_per_frame: 0.012,
        }),
    ));
    meshes
}

/// Inside the court, looking across it from 4.6 m off the centre at eye height 2.9 m,
/// slightly down, with a wide (70 degree) lens; a quarter degree of orbit per frame.
fn camera() -> CameraRig {
    CameraRig {
        target: Vec3::new(0.0, 2.4, 0.0),
        distance: 4.6,
        yaw_degrees: 30.0,
        pitch_degrees: 6.0,
        fov_y_degrees: 70.0,
        near: 0.05,
        far: 60.0,
        orbit_degrees_per_frame: 0.25,
    }
}

/// The material of a part (texture indices follow the order of the scene's texture list).
fn material(part: Part) -> Material {
    let textured = |name: &str, texture: usize, specular: f32, shininess: f32| Material {
        name: format!("atrium {name}"),
        base_color: Vec3::ONE,
        base_color_texture: Some(texture),
        specular: Vec3::splat(specular),
        shininess,
        double_sided: false,
        ..Material::default()
    };
    let masked = |m: Material| Material {
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        double_sided: true,
        ..m
    };
    let plain = |name: &str, rgb: Vec3, specular: Vec3, shininess: f32| Material {
        name: format!("atrium {name}"),
        base_color: rgb,
        specular,
        shininess,
        double_sided: false,
        ..Material::default()
    };
    match part {
        Part::Floor => textured("marble floor", 0, 0.5, 200.0),
        Part::Brick => textured("bricks", 1, 0.04, 16.0),
        Part::Stone => textured("sandstone", 2, 0.08, 20.0),
        Part::Frieze => textured("inscription", 3, 0.08, 20.0),
        Part::Notice => textured("noticeboard", 4, 0.02, 8.0),
        Part::Foliage => masked(textured("foliage", 5, 0.08, 12.0)),
        Part::Fence => masked(textured("chain link", 6, 0.5, 40.0)),
        Part::Lattice => masked(textured("lattice", 7, 0.2, 30.0)),
        Part::Iron => plain("wrought iron", Vec3::splat(0.035), Vec3::splat(0.4), 60.0),
        Part::Cable => plain("cable", Vec3::splat(0.02), Vec3::splat(0.3), 40.0),
        Part::Brass => plain(
            "brass",
            Vec3::new(0.55, 0.36, 0.12),
            Vec3::new(0.9, 0.75, 0.45),
            90.0,
        ),
        Part::Bulbs => Material {
            unlit: true,
            ..plain("bulbs", Vec3::new(1.0, 0.8, 0.45), Vec3::ZERO, 1.0)
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::procedural::tests::assert_scene_valid;

    #[test]
    fn builds_within_the_triangle_budget() {
        let scene = atrium(&SceneOptions::default());
        assert_scene_valid(&scene);
        let triangles = scene.triangle_count();
        assert!((50_000..=200_000).contains(&triangles), "{triangles}");
        assert!(
            scene.meshes.iter().all(|m| !m.indices.is_empty()),
            "empty part"
        );
        assert_eq!(scene.meshes.iter().filter(|m| m.spin.is_some()).count(), 1);
        let masked = scene
            .materials
            .iter()
            .filter(|m| matches!(m.alpha_mode, AlphaMode::Mask { .. }))
            .count();
        assert_eq!(masked, 3);
    }

    #[test]
    fn is_deterministic_and_seeded() {
        let (a, b) = (meshes(1), meshes(1));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.vertices, y.vertices);
            assert_eq!(x.indices, y.indices);
        }
        let other = meshes(2);
        let foliage = Part::Foliage as usize;
        assert_ne!(a[foliage].vertices, other[foliage].vertices);
        assert_eq!(
            textures::inscription(4).image,
            textures::inscription(4).image
        );
        assert_ne!(
            textures::inscription(4).image,
            textures::inscription(5).image
        );
    }

    #[test]
    fn camera_orbits_inside_the_court() {
        let rig = camera();
        let horizontal = rig.distance * rig.pitch_degrees.to_radians().cos();
        assert!(horizontal < COURT - WALL_HALF - 0.5, "{horizontal}");
        let eye_height = rig.target.y + rig.distance * rig.pitch_degrees.to_radians().sin();
        assert!(eye_height > 1.5 && eye_height < GROUND.spring);
    }
}
