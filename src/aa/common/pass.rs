//! The pieces a technique's full-screen passes are built from, spelled one way for every
//! technique: bind-group layouts declared as a list of `(binding, kind)` pairs ([`layout`],
//! [`stage_layout`] for compute passes;
//! explicit rather than derived from the shader, because several passes share one WGSL module
//! and a derived layout would list only what one entry point uses), bind groups from
//! resources in binding order ([`bind_group`]), full-screen pipelines with an optional
//! stencil test or mark ([`Vertex::pipeline`], over the shared `crate::gpu::fullscreen`
//! vertex stage), private render targets ([`target`]), a cleared colour attachment and a
//! stencil-tested draw ([`stencil_pass`]), and uniform buffers ([`uniform_buffer`]).

use crate::gpu::fullscreen::{FragmentDesc, Fullscreen};
use crate::graph::PassContext;

/// What one binding holds.
#[derive(Clone, Copy, Debug)]
pub enum Binding {
    /// A uniform buffer.
    Uniform,
    /// A filterable float texture (sampled or loaded).
    Texture,
    /// A depth texture, loaded.
    Depth,
    /// A multisampled colour texture, loaded.
    MultisampledTexture,
    /// A multisampled depth texture, loaded.
    MultisampledDepth,
    /// A filtering sampler.
    Sampler,
    /// A uniform buffer bound at a dynamic offset (one slot per draw).
    DynamicUniform,
    /// A float texture that is only loaded, of a format that need not be filterable.
    UnfilterableTexture,
    /// A read-write storage buffer.
    StorageBuffer,
    /// A 2D storage texture of this format, written only.
    WriteOnlyTexture(wgpu::TextureFormat),
}

/// A bind-group layout for fragment-stage bindings.
pub fn layout(
    device: &wgpu::Device,
    label: &str,
    bindings: &[(u32, Binding)],
) -> wgpu::BindGroupLayout {
    stage_layout(device, label, wgpu::ShaderStages::FRAGMENT, bindings)
}

/// A bind-group layout whose bindings are visible to `stage` (compute passes, or a pass
/// whose vertex stage reads them too).
pub fn stage_layout(
    device: &wgpu::Device,
    label: &str,
    stage: wgpu::ShaderStages,
    bindings: &[(u32, Binding)],
) -> wgpu::BindGroupLayout {
    let texture = |sample_type, multisampled| wgpu::BindingType::Texture {
        sample_type,
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled,
    };
    let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
        .iter()
        .map(|&(binding, kind)| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: stage,
            ty: match kind {
                Binding::Uniform | Binding::DynamicUniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: matches!(kind, Binding::DynamicUniform),
                    min_binding_size: None,
                },
                Binding::StorageBuffer => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Storage { read_only: false },
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Binding::UnfilterableTexture => {
                    texture(wgpu::TextureSampleType::Float { filterable: false }, false)
                }
                Binding::Texture => {
                    texture(wgpu::TextureSampleType::Float { filterable: true }, false)
                }
                Binding::Depth => texture(wgpu::TextureSampleType::Depth, false),
                Binding::MultisampledTexture => {
                    texture(wgpu::TextureSampleType::Float { filterable: false }, true)
                }
                Binding::MultisampledDepth => texture(wgpu::TextureSampleType::Depth, true),
                Binding::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                Binding::WriteOnlyTexture(format) => wgpu::BindingType::StorageTexture {
                    access: wgpu::StorageTextureAccess::WriteOnly,
                    format,
                    view_dimension: wgpu::TextureViewDimension::D2,
                },
            },
            count: None,
        })
        .collect();
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &entries,
    })
}

/// A bind group from `(binding, resource)` pairs.
pub fn bind_group(
    device: &wgpu::Device,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    resources: &[(u32, wgpu::BindingResource<'_>)],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = resources
        .iter()
        .map(|(binding, resource)| wgpu::BindGroupEntry {
            binding: *binding,
            resource: resource.clone(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// How a fullscreen pass uses a stencil attachment.
#[derive(Clone, Copy, Debug)]
pub enum Stencil {
    /// No depth-stencil attachment.
    None,
    /// Writes the reference value wherever a fragment survives (edge pass).
    Mark,
    /// Runs only where the stencil equals the reference value (weight pass).
    Test,
    /// Writes `@builtin(frag_depth)` into a depth attachment unconditionally.
    WriteDepth,
}

/// Stencil format of the edge mask.
pub const STENCIL_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Stencil8;

/// A fullscreen pipeline.
pub struct PassDesc<'a> {
    /// Label.
    pub label: &'a str,
    /// Module with the fragment entry point.
    pub module: &'a wgpu::ShaderModule,
    /// Entry point.
    pub entry_point: &'a str,
    /// Its bind-group layout (group 0).
    pub layout: &'a wgpu::BindGroupLayout,
    /// Colour target format.
    pub format: wgpu::TextureFormat,
    /// WGSL override constants.
    pub constants: &'a [(&'a str, f64)],
    /// Stencil use.
    pub stencil: Stencil,
}

/// The shared full-screen vertex stage, building SMAA's pipelines.
pub struct Vertex(Fullscreen);

impl Vertex {
    /// Compiles the vertex stage.
    pub fn new(device: &wgpu::Device) -> Self {
        Self(Fullscreen::new(device))
    }

    /// Builds a fullscreen pipeline drawing one triangle.
    pub fn pipeline(&self, device: &wgpu::Device, desc: &PassDesc<'_>) -> wgpu::RenderPipeline {
        let face = |compare, pass_op| wgpu::StencilFaceState {
            compare,
            fail_op: wgpu::StencilOperation::Keep,
            depth_fail_op: wgpu::StencilOperation::Keep,
            pass_op,
        };
        let stencil = |compare, pass_op| wgpu::DepthStencilState {
            format: STENCIL_FORMAT,
            depth_write_enabled: None,
            depth_compare: None,
            stencil: wgpu::StencilState {
                front: face(compare, pass_op),
                back: face(compare, pass_op),
                read_mask: 0xff,
                write_mask: 0xff,
            },
            bias: Default::default(),
        };
        let depth_stencil = match desc.stencil {
            Stencil::None => None,
            Stencil::Mark => Some(stencil(
                wgpu::CompareFunction::Always,
                wgpu::StencilOperation::Replace,
            )),
            Stencil::Test => Some(stencil(
                wgpu::CompareFunction::Equal,
                wgpu::StencilOperation::Keep,
            )),
            Stencil::WriteDepth => Some(wgpu::DepthStencilState {
                format: crate::gpu::DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Always),
                stencil: Default::default(),
                bias: Default::default(),
            }),
        };
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(desc.label),
            bind_group_layouts: &[Some(desc.layout)],
            immediate_size: 0,
        });
        self.0.pipeline_with_depth(
            device,
            &FragmentDesc {
                label: desc.label,
                module: desc.module,
                entry_point: desc.entry_point,
                targets: &[desc.format],
                constants: desc.constants,
                layout: Some(&pipeline_layout),
            },
            depth_stencil,
        )
    }
}

/// A single-sample 2D render target that passes can also read.
pub fn target(
    device: &wgpu::Device,
    label: &str,
    size: (u32, u32),
    format: wgpu::TextureFormat,
    view_formats: &[wgpu::TextureFormat],
) -> wgpu::Texture {
    crate::gpu::texture_2d(
        device,
        &crate::gpu::Texture2d {
            view_formats,
            ..crate::gpu::Texture2d::new(
                label,
                size,
                format,
                wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
            )
        },
    )
}

/// A colour attachment cleared to zero.
pub use crate::gpu::cleared_attachment as cleared;

/// One full-screen draw of a morphological pass into `target` (cleared first) with the edge
/// stencil `stencil` bound at reference 1: the edge pass clears the stencil
/// (`wgpu::LoadOp::Clear(0)`) and its pipeline marks the edge pixels, the weight pass loads it
/// (`wgpu::LoadOp::Load`) and its pipeline runs only on the marked pixels.
pub fn stencil_pass(
    ctx: &mut PassContext<'_>,
    pass: &str,
    target: &wgpu::TextureView,
    stencil: &wgpu::TextureView,
    stencil_load: wgpu::LoadOp<u32>,
    (pipeline, group): (&wgpu::RenderPipeline, &wgpu::BindGroup),
) {
    let stencil_attachment = wgpu::RenderPassDepthStencilAttachment {
        view: stencil,
        depth_ops: None,
        stencil_ops: Some(wgpu::Operations {
            load: stencil_load,
            store: wgpu::StoreOp::Store,
        }),
    };
    ctx.render_pass(
        pass,
        &[Some(cleared(target))],
        Some(stencil_attachment),
        |pass| {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, group, &[]);
            pass.set_stencil_reference(1);
            pass.draw(0..3, 0..1);
        },
    );
}

/// A uniform buffer holding one `T` (a `#[repr(C)]` block mirroring the shader's), which
/// the queue writes every frame.
pub fn uniform_buffer<T>(device: &wgpu::Device, label: &str) -> wgpu::Buffer {
    uniform_buffer_of_size(device, label, std::mem::size_of::<T>() as u64)
}

/// A uniform buffer of `size` bytes that the queue writes (`COPY_DST`), labelled.
pub fn uniform_buffer_of_size(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
