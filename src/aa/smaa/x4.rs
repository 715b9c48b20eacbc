//! SMAA 4x, the top mode of Jorge Jimenez, Jose I. Echevarria, Tiago Sousa and Diego
//! Gutierrez, "SMAA: Enhanced Subpixel Morphological Antialiasing" (Eurographics 2012): SMAA
//! S2x and T2x combined. Every frame takes two samples per pixel at the standard 2x MSAA
//! positions, shifted by an eighth of a pixel one way on even frames and the other way on odd
//! frames ([`SHIFT`]); each sample gets SMAA 1x with the area sub-tables of its position, the
//! two results are averaged, and the average is resolved with the previous frame's through
//! motion vectors, exactly as T2x resolves its frames. Over two frames a pixel sees four
//! samples on a rotated grid, whose sub-sample indices are the paper's (5, 3, 1, 3),
//! (4, 6, 2, 3), (3, 5, 1, 4) and (6, 4, 2, 4).
//!
//! The two samples come from a jittered 2x MSAA render the technique makes itself (the frame
//! graph's shared renders are either jittered or multisampled, not both) where the adapter has
//! 2x MSAA, read sample by sample; elsewhere (software Vulkan offers only 1x and 4x) from two
//! jittered 1x renders at the samples' positions, as SMAA S2x falls back
//! ([`S2xPath::Renders`]); [`Technique::path_note`] says which.
//!
//! Built from the parts of the SMAA family's folder: its passes, S2x's sample copy and average, T2x's
//! resolve, settings and presets (`low` .. `ultra`, with T2x's velocity weighting and mip
//! bias). Debug views: edges and blending weights of the first sample.
//!
//! Before the tonemapper of an HDR frame (`tonemap_order`) the renders are radiance, each
//! sample's SMAA runs on it, and both the average and the resolve are Karis-weighted (see the
//! SMAA module docs).
//!
//! Figures: `docs/techniques/smaa.md`.

use glam::Vec2;

use super::multisample::{Multisample, S2xPath, sample_offsets};
use super::passes::{Input, SmaaPasses};
use super::temporal::{ResolveFrame, Temporal};
use super::{SmaaSettings, s2x_availability};
use crate::aa::common::pass::{self, Binding, PassDesc, Stencil, bind_group, cleared};
use crate::aa::common::{holds_radiance, output_format};
use crate::aa::info::TechniqueInfo;
use crate::aa::{DebugView, FrameInfo, SceneInput, Technique};
use crate::gpu::shader::Shader;
use crate::gpu::{Gpu, MOTION_FORMAT};
use crate::graph::hdr::TonemapOrder;
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::{RasterOptions, SceneTargets, TargetDesc};

/// Stable id, as on the command line.
pub const ID: &str = "smaa-4x";

/// The first sample's motion vectors copied out of the jittered 2x render.
const WGSL: Shader = crate::wgsl!("src/aa/smaa/smaa_4x.wgsl");

/// The registry entry.
pub const INFO: TechniqueInfo = TechniqueInfo {
    id: ID,
    name: "SMAA 4x",
    summary: "SMAA S2x and T2x combined, the top mode of the SMAA paper: every frame SMAA 1x runs on \
         each sample of a two-sample render, the two are averaged, and the result is mixed with the \
         previous frame's through motion vectors; the samples shift by an eighth of a pixel between \
         frames, so a still pixel sees four sample positions. The sharpest SMAA on thin geometry, at \
         the cost of a 2x render, two SMAA runs and T2x's temporal risks (ghosting where the \
         history cannot be matched). Without 2x MSAA on the adapter it renders the scene twice per \
         frame at the two positions instead, as S2x does.",
    availability: s2x_availability,
    create: |gpu| Box::new(Smaa4x::new(gpu)),
    shaders: &[WGSL],
};

/// Shift of both samples from the standard 2x positions on even and odd frames, in pixels
/// (x right, y down).
pub const SHIFT: [Vec2; 2] = [Vec2::new(-0.125, 0.125), Vec2::new(0.125, -0.125)];

/// The two sample positions of a frame, relative to the pixel centre (pixels, y down).
pub fn sample_positions(frame: u64) -> [Vec2; 2] {
    let shift = SHIFT[(frame % 2) as usize];
    sample_offsets().map(|offset| offset + shift)
}

struct Targets {
    size: (u32, u32),
    /// The jittered two-sample render ([`S2xPath::Msaa`] only).
    multisampled: Option<SceneTargets>,
    /// One sample's colour and depth; with motion vectors on [`S2xPath::Renders`].
    sample: SceneTargets,
    /// The first sample's motion vectors copied out of `multisampled`.
    motion: Option<wgpu::Texture>,
    /// SMAA of each sample.
    results: [wgpu::Texture; 2],
}

impl Targets {
    /// The targets of `path` at `size`, of radiance or display values.
    fn new(gpu: &Gpu, path: S2xPath, size: (u32, u32), radiance: bool) -> Self {
        let msaa = path == S2xPath::Msaa;
        let scene = |label, sample_count, motion| {
            SceneTargets::new(
                gpu,
                label,
                TargetDesc {
                    size,
                    sample_count,
                    motion,
                    hdr: radiance,
                    reactive_mask: false,
                },
            )
        };
        let target = |label: &str, format| pass::target(&gpu.device, label, size, format, &[]);
        Self {
            size,
            multisampled: msaa.then(|| scene("smaa 4x scene 2x", 2, true)),
            sample: scene("smaa 4x sample", 1, !msaa),
            motion: msaa.then(|| target("smaa 4x motion", MOTION_FORMAT)),
            results: [0, 1]
                .map(|i| target(&format!("smaa 4x sample {i}"), output_format(radiance))),
        }
    }

    /// The motion vectors of this frame, whichever path wrote them.
    fn motion(&self) -> Option<&wgpu::Texture> {
        self.motion.as_ref().or(self.sample.motion.as_ref())
    }
}

/// The SMAA 4x technique.
pub struct Smaa4x {
    settings: SmaaSettings,
    passes: SmaaPasses,
    multisample: Multisample,
    temporal: Temporal,
    extract_motion_layout: wgpu::BindGroupLayout,
    extract_motion: wgpu::RenderPipeline,
    targets: Option<Targets>,
    debug_enabled: bool,
}

impl Smaa4x {
    /// SMAA 4x with the default (High) settings, on this adapter's path.
    pub fn new(gpu: &Gpu) -> Self {
        let device = &gpu.device;
        let passes = SmaaPasses::new(gpu);
        let extract_motion_layout = pass::layout(
            device,
            "smaa 4x extract motion",
            &[(0, Binding::MultisampledTexture)],
        );
        let module = WGSL.module(device);
        let extract_motion = passes.vertex.pipeline(
            device,
            &PassDesc {
                label: "smaa 4x extract motion",
                module: &module,
                entry_point: "fs_extract_motion",
                layout: &extract_motion_layout,
                format: MOTION_FORMAT,
                constants: &[],
                stencil: Stencil::None,
            },
        );
        Self {
            settings: SmaaSettings::default(),
            multisample: Multisample::new(device, &gpu.caps, &passes),
            temporal: Temporal::new(device, &passes),
            passes,
            extract_motion_layout,
            extract_motion,
            targets: None,
            debug_enabled: false,
        }
    }

    /// The current settings.
    pub fn settings(&self) -> &SmaaSettings {
        &self.settings
    }
}

/// Records the jittered 2x render and copies its first sample's motion vectors out.
fn render_multisampled(
    ctx: &mut PassContext<'_>,
    extract: (&wgpu::RenderPipeline, &wgpu::BindGroupLayout),
    scene: &SceneTargets,
    motion: &wgpu::Texture,
    shift: Vec2,
    mip_bias: f32,
) {
    let view = ctx.frame.camera.params(-shift, mip_bias);
    ctx.render_scene("scene 2x", scene, &view, RasterOptions::default());
    let Some(samples_motion) = &scene.motion else {
        return;
    };
    let source = samples_motion.create_view(&Default::default());
    let group = bind_group(
        &ctx.gpu.device,
        "smaa 4x extract motion",
        extract.1,
        &[(0, wgpu::BindingResource::TextureView(&source))],
    );
    let target = motion.create_view(&Default::default());
    ctx.render_pass("extract motion", &[Some(cleared(&target))], None, |pass| {
        pass.set_pipeline(extract.0);
        pass.set_bind_group(0, &group, &[]);
        pass.draw(0..3, 0..1);
    });
}

impl Technique for Smaa4x {
    fn id(&self) -> &'static str {
        ID
    }

    fn label(&self) -> String {
        INFO.name.to_owned()
    }

    /// SMAA 4x renders the scene itself: jittered and, where it can, multisampled.
    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        None
    }

    fn temporal(&self) -> bool {
        true
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        _input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let size = ctx.frame.size();
        let path = self.multisample.path();
        let radiance = holds_radiance(output);
        if (self.targets.as_ref()).is_none_or(|t| t.size != size || t.sample.desc.hdr != radiance) {
            self.targets = Some(Targets::new(ctx.gpu, path, size, radiance));
        }
        let Self {
            settings,
            passes,
            multisample,
            temporal,
            extract_motion_layout,
            extract_motion,
            targets,
            debug_enabled,
        } = self;
        let (settings, debug_enabled) = (&*settings, *debug_enabled);
        let Some(targets) = targets.as_ref() else {
            return;
        };
        let Some(motion) = targets.motion() else {
            return;
        };
        let frame = ctx.frame.camera.frame;
        let shift = SHIFT[(frame % 2) as usize];
        let sampler = passes.sampler.clone();
        let current_frame = |ctx: &mut PassContext<'_>, current: &wgpu::TextureView| {
            if let (Some(scene), Some(motion)) = (&targets.multisampled, &targets.motion) {
                let extract = (&*extract_motion, &*extract_motion_layout);
                render_multisampled(ctx, extract, scene, motion, shift, settings.mip_bias);
            }
            for (sample, position) in sample_positions(frame).into_iter().enumerate() {
                match &targets.multisampled {
                    Some(scene) => multisample.copy_sample(ctx, scene, &targets.sample, sample),
                    None => {
                        // The sample at `position` from the centre: the image moves by -position.
                        let view = ctx.frame.camera.params(-position, settings.mip_bias);
                        ctx.render_scene(
                            &format!("sample {sample} scene"),
                            &targets.sample,
                            &view,
                            RasterOptions::default(),
                        );
                    }
                }
                let input = Input {
                    color: &targets.sample.color,
                    depth: &targets.sample.depth,
                    motion: Some(motion),
                };
                let result = targets.results[sample].create_view(&Default::default());
                let prefix = format!("sample {sample} ");
                passes.run(ctx, settings, &input, &result, sample, position, &prefix);
                if debug_enabled && sample == 0 {
                    passes.encode_debug(ctx);
                }
            }
            multisample.average(ctx, &targets.results, current);
        };
        let resolve = ResolveFrame {
            size,
            motion,
            sampler: &sampler,
        };
        temporal.resolve(ctx, settings, &resolve, output, current_frame);
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.settings.tonemap_order
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let id = self.id();
        let mut items = self.passes.memory(id);
        items.extend(self.temporal.memory(id));
        if let Some(t) = &self.targets {
            let scenes = [
                ("scene 2x", t.multisampled.as_ref()),
                ("sample", Some(&t.sample)),
            ];
            for (label, scene) in scenes {
                for (name, texture) in scene.into_iter().flat_map(SceneTargets::textures) {
                    items.push(MemoryItem::texture(format!("{id} {label} {name}"), texture));
                }
            }
            if let Some(motion) = &t.motion {
                items.push(MemoryItem::texture(format!("{id} motion"), motion));
            }
            for (i, r) in t.results.iter().enumerate() {
                items.push(MemoryItem::texture(format!("{id} sample {i} result"), r));
            }
        }
        items
    }

    crate::aa::common::tunable_settings!(settings);

    fn set_debug_views(&mut self, enabled: bool) {
        self.debug_enabled = enabled;
    }

    fn debug_views(&self) -> Vec<DebugView<'_>> {
        self.passes.debug_views(
            self.debug_enabled,
            [
                "Edges SMAA found in this frame's first sample: red on a pixel's left \
                              side, green on its top side, yellow both.",
                "Blending weights of this frame's first sample: red blends across the \
                              pixel's top edge, green across its left edge, brighter is more \
                              (doubled).",
            ],
        )
    }

    fn path_note(&self) -> Option<String> {
        let samples = match self.multisample.path() {
            S2xPath::Msaa => {
                "SMAA on each sample of a jittered 2x MSAA render, averaged".to_owned()
            }
            S2xPath::Renders => S2xPath::Renders.describe().to_owned(),
        };
        Some(format!(
            "{samples}; the samples shift by 1/8 pixel each frame and the temporal resolve mixes \
             two frames (4 sample positions); {}",
            super::settings_note(&self.settings)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aa::smaa::lut::subsample_indices;

    #[test]
    fn samples_give_the_papers_4x_subsample_indices() {
        let indices: Vec<[u32; 4]> = [0, 1]
            .into_iter()
            .flat_map(|frame| sample_positions(frame).map(subsample_indices))
            .collect();
        assert_eq!(
            indices,
            [[5, 3, 1, 3], [4, 6, 2, 3], [3, 5, 1, 4], [6, 4, 2, 4]]
        );
        // Four distinct columns and rows over two frames: a rotated grid.
        let all: Vec<Vec2> = [0, 1].into_iter().flat_map(sample_positions).collect();
        for (i, a) in all.iter().enumerate() {
            for b in &all[i + 1..] {
                assert!(
                    a.x != b.x && a.y != b.y,
                    "{a} and {b} share a row or column"
                );
            }
        }
        assert_eq!(sample_positions(2), sample_positions(0));
    }
}
