//! User techniques: a post-process pass written by the user in WGSL, run beside the built-in
//! techniques on the same frame (`--technique user:PATH.wgsl`, the viewer's "Add technique
//! from file"). The contract (`docs/user-techniques.md`): the file defines
//! `fn aa_main(pixel: vec2<u32>, uv: vec2<f32>) -> vec4<f32>` returning the pixel's linear
//! colour; aa-lab places its prelude (`prelude.wgsl`: `aa_load`, `aa_sample`, `aa_depth`,
//! `aa_motion`, `aa_size`, `aa_frame`) before the file and the fragment entry point
//! (`epilogue.wgsl`) after it; `override` constants become parameters.
//!
//! [`program`] checks the file with naga before any GPU object exists, so errors name the
//! user's file, line and column; the pipeline is then built inside an error scope so that a
//! backend's refusal is an error of this technique, never a panic. All of it runs on a thread
//! of its own ([`build`]), so a shader the driver takes minutes to compile stalls neither the
//! viewer's other techniques nor the command line past `--build-timeout`.
//!
//! Input: the shared 1x render (the one No AA shows) when the code never calls `aa_motion`,
//! otherwise a 1x render with motion vectors at a zero jitter offset (the same image, plus
//! motion; one more scene render per frame). A file that calls neither `aa_depth` nor
//! `aa_motion` reads colour only and so also runs on a finished image.
//!
//! Tonemap order (`tonemap_order`, `after` by default, as engines run post passes): after the
//! tonemapper, and in every LDR frame, the file reads display values as above. Before the
//! tonemapper of an HDR frame it reads the radiance compressed with Karis' c / (1 + luma)
//! (`aa::common::perceptual`, in half floats, after the frame's exposure), and what `aa_main`
//! returns is expanded back with c / (1 - luma), the exposure taken off again, into a
//! half-float output that the graph tonemaps (the second entry point of `epilogue.wgsl`).
//! This is the contract the morphological techniques' edge tests keep, and for the same
//! reason: a user's thresholds and blends are written for values in 0..1 that look like the
//! displayed image, and raw radiance (up to 40 on `neon`) would make every one of them
//! meaningless; the file needs no change to run in either order. Blends of
//! compressed values are Karis-weighted averages of radiance (as TAA's), not plain ones. The
//! copy is in half floats, not SMAA's 8-bit sRGB, because the expansion would magnify 8-bit
//! steps near white into large radiance errors (`docs/user-techniques.md`).
//!
//! Identity: the id is `user:` followed by the file's canonical path, so that a record made
//! anywhere reproduces from any directory; records also keep the content hash
//! ([`Technique::source_hash`]), and replaying one refuses a file that has changed. Ids,
//! parameter names and help texts are `&'static str` throughout aa-lab: a user technique's
//! are interned (each distinct string is kept once for the life of the process).

pub mod build;
pub mod program;
pub mod watch;

use std::borrow::Cow;
use std::path::Path;

use glam::Vec2;

use super::params::{
    Param, ParamError, ParamField, ParamKind, ParamValue, as_bool, as_f32, as_i64,
};
use super::{FrameInfo, SceneInput, Technique};
use crate::aa::common::holds_radiance;
use crate::aa::common::pass::{self, Binding};
use crate::aa::common::perceptual::PerceptualCopy;
use crate::gpu::fullscreen::{FragmentDesc, Fullscreen};
use crate::gpu::{COLOR_FORMAT, Gpu, HDR_FORMAT};
use crate::graph::hdr::{TONEMAP_ORDER_KEY, TonemapOrder};
use crate::graph::{MemoryItem, PassContext};
use crate::scene::renderer::SceneTargets;
pub use build::{BuildWait, PendingBuild};
pub use program::{LoadError, OverrideType, Program};

/// The prefix of user technique ids.
pub const PREFIX: &str = "user:";

/// Whether an id names a user technique (`user:PATH`).
pub fn is_user_id(id: &str) -> bool {
    id.starts_with(PREFIX)
}

/// The file of a user technique id.
pub fn path_of(id: &str) -> Option<&Path> {
    id.strip_prefix(PREFIX).map(Path::new)
}

/// A file-name-safe form of a technique id: built-in ids unchanged but for the `:` before a
/// combination's upscaler (`smaa@quality-easu`), a user technique's
/// `user-<file stem>-<6 hex digits of its path's hash>`.
pub fn file_name_part(id: &str) -> Cow<'_, str> {
    let Some(path) = path_of(id) else {
        return match id.contains(':') {
            true => Cow::Owned(id.replace(':', "-")),
            false => Cow::Borrowed(id),
        };
    };
    let stem: String = path
        .file_stem()
        .map(|s| s.to_string_lossy())
        .unwrap_or_default()
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    let hash = program::content_hash(path.as_os_str().as_encoded_bytes());
    let short = &hash[hash.len() - 6..];
    Cow::Owned(format!("user-{stem}-{short}"))
}

/// The technique a `--set` target names: `user` stands for the one user technique among
/// `ids` (an error when there are several: then the full `user:PATH` is needed); any other
/// target is returned unchanged.
pub fn resolve_alias<'a>(target: &'a str, ids: &'a [String]) -> Result<&'a str, String> {
    if target != "user" {
        return Ok(target);
    }
    let users: Vec<&String> = ids.iter().filter(|id| is_user_id(id)).collect();
    match users.as_slice() {
        [only] => Ok(only.as_str()),
        [] => Err(
            "`user` names the user technique, and no `user:PATH` is among --technique".to_owned(),
        ),
        _ => Err(format!(
            "`user` is ambiguous among {} user techniques; name one as `user:PATH.KEY`",
            users.len()
        )),
    }
}

pub use crate::aa::common::intern;

/// The canonical id of the user technique in `path` (`user:` and the absolute path).
pub fn id_for(path: &Path) -> Result<String, LoadError> {
    let canonical = std::fs::canonicalize(path).map_err(|e| LoadError {
        path: path.to_owned(),
        location: None,
        message: format!("cannot read the file: {e}"),
        excerpt: None,
    })?;
    Ok(format!("{PREFIX}{}", canonical.display()))
}

/// [`id_for`], interned (the form technique ids take).
pub fn interned_id(path: &Path) -> Result<&'static str, LoadError> {
    id_for(path).map(|id| intern(&id))
}

/// The display name of a user technique id: its file's stem, marked as the user's.
pub fn display_name(id: &str) -> String {
    let path = path_of(id).unwrap_or(Path::new(id));
    let stem = path
        .file_stem()
        .map_or_else(|| id.to_owned(), |s| s.to_string_lossy().into_owned());
    format!("{stem} (user)")
}

/// Loads, checks and builds the user technique of an id (`user:PATH`) on a thread of its own,
/// waiting for it as [`build::set_build_wait`] last said (see [`build`]).
pub fn create(gpu: &Gpu, id: &str) -> Result<Box<dyn Technique>, LoadError> {
    let path = path_of(id).unwrap_or(Path::new(id));
    PendingBuild::start(gpu, interned_id(path)?).wait(build::build_wait())
}

/// Loads, checks and builds the user technique of an id on this thread.
fn build_here(gpu: &Gpu, id: &str) -> Result<Box<dyn Technique>, LoadError> {
    let path = path_of(id).unwrap_or(Path::new(id));
    let canonical = id_for(path)?;
    let program = program::load(Path::new(&canonical[PREFIX.len()..]))?;
    Ok(Box::new(UserTechnique::new(
        gpu,
        intern(&canonical),
        program,
    )?))
}

/// One `override` constant with its current value.
struct Setting {
    key: &'static str,
    help: &'static str,
    constant_key: String,
    ty: OverrideType,
    kind: ParamKind,
    value: ParamValue,
}

impl Setting {
    fn constant(&self) -> f64 {
        match self.ty {
            OverrideType::F32 => f64::from(as_f32(&self.value)),
            OverrideType::I32 | OverrideType::U32 => as_i64(&self.value) as f64,
            OverrideType::Bool => f64::from(u8::from(as_bool(&self.value))),
        }
    }
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniform {
    frame: [u32; 4],
    exposure: [f32; 4],
}

/// A user technique (see the module docs).
pub struct UserTechnique {
    id: &'static str,
    label: String,
    hash: String,
    uses_depth: bool,
    uses_motion: bool,
    settings: Vec<Setting>,
    device: wgpu::Device,
    fullscreen: Fullscreen,
    module: wgpu::ShaderModule,
    bind_group_layout: wgpu::BindGroupLayout,
    pipeline_layout: wgpu::PipelineLayout,
    /// Writes display values (after the tonemapper, LDR frames).
    pipeline: wgpu::RenderPipeline,
    /// Writes radiance; built while the order is before the tonemapper.
    radiance_pipeline: Option<wgpu::RenderPipeline>,
    tonemap_order: TonemapOrder,
    /// What the file reads before the tonemapper of an HDR frame.
    perceptual: PerceptualCopy,
    sampler: wgpu::Sampler,
    uniform: wgpu::Buffer,
    /// Bound as the motion vectors when the input has none (the code never reads them).
    no_motion: wgpu::Texture,
}

impl UserTechnique {
    fn new(gpu: &Gpu, id: &'static str, program: Program) -> Result<Self, LoadError> {
        let device = &gpu.device;
        let gpu_error = |what: &str, error: wgpu::Error| LoadError {
            path: program.path.clone(),
            location: None,
            message: format!("the GPU refused the {what}: {error}"),
            excerpt: None,
        };
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(id),
            source: wgpu::ShaderSource::Wgsl(program.combined.as_str().into()),
        });
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(gpu_error("shader", error));
        }
        let bind_group_layout = pass::layout(
            device,
            "user technique",
            &[
                (0, Binding::Texture),
                (1, Binding::Depth),
                (2, Binding::UnfilterableTexture),
                (3, Binding::Sampler),
                (4, Binding::Uniform),
            ],
        );
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("user technique"),
            bind_group_layouts: &[Some(&bind_group_layout)],
            immediate_size: 0,
        });
        let settings: Vec<Setting> = program
            .overrides
            .iter()
            .map(|o| Setting {
                key: intern(&o.name),
                help: intern(&o.help),
                constant_key: o.constant_key.clone(),
                ty: o.ty,
                kind: o.kind.clone(),
                value: o.default.clone(),
            })
            .collect();
        let fullscreen = Fullscreen::new(device);
        let scope = device.push_error_scope(wgpu::ErrorFilter::Validation);
        let pipeline = build_pipeline(
            device,
            &fullscreen,
            &module,
            &pipeline_layout,
            &settings,
            false,
        );
        if let Some(error) = pollster::block_on(scope.pop()) {
            return Err(gpu_error("pipeline", error));
        }
        Ok(Self {
            id,
            label: display_name(id),
            hash: program.hash,
            uses_depth: program.uses_depth,
            uses_motion: program.uses_motion,
            settings,
            fullscreen,
            module,
            bind_group_layout,
            pipeline_layout,
            pipeline,
            radiance_pipeline: None,
            tonemap_order: TonemapOrder::After,
            perceptual: PerceptualCopy::half_float(),
            sampler: crate::aa::common::bilinear_clamp_sampler(device, "user technique bilinear"),
            uniform: pass::uniform_buffer::<FrameUniform>(device, "user technique frame"),
            no_motion: crate::gpu::texture_2d(
                device,
                &crate::gpu::Texture2d::new(
                    "user technique no motion",
                    (1, 1),
                    crate::gpu::MOTION_FORMAT,
                    wgpu::TextureUsages::TEXTURE_BINDING,
                ),
            ),
            device: device.clone(),
        })
    }

    /// Builds the pipelines the current settings and order need, inside an error scope; on
    /// an error the old ones stay.
    fn rebuild_pipelines(&mut self) -> Result<(), wgpu::Error> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let build = |radiance| {
            build_pipeline(
                &self.device,
                &self.fullscreen,
                &self.module,
                &self.pipeline_layout,
                &self.settings,
                radiance,
            )
        };
        let pipeline = build(false);
        let radiance_pipeline = (self.tonemap_order == TonemapOrder::Before).then(|| build(true));
        match pollster::block_on(scope.pop()) {
            Some(error) => Err(error),
            None => {
                self.pipeline = pipeline;
                self.radiance_pipeline = radiance_pipeline;
                Ok(())
            }
        }
    }
}

/// The pipeline with the settings' current values as pipeline constants, writing radiance
/// (the entry point that expands the compressed colour) or display values.
fn build_pipeline(
    device: &wgpu::Device,
    fullscreen: &Fullscreen,
    module: &wgpu::ShaderModule,
    layout: &wgpu::PipelineLayout,
    settings: &[Setting],
    radiance: bool,
) -> wgpu::RenderPipeline {
    let (entry_point, target) = if radiance {
        (program::RADIANCE_ENTRY_POINT, HDR_FORMAT)
    } else {
        (program::ENTRY_POINT, COLOR_FORMAT)
    };
    let constants: Vec<(&str, f64)> = settings
        .iter()
        .map(|s| (s.constant_key.as_str(), s.constant()))
        .collect();
    fullscreen.pipeline(
        device,
        &FragmentDesc {
            label: "user technique",
            module,
            entry_point,
            targets: &[target],
            constants: &constants,
            layout: Some(layout),
        },
    )
}

impl Technique for UserTechnique {
    fn id(&self) -> &'static str {
        self.id
    }

    fn label(&self) -> String {
        self.label.clone()
    }

    fn color_only(&self) -> bool {
        !self.uses_depth && !self.uses_motion
    }

    fn scene_input(&self, _frame: &FrameInfo) -> Option<SceneInput> {
        Some(if self.uses_motion {
            SceneInput::jittered(Vec2::ZERO, 0.0)
        } else {
            SceneInput::Shared1x
        })
    }

    fn encode(
        &mut self,
        ctx: &mut PassContext<'_>,
        input: Option<&SceneTargets>,
        output: &wgpu::Texture,
    ) {
        let Some(input) = input else { return };
        // The graph hands a radiance output only to a technique ordered before the
        // tonemapper, whose radiance pipeline then exists.
        let pipeline = if holds_radiance(output) {
            self.radiance_pipeline.as_ref()
        } else {
            Some(&self.pipeline)
        };
        let Some(pipeline) = pipeline else { return };
        let frame = FrameUniform {
            frame: [ctx.frame.camera.frame as u32, 0, 0, 0],
            exposure: [ctx.exposure_scale(), 0.0, 0.0, 0.0],
        };
        ctx.gpu
            .queue
            .write_buffer(&self.uniform, 0, bytemuck::bytes_of(&frame));
        let color =
            (self.perceptual.source(ctx, input.color_1x(), "")).create_view(&Default::default());
        let depth = input.depth.create_view(&wgpu::TextureViewDescriptor {
            aspect: wgpu::TextureAspect::DepthOnly,
            ..Default::default()
        });
        let motion = input
            .motion
            .as_ref()
            .unwrap_or(&self.no_motion)
            .create_view(&Default::default());
        let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("user technique"),
            layout: &self.bind_group_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&color),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&depth),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::TextureView(&motion),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::Sampler(&self.sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: self.uniform.as_entire_binding(),
                },
            ],
        });
        let target = output.create_view(&Default::default());
        ctx.fullscreen_pass("user", &target, pipeline, &bind_group);
    }

    fn memory(&self) -> Vec<MemoryItem> {
        let mut items = vec![MemoryItem::buffer("user technique frame", &self.uniform)];
        items.extend(self.perceptual.memory(self.id));
        items
    }

    fn tonemap_order(&self) -> TonemapOrder {
        self.tonemap_order
    }

    fn params(&self) -> Vec<Param> {
        self.settings
            .iter()
            .map(|s| Param {
                key: s.key,
                label: s.key,
                help: s.help,
                kind: s.kind.clone(),
                value: s.value.clone(),
            })
            .chain([self.tonemap_order.param()])
            .collect()
    }

    fn set_param(&mut self, key: &str, value: &ParamValue) -> Result<(), ParamError> {
        let previous_order = self.tonemap_order;
        let previous_setting = if key == TONEMAP_ORDER_KEY {
            self.tonemap_order.assign(value);
            None
        } else {
            let Some(index) = self.settings.iter().position(|s| s.key == key) else {
                return Err(ParamError::unknown_key(self.id, key, &self.params()));
            };
            let previous = std::mem::replace(&mut self.settings[index].value, value.clone());
            Some((index, previous))
        };
        let Err(error) = self.rebuild_pipelines() else {
            return Ok(());
        };
        self.tonemap_order = previous_order;
        if let Some((index, previous)) = previous_setting {
            self.settings[index].value = previous;
        }
        Err(ParamError::BadValue {
            technique: self.id.to_owned(),
            key: key.to_owned(),
            reason: format!("the GPU refused the pipeline with {value}: {error}"),
        })
    }

    fn source_hash(&self) -> Option<String> {
        Some(self.hash.clone())
    }
}
