//! SMAA, enhanced subpixel morphological antialiasing, after Jorge Jimenez, Jose I.
//! Echevarria, Tiago Sousa and Diego Gutierrez, "SMAA: Enhanced Subpixel Morphological
//! Antialiasing", Computer Graphics Forum (Eurographics 2012). This is aa-lab's own
//! implementation of the paper's ideas and parameters.
//!
//! SMAA finds the edges of the finished image, recognises the shape of each staircase (L, Z
//! and U patterns along horizontal and vertical edges, 45-degree diagonals, sharp corners),
//! estimates the true edge line behind it and blends each pixel with its neighbour by the area
//! that line covers. Three modes share the same passes:
//! - `smaa` (1x): on the shared one-sample render ([`passes`]);
//! - `smaa-t2x`: on a render jittered a quarter pixel back and forth each frame, resolved with
//!   the previous frame through motion vectors ([`temporal`]);
//! - `smaa-s2x`: per sample of a two-sample render, averaged ([`multisample`]).
//!
//! SMAA 4x, S2x and T2x combined, is a technique of its own ([`x4`]) built from these parts.
//!
//! The lookup tables are generated at first use from their rules ([`lut`]); the settings,
//! presets and parameters live in [`settings`]; [`pipeline`] has the wgpu helpers; the WGSL
//! is `smaa.wgsl` (the three SMAA passes, debug views) and `smaa_modes.wgsl` (T2x, S2x) here. Only edge
//! pixels run the blending-weight pass: the edge pass marks them in a stencil buffer that the
//! weight pass tests. Debug views: the edges and the blending weights.
//!
//! Every mode runs before or after the tonemapper of an HDR frame (`tonemap_order`, after by
//! default, as engines run it). Before, the edges are found on a perceptual copy of the
//! radiance (Karis-compressed and sRGB-encoded, `aa::common::perceptual`), the blends mix
//! radiance into half-float targets, and where a mode averages (S2x's two samples, T2x's and
//! 4x's temporal resolve) it averages Karis-weighted, through the reversible tonemap
//! `aa::common::RADIANCE_WGSL` compiled in front of `smaa_modes.wgsl`, as TAA does.
//!
//! Figures on lavapipe and a GPU, and the lookup tables in full: `docs/techniques/smaa.md`.

pub mod lut;
pub mod multisample;
pub mod passes;
pub mod settings;
pub mod temporal;
pub mod x4;

pub use settings::{EdgeMode, Preset, SmaaSettings};

use crate::aa::common::RADIANCE_WGSL;
use crate::aa::common::perceptual::PERCEPTUAL_WGSL;
use crate::aa::info::{FULL_SET_HINT, TechniqueInfo, needs_encoded_views};
use crate::aa::params::{Named, Param, ParamError, ParamValue, Tunable};
use crate::aa::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::shader::Shader;
use crate::gpu::{Capabilities, Gpu};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;
use multisample::Multisample;
use passes::{Input, SmaaPasses};
use temporal::Temporal;

/// Stable id of SMAA 1x.
pub const ID_1X: &str = "smaa";
/// Stable id of SMAA T2x.
pub const ID_T2X: &str = "smaa-t2x";
/// Stable id of SMAA S2x.
pub const ID_S2X: &str = "smaa-s2x";

/// The edge, blending-weight and neighbourhood-blending passes and the debug views.
const WGSL: Shader = crate::wgsl!("src/aa/smaa/smaa.wgsl");
/// The T2x temporal resolve and the S2x sample passes, after Karis' reversible tonemap.
const MODES_WGSL: Shader = crate::wgsl!("src/aa/smaa/smaa_modes.wgsl", prelude = RADIANCE_WGSL);

/// The registry entries of the three modes.
pub const INFOS: [TechniqueInfo; 3] = [
    TechniqueInfo {
        id: ID_1X,
        name: "SMAA 1x",
        summary: "Morphological antialiasing of the finished image: edges are found by luma (or colour or \
             depth), the shape of each staircase is recognised (L, Z and U patterns, 45-degree diagonals, sharp corners) \
             and every edge pixel is blended with its neighbour by the area the reconstructed edge line covers, read from \
             precomputed tables. Smooth, sharp edges for about the cost of three fullscreen passes and no extra scene \
             memory, but it cannot recover detail the single sample missed (sub-pixel geometry still breaks up and \
             flickers) and it may soften text and fine texture.",
        availability: needs_encoded_views,
        create: |gpu| Box::new(Smaa::new(gpu, Mode::X1)),
        shaders: &[WGSL, MODES_WGSL, PERCEPTUAL_WGSL, RADIANCE_WGSL],
    },
    TechniqueInfo {
        id: ID_T2X,
        name: "SMAA T2x",
        summary: "SMAA 1x on a render jittered by a quarter pixel, alternating between two offsets, mixed \
             with the previous frame found through motion vectors (half weight, less where the pixel's speed \
             changed). Two samples per pixel over two frames recover some sub-pixel detail and steady \
             crawling edges for the cost of SMAA plus one resolve pass, but fast motion and disocclusions \
             fall back to SMAA 1x and the jitter can shimmer where the history is rejected.",
        availability: needs_encoded_views,
        create: |gpu| Box::new(Smaa::new(gpu, Mode::T2x)),
        shaders: &[WGSL, MODES_WGSL, PERCEPTUAL_WGSL, RADIANCE_WGSL],
    },
    TechniqueInfo {
        id: ID_S2X,
        name: "SMAA S2x",
        summary: "SMAA 1x on each sample of a two-sample render at the standard 2x MSAA positions, averaged: \
             MSAA's real sub-pixel coverage plus SMAA's gradients, better than either alone on thin geometry, \
             at the cost of a 2x render and two SMAA runs. Without 2x MSAA on the adapter it renders the scene \
             twice at the two positions instead.",
        availability: s2x_availability,
        create: |gpu| Box::new(Smaa::new(gpu, Mode::S2x)),
        shaders: &[WGSL, MODES_WGSL, PERCEPTUAL_WGSL, RADIANCE_WGSL],
    },
];

/// SMAA S2x reads depth with `textureLoad`, which wgpu cannot translate to GLSL.
pub(crate) fn s2x_availability(caps: &Capabilities) -> Result<(), String> {
    needs_encoded_views(caps)?;
    if caps.is_gl() {
        Err(format!(
            "SMAA S2x loads depth samples with textureLoad, which the OpenGL backend's GLSL \
             cannot do; {FULL_SET_HINT}"
        ))
    } else {
        Ok(())
    }
}

/// The part of a path note every SMAA mode shares: the preset (or custom settings), the edge
/// detection and the stencil early-out.
pub(crate) fn settings_note(settings: &SmaaSettings) -> String {
    let preset = settings.matching_preset().map_or_else(
        || "custom settings".to_owned(),
        |p| format!("{} preset", p.name()),
    );
    format!(
        "{preset}, {} edges, stencil early-out for the weight pass",
        settings.edge_mode.name()
    )
}

/// Which SMAA mode a technique runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// SMAA 1x.
    X1,
    /// SMAA T2x (temporal).
    T2x,
    /// SMAA S2x (two samples).
    S2x,
}

impl Mode {
    /// The technique id.
    pub fn id(self) -> &'static str {
        self.info().id
    }

    /// The mode's registry entry.
    pub fn info(self) -> &'static TechniqueInfo {
        match self {
            Self::X1 => &INFOS[0],
            Self::T2x => &INFOS[1],
            Self::S2x => &INFOS[2],
        }
    }
}

enum State {
    X1,
    T2x(Box<Temporal>),
    S2x(Box<Multisample>),
}

/// An SMAA technique in one of its modes.
pub struct Smaa {
    mode: Mode,
    settings: SmaaSettings,
    passes: SmaaPasses,
    state: State,
    debug_enabled: bool,
}

impl Smaa {
    /// SMAA in `mode` with the default (High) settings.
    pub fn new(gpu: &Gpu, mode: Mode) -> Self {
        let passes = SmaaPasses::new(gpu);
        let state = match mode {
            Mode::X1 => State::X1,
            Mode::T2x => State::T2x(Box::new(Temporal::new(&gpu.device, &passes))),
            Mode::S2x => State::S2x(Box::new(Multisample::new(&gpu.device, &gpu.caps, &passes))),
        };
        Self {
            mode,
            settings: SmaaSettings::default(),
            passes,
            state,
            debug_enabled: false,
        }
    }

    /// The current settings.
    pub fn settings(&self) -> &SmaaSettings {
        &self.settings
    }

    /// Replaces the settings (T2x drops its history on the next frame when they differ).
    pub fn set_settings(&mut self, settings: SmaaSettings) {
        self.settings = settings;
    }
}

impl Technique for Smaa {
    fn id(&self) -> &'static str {
        self.mode.id()
    }

    fn label(&self) -> String {
        self.mode.info().name.to_owned()
    }

    fn scene_input(&self, frame: &FrameInfo) -> Option<SceneInput> {
        match &self.state {
            State::X1 => Some(SceneInput::Shared1x),
            State::T2x(_) => Some(SceneInput::jittered(
                temporal::jitter(frame.camera.frame),
                self.settings.mip_bias,
            )),
            State::S2x(multisample) => multisample.scene_input(),
        }
    }

    fn temporal(&self) -> bool {
        self.mode == Mode::T2x
    }

    fn color_only(&self) -> bool {
        matches!(self.state, State::X1)
            && self.settings.edge_mode != EdgeMode::Depth
            && !self.settings.predication
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let settings = self.settings;
        match &mut self.state {
            State::X1 => {
                let Some(input) = input else { return };
                let target = output.create_view(&Default::default());
                let input = Input {
                    color: &input.color,
                    depth: &input.depth,
                    motion: None,
                };
                self.passes
                    .run(ctx, &settings, &input, &target, 0, glam::Vec2::ZERO, "");
                if self.debug_enabled {
                    self.passes.encode_debug(ctx);
                }
            }
            State::T2x(temporal) => {
                let Some(input) = input else { return };
                temporal.encode(ctx, &mut self.passes, &settings, input, output);
                if self.debug_enabled {
                    self.passes.encode_debug(ctx);
                }
            }
            State::S2x(multisample) => {
                multisample.encode(
                    ctx,
                    &mut self.passes,
                    &settings,
                    input,
                    output,
                    self.debug_enabled,
                );
            }
        }
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let id = self.id();
        let mut items = self.passes.memory(id);
        match &self.state {
            State::X1 => {}
            State::T2x(temporal) => items.extend(temporal.memory(id)),
            State::S2x(multisample) => items.extend(multisample.memory(id)),
        }
        items
    }

    fn params(&self) -> Vec<Param> {
        self.settings.params_for(self.mode == Mode::T2x)
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        let temporal_only = settings::TEMPORAL_KEYS.contains(&key) && self.mode != Mode::T2x;
        if temporal_only || !self.settings.set(key, value) {
            return Err(ParamError::unknown_key(self.id(), key, &self.params()));
        }
        Ok(())
    }

    fn presets(&self) -> &'static [&'static str] {
        self.settings.preset_names()
    }

    fn apply_preset(&mut self, name: &str) -> Result<(), ParamError> {
        self.settings.apply_preset_named(self.mode.id(), name)
    }

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        self.passes.debug_views(
            self.debug_enabled,
            [
                "Edges SMAA found (S2x: first sample): red on a pixel's left side, green on its top \
                              side, yellow both.",
                "Blending weights (S2x: first sample): red blends across the pixel's top edge, green \
                              across its left edge, brighter is more (doubled).",
            ],
        )
    }

    fn path_note(&self) -> Option<String> {
        let mut note = settings_note(&self.settings);
        if let State::S2x(multisample) = &self.state {
            note = format!("{}; {note}", multisample.path().describe());
        }
        Some(note)
    }
}
