//! TAA's debug views: `velocity` (the motion vectors it reprojects with), `jitter` (the sample
//! pattern inside one enlarged pixel, drawn by `taa_debug.wgsl`) and `rejection` (where the
//! history was rectified or dropped, written by the resolve itself as a third target).

use glam::Vec2;

use crate::aa::common::pass;
use crate::aa::common::temporal::jitter_offset;
use crate::aa::common::{debug_texture, encoded_view};
use crate::gpu::COLOR_FORMAT_ENCODED_VIEW;
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::graph::PassContext;

/// Longest jitter sequence (the jitter debug view's uniform holds this many positions).
const MAX_SAMPLES: usize = 16;
/// Speed in pixels per frame that the velocity view shows at half brightness.
const VELOCITY_HALF_SPEED: f32 = 2.0;

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DebugUniform {
    size: [f32; 4],
    samples: [[f32; 4]; MAX_SAMPLES],
}

/// Debug-view targets and the passes that fill the velocity and jitter views.
pub(super) struct TaaDebug {
    /// Written by the resolve's debug variant.
    pub(super) rejection: wgpu::Texture,
    pub(super) velocity: wgpu::Texture,
    pub(super) jitter: wgpu::Texture,
    pub(super) uniform: wgpu::Buffer,
    velocity_pipeline: wgpu::RenderPipeline,
    jitter_pipeline: wgpu::RenderPipeline,
}

impl TaaDebug {
    /// Builds the views' targets and pipelines for `size`.
    pub(super) fn new(
        ctx: &PassContext<'_>,
        device: &wgpu::Device,
        shader: &Shader,
        size: (u32, u32),
    ) -> Self {
        let module = shader.module(device);
        let pipeline = |entry_point: &str| {
            ctx.fullscreen.pipeline(
                device,
                &FragmentDesc {
                    label: &format!("taa {entry_point}"),
                    module: &module,
                    entry_point,
                    targets: &[COLOR_FORMAT_ENCODED_VIEW],
                    constants: &[],
                    layout: None,
                },
            )
        };
        Self {
            rejection: debug_texture(device, "taa rejection", size),
            velocity: debug_texture(device, "taa velocity", size),
            jitter: debug_texture(device, "taa jitter", size),
            uniform: pass::uniform_buffer::<DebugUniform>(device, "taa debug params"),
            velocity_pipeline: pipeline("fs_velocity"),
            jitter_pipeline: pipeline("fs_jitter"),
        }
    }

    /// The output size the views were made for.
    pub(super) fn size(&self) -> (u32, u32) {
        (self.rejection.width(), self.rejection.height())
    }

    /// Records the velocity and jitter views (the rejection view comes from the resolve) for a
    /// jitter sequence of `samples` positions.
    pub(super) fn encode(
        &self,
        ctx: &mut PassContext<'_>,
        device: &wgpu::Device,
        motion: &wgpu::Texture,
        samples: u32,
    ) {
        let (width, height) = (self.velocity.width(), self.velocity.height());
        let n = samples.min(MAX_SAMPLES as u32);
        let current = (ctx.frame.camera.frame % u64::from(n.max(1))) as u32;
        let mut uniform = DebugUniform {
            size: [width as f32, height as f32, VELOCITY_HALF_SPEED, n as f32],
            samples: [[0.0; 4]; MAX_SAMPLES],
        };
        for (k, slot) in uniform.samples.iter_mut().enumerate().take(n as usize) {
            let position = Vec2::splat(0.5) - jitter_offset(k as u64, n);
            let state = match (k as u32).cmp(&current) {
                std::cmp::Ordering::Less => 1.0,
                std::cmp::Ordering::Equal => 2.0,
                std::cmp::Ordering::Greater => 0.0,
            };
            *slot = [position.x, position.y, state, 0.0];
        }
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let motion_view = motion.create_view(&Default::default());
        let velocity_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("taa velocity view"),
            layout: &self.velocity_pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&motion_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: self.uniform.as_entire_binding(),
                },
            ],
        });
        let jitter_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("taa jitter view"),
            layout: &self.jitter_pipeline.get_bind_group_layout(0),
            entries: &[wgpu::BindGroupEntry {
                binding: 1,
                resource: self.uniform.as_entire_binding(),
            }],
        });
        ctx.fullscreen_pass(
            "debug velocity",
            &encoded_view(&self.velocity),
            &self.velocity_pipeline,
            &velocity_group,
        );
        ctx.fullscreen_pass(
            "debug jitter",
            &encoded_view(&self.jitter),
            &self.jitter_pipeline,
            &jitter_group,
        );
    }
}
