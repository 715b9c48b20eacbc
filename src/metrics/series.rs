//! The image figures of a series of frames against its reference, frame by frame: each pair's
//! SSIM, PSNR, MAE and FLIP ([`compare_with_maps`]) and their summary over the series (the
//! means; PSNR from the mean squared error of every frame, so that one identical frame does not
//! make it infinite; the worst frame by FLIP). `aa-lab compare` on two sequences and
//! `aa-lab clip` score their frames through this one accumulator, so the two report the same
//! figures for the same frames.

use super::pixel::psnr_from_mse;
use super::{Comparison, ComparisonMaps, MetricsError, compare_with_maps};

/// Every frame's figures so far, and the sum of their mean squared errors.
#[derive(Clone, Debug, Default)]
pub struct FrameSeries {
    per_frame: Vec<Comparison>,
    mse_sum: f64,
}

/// The figures of a whole series.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SeriesSummary {
    /// Means over the frames; PSNR from the mean squared error over all frames.
    #[serde(flatten)]
    pub scores: Comparison,
    /// The frame with the largest mean FLIP error (0-based).
    pub worst_frame: usize,
    /// That frame's mean FLIP error.
    pub worst_flip: f64,
}

impl FrameSeries {
    /// An empty series.
    pub fn new() -> Self {
        Self::default()
    }

    /// Scores the next frame pair and returns its maps (for heatmaps).
    pub fn push(
        &mut self,
        reference: &image::RgbaImage,
        test: &image::RgbaImage,
    ) -> Result<ComparisonMaps, MetricsError> {
        let (scores, maps) = compare_with_maps(reference, test)?;
        self.mse_sum += maps.errors.pool(None).mse;
        self.per_frame.push(scores);
        Ok(maps)
    }

    /// Each frame's figures, in order.
    pub fn per_frame(&self) -> &[Comparison] {
        &self.per_frame
    }

    /// The figures over every frame pushed so far (all zero for none).
    pub fn summary(&self) -> SeriesSummary {
        let count = self.per_frame.len().max(1) as f64;
        let mean = |f: fn(&Comparison) -> f64| self.per_frame.iter().map(f).sum::<f64>() / count;
        let worst = self
            .per_frame
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.flip.total_cmp(&b.1.flip));
        SeriesSummary {
            scores: Comparison {
                ssim: mean(|s| s.ssim),
                psnr: psnr_from_mse(self.mse_sum / count),
                mae: mean(|s| s.mae),
                flip: mean(|s| s.flip),
            },
            worst_frame: worst.map_or(0, |(i, _)| i),
            worst_flip: worst.map_or(0.0, |(_, s)| s.flip),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(shift: u32) -> image::RgbaImage {
        image::RgbaImage::from_fn(16, 16, |x, y| {
            let v = ((x + shift) * 13 + y * 5) as u8;
            image::Rgba([v, v, v, 255])
        })
    }

    #[test]
    fn the_summary_averages_the_frames_and_names_the_worst() {
        let reference = gradient(0);
        let mut series = FrameSeries::new();
        series.push(&reference, &reference).expect("scored");
        series.push(&reference, &gradient(3)).expect("scored");
        series.push(&reference, &gradient(1)).expect("scored");
        let summary = series.summary();
        let frames = series.per_frame();
        assert_eq!(frames.len(), 3);
        assert_eq!(frames[0].flip, 0.0);
        assert_eq!(summary.worst_frame, 1);
        assert_eq!(summary.worst_flip, frames[1].flip);
        let mean_ssim = frames.iter().map(|f| f.ssim).sum::<f64>() / 3.0;
        assert!((summary.scores.ssim - mean_ssim).abs() < 1e-12);
        // One identical frame does not make the PSNR of the series infinite.
        assert!(summary.scores.psnr.is_finite());
    }
}
