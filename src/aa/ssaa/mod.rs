//! SSAA (supersampling): every sample is fully shaded, the brute-force answer that the other
//! techniques approximate, and with 64 samples the reference the quality metrics compare with.
//!
//! Two modes, after the MSAA article's discussion of sample patterns:
//! - `ordered`: the ordered grid k x k. The scene is rendered k times larger in each direction
//!   and box-filtered down in linear light. Large images are rendered in tiles (each tile with
//!   the projection of its part of the big image), so k = 8 at 4K needs no 30720-pixel texture.
//! - `jittered`: N one-sample renders, each with the projection shifted to one position of a
//!   pattern (regular grid, rotated grid, uniform random, Poisson disk, Halton(2,3)), gathered
//!   into a float accumulator with a reconstruction filter (box, tent, Gaussian,
//!   Blackman-Harris) whose weights come from `aa::common::sampling`. Textures get a mip bias of
//!   -log2(N)/2 so they are as sharp as a render N times larger would have them.
//!
//! [`Ssaa::encode_progressive`] spreads the jittered mode over frames for the viewer's
//! reference: each call adds a few more samples (visited in farthest-point order, so every
//! prefix covers the pixel evenly) and resolves the partial sum divided by the weight
//! accumulated so far. A 64-sample `grid` pattern with the box filter gives the same samples as
//! the ordered 8 x 8 reference.
//!
//! Figures: `docs/techniques/ssaa.md`.

use glam::Vec2;
use wgpu::util::DeviceExt;

mod plan;
pub mod settings;

pub use plan::{MAX_TILE_SIDE, SOFTWARE_MAX_TILE_SIDE, TilePlan, progressive_order};
pub use settings::{MAX_FACTOR, MAX_SAMPLES, Mode, SsaaSettings};

use crate::aa::common::pass::{self, Binding};
use crate::aa::common::sampling::{Filter, Pattern, accumulation_weights};
use crate::aa::info::{TechniqueInfo, anywhere};
use crate::aa::params::{Named, Param, ParamError, ParamValue, as_i64, as_named};
use crate::aa::{FrameInfo, SceneInput, Technique};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT, Gpu, HDR_FORMAT};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::camera::PixelRect;
use crate::scene::renderer::{RasterOptions, SceneTargets, TargetDesc};

/// Stable id, as on the command line.
pub const ID: &str = "ssaa";

/// The ordered-grid downsample and the jittered accumulation and resolve.
const WGSL: Shader = crate::wgsl!("src/aa/ssaa/ssaa.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "SSAA",
    summary: "Supersampling: every sample is fully shaded (k x k ordered grid, or N jittered samples \
         with a chosen pattern and filter). It fixes every kind of aliasing - edges, textures, \
         highlights, sub-pixel geometry - and is the reference the others are measured against, \
         but it costs N times the shading, fill and memory bandwidth.",
    availability: anywhere,
    create: |gpu| Box::new(Ssaa::new(gpu)),
    shaders: &[WGSL],
};

/// Bytes between per-sample uniform slots (dynamic offsets need 256-byte alignment).
const SLOT: u64 = 256;

struct Ordered {
    plan: TilePlan,
    targets: SceneTargets,
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
}

struct Jittered {
    size: (u32, u32),
    settings: SsaaSettings,
    /// Built for progressive accumulation (positions in farthest-point order).
    progressive: bool,
    positions: Vec<Vec2>,
    /// Sum of each sample's 3x3 weights (the normaliser of a partial accumulation).
    weight_sums: Vec<f32>,
    /// Samples in the accumulator (progressive mode).
    accumulated: u32,
    target: SceneTargets,
    accumulator: wgpu::Buffer,
    weights: wgpu::Buffer,
    accumulate_pipeline: wgpu::ComputePipeline,
    accumulate_group: wgpu::BindGroup,
    resolve_pipeline: wgpu::RenderPipeline,
    resolve_group: wgpu::BindGroup,
    /// xy: image size, z: bits of the f32 scale applied to the accumulated sum.
    resolve_params: wgpu::Buffer,
}

/// How far a progressive accumulation ([`Ssaa::encode_progressive`]) has come.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Progress {
    /// Samples accumulated so far.
    pub samples: u32,
    /// Samples of the whole pattern.
    pub total: u32,
}

impl Progress {
    /// Whether every sample of the pattern is in.
    pub fn complete(&self) -> bool {
        self.total > 0 && self.samples >= self.total
    }
}

/// The SSAA technique.
pub struct Ssaa {
    settings: SsaaSettings,
    device: wgpu::Device,
    max_tile_side: u32,
    module: wgpu::ShaderModule,
    ordered: Option<Ordered>,
    jittered: Option<Jittered>,
    /// Whether the samples are HDR radiance (the output is `HDR_FORMAT`: the graph tonemaps
    /// the average, as a camera would) rather than display values.
    hdr: bool,
}

impl Ssaa {
    /// SSAA with default settings (ordered 2 x 2).
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, SsaaSettings::default())
    }

    /// SSAA with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: SsaaSettings) -> Self {
        Self {
            settings,
            device: gpu.device.clone(),
            max_tile_side: gpu.caps.max_texture_dimension_2d.min(if gpu.caps.software {
                SOFTWARE_MAX_TILE_SIDE
            } else {
                MAX_TILE_SIDE
            }),
            module: WGSL.module(&gpu.device),
            ordered: None,
            jittered: None,
            hdr: false,
        }
    }

    /// Current settings.
    pub fn settings(&self) -> SsaaSettings {
        self.settings
    }

    /// The format of the output the pipelines write.
    fn output_format(&self) -> wgpu::TextureFormat {
        if self.hdr { HDR_FORMAT } else { COLOR_FORMAT }
    }

    /// Follows the output's format: HDR radiance or display values (dropping the targets and
    /// pipelines of the other).
    fn follow_output(&mut self, output: &wgpu::Texture) {
        let hdr = output.format() == HDR_FORMAT;
        if hdr != self.hdr {
            self.hdr = hdr;
            self.ordered = None;
            self.jittered = None;
        }
    }

    fn ensure_ordered(&mut self, ctx: &PassContext<'_>, size: (u32, u32)) {
        let plan = TilePlan::new(size, self.settings.factor, self.max_tile_side);
        if self.ordered.as_ref().is_some_and(|o| o.plan == plan) {
            return;
        }
        self.jittered = None;
        let device = &self.device;
        let desc = TargetDesc {
            size: (plan.tile.x * plan.factor, plan.tile.y * plan.factor),
            sample_count: 1,
            motion: false,
            hdr: self.hdr,
            reactive_mask: false,
        };
        let targets = SceneTargets::new(ctx.gpu, "ssaa tile", desc);
        let tiles = plan.tiles().len() as u64;
        let params = pass::uniform_buffer_of_size(device, "ssaa tile origins", tiles * SLOT);
        let tile_view = targets.color.create_view(&Default::default());
        let layout = pass::layout(
            device,
            "ssaa downsample",
            &[
                (0, Binding::UnfilterableTexture),
                (1, Binding::DynamicUniform),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("ssaa downsample"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = ctx.fullscreen.pipeline(
            device,
            &FragmentDesc {
                label: "ssaa downsample",
                module: &self.module,
                entry_point: "fs_downsample",
                targets: &[self.output_format()],
                constants: &[],
                layout: Some(&pipeline_layout),
            },
        );
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ssaa downsample"),
            layout: &layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&tile_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &params,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
            ],
        });
        self.ordered = Some(Ordered {
            plan,
            targets,
            pipeline,
            params,
            bind_group,
        });
    }

    fn encode_ordered(&mut self, ctx: &mut PassContext<'_>, output: &wgpu::Texture) {
        self.follow_output(output);
        let size = ctx.frame.size();
        self.ensure_ordered(ctx, size);
        let Some(ordered) = &self.ordered else { return };
        let tiles = ordered.plan.tiles();
        let mut origins = vec![0u8; tiles.len() * SLOT as usize];
        for (i, tile) in tiles.iter().enumerate() {
            let words = [tile.x, tile.y, ordered.plan.factor, 0];
            origins[i * SLOT as usize..i * SLOT as usize + 16]
                .copy_from_slice(bytemuck::cast_slice(&words));
        }
        ctx.gpu.queue.write_buffer(&ordered.params, 0, &origins);
        let output_view = output.create_view(&Default::default());
        let k = ordered.plan.factor;
        for (i, tile) in tiles.iter().enumerate() {
            // The tile's supersampled rectangle, always the full tile target: tiles cut by the
            // image edge simply render a little beyond it.
            let rect = PixelRect {
                x: tile.x * k,
                y: tile.y * k,
                width: ordered.plan.tile.x * k,
                height: ordered.plan.tile.y * k,
            };
            let view = ctx.frame.camera.tile_params(k, rect, Vec2::ZERO, 0.0);
            ctx.render_scene(
                "scene tile",
                &ordered.targets,
                &view,
                RasterOptions::default(),
            );
            let attachment = wgpu::RenderPassColorAttachment {
                view: &output_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Load,
                    store: wgpu::StoreOp::Store,
                },
            };
            ctx.render_pass("downsample", &[Some(attachment)], None, |pass| {
                pass.set_viewport(
                    tile.x as f32,
                    tile.y as f32,
                    tile.width as f32,
                    tile.height as f32,
                    0.0,
                    1.0,
                );
                pass.set_pipeline(&ordered.pipeline);
                pass.set_bind_group(0, &ordered.bind_group, &[(i as u64 * SLOT) as u32]);
                pass.draw(0..3, 0..1);
            });
        }
    }

    fn ensure_jittered(&mut self, ctx: &PassContext<'_>, size: (u32, u32), progressive: bool) {
        if self.jittered.as_ref().is_some_and(|j| {
            j.size == size && j.settings == self.settings && j.progressive == progressive
        }) {
            return;
        }
        self.ordered = None;
        let device = &self.device;
        let mut positions = self.settings.pattern.positions(self.settings.samples);
        if progressive {
            positions = progressive_order(&positions);
        }
        let weights = accumulation_weights(self.settings.filter, &positions);
        let weight_sums = weights.iter().map(|w| w.iter().sum()).collect();
        let mut weight_bytes = vec![0u8; weights.len() * SLOT as usize];
        for (i, w) in weights.iter().enumerate() {
            let mut slot = [0u32; 40];
            for (j, x) in w.iter().enumerate() {
                slot[j * 4] = x.to_bits();
            }
            slot[36] = size.0;
            slot[37] = size.1;
            weight_bytes[i * SLOT as usize..i * SLOT as usize + 160]
                .copy_from_slice(bytemuck::cast_slice(&slot));
        }
        let weights_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ssaa sample weights"),
            contents: &weight_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let accumulator = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ssaa accumulator"),
            size: u64::from(size.0) * u64::from(size.1) * 16,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let target = SceneTargets::new(
            ctx.gpu,
            "ssaa jittered",
            TargetDesc {
                size,
                sample_count: 1,
                motion: false,
                hdr: self.hdr,
                reactive_mask: false,
            },
        );
        let accumulate_layout = pass::stage_layout(
            device,
            "ssaa accumulate",
            wgpu::ShaderStages::COMPUTE,
            &[
                (0, Binding::UnfilterableTexture),
                (1, Binding::DynamicUniform),
                (2, Binding::StorageBuffer),
            ],
        );
        let accumulate_pipeline =
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("ssaa accumulate"),
                layout: Some(
                    &device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                        label: Some("ssaa accumulate"),
                        bind_group_layouts: &[Some(&accumulate_layout)],
                        immediate_size: 0,
                    }),
                ),
                module: &self.module,
                entry_point: Some("cs_accumulate"),
                compilation_options: Default::default(),
                cache: None,
            });
        let target_view = target.color.create_view(&Default::default());
        let accumulate_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ssaa accumulate"),
            layout: &accumulate_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&target_view),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &weights_buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(160),
                    }),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: accumulator.as_entire_binding(),
                },
            ],
        });
        let resolve_pipeline = ctx.fullscreen.pipeline(
            device,
            &FragmentDesc {
                label: "ssaa resolve accumulated",
                module: &self.module,
                entry_point: "fs_resolve_accumulated",
                targets: &[self.output_format()],
                constants: &[],
                layout: None,
            },
        );
        let resolve_params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("ssaa resolve params"),
            contents: bytemuck::cast_slice(&[size.0, size.1, 1.0f32.to_bits(), 0]),
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        });
        let resolve_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("ssaa resolve accumulated"),
            layout: &resolve_pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: accumulator.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: resolve_params.as_entire_binding(),
                },
            ],
        });
        self.jittered = Some(Jittered {
            size,
            settings: self.settings,
            progressive,
            positions,
            weight_sums,
            accumulated: 0,
            target,
            accumulator,
            weights: weights_buffer,
            accumulate_pipeline,
            accumulate_group,
            resolve_pipeline,
            resolve_group,
            resolve_params,
        });
    }

    fn encode_jittered(&mut self, ctx: &mut PassContext<'_>, output: &wgpu::Texture) {
        self.follow_output(output);
        let size = ctx.frame.size();
        self.ensure_jittered(ctx, size, false);
        let Some(j) = &self.jittered else { return };
        ctx.encoder.clear_buffer(&j.accumulator, 0, None);
        j.accumulate(ctx, 0..j.positions.len());
        j.resolve(ctx, output, 1.0);
    }

    /// Progressive jittered supersampling (see the module docs): adds up to `budget` samples
    /// of the jittered pattern to what earlier calls accumulated and resolves the partial sum
    /// into `output`. The accumulation starts over when `restart` is set (the view changed),
    /// when the size or the settings change, and after the last sample nothing more is
    /// rendered (the resolve alone runs). Ordered settings are treated as the jittered grid of
    /// the same sample count, which takes exactly the ordered grid's samples.
    pub fn encode_progressive(
        &mut self,
        ctx: &mut PassContext<'_>,
        output: &wgpu::Texture,
        restart: bool,
        budget: u32,
    ) -> Progress {
        self.follow_output(output);
        if self.settings.mode == Mode::Ordered {
            self.settings = SsaaSettings {
                mode: Mode::Jittered,
                samples: self.settings.factor * self.settings.factor,
                pattern: Pattern::Grid,
                filter: Filter::Box,
                ..self.settings
            };
        }
        let size = ctx.frame.size();
        self.ensure_jittered(ctx, size, true);
        let Some(j) = &mut self.jittered else {
            return Progress::default();
        };
        if restart {
            j.accumulated = 0;
        }
        let total = j.positions.len() as u32;
        let start = j.accumulated.min(total);
        let end = start.saturating_add(budget).min(total);
        if start == 0 {
            ctx.encoder.clear_buffer(&j.accumulator, 0, None);
        }
        j.accumulate(ctx, start as usize..end as usize);
        j.accumulated = end;
        let weight: f32 = j.weight_sums[..end as usize].iter().sum();
        j.resolve(ctx, output, if weight > 0.0 { 1.0 / weight } else { 0.0 });
        Progress {
            samples: end,
            total,
        }
    }
}

impl Jittered {
    /// Renders and accumulates the samples in `range` of the pattern.
    fn accumulate(&self, ctx: &mut PassContext<'_>, range: std::ops::Range<usize>) {
        let size = self.size;
        let mip_bias = -0.5 * (self.positions.len() as f32).log2();
        let groups = (size.0.div_ceil(8), size.1.div_ceil(8));
        for (i, position) in self
            .positions
            .iter()
            .enumerate()
            .take(range.end)
            .skip(range.start)
        {
            // A sample at `position` inside the pixel is the image moved by centre - position.
            let view = ctx
                .frame
                .camera
                .params(Vec2::splat(0.5) - *position, mip_bias);
            ctx.render_scene(
                "scene sample",
                &self.target,
                &view,
                RasterOptions::default(),
            );
            ctx.compute_pass("accumulate", |pass| {
                pass.set_pipeline(&self.accumulate_pipeline);
                pass.set_bind_group(0, &self.accumulate_group, &[(i as u64 * SLOT) as u32]);
                pass.dispatch_workgroups(groups.0, groups.1, 1);
            });
        }
    }

    /// Writes the accumulated sum times `scale` to `output`.
    fn resolve(&self, ctx: &mut PassContext<'_>, output: &wgpu::Texture, scale: f32) {
        ctx.gpu.queue.write_buffer(
            &self.resolve_params,
            0,
            bytemuck::cast_slice(&[self.size.0, self.size.1, scale.to_bits(), 0]),
        );
        let view = output.create_view(&Default::default());
        ctx.fullscreen_pass(
            "resolve",
            &view,
            &self.resolve_pipeline,
            &self.resolve_group,
        );
    }
}

impl Technique for Ssaa {
    fn id(&self) -> &'static str {
        ID
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        None
    }

    /// Before by default: supersampling averages radiance and is tonemapped afterwards, as a
    /// camera would.
    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        _input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        if self.settings.mode == Mode::Ordered {
            self.encode_ordered(ctx, output);
        } else {
            self.encode_jittered(ctx, output);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = Vec::new();
        if let Some(o) = &self.ordered {
            for (name, texture) in o.targets.textures() {
                items.push(MemoryItem::texture(format!("ssaa tile {name}"), texture));
            }
            items.push(MemoryItem::buffer("ssaa tile origins", &o.params));
        }
        if let Some(j) = &self.jittered {
            for (name, texture) in j.target.textures() {
                items.push(MemoryItem::texture(
                    format!("ssaa jittered {name}"),
                    texture,
                ));
            }
            items.push(MemoryItem::buffer("ssaa accumulator", &j.accumulator));
            items.push(MemoryItem::buffer("ssaa sample weights", &j.weights));
        }
        items
    }

    fn params(&self) -> Vec<Param> {
        let s = &self.settings;
        vec![
            Param::named(
                "mode",
                "Mode",
                "ordered: render k times larger and average k x k blocks (the classic SSAA and the \
                 reference); jittered: accumulate N one-sample renders at the positions of a pattern \
                 with a reconstruction filter.",
                s.mode,
            ),
            Param::int(
                "factor",
                "Grid factor k",
                "Ordered mode: k x k samples per pixel (k = 8 gives the 64-sample reference).",
                1,
                i64::from(MAX_FACTOR),
                i64::from(s.factor),
            ),
            Param::int(
                "samples",
                "Samples",
                "Jittered mode: samples per pixel (grid patterns round to a square count).",
                1,
                i64::from(MAX_SAMPLES),
                i64::from(s.samples),
            ),
            Param::named(
                "pattern",
                "Pattern",
                "Jittered mode: where the samples fall inside the pixel. grid: regular; rgss: rotated \
                 grid, every sample in its own row and column (better on near-horizontal and \
                 near-vertical edges); random: uniform; poisson: random but never clumped; halton: \
                 low-discrepancy Halton(2,3).",
                s.pattern,
            ),
            Param::named(
                "filter",
                "Filter",
                "Jittered mode: reconstruction filter. box averages the pixel's own samples; tent, \
                 gaussian and blackman-harris also weigh samples of neighbouring pixels (smoother, \
                 slightly softer).",
                s.filter,
            ),
            Param::named(
                "tonemap_order",
                "Tonemap order",
                "In HDR scenes: before averages radiance and tonemaps the average, as a camera \
                 would (the reference's default: a thin emitter brighter than white widens); after \
                 tonemaps every sample and averages the displayed values (the display-referred \
                 ideal that tonemap-aware resolves such as Karis' weighting approximate).",
                s.tonemap_order,
            ),
        ]
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        let s = &mut self.settings;
        match key {
            "mode" => s.mode = as_named(value).unwrap_or(s.mode),
            "factor" => s.factor = as_i64(value).clamp(1, i64::from(MAX_FACTOR)) as u32,
            "samples" => s.samples = as_i64(value).clamp(1, i64::from(MAX_SAMPLES)) as u32,
            "pattern" => s.pattern = as_named(value).unwrap_or(s.pattern),
            "filter" => s.filter = as_named(value).unwrap_or(s.filter),
            "tonemap_order" => s.tonemap_order = as_named(value).unwrap_or(s.tonemap_order),
            _ => return Err(ParamError::unknown_key(ID, key, &self.params())),
        }
        Ok(())
    }

    fn label(&self) -> String {
        let s = &self.settings;
        if s.mode == Mode::Ordered {
            format!("SSAA {}x", s.samples_per_pixel())
        } else {
            format!("SSAA {}x {}", s.samples_per_pixel(), s.pattern.name())
        }
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        Some(if s.mode == Mode::Ordered {
            format!(
                "ordered grid {k}x{k} ({} samples), box filter",
                s.factor * s.factor,
                k = s.factor
            )
        } else {
            let n = s.pattern.effective_count(s.samples);
            let rounded = if n == s.samples {
                String::new()
            } else {
                format!(" (asked for {})", s.samples)
            };
            format!(
                "jittered {n} samples{rounded}, {} pattern, {} filter",
                s.pattern.name(),
                s.filter.name()
            )
        })
    }
}
