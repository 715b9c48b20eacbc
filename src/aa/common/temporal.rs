//! What the temporal techniques (TAA, the temporal upscaler) share: the Halton(2,3) jitter
//! sequence, the test that a camera continues the history's and when the history restarts,
//! a ping-pong pair of history textures, the pieces a resolve pass is built from, the
//! choices of history filter and rectification, and the falloff of the history's share under
//! motion. Each technique keeps its
//! own resolve; these are the pieces that mean the same in both.

use std::fmt::Debug;
use std::hash::Hash;

use glam::Vec2;

use super::pass::{self, Binding};
use super::sampling::halton;
use super::{PipelineCache, bilinear_clamp_sampler};
use crate::aa::FrameInfo;
use crate::gpu::Gpu;
use crate::gpu::fullscreen::FragmentDesc;
use crate::gpu::shader::Shader;
use crate::graph::PassContext;
use crate::graph::params::Param;
use crate::scene::camera::FrameCamera;

crate::named_enum! {
    /// How the reprojected history is read.
    pub enum HistoryFilter {
        /// One bilinear tap (cheap, blurs a little more every frame the camera moves).
        Bilinear => "bilinear",
        /// Five-tap bilinear-optimised Catmull-Rom (keeps the history sharp under motion).
        CatmullRom => "catmull-rom",
    }
}

crate::named_enum! {
    /// How the history is made consistent with the current frame.
    pub enum Rectify {
        /// Not at all: moving content leaves ghost trails (for comparison).
        None => "none",
        /// Per-channel clamp to the 3x3 neighbourhood's RGB min/max.
        Clamp => "clamp",
        /// Clip towards the centre of the neighbourhood's YCoCg min/max box (Karis).
        Clip => "clip",
        /// Clip to the YCoCg variance box mean +/- gamma sigma, within min/max (Salvi).
        Variance => "variance",
    }
}

/// The default falloff length of the history under motion, in pixels per frame, of both the
/// parallax around the pixel (TAA, and the temporal upscaler at native scale) and the speed;
/// measured under the orbit at three sizes: `docs/techniques/taa.md`, `docs/upscaling.md`.
pub const MOTION_FALLOFF: f32 = 16.0;

/// The setting of the history's falloff with the parallax: the history's share (TAA) or
/// samples (the temporal upscaler, at native scale only) are multiplied by
/// exp(-parallax / `length`) (off at 0). Parallax is how differently the
/// nearest and the farthest surface of the resolve's depth search move: one motion vector
/// cannot carry a pixel whose surfaces part (the strands of a tangle, a silhouette over a far
/// background), and its history then holds colours that belong elsewhere, more the faster
/// they part.
pub fn parallax_falloff_param(length: f32) -> Param {
    Param::float(
        "parallax_falloff",
        "Parallax falloff",
        "Parallax in pixels per frame (how differently the nearest and the farthest surface \
         around the pixel move) over which the history's weight falls to 1/e. One motion vector \
         cannot carry a pixel whose surfaces part: the strands of a tangle, a silhouette over a \
         far background; its history holds colours that belong elsewhere, more the faster they \
         part. Smaller follows the current frame sooner (sharper, a little more aliasing); 0 \
         turns the falloff off. The temporal upscaler applies it at native scale only: below \
         it, its current estimate reaches past the pixel's neighbours.",
        0.0,
        64.0,
        length,
    )
}

/// The default parallax falloff length at a silhouette over a broad background (TAA), in
/// pixels per frame: measured at three sizes, frames 16 and 40, on hairball and atrium
/// (`docs/techniques/taa.md`).
pub const SILHOUETTE_FALLOFF: f32 = 2.0;

/// The setting of the parallax falloff where the farthest surface around the pixel is broad:
/// the falloff length moves from `parallax_falloff`'s towards `length` as the farthest
/// surface's share of the depths the resolve searched rises from 2 of 7 to 6 of 7 (off at 0).
/// A foreground edge over a wide background (a column before a wall) then leans on the current
/// frame as soon as the two part, while a tangle of strands over other strands, whose
/// farthest surface is as thin as its nearest, keeps its history: the one parallax length
/// had to choose between them (`docs/techniques/taa.md`).
pub fn silhouette_falloff_param(length: f32) -> Param {
    Param::float(
        "silhouette_falloff",
        "Silhouette falloff",
        "Parallax in pixels per frame over which the history's weight falls to 1/e where the \
         farthest surface around the pixel is broad: an edge over a wide background, such as \
         a column before a wall. It takes over from the parallax falloff as the farthest \
         surface's share of the depths searched rises from 2 of 7 to 6 of 7, so a tangle of \
         strands over other strands keeps the parallax falloff's longer history while a \
         silhouette follows the current frame as soon as its surfaces part. 0 turns it off \
         (the parallax falloff everywhere).",
        0.0,
        64.0,
        length,
    )
}

/// The setting of the history's falloff with the speed: the history's weight is multiplied by
/// exp(-speed / `length`) (off at 0).
pub fn speed_falloff_param(length: f32) -> Param {
    Param::float(
        "speed_falloff",
        "Speed falloff",
        "Speed in pixels per frame over which the history's weight falls to 1/e: the faster the \
         image moves, the more the current frame counts. Under a moving camera the history \
         keeps less of the scene's detail the faster it moves, more than the blur of each read \
         between texels accounts for (measured: docs/techniques/taa.md). 0 turns the falloff \
         off.",
        0.0,
        64.0,
        length,
    )
}

/// A falloff length as the shader's rate: 1 / `length`, or 0 (no falloff) for 0.
pub fn falloff_rate(length: f32) -> f32 {
    if length > 0.0 { 1.0 / length } else { 0.0 }
}

/// The jitter offset of a frame in render pixels (content moves by it; the pixel's sample sits
/// at its centre minus the offset): element `frame mod phases` + 1 of Halton(2,3), centred, so
/// offsets lie in [-0.5, 0.5). Index 0 of the sequence (the origin) is skipped.
pub fn jitter_offset(frame: u64, phases: u32) -> Vec2 {
    let index = (frame % u64::from(phases.max(1))) as u32 + 1;
    Vec2::new(halton(index, 2), halton(index, 3)) - Vec2::splat(0.5)
}

/// Whether `next` continues the history made with `last`: the same frame again, or the next
/// frame from the pose the history was made with, at the same size.
pub fn continues(last: &FrameCamera, next: &FrameCamera) -> bool {
    let same = next.frame == last.frame && next.pose == last.pose;
    let following = next.frame == last.frame + 1 && next.prev_pose == last.pose;
    (same || following) && next.size == last.size && next.render_size == last.render_size
}

/// A colour attachment cleared to black and stored.
pub fn cleared_black(view: &wgpu::TextureView) -> Option<wgpu::RenderPassColorAttachment<'_>> {
    Some(wgpu::RenderPassColorAttachment {
        view,
        depth_slice: None,
        resolve_target: None,
        ops: wgpu::Operations {
            load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
            store: wgpu::StoreOp::Store,
        },
    })
}

/// Two textures a temporal resolve reads one of and writes the other, in turn.
pub struct PingPong {
    /// The pair.
    pub textures: [wgpu::Texture; 2],
    /// Which holds the latest result.
    pub latest: usize,
    /// False until a frame has been resolved into `textures[latest]`.
    pub valid: bool,
}

impl PingPong {
    /// A pair of textures of `size` and `format`, labelled `LABEL a` and `b`, sampled and
    /// written as storage textures. The resolves store their history rather than export it
    /// to a render target: an export goes through the GPU's fixed-function output stage,
    /// which on the compute GPUs aa-lab was measured on (NVIDIA H200) costs in proportion to
    /// the bytes written and was most of TAAU's resolve with three targets
    /// (docs/upscaling.md); a history needs no blending, so a store does the same job.
    pub fn new(
        device: &wgpu::Device,
        label: &str,
        size: (u32, u32),
        format: wgpu::TextureFormat,
    ) -> Self {
        let texture = |suffix: &str| {
            crate::gpu::texture_2d(
                device,
                &crate::gpu::Texture2d::new(
                    &format!("{label} {suffix}"),
                    size,
                    format,
                    wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::TEXTURE_BINDING,
                ),
            )
        };
        Self {
            textures: [texture("a"), texture("b")],
            latest: 0,
            valid: false,
        }
    }

    /// The size of the textures.
    pub fn size(&self) -> (u32, u32) {
        (self.textures[0].width(), self.textures[0].height())
    }

    /// The texture holding the latest result.
    pub fn read(&self) -> &wgpu::Texture {
        &self.textures[self.latest]
    }

    /// The texture the next result goes to.
    pub fn write(&self) -> &wgpu::Texture {
        &self.textures[1 - self.latest]
    }

    /// Makes the texture just written the latest.
    pub fn swap(&mut self) {
        self.latest = 1 - self.latest;
        self.valid = true;
    }
}

/// When a temporal technique's history must start again: on the frame's request, after a
/// setting changed ([`HistoryReset::invalidate`]), and when the camera does not continue the
/// one the history was made with.
pub struct HistoryReset {
    pending: bool,
    last_camera: Option<FrameCamera>,
}

impl Default for HistoryReset {
    fn default() -> Self {
        Self {
            pending: true,
            last_camera: None,
        }
    }
}

impl HistoryReset {
    /// The next frame starts a new history.
    pub fn invalidate(&mut self) {
        self.pending = true;
    }

    /// Whether `frame` starts a new history; remembers its camera.
    pub fn restarts(&mut self, frame: &FrameInfo) -> bool {
        let camera = frame.camera;
        let reset = frame.reset_history
            || self.pending
            || !self
                .last_camera
                .is_some_and(|last| continues(&last, &camera));
        self.pending = false;
        self.last_camera = Some(camera);
        reset
    }
}

/// What a temporal resolve is built from: its shader module, one explicit bind-group layout
/// that every pipeline variant shares (whatever bindings its override constants leave
/// unused), the history's bilinear sampler, a uniform buffer, and the pipeline variants by
/// what they are specialised on.
pub struct ResolvePass<K> {
    /// The device.
    pub device: wgpu::Device,
    /// The bind-group layout.
    pub layout: wgpu::BindGroupLayout,
    /// The history sampler (bilinear, clamped).
    pub sampler: wgpu::Sampler,
    /// The uniform buffer.
    pub uniform: wgpu::Buffer,
    label: &'static str,
    module: wgpu::ShaderModule,
    pipeline_layout: wgpu::PipelineLayout,
    pipelines: PipelineCache<K>,
}

impl<K: Eq + Hash + Debug> ResolvePass<K> {
    /// The pieces of the resolve `label` in `shader`, with `bindings` and a uniform of `U`.
    pub fn new<U>(
        gpu: &Gpu,
        label: &'static str,
        shader: &Shader,
        bindings: &[(u32, Binding)],
    ) -> Self {
        let device = &gpu.device;
        let layout = pass::layout(device, label, bindings);
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        Self {
            device: device.clone(),
            sampler: bilinear_clamp_sampler(device, &format!("{label} history")),
            uniform: pass::uniform_buffer::<U>(device, &format!("{label} params")),
            module: shader.module(device),
            label,
            layout,
            pipeline_layout,
            pipelines: PipelineCache::default(),
        }
    }

    /// The pipeline of `key`: `entry_point` writing `targets`, with override `constants`.
    pub fn pipeline(
        &mut self,
        ctx: &PassContext<'_>,
        key: K,
        entry_point: &str,
        targets: &[wgpu::TextureFormat],
        constants: &[(&str, f64)],
    ) -> wgpu::RenderPipeline {
        let (device, module, layout) = (&self.device, &self.module, &self.pipeline_layout);
        let label = self.label;
        self.pipelines.get_or_build(key, |key| {
            ctx.fullscreen.pipeline(
                device,
                &FragmentDesc {
                    label: &format!("{label} {entry_point} {key:?}"),
                    module,
                    entry_point,
                    targets,
                    constants,
                    layout: Some(layout),
                },
            )
        })
    }

    /// Writes this frame's uniform block.
    pub fn write_uniform<U: bytemuck::Pod>(&self, ctx: &PassContext<'_>, uniform: &U) {
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(uniform));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jitter_is_centred_halton_and_repeats() {
        assert_eq!(jitter_offset(0, 8), Vec2::new(0.0, 1.0 / 3.0 - 0.5));
        assert_eq!(jitter_offset(1, 8), Vec2::new(-0.25, 2.0 / 3.0 - 0.5));
        for phases in [8u32, 16, 18, 32] {
            let offsets: Vec<Vec2> = (0..u64::from(phases))
                .map(|f| jitter_offset(f, phases))
                .collect();
            assert!(
                offsets
                    .iter()
                    .all(|o| o.cmpge(Vec2::splat(-0.5)).all() && o.cmplt(Vec2::splat(0.5)).all())
            );
            // Distinct positions, no repeat within a cycle, then the cycle repeats.
            for (i, a) in offsets.iter().enumerate() {
                for b in &offsets[i + 1..] {
                    assert!((*a - *b).length() > 1e-3);
                }
            }
            assert_eq!(jitter_offset(u64::from(phases) + 3, phases), offsets[3]);
            // Low discrepancy: the mean offset of a cycle is near the pixel centre.
            let mean = offsets.iter().copied().sum::<Vec2>() / phases as f32;
            assert!(mean.length() < 0.08, "{phases}: {mean}");
            // Every quadrant of the pixel gets samples.
            for quadrant in 0..4 {
                let (sx, sy) = (quadrant % 2 == 0, quadrant / 2 == 0);
                assert!(
                    offsets
                        .iter()
                        .any(|o| (o.x < 0.0) == sx && (o.y < 0.0) == sy),
                    "{phases} {quadrant}"
                );
            }
        }
    }

    #[test]
    fn a_camera_continues_on_the_next_frame_from_its_own_pose_or_on_a_repeat() {
        let rig = crate::scene::CameraRig::default();
        let at = |frame| FrameCamera::from_rig(&rig, frame, (64, 36));
        assert!(continues(&at(4), &at(5)));
        assert!(continues(&at(5), &at(5)));
        assert!(!continues(&at(4), &at(6)), "a skipped frame");
        assert!(!continues(&at(5), &at(4)), "going back");
        let mut moved = at(5);
        moved.prev_pose.distance += 1.0;
        assert!(!continues(&at(4), &moved), "a cut");
        let mut resized = at(5);
        resized.size = (32, 18);
        assert!(!continues(&at(4), &resized), "a resize");
        let rescaled = at(5).at_render_size((32, 18));
        assert!(!continues(&at(4), &rescaled), "a new render size");
    }
}
