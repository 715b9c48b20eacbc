//! Small wgpu helpers shared by the SMAA passes: explicit bind-group layouts (the passes
//! share one WGSL module per file, so layouts are spelled out rather than derived),
//! full-screen pipelines with SMAA's stencil use (built by the shared
//! `crate::gpu::fullscreen` helper), bind groups, private render targets and the lookup-table
//! textures; and what the three morphological passes of SMAA and MLAA share: their pipelines,
//! working targets, edge and weight passes and debug views.

use crate::aa::common::{debug_texture, view_as};
use crate::gpu::fullscreen::{FragmentDesc, Fullscreen};
use crate::graph::{MemoryItem, PassContext};

use super::lut;

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
}

/// A bind-group layout for fragment-stage bindings.
pub fn layout(
    device: &wgpu::Device,
    label: &str,
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
            visibility: wgpu::ShaderStages::FRAGMENT,
            ty: match kind {
                Binding::Uniform => wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                Binding::Texture => {
                    texture(wgpu::TextureSampleType::Float { filterable: true }, false)
                }
                Binding::Depth => texture(wgpu::TextureSampleType::Depth, false),
                Binding::MultisampledTexture => {
                    texture(wgpu::TextureSampleType::Float { filterable: false }, true)
                }
                Binding::MultisampledDepth => texture(wgpu::TextureSampleType::Depth, true),
                Binding::Sampler => wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
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
pub fn cleared(view: &wgpu::TextureView) -> wgpu::RenderPassColorAttachment<'_> {
    wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
            store: wgpu::StoreOp::Store,
        },
    }
}

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

/// What the three morphological passes (MLAA's and SMAA's) are built from: one WGSL module
/// with the entry points `edge_entry`, `fs_weights` and `fs_blend`, a layout per pass and the
/// override constants they share.
pub struct MorphologicalDesc<'a> {
    /// Starts the pipelines' labels (the technique's id).
    pub prefix: &'a str,
    /// The module with the three entry points.
    pub module: &'a wgpu::ShaderModule,
    /// The edge pass's entry point.
    pub edge_entry: &'a str,
    /// The edge, weight and blend passes' layouts.
    pub layouts: [&'a wgpu::BindGroupLayout; 3],
    /// WGSL override constants.
    pub constants: &'a [(&'a str, f64)],
}

/// The pipelines of the three morphological passes.
pub struct MorphologicalPipelines {
    /// Finds the edges and marks them in the stencil.
    pub edges: wgpu::RenderPipeline,
    /// Computes the blending weights on the marked pixels.
    pub weights: wgpu::RenderPipeline,
    /// Blends each pixel with its neighbours by the weights.
    pub blend: wgpu::RenderPipeline,
}

impl Vertex {
    /// Builds the three morphological passes' pipelines.
    pub fn morphological(
        &self,
        device: &wgpu::Device,
        desc: &MorphologicalDesc<'_>,
    ) -> MorphologicalPipelines {
        let [edge_layout, weight_layout, blend_layout] = desc.layouts;
        let build = |pass: &str, entry_point: &str, layout, format, stencil| {
            self.pipeline(
                device,
                &PassDesc {
                    label: &format!("{} {pass}", desc.prefix),
                    module: desc.module,
                    entry_point,
                    layout,
                    format,
                    constants: desc.constants,
                    stencil,
                },
            )
        };
        MorphologicalPipelines {
            edges: build(
                "edges",
                desc.edge_entry,
                edge_layout,
                wgpu::TextureFormat::Rg8Unorm,
                Stencil::Mark,
            ),
            weights: build(
                "weights",
                "fs_weights",
                weight_layout,
                wgpu::TextureFormat::Rgba8Unorm,
                Stencil::Test,
            ),
            blend: build(
                "blend",
                "fs_blend",
                blend_layout,
                crate::gpu::COLOR_FORMAT,
                Stencil::None,
            ),
        }
    }

    /// The two debug-view pipelines of a morphological technique, `fs_debug_edges` and
    /// `fs_debug_weights` of `module`, each reading one texture through `layout` and writing
    /// encoded colour.
    pub fn debug_pipelines(
        &self,
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        layout: &wgpu::BindGroupLayout,
    ) -> [wgpu::RenderPipeline; 2] {
        ["fs_debug_edges", "fs_debug_weights"].map(|entry_point| {
            self.pipeline(
                device,
                &PassDesc {
                    label: entry_point,
                    module,
                    entry_point,
                    layout,
                    format: crate::gpu::COLOR_FORMAT_ENCODED_VIEW,
                    constants: &[],
                    stencil: Stencil::None,
                },
            )
        })
    }
}

/// The working textures of the morphological passes, all of the output's size: the edges,
/// the stencil the edge pass marks them in, and the blending weights.
pub struct EdgeTargets {
    /// Their size.
    pub size: (u32, u32),
    /// Edges (red: left side, green: top side).
    pub edges: wgpu::Texture,
    /// The edge mask.
    pub stencil: wgpu::Texture,
    /// Blending weights.
    pub weights: wgpu::Texture,
}

/// Views of [`EdgeTargets`] for one run.
pub struct EdgeViews {
    /// The edges.
    pub edges: wgpu::TextureView,
    /// The edge mask.
    pub stencil: wgpu::TextureView,
    /// The blending weights.
    pub weights: wgpu::TextureView,
}

impl EdgeTargets {
    /// The targets at `size`, labelled after `prefix` (the technique's id).
    pub fn new(device: &wgpu::Device, prefix: &str, size: (u32, u32)) -> Self {
        let target =
            |name: &str, format| target(device, &format!("{prefix} {name}"), size, format, &[]);
        Self {
            size,
            edges: target("edges", wgpu::TextureFormat::Rg8Unorm),
            stencil: target("edge stencil", STENCIL_FORMAT),
            weights: target("weights", wgpu::TextureFormat::Rgba8Unorm),
        }
    }

    /// Views for one run.
    pub fn views(&self) -> EdgeViews {
        let view = |texture: &wgpu::Texture| texture.create_view(&Default::default());
        EdgeViews {
            edges: view(&self.edges),
            stencil: view(&self.stencil),
            weights: view(&self.weights),
        }
    }

    /// Their memory, labelled after `prefix`.
    pub fn memory(&self, prefix: &str) -> [MemoryItem; 3] {
        [
            MemoryItem::texture(format!("{prefix} edges"), &self.edges),
            MemoryItem::texture(format!("{prefix} edge stencil"), &self.stencil),
            MemoryItem::texture(format!("{prefix} weights"), &self.weights),
        ]
    }
}

/// Records the edge pass (it clears the stencil and marks the edge pixels) and the weight pass
/// (only on the marked pixels), named `{prefix}edges` and `{prefix}weights` in the timings.
pub fn edge_and_weight_passes(
    ctx: &mut PassContext<'_>,
    prefix: &str,
    views: &EdgeViews,
    pipelines: &MorphologicalPipelines,
    [edge_group, weight_group]: [&wgpu::BindGroup; 2],
) {
    stencil_pass(
        ctx,
        &format!("{prefix}edges"),
        &views.edges,
        &views.stencil,
        wgpu::LoadOp::Clear(0),
        (&pipelines.edges, edge_group),
    );
    stencil_pass(
        ctx,
        &format!("{prefix}weights"),
        &views.weights,
        &views.stencil,
        wgpu::LoadOp::Load,
        (&pipelines.weights, weight_group),
    );
}

/// The debug views of a morphological technique: its edges and blending weights as images.
pub struct EdgeDebugViews {
    /// The edges.
    pub edges: wgpu::Texture,
    /// The blending weights.
    pub weights: wgpu::Texture,
}

impl EdgeDebugViews {
    /// The views at `size`, labelled after `prefix`.
    pub fn new(device: &wgpu::Device, prefix: &str, size: (u32, u32)) -> Self {
        Self {
            edges: debug_texture(device, &format!("{prefix} edges view"), size),
            weights: debug_texture(device, &format!("{prefix} weights view"), size),
        }
    }

    /// Records both views of `targets`' last run with the [`Vertex::debug_pipelines`], which
    /// read their source at `binding`.
    pub fn encode(
        &self,
        ctx: &mut PassContext<'_>,
        targets: &EdgeTargets,
        pipelines: &[wgpu::RenderPipeline; 2],
        binding: u32,
    ) {
        let views = [
            ("debug edges", &targets.edges, &self.edges),
            ("debug weights", &targets.weights, &self.weights),
        ];
        for ((name, source, view), pipeline) in views.into_iter().zip(pipelines) {
            let source = source.create_view(&Default::default());
            let group = bind_group(
                &ctx.gpu.device,
                name,
                &pipeline.get_bind_group_layout(0),
                &[(binding, wgpu::BindingResource::TextureView(&source))],
            );
            let target = view_as(view, crate::gpu::COLOR_FORMAT_ENCODED_VIEW);
            ctx.fullscreen_pass(name, &target, pipeline, &group);
        }
    }

    /// Their memory, labelled after `prefix`.
    pub fn memory(&self, prefix: &str) -> [MemoryItem; 2] {
        [
            MemoryItem::texture(format!("{prefix} edges view"), &self.edges),
            MemoryItem::texture(format!("{prefix} weights view"), &self.weights),
        ]
    }
}

/// The lookup tables on the GPU.
pub struct LutTextures {
    /// Area table, Rg8Unorm, sampled bilinearly.
    pub area: wgpu::Texture,
    /// Search table, R8Unorm, loaded texel by texel.
    pub search: wgpu::Texture,
}

impl LutTextures {
    /// Uploads the (cached) generated tables.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue) -> Self {
        let tables = lut::tables();
        let upload = |label: &str,
                      size: (u32, u32),
                      format: wgpu::TextureFormat,
                      texel: u32,
                      data: &[u8]| {
            let texture = crate::gpu::texture_2d(
                device,
                &crate::gpu::Texture2d::new(
                    label,
                    size,
                    format,
                    wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
                ),
            );
            queue.write_texture(
                texture.as_image_copy(),
                data,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(size.0 * texel),
                    rows_per_image: Some(size.1),
                },
                texture.size(),
            );
            texture
        };
        Self {
            area: upload(
                "smaa area table",
                lut::AREA_SIZE,
                wgpu::TextureFormat::Rg8Unorm,
                2,
                &tables.area,
            ),
            search: upload(
                "smaa search table",
                lut::SEARCH_SIZE,
                wgpu::TextureFormat::R8Unorm,
                1,
                &tables.search,
            ),
        }
    }
}
