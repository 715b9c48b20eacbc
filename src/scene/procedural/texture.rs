//! Texture painting for the procedural scenes: a linear-light RGBA [`Canvas`] with
//! antialiased primitives, tileable value noise, and the generators several scenes share
//! (glyph-like text lines, diamond wire mesh).
//!
//! Pixels are painted in linear RGB with straight (non-premultiplied) alpha and encoded to
//! sRGB bytes once at the end through a lookup table, so that coverage-weighted edges blend
//! in linear light like the GPU does. Shapes are antialiased analytically: axis-aligned
//! rectangles by their exact pixel overlap, other shapes by a signed distance in pixels
//! (coverage = clamp(0.5 - distance)). Texture content must not alias on its own: the
//! scenes test the renderer's antialiasing, not the texture generator's.

use std::sync::OnceLock;

use glam::{Vec2, Vec3};

use super::rng::Rng;
use crate::scene::TextureImage;

/// Linear RGB plus alpha.
pub(crate) type Rgba = [f32; 4];

/// Opaque linear colour.
pub(crate) fn opaque(rgb: Vec3) -> Rgba {
    [rgb.x, rgb.y, rgb.z, 1.0]
}

/// sRGB-encoded byte of a linear value in 0..1 (values outside are clamped).
pub(crate) fn encode_srgb(linear: f32) -> u8 {
    const STEPS: usize = 1 << 14;
    static TABLE: OnceLock<Vec<u8>> = OnceLock::new();
    let table = TABLE.get_or_init(|| {
        (0..STEPS)
            .map(|i| {
                let c = i as f32 / (STEPS - 1) as f32;
                let s = if c <= 0.003_130_8 {
                    12.92 * c
                } else {
                    1.055 * c.powf(1.0 / 2.4) - 0.055
                };
                (s * 255.0).round() as u8
            })
            .collect()
    });
    table[(linear.clamp(0.0, 1.0) * (STEPS - 1) as f32 + 0.5) as usize]
}

/// A square RGBA image in linear light being painted.
pub(crate) struct Canvas {
    size: u32,
    pixels: Vec<Rgba>,
}

impl Canvas {
    /// A canvas of `size x size` pixels filled with `color`.
    pub(crate) fn new(size: u32, color: Rgba) -> Self {
        Self {
            size,
            pixels: vec![color; (size * size) as usize],
        }
    }

    /// A canvas whose pixel at (x, y) (pixel centres at half-integers) is `f(x, y)`.
    pub(crate) fn from_fn(size: u32, mut f: impl FnMut(f32, f32) -> Rgba) -> Self {
        let mut pixels = Vec::with_capacity((size * size) as usize);
        for y in 0..size {
            for x in 0..size {
                pixels.push(f(x as f32 + 0.5, y as f32 + 0.5));
            }
        }
        Self { size, pixels }
    }

    /// Blends `color` over the pixel at (x, y) with weight `coverage` (0..1), on colour and
    /// alpha alike ("over" with straight alpha).
    fn blend(&mut self, x: u32, y: u32, color: Rgba, coverage: f32) {
        let a = color[3] * coverage;
        if a <= 0.0 {
            return;
        }
        let dst = &mut self.pixels[(y * self.size + x) as usize];
        let out_alpha = a + dst[3] * (1.0 - a);
        for c in 0..3 {
            let mixed = color[c] * a + dst[c] * dst[3] * (1.0 - a);
            dst[c] = if out_alpha > 0.0 {
                mixed / out_alpha
            } else {
                color[c]
            };
        }
        dst[3] = out_alpha;
    }

    /// Pixel range (clamped to the canvas) overlapping `lo..hi`.
    fn span(&self, lo: f32, hi: f32) -> std::ops::Range<u32> {
        let start = lo.floor().max(0.0) as u32;
        let end = (hi.ceil().max(0.0) as u32).min(self.size);
        start..end
    }

    /// Blends an axis-aligned rectangle (pixel units, exact area coverage).
    pub(crate) fn rect(&mut self, min: Vec2, max: Vec2, color: Rgba) {
        let overlap =
            |p: u32, lo: f32, hi: f32| (hi.min(p as f32 + 1.0) - lo.max(p as f32)).max(0.0);
        for y in self.span(min.y, max.y) {
            let cy = overlap(y, min.y, max.y);
            for x in self.span(min.x, max.x) {
                self.blend(x, y, color, cy * overlap(x, min.x, max.x));
            }
        }
    }

    /// Blends a shape given by its signed distance in pixels (negative inside) over the
    /// pixels of the box `min..max`; `color(p, distance)` may shade the interior.
    pub(crate) fn shape(
        &mut self,
        min: Vec2,
        max: Vec2,
        distance: impl Fn(Vec2) -> f32,
        color: impl Fn(Vec2, f32) -> Rgba,
    ) {
        for y in self.span(min.y, max.y) {
            for x in self.span(min.x, max.x) {
                let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let d = distance(p);
                let coverage = (0.5 - d).clamp(0.0, 1.0);
                if coverage > 0.0 {
                    self.blend(x, y, color(p, d), coverage);
                }
            }
        }
    }

    /// Blends a round-capped stroke from `a` to `b` of width `width` pixels.
    pub(crate) fn stroke(&mut self, a: Vec2, b: Vec2, width: f32, color: Rgba) {
        let pad = Vec2::splat(width * 0.5 + 1.0);
        let ab = b - a;
        let length2 = ab.length_squared().max(1e-12);
        let distance = |p: Vec2| {
            let t = ((p - a).dot(ab) / length2).clamp(0.0, 1.0);
            p.distance(a + ab * t) - width * 0.5
        };
        self.shape(a.min(b) - pad, a.max(b) + pad, distance, |_, _| color);
    }

    /// The finished texture, sRGB-encoded.
    pub(crate) fn into_texture(self, label: &str) -> TextureImage {
        let mut image = image::RgbaImage::new(self.size, self.size);
        for (dst, src) in image.chunks_exact_mut(4).zip(&self.pixels) {
            dst[0] = encode_srgb(src[0]);
            dst[1] = encode_srgb(src[1]);
            dst[2] = encode_srgb(src[2]);
            dst[3] = (src[3].clamp(0.0, 1.0) * 255.0).round() as u8;
        }
        TextureImage {
            label: label.to_owned(),
            image,
        }
    }
}

/// A random value in 0..1 for an integer pair (per-brick colours, per-tile variation).
pub(crate) fn hash2(seed: u64, x: i32, y: i32) -> f32 {
    let key = (u64::from(x as u32) << 32) | u64::from(y as u32);
    let mut h = seed ^ key.wrapping_mul(0x9E37_79B9_7F4A_7C15);
    h = (h ^ (h >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 32;
    (h & 0xFF_FFFF) as f32 / 0xFF_FFFF as f32
}

/// Tileable value noise: random values on an integer lattice that wraps every `period`
/// cells, smoothly interpolated.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Noise {
    seed: u64,
    period: i32,
}

impl Noise {
    /// Noise wrapping every `period` lattice cells.
    pub(crate) fn new(seed: u64, period: u32) -> Self {
        Self {
            seed,
            period: period.max(1) as i32,
        }
    }

    fn lattice(&self, x: i32, y: i32, period: i32) -> f32 {
        hash2(self.seed, x.rem_euclid(period), y.rem_euclid(period))
    }

    /// Noise in 0..1 at `p` in lattice units, with the lattice wrapping every `period` cells.
    fn sample(&self, p: Vec2, period: i32) -> f32 {
        let cell = p.floor();
        let f = p - cell;
        let s = f * f * (Vec2::splat(3.0) - 2.0 * f);
        let (x, y) = (cell.x as i32, cell.y as i32);
        let top = self.lattice(x, y, period) * (1.0 - s.x) + self.lattice(x + 1, y, period) * s.x;
        let bottom =
            self.lattice(x, y + 1, period) * (1.0 - s.x) + self.lattice(x + 1, y + 1, period) * s.x;
        top * (1.0 - s.y) + bottom * s.y
    }

    /// Fractal sum of `octaves` octaves at `uv` in 0..1 (tiles with period 1), normalised to
    /// 0..1. Octave k has `period << k` cells across the tile.
    pub(crate) fn fbm(&self, uv: Vec2, octaves: u32) -> f32 {
        let (mut sum, mut weight, mut total) = (0.0, 1.0, 0.0);
        for k in 0..octaves {
            let period = self.period << k;
            sum += weight * self.sample(uv * period as f32, period);
            total += weight;
            weight *= 0.5;
        }
        sum / total
    }
}

/// Linear interpolation between colours.
pub(crate) fn mix(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    a + (b - a) * t
}

/// Lines of glyph-like marks: "words" of random stroke glyphs (bars and ticks on a 3 x 5
/// grid, like a segment display), set left to right with ragged line ends. Looks like small
/// print from a distance and gives the renderer dense high-frequency detail.
pub(crate) struct TextBlock {
    /// Top-left of the block, pixels.
    pub(crate) origin: Vec2,
    /// Width available to a line, pixels.
    pub(crate) width: f32,
    /// Number of lines.
    pub(crate) lines: u32,
    /// Cap height of a glyph, pixels.
    pub(crate) glyph_height: f32,
    /// Baseline-to-baseline distance, pixels.
    pub(crate) line_pitch: f32,
    /// Horizontal scale of glyphs and vertical strokes (0.5 for a texture that will be
    /// stretched 2:1 across its surface).
    pub(crate) x_scale: f32,
    /// Ink colour.
    pub(crate) ink: Rgba,
    /// Colour drawn one pixel below each stroke first (a carved or embossed look), if any.
    pub(crate) relief: Option<Rgba>,
}

impl TextBlock {
    /// Paints the block with glyphs drawn from `rng`.
    pub(crate) fn paint(&self, canvas: &mut Canvas, rng: &mut Rng) {
        let h = self.glyph_height;
        let w = h * 0.62 * self.x_scale;
        let stroke = (h * 0.16 * self.x_scale).max(1.0);
        for line in 0..self.lines {
            let top = self.origin.y + line as f32 * self.line_pitch;
            // Ragged right margin; the last line of a paragraph stops short.
            let end = self.width
                * if line + 1 == self.lines {
                    rng.range(0.3, 0.7)
                } else {
                    rng.range(0.85, 1.0)
                };
            let mut x = 0.0;
            loop {
                let letters = 1 + rng.below(8);
                let word = letters as f32 * (w + stroke) - stroke;
                if x + word > end {
                    break;
                }
                for _ in 0..letters {
                    self.glyph(canvas, rng, Vec2::new(self.origin.x + x, top), w, h, stroke);
                    x += w + stroke;
                }
                x += w * 0.8;
            }
        }
    }

    /// One glyph: two to four strokes between nodes of a 3 x 5 grid.
    fn glyph(&self, canvas: &mut Canvas, rng: &mut Rng, at: Vec2, w: f32, h: f32, stroke: f32) {
        const SEGMENTS: [((u8, u8), (u8, u8)); 14] = [
            ((0, 0), (0, 2)),
            ((0, 2), (0, 4)),
            ((2, 0), (2, 2)),
            ((2, 2), (2, 4)),
            ((1, 0), (1, 4)),
            ((0, 0), (2, 0)),
            ((0, 2), (2, 2)),
            ((0, 4), (2, 4)),
            ((0, 0), (2, 4)),
            ((0, 4), (2, 0)),
            ((0, 0), (1, 2)),
            ((2, 0), (1, 2)),
            ((0, 4), (1, 2)),
            ((0, 0), (0, 4)),
        ];
        let node = |(i, j): (u8, u8)| {
            let inset = stroke * 0.5;
            at + Vec2::new(
                inset + f32::from(i) * 0.5 * (w - 2.0 * inset),
                inset + f32::from(j) * 0.25 * (h - 2.0 * inset),
            )
        };
        let strokes = 2 + rng.below(3);
        for _ in 0..strokes {
            let (a, b) = SEGMENTS[rng.below(SEGMENTS.len())];
            let (a, b) = (node(a), node(b));
            if let Some(relief) = self.relief {
                canvas.stroke(a + Vec2::Y, b + Vec2::Y, stroke, relief);
            }
            canvas.stroke(a, b, stroke, self.ink);
        }
    }
}

/// A tileable diamond wire mesh with alpha (chain-link fence, lattice screens): `cells`
/// diamonds across the tile, wires `wire` pixels wide running along both diagonals, shaded
/// from `color` at the wire's centre line to 60% at its edges so that the wires read round.
pub(crate) fn diamond_mesh(
    size: u32,
    cells: u32,
    wire: f32,
    color: Vec3,
    label: &str,
) -> TextureImage {
    // Wire centre lines satisfy x + y = k * pitch and x - y = k * pitch (pixels).
    let pitch = size as f32 / cells as f32;
    let half = wire * 0.5;
    let canvas = Canvas::from_fn(size, |x, y| {
        let distance = |s: f32| {
            let t = s / pitch;
            (t - t.round()).abs() * pitch * std::f32::consts::FRAC_1_SQRT_2
        };
        let d = distance(x + y).min(distance(x - y));
        let coverage = (half - d + 0.5).clamp(0.0, 1.0);
        let shade = 1.0 - 0.4 * (d / half.max(0.5)).min(1.0).powi(2);
        let rgb = color * shade;
        [rgb.x, rgb.y, rgb.z, coverage]
    });
    canvas.into_texture(label)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_encoding_matches_the_standard_curve() {
        assert_eq!(encode_srgb(0.0), 0);
        assert_eq!(encode_srgb(1.0), 255);
        assert_eq!(encode_srgb(0.5), 188);
        assert_eq!(encode_srgb(0.216), 128);
        assert_eq!(encode_srgb(-1.0), 0);
        assert_eq!(encode_srgb(f32::NAN), 0);
    }

    #[test]
    fn rect_coverage_is_the_overlap_area() {
        let mut canvas = Canvas::new(4, [1.0, 1.0, 1.0, 1.0]);
        canvas.rect(
            Vec2::new(1.0, 1.0),
            Vec2::new(2.5, 2.0),
            [0.0, 0.0, 0.0, 1.0],
        );
        let texture = canvas.into_texture("t");
        assert_eq!(texture.image.get_pixel(1, 1).0, [0, 0, 0, 255]);
        // Half covered: linear 0.5, sRGB 188.
        assert_eq!(texture.image.get_pixel(2, 1).0, [188, 188, 188, 255]);
        assert_eq!(texture.image.get_pixel(3, 1).0, [255, 255, 255, 255]);
    }

    #[test]
    fn noise_tiles_and_stays_in_range() {
        let noise = Noise::new(3, 4);
        for i in 0..50 {
            let p = Vec2::new(i as f32 * 0.137, i as f32 * 0.071);
            let v = noise.fbm(p, 3);
            assert!((0.0..=1.0).contains(&v));
            assert!((v - noise.fbm(p + Vec2::X, 3)).abs() < 1e-4);
            assert!((v - noise.fbm(p + Vec2::Y, 3)).abs() < 1e-4);
        }
    }

    #[test]
    fn diamond_mesh_tiles_seamlessly() {
        let texture = diamond_mesh(64, 4, 2.0, Vec3::ONE, "mesh");
        let image = &texture.image;
        // Shifting by one diamond (16 px) in x or y, wrapping at the edge, gives the same
        // image: the tile repeats without a seam.
        for y in 0..64 {
            for x in 0..64 {
                assert_eq!(image.get_pixel(x, y), image.get_pixel((x + 16) % 64, y));
                assert_eq!(image.get_pixel(x, y), image.get_pixel(x, (y + 16) % 64));
            }
        }
        let holes = image.pixels().filter(|p| p[3] == 0).count();
        assert!(holes > 64 * 64 / 3, "mostly open mesh: {holes}");
    }
}
