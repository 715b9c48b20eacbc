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

/// `x.floor()` for |x| < 2^31, without a libm call: the baseline x86-64 target has no
/// rounding instruction, and per-texel noise calls floor millions of times.
pub(crate) fn floor(x: f32) -> f32 {
    let truncated = x as i32 as f32;
    if truncated > x {
        truncated - 1.0
    } else {
        truncated
    }
}

/// Distance from `x` to the nearest integer (0..0.5).
pub(crate) fn distance_to_integer(x: f32) -> f32 {
    (x - floor(x + 0.5)).abs()
}

/// Entries of the linear-to-sRGB table: 2^14 steps keep every output within half a code
/// of the exact curve except in the darkest few codes, where it is within one.
const SRGB_STEPS: usize = 1 << 14;

/// The linear-to-sRGB encoding table, built on first use.
fn srgb_table() -> &'static [u8] {
    static TABLE: OnceLock<Vec<u8>> = OnceLock::new();
    TABLE.get_or_init(|| {
        (0..SRGB_STEPS)
            .map(|i| crate::srgb::encode_byte(i as f32 / (SRGB_STEPS - 1) as f32))
            .collect()
    })
}

/// Encodes with a table from [`srgb_table`]; values outside 0..1 (and NaN) are clamped.
fn encode_with(table: &[u8], linear: f32) -> u8 {
    table[(linear.clamp(0.0, 1.0) * (SRGB_STEPS - 1) as f32 + 0.5) as usize]
}

/// sRGB-encoded byte of a linear value in 0..1 (values outside are clamped).
pub(crate) fn encode_srgb(linear: f32) -> u8 {
    encode_with(srgb_table(), linear)
}

/// One texel as stored: sRGB-encoded colour, linear alpha.
fn encode_pixel(table: &[u8], rgba: Rgba, dst: &mut [u8]) {
    dst[0] = encode_with(table, rgba[0]);
    dst[1] = encode_with(table, rgba[1]);
    dst[2] = encode_with(table, rgba[2]);
    dst[3] = (rgba[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
}

/// A texture whose texel at (x, y) (centres at half-integers) is `f(x, y)`, encoded as it
/// is computed: textures that need no painting on top skip the linear canvas, which halves
/// their cost (the canvas is 16 bytes a texel of memory traffic).
pub(crate) fn texture_from_fn(
    size: u32,
    label: &str,
    mut f: impl FnMut(f32, f32) -> Rgba,
) -> TextureImage {
    let mut image = image::RgbaImage::new(size, size);
    let table = srgb_table();
    for (y, row) in image.chunks_exact_mut(size as usize * 4).enumerate() {
        for (x, dst) in row.chunks_exact_mut(4).enumerate() {
            encode_pixel(table, f(x as f32 + 0.5, y as f32 + 0.5), dst);
        }
    }
    TextureImage {
        label: label.to_owned(),
        image,
    }
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
        let table = srgb_table();
        for (dst, &src) in image.chunks_exact_mut(4).zip(&self.pixels) {
            encode_pixel(table, src, dst);
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

/// One octave of tileable value noise: random values on a `period x period` lattice that
/// wraps, smoothly (smoothstep) interpolated.
struct Lattice {
    period: usize,
    values: Vec<f32>,
}

/// Where a pixel centre falls between lattice lines along one axis: the two lattice
/// indices and the smoothstep weight of the second.
fn lattice_steps(size: usize, period: usize) -> Vec<(usize, usize, f32)> {
    let mask = period - 1;
    (0..size)
        .map(|x| {
            let p = (x as f32 + 0.5) * period as f32 / size as f32;
            let cell = floor(p);
            let f = p - cell;
            let i = cell as usize & mask;
            (i, (i + 1) & mask, f * f * (3.0 - 2.0 * f))
        })
        .collect()
}

impl Lattice {
    fn new(seed: u64, period: usize) -> Self {
        let values = (0..period * period)
            .map(|i| hash2(seed, (i % period) as i32, (i / period) as i32))
            .collect();
        Self { period, values }
    }

    /// Adds `weight * fold(noise)` at every pixel centre of a `size x size` tile to `out`.
    /// Interpolation is separable: each image row first blends two lattice rows, then each
    /// pixel blends two entries of that blended row.
    fn accumulate(&self, size: usize, weight: f32, fold: impl Fn(f32) -> f32, out: &mut [f32]) {
        let steps = lattice_steps(size, self.period);
        let mut row = vec![0.0; self.period];
        for (y, &(y0, y1, sy)) in steps.iter().enumerate() {
            let (a, b) = (
                &self.values[y0 * self.period..],
                &self.values[y1 * self.period..],
            );
            for (i, r) in row.iter_mut().enumerate() {
                *r = a[i] + (b[i] - a[i]) * sy;
            }
            for (o, &(x0, x1, sx)) in out[y * size..(y + 1) * size].iter_mut().zip(&steps) {
                *o += weight * fold(row[x0] + (row[x1] - row[x0]) * sx);
            }
        }
    }
}

/// Tileable fractal value noise: octave k has `period << k` lattice cells across the tile
/// and weight 2^-k. Generated as whole fields (one value per texel), which costs a couple of
/// nanoseconds per texel and octave.
pub(crate) struct Noise {
    octaves: Vec<Lattice>,
}

impl Noise {
    /// Noise of `octaves` octaves whose first has `period` cells across the tile (rounded up
    /// to a power of two).
    pub(crate) fn new(seed: u64, period: u32, octaves: u32) -> Self {
        let base = period.max(1).next_power_of_two() as usize;
        Self {
            octaves: (0..octaves.max(1))
                .map(|k| Lattice::new(seed.wrapping_add(u64::from(k)), base << k))
                .collect(),
        }
    }

    /// Weighted sum of `fold(octave)` at every texel of a `size x size` tile (row-major),
    /// normalised by the weights.
    fn field(&self, size: u32, fold: impl Fn(f32) -> f32 + Copy) -> Vec<f32> {
        let size = size as usize;
        let mut out = vec![0.0; size * size];
        let mut weight = 1.0;
        for octave in &self.octaves {
            octave.accumulate(size, weight, fold, &mut out);
            weight *= 0.5;
        }
        let total = 2.0 - 2.0 * weight;
        out.iter_mut().for_each(|v| *v /= total);
        out
    }

    /// Fractal noise in 0..1 at every texel of a `size x size` tile.
    pub(crate) fn fbm(&self, size: u32) -> Vec<f32> {
        self.field(size, |v| v)
    }

    /// Turbulence (sum of folded octaves |2n - 1|) in 0..1 at every texel: sharp creases
    /// where an octave crosses its mean, the classic ingredient of marble veins.
    pub(crate) fn turbulence(&self, size: u32) -> Vec<f32> {
        self.field(size, |v| (2.0 * v - 1.0).abs())
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
    /// Lines run to the full width (an inscription) instead of a ragged margin with a short
    /// last line (a paragraph).
    pub(crate) full_lines: bool,
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
                * if self.full_lines {
                    1.0
                } else if line + 1 == self.lines {
                    rng.range(0.3, 0.7)
                } else {
                    rng.range(0.85, 1.0)
                };
            let mut x = 0.0;
            loop {
                // The longest word that still fits, then a random length up to it.
                let fits = ((end - x + stroke) / (w + stroke)).floor() as usize;
                if fits == 0 {
                    break;
                }
                let letters = 1 + rng.below(fits.min(8));
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
    texture_from_fn(size, label, |x, y| {
        let distance =
            |s: f32| distance_to_integer(s / pitch) * pitch * std::f32::consts::FRAC_1_SQRT_2;
        let d = distance(x + y).min(distance(x - y));
        let coverage = (half - d + 0.5).clamp(0.0, 1.0);
        let shade = 1.0 - 0.4 * (d / half.max(0.5)).min(1.0).powi(2);
        let rgb = color * shade;
        [rgb.x, rgb.y, rgb.z, coverage]
    })
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
    fn noise_fields_tile_and_stay_in_range() {
        let noise = Noise::new(3, 4, 3);
        let size = 64;
        for field in [noise.fbm(size), noise.turbulence(size)] {
            assert!(field.iter().all(|v| (0.0..=1.0).contains(v)));
            // Across the tile's edge the field changes no more than between neighbours
            // inside it: it wraps without a seam.
            let at = |x: u32, y: u32| field[(y * size + x) as usize];
            let step = (0..size)
                .map(|y| (at(1, y) - at(0, y)).abs())
                .fold(0.0, f32::max);
            let seam = (0..size)
                .map(|y| (at(0, y) - at(size - 1, y)).abs())
                .fold(0.0, f32::max);
            assert!(seam <= 2.0 * step + 1e-6, "{seam} {step}");
        }
        let mean = noise.fbm(size).iter().sum::<f32>() / (size * size) as f32;
        assert!((0.3..0.7).contains(&mean), "{mean}");
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
