//! SMAA 1x on one single-sample image, the building block of every SMAA mode: the edge,
//! blending-weight and neighbourhood-blending passes of `smaa.wgsl`, their private
//! targets, the lookup-table textures and the debug views.
//!
//! The edge pass writes a `Stencil8` mask (reference 1 wherever a fragment survives, i.e. on
//! edge pixels); the weight pass tests it, so its search loops run only on edge pixels, and its
//! target is cleared to zero elsewhere. Pipelines depend only on [`PipelineKey`] (override
//! constants) and are rebuilt when it changes; thresholds, the sub-sample indices and the
//! corner rounding are uniforms, written per run into the run's own uniform slot so that
//! several runs can share one command encoder (SMAA S2x).

use glam::Vec2;

use super::pipeline::{
    self, Binding, LutTextures, PassDesc, Stencil, Vertex, bind_group, stencil_pass,
};
use super::settings::{EdgeMode, PipelineKey, SmaaSettings};
use crate::aa::common::{bilinear_clamp_sampler, view_as};
use crate::gpu::{COLOR_FORMAT, COLOR_FORMAT_ENCODED_VIEW, Gpu, MOTION_FORMAT};
use crate::graph::{MemoryItem, PassContext};

/// The uniform block of `smaa.wgsl` (`Params`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    size: [f32; 2],
    threshold: f32,
    depth_threshold: f32,
    local_contrast: f32,
    predication_threshold: f32,
    predication_scale: f32,
    predication_strength: f32,
    subsample: [u32; 4],
    corner_rounding: f32,
    pad: [f32; 3],
}

impl Params {
    fn new(settings: &SmaaSettings, size: (u32, u32), subsample: [u32; 4]) -> Self {
        Self {
            size: [size.0 as f32, size.1 as f32],
            threshold: settings.threshold,
            depth_threshold: settings.depth_threshold(),
            local_contrast: settings.local_contrast_factor,
            predication_threshold: settings.predication_threshold,
            predication_scale: settings.predication_scale,
            predication_strength: settings.predication_strength,
            subsample,
            corner_rounding: settings.corner_rounding as f32 / 100.0,
            pad: [0.0; 3],
        }
    }
}

struct Pipelines {
    key: PipelineKey,
    edges: wgpu::RenderPipeline,
    weights: wgpu::RenderPipeline,
    blend: wgpu::RenderPipeline,
    blend_velocity: wgpu::RenderPipeline,
}

struct Targets {
    size: (u32, u32),
    edges: wgpu::Texture,
    stencil: wgpu::Texture,
    weights: wgpu::Texture,
}

struct DebugViews {
    edges_pipeline: wgpu::RenderPipeline,
    weights_pipeline: wgpu::RenderPipeline,
    edges: wgpu::Texture,
    weights: wgpu::Texture,
}

/// The images one SMAA 1x run reads.
pub struct Input<'a> {
    /// Colour, single sample, [`COLOR_FORMAT`] with an encoded view.
    pub color: &'a wgpu::Texture,
    /// Depth of the same render (depth edges and predication).
    pub depth: &'a wgpu::Texture,
    /// Motion vectors: when given, the result's alpha holds the pixel's speed (SMAA T2x).
    pub motion: Option<&'a wgpu::Texture>,
}

/// SMAA 1x passes with their targets; see the module docs.
pub struct SmaaPasses {
    device: wgpu::Device,
    /// The shared fullscreen vertex stage.
    pub vertex: Vertex,
    module: wgpu::ShaderModule,
    /// `smaa_modes.wgsl`, shared with the T2x and S2x passes.
    pub modes_module: wgpu::ShaderModule,
    /// Bilinear, clamp-to-edge.
    pub sampler: wgpu::Sampler,
    edge_layout: wgpu::BindGroupLayout,
    weight_layout: wgpu::BindGroupLayout,
    blend_layout: wgpu::BindGroupLayout,
    luts: LutTextures,
    no_motion: wgpu::Texture,
    uniforms: Vec<wgpu::Buffer>,
    pipelines: Option<Pipelines>,
    targets: Option<Targets>,
    debug: Option<DebugViews>,
}

impl SmaaPasses {
    /// Compiles the shaders and uploads the lookup tables (generated on first use).
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let no_motion = pipeline::target(device, "smaa no motion", (1, 1), MOTION_FORMAT, &[]);
        Self {
            vertex: Vertex::new(device),
            module: super::WGSL.module(device),
            modes_module: super::MODES_WGSL.module(device),
            sampler: bilinear_clamp_sampler(device, "smaa bilinear"),
            edge_layout: pipeline::layout(
                device,
                "smaa edges",
                &[
                    (0, Binding::Uniform),
                    (1, Binding::Texture),
                    (2, Binding::Depth),
                ],
            ),
            weight_layout: pipeline::layout(
                device,
                "smaa weights",
                &[
                    (0, Binding::Uniform),
                    (3, Binding::Texture),
                    (4, Binding::Texture),
                    (5, Binding::Texture),
                    (6, Binding::Sampler),
                ],
            ),
            blend_layout: pipeline::layout(
                device,
                "smaa blend",
                &[
                    (0, Binding::Uniform),
                    (6, Binding::Sampler),
                    (7, Binding::Texture),
                    (8, Binding::Texture),
                    (9, Binding::Texture),
                ],
            ),
            luts: LutTextures::upload(device, &gpu.queue),
            no_motion,
            uniforms: Vec::new(),
            pipelines: None,
            targets: None,
            debug: None,
            device: device.clone(),
        }
    }

    fn ensure_pipelines(&mut self, key: PipelineKey) {
        if self.pipelines.as_ref().is_some_and(|p| p.key == key) {
            return;
        }
        let constants = [
            (
                "EDGE_MODE",
                f64::from(u8::from(key.edge_mode == EdgeMode::Color)),
            ),
            ("PREDICATION", f64::from(u8::from(key.predication))),
            ("MAX_SEARCH_STEPS", f64::from(key.max_search_steps)),
            ("MAX_SEARCH_STEPS_DIAG", f64::from(key.diagonal_steps)),
            (
                "CORNER_DETECTION",
                f64::from(u8::from(key.corner_detection)),
            ),
        ];
        let build = |label: &str, entry_point: &str, layout, format, stencil| {
            self.vertex.pipeline(
                &self.device,
                &PassDesc {
                    label,
                    module: &self.module,
                    entry_point,
                    layout,
                    format,
                    constants: &constants,
                    stencil,
                },
            )
        };
        let edge_entry = if key.edge_mode == EdgeMode::Depth {
            "fs_edges_depth"
        } else {
            "fs_edges"
        };
        self.pipelines = Some(Pipelines {
            key,
            edges: build(
                "smaa edges",
                edge_entry,
                &self.edge_layout,
                wgpu::TextureFormat::Rg8Unorm,
                Stencil::Mark,
            ),
            weights: build(
                "smaa weights",
                "fs_weights",
                &self.weight_layout,
                wgpu::TextureFormat::Rgba8Unorm,
                Stencil::Test,
            ),
            blend: build(
                "smaa blend",
                "fs_blend",
                &self.blend_layout,
                COLOR_FORMAT,
                Stencil::None,
            ),
            blend_velocity: build(
                "smaa blend with velocity",
                "fs_blend_velocity",
                &self.blend_layout,
                COLOR_FORMAT,
                Stencil::None,
            ),
        });
    }

    fn ensure_targets(&mut self, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let device = &self.device;
        self.targets = Some(Targets {
            size,
            edges: pipeline::target(
                device,
                "smaa edges",
                size,
                wgpu::TextureFormat::Rg8Unorm,
                &[],
            ),
            stencil: pipeline::target(
                device,
                "smaa edge stencil",
                size,
                pipeline::STENCIL_FORMAT,
                &[],
            ),
            weights: pipeline::target(
                device,
                "smaa weights",
                size,
                wgpu::TextureFormat::Rgba8Unorm,
                &[],
            ),
        });
        self.debug = None;
    }

    fn uniform_slot(&mut self, slot: usize) -> &wgpu::Buffer {
        while self.uniforms.len() <= slot {
            self.uniforms
                .push(self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("smaa params"),
                    size: std::mem::size_of::<Params>() as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                }));
        }
        &self.uniforms[slot]
    }

    /// Records SMAA 1x of `input` into `target` (a view of a [`COLOR_FORMAT`] texture of the
    /// same size). `slot` picks the uniform block (distinct for runs in one frame), `position`
    /// is the sample position relative to the pixel centre (chooses the area sub-tables) and
    /// `prefix` starts the pass names in the timings.
    #[allow(clippy::too_many_arguments)]
    pub fn run(
        &mut self,
        ctx: &mut PassContext<'_>,
        settings: &SmaaSettings,
        input: &Input<'_>,
        target: &wgpu::TextureView,
        slot: usize,
        position: Vec2,
        prefix: &str,
    ) {
        let size = (input.color.width(), input.color.height());
        self.ensure_pipelines(settings.pipeline_key());
        self.ensure_targets(size);
        let params = Params::new(settings, size, super::lut::subsample_indices(position));
        ctx.gpu
            .queue
            .write_buffer(self.uniform_slot(slot), 0, bytemuck::bytes_of(&params));
        let (Some(pipelines), Some(targets)) = (&self.pipelines, &self.targets) else {
            return;
        };
        let device = &self.device;
        let uniform = self.uniforms[slot].as_entire_binding();
        let color_encoded = view_as(input.color, COLOR_FORMAT_ENCODED_VIEW);
        let color_linear = input.color.create_view(&Default::default());
        let depth = input.depth.create_view(&Default::default());
        let edges = targets.edges.create_view(&Default::default());
        let stencil = targets.stencil.create_view(&Default::default());
        let weights = targets.weights.create_view(&Default::default());
        let area = self.luts.area.create_view(&Default::default());
        let search = self.luts.search.create_view(&Default::default());
        let motion = input
            .motion
            .unwrap_or(&self.no_motion)
            .create_view(&Default::default());
        use wgpu::BindingResource::{Sampler, TextureView};

        let edge_group = bind_group(
            device,
            "smaa edges",
            &self.edge_layout,
            &[
                (0, uniform.clone()),
                (1, TextureView(&color_encoded)),
                (2, TextureView(&depth)),
            ],
        );
        stencil_pass(
            ctx,
            &format!("{prefix}edges"),
            &edges,
            &stencil,
            wgpu::LoadOp::Clear(0),
            (&pipelines.edges, &edge_group),
        );

        let weight_group = bind_group(
            device,
            "smaa weights",
            &self.weight_layout,
            &[
                (0, uniform.clone()),
                (3, TextureView(&edges)),
                (4, TextureView(&area)),
                (5, TextureView(&search)),
                (6, Sampler(&self.sampler)),
            ],
        );
        stencil_pass(
            ctx,
            &format!("{prefix}weights"),
            &weights,
            &stencil,
            wgpu::LoadOp::Load,
            (&pipelines.weights, &weight_group),
        );

        let blend_group = bind_group(
            device,
            "smaa blend",
            &self.blend_layout,
            &[
                (0, uniform),
                (6, Sampler(&self.sampler)),
                (7, TextureView(&color_linear)),
                (8, TextureView(&weights)),
                (9, TextureView(&motion)),
            ],
        );
        let blend = if input.motion.is_some() {
            &pipelines.blend_velocity
        } else {
            &pipelines.blend
        };
        ctx.fullscreen_pass(&format!("{prefix}blend"), target, blend, &blend_group);
    }

    /// Records the debug views of the last run (edges and weights as RGBA8 images).
    pub fn encode_debug(&mut self, ctx: &mut PassContext<'_>) {
        let Some(targets) = &self.targets else { return };
        if self.debug.is_none() {
            let layout = pipeline::layout(&self.device, "smaa debug", &[(9, Binding::Texture)]);
            let build = |entry_point: &str| {
                self.vertex.pipeline(
                    &self.device,
                    &PassDesc {
                        label: entry_point,
                        module: &self.modes_module,
                        entry_point,
                        layout: &layout,
                        format: COLOR_FORMAT_ENCODED_VIEW,
                        constants: &[],
                        stencil: Stencil::None,
                    },
                )
            };
            self.debug = Some(DebugViews {
                edges_pipeline: build("fs_debug_edges"),
                weights_pipeline: build("fs_debug_weights"),
                edges: crate::aa::common::debug_texture(
                    &self.device,
                    "smaa edges view",
                    targets.size,
                ),
                weights: crate::aa::common::debug_texture(
                    &self.device,
                    "smaa weights view",
                    targets.size,
                ),
            });
        }
        let Some(debug) = &self.debug else { return };
        let views = [
            (
                "debug edges",
                &debug.edges_pipeline,
                &targets.edges,
                &debug.edges,
            ),
            (
                "debug weights",
                &debug.weights_pipeline,
                &targets.weights,
                &debug.weights,
            ),
        ];
        for (name, pipeline, source, view) in views {
            let source = source.create_view(&Default::default());
            let group = bind_group(
                &self.device,
                name,
                &pipeline.get_bind_group_layout(0),
                &[(9, wgpu::BindingResource::TextureView(&source))],
            );
            let target = view_as(view, COLOR_FORMAT_ENCODED_VIEW);
            ctx.fullscreen_pass(name, &target, pipeline, &group);
        }
    }

    /// The debug views, when they have been rendered: (edges, weights).
    pub fn debug_textures(&self) -> Option<(&wgpu::Texture, &wgpu::Texture)> {
        self.debug.as_ref().map(|d| (&d.edges, &d.weights))
    }

    /// Memory of the targets, tables and uniforms, labelled with the technique id.
    pub fn memory(&self, id: &str) -> Vec<MemoryItem> {
        let mut items = vec![
            MemoryItem::texture(format!("{id} area table"), &self.luts.area),
            MemoryItem::texture(format!("{id} search table"), &self.luts.search),
        ];
        if let Some(t) = &self.targets {
            items.push(MemoryItem::texture(format!("{id} edges"), &t.edges));
            items.push(MemoryItem::texture(
                format!("{id} edge stencil"),
                &t.stencil,
            ));
            items.push(MemoryItem::texture(format!("{id} weights"), &t.weights));
        }
        if let Some(d) = &self.debug {
            items.push(MemoryItem::texture(format!("{id} edges view"), &d.edges));
            items.push(MemoryItem::texture(
                format!("{id} weights view"),
                &d.weights,
            ));
        }
        items.extend(
            self.uniforms
                .iter()
                .map(|u| MemoryItem::buffer(format!("{id} params"), u)),
        );
        items
    }
}
