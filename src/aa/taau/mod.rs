//! The temporal upscaler (`taau`): the descendant of this project's TAA that reconstructs at
//! the output resolution from jittered renders at a lower (or the same) resolution. At scale 1
//! (plain `taau`) it is a native-resolution temporal AA, the engines' "native AA" mode; at a
//! render scale (`taau@quality`, `taau@0.5`) `aa::scaled` hands it the render-size frame and
//! the output-size target, and no spatial upscale follows
//! ([`Technique::reconstructs_at_output`]).
//!
//! The ideas are those AMD documents for FidelityFX Super Resolution 2 (Thomas Arcila et al.),
//! written anew here (no AMD shader text), on top of the TAA of Karis (2014) and Salvi (2016):
//! - **Jitter**: Halton(2,3) with 8 phases per output pixel, i.e. 8 x ratio^2 phases in all
//!   (FSR 2's count), in render pixels; textures get log2(render / output) from the render
//!   scale plus this technique's own bias (-1 by default, FSR 2's "one more level down").
//! - **Accumulation at the output resolution**: every new render sample joins the history of
//!   the output pixels near it with a weight from its distance to their centres (a Gaussian
//!   with a one-pixel spread, or Lanczos-2; at native scale, in motion, the kernel's
//!   estimate of the pixel takes its own sample's place in full only where the 3x3 spans more
//!   than one surface, and half of it on one surface, so textures stay sharp and edges are
//!   averaged); the history keeps how many samples it holds (its confidence, capped: lower
//!   wherever the pixel moves, since every frame's read between texels blurs the history a
//!   little more, and below native each frame adds fewer samples, so a capped history
//!   outlives more reads, and falling off exponentially with the speed,
//!   `speed_falloff`; at native scale the parallax, `parallax_falloff`, faster where the
//!   farthest surface of the 3x3 is broad, `silhouette_falloff`, scales the history's share
//!   against one new sample, as it scales TAA's, so that a long history cannot outlast it),
//!   so a pixel that got no sample this frame keeps
//!   its history and one that just lost its history takes the new samples at full weight.
//!   Where the two together hold too little (first frame, disocclusion), a wide Gaussian of
//!   the render samples fills in: a spatial upscale that the next samples replace.
//! - **Motion of the nearest surface** (largest reverse-Z depth of the 3x3 render pixels).
//! - **Disocclusion from depth**: the history keeps the nearest depth it was written with (a
//!   second output-size texture); where the reprojected place held a surface at another depth
//!   the history is dropped.
//! - **Thin features** are kept by TAA's velocity trust instead of FSR 2's locks: the history
//!   keeps the speed it was written with, and rectification eases off where the pixel moves at
//!   that speed (a missed thin line moves with its surroundings, a ghost does not).
//! - **Reactive mask**: derived from motion, surfaces whose motion the camera does not explain
//!   (objects moving on their own) keep less history (`reactive`, off by default); and, as
//!   FSR 2's reactive mask for transparency, the renderer's mask of how much alpha-blended
//!   surfaces cover each render pixel (`reactive_mask`, off by default: the render then writes
//!   no mask and the pipeline reads none), which keeps that much less history and drops the
//!   velocity trust there (blended surfaces carry the motion of what is behind them).
//!
//! The history is dropped when the frame asks for it, when the camera does not continue the
//! history's, when the output or render size changes and when a setting changes (as TAA's).
//! Debug views: `motion`, `disocclusion`, `confidence`, `weight` and `reactive` (see
//! `debug.rs`). Measurements: `docs/upscaling.md`.

mod debug;
pub mod settings;

pub use settings::{Kernel, PhasesPerPixel, Preset, TaauSettings};

use glam::Mat4;

use crate::aa::common::pass::{self, Binding};
use crate::aa::common::temporal::{
    HistoryReset, PingPong, ResolvePass, cleared_black, falloff_rate, jitter_offset,
};
use crate::aa::common::{RADIANCE_WGSL, TEMPORAL_WGSL, holds_radiance, output_format};
use crate::aa::info::{TechniqueInfo, needs_history_stores};
use crate::aa::params::Named;
use crate::aa::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::Gpu;
use crate::gpu::shader::Shader;
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;
use debug::{STATE_FORMAT, TaauDebug};

/// Stable id, as on the command line.
pub const ID: &str = "taau";

/// The resolve (samples, reprojection, disocclusion, rectification, accumulation).
const WGSL: Shader = crate::wgsl!("src/aa/taau/taau.wgsl", prelude = TEMPORAL_WGSL);
/// The debug views.
const DEBUG_WGSL: Shader = crate::wgsl!("src/aa/taau/taau_debug.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "TAAU",
    summary: "Temporal upscaler (after AMD FSR 2's design): renders one jittered sample per \
         render pixel, at the output size or below it (taau@quality, taau@0.5), and \
         accumulates the samples into an output-resolution history, each weighted by its \
         distance to the output pixel's centre, with disocclusion detected from depth and \
         thin features kept by their motion. At scale 1 it is a native temporal AA; below it \
         it reconstructs detail a spatial upscaler cannot, at the price of TAA's: motion \
         vectors, softness under motion and possible ghosting.",
    availability: needs_history_stores,
    create: |gpu| Box::new(Taau::new(gpu)),
    shaders: &[WGSL, DEBUG_WGSL, TEMPORAL_WGSL, RADIANCE_WGSL],
};

/// Format of the accumulated colour (alpha: samples accumulated).
const HISTORY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// Format of the depth and speed kept with the history (red and green; blue and alpha
/// unused): half floats, since the disocclusion test compares depths relative to each other,
/// to a tolerance far above their 1/2048 precision, and a filterable format lets the resolve
/// gather the four texels around the reprojected place in one fetch. Four channels because
/// two-channel half floats are no storage format in WebGPU.
const AUX_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The confidence (in samples) below which the spatial estimate fills in.
const FILL_FLOOR: f32 = 1.0;

/// Everything a resolve pipeline is specialised on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PipelineKey {
    constants: [(&'static str, u64); 7],
    debug: bool,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TaauUniform {
    output: [f32; 4],
    render: [f32; 4],
    jitter: [f32; 4],
    accumulate: [f32; 4],
    guard: [f32; 4],
    falloff: [f32; 4],
    reproject: [[f32; 4]; 4],
}

/// The upscale ratio (output / render, the mean of both axes) of a frame.
fn ratio(frame: &FrameInfo) -> f32 {
    let (render, output) = (frame.size(), frame.output_size());
    0.5 * (output.0 as f32 / render.0.max(1) as f32 + output.1 as f32 / render.1.max(1) as f32)
}

/// The history: colour with confidence, and depth with speed, both at the output size.
struct History {
    colour: PingPong,
    aux: PingPong,
    render_size: (u32, u32),
    /// Whether it holds compressed radiance (the technique runs before the tonemapper).
    radiance: bool,
}

/// The temporal upscaler.
pub struct Taau {
    settings: TaauSettings,
    resolve: ResolvePass<PipelineKey>,
    history: Option<History>,
    reset: HistoryReset,
    debug_enabled: bool,
    debug: Option<TaauDebug>,
}

impl Taau {
    /// The temporal upscaler with default settings.
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, TaauSettings::default())
    }

    /// The temporal upscaler with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: TaauSettings) -> Self {
        let bindings = [
            (0, Binding::Texture),
            (1, Binding::Depth),
            (2, Binding::Texture),
            (3, Binding::Texture),
            (4, Binding::Texture),
            (5, Binding::Sampler),
            (6, Binding::Uniform),
            (7, Binding::Texture),
            (8, Binding::WriteOnlyTexture(HISTORY_FORMAT)),
            (9, Binding::WriteOnlyTexture(AUX_FORMAT)),
        ];
        Self {
            settings,
            resolve: ResolvePass::new::<TaauUniform>(gpu, "taau resolve", &WGSL, &bindings),
            history: None,
            reset: HistoryReset::default(),
            debug_enabled: false,
            debug: None,
        }
    }

    /// Current settings.
    pub fn settings(&self) -> TaauSettings {
        self.settings
    }

    /// Replaces the settings; the next frame starts a new history.
    pub fn set_settings(&mut self, settings: TaauSettings) {
        self.settings = settings;
        self.reset.invalidate();
    }

    /// This frame's jitter in render pixels.
    fn jitter(&self, frame: &FrameInfo) -> glam::Vec2 {
        jitter_offset(
            frame.camera.frame,
            self.settings.phases.phases(ratio(frame)),
        )
    }

    fn resolve_pipeline(
        &mut self,
        ctx: &PassContext<'_>,
        debug: bool,
        radiance: bool,
    ) -> wgpu::RenderPipeline {
        let native = ctx.frame.size() == ctx.frame.output_size();
        let constants = self.settings.constants(radiance, native);
        let output = output_format(radiance);
        let key = PipelineKey {
            constants: constants.map(|(name, value)| (name, value.to_bits())),
            debug,
        };
        let (entry_point, targets): (&str, &[wgpu::TextureFormat]) = if debug {
            ("fs_resolve_debug", &[output, STATE_FORMAT])
        } else {
            ("fs_resolve", &[output])
        };
        self.resolve
            .pipeline(ctx, key, entry_point, targets, &constants)
    }

    /// The uniform block of a frame.
    fn uniform(&self, frame: &FrameInfo, reset: bool) -> TaauUniform {
        let s = &self.settings;
        let (render, output) = (frame.size(), frame.output_size());
        let texel = |(w, h): (u32, u32)| [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32];
        let jitter = self.jitter(frame);
        let camera = &frame.camera;
        let reproject = camera.prev_view_proj() * camera.view_proj().inverse();
        TaauUniform {
            output: texel(output),
            render: texel(render),
            jitter: [
                jitter.x,
                jitter.y,
                f32::from(u8::from(reset)),
                s.kernel_width,
            ],
            accumulate: [
                s.max_samples,
                s.motion_samples,
                s.gamma,
                s.velocity_tolerance,
            ],
            guard: [s.depth_tolerance, s.reactive, FILL_FLOOR, s.reactive_mask],
            falloff: [
                falloff_rate(s.speed_falloff),
                falloff_rate(s.parallax_falloff),
                falloff_rate(s.silhouette_falloff),
                0.0,
            ],
            reproject: Mat4::to_cols_array_2d(&reproject),
        }
    }

    /// Makes sure the history and the debug views fit this frame; whether the history must
    /// start again.
    /// Makes the history and debug targets fit; `radiance`: the history holds compressed
    /// radiance (before the tonemapper), and a flip starts it over.
    fn prepare(&mut self, ctx: &PassContext<'_>, render_size: (u32, u32), radiance: bool) -> bool {
        let output_size = ctx.frame.output_size();
        let fits = self.history.as_ref().is_some_and(|h| {
            h.colour.size() == output_size && h.render_size == render_size && h.radiance == radiance
        });
        if !fits {
            let device = &self.resolve.device;
            self.history = Some(History {
                colour: PingPong::new(device, "taau history", output_size, HISTORY_FORMAT),
                aux: PingPong::new(device, "taau depth", output_size, AUX_FORMAT),
                render_size,
                radiance,
            });
        }
        let device = &self.resolve.device;
        if self.debug_enabled && self.debug.as_ref().is_none_or(|d| d.size() != output_size) {
            self.debug = Some(TaauDebug::new(ctx, device, &DEBUG_WGSL, output_size));
        }
        self.reset.restarts(ctx.frame) || self.history.as_ref().is_none_or(|h| !h.colour.valid)
    }
}

impl Technique for Taau {
    fn id(&self) -> &'static str {
        ID
    }

    fn label(&self) -> String {
        INFO.name.to_owned()
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn scene_input(&self, frame: &FrameInfo) -> Option<SceneInput> {
        let input = SceneInput::jittered(self.jitter(frame), self.settings.mip_bias);
        Some(input.with_reactive_mask(self.settings.reactive_mask > 0.0))
    }

    fn temporal(&self) -> bool {
        true
    }

    fn reconstructs_at_output(&self) -> bool {
        true
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        let Some(motion) = &input.motion else {
            // Jittered inputs always carry motion vectors.
            return;
        };
        let radiance = holds_radiance(output);
        let reset = self.prepare(ctx, input.desc.size, radiance);
        let debug = self.debug_enabled;
        let pipeline = self.resolve_pipeline(ctx, debug, radiance);
        self.resolve
            .write_uniform(ctx, &self.uniform(ctx.frame, reset));
        let Some(history) = &mut self.history else {
            return;
        };
        // Without the mask the pipeline reads nothing at binding 7: the motion fills it.
        let views = [
            &input.color,
            &input.depth,
            motion,
            history.colour.read(),
            history.aux.read(),
            input.reactive.as_ref().unwrap_or(motion),
            history.colour.write(),
            history.aux.write(),
        ]
        .map(|t| t.create_view(&Default::default()));
        let mut resources: Vec<(u32, wgpu::BindingResource<'_>)> = views
            .iter()
            .zip([0, 1, 2, 3, 4, 7, 8, 9])
            .map(|(view, binding)| (binding, wgpu::BindingResource::TextureView(view)))
            .collect();
        let resolve = &self.resolve;
        resources.push((5, wgpu::BindingResource::Sampler(&resolve.sampler)));
        resources.push((6, resolve.uniform.as_entire_binding()));
        let bind_group =
            pass::bind_group(&resolve.device, "taau resolve", &resolve.layout, &resources);
        let output_view = output.create_view(&Default::default());
        let state_view = self
            .debug
            .as_ref()
            .filter(|_| debug)
            .map(|d| d.state.create_view(&Default::default()));
        let attachments: Vec<_> = std::iter::once(&output_view)
            .chain(&state_view)
            .map(cleared_black)
            .collect();
        ctx.render_pass("resolve", &attachments, None, |pass| {
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        });
        history.colour.swap();
        history.aux.swap();
        if let Some(views) = self.debug.as_ref().filter(|_| debug) {
            views.encode(ctx, &resolve.device, motion, self.settings.max_samples);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("taau params", &self.resolve.uniform)];
        if let Some(h) = &self.history {
            for (pair, label) in [(&h.colour, "taau history"), (&h.aux, "taau depth")] {
                items.push(MemoryItem::texture(format!("{label} a"), &pair.textures[0]));
                items.push(MemoryItem::texture(format!("{label} b"), &pair.textures[1]));
            }
        }
        if let Some(d) = &self.debug {
            items.extend(d.memory());
        }
        items
    }

    crate::aa::common::tunable_settings!(settings, then set_settings);

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        match (&self.debug, self.debug_enabled) {
            (Some(d), true) => d.views(),
            _ => Vec::new(),
        }
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        Some(format!(
            "{} jitter phases per output pixel, {} kernel of width {}, {} history, {} \
             rectification, at most {} samples ({} in motion, falling off over {} px/frame of speed \
             and, at native scale, {} of parallax, {} at silhouettes)",
            s.phases.name(),
            s.kernel.name(),
            s.kernel_width,
            s.history_filter.name(),
            s.rectify.name(),
            s.max_samples,
            s.motion_samples,
            s.speed_falloff,
            s.parallax_falloff,
            s.silhouette_falloff
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn phases_grow_with_the_square_of_the_upscale_ratio() {
        assert_eq!(PhasesPerPixel::Eight.phases(1.0), 8);
        assert_eq!(PhasesPerPixel::Eight.phases(1.5), 18);
        assert_eq!(PhasesPerPixel::Eight.phases(2.0), 32);
        assert_eq!(PhasesPerPixel::Sixteen.phases(3.0), 144);
        assert_eq!(PhasesPerPixel::Eight.phases(0.5), 8, "never below the base");
    }

    #[test]
    fn presets_round_trip_and_differ() {
        for preset in Preset::ALL {
            assert_eq!(Preset::from_name(preset.name()), Some(*preset));
            if *preset != Preset::Default {
                assert_ne!(TaauSettings::preset(*preset), TaauSettings::default());
            }
        }
    }
}
