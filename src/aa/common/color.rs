//! Colour maths shared by the post-process techniques, as CPU functions that the shaders
//! (`src/aa/fxaa/fxaa.wgsl`, `src/aa/taa/taa.wgsl`) mirror line for line, so that the tests can
//! check the formulas without a GPU.
//!
//! - Luma: FXAA measures contrast on the sRGB-encoded image with the BT.601 weights (or the
//!   green channel alone); TAA weighs its blend by the Rec. 709 luminance of linear colour.
//! - YCoCg: the lossless-in-reals luma/chroma transform TAA clips history in (Karis 2014),
//!   where the neighbourhood's bounding box hugs the colours more tightly than in RGB.
//! - Neighbourhood rectification: clipping a colour towards the centre of a box, and the
//!   variance box mean +/- gamma * sigma (Salvi 2016).
//! - Catmull-Rom history filtering: the cubic's four weights and their bilinear-optimised
//!   form, which reads a 4x4 footprint with five bilinear taps by dropping the four corners
//!   (after Jimenez's and Drobot's filtering in real-time TAA).
//! - Karis' luminance-weighted blend of the current frame with the history, which keeps
//!   bright sub-pixel features from flickering.

use glam::{Vec2, Vec3};

#[cfg(test)]
use crate::graph::params::Named;

/// BT.601 luma weights, applied to sRGB-encoded values (FXAA's perceptual luma).
pub const LUMA_BT601: Vec3 = Vec3::new(0.299, 0.587, 0.114);

/// Rec. 709 luminance weights, applied to linear values.
pub const LUMINANCE_REC709: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

crate::named_enum! {
    /// Which luma FXAA computes from a sample.
    pub enum LumaSource {
        /// BT.601 weights on the sRGB-encoded colour, computed for every tap in the pass.
        Bt601 => "bt601",
        /// The encoded green channel (FXAA's `FXAA_GREEN_AS_LUMA`: cheaper, misses red/blue
        /// edges).
        Green => "green",
    }
}

impl LumaSource {
    /// Luma of a sRGB-encoded colour.
    pub fn luma(self, encoded: Vec3) -> f32 {
        match self {
            Self::Bt601 => encoded.dot(LUMA_BT601),
            Self::Green => encoded.y,
        }
    }
}

/// Luminance of a linear colour (Rec. 709).
pub fn luminance(linear: Vec3) -> f32 {
    linear.dot(LUMINANCE_REC709)
}

/// RGB to YCoCg (Y in 0..1, Co and Cg in -0.5..0.5 for RGB in 0..1).
pub fn rgb_to_ycocg(rgb: Vec3) -> Vec3 {
    Vec3::new(
        0.25 * rgb.x + 0.5 * rgb.y + 0.25 * rgb.z,
        0.5 * rgb.x - 0.5 * rgb.z,
        -0.25 * rgb.x + 0.5 * rgb.y - 0.25 * rgb.z,
    )
}

/// YCoCg back to RGB (exact inverse of [`rgb_to_ycocg`]).
pub fn ycocg_to_rgb(ycocg: Vec3) -> Vec3 {
    let (y, co, cg) = (ycocg.x, ycocg.y, ycocg.z);
    Vec3::new(y + co - cg, y + cg, y - co - cg)
}

/// Moves `colour` along the line towards `center` until it lies inside the axis-aligned box
/// `center +/- extent`; colours already inside are returned unchanged. Unlike a per-channel
/// clamp this keeps the colour's hue relation to the box centre (Karis 2014).
pub fn clip_towards_center(colour: Vec3, center: Vec3, extent: Vec3) -> Vec3 {
    let offset = colour - center;
    let units = (offset / extent.max(Vec3::splat(1e-6))).abs();
    let largest = units.max_element();
    if largest > 1.0 {
        center + offset / largest
    } else {
        colour
    }
}

/// The box a history colour is clipped into under variance clipping (Salvi 2016): the
/// neighbourhood mean +/- `gamma` standard deviations, intersected with the neighbourhood's
/// min/max box so that a large gamma never accepts colours the neighbourhood does not have.
/// `mean` and `mean_square` are the first two moments of the neighbourhood. Returns (min, max).
pub fn variance_box(
    mean: Vec3,
    mean_square: Vec3,
    gamma: f32,
    min: Vec3,
    max: Vec3,
) -> (Vec3, Vec3) {
    let sigma = (mean_square - mean * mean).max(Vec3::ZERO).sqrt();
    (
        (mean - gamma * sigma).max(min),
        (mean + gamma * sigma).min(max),
    )
}

/// The Catmull-Rom cubic's weights for the four samples at -1, 0, 1, 2 around a fractional
/// position `t` in 0..1 past sample 0. They sum to one; at `t` = 0 only sample 0 counts.
pub fn catmull_rom_weights(t: f32) -> [f32; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        -0.5 * t3 + t2 - 0.5 * t,
        1.5 * t3 - 2.5 * t2 + 1.0,
        -1.5 * t3 + 2.0 * t2 + 0.5 * t,
        0.5 * t3 - 0.5 * t2,
    ]
}

/// One bilinear tap of the five-tap Catmull-Rom filter: where to sample (in texels, relative
/// to the texel centre left/above the sample point) and with what weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterTap {
    /// Offset in texels from the centre of the texel at the floor of the sample position.
    pub offset: Vec2,
    /// Weight of the tap (the five weights are renormalised to sum to one).
    pub weight: f32,
}

/// The five bilinear taps that approximate a 4x4 Catmull-Rom filter at fractional position
/// `fraction` (0..1 on each axis past the texel centre at offset 0). The middle two samples of
/// each axis have weights of the same sign, so one bilinear tap at offset w2 / (w1 + w2)
/// reads both; the four corner taps, whose weights are products of two small negative lobes,
/// are dropped and the rest renormalised.
pub fn catmull_rom_5tap(fraction: Vec2) -> [FilterTap; 5] {
    let wx = catmull_rom_weights(fraction.x);
    let wy = catmull_rom_weights(fraction.y);
    let middle = Vec2::new(wx[1] + wx[2], wy[1] + wy[2]);
    let middle_offset = Vec2::new(wx[2] / middle.x, wy[2] / middle.y);
    let taps = [
        (Vec2::new(middle_offset.x, -1.0), middle.x * wy[0]),
        (Vec2::new(-1.0, middle_offset.y), wx[0] * middle.y),
        (middle_offset, middle.x * middle.y),
        (Vec2::new(2.0, middle_offset.y), wx[3] * middle.y),
        (Vec2::new(middle_offset.x, 2.0), middle.x * wy[3]),
    ];
    let total: f32 = taps.iter().map(|(_, w)| w).sum();
    taps.map(|(offset, weight)| FilterTap {
        offset,
        weight: weight / total,
    })
}

/// Karis' luminance-weighted blend of the current sample with the (rectified) history:
/// each input's share is divided by (1 + its luminance) before normalising, so a single bright
/// sample moves the result less than a plain linear blend would (less flicker).
/// `current_weight` is the current frame's share before weighting.
pub fn luminance_weighted_blend(current: Vec3, history: Vec3, current_weight: f32) -> Vec3 {
    let wc = current_weight / (1.0 + luminance(current));
    let wh = (1.0 - current_weight) / (1.0 + luminance(history));
    (current * wc + history * wh) / (wc + wh)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f32, b: f32, eps: f32) -> bool {
        (a - b).abs() <= eps
    }

    #[test]
    fn luma_of_primaries_and_grey() {
        assert!(close(LumaSource::Bt601.luma(Vec3::ONE), 1.0, 1e-6));
        assert!(close(LumaSource::Bt601.luma(Vec3::X), 0.299, 1e-6));
        assert!(close(LumaSource::Bt601.luma(Vec3::Y), 0.587, 1e-6));
        assert!(close(LumaSource::Bt601.luma(Vec3::Z), 0.114, 1e-6));
        assert_eq!(LumaSource::Green.luma(Vec3::new(0.9, 0.25, 0.1)), 0.25);
        assert!(close(luminance(Vec3::splat(0.5)), 0.5, 1e-6));
        assert!(close(luminance(Vec3::Y), 0.7152, 1e-6));
        for name in LumaSource::NAMES {
            assert_eq!(
                LumaSource::from_name(name).expect("listed name").name(),
                *name
            );
        }
    }

    #[test]
    fn luma_is_linear_so_bilinear_taps_average_lumas() {
        // FXAA's edge-end search reads luma of bilinear samples; computing luma after the
        // filter must equal filtering precomputed lumas.
        let a = Vec3::new(0.9, 0.2, 0.4);
        let b = Vec3::new(0.1, 0.7, 0.3);
        let mixed = a.lerp(b, 0.3);
        let l = |c| LumaSource::Bt601.luma(c);
        assert!(close(l(mixed), l(a) * 0.7 + l(b) * 0.3, 1e-6));
    }

    #[test]
    fn ycocg_round_trips_and_separates_grey() {
        for rgb in [
            Vec3::ZERO,
            Vec3::ONE,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.2, 0.6, 0.9),
            Vec3::new(0.31, 0.02, 0.77),
        ] {
            let back = ycocg_to_rgb(rgb_to_ycocg(rgb));
            assert!((back - rgb).abs().max_element() < 1e-6, "{rgb} -> {back}");
        }
        // Greys have no chroma; Y is the mean-like luma (R + 2G + B) / 4.
        let grey = rgb_to_ycocg(Vec3::splat(0.4));
        assert!(close(grey.x, 0.4, 1e-6) && grey.y == 0.0 && grey.z == 0.0);
        let red = rgb_to_ycocg(Vec3::X);
        assert_eq!(red, Vec3::new(0.25, 0.5, -0.25));
    }

    #[test]
    fn clipping_keeps_inside_points_and_lands_on_the_box() {
        let center = Vec3::new(0.5, 0.0, 0.0);
        let extent = Vec3::new(0.1, 0.2, 0.05);
        let inside = Vec3::new(0.55, -0.1, 0.01);
        assert_eq!(clip_towards_center(inside, center, extent), inside);
        let outside = Vec3::new(0.9, 0.1, 0.0);
        let clipped = clip_towards_center(outside, center, extent);
        // On the box face x = 0.6, on the segment from the centre to the point.
        assert!(close(clipped.x, 0.6, 1e-6), "{clipped}");
        assert!(close(clipped.y, 0.1 * 0.25, 1e-6), "{clipped}");
        // A degenerate (flat) box collapses everything onto its centre.
        let flat = clip_towards_center(outside, center, Vec3::ZERO);
        assert!((flat - center).abs().max_element() < 1e-4, "{flat}");
    }

    #[test]
    fn variance_box_is_mean_plus_minus_gamma_sigma_within_min_max() {
        // Samples 0 and 1 in equal numbers: mean 0.5, sigma 0.5.
        let mean = Vec3::splat(0.5);
        let mean_square = Vec3::splat(0.5);
        let (lo, hi) = variance_box(mean, mean_square, 0.5, Vec3::ZERO, Vec3::ONE);
        assert!((lo - Vec3::splat(0.25)).abs().max_element() < 1e-6);
        assert!((hi - Vec3::splat(0.75)).abs().max_element() < 1e-6);
        let (lo, hi) = variance_box(mean, mean_square, 3.0, Vec3::ZERO, Vec3::ONE);
        assert_eq!((lo, hi), (Vec3::ZERO, Vec3::ONE));
        // A flat neighbourhood gives a point box even with rounding in the moments.
        let (lo, hi) = variance_box(
            Vec3::splat(0.3),
            Vec3::splat(0.09 - 1e-7),
            1.0,
            Vec3::splat(0.3),
            Vec3::splat(0.3),
        );
        assert_eq!((lo, hi), (Vec3::splat(0.3), Vec3::splat(0.3)));
    }

    #[test]
    fn catmull_rom_weights_interpolate() {
        for i in 0..=16 {
            let t = i as f32 / 16.0;
            let w = catmull_rom_weights(t);
            assert!(close(w.iter().sum::<f32>(), 1.0, 1e-6), "{t}: {w:?}");
            // Reproduces linear functions exactly: sum w_i * x_i = t for x = -1, 0, 1, 2.
            let x = -w[0] + w[2] + 2.0 * w[3];
            assert!(close(x, t, 1e-6), "{t}: {x}");
        }
        assert_eq!(catmull_rom_weights(0.0), [0.0, 1.0, 0.0, 0.0]);
        let half = catmull_rom_weights(0.5);
        assert!(close(half[0], -0.0625, 1e-7) && close(half[1], 0.5625, 1e-7));
        assert!(close(half[2], 0.5625, 1e-7) && close(half[3], -0.0625, 1e-7));
        // The middle weights never change sign, which the bilinear-optimised form relies on.
        for i in 0..=16 {
            let w = catmull_rom_weights(i as f32 / 16.0);
            assert!(w[1] >= 0.0 && w[2] >= 0.0);
        }
    }

    /// A 1D signal sampled like a texture: the exact 4-tap cubic against the optimised form
    /// (two weighted linear-interpolation taps for the middle pair).
    #[test]
    fn five_tap_matches_the_full_filter_without_corners() {
        let texel = |x: i32, y: i32| ((x * 7 + y * 13) % 11) as f32 / 10.0;
        let bilinear = |p: Vec2| {
            let (x0, y0) = (p.x.floor(), p.y.floor());
            let (fx, fy) = (p.x - x0, p.y - y0);
            let (x0, y0) = (x0 as i32, y0 as i32);
            let top = texel(x0, y0) * (1.0 - fx) + texel(x0 + 1, y0) * fx;
            let bottom = texel(x0, y0 + 1) * (1.0 - fx) + texel(x0 + 1, y0 + 1) * fx;
            top * (1.0 - fy) + bottom * fy
        };
        for fraction in [
            Vec2::new(0.0, 0.0),
            Vec2::new(0.3, 0.7),
            Vec2::new(0.9, 0.1),
        ] {
            let taps = catmull_rom_5tap(fraction);
            assert!(close(taps.iter().map(|t| t.weight).sum(), 1.0, 1e-6));
            let fast: f32 = taps.iter().map(|t| t.weight * bilinear(t.offset)).sum();
            // Reference: the 4x4 cubic without its four corner texels, renormalised.
            let wx = catmull_rom_weights(fraction.x);
            let wy = catmull_rom_weights(fraction.y);
            let (mut sum, mut total) = (0.0, 0.0);
            for (j, wyj) in wy.iter().enumerate() {
                for (i, wxi) in wx.iter().enumerate() {
                    let corner = (i == 0 || i == 3) && (j == 0 || j == 3);
                    if !corner {
                        sum += wxi * wyj * texel(i as i32 - 1, j as i32 - 1);
                        total += wxi * wyj;
                    }
                }
            }
            assert!(
                close(fast, sum / total, 1e-5),
                "{fraction}: {fast} vs {}",
                sum / total
            );
        }
        // At a texel centre the filter returns that texel.
        let taps = catmull_rom_5tap(Vec2::ZERO);
        let centre = taps
            .iter()
            .find(|t| t.offset == Vec2::ZERO)
            .expect("centre tap");
        assert!(close(centre.weight, 1.0, 1e-6));
    }

    #[test]
    fn luminance_weighting_damps_bright_outliers() {
        let dark = Vec3::splat(0.1);
        let bright = Vec3::ONE;
        let plain = dark.lerp(bright, 0.1);
        let weighted = luminance_weighted_blend(bright, dark, 0.1);
        assert!(weighted.x < plain.x, "{weighted} vs {plain}");
        assert!(weighted.x > dark.x);
        // Equal inputs are returned unchanged (flat regions stay flat).
        let c = Vec3::new(0.2, 0.4, 0.6);
        assert!(
            (luminance_weighted_blend(c, c, 0.1) - c)
                .abs()
                .max_element()
                < 1e-6
        );
        // Weight 1 is the current frame alone.
        assert!(
            (luminance_weighted_blend(bright, dark, 1.0) - bright)
                .abs()
                .max_element()
                < 1e-6
        );
    }
}
