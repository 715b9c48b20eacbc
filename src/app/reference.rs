//! The viewer's reference image: supersampling accumulated progressively while the camera is
//! still, so that quality figures converge within seconds without one long frame.
//!
//! It is a frame-graph technique with the id `reference` (so its passes are timed and its
//! memory counted like any other) wrapping [`Ssaa::encode_progressive`] with the k x k grid
//! and box filter of the CLI's ordered reference (`--ssaa-factor k`): once complete, the two
//! take the same samples. The viewer steers it through a shared [`ReferenceControl`]: whether
//! to start over (the view changed) and how many samples to add this frame; the technique
//! reports back how many samples the image rests on.

use crate::graph::hdr::TonemapOrder;
use std::sync::{Arc, Mutex, MutexGuard, PoisonError};

use crate::aa::ssaa::{Progress, Ssaa, SsaaSettings};
use crate::aa::{FrameInfo, SceneInput, Technique};
use crate::gpu::Gpu;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Id of the reference in the frame graph (timings read `reference/...`).
pub const REFERENCE_ID: &str = "reference";

/// Shared between the viewer and the technique inside the graph.
#[derive(Clone, Copy, Debug, Default)]
pub struct ReferenceControl {
    /// Drop the accumulated samples before adding new ones.
    pub restart: bool,
    /// Samples to add in the next frame.
    pub budget: u32,
    /// Where the accumulation stands after the last frame.
    pub progress: Progress,
}

/// The control as the viewer and the technique share it (the technique may live on another
/// thread than the viewer's panels).
#[derive(Clone, Debug, Default)]
pub struct SharedControl(Arc<Mutex<ReferenceControl>>);

impl SharedControl {
    /// Exclusive access; a panic elsewhere while it was held leaves plain data behind, which
    /// stays usable.
    pub fn lock(&self) -> MutexGuard<'_, ReferenceControl> {
        self.0.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The progressive reference technique.
pub struct ProgressiveReference {
    ssaa: Ssaa,
    control: SharedControl,
}

impl ProgressiveReference {
    /// A reference of `samples` samples per pixel (a square: 16, 64, 256) and its control.
    pub fn new(gpu: &Gpu, samples: u32) -> (Self, SharedControl) {
        let control = SharedControl::default();
        let reference = Self {
            ssaa: Ssaa::with_settings(gpu, SsaaSettings::reference(grid_factor(samples))),
            control: control.clone(),
        };
        (reference, control)
    }
}

/// The grid factor k of a square sample count (k x k = samples).
pub fn grid_factor(samples: u32) -> u32 {
    ((samples.max(1) as f32).sqrt().round() as u32).max(1)
}

impl Technique for ProgressiveReference {
    fn id(&self) -> &'static str {
        REFERENCE_ID
    }

    fn label(&self) -> String {
        "Reference".to_owned()
    }

    /// The reference averages radiance and is tonemapped afterwards, as a camera would.
    fn tonemap_order(&self) -> TonemapOrder {
        TonemapOrder::Before
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        None
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        _input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let mut control = self.control.lock();
        control.progress =
            self.ssaa
                .encode_progressive(ctx, output, control.restart, control.budget.max(1));
        control.restart = false;
    }

    fn memory(&self) -> Vec<MemoryItem> {
        self.ssaa.memory()
    }

    fn path_note(&self) -> Option<String> {
        let progress = self.control.lock().progress;
        Some(format!(
            "progressive {}-sample grid, box filter: {} of {} samples",
            progress.total, progress.samples, progress.total
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_factors_of_square_counts() {
        assert_eq!(grid_factor(16), 4);
        assert_eq!(grid_factor(64), 8);
        assert_eq!(grid_factor(256), 16);
        assert_eq!(grid_factor(0), 1);
    }
}
