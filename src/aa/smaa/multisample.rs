//! SMAA S2x: SMAA 1x on each sample of a two-sample image at the standard 2x MSAA positions,
//! then the average of the two results in linear light.
//!
//! Two paths give the per-sample images:
//! - [`S2xPath::Msaa`]: where the adapter renders 2x MSAA, the frame graph's 2x render is read
//!   sample by sample (`fs_extract_sample` copies one sample's colour and depth into
//!   single-sample targets);
//! - [`S2xPath::Renders`]: elsewhere (software Vulkan offers only 1x and 4x) the technique
//!   renders the scene twice itself, each time with the projection shifted so that the pixel's
//!   one sample sits at one of the 2x positions. That is the per-sample-shaded equivalent of
//!   the MSAA render (MSAA shades once per pixel, so inside triangles it can differ slightly).
//!
//! Each sample's SMAA uses the area sub-tables of its position.
//!
//! Before the tonemapper of an HDR frame the samples hold radiance, each sample's SMAA runs on
//! it (see `passes`) and the average is Karis-weighted (`RADIANCE` in `smaa_modes.wgsl`); the
//! pipelines of either kind are built on first use.

use glam::Vec2;

use super::passes::{Input, SmaaPasses};
use super::settings::SmaaSettings;
use crate::aa::SceneInput;
use crate::aa::common::pass::{self, Binding, PassDesc, Stencil, Vertex, bind_group, cleared};
use crate::aa::common::sampling::standard_msaa_positions;
use crate::aa::common::{PipelineCache, encoded_or_radiance_view, holds_radiance, output_format};
use crate::gpu::{COLOR_FORMAT_ENCODED_VIEW, Capabilities, HDR_FORMAT};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::{RasterOptions, SceneTargets, TargetDesc};

/// Where the two samples come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum S2xPath {
    /// One 2x MSAA render, read per sample.
    Msaa,
    /// Two jittered single-sample renders (no 2x MSAA on the adapter).
    Renders,
}

impl S2xPath {
    /// The path an adapter supports.
    pub fn for_adapter(caps: &Capabilities) -> Self {
        if caps.supports_sample_count(2) {
            Self::Msaa
        } else {
            Self::Renders
        }
    }

    /// One line for `path_note`.
    pub fn describe(self) -> &'static str {
        match self {
            Self::Msaa => "SMAA on each sample of a 2x MSAA render, averaged",
            Self::Renders => {
                "2x MSAA is not supported here: SMAA on two jittered 1x renders at the 2x sample \
                 positions (per-sample shading), averaged"
            }
        }
    }
}

/// The two sample positions relative to the pixel centre (pixels, y down).
pub fn sample_offsets() -> [Vec2; 2] {
    let positions = standard_msaa_positions(2).unwrap_or_default();
    let at = |i: usize| positions.get(i).copied().unwrap_or(Vec2::splat(0.5)) - Vec2::splat(0.5);
    [at(0), at(1)]
}

struct Targets {
    size: (u32, u32),
    sample: SceneTargets,
    results: [wgpu::Texture; 2],
}

/// A pass of `smaa_modes.wgsl` that S2x runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum ModePass {
    /// The copy of one sample (its index).
    Extract(usize),
    /// The average of the two results.
    Average,
}

/// The S2x state.
pub struct Multisample {
    path: S2xPath,
    vertex: Vertex,
    module: wgpu::ShaderModule,
    extract_layout: wgpu::BindGroupLayout,
    average_layout: wgpu::BindGroupLayout,
    /// The passes' pipelines, by pass and whether they work on radiance.
    pipelines: PipelineCache<(ModePass, bool)>,
    targets: Option<Targets>,
}

impl Multisample {
    /// The extraction and averaging passes for the adapter's path over `passes`' module; their
    /// pipelines are built on first use.
    pub fn new(device: &wgpu::Device, caps: &Capabilities, passes: &SmaaPasses) -> Self {
        let extract_layout = pass::layout(
            device,
            "smaa s2x extract",
            &[
                (5, Binding::MultisampledTexture),
                (6, Binding::MultisampledDepth),
            ],
        );
        let average_layout = pass::layout(
            device,
            "smaa s2x average",
            &[(7, Binding::Texture), (8, Binding::Texture)],
        );
        Self {
            path: S2xPath::for_adapter(caps),
            vertex: Vertex::new(device),
            module: passes.modes_module.clone(),
            extract_layout,
            average_layout,
            pipelines: PipelineCache::default(),
            targets: None,
        }
    }

    /// The pipeline of `pass` on radiance or display values, built on first use.
    fn pipeline(
        &mut self,
        device: &wgpu::Device,
        pass: ModePass,
        radiance: bool,
    ) -> wgpu::RenderPipeline {
        let (vertex, module) = (&self.vertex, &self.module);
        let (extract_layout, average_layout) = (&self.extract_layout, &self.average_layout);
        self.pipelines.get_or_build((pass, radiance), |_| {
            let radiance_constant = ("RADIANCE", f64::from(u8::from(radiance)));
            let (label, entry_point, layout, format, stencil, constants) = match pass {
                ModePass::Extract(sample) => (
                    format!("smaa s2x extract sample {sample}"),
                    "fs_extract_sample",
                    extract_layout,
                    if radiance {
                        HDR_FORMAT
                    } else {
                        COLOR_FORMAT_ENCODED_VIEW
                    },
                    Stencil::WriteDepth,
                    vec![radiance_constant, ("SAMPLE_INDEX", sample as f64)],
                ),
                ModePass::Average => (
                    "smaa s2x average".to_owned(),
                    "fs_average",
                    average_layout,
                    output_format(radiance),
                    Stencil::None,
                    vec![radiance_constant],
                ),
            };
            vertex.pipeline(
                device,
                &PassDesc {
                    label: &label,
                    module,
                    entry_point,
                    layout,
                    format,
                    constants: &constants,
                    stencil,
                },
            )
        })
    }

    /// The path this adapter runs.
    pub fn path(&self) -> S2xPath {
        self.path
    }

    /// The scene render S2x reads: the 2x MSAA render, or none when it renders its own.
    pub fn scene_input(&self) -> Option<SceneInput> {
        match self.path {
            S2xPath::Msaa => Some(SceneInput::Msaa {
                samples: 2,
                raster: RasterOptions::default(),
            }),
            S2xPath::Renders => None,
        }
    }

    /// Records the copy of one sample's colour and depth from the two-sample `input` into the
    /// single-sample `destination` (SMAA 4x copies from its own jittered 2x render); both hold
    /// radiance or both display values.
    pub(crate) fn copy_sample(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: &SceneTargets,
        destination: &SceneTargets,
        sample: usize,
    ) {
        let radiance = holds_radiance(&input.color);
        let pipeline = self.pipeline(&ctx.gpu.device, ModePass::Extract(sample), radiance);
        let color = encoded_or_radiance_view(&input.color);
        let depth = input.depth.create_view(&Default::default());
        let group = bind_group(
            &ctx.gpu.device,
            "smaa s2x extract",
            &self.extract_layout,
            &[
                (5, wgpu::BindingResource::TextureView(&color)),
                (6, wgpu::BindingResource::TextureView(&depth)),
            ],
        );
        let color_target = encoded_or_radiance_view(&destination.color);
        let depth_target = destination.depth.create_view(&Default::default());
        ctx.render_pass(
            &format!("sample {sample} extract"),
            &[Some(cleared(&color_target))],
            Some(wgpu::RenderPassDepthStencilAttachment {
                view: &depth_target,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            |pass| {
                pass.set_pipeline(&pipeline);
                pass.set_bind_group(0, &group, &[]);
                pass.draw(0..3, 0..1);
            },
        );
    }

    /// Records S2x into `output`; `input` is the 2x render on the MSAA path. The debug views
    /// show the first sample when `debug` is set.
    pub fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        passes: &mut SmaaPasses,
        settings: &SmaaSettings,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
        debug: bool,
    ) {
        let size = ctx.frame.size();
        let radiance = holds_radiance(output);
        if (self.targets.as_ref()).is_none_or(|t| t.size != size || t.sample.desc.hdr != radiance) {
            let device = &ctx.gpu.device;
            let result = |i: usize| {
                pass::target(
                    device,
                    &format!("smaa s2x sample {i}"),
                    size,
                    output_format(radiance),
                    &[],
                )
            };
            self.targets = Some(Targets {
                size,
                sample: SceneTargets::new(
                    ctx.gpu,
                    "smaa s2x sample",
                    TargetDesc {
                        size,
                        sample_count: 1,
                        motion: false,
                        hdr: radiance,
                        reactive_mask: false,
                    },
                ),
                results: [result(0), result(1)],
            });
        }
        // Out of `self` while the passes borrow it; put back below.
        let Some(targets) = self.targets.take() else {
            return;
        };
        for (sample, offset) in sample_offsets().into_iter().enumerate() {
            match (self.path, input) {
                (S2xPath::Msaa, Some(input)) => {
                    self.copy_sample(ctx, input, &targets.sample, sample);
                }
                (S2xPath::Msaa, None) => {
                    self.targets = Some(targets);
                    return;
                }
                (S2xPath::Renders, _) => {
                    // The sample at `offset` from the centre: the image moves by -offset.
                    let view = ctx.frame.camera.params(-offset, 0.0);
                    ctx.render_scene(
                        &format!("sample {sample} scene"),
                        &targets.sample,
                        &view,
                        RasterOptions::default(),
                    );
                }
            }
            let result = targets.results[sample].create_view(&Default::default());
            let sample_input = Input {
                color: &targets.sample.color,
                depth: &targets.sample.depth,
                motion: None,
            };
            passes.run(
                ctx,
                settings,
                &sample_input,
                &result,
                sample,
                offset,
                &format!("sample {sample} "),
            );
            if debug && sample == 0 {
                passes.encode_debug(ctx);
            }
        }
        let target = output.create_view(&Default::default());
        self.average(ctx, &targets.results, &target);
        self.targets = Some(targets);
    }

    /// Records the average of the two per-sample results into `target`, in linear light
    /// (alpha too, so that SMAA 4x keeps the speed its resolve reads there); Karis-weighted
    /// when they hold radiance.
    pub(crate) fn average(
        &mut self,
        ctx: &mut PassContext<'_>,
        results: &[wgpu::Texture; 2],
        target: &wgpu::TextureView,
    ) {
        let radiance = holds_radiance(&results[0]);
        let pipeline = self.pipeline(&ctx.gpu.device, ModePass::Average, radiance);
        let views = results
            .each_ref()
            .map(|t| t.create_view(&Default::default()));
        let group = bind_group(
            &ctx.gpu.device,
            "smaa s2x average",
            &self.average_layout,
            &[
                (7, wgpu::BindingResource::TextureView(&views[0])),
                (8, wgpu::BindingResource::TextureView(&views[1])),
            ],
        );
        ctx.fullscreen_pass("average", target, &pipeline, &group);
    }

    /// Memory of the per-sample targets.
    pub fn memory(&self, id: &str) -> Vec<MemoryItem> {
        let Some(t) = &self.targets else {
            return Vec::new();
        };
        let mut items: Vec<MemoryItem> = t
            .sample
            .textures()
            .into_iter()
            .map(|(name, texture)| MemoryItem::texture(format!("{id} sample {name}"), texture))
            .collect();
        for (i, r) in t.results.iter().enumerate() {
            items.push(MemoryItem::texture(format!("{id} sample {i} result"), r));
        }
        items
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::smaa::lut::subsample_indices;

    #[test]
    fn samples_sit_at_the_standard_2x_positions() {
        assert_eq!(sample_offsets(), [Vec2::splat(0.25), Vec2::splat(-0.25)]);
        // Both samples lie on the "\" diagonal through the centre, so "\" staircases keep the
        // unshifted table and "/" staircases shift by half a step each way.
        assert_eq!(subsample_indices(sample_offsets()[0]), [1, 1, 1, 0]);
        assert_eq!(subsample_indices(sample_offsets()[1]), [2, 2, 2, 0]);
    }
}
