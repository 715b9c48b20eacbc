//! Pixel-wise errors on the sRGB-encoded R', G', B' channels in 0..255 (alpha ignored): the
//! absolute and squared error per pixel (each averaged over the three channels), and from them
//! the mean absolute error and PSNR = 10 log10(255^2 / MSE), infinite for identical images.
//! The same definitions are used by the GPU path.

use super::MetricsError;
use super::map::{Mask, Plane};

/// Per-pixel absolute and squared errors.
#[derive(Clone, Debug)]
pub struct PixelErrorMaps {
    /// Mean over R', G', B' of `|a - b|`, 0..255.
    pub abs_error: Plane,
    /// Mean over R', G', B' of `(a - b)^2`, 0..65025.
    pub sq_error: Plane,
}

/// Pooled pixel errors.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PixelErrors {
    /// Mean absolute error, 0..255.
    pub mae: f64,
    /// Mean squared error.
    pub mse: f64,
}

impl PixelErrors {
    /// Peak signal-to-noise ratio in dB; infinite when the images are identical.
    pub fn psnr(&self) -> f64 {
        psnr_from_mse(self.mse)
    }
}

/// PSNR in dB of a mean squared error on 8-bit values.
pub fn psnr_from_mse(mse: f64) -> f64 {
    if mse <= 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// The per-pixel error maps of two equally sized images.
pub fn error_maps(
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<PixelErrorMaps, MetricsError> {
    if reference.dimensions() != test.dimensions() {
        return Err(MetricsError::SizeMismatch {
            reference: reference.dimensions(),
            test: test.dimensions(),
        });
    }
    let (w, h) = reference.dimensions();
    let mut abs_error = Vec::with_capacity((w * h) as usize);
    let mut sq_error = Vec::with_capacity((w * h) as usize);
    for (a, b) in reference.pixels().zip(test.pixels()) {
        let (mut abs, mut sq) = (0.0f32, 0.0f32);
        for c in 0..3 {
            let d = f32::from(a[c]) - f32::from(b[c]);
            abs += d.abs();
            sq += d * d;
        }
        abs_error.push(abs / 3.0);
        sq_error.push(sq / 3.0);
    }
    Ok(PixelErrorMaps {
        abs_error: Plane {
            width: w,
            height: h,
            data: abs_error,
        },
        sq_error: Plane {
            width: w,
            height: h,
            data: sq_error,
        },
    })
}

impl PixelErrorMaps {
    /// MAE and MSE over the pixels `mask` selects (all when `None`); zero for an empty
    /// selection.
    pub fn pool(&self, mask: Option<&Mask>) -> PixelErrors {
        PixelErrors {
            mae: self.abs_error.mean(mask).unwrap_or(0.0),
            mse: self.sq_error.mean(mask).unwrap_or(0.0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn errors_of_a_known_difference() {
        let a = image::RgbaImage::from_pixel(4, 2, image::Rgba([10, 20, 30, 255]));
        let mut b = a.clone();
        b.put_pixel(0, 0, image::Rgba([13, 20, 30, 0]));
        let maps = error_maps(&a, &b).unwrap();
        let e = maps.pool(None);
        assert!((e.mae - 1.0 / 8.0).abs() < 1e-9);
        assert!((e.mse - 3.0 / 8.0).abs() < 1e-9);
        assert!((e.psnr() - 10.0 * (65025.0f64 / 0.375).log10()).abs() < 1e-9);
        assert_eq!(error_maps(&a, &a).unwrap().pool(None).psnr(), f64::INFINITY);
        let wrong = image::RgbaImage::new(4, 3);
        assert!(error_maps(&a, &wrong).is_err());
    }
}
