//! CMAA 2, Conservative Morphological Anti-Aliasing 2.0 by Filip Strugar and Adam T. Lake
//! (Intel, 2018): a compute-shader post-process that blends only clear geometric edges, so that
//! texture and text detail is left nearly untouched. This is aa-lab's own port of the
//! technique's ideas and parameters (`cmaa2.wgsl`), not Intel's code.
//!
//! Passes over the shared one-sample render, all timed by the frame graph:
//! 1. `edges` (compute, one thread per pixel): the four edges of every pixel on sRGB-encoded
//!    luma (or colour), each kept only if its contrast exceeds the preset's threshold after
//!    local contrast adaptation (a tenth of the strongest edge touching its ends is
//!    subtracted); pixels where two edges meet in a corner are appended to the shape
//!    candidates;
//! 2. `candidate args` and `process candidates` (indirect dispatch sized by the candidate
//!    counter): each candidate blends itself with the neighbours across its edges (the simple
//!    shape, damped where many edges crowd, e.g. in text), then looks for a Z shape along a
//!    horizontal or vertical edge through it, traces the two edge runs of the step (the
//!    longer run cut at 1.3 times the shorter, for a symmetric ramp) and writes a linear blend
//!    ramp along them; runs shorter than five pixels (after the shape's quality penalty) are
//!    left alone. Blends are in linear light. Intel keeps a per-pixel linked list of blended
//!    colours; here every blend is added to its pixel's fixed-point sums with integer atomics
//!    (so the result does not depend on thread order: frames are reproducible);
//! 3. `apply` (fullscreen): a pixel with blends gets their weighted average (a Z-ramp blend
//!    counts three times a corner blend, as Intel's 1.5 to 0.5), encoded to sRGB, and its sums
//!    are cleared for the next frame; every other pixel keeps its exact bytes. Intel applies
//!    with an indirect dispatch over a list of the blended pixels into a storage view of the
//!    output; here the output is sRGB, which cannot be a storage texture, and one fullscreen
//!    pass through its encoded view is cheaper than drawing the blended pixels one by one
//!    wherever most pixels get a blend.
//!
//! Settings ([`settings`]): Intel's quality presets `low`/`medium`/`high`/`ultra` (edge
//! threshold 0.15/0.10/0.07/0.05) and `texture-safe` (high with extra sharpness), extra
//! sharpness, luma or colour edges. Debug views: `edges`
//! and `blends` (which pixels changed, by which kind of blend, and how much).
//!
//! Before the tonemapper of an HDR frame (`tonemap_order`, after by default, as engines run
//! it) the edge pass reads the perceptual copy of the radiance (Karis-compressed and
//! sRGB-encoded, `aa::common::perceptual`, so the thresholds keep their meaning), the blends
//! mix radiance, a pixel's blends are averaged Karis-weighted (`RADIANCE` in `cmaa2.wgsl`) and
//! the apply pass writes radiance; that set of pipelines is built on the first such frame.
//!
//! Measurements and what was tried: `docs/techniques/cmaa2.md`.

pub mod settings;

pub use settings::{Cmaa2Settings, EdgeDetection, Preset, Quality};

use crate::aa::common::pass;
use crate::aa::common::perceptual::{PERCEPTUAL_WGSL, PerceptualCopy};
use crate::aa::common::{
    RADIANCE_WGSL, debug_texture, encoded_or_radiance_view, encoded_view, holds_radiance,
};
use crate::aa::info::{TechniqueInfo, needs_encoded_views};
use crate::aa::params::Named;
use crate::aa::{DebugView, Technique};
use crate::gpu::fullscreen::{FragmentDesc, Fullscreen};
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu, HDR_FORMAT};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Stable id, as on the command line.
pub const ID: &str = "cmaa2";

/// The edge, candidate, apply and debug passes.
const WGSL: Shader = crate::wgsl!("src/aa/cmaa2/cmaa2.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "CMAA 2",
    summary: "Conservative Morphological Antialiasing 2.0 (Strugar and Lake, Intel, 2018): \
         compute passes find luma edges with local contrast adaptation, collect the pixels \
         where edges meet in corners, recognise Z-shaped steps and blend a ramp along the \
         two edge runs, and apply only the blended pixels. Deliberately conservative: it \
         leaves texture and text detail nearly untouched and costs about what FXAA does, \
         but it smooths less than SMAA (short steps and sub-pixel detail stay aliased) \
         and, like every post process, cannot recover geometry the single sample missed.",
    availability: needs_encoded_views,
    create: |gpu| Box::new(Cmaa2::new(gpu)),
    shaders: &[WGSL, PERCEPTUAL_WGSL, RADIANCE_WGSL],
};

/// Threads per workgroup side of the edge pass (`cs_edges`).
const EDGE_GROUP: u32 = 8;

/// The bindings of `cmaa2.wgsl`, by number.
#[derive(Clone, Copy)]
enum Binding {
    Encoded = 0,
    Linear = 1,
    Params = 2,
    Edges = 3,
    Candidates = 4,
    Control = 5,
    Sums = 6,
    Indirect = 7,
}

const EDGES: &str = "cmaa2 edges";
const CANDIDATES: &str = "cmaa2 shape candidates";
const CONTROL: &str = "cmaa2 counters";
const SUMS: &str = "cmaa2 blend sums";
const INDIRECT: &str = "cmaa2 indirect args";

/// The working buffers of one image size: packed edges (4 bytes a pixel), the candidate list (4
/// bytes a pixel, never full), the blend sums (16 bytes a pixel), the counters and the
/// indirect arguments.
struct Buffers {
    size: (u32, u32),
    edges: wgpu::Buffer,
    candidates: wgpu::Buffer,
    control: wgpu::Buffer,
    sums: wgpu::Buffer,
    indirect: wgpu::Buffer,
}

impl Buffers {
    fn new(device: &wgpu::Device, size: (u32, u32)) -> Self {
        let pixels = u64::from(size.0) * u64::from(size.1);
        let storage = |label: &str, bytes: u64, extra: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: bytes.max(16),
                usage: wgpu::BufferUsages::STORAGE | extra,
                mapped_at_creation: false,
            })
        };
        let none = wgpu::BufferUsages::empty();
        Self {
            size,
            edges: storage(EDGES, 4 * pixels, none),
            candidates: storage(CANDIDATES, 4 * pixels, none),
            control: storage(CONTROL, 16, none),
            sums: storage(SUMS, 16 * pixels, none),
            indirect: storage(INDIRECT, 16, wgpu::BufferUsages::INDIRECT),
        }
    }

    /// Every buffer with its label.
    fn all(&self) -> [(&'static str, &wgpu::Buffer); 5] {
        [
            (EDGES, &self.edges),
            (CANDIDATES, &self.candidates),
            (CONTROL, &self.control),
            (SUMS, &self.sums),
            (INDIRECT, &self.indirect),
        ]
    }
}

/// The debug images.
struct DebugTargets {
    edges: wgpu::Texture,
    blends: wgpu::Texture,
}

/// A pipeline with its bind group layout (derived from the shader) and the bindings its entry
/// points use.
struct Pass<P> {
    pipeline: P,
    layout: wgpu::BindGroupLayout,
    bindings: &'static [Binding],
}

/// The pipelines of every pass, for display values or for radiance (`RADIANCE`).
struct Passes {
    edges: Pass<wgpu::ComputePipeline>,
    candidate_args: Pass<wgpu::ComputePipeline>,
    process: Pass<wgpu::ComputePipeline>,
    apply: Pass<wgpu::RenderPipeline>,
    debug_edges: Pass<wgpu::RenderPipeline>,
    debug_blends: Pass<wgpu::RenderPipeline>,
}

impl Passes {
    /// Builds every pass of `module`; on `radiance` the apply pass writes half floats.
    fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        fullscreen: &Fullscreen,
        radiance: bool,
    ) -> Self {
        use Binding::*;
        let constants = [("RADIANCE", f64::from(u8::from(radiance)))];
        let compute_pass = |entry_point: &str, bindings: &'static [Binding]| {
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(&format!("cmaa2 {entry_point}")),
                layout: None,
                module,
                entry_point: Some(entry_point),
                compilation_options: wgpu::PipelineCompilationOptions {
                    constants: &constants,
                    ..Default::default()
                },
                cache: None,
            });
            Pass {
                layout: pipeline.get_bind_group_layout(0),
                pipeline,
                bindings,
            }
        };
        let fullscreen_pass = |entry_point: &str, format, bindings: &'static [Binding]| {
            let desc = FragmentDesc {
                label: &format!("cmaa2 {entry_point}"),
                module,
                entry_point,
                targets: &[format],
                constants: &constants,
                layout: None,
            };
            let pipeline = fullscreen.pipeline(device, &desc);
            Pass {
                layout: pipeline.get_bind_group_layout(0),
                pipeline,
                bindings,
            }
        };
        let apply_format = if radiance {
            HDR_FORMAT
        } else {
            COLOR_FORMAT_ENCODED_VIEW
        };
        Self {
            edges: compute_pass("cs_edges", &[Encoded, Params, Edges, Candidates, Control]),
            candidate_args: compute_pass("cs_candidate_args", &[Params, Control, Indirect]),
            process: compute_pass(
                "cs_process",
                &[Linear, Params, Edges, Candidates, Control, Sums],
            ),
            apply: fullscreen_pass("fs_apply", apply_format, &[Encoded, Linear, Params, Sums]),
            debug_edges: fullscreen_pass(
                "fs_debug_edges",
                COLOR_FORMAT_ENCODED_VIEW,
                &[Encoded, Params, Edges],
            ),
            debug_blends: fullscreen_pass(
                "fs_debug_blends",
                COLOR_FORMAT_ENCODED_VIEW,
                &[Encoded, Linear, Params, Sums],
            ),
        }
    }
}

/// The CMAA 2 technique.
pub struct Cmaa2 {
    settings: Cmaa2Settings,
    device: wgpu::Device,
    module: wgpu::ShaderModule,
    fullscreen: Fullscreen,
    uniform: wgpu::Buffer,
    /// The passes on display values.
    passes: Passes,
    /// The passes on radiance, built on the first HDR frame before the tonemapper.
    radiance_passes: Option<Passes>,
    perceptual: PerceptualCopy,
    buffers: Option<Buffers>,
    debug_enabled: bool,
    debug: Option<DebugTargets>,
}

impl Cmaa2 {
    /// CMAA 2 with Intel's defaults (high quality).
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, Cmaa2Settings::default())
    }

    /// CMAA 2 with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: Cmaa2Settings) -> Self {
        let device = &gpu.device;
        let module = WGSL.module(device);
        let fullscreen = Fullscreen::new(device);
        Self {
            settings,
            uniform: pass::uniform_buffer::<settings::Cmaa2Uniform>(device, "cmaa2 params"),
            passes: Passes::new(device, &module, &fullscreen, false),
            radiance_passes: None,
            perceptual: PerceptualCopy::default(),
            module,
            fullscreen,
            device: device.clone(),
            buffers: None,
            debug_enabled: false,
            debug: None,
        }
    }

    /// Current settings.
    pub fn settings(&self) -> Cmaa2Settings {
        self.settings
    }

    /// The bind group of a pass over this frame's input views (encoded, linear).
    fn bind_group<P>(
        &self,
        pass: &Pass<P>,
        input: (&wgpu::TextureView, &wgpu::TextureView),
        buffers: &Buffers,
    ) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = pass
            .bindings
            .iter()
            .map(|&binding| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: match binding {
                    Binding::Encoded => wgpu::BindingResource::TextureView(input.0),
                    Binding::Linear => wgpu::BindingResource::TextureView(input.1),
                    Binding::Params => self.uniform.as_entire_binding(),
                    Binding::Edges => buffers.edges.as_entire_binding(),
                    Binding::Candidates => buffers.candidates.as_entire_binding(),
                    Binding::Control => buffers.control.as_entire_binding(),
                    Binding::Sums => buffers.sums.as_entire_binding(),
                    Binding::Indirect => buffers.indirect.as_entire_binding(),
                },
            })
            .collect();
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(ID),
            layout: &pass.layout,
            entries: &entries,
        })
    }
}

impl Technique for Cmaa2 {
    crate::aa::common::shared_1x_post_process!(INFO);

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        let size = input.desc.size;
        if self.buffers.as_ref().is_none_or(|b| b.size != size) {
            self.buffers = Some(Buffers::new(&self.device, size));
        }
        if self.debug_enabled
            && self
                .debug
                .as_ref()
                .is_none_or(|d| (d.edges.width(), d.edges.height()) != size)
        {
            self.debug = Some(DebugTargets {
                edges: debug_texture(&self.device, "cmaa2 edges view", size),
                blends: debug_texture(&self.device, "cmaa2 blends view", size),
            });
        }
        ctx.gpu.queue.write_buffer(
            &self.uniform,
            0,
            bytemuck::bytes_of(&self.settings.uniform(size)),
        );
        let color = input.color_1x();
        let radiance = holds_radiance(color);
        if radiance && self.radiance_passes.is_none() {
            let passes = Passes::new(&self.device, &self.module, &self.fullscreen, true);
            self.radiance_passes = Some(passes);
        }
        let encoded = encoded_view(self.perceptual.source(ctx, color, ""));
        let linear = color.create_view(&Default::default());
        let views = (&encoded, &linear);
        let (Some(buffers), Some(passes)) = (
            self.buffers.as_ref(),
            if radiance {
                self.radiance_passes.as_ref()
            } else {
                Some(&self.passes)
            },
        ) else {
            return;
        };
        let group = self.bind_group(&passes.edges, views, buffers);
        ctx.compute_pass("edges", |pass| {
            pass.set_pipeline(&passes.edges.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(EDGE_GROUP), size.1.div_ceil(EDGE_GROUP), 1);
        });
        let group = self.bind_group(&passes.candidate_args, views, buffers);
        ctx.compute_pass("candidate args", |pass| {
            pass.set_pipeline(&passes.candidate_args.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        });
        let group = self.bind_group(&passes.process, views, buffers);
        ctx.compute_pass("process candidates", |pass| {
            pass.set_pipeline(&passes.process.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups_indirect(&buffers.indirect, 0);
        });
        if let (true, Some(debug)) = (self.debug_enabled, &self.debug) {
            for (name, pass, target) in [
                ("debug edges", &passes.debug_edges, &debug.edges),
                ("debug blends", &passes.debug_blends, &debug.blends),
            ] {
                let group = self.bind_group(pass, views, buffers);
                ctx.fullscreen_pass(name, &encoded_view(target), &pass.pipeline, &group);
            }
        }
        let group = self.bind_group(&passes.apply, views, buffers);
        let target = encoded_or_radiance_view(output);
        ctx.fullscreen_pass("apply", &target, &passes.apply.pipeline, &group);
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("cmaa2 params", &self.uniform)];
        if let Some(b) = &self.buffers {
            items.extend(
                b.all()
                    .into_iter()
                    .map(|(label, buffer)| MemoryItem::buffer(label, buffer)),
            );
        }
        if let Some(debug) = &self.debug {
            items.push(MemoryItem::texture("cmaa2 edges view", &debug.edges));
            items.push(MemoryItem::texture("cmaa2 blends view", &debug.blends));
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
        match (&self.debug, self.debug_enabled) {
            (Some(debug), true) => vec![
                DebugView {
                    name: "edges",
                    description: "CMAA 2's edges over the dimmed luma: red pixels have an edge \
                         to the left or right, green ones above or below, yellow ones both (a \
                         corner: a shape candidate). Edges that a stronger neighbouring edge \
                         dominates were dropped by local contrast adaptation.",
                    texture: &debug.edges,
                },
                DebugView {
                    name: "blends",
                    description: "The pixels CMAA 2 changed, over the dimmed luma: blue ones lie \
                         on the blend ramp of a Z-shaped step (a long edge), orange ones only got \
                         a corner blend; the brighter, the more the pixel moved. Every other \
                         pixel is left exactly as rendered.",
                    texture: &debug.blends,
                },
            ],
            _ => Vec::new(),
        }
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        Some(format!(
            "{} preset (edge threshold {}), {} edges on sRGB-encoded values{}, blends in linear \
             light; compute passes, candidates processed by indirect dispatch",
            s.quality.name(),
            s.quality.edge_threshold(),
            s.edge_detection.name(),
            if s.extra_sharpness {
                ", extra sharpness"
            } else {
                ""
            }
        ))
    }
}
