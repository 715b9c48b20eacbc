//! The CPU metrics against the conventional implementations, on small crops of real renders
//! (hairball No AA vs SSAA, atrium MSAA 4x vs SSAA) and a noisy pair, all under
//! tests/fixtures/metrics/. The expected values were computed once with scikit-image 0.26.0
//! (NumPy 2.4, SciPy 1.17) by this snippet, run in that folder:
//!
//! ```python
//! import numpy as np
//! from PIL import Image
//! from skimage.metrics import structural_similarity, peak_signal_noise_ratio
//! def load(p): return np.asarray(Image.open(p).convert('RGBA')).astype(np.float64)
//! def luma(a): return 0.299 * a[..., 0] + 0.587 * a[..., 1] + 0.114 * a[..., 2]
//! for ref, test in [('hairball_ssaa', 'hairball_none'), ('atrium_ssaa', 'atrium_msaa4'),
//!                   ('noise_clean', 'noise_noisy')]:
//!     a, b = load(f'{ref}.png'), load(f'{test}.png')
//!     mean, smap = structural_similarity(luma(a), luma(b), gaussian_weights=True, sigma=1.5,
//!         use_sample_covariance=False, data_range=255, full=True)
//!     psnr = peak_signal_noise_ratio(a[..., :3], b[..., :3], data_range=255)
//!     mae = np.abs(a[..., :3] - b[..., :3]).mean()
//!     h, w = smap.shape
//!     probes = [(0, 0), (w - 1, h - 1), (3, h // 2), (w // 2, 1), (w // 2, h // 2)]
//!     print(ref, test, mean, psnr, mae, [(x, y, smap[y, x]) for x, y in probes])
//! ```
//!
//! The probes include corner and edge pixels, where the window is mirrored.

mod common;

use aa_lab::metrics::{self, ssim};

/// (reference, test, mean SSIM, PSNR dB, MAE, SSIM map probes (x, y, value)).
type Expected = (
    &'static str,
    &'static str,
    f64,
    f64,
    f64,
    &'static [(u32, u32, f64)],
);

const EXPECTED: &[Expected] = &[
    (
        "hairball_ssaa",
        "hairball_none",
        0.497488695,
        14.976807243,
        34.325183256,
        &[
            (0, 0, 0.789779957),
            (95, 71, 0.563845648),
            (3, 36, 0.619241959),
            (48, 1, 0.528582997),
            (48, 36, 0.433791737),
        ],
    ),
    (
        "atrium_ssaa",
        "atrium_msaa4",
        0.969670396,
        39.666737990,
        1.361593364,
        &[
            (0, 0, 0.995127668),
            (95, 71, 0.993591395),
            (3, 36, 0.978539797),
            (48, 1, 0.980262482),
            (48, 36, 0.990104131),
        ],
    ),
    (
        "noise_clean",
        "noise_noisy",
        0.574342364,
        25.163516828,
        12.232757348,
        &[
            (0, 0, 0.668282077),
            (60, 36, 0.406362875),
            (3, 18, 0.843096131),
            (30, 1, 0.389635188),
            (30, 18, 0.444658311),
        ],
    ),
];

#[test]
fn ssim_psnr_and_mae_agree_with_scikit_image() {
    for &(reference, test, mean, psnr, mae, probes) in EXPECTED {
        let (a, b) = (
            common::metrics_fixture(reference),
            common::metrics_fixture(test),
        );
        let s = ssim::ssim(&a, &b).unwrap();
        assert!(
            (s.mean - mean).abs() < 1e-4,
            "{test}: SSIM {} vs scikit-image {mean}",
            s.mean
        );
        for &(x, y, value) in probes {
            let got = f64::from(s.map.at(x, y));
            assert!(
                (got - value).abs() < 1e-4,
                "{test}: SSIM map at ({x}, {y}) {got} vs {value}"
            );
        }
        let c = metrics::compare(&a, &b).unwrap();
        assert!((c.ssim - s.mean).abs() < 1e-12);
        assert!(
            (c.psnr - psnr).abs() < 1e-6,
            "{test}: PSNR {} vs {psnr}",
            c.psnr
        );
        assert!((c.mae - mae).abs() < 1e-6, "{test}: MAE {} vs {mae}", c.mae);
        assert!(c.flip > 0.0 && c.flip < 1.0, "{test}: FLIP {}", c.flip);
    }
}

#[test]
fn better_antialiasing_scores_better_on_every_metric() {
    let reference = common::metrics_fixture("hairball_ssaa");
    let aliased = metrics::compare(&reference, &common::metrics_fixture("hairball_none")).unwrap();
    let same = metrics::compare(&reference, &reference).unwrap();
    assert!(same.ssim > aliased.ssim);
    assert!(same.flip < aliased.flip && same.mae < aliased.mae);
    assert_eq!(same.psnr, f64::INFINITY);
}
