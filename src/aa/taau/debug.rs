//! The temporal upscaler's debug views at the output size: `motion` (the motion vectors it
//! reprojects with), `disocclusion` (where the history was dropped), `confidence` (samples
//! accumulated), `weight` (the new samples' kernel weight) and `reactive` (the reactive mask).
//! The resolve's debug variant writes one state image per frame; `taau_debug.wgsl` draws each
//! view from it (and the motion view from the motion vectors).

use crate::aa::common::pass::{self, Binding};
use crate::aa::common::{debug_texture, encoded_view};
use crate::gpu::COLOR_FORMAT_ENCODED_VIEW;
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::graph::PassContext;

/// Format of the state image the resolve writes.
pub(super) const STATE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Speed in output pixels per frame that the motion view draws at half saturation.
const MOTION_HALF_SPEED: f32 = 2.0;

/// Every view: name, description, fragment entry point.
const VIEWS: [(&str, &str, &str); 5] = [
    (
        "motion",
        "Motion vectors the history is reprojected with (of the nearest surface), in output \
         pixels per frame: red grows to the right, green downwards, grey is still; the further \
         from grey, the faster (half way at 2 pixels per frame).",
        "fs_motion",
    ),
    (
        "disocclusion",
        "Where the history was dropped: red where the reprojected place held another surface \
         (disocclusion, from the depth kept with the history), blue on a reset or where the \
         history falls off screen; dark where it was kept.",
        "fs_disocclusion",
    ),
    (
        "confidence",
        "History confidence: the samples accumulated (in kernel weight), black none, white the \
         most the history keeps (max_samples).",
        "fs_confidence",
    ),
    (
        "weight",
        "The new samples' weight this frame: the sum of their kernel weights at the pixel \
         (black none, yellow as much as one sample at the centre). Below native the samples \
         fall on a few output pixels each frame and move with the jitter.",
        "fs_weight",
    ),
    (
        "reactive",
        "The reactive mask: magenta where a surface moves on its own (its motion differs from \
         what the camera explains), as far as it leans on the current frame.",
        "fs_reactive",
    ),
];

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ViewUniform {
    size: [f32; 4],
}

/// The state image, the views and the passes that draw them.
pub(super) struct TaauDebug {
    /// Written by the resolve's debug variant.
    pub(super) state: wgpu::Texture,
    views: Vec<wgpu::Texture>,
    uniform: wgpu::Buffer,
    layout: wgpu::BindGroupLayout,
    pipelines: Vec<wgpu::RenderPipeline>,
}

impl TaauDebug {
    /// Builds the views' targets and pipelines for the output `size`.
    pub(super) fn new(
        ctx: &PassContext<'_>,
        device: &wgpu::Device,
        shader: &Shader,
        size: (u32, u32),
    ) -> Self {
        let module = shader.module(device);
        let layout = pass::layout(
            device,
            "taau debug",
            &[
                (0, Binding::Texture),
                (1, Binding::Texture),
                (2, Binding::Uniform),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("taau debug"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipelines = VIEWS
            .iter()
            .map(|(_, _, entry_point)| {
                ctx.fullscreen.pipeline(
                    device,
                    &FragmentDesc {
                        label: &format!("taau {entry_point}"),
                        module: &module,
                        entry_point,
                        targets: &[COLOR_FORMAT_ENCODED_VIEW],
                        constants: &[],
                        layout: Some(&pipeline_layout),
                    },
                )
            })
            .collect();
        Self {
            state: pass::target(device, "taau debug state", size, STATE_FORMAT, &[]),
            views: VIEWS
                .iter()
                .map(|(name, _, _)| debug_texture(device, &format!("taau {name}"), size))
                .collect(),
            uniform: pass::uniform_buffer::<ViewUniform>(device, "taau debug params"),
            layout,
            pipelines,
        }
    }

    /// The output size the views were made for.
    pub(super) fn size(&self) -> (u32, u32) {
        (self.state.width(), self.state.height())
    }

    /// Draws every view from the state image the resolve wrote and the motion vectors.
    pub(super) fn encode(
        &self,
        ctx: &mut PassContext<'_>,
        device: &wgpu::Device,
        motion: &wgpu::Texture,
        max_samples: f32,
    ) {
        let (width, height) = self.size();
        let uniform = ViewUniform {
            size: [width as f32, height as f32, MOTION_HALF_SPEED, max_samples],
        };
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let state_view = self.state.create_view(&Default::default());
        let motion_view = motion.create_view(&Default::default());
        let group = pass::bind_group(
            device,
            "taau debug",
            &self.layout,
            &[
                (0, wgpu::BindingResource::TextureView(&state_view)),
                (1, wgpu::BindingResource::TextureView(&motion_view)),
                (2, self.uniform.as_entire_binding()),
            ],
        );
        for (((name, _, _), texture), pipeline) in
            VIEWS.iter().zip(&self.views).zip(&self.pipelines)
        {
            ctx.fullscreen_pass(
                &format!("debug {name}"),
                &encoded_view(texture),
                pipeline,
                &group,
            );
        }
    }

    /// The views, named and described.
    pub(super) fn views(&self) -> Vec<crate::aa::DebugView<'_>> {
        VIEWS
            .iter()
            .zip(&self.views)
            .map(|((name, description, _), texture)| crate::aa::DebugView {
                name,
                description,
                texture,
            })
            .collect()
    }

    /// The memory the views hold.
    pub(super) fn memory(&self) -> Vec<crate::graph::MemoryItem> {
        let mut items = vec![
            crate::graph::MemoryItem::texture("taau debug state", &self.state),
            crate::graph::MemoryItem::buffer("taau debug params", &self.uniform),
        ];
        items.extend(VIEWS.iter().zip(&self.views).map(|((name, _, _), t)| {
            crate::graph::MemoryItem::texture(format!("taau {name} view"), t)
        }));
        items
    }
}
