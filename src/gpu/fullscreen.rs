//! The fullscreen-triangle helper every post-process pass uses: one shared vertex stage
//! (`shaders/fullscreen.wgsl`) and a function that builds a pass pipeline from a fragment
//! entry point with override constants, so techniques write only their fragment shaders.

use super::shader;

/// The shared vertex stage.
pub struct Fullscreen {
    vertex: wgpu::ShaderModule,
}

/// A fragment stage for [`Fullscreen::pipeline`].
pub struct FragmentDesc<'a> {
    /// Pipeline label.
    pub label: &'a str,
    /// Module holding the fragment entry point.
    pub module: &'a wgpu::ShaderModule,
    /// Entry point name.
    pub entry_point: &'a str,
    /// Colour target formats, one per attachment.
    pub targets: &'a [wgpu::TextureFormat],
    /// WGSL `override` constants.
    pub constants: &'a [(&'a str, f64)],
    /// Explicit pipeline layout; `None` derives it from the shader.
    pub layout: Option<&'a wgpu::PipelineLayout>,
}

impl Fullscreen {
    /// Compiles the vertex stage.
    pub fn new(device: &wgpu::Device) -> Self {
        Self {
            vertex: shader::module(device, "fullscreen.wgsl"),
        }
    }

    /// A render pipeline drawing one fullscreen triangle with `fragment`, no blending, no
    /// depth, one sample.
    pub fn pipeline(
        &self,
        device: &wgpu::Device,
        fragment: &FragmentDesc<'_>,
    ) -> wgpu::RenderPipeline {
        self.pipeline_with_depth(device, fragment, None)
    }

    /// [`Fullscreen::pipeline`] with a depth/stencil state (passes masked by a stencil, or
    /// writing depth).
    pub fn pipeline_with_depth(
        &self,
        device: &wgpu::Device,
        fragment: &FragmentDesc<'_>,
        depth_stencil: Option<wgpu::DepthStencilState>,
    ) -> wgpu::RenderPipeline {
        self.build(device, fragment, depth_stencil, None, 1)
    }

    /// [`Fullscreen::pipeline`] blending its colour over the target with `blend`, into a
    /// target of `sample_count` samples (every sample of a pixel gets the same colour).
    pub fn pipeline_blended(
        &self,
        device: &wgpu::Device,
        fragment: &FragmentDesc<'_>,
        blend: wgpu::BlendState,
        sample_count: u32,
    ) -> wgpu::RenderPipeline {
        self.build(device, fragment, None, Some(blend), sample_count)
    }

    fn build(
        &self,
        device: &wgpu::Device,
        fragment: &FragmentDesc<'_>,
        depth_stencil: Option<wgpu::DepthStencilState>,
        blend: Option<wgpu::BlendState>,
        sample_count: u32,
    ) -> wgpu::RenderPipeline {
        let targets: Vec<Option<wgpu::ColorTargetState>> = fragment
            .targets
            .iter()
            .map(|&format| {
                Some(wgpu::ColorTargetState {
                    format,
                    blend,
                    write_mask: wgpu::ColorWrites::ALL,
                })
            })
            .collect();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(fragment.label),
            layout: fragment.layout,
            vertex: wgpu::VertexState {
                module: &self.vertex,
                entry_point: Some("vs_fullscreen"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: Default::default(),
            depth_stencil,
            multisample: wgpu::MultisampleState {
                count: sample_count,
                ..Default::default()
            },
            fragment: Some(wgpu::FragmentState {
                module: fragment.module,
                entry_point: Some(fragment.entry_point),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: fragment.constants,
                    ..Default::default()
                },
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}
