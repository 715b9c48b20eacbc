//! HDR-FLIP (Andersson, Nilsson, Shirley and Akenine-Möller, "Visualizing Errors in Rendered
//! High Dynamic Range Images", Eurographics 2021): FLIP for linear radiance. An HDR image has
//! no single look, so both images are shown at a range of exposures through a tonemapper, LDR
//! FLIP compares each pair, and a pixel's error is its largest over the exposures.
//!
//! As the authors define it: the tonemapper is their ACES fit (Narkowicz's curve with the
//! input scaled by 0.6); the exposures run from the one that maps the reference's brightest
//! luminance to 0.85 (nothing of it is clipped) to the one that maps its median luminance to
//! 0.5 (the typical content at mid grey), in whole stops or closer, at least two. The LDR FLIP
//! of each pair runs through NVIDIA's implementation (`nv-flip`, as [`super::flip`] does),
//! which takes sRGB-encoded 8-bit images: each tonemapped exposure is encoded to 8 bits first,
//! where the authors' tool keeps floats. The 1/255 steps this adds are far below the
//! differences FLIP reports for antialiasing.

use super::MetricsError;
use super::flip::PIXELS_PER_DEGREE;
use super::map::Plane;

/// The ACES fit HDR-FLIP tonemaps with: `(a x² + b x) / (c x² + d x + e)`, input scaled by 0.6.
const ACES: [f32; 5] = [
    0.6 * 0.6 * 2.51,
    0.6 * 0.03,
    0.6 * 0.6 * 2.43,
    0.6 * 0.59,
    0.14,
];

/// Most exposures evaluated: a scene spanning more stops is sampled more sparsely.
const MAX_EXPOSURES: usize = 24;

/// HDR-FLIP of a test image against a reference.
#[derive(Clone, Debug)]
pub struct HdrFlip {
    /// Per pixel, the largest LDR FLIP over the exposures (0..1).
    pub map: Plane,
    /// The mean of the map.
    pub mean: f64,
    /// The first and last exposure, in stops.
    pub exposure_range: (f32, f32),
    /// How many exposures were compared.
    pub exposures: usize,
}

fn aces(x: f32) -> f32 {
    let [a, b, c, d, e] = ACES;
    ((a * x * x + b * x) / (c * x * x + d * x + e)).clamp(0.0, 1.0)
}

/// The input the ACES fit maps to `target` (a root of the quadratic it becomes).
fn aces_inverse(target: f32) -> f32 {
    let [a, b, c, d, e] = ACES;
    let (qa, qb, qc) = (a - target * c, b - target * d, -target * e);
    (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa)
}

fn luminance(p: &image::Rgb<f32>) -> f32 {
    0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
}

/// The exposures of the module docs for `reference`, in stops.
fn exposures(reference: &image::Rgb32FImage) -> Vec<f32> {
    let mut luma: Vec<f32> = reference
        .pixels()
        .map(luminance)
        .filter(|l| l.is_finite())
        .map(|l| l.max(0.0))
        .collect();
    luma.sort_by(f32::total_cmp);
    let brightest = luma.last().copied().unwrap_or(1.0).max(1e-6);
    // A median of black (mostly empty images) is taken 20 stops below the brightest.
    let median = luma.get(luma.len() / 2).copied().unwrap_or(1.0);
    let median = median.max(brightest * 2f32.powi(-20));
    let start = (aces_inverse(0.85) / brightest).log2();
    let stop = (aces_inverse(0.5) / median).log2().max(start);
    let count = ((stop - start).ceil() as usize).clamp(2, MAX_EXPOSURES);
    (0..count)
        .map(|i| start + (stop - start) * i as f32 / (count - 1) as f32)
        .collect()
}

/// The image at `exposure` stops through the ACES fit, sRGB-encoded for LDR FLIP.
fn exposed(image: &image::Rgb32FImage, exposure: f32) -> nv_flip::FlipImageRgb8 {
    let scale = exposure.exp2();
    let bytes: Vec<u8> = image
        .pixels()
        .flat_map(|p| p.0)
        .map(|v| {
            let v = if v.is_finite() { v.max(0.0) } else { 0.0 };
            crate::srgb::encode_byte(aces(v * scale))
        })
        .collect();
    nv_flip::FlipImageRgb8::with_data(image.width(), image.height(), &bytes)
}

/// HDR-FLIP of `test` against `reference`, both linear radiance (see the module docs).
pub fn hdr_flip(
    reference: &image::Rgb32FImage,
    test: &image::Rgb32FImage,
) -> Result<HdrFlip, MetricsError> {
    if reference.dimensions() != test.dimensions() {
        return Err(MetricsError::SizeMismatch {
            reference: reference.dimensions(),
            test: test.dimensions(),
        });
    }
    let (width, height) = reference.dimensions();
    if width == 0 || height == 0 {
        return Err(MetricsError::TooSmall { width, height });
    }
    let stops = exposures(reference);
    let mut map = vec![0.0f32; (width * height) as usize];
    for &exposure in &stops {
        let errors = nv_flip::flip(
            exposed(reference, exposure),
            exposed(test, exposure),
            PIXELS_PER_DEGREE,
        );
        for (worst, error) in map.iter_mut().zip(errors.to_vec()) {
            *worst = worst.max(error);
        }
    }
    let mean = map.iter().map(|&v| f64::from(v)).sum::<f64>() / map.len() as f64;
    Ok(HdrFlip {
        map: Plane {
            width,
            height,
            data: map,
        },
        mean,
        exposure_range: (stops[0], stops[stops.len() - 1]),
        exposures: stops.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(width: u32, height: u32, f: impl Fn(u32, u32) -> f32) -> image::Rgb32FImage {
        image::Rgb32FImage::from_fn(width, height, |x, y| image::Rgb([f(x, y); 3]))
    }

    #[test]
    fn the_curve_and_its_inverse_agree() {
        for target in [0.1, 0.5, 0.85] {
            assert!(
                (aces(aces_inverse(target)) - target).abs() < 1e-4,
                "{target}"
            );
        }
        assert_eq!(aces(0.0), 0.0);
        assert!(aces(1e6) <= 1.0);
    }

    #[test]
    fn identical_images_score_zero_and_the_exposures_span_the_range() {
        // A dim background (median 0.05) with a line of radiance 50.
        let reference = image(64, 48, |x, _| if x == 20 { 50.0 } else { 0.05 });
        let same = hdr_flip(&reference, &reference).expect("same size");
        assert_eq!(same.mean, 0.0);
        // From 50 at 0.85 to 0.05 at 0.5: about ten stops apart.
        assert!((8..=12).contains(&same.exposures), "{}", same.exposures);
        assert!(same.exposure_range.0 < same.exposure_range.1);
    }

    #[test]
    fn an_error_in_the_highlights_counts_although_ldr_clipping_would_hide_it() {
        // 50 against 20: both white at any exposure that shows the background, different at
        // the low exposures HDR-FLIP adds for the highlights.
        let reference = image(
            64,
            48,
            |x, _| if (20..23).contains(&x) { 50.0 } else { 0.05 },
        );
        let test = image(
            64,
            48,
            |x, _| if (20..23).contains(&x) { 20.0 } else { 0.05 },
        );
        let scored = hdr_flip(&reference, &test).expect("same size");
        let line = scored.map.data[(10 * 64 + 21) as usize];
        let background = scored.map.data[(10 * 64 + 50) as usize];
        assert!(line > 0.1 && background < 0.01, "{line} {background}");
        let other = image(32, 48, |_, _| 0.0);
        assert!(hdr_flip(&reference, &other).is_err());
    }
}
