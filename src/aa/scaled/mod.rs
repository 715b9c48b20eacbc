//! Any technique at a render scale, upscaled to the output size, and optionally sharpened:
//! the technique behind a combination id `ID[@SCALE][:UPSCALER][+SHARPEN[=STRENGTH]]` (the
//! string form is `aa::combo`).
//!
//! [`Scaled`] wraps the technique `ID` creates. Every frame it hands the inner technique the
//! frame at the render size ([`FrameInfo::at_render_size`]: the camera keeps the output's
//! projection, jitter is in render pixels and textures get the scale's mip bias,
//! log2(render / output)), so the inner technique's scene input is rendered at that size and
//! shared with every other technique asking for the same input at the same scale, and
//! techniques that render the scene themselves (supersampling) render at that size too. The
//! inner technique writes a render-size image of its own; an upscale pass brings it to the
//! output size and a sharpening pass follows when asked for. Both are passes of the technique
//! (`ID@…/upscale`, `ID@…/sharpen`), timed like any other, and their images are in its memory
//! report. A temporal technique keeps its history at the render size. A technique that
//! reconstructs at the output size itself (`Technique::reconstructs_at_output`, the temporal
//! upscaler) gets the same render-size frame but writes the output-size image (straight into
//! the output, or into the image the sharpening reads), and no upscale runs after it. Debug
//! views are shown at the output size, each render pixel as a block (nearest neighbour). At
//! scale 1 with sharpening, no upscale runs; a plain id (scale 1, no sharpening) is never
//! wrapped.
//!
//! The upscalers and sharpening filters are in `resample.wgsl`; the edge-adaptive upscaler
//! and the two sharpening filters follow the ideas AMD documents for FidelityFX FSR 1 (EASU
//! and RCAS, Timothy Lottes) and FidelityFX CAS, written anew here (no AMD shader text).
//! Measurements: `docs/upscaling.md`.

pub mod passes;

use crate::aa::combo::Combo;
use crate::aa::combo::Upscaler;
use crate::aa::common::{debug_texture, intern};
use crate::aa::{DebugView, FrameInfo, ParamError, ParamValue, SceneInput, Technique};
use crate::graph::hdr::TonemapOrder;
use crate::graph::params::{Named, Param};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;
use passes::Resampler;

/// The shaders of every scaled technique, which the naga test validates.
pub const SHADERS: &[crate::gpu::shader::Shader] = &[passes::WGSL];

/// A technique at a render scale with an upscaler and optional sharpening. See the module docs.
pub struct Scaled {
    inner: Box<dyn Technique>,
    combo: Combo,
    id: &'static str,
    gpu: crate::gpu::Gpu,
    resampler: Resampler,
    /// The inner technique's output, at the render size.
    rendered: Option<wgpu::Texture>,
    /// The upscaled image before sharpening (scale below 1 with sharpening).
    upscaled: Option<wgpu::Texture>,
    debug_enabled: bool,
    /// The inner technique's debug views at the output size.
    debug: Vec<(&'static str, &'static str, wgpu::Texture)>,
}

/// A texture of `size` that stays as it is while its size is right, else a new one.
fn sized(
    texture: &mut Option<wgpu::Texture>,
    size: (u32, u32),
    make: impl FnOnce() -> wgpu::Texture,
) -> &wgpu::Texture {
    if texture
        .as_ref()
        .is_none_or(|t| (t.width(), t.height()) != size)
    {
        *texture = Some(make());
    }
    texture.get_or_insert_with(|| unreachable!("set above"))
}

impl Scaled {
    /// `inner` (created from `combo.base`) at `combo`'s scale, upscaler and sharpening.
    pub fn new(gpu: &crate::gpu::Gpu, inner: Box<dyn Technique>, combo: Combo) -> Self {
        Self {
            id: intern(&combo.id()),
            inner,
            combo,
            gpu: gpu.clone(),
            resampler: Resampler::new(gpu),
            rendered: None,
            upscaled: None,
            debug_enabled: false,
            debug: Vec::new(),
        }
    }

    /// The frame the inner technique sees.
    fn inner_frame(&self, frame: &FrameInfo) -> FrameInfo {
        frame.at_render_size(self.combo.render_size(frame.output_size()))
    }

    /// Shows the inner technique's debug views at the output size.
    fn upscale_debug_views(&mut self, ctx: &mut PassContext<'_>, output: (u32, u32)) {
        let views = self.inner.debug_views();
        self.debug.truncate(views.len());
        for (n, view) in views.iter().enumerate() {
            let label = format!("{} {}", self.id, view.name);
            if self
                .debug
                .get(n)
                .is_none_or(|(name, _, t)| *name != view.name || (t.width(), t.height()) != output)
            {
                let texture = debug_texture(&self.gpu.device, &label, output);
                let entry = (view.name, view.description, texture);
                if n < self.debug.len() {
                    self.debug[n] = entry;
                } else {
                    self.debug.push(entry);
                }
            }
            let pass = format!("debug {}", view.name);
            self.resampler
                .nearest(ctx, &pass, view.texture, &self.debug[n].2);
        }
    }
}

impl Technique for Scaled {
    fn id(&self) -> &'static str {
        self.id
    }

    fn label(&self) -> String {
        format!("{}{}", self.inner.label(), self.combo.label_suffix())
    }

    fn scene_input(&self, frame: &FrameInfo) -> Option<SceneInput> {
        self.inner.scene_input(&self.inner_frame(frame))
    }

    fn render_size(&self, frame: &FrameInfo) -> (u32, u32) {
        self.combo.render_size(frame.output_size())
    }

    fn temporal(&self) -> bool {
        self.inner.temporal()
    }

    /// The inner technique's when it writes the output itself (a temporal upscaler without
    /// sharpening); after the tonemapper otherwise, as the upscale and sharpening passes run
    /// on display values.
    fn tonemap_order(&self) -> TonemapOrder {
        if self.inner.reconstructs_at_output() && self.combo.sharpen.is_none() {
            self.inner.tonemap_order()
        } else {
            TonemapOrder::After
        }
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let output_size = (output.width(), output.height());
        let inner_frame = self.inner_frame(ctx.frame);
        // What the inner technique writes: its render-size image, or the output-size image
        // where it reconstructs at the output size itself.
        let written_size = if self.inner.reconstructs_at_output() {
            output_size
        } else {
            inner_frame.size()
        };
        let inner = &mut self.inner;
        match (written_size != output_size, self.combo.sharpen) {
            (false, None) => ctx.with_frame(&inner_frame, |ctx| inner.encode(ctx, input, output)),
            (resample, sharpen) => {
                let gpu = &self.gpu;
                let rendered = sized(&mut self.rendered, written_size, || {
                    crate::graph::output_texture(gpu, &format!("{} render", self.id), written_size)
                });
                ctx.with_frame(&inner_frame, |ctx| inner.encode(ctx, input, rendered));
                let upscaler = self.combo.upscaler.unwrap_or(Upscaler::Easu);
                match sharpen {
                    None => self.resampler.upscale(ctx, upscaler, rendered, output),
                    Some(sharpening) if !resample => {
                        self.resampler.sharpen(ctx, sharpening, rendered, output)
                    }
                    Some(sharpening) => {
                        let upscaled = sized(&mut self.upscaled, output_size, || {
                            crate::graph::output_texture(
                                gpu,
                                &format!("{} upscaled", self.id),
                                output_size,
                            )
                        });
                        self.resampler.upscale(ctx, upscaler, rendered, upscaled);
                        self.resampler.sharpen(ctx, sharpening, upscaled, output);
                    }
                }
            }
        }
        if self.debug_enabled {
            self.upscale_debug_views(ctx, output_size);
        }
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = self.inner.memory();
        items.extend(
            self.rendered
                .iter()
                .map(|t| MemoryItem::texture(format!("{} render", self.id), t)),
        );
        items.extend(
            self.upscaled
                .iter()
                .map(|t| MemoryItem::texture(format!("{} upscaled", self.id), t)),
        );
        items.extend(
            self.debug
                .iter()
                .map(|(name, _, t)| MemoryItem::texture(format!("{name} view at output size"), t)),
        );
        items.extend(self.resampler.memory());
        items
    }

    fn params(&self) -> Vec<Param> {
        self.inner.params()
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        self.inner.set_param(key, value)
    }

    fn presets(&self) -> &'static [&'static str] {
        self.inner.presets()
    }

    fn apply_preset(&mut self, name: &str) -> Result<(), ParamError> {
        self.inner.apply_preset(name)
    }

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
        self.inner.set_debug_views(enabled);
        if !enabled {
            self.debug.clear();
        }
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        if !self.debug_enabled {
            return Vec::new();
        }
        self.debug
            .iter()
            .map(|(name, description, texture)| DebugView {
                name,
                description,
                texture,
            })
            .collect()
    }

    fn path_note(&self) -> Option<String> {
        let own = match (self.combo.scale < 1.0, self.combo.upscaler) {
            (true, Some(upscaler)) => format!(
                "rendered at {:.1}% per axis, upscaled with {}",
                self.combo.scale * 100.0,
                upscaler.name()
            ),
            (true, None) => format!(
                "rendered at {:.1}% per axis, reconstructed at the output size by the technique",
                self.combo.scale * 100.0
            ),
            (false, _) => "rendered at the output size".to_owned(),
        };
        let own = match self.combo.sharpen {
            Some(s) => format!("{own}, then {} at strength {}", s.filter.name(), s.strength),
            None => own,
        };
        Some(match self.inner.path_note() {
            Some(inner) => format!("{inner}; {own}"),
            None => own,
        })
    }

    fn color_only(&self) -> bool {
        self.inner.color_only() && self.combo.scale == 1.0
    }

    fn source_hash(&self) -> Option<String> {
        self.inner.source_hash()
    }
}
