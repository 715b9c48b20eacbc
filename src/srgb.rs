//! The sRGB transfer function (IEC 61966-2-1), once for the whole crate: the scene's textures
//! and mip chains, material colours read from files, the chart's ground truth and the tests
//! encode and decode through these. The GPU does the same conversions in hardware when it
//! reads or writes the `*Srgb` texture formats.
//!
//! [`display_rgba8`] turns any decoded image (linear floating-point OpenEXR included) into the
//! 8-bit sRGB-encoded RGBA the metrics take.
//!
//! Every function comes in `f32` and `f64` (suffix `_f64`) forms generated from one body, so
//! each caller keeps its precision.

/// Generates the four conversions for one float type.
macro_rules! transfer {
    ($float:ty, $encode:ident, $decode:ident, $encode_byte:ident, $decode_byte:ident) => {
        /// sRGB encoding of a linear value; values outside 0..1 are clamped first.
        pub fn $encode(linear: $float) -> $float {
            let c = linear.clamp(0.0, 1.0);
            if c <= 0.003_130_8 {
                12.92 * c
            } else {
                1.055 * c.powf(1.0 / 2.4) - 0.055
            }
        }

        /// The linear value of an sRGB-encoded value in 0..1.
        pub fn $decode(encoded: $float) -> $float {
            if encoded <= 0.04045 {
                encoded / 12.92
            } else {
                ((encoded + 0.055) / 1.055).powf(2.4)
            }
        }

        /// The sRGB-encoded byte of a linear value (clamped to 0..1, rounded; NaN gives 0).
        pub fn $encode_byte(linear: $float) -> u8 {
            ($encode(linear) * 255.0).round() as u8
        }

        /// The linear value of an sRGB-encoded byte.
        pub fn $decode_byte(byte: u8) -> $float {
            $decode(<$float>::from(byte) / 255.0)
        }
    };
}

transfer!(f32, encode, decode, encode_byte, decode_byte);
transfer!(
    f64,
    encode_f64,
    decode_f64,
    encode_byte_f64,
    decode_byte_f64
);

/// The 8-bit sRGB-encoded RGBA of a decoded image, as the metrics and the viewer take it.
/// Integer images are sRGB-encoded already and are converted as they are (16-bit channels
/// scaled to 8). Floating-point images (OpenEXR) hold linear light: each colour channel is
/// clamped to 0..1 and sRGB-encoded ([`encode_byte`]), alpha clamped and scaled. Clamping,
/// not tonemapping: values above 1 show as an SDR display would show them, white.
pub fn display_rgba8(image: image::DynamicImage) -> image::RgbaImage {
    display_rgba8_mapped(image, |linear| linear)
}

/// [`display_rgba8`] with floating-point (linear) images first passed through `to_display`
/// pixel by pixel (linear RGB in, linear display RGB out, clamped afterwards): a tonemapper,
/// for HDR captures. Integer images are display values already and are not mapped.
pub fn display_rgba8_mapped(
    image: image::DynamicImage,
    to_display: impl Fn([f32; 3]) -> [f32; 3],
) -> image::RgbaImage {
    match image {
        image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_) => {
            let linear = image.into_rgba32f();
            image::RgbaImage::from_fn(linear.width(), linear.height(), |x, y| {
                let [r, g, b, a] = linear.get_pixel(x, y).0;
                let [r, g, b] = to_display([r, g, b]);
                let alpha = (a.clamp(0.0, 1.0) * 255.0).round() as u8;
                image::Rgba([encode_byte(r), encode_byte(g), encode_byte(b), alpha])
            })
        }
        other => other.to_rgba8(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_points_mid_grey_and_round_trips() {
        assert_eq!(encode_byte(0.0), 0);
        assert_eq!(encode_byte(1.0), 255);
        assert_eq!(encode_byte(0.5), 188);
        assert_eq!(encode_byte(-1.0), 0);
        assert_eq!(encode_byte(f32::NAN), 0);
        assert_eq!(encode_byte_f64(0.215_861), 128);
        assert!((decode(0.5) - 0.214_041).abs() < 1e-5);
        for byte in 0..=255u8 {
            assert_eq!(encode_byte(decode_byte(byte)), byte);
            assert_eq!(encode_byte_f64(decode_byte_f64(byte)), byte);
        }
    }
}
