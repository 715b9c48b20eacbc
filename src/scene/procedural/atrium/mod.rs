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

mod textures;

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

/// A point of side 0: `u` along the side (+X), height `y`, depth `w` from the centre (+Z).
fn side_point(u: f32, y: f32, w: f32) -> Vec3 {
    Vec3::new(u, y, w)
}

/// Along-side extent of a strip at depth `w0..w1` so that the four sides tile the ring
/// pinwheel-fashion (see the module docs).
fn pinwheel(w0: f32, w1: f32) -> (f32, f32) {
    (-w1, w0)
}

/// An axis-aligned box of side 0 between depths `w0..w1` and heights `y0..y1`, spanning
/// its pinwheel extent along the side.
fn ring_box(b: &mut MeshBuilder, (w0, w1): (f32, f32), (y0, y1): (f32, f32), tile: f32) {
    let (u0, u1) = pinwheel(w0, w1);
    b.cuboid(side_point(u0, y0, w0), side_point(u1, y1, w1), tile);
}

/// Profile of a column of height `height` and radius scale `s`, from the top of its plinth
/// to the underside of its abacus: an attic base (torus, scotia, torus), a shaft with a
/// slight entasis, a necking ring and a flaring echinus.
fn column_profile(height: f32, s: f32) -> Vec<ProfilePoint> {
    let plinth = 0.12 * s;
    let abacus = 0.12 * s;
    let base: [(f32, f32); 8] = [
        (0.27, 0.0),
        (0.285, 0.03),
        (0.27, 0.07),
        (0.235, 0.09),
        (0.225, 0.12),
        (0.24, 0.15),
        (0.232, 0.17),
        (0.2, 0.19),
    ];
    let capital: [(f32, f32); 8] = [
        (0.19, 0.0),
        (0.19, 0.04),
        (0.178, 0.06),
        (0.19, 0.08),
        (0.23, 0.15),
        (0.27, 0.2),
        (0.3, 0.24),
        (0.3, 0.28),
    ];
    let shaft_bottom = plinth + 0.19 * s;
    let shaft_top = height - abacus - 0.28 * s;
    let mut profile: Vec<ProfilePoint> = base
        .iter()
        .map(|&(r, y)| Vec2::new(r * s, plinth + y * s))
        .collect();
    for k in 1..=4 {
        let t = k as f32 / 4.0;
        // Entasis: the shaft narrows by 12% towards the top, along a gentle curve.
        let r = 0.2 * s * (1.0 - 0.12 * t * t);
        profile.push(Vec2::new(r, shaft_bottom + (shaft_top - shaft_bottom) * t));
    }
    profile.extend(
        capital
            .iter()
            .map(|&(r, y)| Vec2::new(r * s, shaft_top + y * s)),
    );
    profile
}

/// A column of a storey at `u` along side 0, on the column line.
fn column(b: &mut MeshBuilder, storey: &Storey, u: f32) {
    let s = storey.scale;
    let height = storey.spring - storey.floor;
    let foot = side_point(u, storey.floor, COURT);
    let plinth = Vec3::new(0.3 * s, 0.12 * s, 0.3 * s);
    b.cuboid(
        foot - plinth * Vec3::new(1.0, 0.0, 1.0),
        foot + plinth * Vec3::new(1.0, 1.0, 1.0),
        STONE_TILE,
    );
    b.lathe(foot, &column_profile(height, s), 24, 1.0, 1.0 / STONE_TILE);
    let abacus = Vec3::new(0.31 * s, 0.12 * s, 0.31 * s);
    let top = side_point(u, storey.spring, COURT);
    b.cuboid(
        top - abacus,
        top + abacus * Vec3::new(1.0, 0.0, 1.0),
        STONE_TILE,
    );
}

/// The arched wall of one bay centred at `center` along side 0: front and back faces
/// (the rectangle of the bay above the springing line, minus the semicircle) triangulated
/// as strips between the arch curve and the rectangle's border, and the curved soffit.
fn arched_wall(b: &mut MeshBuilder, storey: &Storey, center: f32) {
    const SEGMENTS: usize = 16;
    let half = BAY * 0.5;
    let height = storey.top - storey.spring;
    // Angles from the left springing point (pi) to the right (0), including the rectangle's
    // top corners so that every strip quad has its outer edge on one side of the rectangle.
    let corner = height.atan2(half);
    let mut angles: Vec<f32> = (0..=SEGMENTS)
        .map(|k| std::f32::consts::PI * (1.0 - k as f32 / SEGMENTS as f32))
        .collect();
    angles.extend([std::f32::consts::PI - corner, corner]);
    angles.sort_by(|a, b| b.total_cmp(a));
    angles.dedup_by(|a, b| (*a - *b).abs() < 1e-4);
    let origin = Vec2::new(center, storey.spring);
    let rim: Vec<(Vec2, Vec2, Vec2)> = angles
        .iter()
        .map(|&a| {
            let d = Vec2::from_angle(a);
            // Ray from the arch centre to the rectangle [-half, half] x [0, height].
            let t_side = if d.x.abs() > 1e-6 {
                half / d.x.abs()
            } else {
                f32::MAX
            };
            let t_top = if d.y > 1e-6 { height / d.y } else { f32::MAX };
            (origin + d * ARCH_RADIUS, origin + d * t_side.min(t_top), d)
        })
        .collect();
    let (front, back) = (COURT - WALL_HALF, COURT + WALL_HALF);
    let uv = |p: Vec2| Vec2::new(p.x, -p.y) / STONE_TILE;
    let mut arc = 0.0;
    for pair in rim.windows(2) {
        let [(inner0, outer0, d0), (inner1, outer1, d1)] = [pair[0], pair[1]];
        for (w, facing) in [(front, Vec3::NEG_Z), (back, Vec3::Z)] {
            let corners =
                [inner0, outer0, outer1, inner1].map(|p| (side_point(p.x, p.y, w), facing, uv(p)));
            b.quad_facing(corners, facing);
        }
        // Soffit: normals point at the arch's centre.
        let step = inner0.distance(inner1);
        let soffit = |p: Vec2, d: Vec2, w: f32, along: f32| {
            (
                side_point(p.x, p.y, w),
                -d.extend(0.0),
                Vec2::new(along, w) / STONE_TILE,
            )
        };
        let facing = -(d0 + d1).extend(0.0);
        b.quad_facing(
            [
                soffit(inner0, d0, front, arc),
                soffit(inner0, d0, back, arc),
                soffit(inner1, d1, back, arc + step),
                soffit(inner1, d1, front, arc + step),
            ],
            facing,
        );
        arc += step;
    }
}

/// The solid strip of arched wall between a side's first column and the outer corner.
fn corner_strip(b: &mut MeshBuilder, storey: &Storey) {
    let (u0, u1) = (-COURT - WALL_HALF, -COURT);
    let height = storey.top - storey.spring;
    let front = side_point(u1, storey.spring, COURT - WALL_HALF);
    b.plane(front, Vec3::NEG_X * (u1 - u0), Vec3::Y * height, STONE_TILE);
    let back = side_point(u0, storey.spring, COURT + WALL_HALF);
    b.plane(back, Vec3::X * (u1 - u0), Vec3::Y * height, STONE_TILE);
}

/// One storey of side 0: columns, arched walls and the corner strip.
fn arcade(parts: &mut Parts, storey: &Storey) {
    let stone = parts.get(Part::Stone);
    for i in 0..COLUMNS_PER_SIDE {
        let u = -COURT + i as f32 * BAY;
        column(stone, storey, u);
        arched_wall(stone, storey, u + BAY * 0.5);
    }
    corner_strip(stone, storey);
}

/// The ground storey's entablature: a frieze carrying the inscription on the court face,
/// a moulded cornice above it, and the gallery floor slab behind.
fn ground_entablature(parts: &mut Parts) {
    let (y0, y1) = (GROUND.top, 4.5);
    let (front, back) = (COURT - WALL_HALF, COURT + WALL_HALF);
    let (u0, u1) = pinwheel(front, back);
    // The inscription texture covers 1 m of band per repeat, top edge at v = 0.
    let length = u1 - u0;
    parts.get(Part::Frieze).plane_uv(
        side_point(u1, y0, front),
        Vec3::NEG_X * length,
        Vec3::Y * (y1 - y0),
        Vec2::new(0.0, 1.0),
        Vec2::new(length, 0.0),
    );
    let stone = parts.get(Part::Stone);
    stone.plane(
        side_point(u0, y0, back),
        Vec3::X * length,
        Vec3::Y * (y1 - y0),
        STONE_TILE,
    );
    ring_box(stone, (front - 0.12, back), (y1, GALLERY.floor), STONE_TILE);
    ring_box(stone, (back, OUTER), (4.4, GALLERY.floor), STONE_TILE);
}

/// The gallery storey's entablature, cornice and roof slab.
fn gallery_entablature(parts: &mut Parts) {
    let stone = parts.get(Part::Stone);
    let (front, back) = (COURT - WALL_HALF, COURT + WALL_HALF);
    ring_box(stone, (front, back), (GALLERY.top, 8.5), STONE_TILE);
    ring_box(stone, (front - 0.15, back), (8.5, ROOF_TOP), STONE_TILE);
    ring_box(stone, (back, OUTER), (8.5, ROOF_TOP), STONE_TILE);
}

/// Wrought-iron balustrades between the gallery columns: handrail, bottom rail and
/// balusters every 10 cm.
fn balustrades(parts: &mut Parts) {
    let iron = parts.get(Part::Iron);
    let (bottom, top) = (GALLERY.floor + 0.11, GALLERY.floor + 0.97);
    for i in 0..COLUMNS_PER_SIDE {
        let (u0, u1) = (
            -COURT + i as f32 * BAY + 0.2,
            -COURT + (i + 1) as f32 * BAY - 0.2,
        );
        for (y, radius, sides) in [(top, 0.028, 10), (bottom, 0.016, 8)] {
            iron.tube(
                &[side_point(u0, y, COURT), side_point(u1, y, COURT)],
                sides,
                false,
                1.0,
                |_| radius,
            );
        }
        let count = ((u1 - u0) / 0.1).round() as usize;
        for k in 1..count {
            let u = u0 + (u1 - u0) * k as f32 / count as f32;
            iron.tube(
                &[side_point(u, bottom, COURT), side_point(u, top, COURT)],
                6,
                false,
                1.0,
                |_| 0.011,
            );
        }
    }
}

/// Lattice screens filling the gallery arches' heads, in the middle of the wall.
fn fanlights(parts: &mut Parts) {
    let lattice = parts.get(Part::Lattice);
    for i in 0..COLUMNS_PER_SIDE {
        let center = -COURT + (i as f32 + 0.5) * BAY;
        let origin = side_point(center + ARCH_RADIUS, GALLERY.spring, COURT);
        lattice.plane(
            origin,
            Vec3::NEG_X * 2.0 * ARCH_RADIUS,
            Vec3::Y * ARCH_RADIUS,
            LATTICE_TILE,
        );
    }
}

/// Outer brick wall of side 0, with a noticeboard seen through the middle arch.
fn outer_wall(parts: &mut Parts) {
    parts.get(Part::Brick).plane(
        side_point(OUTER, 0.0, OUTER),
        Vec3::NEG_X * 2.0 * OUTER,
        Vec3::Y * ROOF_TOP,
        BRICK_TILE,
    );
    parts.get(Part::Notice).plane_uv(
        side_point(1.65, 1.05, OUTER - 0.01),
        Vec3::NEG_X * 1.3,
        Vec3::Y * 1.0,
        Vec2::new(0.0, 1.0),
        Vec2::new(1.0, 0.0),
    );
}

/// A stone urn on the floor at `at`; returns the height of its soil.
fn urn(b: &mut MeshBuilder, at: Vec3) -> f32 {
    let profile = [
        (0.2, 0.0),
        (0.24, 0.04),
        (0.24, 0.08),
        (0.16, 0.14),
        (0.18, 0.2),
        (0.32, 0.34),
        (0.42, 0.5),
        (0.46, 0.62),
        (0.5, 0.66),
        (0.5, 0.72),
        (0.44, 0.72),
        (0.42, 0.66),
        (0.0, 0.66),
    ]
    .map(|(r, y)| Vec2::new(r, y));
    b.lathe(at, &profile, 24, 2.0, 1.0 / STONE_TILE);
    0.66
}

/// A bush of alpha-tested cards rising from `base`: each card a bent 1 x 3 strip, leaning
/// out at a random azimuth, with the sprig texture upright on it.
fn bush(b: &mut MeshBuilder, rng: &mut Rng, base: Vec3, cards: usize, size: f32) {
    const ROWS: u32 = 3;
    for k in 0..cards {
        let azimuth = (k as f32 + rng.range(0.0, 0.8)) / cards as f32 * std::f32::consts::TAU;
        let across = Vec3::new(azimuth.cos(), 0.0, -azimuth.sin());
        let outward = Vec3::Y.cross(across);
        let width = size * rng.range(0.5, 0.75);
        let height = size * rng.range(0.7, 1.0);
        let lean = rng.range(0.15, 0.55);
        let root = base + outward * rng.range(-0.1, 0.15) * size;
        let first = b.mark().0 as u32;
        let mut p = root;
        for row in 0..=ROWS {
            let t = row as f32 / ROWS as f32;
            // The card curls outwards as it rises.
            let tilt = lean * (0.4 + t);
            let up = (Vec3::Y * tilt.cos() + outward * tilt.sin()).normalize();
            let normal = across.cross(up);
            for side in [-0.5f32, 0.5] {
                b.vertex(p + across * side * width, normal, [side + 0.5, 1.0 - t]);
            }
            p += up * height / ROWS as f32;
        }
        b.grid(first, 1, ROWS);
    }
}

/// Urns with bushes: one in each corner of the court and two along each arcade.
fn planters(parts: &mut Parts, rng: &mut Rng) {
    let spots = [(-4.9, 4.9, 1.3), (-3.0, 5.2, 1.0), (3.0, 5.2, 1.0)];
    for (u, w, size) in spots {
        let at = side_point(u, 0.0, w);
        let soil = urn(parts.get(Part::Stone), at);
        let cards = (22.0 * size) as usize;
        bush(
            parts.get(Part::Foliage),
            rng,
            at + Vec3::Y * (soil - 0.05),
            cards,
            size,
        );
    }
}

/// The chain-link fence ringing the sculpture: eight panels between iron posts.
fn fence(parts: &mut Parts) {
    const SIDES: usize = 8;
    const RADIUS: f32 = 1.5;
    const HEIGHT: f32 = 1.0;
    let post = |k: usize| {
        let a = (k as f32 + 0.5) / SIDES as f32 * std::f32::consts::TAU;
        Vec3::new(a.cos(), 0.0, a.sin()) * RADIUS
    };
    for k in 0..SIDES {
        let (a, b) = (post(k), post(k + 1));
        let iron = parts.get(Part::Iron);
        iron.tube(&[a, a + Vec3::Y * (HEIGHT + 0.06)], 8, false, 1.0, |_| {
            0.024
        });
        iron.tube(
            &[a + Vec3::Y * HEIGHT, b + Vec3::Y * HEIGHT],
            8,
            false,
            1.0,
            |_| 0.016,
        );
        parts.get(Part::Fence).plane(
            a + Vec3::Y * 0.04,
            b - a,
            Vec3::Y * (HEIGHT - 0.04),
            CHAIN_LINK_TILE,
        );
    }
}

/// A closed ring tube of `radius` about `center` in the plane spanned by unit `x` and `y`.
fn ring(b: &mut MeshBuilder, center: Vec3, x: Vec3, y: Vec3, radius: f32, thickness: f32) {
    const SEGMENTS: usize = 96;
    let path: Vec<Vec3> = (0..SEGMENTS)
        .map(|k| {
            let (sin, cos) = (k as f32 / SEGMENTS as f32 * std::f32::consts::TAU).sin_cos();
            center + (x * cos + y * sin) * radius
        })
        .collect();
    b.tube(&path, 8, true, 1.0, |_| thickness);
}

/// A sphere of `radius` at `center` (a lathe of a semicircle).
fn sphere(b: &mut MeshBuilder, center: Vec3, radius: f32, sides: u32) {
    let rings = sides / 2;
    let profile: Vec<ProfilePoint> = (0..=rings)
        .map(|k| {
            Vec2::from_angle(
                -std::f32::consts::FRAC_PI_2 + k as f32 / rings as f32 * std::f32::consts::PI,
            ) * radius
        })
        .collect();
    b.lathe(center, &profile, sides, 1.0, 1.0);
}

/// The pedestal (static) and the armillary sphere, whose mesh is returned with its spin.
fn sculpture(parts: &mut Parts) -> MeshBuilder {
    let pedestal = [
        (0.42, 0.0),
        (0.42, 0.1),
        (0.36, 0.14),
        (0.3, 0.2),
        (0.28, 0.55),
        (0.3, 0.9),
        (0.36, 0.96),
        (0.4, 1.02),
        (0.4, 1.08),
        (0.0, 1.08),
    ]
    .map(|(r, y)| Vec2::new(r, y));
    parts
        .get(Part::Stone)
        .lathe(Vec3::ZERO, &pedestal, 32, 1.0, 1.0 / STONE_TILE);
    let stem = [
        (0.12, 1.08),
        (0.05, 1.12),
        (0.04, 1.13),
        (0.07, 1.16),
        (0.0, 1.16),
    ]
    .map(|(r, y)| Vec2::new(r, y));
    parts
        .get(Part::Brass)
        .lathe(Vec3::ZERO, &stem, 16, 1.0, 1.0);

    let center = SCULPTURE_CENTER;
    let axis = SCULPTURE_AXIS;
    let e1 = Vec3::Z.cross(axis).normalize();
    let e2 = axis.cross(e1);
    let r = 0.55;
    let obliquity = 23.4f32.to_radians();
    let mut b = MeshBuilder::default();
    ring(&mut b, center, e1, e2, r, 0.016);
    for side in [-1.0f32, 1.0] {
        ring(
            &mut b,
            center + axis * side * r * obliquity.sin(),
            e1,
            e2,
            r * obliquity.cos(),
            0.01,
        );
    }
    ring(&mut b, center, e1, axis, r + 0.012, 0.014);
    ring(&mut b, center, e2, axis, r + 0.024, 0.014);
    let ecliptic = e2 * obliquity.cos() + axis * obliquity.sin();
    ring(&mut b, center, e1, ecliptic, r - 0.012, 0.02);
    b.tube(
        &[center - axis * 0.72, center + axis * 0.72],
        8,
        false,
        1.0,
        |_| 0.012,
    );
    sphere(&mut b, center, 0.11, 24);
    b
}

/// Where the armillary sphere turns, and about which axis (tilted like the Earth's).
const SCULPTURE_CENTER: Vec3 = Vec3::new(0.0, 1.75, 0.0);
const SCULPTURE_AXIS: Vec3 = Vec3::new(0.397_148_4, 0.917_754_6, 0.0);

/// Points of a hanging cable between level anchors `a` and `b` sagging `sag` in the middle:
/// a true catenary `y = c cosh(x / c)`, its parameter `c` found by bisection.
fn catenary(a: Vec3, b: Vec3, sag: f32, points: usize) -> Vec<Vec3> {
    let span = Vec2::new(b.x - a.x, b.z - a.z).length();
    let drop = |c: f32| c * ((span / (2.0 * c)).cosh() - 1.0);
    // drop(c) falls as c grows.
    let (mut lo, mut hi) = (span * 0.05, span * 100.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if drop(mid) > sag {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let c = 0.5 * (lo + hi);
    (0..points)
        .map(|i| {
            let t = i as f32 / (points - 1) as f32;
            let x = (t - 0.5) * span;
            let p = a.lerp(b, t);
            Vec3::new(p.x, p.y - sag + c * ((x / c).cosh() - 1.0), p.z)
        })
        .collect()
}

/// Cables strung across the court between the gallery columns, and two diagonal strings of
/// bulbs between the corner columns.
fn cables(parts: &mut Parts) {
    const POINTS: usize = 48;
    let reach = COURT - 0.15;
    let mut lines: Vec<(Vec3, Vec3, f32, bool)> = Vec::new();
    for x in [-4.0, 0.0, 4.0] {
        lines.push((
            Vec3::new(x, 6.4, -reach),
            Vec3::new(x, 6.4, reach),
            0.8,
            false,
        ));
        lines.push((
            Vec3::new(-reach, 6.1, x),
            Vec3::new(reach, 6.1, x),
            0.9,
            false,
        ));
    }
    let corner = COURT - 0.1;
    lines.push((
        Vec3::new(-corner, 6.75, -corner),
        Vec3::new(corner, 6.75, corner),
        1.3,
        true,
    ));
    lines.push((
        Vec3::new(corner, 6.9, -corner),
        Vec3::new(-corner, 6.9, corner),
        1.05,
        true,
    ));
    for (a, b, sag, bulbs) in lines {
        let path = catenary(a, b, sag, POINTS);
        parts.get(Part::Cable).tube(&path, 6, false, 1.0, |_| 0.006);
        if bulbs {
            let bulb = parts.get(Part::Bulbs);
            for p in path.iter().skip(3).step_by(3).take(POINTS / 3 - 2) {
                let profile = [
                    (0.0, -0.1),
                    (0.03, -0.09),
                    (0.035, -0.06),
                    (0.008, -0.03),
                    (0.008, 0.0),
                    (0.0, 0.0),
                ]
                .map(|(r, y)| Vec2::new(r, y));
                bulb.lathe(*p, &profile, 8, 1.0, 1.0);
            }
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

    #[test]
    fn catenary_hangs_between_its_anchors() {
        let a = Vec3::new(-5.0, 6.0, 0.0);
        let b = Vec3::new(5.0, 6.0, 0.0);
        let path = catenary(a, b, 0.8, 33);
        assert!(path[0].distance(a) < 1e-3 && path[32].distance(b) < 1e-3);
        assert!((path[16].y - 5.2).abs() < 1e-3, "{}", path[16].y);
        assert!(path.windows(2).take(16).all(|w| w[1].y < w[0].y));
    }

    #[test]
    fn sculpture_axis_is_unit() {
        assert!((SCULPTURE_AXIS.length() - 1.0).abs() < 1e-5);
        let tilt = SCULPTURE_AXIS.angle_between(Vec3::Y).to_degrees();
        assert!((tilt - 23.4).abs() < 0.01, "{tilt}");
    }
}
