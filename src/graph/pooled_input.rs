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
    /// Whether this is `input` rendered at `size`, as radiance when `hdr`.
    pub(super) fn is(&self, input: SceneInput, size: (u32, u32), hdr: bool) -> bool {
        self.input == input && self.desc.size == size && self.desc.hdr == hdr
    }

    /// The input's label, with its size when it is rendered below the output size `output`.
    pub(super) fn label(&self, output: (u32, u32)) -> String {
        let mut label = self.input.label();
        if self.desc.size != output {
            let (width, height) = self.desc.size;
            label += &format!(" {width}x{height}");
        }
        if self.desc.hdr {
            label += " hdr";
        }
        label
    }
}
