//! SMAA T2x: SMAA 1x on a render jittered by a quarter pixel diagonally, alternating between
//! two offsets frame by frame, then a temporal resolve with the previous frame's SMAA result.
//!
//! The jitter of frame N is [`JITTER`]`[N % 2]`, an offset of the image in pixels (the sample
//! sits at the pixel centre minus it); the area sub-tables follow the sample position
//! (`lut::subsample_indices`). The resolve (`fs_resolve` in `smaa_modes.wgsl`) fetches
//! the previous result where the motion vector says the pixel was and mixes it in with weight
//! 1/2, lowered where the pixel's speed changed between the frames (velocity weighting; the
//! speed travels in the results' alpha). The history is dropped on `reset_history`, on a
//! resize and whenever a setting changes, so frame N depends only on frames 0..=N.
//!
//! Before the tonemapper of an HDR frame the two frames hold radiance and the resolve mixes
//! them Karis-weighted (`RADIANCE` in `smaa_modes.wgsl`); its pipeline for that is built on the
//! first such frame, and the history is dropped when the frames switch between radiance and
//! display values.

use glam::Vec2;

use super::passes::{Input, SmaaPasses};
use super::settings::SmaaSettings;
use crate::aa::common::pass::{self, Binding, PassDesc, Stencil, Vertex, bind_group};
use crate::aa::common::{PipelineCache, holds_radiance, output_format};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;

/// Image offsets of even and odd frames, in pixels (x right, y down): the paper's jitter
/// (-1/4, 1/4) and (1/4, -1/4) is given in projection space, whose y points up. The samples
/// land on the standard 2x MSAA positions (3/4, 3/4) and (1/4, 1/4).
pub const JITTER: [Vec2; 2] = [Vec2::new(-0.25, -0.25), Vec2::new(0.25, 0.25)];

/// The jitter of a frame.
pub fn jitter(frame: u64) -> Vec2 {
    JITTER[(frame % 2) as usize]
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct ResolveParams {
    history: f32,
    weight_scale: f32,
    pad: [f32; 2],
}

struct History {
    size: (u32, u32),
    settings: SmaaSettings,
    current: wgpu::Texture,
    previous: wgpu::Texture,
    valid: bool,
}

/// What [`Temporal::resolve`] reads besides the two frames' results.
pub(crate) struct ResolveFrame<'a> {
    /// Image size.
    pub size: (u32, u32),
    /// This frame's motion vectors (one sample per pixel).
    pub motion: &'a wgpu::Texture,
    /// The bilinear sampler the previous frame is fetched with.
    pub sampler: &'a wgpu::Sampler,
}

/// The T2x state: resolve pipelines and the two frames.
pub struct Temporal {
    vertex: Vertex,
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    /// The resolve, by whether it works on radiance.
    pipelines: PipelineCache<bool>,
    params: wgpu::Buffer,
    history: Option<History>,
}

impl Temporal {
    /// The resolve over `passes`' module; its pipelines are built on first use.
    pub fn new(device: &wgpu::Device, passes: &SmaaPasses) -> Self {
        let layout = pass::layout(
            device,
            "smaa t2x resolve",
            &[
                (0, Binding::Uniform),
                (1, Binding::Texture),
                (2, Binding::Texture),
                (3, Binding::Texture),
                (4, Binding::Sampler),
            ],
        );
        Self {
            vertex: Vertex::new(device),
            module: passes.modes_module.clone(),
            layout,
            pipelines: PipelineCache::default(),
            params: pass::uniform_buffer::<ResolveParams>(device, "smaa t2x resolve params"),
            history: None,
        }
    }

    /// Records one T2x frame: SMAA of the jittered `input`, then the resolve into `output`.
    pub fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        passes: &mut SmaaPasses,
        settings: &SmaaSettings,
        input: &SceneTargets,
        output: &wgpu::Texture,
    ) {
        // Jittered inputs always carry motion vectors.
        let Some(motion) = input.motion.as_ref() else {
            return;
        };
        let sampler = passes.sampler.clone();
        let position = -jitter(ctx.frame.camera.frame);
        let current_frame = |ctx: &mut PassContext<'_>, current: &wgpu::TextureView| {
            let input = Input {
                color: &input.color,
                depth: &input.depth,
                motion: Some(motion),
            };
            passes.run(ctx, settings, &input, current, 0, position, "");
        };
        let frame = ResolveFrame {
            size: input.desc.size,
            motion,
            sampler: &sampler,
        };
        self.resolve(ctx, settings, &frame, output, current_frame);
    }

    /// Records the temporal resolve of one frame: `current_frame` records this frame's SMAA
    /// result, with the pixel's speed in alpha (`fs_blend_velocity`), into the view it is
    /// given; the previous frame's result is then mixed in through `frame.motion` and the
    /// result written to `output`. SMAA 4x resolves its two-sample frames with it.
    pub(crate) fn resolve(
        &mut self,
        ctx: &mut PassContext<'_>,
        settings: &SmaaSettings,
        frame: &ResolveFrame<'_>,
        output: &wgpu::Texture,
        current_frame: impl FnOnce(&mut PassContext<'_>, &wgpu::TextureView),
    ) {
        let size = frame.size;
        let radiance = holds_radiance(output);
        let format = output_format(radiance);
        let device = ctx.gpu.device.clone();
        let history = match self.history.take() {
            Some(h) if h.size == size && h.current.format() == format => History {
                valid: h.valid && h.settings == *settings && !ctx.frame.reset_history,
                settings: *settings,
                ..h
            },
            _ => History {
                size,
                settings: *settings,
                current: pass::target(&device, "smaa t2x current", size, format, &[]),
                previous: pass::target(&device, "smaa t2x previous", size, format, &[]),
                valid: false,
            },
        };
        let current = history.current.create_view(&Default::default());
        current_frame(ctx, &current);
        let params = ResolveParams {
            history: f32::from(u8::from(history.valid)),
            weight_scale: settings.reprojection_weight_scale,
            pad: [0.0; 2],
        };
        ctx.gpu
            .queue
            .write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let previous = history.previous.create_view(&Default::default());
        let motion = frame.motion.create_view(&Default::default());
        use wgpu::BindingResource::{Sampler, TextureView};
        let group = bind_group(
            &device,
            "smaa t2x resolve",
            &self.layout,
            &[
                (0, self.params.as_entire_binding()),
                (1, TextureView(&current)),
                (2, TextureView(&previous)),
                (3, TextureView(&motion)),
                (4, Sampler(frame.sampler)),
            ],
        );
        let pipeline = self.pipelines.get_or_build(radiance, |&radiance| {
            self.vertex.pipeline(
                &device,
                &PassDesc {
                    label: "smaa t2x resolve",
                    module: &self.module,
                    entry_point: "fs_resolve",
                    layout: &self.layout,
                    format,
                    constants: &[("RADIANCE", f64::from(u8::from(radiance)))],
                    stencil: Stencil::None,
                },
            )
        });
        let target = output.create_view(&Default::default());
        ctx.fullscreen_pass("resolve", &target, &pipeline, &group);
        // This frame's result is the next frame's history.
        self.history = Some(History {
            current: history.previous,
            previous: history.current,
            valid: true,
            ..history
        });
    }

    /// Memory of the two frames.
    pub fn memory(&self, id: &str) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer(
            format!("{id} resolve params"),
            &self.params,
        )];
        if let Some(h) = &self.history {
            items.push(MemoryItem::texture(
                format!("{id} current frame"),
                &h.current,
            ));
            items.push(MemoryItem::texture(
                format!("{id} previous frame"),
                &h.previous,
            ));
        }
        items
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::smaa::lut::subsample_indices;

    #[test]
    fn jitter_alternates_between_the_two_diagonal_offsets() {
        assert_eq!(jitter(0), Vec2::new(-0.25, -0.25));
        assert_eq!(jitter(1), Vec2::new(0.25, 0.25));
        assert_eq!(jitter(10), jitter(0));
        assert_eq!(JITTER[0] + JITTER[1], Vec2::ZERO);
        // The samples sit at the 2x MSAA positions, which gives the paper's sub-sample
        // indices (1, 1, 1, 0) and (2, 2, 2, 0).
        assert_eq!(subsample_indices(-jitter(0)), [1, 1, 1, 0]);
        assert_eq!(subsample_indices(-jitter(1)), [2, 2, 2, 0]);
    }
}
