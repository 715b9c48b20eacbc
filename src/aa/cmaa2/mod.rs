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
//! threshold 0.15/0.10/0.07/0.05), extra sharpness, luma or colour edges. Debug views: `edges`
//! and `blends` (which pixels changed, by which kind of blend, and how much).
//!
//! Measurements and what was tried: `docs/techniques/cmaa2.md`.

pub mod settings;

pub use settings::{Cmaa2Settings, EdgeDetection, Quality};

use crate::aa::common::pass;
use crate::aa::common::{debug_texture, encoded_view};
use crate::aa::info::{TechniqueInfo, needs_encoded_views};
use crate::aa::params::Named;
use crate::aa::{DebugView, Technique};
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu};
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
    shaders: &[WGSL],
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

/// The CMAA 2 technique.
pub struct Cmaa2 {
    settings: Cmaa2Settings,
    device: wgpu::Device,
    uniform: wgpu::Buffer,
    edges: Pass<wgpu::ComputePipeline>,
    candidate_args: Pass<wgpu::ComputePipeline>,
    process: Pass<wgpu::ComputePipeline>,
    apply: Pass<wgpu::RenderPipeline>,
    debug_edges: Pass<wgpu::RenderPipeline>,
    debug_blends: Pass<wgpu::RenderPipeline>,
    buffers: Option<Buffers>,
    debug_enabled: bool,
    debug: Option<DebugTargets>,
}

/// The compute pass of `cmaa2.wgsl`'s `entry_point`.
fn compute_pass(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry_point: &str,
    bindings: &'static [Binding],
) -> Pass<wgpu::ComputePipeline> {
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(&format!("cmaa2 {entry_point}")),
        layout: None,
        module,
        entry_point: Some(entry_point),
        compilation_options: Default::default(),
        cache: None,
    });
    Pass {
        layout: pipeline.get_bind_group_layout(0),
        pipeline,
        bindings,
    }
}

impl Cmaa2 {
    /// CMAA 2 with Intel's defaults (high quality).
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, Cmaa2Settings::default())
    }

    /// CMAA 2 with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: Cmaa2Settings) -> Self {
        use Binding::*;
        let device = &gpu.device;
        let module = WGSL.module(device);
        let fullscreen = crate::gpu::fullscreen::Fullscreen::new(device);
        let fullscreen_pass = |entry_point: &str, bindings: &'static [Binding]| {
            let desc = crate::gpu::fullscreen::FragmentDesc {
                label: &format!("cmaa2 {entry_point}"),
                module: &module,
                entry_point,
                targets: &[COLOR_FORMAT_ENCODED_VIEW],
                constants: &[],
                layout: None,
            };
            let pipeline = fullscreen.pipeline(device, &desc);
            Pass {
                layout: pipeline.get_bind_group_layout(0),
                pipeline,
                bindings,
            }
        };
        Self {
            settings,
            uniform: pass::uniform_buffer::<settings::Cmaa2Uniform>(device, "cmaa2 params"),
            edges: compute_pass(
                device,
                &module,
                "cs_edges",
                &[Encoded, Params, Edges, Candidates, Control],
            ),
            candidate_args: compute_pass(
                device,
                &module,
                "cs_candidate_args",
                &[Params, Control, Indirect],
            ),
            process: compute_pass(
                device,
                &module,
                "cs_process",
                &[Linear, Params, Edges, Candidates, Control, Sums],
            ),
            apply: fullscreen_pass("fs_apply", &[Encoded, Params, Sums]),
            debug_edges: fullscreen_pass("fs_debug_edges", &[Encoded, Params, Edges]),
            debug_blends: fullscreen_pass("fs_debug_blends", &[Encoded, Linear, Params, Sums]),
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
        let Some(buffers) = self.buffers.as_ref() else {
            return;
        };
        ctx.gpu.queue.write_buffer(
            &self.uniform,
            0,
            bytemuck::bytes_of(&self.settings.uniform(size)),
        );
        let encoded = encoded_view(input.color_1x());
        let linear = input.color_1x().create_view(&Default::default());
        let views = (&encoded, &linear);
        let group = self.bind_group(&self.edges, views, buffers);
        ctx.compute_pass("edges", |pass| {
            pass.set_pipeline(&self.edges.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(size.0.div_ceil(EDGE_GROUP), size.1.div_ceil(EDGE_GROUP), 1);
        });
        let group = self.bind_group(&self.candidate_args, views, buffers);
        ctx.compute_pass("candidate args", |pass| {
            pass.set_pipeline(&self.candidate_args.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups(1, 1, 1);
        });
        let group = self.bind_group(&self.process, views, buffers);
        ctx.compute_pass("process candidates", |pass| {
            pass.set_pipeline(&self.process.pipeline);
            pass.set_bind_group(0, &group, &[]);
            pass.dispatch_workgroups_indirect(&buffers.indirect, 0);
        });
        if let (true, Some(debug)) = (self.debug_enabled, &self.debug) {
            for (name, pass, target) in [
                ("debug edges", &self.debug_edges, &debug.edges),
                ("debug blends", &self.debug_blends, &debug.blends),
            ] {
                let group = self.bind_group(pass, views, buffers);
                ctx.fullscreen_pass(name, &encoded_view(target), &pass.pipeline, &group);
            }
        }
        let group = self.bind_group(&self.apply, views, buffers);
        ctx.fullscreen_pass("apply", &encoded_view(output), &self.apply.pipeline, &group);
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
        items
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
