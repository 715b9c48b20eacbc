//! MSAA's debug views: how many of each pixel's samples geometry covers (from the multisampled
//! depth) and which pixels are "complex" (their samples differ: the only pixels MSAA
//! antialiases), drawn by `msaa_debug.wgsl` into textures of the output's size.

use crate::aa::common::debug_texture;
use crate::gpu::COLOR_FORMAT;
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::graph::PassContext;
use crate::scene::renderer::SceneTargets;

/// The debug views' pipelines and textures, for one output size.
pub(super) struct MsaaDebug {
    coverage_pipeline: wgpu::RenderPipeline,
    complex_pipeline: wgpu::RenderPipeline,
    /// Covered samples per pixel.
    pub(super) coverage: wgpu::Texture,
    /// The complex-pixel mask.
    pub(super) complex: wgpu::Texture,
}

impl MsaaDebug {
    /// Builds the pipelines and textures for `size`.
    pub(super) fn new(
        ctx: &PassContext<'_>,
        device: &wgpu::Device,
        id: &str,
        shader: &Shader,
        size: (u32, u32),
    ) -> Self {
        let module = shader.module(device);
        let pipeline = |entry_point: &str| {
            ctx.fullscreen.pipeline(
                device,
                &FragmentDesc {
                    label: &format!("{id} {entry_point}"),
                    module: &module,
                    entry_point,
                    targets: &[COLOR_FORMAT],
                    constants: &[],
                    layout: None,
                },
            )
        };
        Self {
            coverage_pipeline: pipeline("fs_coverage"),
            complex_pipeline: pipeline("fs_complex"),
            coverage: debug_texture(device, &format!("{id} coverage"), size),
            complex: debug_texture(device, &format!("{id} complex pixels"), size),
        }
    }

    /// The output size the views were made for.
    pub(super) fn size(&self) -> (u32, u32) {
        (self.coverage.width(), self.coverage.height())
    }

    /// Draws both views from the multisampled scene render.
    pub(super) fn encode(
        &self,
        ctx: &mut PassContext<'_>,
        device: &wgpu::Device,
        input: &SceneTargets,
    ) {
        let views = [
            (
                &self.coverage_pipeline,
                &self.coverage,
                &input.depth,
                "coverage",
            ),
            (
                &self.complex_pipeline,
                &self.complex,
                &input.color,
                "complex pixels",
            ),
        ];
        for (binding, (pipeline, target, source, name)) in views.into_iter().enumerate() {
            let source_view = source.create_view(&Default::default());
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(name),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: binding as u32,
                    resource: wgpu::BindingResource::TextureView(&source_view),
                }],
            });
            let target_view = target.create_view(&Default::default());
            ctx.fullscreen_pass(
                &format!("debug {name}"),
                &target_view,
                pipeline,
                &bind_group,
            );
        }
    }
}
