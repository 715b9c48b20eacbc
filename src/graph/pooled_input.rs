//! A distinct scene input of a frame in the frame graph's pool (see `FrameGraph::plan_inputs`).

use super::SceneInput;
use crate::scene::renderer::TargetDesc;

/// A distinct scene input of a frame: which pooled target holds it, and whether a technique
/// that runs in the frame reads it (it is rendered then; otherwise it holds an earlier
/// frame's render for a technique that keeps its image).
pub(super) struct PooledInput {
    pub(super) input: SceneInput,
    pub(super) desc: TargetDesc,
    /// Index among the pooled targets of `desc`.
    pub(super) index: usize,
    pub(super) rendered: bool,
}

impl PooledInput {
    /// Whether this is `input` rendered at `size`.
    pub(super) fn is(&self, input: SceneInput, size: (u32, u32)) -> bool {
        self.input == input && self.desc.size == size
    }

    /// The input's label, with its size when it is rendered below the output size `output`.
    pub(super) fn label(&self, output: (u32, u32)) -> String {
        if self.desc.size == output {
            self.input.label()
        } else {
            let (width, height) = self.desc.size;
            format!("{} {width}x{height}", self.input.label())
        }
    }
}
