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
//! Debug views: per-pixel count of covered samples and the "complex pixel" mask.
//! Sample counts are queried from the adapter; the registry offers only supported ones.

use super::params::{Param, ParamError, ParamValue, as_bool, as_choice};
use super::sampling::{Filter, gather_weights, quincunx_weights, standard_msaa_positions};
use super::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::{COLOR_FORMAT, Gpu, shader};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::{RasterOptions, SceneTargets, ShadingRate};
use wgpu::util::DeviceExt;

/// Resolve choices, as the `resolve` parameter names them.
pub const RESOLVE_NAMES: &[&str] = &["box", "tent", "gaussian", "blackman-harris", "quincunx"];

/// Stable ids of the MSAA techniques by sample count.
pub fn id_for(samples: u32) -> Option<&'static str> {
    Some(match samples {
        2 => "msaa2",
        4 => "msaa4",
        8 => "msaa8",
        16 => "msaa16",
        _ => return None,
    })
}

/// MSAA with a fixed sample count.
pub struct Msaa {
    id: &'static str,
    samples: u32,
    resolve: &'static str,
    raster: RasterOptions,
    device: wgpu::Device,
    resolve_module: wgpu::ShaderModule,
    /// The custom resolve's pipeline and its weight table, for the resolve they were built for.
    custom: Option<(&'static str, wgpu::RenderPipeline, wgpu::Buffer)>,
    debug: Option<MsaaDebug>,
    debug_enabled: bool,
}

struct MsaaDebug {
    coverage_pipeline: wgpu::RenderPipeline,
    complex_pipeline: wgpu::RenderPipeline,
    coverage: wgpu::Texture,
    complex: wgpu::Texture,
}

impl Msaa {
    /// MSAA with `samples` samples; the caller has checked the adapter supports the count.
    pub fn new(gpu: &Gpu, samples: u32) -> Self {
        Self {
            id: id_for(samples).unwrap_or("msaa"),
            samples,
            resolve: "box",
            raster: RasterOptions::default(),
            resolve_module: shader::module(&gpu.device, "msaa_resolve.wgsl"),
            device: gpu.device.clone(),
            custom: None,
            debug: None,
            debug_enabled: false,
        }
    }

    /// The weight table of a custom resolve.
    fn resolve_weights(&self) -> Vec<f32> {
        let positions = standard_msaa_positions(self.samples).unwrap_or_default();
        match Filter::from_name(self.resolve) {
            Some(filter) => gather_weights(filter, &positions),
            None => quincunx_weights(&positions),
        }
    }

    fn custom_resolve(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: &SceneTargets,
        output: &wgpu::Texture,
    ) {
        if self
            .custom
            .as_ref()
            .is_none_or(|(name, _, _)| *name != self.resolve)
        {
            let weights = self.resolve_weights();
            let pipeline = ctx.fullscreen.pipeline(
                &self.device,
                &FragmentDesc {
                    label: &format!("{} resolve {}", self.id, self.resolve),
                    module: &self.resolve_module,
                    entry_point: "fs_resolve",
                    targets: &[COLOR_FORMAT],
                    constants: &[],
                    layout: None,
                },
            );
            let table = self
                .device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(&format!("{} {} weights", self.id, self.resolve)),
                    contents: bytemuck::cast_slice(&weights),
                    usage: wgpu::BufferUsages::UNIFORM,
                });
            self.custom = Some((self.resolve, pipeline, table));
        }
        let Some((_, pipeline, table)) = &self.custom else {
            return;
        };
        let samples_view = input.color.create_view(&Default::default());
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("msaa resolve"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&samples_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: table.as_entire_binding(),
                },
            ],
        });
        let target = output.create_view(&Default::default());
        ctx.fullscreen_pass(
            &format!("resolve {}", self.resolve),
            &target,
            pipeline,
            &bind_group,
        );
    }

    fn encode_debug(&mut self, ctx: &mut PassContext<'_>, input: &SceneTargets) {
        let size = input.desc.size;
        let stale = self
            .debug
            .as_ref()
            .is_none_or(|d| (d.coverage.width(), d.coverage.height()) != size);
        if stale {
            let module = shader::module(&self.device, "msaa_debug.wgsl");
            let pipeline = |entry_point: &str| {
                ctx.fullscreen.pipeline(
                    &self.device,
                    &FragmentDesc {
                        label: &format!("{} {entry_point}", self.id),
                        module: &module,
                        entry_point,
                        targets: &[COLOR_FORMAT],
                        constants: &[],
                        layout: None,
                    },
                )
            };
            self.debug = Some(MsaaDebug {
                coverage_pipeline: pipeline("fs_coverage"),
                complex_pipeline: pipeline("fs_complex"),
                coverage: debug_texture(&self.device, &format!("{} coverage", self.id), size),
                complex: debug_texture(&self.device, &format!("{} complex pixels", self.id), size),
            });
        }
        let Some(debug) = &self.debug else { return };
        let views = [
            (
                &debug.coverage_pipeline,
                &debug.coverage,
                &input.depth,
                "coverage",
            ),
            (
                &debug.complex_pipeline,
                &debug.complex,
                &input.color,
                "complex pixels",
            ),
        ];
        for (binding, (pipeline, target, source, name)) in views.into_iter().enumerate() {
            let source_view = source.create_view(&Default::default());
            let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(name),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &[wgpu::BindGroupEntry {
                    binding: binding as u32,
                    resource: wgpu::BindingResource::TextureView(&source_view),
                }],
            });
            let target_view = target.create_view(&Default::default());
            ctx.fullscreen_pass(
                &format!("debug {name}"),
                &target_view,
                pipeline,
                &bind_group,
            );
        }
    }
}

/// A debug-view texture: RGBA8 sRGB at the output size, readable back and viewable by egui.
pub fn debug_texture(device: &wgpu::Device, label: &str, size: (u32, u32)) -> wgpu::Texture {
    crate::gpu::texture_2d(
        device,
        &crate::gpu::Texture2d {
            view_formats: &[crate::gpu::COLOR_FORMAT_ENCODED_VIEW],
            ..crate::gpu::Texture2d::new(
                label,
                size,
                COLOR_FORMAT,
                wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
            )
        },
    )
}

impl Technique for Msaa {
    fn id(&self) -> &'static str {
        self.id
    }

    fn label(&self) -> String {
        super::registry::display_name(self.id())
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
        if self.resolve == "box" {
            ctx.copy_texture("copy resolve", input.color_1x(), output);
        } else {
            self.custom_resolve(ctx, input, output);
        }
        if self.debug_enabled {
            self.encode_debug(ctx, input);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = Vec::new();
        if let Some((name, _, table)) = &self.custom {
            items.push(MemoryItem::buffer(
                format!("{} {name} weights", self.id),
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
            Param::choice(
                "resolve",
                "Resolve",
                "How samples become pixels: box is the hardware average of the pixel's own samples; \
                 tent, gaussian and blackman-harris weigh the samples of neighbouring pixels too, by \
                 their distance from the pixel centre (smoother edges, slightly softer image); \
                 quincunx takes half the pixel and an eighth of each corner (soft, like NVIDIA's Quincunx).",
                RESOLVE_NAMES,
                self.resolve,
            ),
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
            "resolve" => {
                let name = as_choice(value);
                self.resolve = RESOLVE_NAMES
                    .iter()
                    .copied()
                    .find(|n| *n == name)
                    .unwrap_or("box");
            }
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
