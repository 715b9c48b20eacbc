//! The one trait every antialiasing technique implements, and what the frame graph hands it:
//! the scene render it reads ([`SceneInput`]), the per-frame facts ([`FrameInfo`]) and the
//! debug images it can show ([`DebugView`]). It lives in `graph/` because the graph runs
//! techniques without knowing any of them: `aa/` implements this trait and depends on `graph/`,
//! never the reverse.
//!
//! Life cycle: the graph renders each distinct [`SceneInput`] once per frame, then asks every
//! enabled technique to [`Technique::encode`] its passes into the technique's output texture.
//! A technique owns its pipelines, private textures and settings; its settings are described as
//! data ([`Param`]) so that the command line, the viewer and sidecar files handle every
//! technique the same way.

use glam::Vec2;

use super::hdr::TonemapOrder;
use super::params::{Param, ParamError, ParamValue};
use super::{MemoryItem, PassContext};
use crate::scene::renderer::{RasterOptions, SceneTargets};

/// The scene render a technique reads. Techniques that ask for equal inputs share one render.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum SceneInput {
    /// One sample per pixel at the pixel centre: No AA, FXAA, SMAA 1x.
    Shared1x,
    /// One sample per pixel with the projection shifted by a sub-pixel offset, with motion
    /// vectors: TAA and SMAA T2x.
    Jittered1x {
        /// Offset in 1/65536 pixel, x right and y down (fixed point so inputs can be compared).
        offset_fixed: (i32, i32),
        /// Texture mip bias in 1/256 (temporal techniques sharpen textures).
        mip_bias_fixed: i32,
        /// Whether the render writes the reactive mask of blended surfaces.
        reactive_mask: bool,
    },
    /// `samples` samples per pixel at the standard positions: MSAA and SMAA S2x.
    Msaa {
        /// Sample count (one the adapter supports).
        samples: u32,
        /// Shading rate, centroid and alpha-to-coverage choices.
        raster: RasterOptions,
    },
}

impl SceneInput {
    /// A jittered input for an offset in pixels and a mip bias.
    pub fn jittered(offset: Vec2, mip_bias: f32) -> Self {
        Self::Jittered1x {
            offset_fixed: (
                (offset.x * 65536.0).round() as i32,
                (offset.y * 65536.0).round() as i32,
            ),
            mip_bias_fixed: (mip_bias * 256.0).round() as i32,
            reactive_mask: false,
        }
    }

    /// This input with the reactive mask of blended surfaces written (`on`) or not; inputs
    /// other than jittered ones write none.
    pub fn with_reactive_mask(self, on: bool) -> Self {
        match self {
            Self::Jittered1x {
                offset_fixed,
                mip_bias_fixed,
                ..
            } => Self::Jittered1x {
                offset_fixed,
                mip_bias_fixed,
                reactive_mask: on,
            },
            other => other,
        }
    }

    /// Whether the render writes the reactive mask.
    pub fn reactive_mask(&self) -> bool {
        matches!(
            self,
            Self::Jittered1x {
                reactive_mask: true,
                ..
            }
        )
    }

    /// Jitter offset in pixels (zero for unjittered inputs).
    pub fn offset(&self) -> Vec2 {
        match self {
            Self::Jittered1x { offset_fixed, .. } => {
                Vec2::new(offset_fixed.0 as f32, offset_fixed.1 as f32) / 65536.0
            }
            _ => Vec2::ZERO,
        }
    }

    /// Texture mip bias.
    pub fn mip_bias(&self) -> f32 {
        match self {
            Self::Jittered1x { mip_bias_fixed, .. } => *mip_bias_fixed as f32 / 256.0,
            _ => 0.0,
        }
    }

    /// Samples per pixel of the render.
    pub fn sample_count(&self) -> u32 {
        match self {
            Self::Msaa { samples, .. } => *samples,
            _ => 1,
        }
    }

    /// Rasterisation options of the render.
    pub fn raster(&self) -> RasterOptions {
        match self {
            Self::Msaa { raster, .. } => *raster,
            _ => RasterOptions::default(),
        }
    }

    /// Whether the render writes motion vectors.
    pub fn motion(&self) -> bool {
        matches!(self, Self::Jittered1x { .. })
    }

    /// Short label for timings and memory reports.
    pub fn label(&self) -> String {
        match self {
            Self::Shared1x => "scene 1x".to_owned(),
            Self::Jittered1x { reactive_mask, .. } => {
                let mask = if *reactive_mask { " reactive" } else { "" };
                format!("scene 1x jittered{mask}")
            }
            Self::Msaa { samples, raster } => {
                let mut label = format!("scene msaa{samples}");
                match raster.shading {
                    crate::scene::renderer::ShadingRate::Pixel => {}
                    crate::scene::renderer::ShadingRate::Centroid => label += " centroid",
                    crate::scene::renderer::ShadingRate::Sample => label += " per-sample",
                }
                if raster.alpha_to_coverage {
                    label += " a2c";
                }
                label
            }
        }
    }
}

/// An extra image a technique can show to explain itself (SMAA edges, TAA velocity...).
pub struct DebugView<'a> {
    /// Stable name (`edges`, `weights`, `velocity`...), used in file names.
    pub name: &'static str,
    /// What the colours mean, for legends and tooltips.
    pub description: &'static str,
    /// The image, RGBA8 with sRGB-encoded values at the output size.
    pub texture: &'a wgpu::Texture,
}

/// The per-frame facts every technique sees.
#[derive(Clone, Copy, Debug)]
pub struct FrameInfo {
    /// Camera of this frame (deterministic for a frame number in the CLI).
    pub camera: crate::scene::camera::FrameCamera,
    /// Temporal techniques must drop their history this frame (camera cut, scene change,
    /// first frame of a sequence).
    pub reset_history: bool,
}

impl FrameInfo {
    /// The size a technique renders at: the output size, or the render size when the
    /// technique runs at a render scale (see [`FrameInfo::at_render_size`]).
    pub fn size(&self) -> (u32, u32) {
        self.camera.image_size()
    }

    /// The output size in pixels, whatever the render scale.
    pub fn output_size(&self) -> (u32, u32) {
        self.camera.size
    }

    /// This frame as a technique running at `render_size` sees it: its camera renders at that
    /// size with the output's projection (and the scale's mip bias).
    pub fn at_render_size(&self, render_size: (u32, u32)) -> Self {
        Self {
            camera: self.camera.at_render_size(render_size),
            ..*self
        }
    }
}

/// One antialiasing technique. See the module docs for the life cycle. `Send`, so that a frame
/// graph holding techniques can live on a render thread of its own.
pub trait Technique: Send {
    /// Stable id (`none`, `msaa4`, `fxaa`...), as on the command line.
    fn id(&self) -> &'static str;

    /// The scene render this technique reads this frame, or `None` when it renders the scene
    /// itself through [`PassContext::render_scene`] (supersampling).
    fn scene_input(&self, frame: &FrameInfo) -> Option<SceneInput>;

    /// The size its scene input is rendered at: the output size, unless the technique runs at
    /// a render scale (`aa::scaled`). Inputs are shared between techniques that ask for the
    /// same input at the same size.
    fn render_size(&self, frame: &FrameInfo) -> (u32, u32) {
        frame.size()
    }

    /// Whether the technique reconstructs the output-size image itself from a scene input
    /// rendered at the render size (a temporal upscaler). At a render scale (`aa::scaled`) it
    /// is handed the frame at the render size ([`FrameInfo::size`]; [`FrameInfo::output_size`]
    /// stays the output's) and an output-size target, and no upscale runs after it; other
    /// techniques write a render-size image that is upscaled.
    fn reconstructs_at_output(&self) -> bool {
        false
    }

    /// Where the technique runs in an HDR frame: on radiance before the tonemapper (it then
    /// reads a half-float input and writes a half-float `output`, which the graph tonemaps)
    /// or on the displayed image after it (the default; see `graph::hdr`).
    fn tonemap_order(&self) -> TonemapOrder {
        TonemapOrder::After
    }

    /// Whether the technique keeps state across frames, so that frame N means running frames
    /// 0..=N.
    fn temporal(&self) -> bool {
        false
    }

    /// Records the technique's passes. `input` is the render of [`Technique::scene_input`];
    /// `output` is the texture to write (RGBA8 sRGB, viewable as `Rgba8Unorm`; half floats
    /// when the technique runs before the tonemapper of an HDR frame).
    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    );

    /// GPU memory the technique owns (its private targets and buffers), at the current size.
    fn memory(&self) -> Vec<MemoryItem> {
        Vec::new()
    }

    /// Parameters with their current values.
    fn params(&self) -> Vec<Param> {
        Vec::new()
    }

    /// Applies a value already validated against [`Technique::params`].
    fn set_param(&mut self, key: &str, _value: &ParamValue) -> Result<(), ParamError> {
        Err(ParamError::unknown_key(self.id(), key, &self.params()))
    }

    /// Named presets, in the order a UI offers them.
    fn presets(&self) -> &'static [&'static str] {
        &[]
    }

    /// Applies a preset by name.
    fn apply_preset(&mut self, name: &str) -> Result<(), ParamError> {
        Err(ParamError::UnknownPreset {
            technique: self.id().to_owned(),
            name: name.to_owned(),
            known: self.presets().join(", "),
        })
    }

    /// Turns the debug views on or off (they cost passes, so they are off by default).
    fn set_debug_views(&mut self, _enabled: bool) {}

    /// The debug views produced by the last `encode`, when enabled.
    fn debug_views(&self) -> Vec<DebugView<'_>> {
        Vec::new()
    }

    /// Which code path runs on this adapter when there is a choice (SMAA S2x without 2x MSAA).
    fn path_note(&self) -> Option<String> {
        None
    }

    /// Whether the technique reads nothing but the colour of the [`SceneInput::Shared1x`]
    /// render, so it can run on a finished image (see [`image_refusal`]). Post-process
    /// techniques say so; the default is no.
    fn color_only(&self) -> bool {
        false
    }

    /// Short name for labels, including the settings that change what it is (`SSAA 16x`).
    fn label(&self) -> String;

    /// A hash of the source file the technique runs, for techniques read from the user's
    /// files (see `aa::user`): records keep it, and replaying a record refuses a changed file.
    fn source_hash(&self) -> Option<String> {
        None
    }
}
