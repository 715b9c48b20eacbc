//! No AA: the shared one-sample render, unchanged. It is the baseline every other technique is
//! compared with, and its scene render is the one FXAA and SMAA 1x post-process.

use super::{FrameInfo, SceneInput, Technique};
use crate::graph::PassContext;
use crate::scene::renderer::SceneTargets;

/// The No AA technique.
pub struct NoAa;

impl Technique for NoAa {
    fn id(&self) -> &'static str {
        "none"
    }

    fn label(&self) -> String {
        super::registry::display_name(self.id())
    }

    fn color_only(&self) -> bool {
        true
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        Some(SceneInput::Shared1x)
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        if let Some(input) = input {
            ctx.copy_texture("copy", &input.color, output);
        }
    }
}
