//! FXAA 3.11, the quality path of Timothy Lottes' Fast Approximate Antialiasing (NVIDIA, 2011):
//! one fullscreen pass over the shared one-sample render that finds luma edges, walks along
//! each edge to its ends and blends across it by how far the pixel is from the nearer end.
//!
//! The pass (`shaders/fxaa.wgsl`) makes every luma test on the sRGB-encoded values (read through
//! an `Rgba8Unorm` view; BT.601 weights, or the green channel), as the thresholds are tuned for
//! perceptual LDR values, but blends in linear light, as Lottes intended for sRGB targets: the
//! final bilinear read goes through the sRGB view, whose texels the sampler decodes before
//! filtering, and is encoded again on output. (Blending the encoded values, as this pass did
//! before, left a half-covered black/white pixel at 100/255 where the reference has 179.)
//! The sub-pixel amount, a softening Lottes tuned on encoded values, moves the read by the linear
//! fraction that moves the encoded luma that far up from the darker side of the edge: read as a
//! linear fraction alone it lifted every black pixel beside a straight black/white edge to
//! 63/255 (5% of the light) where the encoded blend gives 13/255, which cost more than half of
//! the gain on near-vertical edges; read from each pixel's own side, bright pixels gave up more
//! light than dark ones gained (sub-pixel geometry lost 11% of its light, and FLIP rose).
//! Settings:
//! - `quality`: Lottes' presets 10-15 (few steps, a long last step: medium dither), 20-29 (more,
//!   shorter steps: less dither) and 39 (twelve short steps, no dither); the search step list
//!   of the preset goes into the shader as override constants, so a pipeline is built per
//!   preset and luma choice and cached;
//! - `subpix`, `edge_threshold`, `edge_threshold_min` as in FXAA 3.11 (uniforms: changing them
//!   costs nothing);
//! - `luma`: BT.601 luma or green-as-luma.
//!
//! Presets: `default` (Lottes' defaults: quality 12, subpix 0.75, thresholds 0.166 / 0.0833)
//! and Bevy's sensitivity levels `low` .. `extreme`, which set the two thresholds.
//! Debug view `edges`: the luma, with the pixels FXAA treats as edges coloured by orientation.

use std::collections::HashMap;

use super::color::LumaSource;
use super::msaa::debug_texture;
use super::params::{Param, ParamError, ParamValue, as_choice, as_f32};
use super::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu, shader};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Most search steps a preset has (the shader has this many step constants).
pub const MAX_STEPS: usize = 12;

/// FXAA 3.11's quality presets with their edge-search step lengths in pixels.
pub const QUALITY_PRESETS: &[(&str, &[f32])] = &[
    ("10", &[1.5, 3.0, 12.0]),
    ("11", &[1.0, 1.5, 3.0, 12.0]),
    ("12", &[1.0, 1.5, 2.0, 4.0, 12.0]),
    ("13", &[1.0, 1.5, 2.0, 2.0, 4.0, 12.0]),
    ("14", &[1.0, 1.5, 2.0, 2.0, 2.0, 4.0, 12.0]),
    ("15", &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 12.0]),
    ("20", &[1.5, 2.0, 8.0]),
    ("21", &[1.0, 1.5, 2.0, 8.0]),
    ("22", &[1.0, 1.5, 2.0, 2.0, 8.0]),
    ("23", &[1.0, 1.5, 2.0, 2.0, 2.0, 8.0]),
    ("24", &[1.0, 1.5, 2.0, 2.0, 2.0, 3.0, 8.0]),
    ("25", &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0]),
    ("26", &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0]),
    ("27", &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0]),
    (
        "28",
        &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
    ),
    (
        "29",
        &[1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
    ),
    (
        "39",
        &[1.0, 1.0, 1.0, 1.0, 1.0, 1.5, 2.0, 2.0, 2.0, 2.0, 4.0, 8.0],
    ),
];

/// The preset names, as the `quality` parameter accepts them (the first column of
/// [`QUALITY_PRESETS`]).
pub const QUALITY_NAMES: &[&str] = &{
    let mut names = [""; QUALITY_PRESETS.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = QUALITY_PRESETS[i].0;
        i += 1;
    }
    names
};

/// The search steps of a quality preset by name.
pub fn search_steps(quality: &str) -> Option<&'static [f32]> {
    QUALITY_PRESETS
        .iter()
        .find(|(name, _)| *name == quality)
        .map(|(_, steps)| *steps)
}

/// Bevy's sensitivity presets: (name, edge_threshold, edge_threshold_min).
pub const SENSITIVITY_PRESETS: &[(&str, f32, f32)] = &[
    ("low", 0.250, 0.0833),
    ("medium", 0.166, 0.0625),
    ("high", 0.125, 0.0312),
    ("ultra", 0.063, 0.0156),
    ("extreme", 0.031, 0.0078),
];

/// Every preset name: Lottes' defaults, then Bevy's sensitivities.
pub const PRESET_NAMES: &[&str] = &["default", "low", "medium", "high", "ultra", "extreme"];

/// FXAA settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FxaaSettings {
    /// Quality preset name from [`QUALITY_NAMES`].
    pub quality: &'static str,
    /// Sub-pixel blending: 0 off, 0.75 default, 1 softest.
    pub subpix: f32,
    /// Contrast needed to process a pixel, relative to the brightest luma of its cross.
    pub edge_threshold: f32,
    /// Contrast below which dark pixels are skipped regardless.
    pub edge_threshold_min: f32,
    /// How luma is computed.
    pub luma: LumaSource,
}

impl Default for FxaaSettings {
    /// Lottes' FXAA 3.11 defaults.
    fn default() -> Self {
        Self {
            quality: "12",
            subpix: 0.75,
            edge_threshold: 0.166,
            edge_threshold_min: 0.0833,
            luma: LumaSource::Bt601,
        }
    }
}

impl FxaaSettings {
    /// The override constants of the quality preset and luma choice.
    fn constants(&self) -> Vec<(String, f64)> {
        let steps = search_steps(self.quality).unwrap_or(&[]);
        let mut constants = vec![
            (
                "GREEN_AS_LUMA".to_owned(),
                f64::from(u8::from(self.luma == LumaSource::Green)),
            ),
            ("STEP_COUNT".to_owned(), steps.len() as f64),
        ];
        constants.extend((0..MAX_STEPS).map(|i| {
            (
                format!("STEP_{i}"),
                f64::from(steps.get(i).copied().unwrap_or(0.0)),
            )
        }));
        constants
    }
}

/// Which fragment entry point a pipeline runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Pass {
    Antialias,
    Mask,
}

/// Everything a pipeline is specialised on.
type PipelineKey = (&'static str, LumaSource, Pass);

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FxaaUniform {
    rcp_frame_subpix: [f32; 4],
    thresholds: [f32; 4],
}

/// The FXAA technique.
pub struct Fxaa {
    settings: FxaaSettings,
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    sampler: wgpu::Sampler,
    uniform: wgpu::Buffer,
    pipelines: HashMap<PipelineKey, wgpu::RenderPipeline>,
    debug_enabled: bool,
    mask: Option<wgpu::Texture>,
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
            module: shader::module(device, "fxaa.wgsl"),
            sampler: bilinear_clamp_sampler(device, "fxaa bilinear"),
            uniform: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("fxaa params"),
                size: std::mem::size_of::<FxaaUniform>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            device: device.clone(),
            pipelines: HashMap::new(),
            debug_enabled: false,
            mask: None,
        }
    }

    /// Current settings.
    pub fn settings(&self) -> FxaaSettings {
        self.settings
    }

    /// The pipeline for a pass with the current preset, built on first use.
    fn pipeline(&mut self, ctx: &PassContext<'_>, pass: Pass) -> wgpu::RenderPipeline {
        let key = (self.settings.quality, self.settings.luma, pass);
        if let Some(pipeline) = self.pipelines.get(&key) {
            return pipeline.clone();
        }
        let owned = self.settings.constants();
        let constants: Vec<(&str, f64)> = owned.iter().map(|(k, v)| (k.as_str(), *v)).collect();
        let entry_point = match pass {
            Pass::Antialias => "fs_fxaa",
            Pass::Mask => "fs_mask",
        };
        let pipeline = ctx.fullscreen.pipeline(
            &self.device,
            &FragmentDesc {
                label: &format!(
                    "fxaa {entry_point} q{} {}",
                    self.settings.quality,
                    self.settings.luma.name()
                ),
                module: &self.module,
                entry_point,
                targets: &[COLOR_FORMAT_ENCODED_VIEW],
                constants: &constants,
                layout: None,
            },
        );
        self.pipelines.insert(key, pipeline.clone());
        pipeline
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

/// A clamp-to-edge bilinear sampler (post passes read neighbours past the image border as the
/// border pixel).
pub fn bilinear_clamp_sampler(device: &wgpu::Device, label: &str) -> wgpu::Sampler {
    device.create_sampler(&wgpu::SamplerDescriptor {
        label: Some(label),
        address_mode_u: wgpu::AddressMode::ClampToEdge,
        address_mode_v: wgpu::AddressMode::ClampToEdge,
        mag_filter: wgpu::FilterMode::Linear,
        min_filter: wgpu::FilterMode::Linear,
        ..Default::default()
    })
}

/// A view of an RGBA8 sRGB texture that reads and writes the encoded values.
pub fn encoded_view(texture: &wgpu::Texture) -> wgpu::TextureView {
    texture.create_view(&wgpu::TextureViewDescriptor {
        format: Some(COLOR_FORMAT_ENCODED_VIEW),
        ..Default::default()
    })
}

impl Technique for Fxaa {
    fn id(&self) -> &'static str {
        "fxaa"
    }

    fn label(&self) -> String {
        super::registry::display_name(self.id())
    }

    fn color_only(&self) -> bool {
        true
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        Some(SceneInput::Shared1x)
    }

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
            rcp_frame_subpix: [1.0 / width as f32, 1.0 / height as f32, s.subpix, 0.0],
            thresholds: [s.edge_threshold, s.edge_threshold_min, 0.0, 0.0],
        };
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&uniform));
        let source = encoded_view(input.color_1x());
        let linear = input.color_1x().create_view(&Default::default());
        let pipeline = self.pipeline(ctx, Pass::Antialias);
        let bind_group = self.bind_group(&pipeline, &source, &linear);
        ctx.fullscreen_pass("fxaa", &encoded_view(output), &pipeline, &bind_group);

        if self.debug_enabled {
            if self
                .mask
                .as_ref()
                .is_none_or(|m| (m.width(), m.height()) != (width, height))
            {
                self.mask = Some(debug_texture(&self.device, "fxaa edges", (width, height)));
            }
            let pipeline = self.pipeline(ctx, Pass::Mask);
            let bind_group = self.bind_group(&pipeline, &source, &linear);
            if let Some(mask) = &self.mask {
                ctx.fullscreen_pass("debug edges", &encoded_view(mask), &pipeline, &bind_group);
            }
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("fxaa params", &self.uniform)];
        if let Some(mask) = &self.mask {
            items.push(MemoryItem::texture("fxaa edges view", mask));
        }
        items
    }

    fn params(&self) -> Vec<Param> {
        let s = &self.settings;
        vec![
            Param::choice(
                "quality",
                "Quality preset",
                "FXAA 3.11 quality preset: how far and in what steps the pass searches along an edge \
                 for its ends. 10-15: few steps ending in a long jump (fast, some dither on long \
                 edges); 20-29: more, shorter steps; 39: twelve short steps (no dither, slowest). \
                 Lottes' default is 12.",
                QUALITY_NAMES,
                s.quality,
            ),
            Param::float(
                "subpix",
                "Sub-pixel blending",
                "How much single pixels that stand out from their 3x3 neighbourhood are blended \
                 (sub-pixel aliasing): 0 off and sharpest, 0.75 the default, 1 softest.",
                0.0,
                1.0,
                s.subpix,
            ),
            Param::float(
                "edge_threshold",
                "Edge threshold",
                "Local contrast needed to treat a pixel as an edge, relative to the brightest luma \
                 around it: 0.333 too little, 0.25 low quality, 0.166 default, 0.125 high quality, \
                 0.063 overkill (more texture blur).",
                0.03,
                0.5,
                s.edge_threshold,
            ),
            Param::float(
                "edge_threshold_min",
                "Edge threshold (dark)",
                "Contrast below which pixels are left alone however dark they are: 0.0833 default, \
                 0.0625 high quality, 0.0312 visible limit (dark noise gets blurred).",
                0.0,
                0.1,
                s.edge_threshold_min,
            ),
            Param::choice(
                "luma",
                "Luma",
                "Luma used for every test: bt601 weighs the sRGB-encoded red, green and blue \
                 (0.299, 0.587, 0.114); green uses the green channel alone (cheaper, misses \
                 edges between colours of equal green).",
                LumaSource::NAMES,
                s.luma.name(),
            ),
        ]
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        let s = &mut self.settings;
        match key {
            "quality" => {
                let name = as_choice(value);
                s.quality = QUALITY_NAMES
                    .iter()
                    .copied()
                    .find(|n| *n == name)
                    .unwrap_or(s.quality);
            }
            "subpix" => s.subpix = as_f32(value),
            "edge_threshold" => s.edge_threshold = as_f32(value),
            "edge_threshold_min" => s.edge_threshold_min = as_f32(value),
            "luma" => s.luma = LumaSource::from_name(as_choice(value)).unwrap_or(s.luma),
            _ => return Err(ParamError::unknown_key("fxaa", key, &self.params())),
        }
        Ok(())
    }

    fn presets(&self) -> &'static [&'static str] {
        PRESET_NAMES
    }

    fn apply_preset(&mut self, name: &str) -> Result<(), ParamError> {
        if name == "default" {
            self.settings = FxaaSettings::default();
            return Ok(());
        }
        let Some((_, threshold, threshold_min)) =
            SENSITIVITY_PRESETS.iter().find(|(n, _, _)| *n == name)
        else {
            return Err(ParamError::UnknownPreset {
                technique: "fxaa".to_owned(),
                name: name.to_owned(),
                known: PRESET_NAMES.join(", "),
            });
        };
        self.settings.edge_threshold = *threshold;
        self.settings.edge_threshold_min = *threshold_min;
        Ok(())
    }

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
            s.quality,
            search_steps(s.quality).map_or(0, <[f32]>::len),
            s.luma.name()
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_quality_preset_has_a_step_list_within_the_shader_limit() {
        assert_eq!(QUALITY_NAMES.len(), QUALITY_PRESETS.len());
        for name in QUALITY_NAMES {
            let steps = search_steps(name).expect("listed preset");
            assert!((3..=MAX_STEPS).contains(&steps.len()), "{name}");
            // Medium-dither presets end in a 12-pixel guess, the others in 8.
            let last = *steps.last().expect("non-empty");
            assert_eq!(
                last,
                if name.starts_with('1') { 12.0 } else { 8.0 },
                "{name}"
            );
        }
        assert_eq!(
            search_steps("12").expect("preset 12"),
            &[1.0, 1.5, 2.0, 4.0, 12.0]
        );
        assert_eq!(search_steps("39").expect("preset 39").len(), 12);
        assert!(search_steps("16").is_none());
        // Within each family a higher preset searches at least as far.
        let reach = |n: &str| search_steps(n).expect("listed preset").iter().sum::<f32>();
        for pair in QUALITY_NAMES.windows(2) {
            if pair[0].as_bytes()[0] == pair[1].as_bytes()[0] {
                assert!(reach(pair[1]) >= reach(pair[0]), "{pair:?}");
            }
        }
    }

    #[test]
    fn constants_fill_every_step_slot() {
        let settings = FxaaSettings {
            quality: "20",
            luma: LumaSource::Green,
            ..FxaaSettings::default()
        };
        let constants = settings.constants();
        assert_eq!(constants.len(), 2 + MAX_STEPS);
        let get = |k: &str| constants.iter().find(|(n, _)| n == k).expect("constant").1;
        assert_eq!(get("GREEN_AS_LUMA"), 1.0);
        assert_eq!(get("STEP_COUNT"), 3.0);
        assert_eq!(
            (get("STEP_0"), get("STEP_1"), get("STEP_2")),
            (1.5, 2.0, 8.0)
        );
        assert_eq!(get("STEP_11"), 0.0);
    }

    #[test]
    fn sensitivity_presets_tighten_in_order() {
        for pair in SENSITIVITY_PRESETS.windows(2) {
            assert!(pair[1].1 < pair[0].1 && pair[1].2 < pair[0].2);
        }
        assert_eq!(PRESET_NAMES.len(), SENSITIVITY_PRESETS.len() + 1);
    }
}
