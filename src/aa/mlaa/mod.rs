//! MLAA, morphological antialiasing: Alexander Reshetov, "Morphological Antialiasing" (High
//! Performance Graphics 2009), in the GPU form of Jorge Jimenez, Belen Masia, Jose I.
//! Echevarria, Fernando Navarro and Diego Gutierrez, "Practical Morphological
//! Antialiasing" (GPU Pro 2, 2011). This is aa-lab's own implementation of their ideas and
//! parameters; SMAA (`aa::smaa`) is the same authors' later refinement of it.
//!
//! Three fullscreen passes over the shared one-sample render (`mlaa.wgsl` in this folder):
//! edge detection on sRGB-encoded luma or colour with a threshold; blending weights, where
//! each edge pixel searches the two ends of its edge run with bilinear fetches that read two
//! pixels at once (up to `max_search_steps` fetches each way), reads the crossing edges at the
//! ends and looks up the area the revectorised outline (L, Z and U patterns) covers in an area
//! table generated from that geometry ([`area`]); and neighbourhood blending, in linear light,
//! where each pixel mixes with its four neighbours by those areas. Only edge pixels run the
//! weight pass: the edge pass marks them in a stencil buffer that the weight pass tests.
//!
//! What separates it from SMAA: no diagonal patterns (45-degree staircases are read as chains
//! of one-pixel Z shapes), no sharp-corner detection, no local contrast adaptation, a search
//! that cannot tell which of the two last pixels ends the run, and a blend towards all four
//! neighbours at once. Settings and presets: [`settings`]. Debug views: the edges and the
//! blending weights.
//!
//! Before the tonemapper of an HDR frame (`tonemap_order`), the edges are found on the
//! perceptual copy of the radiance (`aa::common::perceptual`: Karis-compressed, sRGB-encoded,
//! so the thresholds keep their meaning) and the blend mixes radiance into a half-float output
//! (an area-weighted mix of neighbours, as the camera reference averages radiance).
//!
//! Figures: `docs/techniques/mlaa.md`.

pub mod area;
pub mod settings;

use wgpu::util::DeviceExt;

pub use settings::{EdgeMode, MlaaSettings, PipelineKey, Preset};

use crate::aa::common::morphology::{
    EdgeDebugViews, EdgeTargets, MorphologicalDesc, MorphologicalPipelines, edge_and_weight_passes,
};
use crate::aa::common::pass::{self, Binding, Vertex, bind_group};
use crate::aa::common::perceptual::{PERCEPTUAL_WGSL, PerceptualCopy};
use crate::aa::common::{bilinear_clamp_sampler, holds_radiance, output_format, view_as};
use crate::aa::info::{TechniqueInfo, needs_encoded_views};
use crate::aa::params::Named;
use crate::aa::{DebugView, Technique};
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Stable id, as on the command line.
pub const ID: &str = "mlaa";

/// The edge, blending-weight and blending passes and the debug views.
const WGSL: Shader = crate::wgsl!("src/aa/mlaa/mlaa.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "MLAA",
    summary: "Morphological antialiasing (Reshetov 2009; the GPU form of Jimenez et al. 2011, the \
         ancestor of SMAA): edges of the finished image are found by luma, each edge is followed to \
         its ends two pixels per fetch, the staircase is read as L, Z or U shapes and every edge pixel \
         is blended with its neighbours by the area the rebuilt outline covers, from a precomputed \
         table. About the cost of SMAA 1x, but without SMAA's diagonal and corner patterns: \
         45-degree edges come out wavy, sharp corners are rounded, and like every post-process it \
         cannot recover sub-pixel geometry.",
    availability: needs_encoded_views,
    create: |gpu| Box::new(Mlaa::new(gpu)),
    shaders: &[WGSL, PERCEPTUAL_WGSL],
};

/// The uniform block of `mlaa.wgsl` (`Params`).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    size: [f32; 2],
    threshold: f32,
    pad: f32,
}

struct Pipelines {
    /// The settings' key and whether the blend writes radiance.
    key: (PipelineKey, bool),
    passes: MorphologicalPipelines,
}

/// The MLAA technique.
pub struct Mlaa {
    device: wgpu::Device,
    settings: MlaaSettings,
    vertex: Vertex,
    module: wgpu::ShaderModule,
    sampler: wgpu::Sampler,
    edge_layout: wgpu::BindGroupLayout,
    weight_layout: wgpu::BindGroupLayout,
    blend_layout: wgpu::BindGroupLayout,
    debug_pipelines: [wgpu::RenderPipeline; 2],
    area: wgpu::Texture,
    uniform: wgpu::Buffer,
    pipelines: Option<Pipelines>,
    perceptual: PerceptualCopy,
    targets: Option<EdgeTargets>,
    debug: Option<EdgeDebugViews>,
    debug_enabled: bool,
}

impl Mlaa {
    /// MLAA with the default (Medium) settings; uploads the area table (generated on first
    /// use).
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let vertex = Vertex::new(device);
        let module = WGSL.module(device);
        let debug_layout = pass::layout(device, "mlaa debug", &[(7, Binding::Texture)]);
        let debug_pipelines = vertex.debug_pipelines(device, &module, &debug_layout);
        let area = device.create_texture_with_data(
            &gpu.queue,
            &crate::gpu::Texture2d::new(
                "mlaa area table",
                area::AREA_SIZE,
                wgpu::TextureFormat::Rg8Unorm,
                wgpu::TextureUsages::TEXTURE_BINDING,
            )
            .descriptor(),
            wgpu::util::TextureDataOrder::LayerMajor,
            area::table(),
        );
        Self {
            settings: MlaaSettings::default(),
            sampler: bilinear_clamp_sampler(device, "mlaa bilinear"),
            edge_layout: pass::layout(
                device,
                "mlaa edges",
                &[(0, Binding::Uniform), (1, Binding::Texture)],
            ),
            weight_layout: pass::layout(
                device,
                "mlaa weights",
                &[
                    (0, Binding::Uniform),
                    (2, Binding::Texture),
                    (3, Binding::Texture),
                    (4, Binding::Sampler),
                ],
            ),
            blend_layout: pass::layout(
                device,
                "mlaa blend",
                &[
                    (0, Binding::Uniform),
                    (4, Binding::Sampler),
                    (5, Binding::Texture),
                    (6, Binding::Texture),
                ],
            ),
            uniform: pass::uniform_buffer::<Params>(device, "mlaa params"),
            debug_pipelines,
            area,
            vertex,
            module,
            pipelines: None,
            perceptual: PerceptualCopy::default(),
            targets: None,
            debug: None,
            debug_enabled: false,
            device: device.clone(),
        }
    }

    /// The current settings.
    pub fn settings(&self) -> &MlaaSettings {
        &self.settings
    }

    /// Builds the pipelines of `key` whose blend writes radiance when `radiance` (before the
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
            ("MAX_SEARCH_STEPS", f64::from(key.max_search_steps)),
        ];
        let passes = self.vertex.morphological(
            &self.device,
            &MorphologicalDesc {
                prefix: "mlaa",
                module: &self.module,
                edge_entry: "fs_edges",
                layouts: [&self.edge_layout, &self.weight_layout, &self.blend_layout],
                constants: &constants,
                blend_format: output_format(radiance),
            },
        );
        self.pipelines = Some(Pipelines {
            key: (key, radiance),
            passes,
        });
    }

    fn ensure_targets(&mut self, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        self.targets = Some(EdgeTargets::new(&self.device, "mlaa", size));
        self.debug = None;
    }

    /// Records the two debug views of the last run.
    fn encode_debug(&mut self, ctx: &mut PassContext<'_>) {
        let Some(targets) = &self.targets else { return };
        self.debug
            .get_or_insert_with(|| EdgeDebugViews::new(&self.device, "mlaa", targets.size))
            .encode(ctx, targets, &self.debug_pipelines, 7);
    }
}

impl Technique for Mlaa {
    crate::aa::common::shared_1x_post_process!(INFO);

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        let size = (input.color.width(), input.color.height());
        let radiance = holds_radiance(&input.color);
        self.ensure_pipelines(self.settings.pipeline_key(), radiance);
        self.ensure_targets(size);
        let params = Params {
            size: [size.0 as f32, size.1 as f32],
            threshold: self.settings.threshold,
            pad: 0.0,
        };
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&params));
        let edge_source = self.perceptual.source(ctx, &input.color, "");
        let color_encoded = view_as(edge_source, COLOR_FORMAT_ENCODED_VIEW);
        let (Some(pipelines), Some(targets)) = (&self.pipelines, &self.targets) else {
            return;
        };
        let device = &self.device;
        let uniform = self.uniform.as_entire_binding();
        let color_linear = input.color.create_view(&Default::default());
        let views = targets.views();
        let area = self.area.create_view(&Default::default());
        use wgpu::BindingResource::{Sampler, TextureView};

        let edge_group = bind_group(
            device,
            "mlaa edges",
            &self.edge_layout,
            &[(0, uniform.clone()), (1, TextureView(&color_encoded))],
        );
        let weight_group = bind_group(
            device,
            "mlaa weights",
            &self.weight_layout,
            &[
                (0, uniform.clone()),
                (2, TextureView(&views.edges)),
                (3, TextureView(&area)),
                (4, Sampler(&self.sampler)),
            ],
        );
        edge_and_weight_passes(
            ctx,
            "",
            &views,
            &pipelines.passes,
            [&edge_group, &weight_group],
        );

        let blend_group = bind_group(
            device,
            "mlaa blend",
            &self.blend_layout,
            &[
                (0, uniform),
                (4, Sampler(&self.sampler)),
                (5, TextureView(&color_linear)),
                (6, TextureView(&views.weights)),
            ],
        );
        let target = output.create_view(&Default::default());
        ctx.fullscreen_pass("blend", &target, &pipelines.passes.blend, &blend_group);
        if self.debug_enabled {
            self.encode_debug(ctx);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![
            MemoryItem::texture("mlaa area table", &self.area),
            MemoryItem::buffer("mlaa params", &self.uniform),
        ];
        if let Some(t) = &self.targets {
            items.extend(t.memory(ID));
        }
        if let Some(d) = &self.debug {
            items.extend(d.memory(ID));
        }
        items.extend(self.perceptual.memory(ID));
        items
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    crate::aa::common::tunable_settings!(settings);

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        let Some(debug) = self.debug.as_ref().filter(|_| self.debug_enabled) else {
            return Vec::new();
        };
        vec![
            DebugView {
                name: "edges",
                description: "Edges MLAA found: red on a pixel's left side, green on its top side, \
                              yellow both.",
                texture: &debug.edges,
            },
            DebugView {
                name: "weights",
                description: "Blending weights: red blends across the pixel's top edge, green across \
                              its left edge, brighter is more (doubled).",
                texture: &debug.weights,
            },
        ]
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        let preset = s.matching_preset().map_or_else(
            || "custom settings".to_owned(),
            |p| format!("{} preset", p.name()),
        );
        Some(format!(
            "{preset}, {} edges, searches of {} pixels each way, orthogonal patterns only, stencil \
             early-out for the weight pass, blend in linear light",
            s.edge_mode.name(),
            2 * s.max_search_steps
        ))
    }
}
