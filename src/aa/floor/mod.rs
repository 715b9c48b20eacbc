//! The physical floor of a post-process pass: a full-screen pass that copies the shared 1x
//! scene render to its output through a fragment shader (`shaders/metrics_copy.wgsl`). Any
//! post-process technique (FXAA, SMAA, TAA) reads at least every input pixel and writes every
//! output pixel, so this pass's GPU time is the least a post-process pass can cost on this
//! adapter at this size; `aa-lab bench` reports each post-process technique's passes as a
//! multiple of it.
//!
//! It implements [`Technique`] so that the frame graph schedules and times it like any other
//! (label `copy-floor/copy`), reading the same shared input as No AA, but it is deliberately
//! not in the registry: it is a measuring stick, not an antialiasing technique.

use crate::aa::{FrameInfo, SceneInput, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu, shader};
use crate::graph::PassContext;
use crate::scene::renderer::SceneTargets;

/// Id of the copy pass in timings (`copy-floor/copy`).
pub const COPY_FLOOR_ID: &str = "copy-floor";

/// The full-screen copy pass.
pub struct CopyFloor {
    device: wgpu::Device,
    pipeline: Option<wgpu::RenderPipeline>,
    /// Bind group for the (input, output) pair it was built for.
    bound: Option<(wgpu::Texture, wgpu::Texture, wgpu::BindGroup)>,
}

impl CopyFloor {
    /// Creates the pass (its pipeline is built on first use).
    pub fn new(gpu: &Gpu) -> Self {
        Self {
            device: gpu.device.clone(),
            pipeline: None,
            bound: None,
        }
    }
}

impl Technique for CopyFloor {
    fn id(&self) -> &'static str {
        COPY_FLOOR_ID
    }

    fn label(&self) -> String {
        COPY_FLOOR_ID.to_owned()
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
        let Some(input) = input else { return };
        let device = &self.device;
        let pipeline = self
            .pipeline
            .get_or_insert_with(|| {
                let module = shader::module(device, "metrics_copy.wgsl");
                ctx.fullscreen.pipeline(
                    device,
                    &FragmentDesc {
                        label: "copy floor",
                        module: &module,
                        entry_point: "fs_copy",
                        targets: &[COLOR_FORMAT_ENCODED_VIEW],
                        constants: &[],
                        layout: None,
                    },
                )
            })
            .clone();
        let encoded = wgpu::TextureViewDescriptor {
            format: Some(COLOR_FORMAT_ENCODED_VIEW),
            ..Default::default()
        };
        let stale = self
            .bound
            .as_ref()
            .is_none_or(|(i, o, _)| i != &input.color || o != output);
        if stale {
            let view = input.color.create_view(&encoded);
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("copy floor"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&view),
                }],
            });
            self.bound = Some((input.color.clone(), output.clone(), bind_group));
        }
        if let Some((_, _, bind_group)) = &self.bound {
            let target = output.create_view(&encoded);
            ctx.fullscreen_pass("copy", &target, &pipeline, bind_group);
        }
    }
}
