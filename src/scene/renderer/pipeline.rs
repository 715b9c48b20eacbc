//! The scene's render pipelines: one per [`PipelineKey`], built from `shaders/scene.wgsl`
//! with the key's entry points (by [`ShadingRate`]) and override constants
//! (`ALPHA_TO_COVERAGE`, `SPECULAR_AA`, `ANISOTROPIC`, `DETAIL`, `BLENDED`, `OUTPUT` and
//! `OPERATOR`), so that a switch that is off compiles to the shader without it rather than to
//! a branch on a uniform. Blended
//! pipelines composite premultiplied colour over the target, test depth without writing it,
//! leave motion alone and composite their alpha into the reactive mask; opaque ones leave the
//! mask at its clear value, zero.

use super::output::SceneOutput;
use super::{REACTIVE_FORMAT, RasterOptions, ShadingRate, Vertex};
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
    /// The material's texture goes through the shader's anisotropic filter (`ANISOTROPIC`);
    /// without it one plain lookup, so untextured scenes pay nothing for the filter.
    pub anisotropic: bool,
    /// The material has normal detail (`DETAIL`); without it the shader skips the detail.
    pub detail: bool,
    /// Geometric specular antialiasing (see `SceneRenderer::set_specular_aa`).
    pub specular_aa: bool,
    /// What the colour target receives (and so its format).
    pub output: SceneOutput,
    /// An alpha-blended material's pipeline.
    pub blend: bool,
    /// Reactive-mask target present.
    pub reactive_mask: bool,
}

/// Premultiplied "over": the source plus what its alpha leaves of the destination.
const PREMULTIPLIED_OVER: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
    operation: wgpu::BlendOperation::Add,
};

/// The reactive mask's "over": coverage a over m gives a + m (1 - a).
const COVERAGE_OVER: wgpu::BlendComponent = wgpu::BlendComponent {
    src_factor: wgpu::BlendFactor::One,
    dst_factor: wgpu::BlendFactor::OneMinusSrc,
    operation: wgpu::BlendOperation::Add,
};

/// The colour, motion and reactive-mask targets of `key`'s pipeline.
fn targets(key: &PipelineKey) -> Vec<Option<wgpu::ColorTargetState>> {
    let blend = key.blend.then_some(wgpu::BlendState {
        color: PREMULTIPLIED_OVER,
        alpha: PREMULTIPLIED_OVER,
    });
    let color_target = wgpu::ColorTargetState {
        format: match key.output {
            SceneOutput::Radiance => HDR_FORMAT,
            SceneOutput::Display | SceneOutput::Tonemapped(_) => COLOR_FORMAT,
        },
        blend,
        // Alpha keeps the clear value 1: with alpha-to-coverage the shader's alpha is a
        // coverage fraction, not an image alpha.
        write_mask: wgpu::ColorWrites::COLOR,
    };
    let motion_target = key.motion.then_some(wgpu::ColorTargetState {
        format: MOTION_FORMAT,
        blend: None,
        // Blended surfaces keep the motion of the opaque surface behind them.
        write_mask: if key.blend {
            wgpu::ColorWrites::empty()
        } else {
            wgpu::ColorWrites::ALL
        },
    });
    let mut targets = vec![Some(color_target), motion_target];
    if key.reactive_mask {
        targets.push(Some(wgpu::ColorTargetState {
            format: REACTIVE_FORMAT,
            blend: key.blend.then_some(wgpu::BlendState {
                color: COVERAGE_OVER,
                alpha: COVERAGE_OVER,
            }),
            write_mask: if key.blend {
                wgpu::ColorWrites::RED
            } else {
                wgpu::ColorWrites::empty()
            },
        }));
    }
    targets
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
    let a2c = key.raster.alpha_to_coverage && key.sample_count > 1 && !key.blend;
    let flag = |on: bool| if on { 1.0 } else { 0.0 };
    let [output, operator] = key.output.constants();
    let constants = [
        ("ALPHA_TO_COVERAGE", flag(a2c)),
        ("SPECULAR_AA", flag(key.specular_aa)),
        ("ANISOTROPIC", flag(key.anisotropic)),
        ("DETAIL", flag(key.detail)),
        ("BLENDED", flag(key.blend)),
        output,
        operator,
    ];
    let options = wgpu::PipelineCompilationOptions {
        constants: &constants,
        ..Default::default()
    };
    let targets = targets(&key);
    let label = format!(
        "scene {}x {:?}{}{}{}{}{} {:?}",
        key.sample_count,
        key.raster.shading,
        if a2c { " a2c" } else { "" },
        if key.anisotropic { " anisotropic" } else { "" },
        if key.detail { " detail" } else { "" },
        if key.specular_aa { " specular-aa" } else { "" },
        if key.blend { " blend" } else { "" },
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
            depth_write_enabled: Some(!key.blend),
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
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}
