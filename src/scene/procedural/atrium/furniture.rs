//! What stands and hangs in the atrium's court: urns and bushes of alpha-tested cards in
//! planters, a chain-link fence, the sculpture of thin rings and spheres, and the cables
//! (catenaries) strung across the court: the thin, masked and sub-pixel features the
//! scene exists to stress.

use super::architecture::side_point;
use super::*;

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
pub(super) fn planters(parts: &mut Parts, rng: &mut Rng) {
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
pub(super) fn fence(parts: &mut Parts) {
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
pub(super) fn sculpture(parts: &mut Parts) -> MeshBuilder {
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
pub(super) const SCULPTURE_CENTER: Vec3 = Vec3::new(0.0, 1.75, 0.0);

pub(super) const SCULPTURE_AXIS: Vec3 = Vec3::new(0.397_148_4, 0.917_754_6, 0.0);

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
pub(super) fn cables(parts: &mut Parts) {
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

#[cfg(test)]
mod tests {
    use super::*;

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
