//! MSAA n (multisample antialiasing): the scene is rasterised with n coverage and depth
//! samples per pixel but shaded once per pixel, then the samples are resolved.
//!
//! Options, after the MSAA article in `../shared/seeds/000_*`:
//! - `resolve`: the hardware box resolve, custom resolves in linear light that weigh the
//!   samples of neighbouring pixels at their standard positions with a wider filter (tent,
//!   Gaussian, Blackman-Harris), or a quincunx-style resolve (centre 1/2, corners 1/8);
//! - `alpha_to_coverage`: alpha-masked materials (foliage, fences) turn alpha into a sample
//!   mask instead of the all-or-nothing alpha test;
//! - `centroid`: texture coordinates interpolated at the centroid of the covered samples;
//! - `sample_shading`: the fragment shader runs per sample, which turns MSAA into SSAA at the
//!   same sample count.
//!
//! Debug views ([`debug`]): per-pixel count of covered samples and the "complex pixel" mask.
//! Sample counts are queried from the adapter; the registry offers only supported ones.
//!
//! Folder: `mod.rs` (the technique and its registry entries), `settings.rs` (the resolves),
//! `debug.rs` (the debug views), `msaa_resolve.wgsl` and `msaa_debug.wgsl`.
//!
//! Figures (cost against scene complexity, on a GPU, in motion): `docs/techniques/msaa.md`.

mod debug;
pub mod settings;

pub use settings::Resolve;

use crate::aa::common::holds_radiance;
use crate::aa::common::pass::{self, Binding};
use crate::aa::common::sampling::{
    gather_weights, own_sample_weights, quincunx_weights, standard_msaa_positions,
};
use crate::aa::info::{TechniqueInfo, needs_encoded_views};
use crate::aa::params::{Named, Param, ParamError, ParamValue, as_bool, as_named};
use crate::aa::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::gpu::{Capabilities, Gpu};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::{RasterOptions, SceneTargets, ShadingRate};
use debug::MsaaDebug;
use wgpu::util::DeviceExt;

/// Stable id of MSAA 2x.
pub const ID_2X: &str = "msaa2";
/// Stable id of MSAA 4x.
pub const ID_4X: &str = "msaa4";
/// Stable id of MSAA 8x.
pub const ID_8X: &str = "msaa8";
/// Stable id of MSAA 16x.
pub const ID_16X: &str = "msaa16";

/// The custom resolves.
const RESOLVE_WGSL: Shader = crate::wgsl!("src/aa/msaa/msaa_resolve.wgsl");
/// The coverage and complex-pixel debug views.
const DEBUG_WGSL: Shader = crate::wgsl!("src/aa/msaa/msaa_debug.wgsl");

const SUMMARY: &str = "Multisampling: coverage and depth are tested at n sample positions per pixel but the \
     pixel shader runs once per pixel, and the samples are averaged at the end. Geometric edges get n+1 \
     coverage levels at a fraction of SSAA's shading cost, but colour and depth memory grow n times, and \
     aliasing inside triangles (textures, specular highlights, alpha-tested cut-outs) is left alone unless \
     alpha-to-coverage or sample-rate shading is switched on. Its cost grows with scene complexity.";

/// The registry entries, one per sample count (the adapter decides which can run).
pub const INFOS: [TechniqueInfo; 4] = [
    TechniqueInfo {
        id: ID_2X,
        name: "MSAA 2x",
        summary: SUMMARY,
        availability: |caps| availability(caps, 2),
        create: |gpu| Box::new(Msaa::new(gpu, 2)),
        shaders: &[RESOLVE_WGSL, DEBUG_WGSL],
    },
    TechniqueInfo {
        id: ID_4X,
        name: "MSAA 4x",
        summary: SUMMARY,
        availability: |caps| availability(caps, 4),
        create: |gpu| Box::new(Msaa::new(gpu, 4)),
        shaders: &[RESOLVE_WGSL, DEBUG_WGSL],
    },
    TechniqueInfo {
        id: ID_8X,
        name: "MSAA 8x",
        summary: SUMMARY,
        availability: |caps| availability(caps, 8),
        create: |gpu| Box::new(Msaa::new(gpu, 8)),
        shaders: &[RESOLVE_WGSL, DEBUG_WGSL],
    },
    TechniqueInfo {
        id: ID_16X,
        name: "MSAA 16x",
        summary: SUMMARY,
        availability: |caps| availability(caps, 16),
        create: |gpu| Box::new(Msaa::new(gpu, 16)),
        shaders: &[RESOLVE_WGSL, DEBUG_WGSL],
    },
];

/// Stable ids of the MSAA techniques by sample count.
pub fn id_for(samples: u32) -> Option<&'static str> {
    Some(match samples {
        2 => ID_2X,
        4 => ID_4X,
        8 => ID_8X,
        16 => ID_16X,
        _ => return None,
    })
}

fn availability(caps: &Capabilities, samples: u32) -> Result<(), String> {
    needs_encoded_views(caps)?;
    if caps.supports_sample_count(samples) {
        Ok(())
    } else {
        Err(format!(
            "{samples}x MSAA is not supported by {} for the scene's colour, depth and motion formats \
             (supported sample counts: {:?})",
            caps.adapter_name, caps.scene_sample_counts
        ))
    }
}

/// What a custom resolve's pipeline and weights are built for: the filter, the luminance
/// weighting and whether it resolves radiance (a half-float output).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct CustomKey {
    resolve: Resolve,
    luma_weighted: bool,
    radiance: bool,
}

/// MSAA with a fixed sample count.
pub struct Msaa {
    id: &'static str,
    samples: u32,
    resolve: Resolve,
    /// Karis' 1 / (1 + luma) weighting of every sample in the resolve.
    luma_weighted: bool,
    /// In HDR frames, resolve radiance (before the tonemapper) or tonemapped samples.
    tonemap_order: TonemapOrder,
    raster: RasterOptions,
    device: wgpu::Device,
    resolve_module: wgpu::ShaderModule,
    /// The custom resolve's bindings: the samples and the weight table.
    resolve_layout: wgpu::BindGroupLayout,
    resolve_pipeline_layout: wgpu::PipelineLayout,
    /// The custom resolve's pipeline and its weight table, for what they were built for.
    custom: Option<(CustomKey, wgpu::RenderPipeline, wgpu::Buffer)>,
    debug: Option<MsaaDebug>,
    debug_enabled: bool,
}

impl Msaa {
    /// MSAA with `samples` samples; the caller has checked the adapter supports the count.
    pub fn new(gpu: &Gpu, samples: u32) -> Self {
        let resolve_layout = pass::layout(
            &gpu.device,
            "msaa resolve",
            &[(0, Binding::MultisampledTexture), (1, Binding::Uniform)],
        );
        let resolve_pipeline_layout =
            gpu.device
                .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("msaa resolve"),
                    bind_group_layouts: &[Some(&resolve_layout)],
                    immediate_size: 0,
                });
        Self {
            id: id_for(samples).unwrap_or("msaa"),
            samples,
            resolve: Resolve::Box,
            luma_weighted: false,
            tonemap_order: TonemapOrder::Before,
            raster: RasterOptions::default(),
            resolve_module: RESOLVE_WGSL.module(&gpu.device),
            resolve_layout,
            resolve_pipeline_layout,
            device: gpu.device.clone(),
            custom: None,
            debug: None,
            debug_enabled: false,
        }
    }

    /// The weight table of a custom resolve.
    fn resolve_weights(&self) -> Vec<f32> {
        let positions = standard_msaa_positions(self.samples).unwrap_or_default();
        match (self.resolve, self.resolve.filter()) {
            (Resolve::Box, _) => own_sample_weights(self.samples),
            (_, Some(filter)) => gather_weights(filter, &positions),
            (_, None) => quincunx_weights(&positions),
        }
    }

    fn custom_resolve(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: &SceneTargets,
        output: &wgpu::Texture,
    ) {
        let key = CustomKey {
            resolve: self.resolve,
            luma_weighted: self.luma_weighted,
            radiance: holds_radiance(output),
        };
        if self
            .custom
            .as_ref()
            .is_none_or(|(built, _, _)| *built != key)
        {
            let weights = self.resolve_weights();
            let pipeline = ctx.fullscreen.pipeline(
                &self.device,
                &FragmentDesc {
                    label: &format!("{} resolve {}", self.id, self.resolve.name()),
                    module: &self.resolve_module,
                    entry_point: "fs_resolve",
                    targets: &[output.format()],
                    constants: &[("LUMA_WEIGHT", f64::from(u8::from(key.luma_weighted)))],
                    layout: Some(&self.resolve_pipeline_layout),
                },
            );
            let table = self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{} {} weights", self.id, self.resolve.name())),
                    contents: bytemuck::cast_slice(&weights),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            self.custom = Some((key, pipeline, table));
        }
        let Some((_, pipeline, table)) = &self.custom else {
            return;
        };
        let samples_view = input.color.create_view(&Default::default());
        let bind_group = pass::bind_group(
            &self.device,
            "msaa resolve",
            &self.resolve_layout,
            &[
                (0, wgpu::BindingResource::TextureView(&samples_view)),
                (1, table.as_entire_binding()),
            ],
        );
        let target = output.create_view(&Default::default());
        ctx.fullscreen_pass(
            &format!("resolve {}", self.resolve.name()),
            &target,
            pipeline,
            &bind_group,
        );
    }
}

impl Technique for Msaa {
    fn id(&self) -> &'static str {
        self.id
    }

    fn label(&self) -> String {
        INFOS
            .iter()
            .find(|info| info.id == self.id)
            .map_or(self.id, |info| info.name)
            .to_owned()
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.tonemap_order
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        Some(SceneInput::Msaa {
            samples: self.samples,
            raster: self.raster,
        })
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        if self.resolve == Resolve::Box && !self.luma_weighted {
            ctx.copy_texture("copy resolve", input.color_1x(), output);
        } else {
            self.custom_resolve(ctx, input, output);
        }
        if self.debug_enabled {
            let debug = self.debug.take().filter(|d| d.size() == input.desc.size);
            let debug = debug.unwrap_or_else(|| {
                MsaaDebug::new(ctx, &self.device, self.id, &DEBUG_WGSL, input.desc.size)
            });
            debug.encode(ctx, &self.device, input);
            self.debug = Some(debug);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = Vec::new();
        if let Some((key, _, table)) = &self.custom {
            items.push(MemoryItem::buffer(
                format!("{} {} weights", self.id, key.resolve.name()),
                table,
            ));
        }
        if let Some(d) = &self.debug {
            items.push(MemoryItem::texture(
                format!("{} coverage view", self.id),
                &d.coverage,
            ));
            items.push(MemoryItem::texture(
                format!("{} complex view", self.id),
                &d.complex,
            ));
        }
        items
    }

    fn params(&self) -> Vec<Param> {
        vec![
            Param::named(
                "resolve",
                "Resolve",
                "How samples become pixels: box is the hardware average of the pixel's own samples; \
                 tent, gaussian and blackman-harris weigh the samples of neighbouring pixels too, by \
                 their distance from the pixel centre (smoother edges, slightly softer image); \
                 quincunx takes half the pixel and an eighth of each corner (soft, like NVIDIA's Quincunx).",
                self.resolve,
            ),
            Param::bool(
                "luma_weighted",
                "Luminance-weighted resolve",
                "Weigh every sample by 1 / (1 + luminance) (Karis), normalised: the tonemap-aware \
                 resolve HDR renderers use, so one very bright sample cannot take over an edge \
                 pixel's average and bright edges keep their antialiasing after the tonemapper.",
                self.luma_weighted,
            ),
            self.tonemap_order.param(),
            Param::bool(
                "alpha_to_coverage",
                "Alpha to coverage",
                "Alpha-masked materials (foliage, fences) set as many samples as their alpha covers \
                 instead of the all-or-nothing alpha test, so cut-out edges are antialiased too.",
                self.raster.alpha_to_coverage,
            ),
            Param::bool(
                "centroid",
                "Centroid sampling",
                "Interpolate texture coordinates at the centre of the covered samples rather than the \
                 pixel centre, so edge pixels never sample texels outside the triangle.",
                self.raster.shading == ShadingRate::Centroid,
            ),
            Param::bool(
                "sample_shading",
                "Sample-rate shading",
                "Run the pixel shader once per sample instead of once per pixel: MSAA becomes SSAA at \
                 the same sample count (shading aliasing such as specular highlights is fixed too, at \
                 n times the shading cost).",
                self.raster.shading == ShadingRate::Sample,
            ),
        ]
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        match key {
            "resolve" => self.resolve = as_named(value).unwrap_or(Resolve::Box),
            "luma_weighted" => self.luma_weighted = as_bool(value),
            "tonemap_order" => self.tonemap_order = as_named(value).unwrap_or(TonemapOrder::Before),
            "alpha_to_coverage" => self.raster.alpha_to_coverage = as_bool(value),
            "centroid" => {
                if as_bool(value) {
                    self.raster.shading = ShadingRate::Centroid;
                } else if self.raster.shading == ShadingRate::Centroid {
                    self.raster.shading = ShadingRate::Pixel;
                }
            }
            "sample_shading" => {
                if as_bool(value) {
                    self.raster.shading = ShadingRate::Sample;
                } else if self.raster.shading == ShadingRate::Sample {
                    self.raster.shading = ShadingRate::Pixel;
                }
            }
            _ => return Err(ParamError::unknown_key(self.id, key, &self.params())),
        }
        Ok(())
    }

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        match (&self.debug, self.debug_enabled) {
            (Some(d), true) => vec![
                DebugView {
                    name: "coverage",
                    description: "Samples of each pixel covered by geometry: black none, blue few, orange half, white all.",
                    texture: &d.coverage,
                },
                DebugView {
                    name: "complex",
                    description: "Magenta: complex pixels whose samples differ (the only pixels MSAA antialiases); the rest dimmed.",
                    texture: &d.complex,
                },
            ],
            _ => Vec::new(),
        }
    }
}
