//! No AA: the shared one-sample render, unchanged. It is the baseline every other technique is
//! compared with, and its scene render is the one FXAA and SMAA 1x post-process.

use crate::aa::Technique;
use crate::aa::info::{TechniqueInfo, anywhere};
use crate::graph::PassContext;
use crate::scene::renderer::SceneTargets;

/// Stable id, as on the command line.
pub const ID: &str = "none";

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "No AA",
    summary: "One sample per pixel at the pixel centre: the cheapest image and the baseline. Every \
         edge is a staircase, sub-pixel geometry breaks up or vanishes, and anything thinner than a \
         pixel flickers as the camera moves.",
    availability: anywhere,
    create: |_| Box::new(NoAa),
    shaders: &[],
};

/// The No AA technique.
pub struct NoAa;

impl Technique for NoAa {
    crate::aa::common::shared_1x_post_process!(INFO);

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
