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
//!
//! On radiance (before the tonemapper of an HDR frame) the edge pass reads the perceptual copy
//! of the input (`aa::common::perceptual`: Karis-compressed and sRGB-encoded, so the thresholds
//! keep their meaning) and the blend pass reads the radiance and writes it to a half-float
//! target: the blend is an area-weighted mix of a pixel and its neighbour, as a camera
//! averages radiance over the pixel.

use glam::Vec2;

use super::settings::{EdgeMode, PipelineKey, SmaaSettings};
use crate::aa::DebugView;
use crate::aa::common::morphology::{
    EdgeDebugViews, EdgeTargets, MorphologicalDesc, MorphologicalPipelines, edge_and_weight_passes,
};
use crate::aa::common::pass::{self, Binding, PassDesc, Stencil, Vertex, bind_group};
use crate::aa::common::perceptual::PerceptualCopy;
use crate::aa::common::{bilinear_clamp_sampler, holds_radiance, output_format, view_as};
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu, MOTION_FORMAT};
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
    /// The settings' key and whether the blends write radiance.
    key: (PipelineKey, bool),
    passes: MorphologicalPipelines,
    blend_velocity: wgpu::RenderPipeline,
}

struct DebugViews {
    pipelines: [wgpu::RenderPipeline; 2],
    views: EdgeDebugViews,
}

/// The images one SMAA 1x run reads.
pub struct Input<'a> {
    /// Colour, single sample: display values ([`crate::gpu::COLOR_FORMAT`] with an encoded
    /// view) or radiance ([`crate::gpu::HDR_FORMAT`]).
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
    perceptual: PerceptualCopy,
    targets: Option<EdgeTargets>,
    debug: Option<DebugViews>,
}

impl SmaaPasses {
    /// Compiles the shaders and uploads the lookup tables (generated on first use).
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let no_motion = pass::target(device, "smaa no motion", (1, 1), MOTION_FORMAT, &[]);
        Self {
            vertex: Vertex::new(device),
            module: super::WGSL.module(device),
            modes_module: super::MODES_WGSL.module(device),
            sampler: bilinear_clamp_sampler(device, "smaa bilinear"),
            edge_layout: pass::layout(
                device,
                "smaa edges",
                &[
                    (0, Binding::Uniform),
                    (1, Binding::Texture),
                    (2, Binding::Depth),
                ],
            ),
            weight_layout: pass::layout(
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
            blend_layout: pass::layout(
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
            perceptual: PerceptualCopy::default(),
            targets: None,
            debug: None,
            device: device.clone(),
        }
    }

    /// Builds the pipelines of `key` whose blends write radiance when `radiance` (before the
    /// tonemapper), unless they are the current ones.
    fn ensure_pipelines(&mut self, key: PipelineKey, radiance: bool) {
        if self
            .pipelines
            .as_ref()
            .is_some_and(|p| p.key == (key, radiance))
        {
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
        let edge_entry = if key.edge_mode == EdgeMode::Depth {
            "fs_edges_depth"
        } else {
            "fs_edges"
        };
        let passes = self.vertex.morphological(
            &self.device,
            &MorphologicalDesc {
                prefix: "smaa",
                module: &self.module,
                edge_entry,
                layouts: [&self.edge_layout, &self.weight_layout, &self.blend_layout],
                constants: &constants,
                blend_format: output_format(radiance),
            },
        );
        let blend_velocity = self.vertex.pipeline(
            &self.device,
            &PassDesc {
                label: "smaa blend with velocity",
                module: &self.module,
                entry_point: "fs_blend_velocity",
                layout: &self.blend_layout,
                format: output_format(radiance),
                constants: &constants,
                stencil: Stencil::None,
            },
        );
        self.pipelines = Some(Pipelines {
            key: (key, radiance),
            passes,
            blend_velocity,
        });
    }

    fn ensure_targets(&mut self, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        self.targets = Some(EdgeTargets::new(&self.device, "smaa", size));
        self.debug = None;
    }

    fn uniform_slot(&mut self, slot: usize) -> &wgpu::Buffer {
        while self.uniforms.len() <= slot {
            self.uniforms
                .push(pass::uniform_buffer::<Params>(&self.device, "smaa params"));
        }
        &self.uniforms[slot]
    }

    /// Records SMAA 1x of `input` into `target` (a view of a texture of the same size, in the
    /// input's kind: display values or radiance). `slot` picks the uniform block (distinct for runs in one frame), `position`
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
        self.ensure_pipelines(settings.pipeline_key(), holds_radiance(input.color));
        self.ensure_targets(size);
        let params = Params::new(settings, size, super::lut::subsample_indices(position));
        ctx.gpu
            .queue
            .write_buffer(self.uniform_slot(slot), 0, bytemuck::bytes_of(&params));
        let edge_source = self.perceptual.source(ctx, input.color, prefix);
        let color_encoded = view_as(edge_source, COLOR_FORMAT_ENCODED_VIEW);
        let (Some(pipelines), Some(targets)) = (&self.pipelines, &self.targets) else {
            return;
        };
        let device = &self.device;
        let uniform = self.uniforms[slot].as_entire_binding();
        let color_linear = input.color.create_view(&Default::default());
        let depth = input.depth.create_view(&Default::default());
        let views = targets.views();
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
        let weight_group = bind_group(
            device,
            "smaa weights",
            &self.weight_layout,
            &[
                (0, uniform.clone()),
                (3, TextureView(&views.edges)),
                (4, TextureView(&area)),
                (5, TextureView(&search)),
                (6, Sampler(&self.sampler)),
            ],
        );
        edge_and_weight_passes(
            ctx,
            prefix,
            &views,
            &pipelines.passes,
            [&edge_group, &weight_group],
        );

        let blend_group = bind_group(
            device,
            "smaa blend",
            &self.blend_layout,
            &[
                (0, uniform),
                (6, Sampler(&self.sampler)),
                (7, TextureView(&color_linear)),
                (8, TextureView(&views.weights)),
                (9, TextureView(&motion)),
            ],
        );
        let blend = if input.motion.is_some() {
            &pipelines.blend_velocity
        } else {
            &pipelines.passes.blend
        };
        ctx.fullscreen_pass(&format!("{prefix}blend"), target, blend, &blend_group);
    }

    /// Records the debug views of the last run (edges and weights as RGBA8 images).
    pub fn encode_debug(&mut self, ctx: &mut PassContext<'_>) {
        let Some(targets) = &self.targets else { return };
        let debug = self.debug.get_or_insert_with(|| {
            let layout = pass::layout(&self.device, "smaa debug", &[(9, Binding::Texture)]);
            DebugViews {
                pipelines: self
                    .vertex
                    .debug_pipelines(&self.device, &self.modes_module, &layout),
                views: EdgeDebugViews::new(&self.device, "smaa", targets.size),
            }
        });
        debug.views.encode(ctx, targets, &debug.pipelines, 9);
    }

    /// The edges and blending-weights debug views, when `enabled` and rendered, with the
    /// technique's descriptions of them.
    pub fn debug_views(
        &self,
        enabled: bool,
        [edges, weights]: [&'static str; 2],
    ) -> Vec<DebugView<'_>> {
        let Some(debug) = self.debug.as_ref().filter(|_| enabled) else {
            return Vec::new();
        };
        vec![
            DebugView {
                name: "edges",
                description: edges,
                texture: &debug.views.edges,
            },
            DebugView {
                name: "weights",
                description: weights,
                texture: &debug.views.weights,
            },
        ]
    }

    /// Memory of the targets, tables and uniforms, labelled with the technique id.
    pub fn memory(&self, id: &str) -> Vec<MemoryItem> {
        let mut items = vec![
            MemoryItem::texture(format!("{id} area table"), &self.luts.area),
            MemoryItem::texture(format!("{id} search table"), &self.luts.search),
        ];
        if let Some(t) = &self.targets {
            items.extend(t.memory(id));
        }
        if let Some(d) = &self.debug {
            items.extend(d.views.memory(id));
        }
        items.extend(self.perceptual.memory(id));
        items.extend(
            self.uniforms
                .iter()
                .map(|u| MemoryItem::buffer(format!("{id} params"), u)),
        );
        items
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
        let tables = super::lut::tables();
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
                super::lut::AREA_SIZE,
                wgpu::TextureFormat::Rg8Unorm,
                2,
                &tables.area,
            ),
            search: upload(
                "smaa search table",
                super::lut::SEARCH_SIZE,
                wgpu::TextureFormat::R8Unorm,
                1,
                &tables.search,
            ),
        }
    }
}
