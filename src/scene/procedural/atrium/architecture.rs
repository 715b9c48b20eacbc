//! The atrium's architecture: two storeys of columns (turned profiles) and arched walls
//! around the court, the entablatures, balustrades, fanlights and the outer wall, built on
//! one side and replicated to the others.

use super::*;

/// A point of side 0: `u` along the side (+X), height `y`, depth `w` from the centre (+Z).
pub(super) fn side_point(u: f32, y: f32, w: f32) -> Vec3 {
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
pub(super) fn arcade(parts: &mut Parts, storey: &Storey) {
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
pub(super) fn ground_entablature(parts: &mut Parts) {
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
pub(super) fn gallery_entablature(parts: &mut Parts) {
    let stone = parts.get(Part::Stone);
    let (front, back) = (COURT - WALL_HALF, COURT + WALL_HALF);
    ring_box(stone, (front, back), (GALLERY.top, 8.5), STONE_TILE);
    ring_box(stone, (front - 0.15, back), (8.5, ROOF_TOP), STONE_TILE);
    ring_box(stone, (back, OUTER), (8.5, ROOF_TOP), STONE_TILE);
}

/// Wrought-iron balustrades between the gallery columns: handrail, bottom rail and
/// balusters every 10 cm.
pub(super) fn balustrades(parts: &mut Parts) {
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
pub(super) fn fanlights(parts: &mut Parts) {
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
pub(super) fn outer_wall(parts: &mut Parts) {
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
