//! FLIP (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and Fairchild, "FLIP: A
//! Difference Evaluator for Alternating Images", 2020), LDR variant, through NVIDIA's reference
//! implementation in the `nv-flip` crate: a per-pixel perceptual error in 0..1 for an observer
//! at 67 pixels per degree (FLIP's default: a 0.7 m wide 4K monitor seen from 0.7 m), pooled
//! by its mean. Unlike SSIM it sees colour, and it weighs edges and points the way the eye's
//! contrast sensitivity does.

use super::MetricsError;
use super::map::Plane;

/// Pixels per degree of visual angle FLIP assumes (the reference implementation's default).
pub const PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

fn flip_rgb(image: &image::RgbaImage) -> nv_flip::FlipImageRgb8 {
    let rgb: Vec<u8> = image.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
    nv_flip::FlipImageRgb8::with_data(image.width(), image.height(), &rgb)
}

/// The FLIP error map of `test` against `reference` (both sRGB-encoded; alpha ignored).
pub fn flip_map(
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<Plane, MetricsError> {
    if reference.dimensions() != test.dimensions() {
        return Err(MetricsError::SizeMismatch {
            reference: reference.dimensions(),
            test: test.dimensions(),
        });
    }
    if reference.width() == 0 || reference.height() == 0 {
        return Err(MetricsError::TooSmall {
            width: reference.width(),
            height: reference.height(),
        });
    }
    let map = nv_flip::flip(flip_rgb(reference), flip_rgb(test), PIXELS_PER_DEGREE);
    Ok(Plane {
        width: map.width(),
        height: map.height(),
        data: map.to_vec(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_images_have_no_error_and_differences_do() {
        let a = image::RgbaImage::from_fn(32, 32, |x, y| {
            let v = if (x / 4 + y / 4) % 2 == 0 { 0 } else { 255 };
            image::Rgba([v, v, v, 255])
        });
        let same = flip_map(&a, &a).unwrap();
        assert!(same.data.iter().all(|&v| v == 0.0));
        let b = image::RgbaImage::from_pixel(32, 32, image::Rgba([128, 128, 128, 255]));
        let diff = flip_map(&a, &b).unwrap();
        let mean = diff.mean(None).unwrap();
        assert!(mean > 0.1 && mean <= 1.0, "{mean}");
        assert!(flip_map(&a, &image::RgbaImage::new(32, 31)).is_err());
    }
}
