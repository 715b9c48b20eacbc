//! The scene's render pipelines: one per [`PipelineKey`], built from `shaders/scene.wgsl`
//! with the key's entry points (by [`ShadingRate`]) and override constants
//! (`ALPHA_TO_COVERAGE`, `SPECULAR_AA`, `OUTPUT` and `OPERATOR`), so that a switch that is off compiles to the shader
//! without it rather than to a branch on a uniform.

use super::output::SceneOutput;
use super::{RasterOptions, ShadingRate, Vertex};
use crate::gpu::{COLOR_FORMAT, DEPTH_FORMAT, HDR_FORMAT, MOTION_FORMAT};

/// Everything that changes a scene pipeline.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    /// Samples per pixel.
    pub sample_count: u32,
    /// Motion target present.
    pub motion: bool,
    /// Rasterisation options (alpha-to-coverage forced off for one sample).
    pub raster: RasterOptions,
    /// Back-face culling.
    pub cull_back: bool,
    /// Geometric specular antialiasing (see `SceneRenderer::set_specular_aa`).
    pub specular_aa: bool,
    /// What the colour target receives (and so its format).
    pub output: SceneOutput,
}

/// Builds the pipeline of `key` from the scene shader module.
pub(super) fn create(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    key: PipelineKey,
) -> wgpu::RenderPipeline {
    let (vs, fs) = match key.raster.shading {
        ShadingRate::Pixel => ("vs_center", "fs_center"),
        ShadingRate::Centroid => ("vs_centroid", "fs_centroid"),
        ShadingRate::Sample => ("vs_sample", "fs_sample"),
    };
    let a2c = key.raster.alpha_to_coverage && key.sample_count > 1;
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    let [output, operator] = key.output.constants();
    let constants = [
        ("ALPHA_TO_COVERAGE", flag(a2c)),
        ("SPECULAR_AA", flag(key.specular_aa)),
        output,
        operator,
    ];
    let options = wgpu::PipelineCompilationOptions {
        constants: &constants,
        ..Default::default()
    };
    let color_target = wgpu::ColorTargetState {
        format: match key.output {
            SceneOutput::Radiance => HDR_FORMAT,
            SceneOutput::Display | SceneOutput::Tonemapped(_) => COLOR_FORMAT,
        },
        blend: None,
        // Alpha keeps the clear value 1: with alpha-to-coverage the shader's alpha is a
        // coverage fraction, not an image alpha.
        write_mask: wgpu::ColorWrites::COLOR,
    };
    let motion_target = key.motion.then_some(wgpu::ColorTargetState {
        format: MOTION_FORMAT,
        blend: None,
        write_mask: wgpu::ColorWrites::ALL,
    });
    let label = format!(
        "scene {}x {:?}{}{} {:?}",
        key.sample_count,
        key.raster.shading,
        if a2c { " a2c" } else { "" },
        if key.specular_aa { " specular-aa" } else { "" },
        key.output,
    );
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(&label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some(vs),
            compilation_options: options.clone(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2],
            })],
        },
        primitive: wgpu::PrimitiveState {
            cull_mode: key.cull_back.then_some(wgpu::Face::Back),
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Greater),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: key.sample_count,
            mask: !0,
            alpha_to_coverage_enabled: a2c,
        },
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(fs),
            compilation_options: options,
            targets: &[Some(color_target), motion_target],
        }),
        multiview_mask: None,
        cache: None,
    })
}
