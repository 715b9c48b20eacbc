//! The atrium's textures, all painted in code: running-bond bricks, polished marble floor
//! tiles, sandstone, a carved inscription band, a noticeboard with pinned sheets of small
//! print, a leafy sprig for foliage cards, chain-link and lattice wire meshes.
//!
//! Each is a pure function of the seed. They are deliberately high-frequency (thin mortar
//! and grout lines, veins, glyph strokes a few texels wide) so that minification, mip
//! selection and texture aliasing show, while every edge is painted antialiased so the
//! textures themselves are clean.

use glam::{Vec2, Vec3};

use crate::scene::TextureImage;
use crate::scene::procedural::rng::Rng;
use crate::scene::procedural::texture::{
    Canvas, Noise, Rgba, TextBlock, diamond_mesh, hash2, mix, opaque,
};

/// Side of the large (1024) textures.
pub(super) const LARGE: u32 = 1024;
/// Side of the small (512) textures.
pub(super) const SMALL: u32 = 512;

/// Distance (pixels, positive inside) from `p` to the border of the cell of size `cell`
/// it falls in, less half a joint of width `joint`; with the cell's index.
fn cell_interior(p: Vec2, cell: Vec2, joint: f32) -> (f32, Vec2) {
    let index = (p / cell).floor();
    let local = p - index * cell;
    let edge = local.min(cell - local);
    (edge.min_element() - joint * 0.5, index)
}

/// Coverage of a cell's interior from its signed distance (1 inside, 0 in the joint).
fn interior_coverage(distance: f32) -> f32 {
    (distance + 0.5).clamp(0.0, 1.0)
}

/// Sandstone colour at `uv` (0..1 tiles): warm beige with soft mottling and fine grain.
fn sandstone(noise: &Noise, grain: &Noise, uv: Vec2) -> Vec3 {
    let mottle = noise.fbm(uv, 3);
    let fine = grain.fbm(uv, 1);
    let base = mix(
        Vec3::new(0.42, 0.34, 0.24),
        Vec3::new(0.62, 0.53, 0.40),
        mottle,
    );
    base * (0.88 + 0.24 * fine)
}

/// Running-bond bricks: 4 bricks by 16 courses per tile, 7-texel mortar joints, each brick
/// its own shade of red-brown with grain.
pub(super) fn bricks(seed: u64) -> TextureImage {
    let (brick, joint) = (Vec2::new(256.0, 64.0), 7.0);
    let grain = Noise::new(seed ^ 0xB1, 64);
    let mortar_noise = Noise::new(seed ^ 0xB2, 32);
    let canvas = Canvas::from_fn(LARGE, |x, y| {
        let course = (y / brick.y).floor();
        let shift = if course as i32 % 2 == 1 {
            brick.x * 0.5
        } else {
            0.0
        };
        let (distance, index) = cell_interior(Vec2::new(x + shift, y), brick, joint);
        let column = (index.x as i32).rem_euclid(4);
        let shade = hash2(seed, column, index.y as i32);
        let uv = Vec2::new(x, y) / LARGE as f32;
        let g = grain.fbm(uv, 2);
        let red = mix(
            Vec3::new(0.30, 0.09, 0.05),
            Vec3::new(0.52, 0.20, 0.10),
            shade,
        );
        // Darker, burnt edges fade in over the outer 6 texels of a brick.
        let edge = (distance / 6.0).clamp(0.0, 1.0);
        let brick_rgb = red * (0.7 + 0.45 * g) * (0.8 + 0.2 * edge);
        let mortar = Vec3::new(0.50, 0.47, 0.42) * (0.8 + 0.3 * mortar_noise.fbm(uv, 2));
        opaque(mix(mortar, brick_rgb, interior_coverage(distance)))
    });
    canvas.into_texture("atrium bricks")
}

/// Polished marble floor: a 4 x 4 checker of veined white and green-black tiles with
/// 3-texel grout lines.
pub(super) fn marble_tiles(seed: u64) -> TextureImage {
    let tile = Vec2::splat(256.0);
    let warp = Noise::new(seed ^ 0xF1, 4);
    let cloud = Noise::new(seed ^ 0xF2, 8);
    let canvas = Canvas::from_fn(LARGE, |x, y| {
        let (distance, index) = cell_interior(Vec2::new(x, y), tile, 3.0);
        let uv = Vec2::new(x, y) / LARGE as f32;
        let dark = (index.x + index.y) as i32 % 2 == 1;
        // Veins: thin level lines of a warped diagonal ramp.
        let w = warp.fbm(uv, 3);
        let ramp = (uv.x * 3.0 + uv.y * 2.0 + w * 2.5) * 6.0;
        let vein = 1.0 - ((ramp - ramp.round()).abs() * 14.0).min(1.0);
        let c = cloud.fbm(uv, 2);
        let rgb = if dark {
            mix(
                Vec3::new(0.010, 0.025, 0.020),
                Vec3::new(0.04, 0.08, 0.06),
                c,
            ) + Vec3::new(0.30, 0.34, 0.30) * vein * vein
        } else {
            mix(Vec3::new(0.62, 0.60, 0.56), Vec3::new(0.80, 0.78, 0.74), c)
                - Vec3::new(0.30, 0.30, 0.28) * vein * vein
        };
        let grout = Vec3::new(0.08, 0.08, 0.07);
        opaque(mix(grout, rgb, interior_coverage(distance)))
    });
    canvas.into_texture("atrium marble tiles")
}

/// Plain sandstone for columns, arches and mouldings.
pub(super) fn stone(seed: u64) -> TextureImage {
    let (noise, grain) = (Noise::new(seed ^ 0x51, 6), Noise::new(seed ^ 0x52, 128));
    let canvas = Canvas::from_fn(LARGE, |x, y| {
        opaque(sandstone(&noise, &grain, Vec2::new(x, y) / LARGE as f32))
    });
    canvas.into_texture("atrium sandstone")
}

/// The inscription band: sandstone with a moulding line top and bottom and three lines of
/// carved glyphs (dark strokes with a light lower lip). The texture is stretched 2:1 across
/// the band, so glyphs are painted half as wide as they will appear.
pub(super) fn inscription(seed: u64) -> TextureImage {
    let (noise, grain) = (Noise::new(seed ^ 0x61, 6), Noise::new(seed ^ 0x62, 128));
    let mut canvas = Canvas::from_fn(LARGE, |x, y| {
        opaque(sandstone(&noise, &grain, Vec2::new(x, y) / LARGE as f32))
    });
    let groove = [0.10, 0.08, 0.06, 1.0];
    let lip = [0.75, 0.68, 0.55, 1.0];
    for y in [40.0, 980.0] {
        canvas.rect(Vec2::new(0.0, y), Vec2::new(LARGE as f32, y + 6.0), groove);
        canvas.rect(
            Vec2::new(0.0, y + 6.0),
            Vec2::new(LARGE as f32, y + 9.0),
            lip,
        );
    }
    let mut rng = Rng::new(seed, 0x1A5C);
    let text = TextBlock {
        origin: Vec2::new(24.0, 130.0),
        width: LARGE as f32 - 48.0,
        lines: 3,
        glyph_height: 190.0,
        line_pitch: 280.0,
        x_scale: 0.5,
        ink: groove,
        relief: Some(lip),
    };
    text.paint(&mut canvas, &mut rng);
    canvas.into_texture("atrium inscription")
}

/// A cork noticeboard in a dark wooden frame with pinned sheets of small print.
pub(super) fn noticeboard(seed: u64) -> TextureImage {
    let cork = Noise::new(seed ^ 0x71, 96);
    let size = LARGE as f32;
    let frame = 36.0;
    let mut canvas = Canvas::from_fn(LARGE, |x, y| {
        let border = x.min(y).min(size - x).min(size - y);
        if border < frame {
            opaque(Vec3::new(0.08, 0.045, 0.025) * (0.8 + 0.4 * (border / frame)))
        } else {
            let c = cork.fbm(Vec2::new(x, y) / size, 2);
            opaque(mix(
                Vec3::new(0.25, 0.13, 0.05),
                Vec3::new(0.45, 0.27, 0.12),
                c,
            ))
        }
    });
    let mut rng = Rng::new(seed, 0x7077);
    let ink = [0.02, 0.02, 0.03, 1.0];
    // Sheets in a loose 3 x 2 arrangement, each with a heading and a paragraph.
    for row in 0..2 {
        for column in 0..3 {
            let cell = Vec2::new(column as f32, row as f32) * Vec2::new(310.0, 470.0)
                + Vec2::splat(frame + 20.0);
            let paper_size = Vec2::new(rng.range(230.0, 280.0), rng.range(300.0, 420.0));
            let at = cell + Vec2::new(rng.range(0.0, 20.0), rng.range(0.0, 20.0));
            let paper = mix(
                Vec3::new(0.80, 0.78, 0.70),
                Vec3::new(0.90, 0.88, 0.84),
                rng.unit(),
            );
            canvas.rect(
                at + Vec2::new(5.0, 6.0),
                at + paper_size + Vec2::new(5.0, 6.0),
                [0.0, 0.0, 0.0, 0.35],
            );
            canvas.rect(at, at + paper_size, opaque(paper));
            let heading = TextBlock {
                origin: at + Vec2::new(16.0, 18.0),
                width: paper_size.x - 32.0,
                lines: 1,
                glyph_height: 18.0,
                line_pitch: 26.0,
                x_scale: 1.0,
                ink,
                relief: None,
            };
            heading.paint(&mut canvas, &mut rng);
            let lines = ((paper_size.y - 70.0) / 13.0) as u32;
            let body = TextBlock {
                origin: at + Vec2::new(16.0, 56.0),
                width: paper_size.x - 32.0,
                lines,
                glyph_height: 7.0,
                line_pitch: 13.0,
                x_scale: 1.0,
                ink,
                relief: None,
            };
            body.paint(&mut canvas, &mut rng);
            let pin = at + Vec2::new(paper_size.x * 0.5, 8.0);
            let pin_color = [[0.6, 0.03, 0.02, 1.0], [0.02, 0.1, 0.6, 1.0]][rng.below(2)];
            canvas.shape(
                pin - Vec2::splat(8.0),
                pin + Vec2::splat(8.0),
                |p| p.distance(pin) - 6.0,
                |_, _| pin_color,
            );
        }
    }
    canvas.into_texture("atrium noticeboard")
}

/// A leafy sprig on a transparent background: a curved main stem with side shoots, each
/// carrying alternate pointed leaves with a lighter midrib. Transparent texels carry a dark
/// green so that filtering at the alpha edge does not halo.
pub(super) fn leaves(seed: u64) -> TextureImage {
    let size = SMALL as f32;
    let mut canvas = Canvas::new(SMALL, [0.02, 0.05, 0.01, 0.0]);
    let mut rng = Rng::new(seed, 0x1EAF);
    let stem_color = [0.10, 0.08, 0.03, 1.0];
    // Stems as (start, end, control) quadratic curves, the main one first.
    let main_top = Vec2::new(size * rng.range(0.4, 0.6), size * 0.06);
    let mut stems = vec![(
        Vec2::new(size * 0.5, size),
        main_top,
        Vec2::new(size * rng.range(0.3, 0.7), size * 0.5),
    )];
    for k in 0..6 {
        let t = 0.25 + k as f32 * 0.11;
        let (a, b, c) = stems[0];
        let start = quadratic(a, c, b, t);
        let side = if k % 2 == 0 { -1.0 } else { 1.0 };
        let end = start
            + Vec2::new(
                side * rng.range(0.25, 0.4) * size,
                -rng.range(0.1, 0.25) * size,
            );
        let control = (start + end) * 0.5 + Vec2::new(0.0, rng.range(0.0, 0.08) * size);
        stems.push((start, end, control));
    }
    for &(a, b, c) in &stems {
        const STEPS: u32 = 12;
        for s in 0..STEPS {
            let (p, q) = (
                quadratic(a, c, b, s as f32 / STEPS as f32),
                quadratic(a, c, b, (s + 1) as f32 / STEPS as f32),
            );
            canvas.stroke(p, q, 3.0, stem_color);
        }
    }
    for (index, &(a, b, c)) in stems.iter().enumerate() {
        let count = if index == 0 { 9 } else { 6 };
        for k in 0..count {
            let t = 0.15 + 0.85 * (k as f32 + 0.5) / count as f32;
            let base = quadratic(a, c, b, t);
            let tangent = (quadratic(a, c, b, (t + 0.01).min(1.0)) - quadratic(a, c, b, t - 0.01))
                .normalize_or(Vec2::NEG_Y);
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let angle = side * rng.range(0.6, 1.0);
            let direction = Vec2::from_angle(angle).rotate(tangent);
            let length = rng.range(55.0, 90.0) * if index == 0 { 1.15 } else { 1.0 };
            let green = mix(
                Vec3::new(0.04, 0.16, 0.02),
                Vec3::new(0.16, 0.34, 0.05),
                rng.unit(),
            );
            leaf(&mut canvas, base, direction, length, length * 0.36, green);
        }
    }
    canvas.into_texture("atrium leaves")
}

/// Point on the quadratic Bezier curve from `a` to `b` with control `c` at parameter `t`.
fn quadratic(a: Vec2, c: Vec2, b: Vec2, t: f32) -> Vec2 {
    let t = t.clamp(0.0, 1.0);
    a * (1.0 - t) * (1.0 - t) + c * 2.0 * t * (1.0 - t) + b * t * t
}

/// A pointed leaf from `base` along unit `direction`: half-width `width / 2 * sin(pi s)^0.7`
/// at fraction `s` of its length, shaded lighter along the midrib and darker to the tip.
fn leaf(canvas: &mut Canvas, base: Vec2, direction: Vec2, length: f32, width: f32, green: Vec3) {
    let across = direction.perp();
    let local = move |p: Vec2| {
        let d = p - base;
        (d.dot(direction), d.dot(across))
    };
    let distance = move |p: Vec2| {
        let (s, t) = local(p);
        let f = (s / length).clamp(0.0, 1.0);
        let half = width * 0.5 * (std::f32::consts::PI * f).sin().powf(0.7);
        // Beyond the ends, the distance to the tip or the base point.
        let outside = (-s).max(s - length).max(0.0);
        (t.abs() - half).max(outside)
    };
    let color = move |p: Vec2, _d: f32| -> Rgba {
        let (s, t) = local(p);
        let midrib = (1.0 - t.abs() / 1.5).clamp(0.0, 1.0);
        let rgb = green * (1.1 - 0.35 * (s / length).clamp(0.0, 1.0))
            + Vec3::new(0.10, 0.12, 0.04) * midrib;
        opaque(rgb)
    };
    let reach = Vec2::splat(length + 2.0);
    canvas.shape(base - reach, base + reach, distance, color);
}

/// Galvanised chain-link: 8 diamonds across the tile, wires about 3 texels wide.
pub(super) fn chain_link() -> TextureImage {
    diamond_mesh(
        SMALL,
        8,
        3.0,
        Vec3::new(0.55, 0.57, 0.60),
        "atrium chain link",
    )
}

/// A dark iron lattice screen: 4 diamonds across the tile, bars 14 texels wide.
pub(super) fn lattice() -> TextureImage {
    diamond_mesh(
        SMALL,
        4,
        14.0,
        Vec3::new(0.09, 0.07, 0.05),
        "atrium lattice",
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn textures_have_their_sizes_and_alpha() {
        for (texture, size, masked) in [
            (bricks(1), LARGE, false),
            (marble_tiles(1), LARGE, false),
            (stone(1), LARGE, false),
            (inscription(1), LARGE, false),
            (noticeboard(1), LARGE, false),
            (leaves(1), SMALL, true),
            (chain_link(), SMALL, true),
            (lattice(), SMALL, true),
        ] {
            assert_eq!(
                texture.image.dimensions(),
                (size, size),
                "{}",
                texture.label
            );
            let transparent = texture.image.pixels().filter(|p| p[3] < 128).count();
            assert_eq!(transparent > 0, masked, "{}", texture.label);
        }
    }

    #[test]
    fn leaves_cover_a_good_part_of_the_card() {
        let texture = leaves(3);
        let opaque = texture.image.pixels().filter(|p| p[3] >= 128).count();
        let fraction = opaque as f32 / (SMALL * SMALL) as f32;
        assert!((0.2..0.8).contains(&fraction), "{fraction}");
        assert_eq!(leaves(3).image, texture.image);
    }
}
