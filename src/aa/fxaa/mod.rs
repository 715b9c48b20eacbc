//! FXAA 3.11, the quality path of Timothy Lottes' Fast Approximate Antialiasing (NVIDIA, 2011):
//! one fullscreen pass over the shared one-sample render that finds luma edges, walks along
//! each edge to its ends and blends across it by how far the pixel is from the nearer end.
//!
//! The pass (`fxaa.wgsl` in this folder) makes every luma test on the sRGB-encoded values (read
//! through an `Rgba8Unorm` view; BT.601 weights, or the green channel), as the thresholds are tuned
//! for perceptual LDR values, but blends in linear light, as Lottes intended for sRGB targets: the
//! final bilinear read goes through the sRGB view, whose texels the sampler decodes before
//! filtering, and is encoded again on output (blending encoded values leaves half-covered pixels
//! far too dark). The sub-pixel amount, Lottes' softening of pixels that stand out of their 3x3
//! neighbourhood, moves the read that fraction of the way to the neighbour across, in linear
//! light, but never further than `subpix_limit` (0.33 of a pixel by default): the pixels that
//! stand out most are the one-pixel strands of sub-pixel geometry, which a longer move nearly
//! erases. The amount depends on where the pixel lies across the edge: brighter or darker than
//! both neighbours across it, it is a strand or dot the edge search cannot place, and its
//! amount is raised (`subpix_strands`); between them and matched by its neighbours along the
//! edge, it lies beside a clean edge that the search places, where the term would only blur it,
//! and its amount is lowered (`subpix_clean_edges`). Lottes' term treats both alike.
//! Settings:
//! - `quality`: Lottes' presets 10-15 (few steps, a long last step: medium dither), 20-29 (more,
//!   shorter steps: less dither) and 39 (twelve short steps, no dither); the search step list
//!   of the preset goes into the shader as override constants, so a pipeline is built per
//!   preset and luma choice and cached;
//! - `subpix`, `edge_threshold`, `edge_threshold_min` as in FXAA 3.11, and `subpix_limit`,
//!   `subpix_strands`, `subpix_clean_edges` (uniforms: changing them costs nothing);
//! - `luma`: BT.601 luma or green-as-luma.
//!
//! Presets: `default` (aa-lab's: quality 39, subpix 1 up to 0.33 of a pixel, 1.3 times that on
//! strands and half beside clean edges, Lottes' thresholds 0.166 / 0.0833), `lottes` (quality
//! 12, subpix 0.75 without a limit or the two factors: FXAA 3.11 as published) and Bevy's
//! sensitivity levels `low` .. `extreme`, which set the two thresholds. The defaults remove as
//! much of No AA's edge error as Bevy's FXAA does, with a lower FLIP.
//! Debug view `edges`: the luma, with the pixels FXAA treats as edges coloured by orientation.
//!
//! Before the tonemapper of an HDR frame (`tonemap_order`), the luma tests read the perceptual
//! copy of the radiance (`aa::common::perceptual`: Karis-compressed, sRGB-encoded, as SMAA,
//! CMAA 2 and MLAA's edge detection does), so the thresholds keep their meaning, and the final
//! read blends radiance into a half-float output. There the sub-pixel move is the fraction of
//! the compressed light that moves the encoded luma that far up from the darker side of the
//! edge (the same fraction of radiance would light the pixels beside a bright tube past white).
//!
//! Folder: `mod.rs` (the technique, its registry entry, passes and debug view), `settings.rs`
//! (quality presets, thresholds, named presets) and `fxaa.wgsl`. Measurements behind the linear
//! blend, the sub-pixel amount and the defaults, and what was tried: `docs/techniques/fxaa.md`.

pub mod settings;

pub use settings::{FxaaSettings, MAX_STEPS, Preset, Quality};

use crate::aa::common::color::LumaSource;
use crate::aa::common::pass;
use crate::aa::common::perceptual::{PERCEPTUAL_WGSL, PerceptualCopy};
use crate::aa::common::{
    PipelineCache, bilinear_clamp_sampler, debug_texture, encoded_or_radiance_view, encoded_view,
    holds_radiance,
};
use crate::aa::info::{TechniqueInfo, needs_encoded_views};
use crate::aa::params::Named;
use crate::aa::{DebugView, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu, HDR_FORMAT};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Stable id, as on the command line.
pub const ID: &str = "fxaa";

/// The antialiasing pass and the edge-mask debug view.
const WGSL: Shader = crate::wgsl!("src/aa/fxaa/fxaa.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "FXAA",
    summary: "Fast Approximate Antialiasing (Lottes, NVIDIA; the FXAA 3.11 quality path): one \
         post pass over the finished image finds luma edges, follows each to its ends and \
         blends across it. About the cost of a blur and independent of scene complexity, \
         but it only sees the final pixels: it cannot recover sub-pixel geometry, it softens \
         textures and text with contrast, and a still image's stair steps become a slight \
         crawl in motion.",
    availability: needs_encoded_views,
    create: |gpu| Box::new(Fxaa::new(gpu)),
    shaders: &[WGSL, PERCEPTUAL_WGSL],
};

/// Which fragment entry point a pipeline runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Pass {
    Antialias,
    Mask,
}

/// Everything a pipeline is specialised on (the last: whether it runs on radiance).
type PipelineKey = (Quality, LumaSource, Pass, bool);

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FxaaUniform {
    rcp_frame_subpix: [f32; 4],
    thresholds: [f32; 4],
    subpix_factors: [f32; 4],
}

/// The FXAA technique.
pub struct Fxaa {
    settings: FxaaSettings,
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    sampler: wgpu::Sampler,
    uniform: wgpu::Buffer,
    pipelines: PipelineCache<PipelineKey>,
    debug_enabled: bool,
    mask: Option<wgpu::Texture>,
    /// What the luma tests read before the tonemapper of an HDR frame.
    perceptual: PerceptualCopy,
}

impl Fxaa {
    /// FXAA with Lottes' default settings.
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, FxaaSettings::default())
    }

    /// FXAA with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: FxaaSettings) -> Self {
        let device = &gpu.device;
        Self {
            settings,
            module: WGSL.module(device),
            sampler: bilinear_clamp_sampler(device, "fxaa bilinear"),
            uniform: pass::uniform_buffer::<FxaaUniform>(device, "fxaa params"),
            device: device.clone(),
            pipelines: PipelineCache::default(),
            debug_enabled: false,
            mask: None,
            perceptual: PerceptualCopy::default(),
        }
    }

    /// Current settings.
    pub fn settings(&self) -> FxaaSettings {
        self.settings
    }

    /// The pipeline for a pass with the current preset, built on first use.
    /// On `radiance` (before the tonemapper) the antialiasing pass writes half floats.
    fn pipeline(
        &mut self,
        ctx: &PassContext<'_>,
        pass: Pass,
        radiance: bool,
    ) -> wgpu::RenderPipeline {
        let settings = self.settings;
        let (device, module) = (&self.device, &self.module);
        self.pipelines
            .get_or_build((settings.quality, settings.luma, pass, radiance), |_| {
                let owned = settings.constants(radiance);
                let constants: Vec<(&str, f64)> =
                    owned.iter().map(|(k, v)| (k.as_str(), *v)).collect();
                let entry_point = match pass {
                    Pass::Antialias => "fs_fxaa",
                    Pass::Mask => "fs_mask",
                };
                ctx.fullscreen.pipeline(
                    device,
                    &FragmentDesc {
                        label: &format!(
                            "fxaa {entry_point} q{} {}",
                            settings.quality.name(),
                            settings.luma.name()
                        ),
                        module,
                        entry_point,
                        targets: &[if radiance && pass == Pass::Antialias {
                            HDR_FORMAT
                        } else {
                            COLOR_FORMAT_ENCODED_VIEW
                        }],
                        constants: &constants,
                        layout: None,
                    },
                )
            })
    }

    /// The bind group of a pipeline (layouts are derived from the shader) over `source`.
    /// `source` is the encoded view (luma tests), `linear` the sRGB view (the blend).
    fn bind_group(
        &self,
        pipeline: &wgpu::RenderPipeline,
        source: &wgpu::TextureView,
        linear: &wgpu::TextureView,
    ) -> wgpu::BindGroup {
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("fxaa"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(source),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: self.uniform.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(linear),
                },
            ],
        })
    }
}

impl Technique for Fxaa {
    crate::aa::common::shared_1x_post_process!(INFO);

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        let (width, height) = input.desc.size;
        let s = &self.settings;
        let uniform = FxaaUniform {
            rcp_frame_subpix: [
                1.0 / width as f32,
                1.0 / height as f32,
                s.subpix,
                s.subpix_limit,
            ],
            thresholds: [s.edge_threshold, s.edge_threshold_min, 0.0, 0.0],
            subpix_factors: [s.subpix_strands, s.subpix_clean_edges, 0.0, 0.0],
        };
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        // Before the tonemapper the luma tests read the perceptual copy and the blend radiance.
        let radiance = holds_radiance(input.color_1x());
        let source = encoded_view(self.perceptual.source(ctx, input.color_1x(), ""));
        let linear = input.color_1x().create_view(&Default::default());
        let pipeline = self.pipeline(ctx, Pass::Antialias, radiance);
        let bind_group = self.bind_group(&pipeline, &source, &linear);
        let target = encoded_or_radiance_view(output);
        ctx.fullscreen_pass("fxaa", &target, &pipeline, &bind_group);

        if self.debug_enabled {
            if self
                .mask
                .as_ref()
                .is_none_or(|m| (m.width(), m.height()) != (width, height))
            {
                self.mask = Some(debug_texture(&self.device, "fxaa edges", (width, height)));
            }
            let pipeline = self.pipeline(ctx, Pass::Mask, radiance);
            let bind_group = self.bind_group(&pipeline, &source, &linear);
            if let Some(mask) = &self.mask {
                ctx.fullscreen_pass("debug edges", &encoded_view(mask), &pipeline, &bind_group);
            }
        }
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("fxaa params", &self.uniform)];
        if let Some(mask) = &self.mask {
            items.push(MemoryItem::texture("fxaa edges view", mask));
        }
        items.extend(self.perceptual.memory(ID));
        items
    }

    crate::aa::common::tunable_settings!(settings);

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        match (&self.mask, self.debug_enabled) {
            (Some(mask), true) => vec![DebugView {
                name: "edges",
                description: "FXAA's edge mask over the dimmed luma: orange pixels lie on horizontal \
                     edges (blended vertically), blue ones on vertical edges (blended horizontally); \
                     the stronger the colour, the further the pass moved the read. Grey pixels fell \
                     below the contrast threshold and are unchanged.",
                texture: mask,
            }],
            _ => Vec::new(),
        }
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        Some(format!(
            "quality {} ({} search steps), {} luma on sRGB-encoded values, blend in linear light",
            s.quality.name(),
            s.quality.search_steps().len(),
            s.luma.name()
        ))
    }
}
