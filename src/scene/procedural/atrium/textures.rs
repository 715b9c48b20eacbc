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
    Canvas, Noise, Rgba, TextBlock, diamond_mesh, distance_to_integer, floor, hash2, mix, opaque,
    texture_from_fn,
};

/// Side of the large (1024) textures.
pub(super) const LARGE: u32 = 1024;
/// Side of the small (512) textures.
pub(super) const SMALL: u32 = 512;

/// Every atrium texture, in the order the materials index them, painted in parallel (each
/// is independent and takes tens of milliseconds).
pub(super) fn all(seed: u64) -> Vec<TextureImage> {
    let painters: [fn(u64) -> TextureImage; 8] = [
        marble_tiles,
        bricks,
        stone,
        inscription,
        noticeboard,
        leaves,
        chain_link,
        lattice,
    ];
    std::thread::scope(|scope| {
        let handles = painters.map(|paint| scope.spawn(move || paint(seed)));
        // A painter only panics on a bug; re-raise it on the caller's thread.
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            })
            .collect()
    })
}

/// Distance (pixels, positive inside) from `p` to the border of the cell of size `cell`
/// it falls in, less half a joint of width `joint`; with the cell's index.
fn cell_interior(p: Vec2, cell: Vec2, joint: f32) -> (f32, Vec2) {
    let index = Vec2::new(floor(p.x / cell.x), floor(p.y / cell.y));
    let local = p - index * cell;
    let edge = local.min(cell - local);
    (edge.min_element() - joint * 0.5, index)
}

/// Coverage of a cell's interior from its signed distance (1 inside, 0 in the joint).
fn interior_coverage(distance: f32) -> f32 {
    (distance + 0.5).clamp(0.0, 1.0)
}

/// Index of the texel whose centre is (x, y) in a large texture.
fn texel(x: f32, y: f32) -> usize {
    y as usize * LARGE as usize + x as usize
}

/// Sandstone: warm beige with soft mottling and fine grain; returns the texel function.
fn sandstone(seed: u64) -> impl Fn(f32, f32) -> Rgba {
    let mottle = Noise::new(seed ^ 0x51, 8, 3).fbm(LARGE);
    let grain = Noise::new(seed ^ 0x52, 128, 1).fbm(LARGE);
    move |x, y| {
        let i = texel(x, y);
        let base = mix(
            Vec3::new(0.42, 0.34, 0.24),
            Vec3::new(0.62, 0.53, 0.40),
            mottle[i],
        );
        opaque(base * (0.88 + 0.24 * grain[i]))
    }
}

/// Running-bond bricks: 4 bricks by 16 courses per tile, 7-texel mortar joints, each brick
/// its own shade of red-brown with grain.
pub(super) fn bricks(seed: u64) -> TextureImage {
    let (brick, joint) = (Vec2::new(256.0, 64.0), 7.0);
    let grain = Noise::new(seed ^ 0xB1, 64, 2).fbm(LARGE);
    let mortar_noise = Noise::new(seed ^ 0xB2, 32, 2).fbm(LARGE);
    texture_from_fn(LARGE, "atrium bricks", |x, y| {
        let course = floor(y / brick.y);
        let shift = if course as i32 % 2 == 1 {
            brick.x * 0.5
        } else {
            0.0
        };
        let (distance, index) = cell_interior(Vec2::new(x + shift, y), brick, joint);
        let column = (index.x as i32).rem_euclid(4);
        let shade = hash2(seed, column, index.y as i32);
        let g = grain[texel(x, y)];
        let red = mix(
            Vec3::new(0.30, 0.09, 0.05),
            Vec3::new(0.52, 0.20, 0.10),
            shade,
        );
        // Darker, burnt edges fade in over the outer 6 texels of a brick.
        let edge = (distance / 6.0).clamp(0.0, 1.0);
        let brick_rgb = red * (0.7 + 0.45 * g) * (0.8 + 0.2 * edge);
        let mortar = Vec3::new(0.50, 0.47, 0.42) * (0.8 + 0.3 * mortar_noise[texel(x, y)]);
        opaque(mix(mortar, brick_rgb, interior_coverage(distance)))
    })
}

/// Polished marble floor: a 4 x 4 checker of veined white and green-black tiles with
/// 3-texel grout lines. Veins are the classic turbulence marble: thin creases where a
/// diagonal ramp, disturbed by turbulence, crosses whole numbers; each tile is cut from a
/// different part of the block.
pub(super) fn marble_tiles(seed: u64) -> TextureImage {
    let tile = Vec2::splat(256.0);
    let turbulence = Noise::new(seed ^ 0xF1, 4, 4).turbulence(LARGE);
    let cloud = Noise::new(seed ^ 0xF2, 8, 2).fbm(LARGE);
    let n = LARGE as usize;
    texture_from_fn(LARGE, "atrium marble tiles", |x, y| {
        let (distance, index) = cell_interior(Vec2::new(x, y), tile, 3.0);
        let uv = Vec2::new(x, y) / LARGE as f32;
        let dark = (index.x + index.y) as i32 % 2 == 1;
        let cut = hash2(seed, index.x as i32, index.y as i32) * 7.0;
        let t = turbulence[texel(x, y)];
        let ramp = uv.x * 2.0 + uv.y * 1.3 + cut + 2.2 * t;
        let crease =
            |r: f32, sharpness: f32| (1.0 - (distance_to_integer(r) * sharpness).min(1.0)).powi(3);
        let vein = crease(ramp * 2.0, 9.0) + 0.5 * crease(ramp * 5.3 + 0.37, 16.0);
        // Each tile reads the cloud field from its own offset.
        let shift = (cut * 131.0) as usize;
        let c = cloud[(y as usize + shift) % n * n + (x as usize + shift) % n];
        let rgb = if dark {
            mix(
                Vec3::new(0.008, 0.03, 0.022),
                Vec3::new(0.035, 0.085, 0.06),
                c,
            ) + Vec3::new(0.25, 0.30, 0.26) * vein
        } else {
            mix(Vec3::new(0.60, 0.59, 0.55), Vec3::new(0.80, 0.79, 0.75), c)
                - Vec3::new(0.32, 0.32, 0.30) * vein
        };
        let grout = Vec3::new(0.08, 0.08, 0.07);
        opaque(mix(grout, rgb.max(Vec3::ZERO), interior_coverage(distance)))
    })
}

/// Plain sandstone for columns, arches and mouldings.
pub(super) fn stone(seed: u64) -> TextureImage {
    texture_from_fn(LARGE, "atrium sandstone", sandstone(seed))
}

/// The inscription band: sandstone with a moulding line top and bottom and three lines of
/// carved glyphs (dark strokes with a light lower lip). The texture is stretched 2:1 across
/// the band, so glyphs are painted half as wide as they will appear.
pub(super) fn inscription(seed: u64) -> TextureImage {
    let mut canvas = Canvas::from_fn(LARGE, sandstone(seed ^ 0x1A5C));
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
        full_lines: true,
        ink: groove,
        relief: Some(lip),
    };
    text.paint(&mut canvas, &mut rng);
    canvas.into_texture("atrium inscription")
}

/// A cork noticeboard in a dark wooden frame, covered with pinned notes of small print:
/// sheets and cards in a few paper colours, each with a heading and a paragraph.
pub(super) fn noticeboard(seed: u64) -> TextureImage {
    let cork = Noise::new(seed ^ 0x71, 128, 2).fbm(LARGE);
    let size = LARGE as f32;
    let frame = 36.0;
    let mut canvas = Canvas::from_fn(LARGE, |x, y| {
        let border = x.min(y).min(size - x).min(size - y);
        if border < frame {
            opaque(Vec3::new(0.08, 0.045, 0.025) * (0.8 + 0.4 * (border / frame)))
        } else {
            let c = cork[texel(x, y)];
            opaque(mix(
                Vec3::new(0.22, 0.11, 0.04),
                Vec3::new(0.45, 0.27, 0.12),
                c,
            ))
        }
    });
    let mut rng = Rng::new(seed, 0x7077);
    let ink = [0.02, 0.02, 0.03, 1.0];
    let papers = [
        Vec3::new(0.86, 0.85, 0.80),
        Vec3::new(0.90, 0.82, 0.35),
        Vec3::new(0.55, 0.72, 0.85),
        Vec3::new(0.88, 0.60, 0.62),
        Vec3::new(0.80, 0.78, 0.70),
    ];
    let (columns, rows) = (4, 3);
    let cell = Vec2::new(
        (size - 2.0 * frame) / columns as f32,
        (size - 2.0 * frame) / rows as f32,
    );
    for row in 0..rows {
        for column in 0..columns {
            let paper_size = cell * Vec2::new(rng.range(0.7, 0.95), rng.range(0.6, 0.92));
            let slack = cell - paper_size;
            let at = Vec2::splat(frame)
                + Vec2::new(column as f32, row as f32) * cell
                + slack * Vec2::new(rng.unit(), rng.unit());
            let paper = papers[rng.below(papers.len())];
            canvas.rect(
                at + Vec2::new(4.0, 5.0),
                at + paper_size + Vec2::new(4.0, 5.0),
                [0.0, 0.0, 0.0, 0.35],
            );
            canvas.rect(at, at + paper_size, opaque(paper));
            let margin = 12.0;
            let heading_height = rng.range(12.0, 22.0);
            let heading = TextBlock {
                origin: at + Vec2::new(margin, margin + 6.0),
                width: paper_size.x - 2.0 * margin,
                lines: 1,
                glyph_height: heading_height,
                line_pitch: heading_height * 1.4,
                x_scale: 1.0,
                full_lines: false,
                ink,
                relief: None,
            };
            heading.paint(&mut canvas, &mut rng);
            let body_top = margin + 12.0 + heading_height * 1.6;
            let pitch = rng.range(10.0, 14.0);
            let body = TextBlock {
                origin: at + Vec2::new(margin, body_top),
                width: paper_size.x - 2.0 * margin,
                lines: ((paper_size.y - body_top - margin) / pitch).max(0.0) as u32,
                glyph_height: pitch * 0.55,
                line_pitch: pitch,
                x_scale: 1.0,
                full_lines: false,
                ink,
                relief: None,
            };
            body.paint(&mut canvas, &mut rng);
            let pin = at + Vec2::new(paper_size.x * 0.5, 7.0);
            let pin_color = [
                [0.6, 0.03, 0.02, 1.0],
                [0.02, 0.1, 0.6, 1.0],
                [0.05, 0.4, 0.05, 1.0],
            ][rng.below(3)];
            canvas.shape(
                pin - Vec2::splat(8.0),
                pin + Vec2::splat(8.0),
                |p| p.distance(pin) - 5.5,
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
        let count = if index == 0 { 11 } else { 7 };
        for k in 0..count {
            let t = 0.15 + 0.85 * (k as f32 + 0.5) / count as f32;
            let base = quadratic(a, c, b, t);
            let tangent = (quadratic(a, c, b, (t + 0.01).min(1.0)) - quadratic(a, c, b, t - 0.01))
                .normalize_or(Vec2::NEG_Y);
            let side = if k % 2 == 0 { 1.0 } else { -1.0 };
            let angle = side * rng.range(0.6, 1.0);
            let direction = Vec2::from_angle(angle).rotate(tangent);
            let length = rng.range(60.0, 95.0) * if index == 0 { 1.15 } else { 1.0 };
            let green = mix(
                Vec3::new(0.04, 0.16, 0.02),
                Vec3::new(0.16, 0.34, 0.05),
                rng.unit(),
            );
            leaf(&mut canvas, base, direction, length, length * 0.42, green);
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
        // sin(pi) is a hair below zero in f32: clamp before the power.
        let half = width * 0.5 * (std::f32::consts::PI * f).sin().max(0.0).powf(0.7);
        // Intersection with the slab between the base and the tip (negative inside it), so
        // that nothing leaks past the ends.
        (t.abs() - half).max((-s).max(s - length))
    };
    let color = move |p: Vec2, _d: f32| -> Rgba {
        let (s, t) = local(p);
        let midrib = (1.0 - t.abs() / 1.5).clamp(0.0, 1.0);
        let rgb = green * (1.1 - 0.35 * (s / length).clamp(0.0, 1.0))
            + Vec3::new(0.10, 0.12, 0.04) * midrib;
        opaque(rgb)
    };
    // Bounding box of the leaf's rectangle, plus a pixel for the antialiased rim.
    let corners = [base, base + direction * length]
        .map(|p| [p + across * width * 0.5, p - across * width * 0.5]);
    let (lo, hi) = corners.iter().flatten().fold(
        (Vec2::splat(f32::MAX), Vec2::splat(f32::MIN)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    canvas.shape(lo - Vec2::ONE, hi + Vec2::ONE, distance, color);
}

/// Galvanised chain-link: 48 diamonds across the tile, wires 1.8 texels wide. The tile is
/// meant to cover about 3 m, so that at the fence's viewing distance a texel is about a
/// pixel: alpha-tested mips of thinner wires would fade below the cutoff and vanish.
pub(super) fn chain_link(_seed: u64) -> TextureImage {
    diamond_mesh(
        SMALL,
        48,
        1.8,
        Vec3::new(0.55, 0.57, 0.60),
        "atrium chain link",
    )
}

/// A dark iron lattice screen: 24 diamonds across the tile, bars 4.5 texels wide (about
/// 4 cm for a tile of 4.3 m).
pub(super) fn lattice(_seed: u64) -> TextureImage {
    diamond_mesh(
        SMALL,
        24,
        4.5,
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
            (chain_link(1), SMALL, true),
            (lattice(1), SMALL, true),
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
        let alpha = |p: &image::Rgba<u8>| p[3];
        let solid = texture.image.pixels().filter(|p| alpha(p) == 255).count();
        let rim = texture
            .image
            .pixels()
            .filter(|p| (1..255).contains(&alpha(p)))
            .count();
        let fraction = solid as f32 / (SMALL * SMALL) as f32;
        assert!((0.2..0.8).contains(&fraction), "{fraction}");
        // Leaves are solid with an antialiased rim, not translucent.
        assert!(rim * 4 < solid, "{rim} rim texels for {solid} solid ones");
        assert_eq!(leaves(3).image, texture.image);
    }
}
