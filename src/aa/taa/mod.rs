//! TAA (temporal antialiasing) after Brian Karis, "High Quality Temporal Supersampling"
//! (SIGGRAPH 2014) and Marco Salvi, "An Excursion in Temporal Supersampling" (GDC 2016), with
//! the bilinear-optimised Catmull-Rom history filter described by Jorge Jimenez and Michal
//! Drobot.
//!
//! Each frame reads the shared jittered render (`SceneInput::jittered`): the projection is
//! shifted by the next offset of a Halton(2,3) sequence of 8 or 16 samples, so over a cycle
//! every pixel is sampled at that many places, and textures get a negative mip bias (-1 by
//! default, as AMD's FSR 2 integration guide recommends at native scale: sharper mip levels,
//! whose aliasing the history averages; -1.5, half the log2 of the 8 samples, scored better on
//! a still camera but worse in FLIP under motion, where the history holds fewer samples). The
//! resolve (`taa.wgsl` in this folder, one fullscreen pass whose one render target is the
//! output) reprojects the history with the renderer's motion vectors
//! (camera and object motion, without jitter; taken from the nearest surface among the pixel
//! and its neighbours), rectifies it against the current neighbourhood's colours (clamp, YCoCg
//! clip or variance clip) and blends it with the current sample, writing the output and
//! storing the next history (ping-pong Rgba16Float storage textures, linear colour). The
//! default makes 11 texture reads per pixel: the colour neighbourhood is shared within each
//! 2x2 quad of fragments through the fine derivatives, depths come in two gathers, and the
//! shader keeps no function-local arrays, which a GPU's compiler may keep in memory (see
//! `gpu/shader.rs`).
//!
//! Under motion the history is resampled between pixels every frame, which softens it, so the
//! current frame's share rises with how much that read blurs it (`resample_feedback`; none on
//! whole-pixel motion), and the current frame then contributes (`current_filter` `gaussian`,
//! the default) its colour neighbourhood weighed by a Gaussian with the variance of the pixel's
//! one-pixel box: an estimate of the pixel's area average, as the 64-sample reference computes
//! it, from reads the rectification makes anyway. A sharp history converges to that average
//! on its own, so the Gaussian is mixed in only as far as the history is blurred.
//!
//! The history's share also falls off exponentially with the parallax around the pixel (the
//! difference between the motions of the nearest and the farthest surface of the depth search,
//! one more motion read: a pixel whose surfaces part cannot be carried by one motion vector, so
//! its history holds colours that belong elsewhere) and with the speed (`parallax_falloff` and
//! `speed_falloff`, 16 pixels per frame each; `aa::common::temporal`). Under the orbit TAA's gap
//! to MSAA 4x on hairball grew with the size, as the motion in pixels does; the falloff closes
//! part of it at 1280x720 and more at 1920x1080, and lifts atrium at every size, for a small
//! loss on hairball at 640x360 (`docs/techniques/taa.md`). Where the farthest surface of the
//! search is broad (most of the depths searched lie on it: an edge over a wide background),
//! the parallax falloff shortens towards `silhouette_falloff` (2 pixels per frame): such a
//! silhouette is better served by the current frame as soon as its surfaces part, while a
//! tangle of strands over other strands, whose farthest surface is as thin as its nearest,
//! keeps the longer history that its sub-pixel detail needs. One length had to trade the two
//! against each other; the farthest surface's share tells them apart for no extra reads.
//!
//! Thin geometry: a line thinner than a pixel is hit by only some of the jitter positions, and
//! clamping the history to the neighbourhood of a frame that missed it would cut the line out
//! again and again. Colour cannot tell such a line from a ghost, but motion can: a ghost
//! appears where an occluder slides over a background of another speed, while a missed line
//! moves with the surfaces around it. So the history keeps the speed it was written with (its
//! alpha) and rectification eases off as the pixel's speed matches it (`velocity_tolerance`;
//! after the velocity weighting of Jimenez et al.'s SMAA T2x). Karis' 1 / (1 + luminance)
//! weighting is off by default (the `karis` preset turns it on): on display-range colours it
//! makes thin dark lines too dark once they are kept.
//!
//! The history is dropped when the frame asks for it (camera cut, scene change, first frame),
//! when the camera does not continue the previous frame (its previous pose is not the one the
//! history was made with, or frames were skipped), when the size changes and when a setting
//! changes, so frame N of a sequence depends only on frames 0..=N since the last reset; the
//! jitter offset is a function of the frame number, which keeps headless renders reproducible.
//! Structural options (history filter, rectification, luminance weighting, velocity dilation,
//! debug output) are override constants with one cached pipeline each; the weights are
//! uniforms. Debug views: `velocity` (motion vectors), `rejection` (where the history was
//! rectified or dropped) and `jitter` (the sample pattern inside one pixel).
//!
//! Transparency: alpha-blended surfaces (glass, particles) write no motion, so their colour
//! is reprojected with the motion of the opaque surface behind them and smears or ghosts. The
//! `reactive_mask` setting (0, off, by default) ports the idea of AMD FidelityFX FSR 2's
//! reactive mask (FSR 2 documentation, "Reactive mask"; no AMD code): the scene render then
//! writes how much blended surfaces cover each pixel, and where they do the current frame's
//! share rises to at least the setting times that coverage and the velocity trust is dropped
//! by the same measure, so the pixel follows the current frame. Off, the pipeline compiles
//! without the read and the render writes no mask.
//!
//! What each read earns, the costs on lavapipe and on a GPU, and what was tried:
//! `docs/techniques/taa.md`.

mod debug;
pub mod settings;

pub use settings::{
    CurrentFilter, HistoryFilter, JitterSamples, Neighbourhood, Preset, Rectify, TaaSettings,
    VelocityTaps,
};

use glam::Vec2;

use crate::aa::common::pass::Binding;
use crate::aa::common::temporal::{
    HistoryReset, PingPong, ResolvePass, cleared_black, falloff_rate, jitter_offset,
};
use crate::aa::common::{
    RADIANCE_WGSL, TEMPORAL_WGSL, encoded_view, holds_radiance, output_format,
};
use crate::aa::info::{TechniqueInfo, needs_history_stores};
use crate::aa::params::Named;
use crate::aa::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Gpu};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;
use debug::TaaDebug;

/// Stable id, as on the command line.
pub const ID: &str = "taa";

/// The resolve (reprojection, rectification, blend).
const WGSL: Shader = crate::wgsl!("src/aa/taa/taa.wgsl", prelude = TEMPORAL_WGSL);
/// The velocity and jitter debug views.
const DEBUG_WGSL: Shader = crate::wgsl!("src/aa/taa/taa_debug.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "TAA",
    summary: "Temporal antialiasing (after Karis 2014 and Salvi 2016): every frame renders one \
         sample per pixel at a different sub-pixel jitter and blends it into a reprojected \
         history, so a still image converges towards many samples per pixel for the cost of \
         one post pass. It handles edges, textures and specular shimmer alike, but needs \
         motion vectors, blurs slightly under motion, and can ghost or smear where the \
         history cannot be matched (disocclusions, transparency, fast-changing shading).",
    availability: needs_history_stores,
    create: |gpu| Box::new(Taa::new(gpu)),
    shaders: &[WGSL, DEBUG_WGSL, TEMPORAL_WGSL, RADIANCE_WGSL],
};

/// Format of the accumulated history.
pub const HISTORY_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The current frame's filter weights for the 3x3 taps (row by row, padded to three vec4s),
/// normalised over the taps of the colour neighbourhood: the Gaussian of each sample's
/// distance from the pixel centre (a sample sits at its pixel's centre minus `jitter`), or the
/// centre tap alone.
fn current_filter_weights(settings: &TaaSettings, jitter: Vec2) -> [[f32; 4]; 3] {
    let mut weights = [0.0f32; 12];
    if settings.current_filter == CurrentFilter::Sample {
        weights[4] = 1.0;
    } else {
        for (tap, weight) in weights.iter_mut().take(9).enumerate() {
            let offset = Vec2::new((tap % 3) as f32 - 1.0, (tap / 3) as f32 - 1.0);
            let diagonal = offset.x != 0.0 && offset.y != 0.0;
            if settings.neighbourhood == Neighbourhood::Box || !diagonal {
                let d = offset - jitter;
                *weight = (-CurrentFilter::GAUSSIAN_SHARPNESS * d.length_squared()).exp();
            }
        }
        let total: f32 = weights.iter().sum();
        weights.iter_mut().for_each(|w| *w /= total);
    }
    [
        [weights[0], weights[1], weights[2], weights[3]],
        [weights[4], weights[5], weights[6], weights[7]],
        [weights[8], weights[9], weights[10], weights[11]],
    ]
}

/// Everything a resolve pipeline is specialised on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PipelineKey {
    history_filter: HistoryFilter,
    rectify: Rectify,
    luma_weight: bool,
    velocity: VelocityTaps,
    neighbourhood: Neighbourhood,
    reactive_mask: bool,
    debug: bool,
    /// Before the tonemapper of an HDR frame: radiance in and out, luminance-weighted.
    radiance: bool,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct TaaUniform {
    size: [f32; 4],
    blend: [f32; 4],
    trust: [f32; 4],
    falloff: [f32; 4],
    current_filter: [[f32; 4]; 3],
}

/// The TAA technique.
pub struct Taa {
    settings: TaaSettings,
    resolve: ResolvePass<PipelineKey>,
    history: Option<PingPong>,
    /// Whether the history holds radiance (it is dropped when the tonemap order flips).
    history_radiance: bool,
    reset: HistoryReset,
    debug_enabled: bool,
    debug: Option<TaaDebug>,
}

impl Taa {
    /// TAA with default settings.
    pub fn new(gpu: &Gpu) -> Self {
        Self::with_settings(gpu, TaaSettings::default())
    }

    /// TAA with the given settings.
    pub fn with_settings(gpu: &Gpu, settings: TaaSettings) -> Self {
        let bindings = [
            (0, Binding::Texture),
            (1, Binding::Depth),
            (2, Binding::Texture),
            (3, Binding::Texture),
            (4, Binding::Sampler),
            (5, Binding::Uniform),
            (6, Binding::Texture),
            (7, Binding::WriteOnlyTexture(HISTORY_FORMAT)),
        ];
        Self {
            settings,
            resolve: ResolvePass::new::<TaaUniform>(gpu, "taa resolve", &WGSL, &bindings),
            history: None,
            history_radiance: false,
            reset: HistoryReset::default(),
            debug_enabled: false,
            debug: None,
        }
    }

    /// Current settings.
    pub fn settings(&self) -> TaaSettings {
        self.settings
    }

    /// Replaces the settings; the next frame starts a new history.
    pub fn set_settings(&mut self, settings: TaaSettings) {
        self.settings = settings;
        self.reset.invalidate();
    }

    fn resolve_pipeline(
        &mut self,
        ctx: &PassContext<'_>,
        debug: bool,
        radiance: bool,
    ) -> wgpu::RenderPipeline {
        let s = self.settings;
        let output = output_format(radiance);
        let key = PipelineKey {
            history_filter: s.history_filter,
            rectify: s.rectify,
            luma_weight: s.luma_weight,
            velocity: s.velocity,
            neighbourhood: s.neighbourhood,
            reactive_mask: s.reactive_mask > 0.0,
            debug,
            radiance,
        };
        let (entry_point, targets): (&str, &[wgpu::TextureFormat]) = if debug {
            ("fs_resolve_debug", &[output, COLOR_FORMAT_ENCODED_VIEW])
        } else {
            ("fs_resolve", &[output])
        };
        self.resolve
            .pipeline(ctx, key, entry_point, targets, &s.constants(radiance))
    }
}

impl Technique for Taa {
    fn id(&self) -> &'static str {
        ID
    }

    fn label(&self) -> String {
        INFO.name.to_owned()
    }

    fn scene_input(&self, frame: &FrameInfo) -> Option<SceneInput> {
        let input = SceneInput::jittered(
            jitter_offset(frame.camera.frame, self.settings.samples.count()),
            self.settings.mip_bias,
        );
        Some(input.with_reactive_mask(self.settings.reactive_mask > 0.0))
    }

    fn temporal(&self) -> bool {
        true
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        let Some(motion) = &input.motion else {
            // Jittered inputs always carry motion vectors; without them show the frame as is.
            ctx.copy_texture("copy (no motion vectors)", &input.color, output);
            return;
        };
        let size = input.desc.size;
        let radiance = holds_radiance(output);
        if self.history.as_ref().is_none_or(|h| h.size() != size)
            || self.history_radiance != radiance
        {
            self.history_radiance = radiance;
            self.history = Some(PingPong::new(
                &self.resolve.device,
                "taa history",
                size,
                HISTORY_FORMAT,
            ));
        }
        let debug = self.debug_enabled;
        if debug {
            let stale = self.debug.as_ref().is_none_or(|d| d.size() != size);
            if stale {
                self.debug = Some(TaaDebug::new(ctx, &self.resolve.device, &DEBUG_WGSL, size));
            }
        }
        let pipeline = self.resolve_pipeline(ctx, debug, radiance);
        let camera = ctx.frame.camera;
        let reset = self.reset.restarts(ctx.frame);
        let Some(history) = &mut self.history else {
            return;
        };
        let reset = reset || !history.valid;
        let uniform = TaaUniform {
            size: [
                size.0 as f32,
                size.1 as f32,
                1.0 / size.0 as f32,
                1.0 / size.1 as f32,
            ],
            blend: [
                self.settings.current_weight,
                self.settings.gamma,
                f32::from(u8::from(reset)),
                self.settings.motion_weight,
            ],
            trust: [
                self.settings.velocity_tolerance,
                f32::from(u8::from(self.settings.resample_feedback)),
                f32::from(u8::from(self.settings.trust_sharp_only)),
                self.settings.reactive_mask,
            ],
            falloff: [
                falloff_rate(self.settings.parallax_falloff),
                falloff_rate(self.settings.speed_falloff),
                falloff_rate(self.settings.silhouette_falloff),
                0.0,
            ],
            current_filter: current_filter_weights(
                &self.settings,
                jitter_offset(camera.frame, self.settings.samples.count()),
            ),
        };
        self.resolve.write_uniform(ctx, &uniform);
        let resolve = &self.resolve;

        let current_view = input.color.create_view(&Default::default());
        let depth_view = input.depth.create_view(&Default::default());
        let motion_view = motion.create_view(&Default::default());
        let history_view = history.read().create_view(&Default::default());
        let next_view = history.write().create_view(&Default::default());
        // Without the mask the pipeline reads nothing at binding 6: the motion view fills it.
        let reactive_view = input.reactive.as_ref().map_or_else(
            || motion_view.clone(),
            |t| t.create_view(&Default::default()),
        );
        let texture = |binding, view| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::TextureView(view),
        };
        let bind_group = resolve
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("taa resolve"),
                layout: &resolve.layout,
                entries: &[
                    texture(0, &current_view),
                    texture(1, &depth_view),
                    texture(2, &motion_view),
                    texture(3, &history_view),
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&resolve.sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: resolve.uniform.as_entire_binding(),
                    },
                    texture(6, &reactive_view),
                    texture(7, &next_view),
                ],
            });
        let output_view = output.create_view(&Default::default());
        let rejection_view = self
            .debug
            .as_ref()
            .filter(|_| debug)
            .map(|d| encoded_view(&d.rejection));
        let mut attachments = vec![cleared_black(&output_view)];
        if let Some(view) = &rejection_view {
            attachments.push(cleared_black(view));
        }
        ctx.render_pass("resolve", &attachments, None, |pass| {
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.draw(0..3, 0..1);
        });
        history.swap();
        if let Some(views) = self.debug.as_ref().filter(|_| debug) {
            views.encode(ctx, &resolve.device, motion, self.settings.samples.count());
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("taa params", &self.resolve.uniform)];
        if let Some(h) = &self.history {
            items.push(MemoryItem::texture("taa history a", &h.textures[0]));
            items.push(MemoryItem::texture("taa history b", &h.textures[1]));
        }
        if let Some(d) = &self.debug {
            items.push(MemoryItem::texture("taa rejection view", &d.rejection));
            items.push(MemoryItem::texture("taa velocity view", &d.velocity));
            items.push(MemoryItem::texture("taa jitter view", &d.jitter));
            items.push(MemoryItem::buffer("taa debug params", &d.uniform));
        }
        items
    }

    crate::aa::common::tunable_settings!(settings, then set_settings);

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        match (&self.debug, self.debug_enabled) {
            (Some(d), true) => vec![
                DebugView {
                    name: "velocity",
                    description: "Motion vectors TAA reprojects with: hue is the direction (right red, \
                         down yellow-green, left cyan, up violet), brightness the speed (half \
                         brightness at 2 pixels per frame); black is static.",
                    texture: &d.velocity,
                },
                DebugView {
                    name: "rejection",
                    description: "History rejection: red where the history was dropped (reset or \
                         reprojected off screen), yellow where rectification pulled it towards the \
                         current neighbourhood (brighter: further); elsewhere the dimmed result.",
                    texture: &d.rejection,
                },
                DebugView {
                    name: "jitter",
                    description: "The jitter pattern inside one enlarged pixel: white samples already \
                         accumulated in this cycle, red this frame's, grey still to come.",
                    texture: &d.jitter,
                },
            ],
            _ => Vec::new(),
        }
    }

    fn path_note(&self) -> Option<String> {
        let s = &self.settings;
        let rectify = s.rectify.name();
        Some(format!(
            "{} jitter samples, {} current frame, {} history, {rectify} rectification on the {} colours{}, {} velocity, current weight {}, history falling off over {} / {} px/frame of parallax / speed ({} of parallax at silhouettes)",
            s.samples.count(),
            s.current_filter.name(),
            s.history_filter.name(),
            s.neighbourhood.name(),
            if s.rectify == Rectify::Variance {
                format!(" (gamma {})", s.gamma)
            } else {
                String::new()
            },
            s.velocity.name(),
            s.current_weight,
            s.parallax_falloff,
            s.speed_falloff,
            s.silhouette_falloff
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_and_names_round_trip() {
        for preset in Preset::ALL {
            assert_eq!(Preset::from_name(preset.name()), Some(*preset));
        }
        assert!(Preset::from_name("nope").is_none());
        for value in Rectify::ALL {
            assert_eq!(Rectify::from_name(value.name()), Some(*value));
        }
        let constants = TaaSettings::preset(Preset::Fast).constants(false);
        assert_eq!(
            constants,
            [
                ("HISTORY_FILTER", 0.0),
                ("RECTIFY", 1.0),
                ("LUMA_WEIGHT", 0.0),
                ("VELOCITY_TAPS", 0.0),
                ("NEIGHBOURHOOD", 1.0),
                ("TRUST_OWN_SPEED", 0.0),
                ("RADIANCE", 0.0),
                ("REACTIVE_MASK", 0.0)
            ]
        );
    }
}
