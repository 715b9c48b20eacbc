//! What the edge detection of the morphological techniques (SMAA, MLAA, CMAA 2) reads when
//! they run before the tonemapper of an HDR frame (`graph::hdr`).
//!
//! Their edge thresholds are tuned for perceptual, sRGB-encoded display values (SMAA's 0.1
//! is a tenth of the encoded range); on raw radiance, which runs to 40 on `neon`, a threshold
//! means nothing. [`PerceptualCopy`] therefore hands the edge passes an 8-bit sRGB copy of the
//! radiance compressed with Karis' reversible tonemap c / (1 + luma) (Brian Karis, "Tone
//! mapping", 2013; the prelude TAA compiles, `radiance.wgsl`), read through its encoded view
//! exactly as a displayed image is: black to white keeps most of its encoded range, and a
//! tube at 8 reads as the near-white it is shown as. The blend passes read the radiance
//! itself and write radiance, which the graph tonemaps. One copy per run costs one full-screen
//! pass, cheaper than compressing and encoding every tap of the edge passes (nine a pixel).
//! The frame's exposure scales the radiance before the compression, as the tonemapper scales
//! it, so that `--exposure` changes the edges found as it changes the image shown (a dim edge
//! brought up by +2 EV is found, as on the displayed image); the blends read the radiance
//! itself, and the tonemap pass applies the exposure to their output.
//! Display-value inputs are handed through untouched: LDR frames and techniques after the
//! tonemapper run exactly as before.
//!
//! User techniques (`aa::user`) read a half-float copy instead ([`PerceptualCopy::half_float`]):
//! the same compressed values, but their output is expanded back to radiance with the inverse
//! c / (1 - luma), which would blow an 8-bit copy's quantisation near white (one step of 255
//! at a compressed 0.98) up into radiance errors of a third of the value.

use super::{RADIANCE_WGSL, holds_radiance, pass};
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::gpu::{COLOR_FORMAT, COLOR_FORMAT_ENCODED_VIEW, HDR_FORMAT};
use crate::graph::{MemoryItem, PassContext};

/// The compression pass, after Karis' tonemap.
pub const PERCEPTUAL_WGSL: Shader =
    crate::wgsl!("src/aa/common/perceptual.wgsl", prelude = RADIANCE_WGSL);

/// The perceptual copy of a radiance input, its pipeline built on the first HDR run.
pub struct PerceptualCopy {
    format: wgpu::TextureFormat,
    pipeline: Option<wgpu::RenderPipeline>,
    /// The exposure factor, made with the pipeline.
    exposure: Option<wgpu::Buffer>,
    copy: Option<wgpu::Texture>,
}

/// The 8-bit sRGB copy the edge passes read through its encoded view.
impl Default for PerceptualCopy {
    fn default() -> Self {
        Self {
            format: COLOR_FORMAT,
            pipeline: None,
            exposure: None,
            copy: None,
        }
    }
}

impl PerceptualCopy {
    /// A copy in half floats ([`HDR_FORMAT`]): the compressed values without quantisation,
    /// for a pass whose output is expanded back to radiance.
    pub fn half_float() -> Self {
        Self {
            format: HDR_FORMAT,
            ..Self::default()
        }
    }

    /// The texture the edge passes (through its encoded view) or a user technique read for
    /// `color`: `color` itself when it holds display values, or else its perceptual copy,
    /// recorded now as the pass `{prefix}perceptual`.
    pub fn source<'a>(
        &'a mut self,
        ctx: &mut PassContext<'_>,
        color: &'a wgpu::Texture,
        prefix: &str,
    ) -> &'a wgpu::Texture {
        if !holds_radiance(color) {
            // An earlier HDR frame's copy is released (and leaves the memory report).
            self.copy = None;
            return color;
        }
        let (gpu, fullscreen) = (ctx.gpu, ctx.fullscreen);
        let device = &gpu.device;
        let size = (color.width(), color.height());
        if self
            .copy
            .as_ref()
            .is_none_or(|c| (c.width(), c.height()) != size)
        {
            let view_formats: &[wgpu::TextureFormat] = if self.format == COLOR_FORMAT {
                &[COLOR_FORMAT_ENCODED_VIEW]
            } else {
                &[]
            };
            self.copy = Some(pass::target(
                device,
                "perceptual copy",
                size,
                self.format,
                view_formats,
            ));
        }
        let format = self.format;
        let pipeline = self.pipeline.get_or_insert_with(|| {
            fullscreen.pipeline(
                device,
                &FragmentDesc {
                    label: "perceptual copy",
                    module: &PERCEPTUAL_WGSL.module(device),
                    entry_point: "fs_perceptual",
                    targets: &[format],
                    constants: &[("RADIANCE", 1.0)],
                    layout: None,
                },
            )
        });
        let exposure = self
            .exposure
            .get_or_insert_with(|| pass::uniform_buffer::<[f32; 4]>(device, "perceptual exposure"));
        let scale = [ctx.exposure_scale(), 0.0, 0.0, 0.0];
        gpu.queue
            .write_buffer(exposure, 0, bytemuck::cast_slice(&scale));
        let source = color.create_view(&Default::default());
        let group = pass::bind_group(
            device,
            "perceptual copy",
            &pipeline.get_bind_group_layout(0),
            &[
                (0, wgpu::BindingResource::TextureView(&source)),
                (1, exposure.as_entire_binding()),
            ],
        );
        let Some(copy) = &self.copy else { return color };
        let target = copy.create_view(&Default::default());
        ctx.fullscreen_pass(&format!("{prefix}perceptual"), &target, pipeline, &group);
        copy
    }

    /// The copy's memory, labelled with the technique id, while HDR frames keep it.
    pub fn memory(&self, id: &str) -> Option<MemoryItem> {
        (self.copy.as_ref()).map(|c| MemoryItem::texture(format!("{id} perceptual copy"), c))
    }
}
