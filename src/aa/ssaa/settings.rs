//! SSAA's settings: ordered grid or jittered accumulation, the grid factor, the jittered
//! sample count, pattern and reconstruction filter.

use crate::aa::common::sampling::{Filter, Pattern};
use crate::graph::hdr::TonemapOrder;

crate::named_enum! {
    /// How the samples are taken (the `mode` parameter).
    pub enum Mode {
        /// Render k times larger and average k x k blocks (the classic SSAA and the reference).
        Ordered => "ordered",
        /// Accumulate N one-sample renders at the positions of a pattern with a reconstruction
        /// filter.
        Jittered => "jittered",
    }
}

/// Largest ordered-grid factor (8 x 8 = 64 samples).
pub const MAX_FACTOR: u32 = 8;
/// Largest jittered sample count.
pub const MAX_SAMPLES: u32 = 256;

/// Supersampling settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsaaSettings {
    /// Ordered grid or jittered accumulation.
    pub mode: Mode,
    /// Ordered-grid factor k (k x k samples).
    pub factor: u32,
    /// Jittered sample count.
    pub samples: u32,
    /// Jittered pattern.
    pub pattern: Pattern,
    /// Jittered reconstruction filter.
    pub filter: Filter,
    /// In HDR frames: average radiance and tonemap the average, as a camera would (before, the
    /// default and the reference's), or tonemap every sample and average the displayed values
    /// (after: the display-referred ideal that tonemap-aware resolves approximate).
    pub tonemap_order: TonemapOrder,
}

impl Default for SsaaSettings {
    fn default() -> Self {
        Self {
            mode: Mode::Ordered,
            factor: 2,
            samples: 16,
            pattern: Pattern::RotatedGrid,
            filter: Filter::Box,
            tonemap_order: TonemapOrder::Before,
        }
    }
}

impl SsaaSettings {
    /// The ordered-grid reference: `factor` x `factor` samples, box filter.
    pub fn reference(factor: u32) -> Self {
        Self {
            mode: Mode::Ordered,
            factor,
            ..Self::default()
        }
    }

    /// Samples per pixel.
    pub fn samples_per_pixel(&self) -> u32 {
        if self.mode == Mode::Ordered {
            self.factor * self.factor
        } else {
            self.pattern.effective_count(self.samples)
        }
    }
}
