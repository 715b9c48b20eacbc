//! Image-quality and performance metrics: a library first (the viewer's live panel uses it), and
//! the engine of `aa-lab compare` and `aa-lab bench`.
//!
//! - [`ssim`]: SSIM on BT.601 luma, mean and per-pixel map, agreeing with scikit-image;
//! - [`pixel`]: mean absolute error and PSNR on sRGB-encoded R'G'B';
//! - [`flip`]: NVIDIA's FLIP (LDR) error map and mean, through `nv-flip`;
//! - [`jod`]: ColorVideoVDP's perceptual video quality in JOD, through `colorvideovdp`;
//! - [`gpu`]: SSIM, MAE and PSNR in compute shaders, for live measurement at 1080p; the CPU
//!   functions above are the reference it is tested against;
//! - [`temporal`]: frame-to-frame change and the flicker ratio against a reference;
//! - [`stability`]: a clip's temporal instability, per-pixel change map and ghosting;
//! - [`series`]: the image metrics of a series of frames against its reference, and their summary;
//! - [`edges`]: edge gain, the share of No AA's error on the reference's edges a technique
//!   removes;
//! - [`coverage`]: exact analytic ground truth for the `chart` scene;
//! - [`stats`]: median and 95th percentile of repeated timings;
//! - [`map`]: the per-pixel planes and masks all of these share.
//!
//! [`compare_with_maps`] runs the image metrics together and keeps their maps, so that
//! [`ComparisonMaps::pool`] can score any region (the chart's test elements) without
//! recomputing anything.

pub mod coverage;
pub mod edges;
pub mod flip;
pub mod gpu;
pub mod hdr_flip;
pub mod jod;
pub mod map;
pub mod pixel;
pub mod series;
pub mod ssim;
pub mod stability;
pub mod stats;
pub mod temporal;

pub use map::{Mask, Plane};
pub use stats::Summary;

/// Errors of the metrics.
#[derive(Debug, thiserror::Error)]
pub enum MetricsError {
    /// The two images (or an image and a mask) differ in size.
    #[error(
        "the images differ in size: the reference is {}x{} but the test image is {}x{}",
        reference.0, reference.1, test.0, test.1
    )]
    SizeMismatch {
        /// Reference width and height.
        reference: (u32, u32),
        /// Test width and height.
        test: (u32, u32),
    },
    /// The images are smaller than the SSIM window.
    #[error(
        "a {width}x{height} image is too small to compare: SSIM needs at least {w}x{w} pixels (its Gaussian window)",
        w = ssim::WINDOW
    )]
    TooSmall {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
    },
    /// A frame of a clip scored against the reference came without the reference's image.
    #[error("a clip frame came without the reference image it is scored against")]
    NoReference,
    /// A clip frame came with another number of technique images than the metrics measure.
    #[error("a clip frame has {got} technique images but {expected} techniques are measured")]
    FrameCount {
        /// Techniques measured.
        expected: usize,
        /// Images given.
        got: usize,
    },
    /// ColorVideoVDP refused the frames or the display model (see [`jod`]).
    #[error("ColorVideoVDP: {0}")]
    Jod(String),
    /// A temporal map was asked of two still images.
    #[error("temporal instability is measured over a recorded clip, not between two images")]
    NotTemporal,
}

/// The per-pixel metrics a [`Metric`] names, for heatmaps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Metric {
    /// SSIM map (1 = identical structure).
    Ssim,
    /// FLIP error map (0 = indistinguishable, 1 = maximal).
    Flip,
    /// Absolute error, mean over R'G'B', 0..255.
    Mae,
}

impl Metric {
    /// Every metric with a per-pixel map.
    pub const ALL: [Metric; 3] = [Metric::Ssim, Metric::Flip, Metric::Mae];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Metric::Ssim => "ssim",
            Metric::Flip => "flip",
            Metric::Mae => "mae",
        }
    }

    /// Parses a command-line name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|m| m.name() == name)
    }

    /// What the map shows, for legends.
    pub fn legend(self) -> &'static str {
        match self {
            Metric::Ssim => "SSIM dissimilarity (1 - SSIM)",
            Metric::Flip => "FLIP error",
            Metric::Mae => "absolute error (0..255, mean of R'G'B')",
        }
    }
}

/// Scores of a test image against a reference.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Comparison {
    /// Mean SSIM on luma (1 = identical).
    pub ssim: f64,
    /// PSNR in dB on R'G'B' (infinite for identical images; `null` in JSON).
    pub psnr: f64,
    /// Mean absolute error on R'G'B', 0..255.
    pub mae: f64,
    /// Mean FLIP error, 0..1.
    pub flip: f64,
}

/// The per-pixel maps behind a [`Comparison`].
#[derive(Clone, Debug)]
pub struct ComparisonMaps {
    /// SSIM per pixel.
    pub ssim: Plane,
    /// Absolute and squared error per pixel.
    pub errors: pixel::PixelErrorMaps,
    /// FLIP error per pixel.
    pub flip: Plane,
}

impl ComparisonMaps {
    /// Pools the maps over `region` (the whole image when `None`). SSIM is always pooled over
    /// pixels whose window stays inside the image, as [`ssim`] defines its mean; a region with
    /// no such pixel scores as the whole image would.
    pub fn pool(&self, region: Option<&Mask>) -> Comparison {
        let (w, h) = self.ssim.size();
        let interior = ssim::mean_region(w, h);
        let ssim_region = region.map_or_else(|| interior.clone(), |r| r.and(&interior));
        let ssim = self
            .ssim
            .mean(Some(&ssim_region))
            .or_else(|| self.ssim.mean(Some(&interior)))
            .unwrap_or(1.0);
        let errors = self.errors.pool(region);
        Comparison {
            ssim,
            psnr: errors.psnr(),
            mae: errors.mae,
            flip: self.flip.mean(region).unwrap_or(0.0),
        }
    }

    /// The map of a metric, oriented so that larger is worse (SSIM becomes `1 - SSIM`).
    pub fn error_map(&self, metric: Metric) -> Plane {
        match metric {
            Metric::Ssim => Plane {
                data: self.ssim.data.iter().map(|v| 1.0 - v).collect(),
                ..self.ssim.clone()
            },
            Metric::Flip => self.flip.clone(),
            Metric::Mae => self.errors.abs_error.clone(),
        }
    }
}

/// Computes every image metric of `test` against `reference` and keeps the maps.
pub fn compare_with_maps(
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<(Comparison, ComparisonMaps), MetricsError> {
    let ssim = ssim::ssim(reference, test)?;
    let maps = ComparisonMaps {
        ssim: ssim.map,
        errors: pixel::error_maps(reference, test)?,
        flip: flip::flip_map(reference, test)?,
    };
    Ok((maps.pool(None), maps))
}

/// Computes every image metric of `test` against `reference`.
pub fn compare(
    reference: &image::RgbaImage,
    test: &image::RgbaImage,
) -> Result<Comparison, MetricsError> {
    compare_with_maps(reference, test).map(|(c, _)| c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn comparison_pools_maps_and_regions() {
        let reference = image::RgbaImage::from_fn(24, 16, |x, y| {
            let v = ((x * 11 + y * 7) % 200) as u8;
            image::Rgba([v, v / 2, 255 - v, 255])
        });
        let mut test = reference.clone();
        for x in 0..6 {
            test.put_pixel(x, 3, image::Rgba([0, 0, 0, 255]));
        }
        let (all, maps) = compare_with_maps(&reference, &test).unwrap();
        assert!(all.ssim < 1.0 && all.mae > 0.0 && all.flip > 0.0 && all.psnr.is_finite());
        // A region away from the damage scores as identical.
        let clean = Mask::from_fn(24, 16, |x, y| x > 16 && y > 8);
        let local = maps.pool(Some(&clean));
        assert_eq!(local.mae, 0.0);
        assert_eq!(local.psnr, f64::INFINITY);
        assert!((local.ssim - 1.0).abs() < 1e-6);
        assert!((compare(&reference, &reference).unwrap().ssim - 1.0).abs() < 1e-12);
        let flipped = maps.error_map(Metric::Ssim);
        assert!(flipped.data.iter().all(|&v| v >= -1e-6));
        assert_eq!(Metric::from_name("flip"), Some(Metric::Flip));
        assert_eq!(Metric::from_name("psnr"), None);
    }
}
