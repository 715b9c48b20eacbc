//! SSIM (Wang, Bovik, Sheikh and Simoncelli, "Image quality assessment: from error visibility to
//! structural similarity", 2004) on BT.601 luma of sRGB-encoded values, the CPU reference
//! implementation that the GPU path (`metrics::gpu`) is tested against.
//!
//! Definition, chosen to agree with scikit-image's `structural_similarity(gaussian_weights=True,
//! sigma=1.5, use_sample_covariance=False, data_range=255)`:
//! - luma `Y' = 0.299 R' + 0.587 G' + 0.114 B'` in 0..255 (dynamic range `L = 255`);
//! - local means, variances and covariance are Gaussian-weighted (sigma 1.5, 11 taps: radius
//!   `int(3.5 sigma + 0.5) = 5`, weights normalised to sum to 1), applied separably, with the
//!   image mirrored at its edges the way SciPy's `reflect` mode does (`d c b a | a b c d`);
//! - per pixel `S = (2 mu_x mu_y + C1)(2 s_xy + C2) / ((mu_x^2 + mu_y^2 + C1)(s_x^2 + s_y^2 + C2))`
//!   with `C1 = (0.01 L)^2`, `C2 = (0.03 L)^2` and population (not sample) moments;
//! - the mean SSIM averages the map over the pixels at least 5 pixels from every edge, which is
//!   where the window never leaves the image (scikit-image crops the same strip).
//!
//! Everything runs in `f64`; the map is stored as `f32`.

use super::MetricsError;
use super::map::{Mask, Plane};

/// Gaussian standard deviation of the SSIM window, pixels.
pub const SIGMA: f64 = 1.5;
/// Radius of the SSIM window: 11 taps.
pub const RADIUS: usize = 5;
/// Window side in pixels.
pub const WINDOW: u32 = 2 * RADIUS as u32 + 1;
/// Stabiliser constant factor K1.
pub const K1: f64 = 0.01;
/// Stabiliser constant factor K2.
pub const K2: f64 = 0.03;
/// Dynamic range of 8-bit values.
pub const DYNAMIC_RANGE: f64 = 255.0;

/// `C1 = (K1 L)^2`.
pub fn c1() -> f64 {
    (K1 * DYNAMIC_RANGE).powi(2)
}

/// `C2 = (K2 L)^2`.
pub fn c2() -> f64 {
    (K2 * DYNAMIC_RANGE).powi(2)
}

/// The normalised 11-tap Gaussian window (sigma 1.5), centre at index 5.
pub fn gaussian_weights() -> [f64; 2 * RADIUS + 1] {
    let mut w = [0.0; 2 * RADIUS + 1];
    for (i, weight) in w.iter_mut().enumerate() {
        let x = i as f64 - RADIUS as f64;
        *weight = (-0.5 * x * x / (SIGMA * SIGMA)).exp();
    }
    let sum: f64 = w.iter().sum();
    w.map(|v| v / sum)
}

/// SciPy's `reflect` boundary: index `i` of a line of `n` samples mirrored about the edge
/// (`-1 -> 0`, `n -> n - 1`). Valid for `-n <= i < 2n`.
pub fn reflect(i: isize, n: usize) -> usize {
    let n = n as isize;
    let r = if i < 0 {
        -i - 1
    } else if i >= n {
        2 * n - i - 1
    } else {
        i
    };
    r as usize
}

/// SSIM of two images: the mean over the interior and the per-pixel map.
#[derive(Clone, Debug)]
pub struct Ssim {
    /// Mean SSIM over the pixels at least [`RADIUS`] from every edge.
    pub mean: f64,
    /// Per-pixel SSIM, every pixel (edges computed with mirrored windows).
    pub map: Plane,
}

/// Checks that two sizes agree and leave room for the SSIM window.
pub fn check_sizes(reference: (u32, u32), test: (u32, u32)) -> Result<(), MetricsError> {
    if reference != test {
        return Err(MetricsError::SizeMismatch { reference, test });
    }
    if reference.0 < WINDOW || reference.1 < WINDOW {
        return Err(MetricsError::TooSmall {
            width: reference.0,
            height: reference.1,
        });
    }
    Ok(())
}

/// The pixels the mean SSIM is taken over.
pub fn mean_region(width: u32, height: u32) -> Mask {
    Mask::interior(width, height, RADIUS as u32)
}

/// Gaussian-blurs five moment images in one sweep: `x`, `y`, `x^2`, `y^2`, `x y`.
fn blurred_moments(x: &Plane, y: &Plane) -> [Vec<f64>; 5] {
    let (w, h) = (x.width as usize, x.height as usize);
    let weights = gaussian_weights();
    // Horizontal pass over the products, then vertical pass.
    let mut horizontal: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; w * h]);
    for row in 0..h {
        for col in 0..w {
            let mut acc = [0.0f64; 5];
            for (k, &wk) in weights.iter().enumerate() {
                let c = reflect(col as isize + k as isize - RADIUS as isize, w);
                let a = f64::from(x.data[row * w + c]);
                let b = f64::from(y.data[row * w + c]);
                acc[0] += wk * a;
                acc[1] += wk * b;
                acc[2] += wk * a * a;
                acc[3] += wk * b * b;
                acc[4] += wk * a * b;
            }
            for (plane, value) in horizontal.iter_mut().zip(acc) {
                plane[row * w + col] = value;
            }
        }
    }
    let mut out: [Vec<f64>; 5] = std::array::from_fn(|_| vec![0.0; w * h]);
    for row in 0..h {
        for col in 0..w {
            for (plane, source) in out.iter_mut().zip(&horizontal) {
                plane[row * w + col] = weights
                    .iter()
                    .enumerate()
                    .map(|(k, &wk)| {
                        let r = reflect(row as isize + k as isize - RADIUS as isize, h);
                        wk * source[r * w + col]
                    })
                    .sum();
            }
        }
    }
    out
}

/// SSIM of two luma planes (values 0..255).
pub fn ssim_planes(reference: &Plane, test: &Plane) -> Result<Ssim, MetricsError> {
    check_sizes(reference.size(), test.size())?;
    let [mx, my, xx, yy, xy] = blurred_moments(reference, test);
    let (c1, c2) = (c1(), c2());
    let data = (0..mx.len())
        .map(|i| {
            let (ux, uy) = (mx[i], my[i]);
            let vx = xx[i] - ux * ux;
            let vy = yy[i] - uy * uy;
            let cov = xy[i] - ux * uy;
            let s = ((2.0 * ux * uy + c1) * (2.0 * cov + c2))
                / ((ux * ux + uy * uy + c1) * (vx + vy + c2));
            s as f32
        })
        .collect();
    let map = Plane {
        width: reference.width,
        height: reference.height,
        data,
    };
    let region = mean_region(map.width, map.height);
    let mean = map.mean(Some(&region)).unwrap_or(1.0);
    Ok(Ssim { mean, map })
}

/// SSIM of two sRGB-encoded images on their BT.601 luma.
pub fn ssim(reference: &image::RgbaImage, test: &image::RgbaImage) -> Result<Ssim, MetricsError> {
    check_sizes(reference.dimensions(), test.dimensions())?;
    ssim_planes(&Plane::luma(reference), &Plane::luma(test))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn window_is_normalised_and_symmetric() {
        let w = gaussian_weights();
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        for i in 0..RADIUS {
            assert_eq!(w[i], w[2 * RADIUS - i]);
        }
        assert!(w[RADIUS] > w[RADIUS - 1]);
    }

    #[test]
    fn reflect_matches_scipy() {
        let got: Vec<usize> = (-3..7).map(|i| reflect(i, 4)).collect();
        assert_eq!(got, vec![2, 1, 0, 0, 1, 2, 3, 3, 2, 1]);
    }

    #[test]
    fn identical_images_score_one_and_sizes_are_checked() {
        let plane = Plane::from_fn(16, 12, |x, y| ((x * 37 + y * 11) % 256) as f32);
        let s = ssim_planes(&plane, &plane).unwrap();
        assert!((s.mean - 1.0).abs() < 1e-9);
        assert!(s.map.data.iter().all(|v| (v - 1.0).abs() < 1e-6));
        let small = Plane::filled(10, 20, 0.0);
        assert!(matches!(
            ssim_planes(&small, &small),
            Err(MetricsError::TooSmall { .. })
        ));
        assert!(matches!(
            ssim_planes(&plane, &Plane::filled(16, 13, 0.0)),
            Err(MetricsError::SizeMismatch { .. })
        ));
    }

    #[test]
    fn constant_offset_lowers_only_luminance_term() {
        // Equal structure, shifted mean: S = (2 a b + C1) / (a^2 + b^2 + C1) everywhere.
        let a = Plane::filled(12, 12, 100.0);
        let b = Plane::filled(12, 12, 120.0);
        let s = ssim_planes(&a, &b).unwrap();
        let expect = (2.0 * 100.0 * 120.0 + c1()) / (100.0f64.powi(2) + 120.0f64.powi(2) + c1());
        assert!((s.mean - expect).abs() < 1e-6, "{} {expect}", s.mean);
    }
}
