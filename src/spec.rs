//! A complete, reproducible description of a render ([`RenderSpec`]: scene, size, frame,
//! camera, techniques with every setting) and the headless runner that turns it into images.
//!
//! Every exported image embeds its spec (plus the adapter and build that produced it), and
//! `aa-lab render --from` runs the spec again, so results can be reproduced bit-exactly on the
//! same adapter. Frame N of a temporal technique means running frames 0..=N of the
//! deterministic camera: warm-up frames run only the temporal techniques.
//!
//! A record is read strictly ([`parse_record`]): a field it does not know (a typo such as
//! `yaw` for `yaw_degrees`), a value of the wrong type and a camera number that is not a finite
//! `f32` are errors naming the field's path (`camera.pitch_degrees`), because a record that
//! silently fell back to defaults would render another picture than the one it describes.
//! Fields left out still take their defaults.

use crate::aa::{self, FrameInfo, ParamMap, TechniqueError};
use crate::gpu::{Gpu, read_texture_rgba8, readback::ReadbackError};
use crate::graph::hdr::TonemapChoice;
use crate::graph::overlay::OverlayOrder;
use crate::graph::{FrameGraph, FrameScope, FrameTimings, GraphError, MemoryReport};
use crate::scene::Scene;
use crate::scene::camera::{FrameCamera, OrbitPose};
use crate::scene::procedural::SceneOptions;

/// One technique with its settings.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TechniqueSpec {
    /// Registry id.
    pub id: String,
    /// Every parameter's value (missing keys keep their defaults).
    #[serde(default)]
    pub settings: ParamMap,
    /// A user technique's content hash (see `aa::user`): the file must still hash to it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source_hash: Option<String>,
}

impl TechniqueSpec {
    /// The record of a technique as it is set up now.
    pub fn of(technique: &dyn aa::Technique) -> Self {
        Self {
            id: technique.id().to_owned(),
            settings: aa::param_map(technique),
            source_hash: technique.source_hash(),
        }
    }

    /// Creates the technique this entry records, with its settings, refusing a user technique
    /// whose file changed since the record was made.
    pub fn create(&self, gpu: &Gpu) -> Result<Box<dyn aa::Technique>, TechniqueError> {
        let mut technique = aa::create(gpu, &self.id)?;
        if let (Some(recorded), Some(current)) = (&self.source_hash, technique.source_hash())
            && *recorded != current
        {
            return Err(TechniqueError::SourceChanged {
                path: aa::user::path_of(&self.id)
                    .map_or_else(|| self.id.clone(), |p| p.display().to_string()),
                recorded: recorded.clone(),
                current,
            });
        }
        aa::apply_param_map(technique.as_mut(), &self.settings)?;
        Ok(technique)
    }
}

/// Everything that determines a render.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RenderSpec {
    /// Built-in scene name or OBJ path.
    pub scene: String,
    /// Built-in scene density (hairball triangle count scale).
    #[serde(default = "default_density")]
    pub density: f32,
    /// Built-in scene seed.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Geometric specular antialiasing in the techniques' scene renders, never in the
    /// reference's ([`FrameGraph::set_specular_aa`]); left out of a record when off.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub specular_aa: bool,
    /// How the scene's radiance is displayed (`--tonemap`): `auto` (left out of a record) puts
    /// HDR scenes through the default tonemapper and leaves the others on the LDR path.
    #[serde(default, skip_serializing_if = "TonemapChoice::is_auto")]
    pub tonemap: TonemapChoice,
    /// Exposure of an HDR render in stops (`--exposure`); left out of a record when 0.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub exposure: f32,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Frame number of the deterministic camera and animation.
    pub frame: u64,
    /// A fixed camera pose (the viewer's): every frame is seen from it. `None` follows the
    /// camera path (`rig`, else the scene's). Any field left out takes its default (see
    /// [`OrbitPose`]).
    #[serde(default)]
    pub camera: Option<OrbitPose>,
    /// A camera path replacing the scene's default view (`--camera-eye`/`--camera-look-at`,
    /// `--fov`, `--camera-motion`); frame N turns `N * orbit_degrees_per_frame` about its
    /// target. Any field left out takes its default (see [`crate::scene::CameraRig`]).
    #[serde(default)]
    pub rig: Option<crate::scene::CameraRig>,
    /// Image mode: the full path of a finished PNG/JPEG image the techniques ran on instead
    /// of a render of `scene` (then only a label); `None` renders the scene.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub image: Option<String>,
    /// Techniques in output order.
    pub techniques: Vec<TechniqueSpec>,
    /// The UI overlay and where it is drawn (`--ui-overlay`); `None`: no overlay.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overlay: Option<OverlayOrder>,
    /// Adapter that produced the image (informational; not used when rendering).
    #[serde(default)]
    pub adapter: Option<String>,
    /// aa-lab version and commit that produced the image (informational).
    #[serde(default)]
    pub build: Option<String>,
}

impl RenderSpec {
    /// The tonemap this spec renders `scene` with (`None`: the LDR path).
    pub fn tonemap_of(&self, scene: &Scene) -> Option<crate::scene::renderer::Tonemap> {
        self.tonemap.resolve(scene.is_hdr(), self.exposure)
    }
}

/// Largest frame number of a render: temporal techniques run every frame up to it, so a
/// larger one would take days and overflow frame arithmetic.
pub const MAX_FRAME: u64 = 1_000_000;

fn is_zero(value: &f32) -> bool {
    *value == 0.0
}

fn default_density() -> f32 {
    1.0
}

fn default_seed() -> u64 {
    SceneOptions::default().seed
}

/// Why a render record's JSON was refused; every message names the field's path.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// Fields a render record does not have (misspelt, or from another program).
    #[error(
        "unknown field(s) {}: a render record has no such field (a misspelt name would \
         silently render another picture)",
        .0.join(", ")
    )]
    UnknownFields(Vec<String>),
    /// A value of the wrong type, out of range, or JSON that is not well formed.
    #[error("{path}: {message}")]
    BadValue {
        /// The field's path (`camera.pitch_degrees`, `techniques[0].id`; `.` for the whole).
        path: String,
        /// The parser's message.
        message: String,
    },
}

/// Parses a render record's JSON strictly (see the module docs).
pub fn parse_record(text: &str) -> Result<RenderSpec, RecordError> {
    let mut unknown = Vec::new();
    let mut json = serde_json::Deserializer::from_str(text);
    // serde_ignored writes `?` for the inside of an `Option`: `camera.?.yaw` is `camera.yaw`.
    let mut note_unknown = |path: serde_ignored::Path<'_>| {
        let path = path.to_string();
        let parts: Vec<&str> = path.split('.').filter(|part| *part != "?").collect();
        unknown.push(parts.join("."));
    };
    let tracked = serde_ignored::Deserializer::new(&mut json, &mut note_unknown);
    let spec: RenderSpec =
        serde_path_to_error::deserialize(tracked).map_err(|error| RecordError::BadValue {
            path: error.path().to_string(),
            message: error.into_inner().to_string(),
        })?;
    json.end().map_err(|error| RecordError::BadValue {
        path: ".".to_owned(),
        message: error.to_string(),
    })?;
    if !unknown.is_empty() {
        return Err(RecordError::UnknownFields(unknown));
    }
    if let Some(path) = first_non_finite(&spec) {
        return Err(RecordError::BadValue {
            path,
            message: "not a finite number a 32-bit float holds".to_owned(),
        });
    }
    Ok(spec)
}

/// The path of the first number of a record's density or camera that is not a finite `f32`
/// (JSON's `1e39` reads as infinity).
fn first_non_finite(spec: &RenderSpec) -> Option<String> {
    let mut fields = vec![("density".to_owned(), spec.density)];
    if let Some(pose) = &spec.camera {
        fields.extend(
            [
                ("camera.distance", pose.distance),
                ("camera.yaw_degrees", pose.yaw_degrees),
                ("camera.pitch_degrees", pose.pitch_degrees),
                ("camera.fov_y_degrees", pose.fov_y_degrees),
                ("camera.near", pose.near),
            ]
            .map(|(name, value)| (name.to_owned(), value)),
        );
        fields.extend((0..3).map(|i| (format!("camera.target[{i}]"), pose.target[i])));
    }
    if let Some(rig) = &spec.rig {
        fields.extend(
            [
                ("rig.distance", rig.distance),
                ("rig.yaw_degrees", rig.yaw_degrees),
                ("rig.pitch_degrees", rig.pitch_degrees),
                ("rig.fov_y_degrees", rig.fov_y_degrees),
                ("rig.near", rig.near),
                ("rig.far", rig.far),
                ("rig.orbit_degrees_per_frame", rig.orbit_degrees_per_frame),
            ]
            .map(|(name, value)| (name.to_owned(), value)),
        );
        fields.extend((0..3).map(|i| (format!("rig.target[{i}]"), rig.target[i])));
    }
    fields
        .into_iter()
        .find(|(_, value)| !value.is_finite())
        .map(|(path, _)| path)
}

/// This build's version and commit.
pub fn build_id() -> String {
    match option_env!("AA_LAB_GIT_HASH") {
        Some(hash) if !hash.is_empty() => format!("aa-lab {} ({hash})", env!("CARGO_PKG_VERSION")),
        _ => format!("aa-lab {}", env!("CARGO_PKG_VERSION")),
    }
}

/// Errors of running a spec.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A technique could not be created or configured.
    #[error(transparent)]
    Technique(#[from] TechniqueError),
    /// The frame failed.
    #[error(transparent)]
    Graph(#[from] GraphError),
    /// Reading the result back failed.
    #[error(transparent)]
    Readback(#[from] ReadbackError),
    /// No technique was given.
    #[error("no technique to render")]
    NoTechnique,
    /// The frame number is beyond [`MAX_FRAME`].
    #[error("frame {0} is beyond the largest frame aa-lab renders ({MAX_FRAME})")]
    FrameTooLarge(u64),
    /// A technique cannot run on a finished image (image mode).
    #[error(
        "{0}; techniques that run on an image: none, fxaa, smaa (SMAA 1x with luma or colour edges)"
    )]
    NotOnImage(String),
}

/// An image a technique produced.
pub struct TechniqueImage {
    /// Technique id.
    pub id: String,
    /// Technique label with its defining settings (`SSAA 16x`).
    pub label: String,
    /// Debug view name, `None` for the technique's output.
    pub view: Option<&'static str>,
    /// The pixels, sRGB-encoded RGBA8.
    pub image: image::RgbaImage,
}

/// The result of running a spec.
pub struct RenderOutput {
    /// Every technique's output, then its debug views when asked for.
    pub images: Vec<TechniqueImage>,
    /// Which code path each technique ran, where it has a choice.
    pub notes: Vec<(String, String)>,
    /// GPU timings of the kept frame (or the median of the timing repeats).
    pub timings: Option<FrameTimings>,
    /// Memory of the kept frame.
    pub memory: MemoryReport,
    /// Scene renders recorded in the kept frame.
    pub scene_renders: usize,
    /// Technique id and linear radiance of every technique that ran before the tonemapper
    /// of an HDR frame (read back only when [`RunOptions::radiance`] asks).
    pub radiance: Vec<(String, image::Rgb32FImage)>,
}

/// Options of [`run`].
#[derive(Default)]
pub struct RunOptions<'a> {
    /// Also read back each technique's debug views.
    pub debug_views: bool,
    /// Render the kept frame this many extra times after reading it back, and report the
    /// per-pass median GPU times (the first frame includes shader compilation).
    pub timing_repeats: u32,
    /// Called after each frame with (frames done, frames total).
    pub progress: Option<&'a dyn Fn(u64, u64)>,
    /// Image mode: this finished image (the spec's size) replaces the 1x scene render; a
    /// technique that needs more than its colour is refused with the reason.
    pub image: Option<&'a image::RgbaImage>,
    /// Also read back the radiance of the techniques that ran before the tonemapper.
    pub radiance: bool,
}

/// The camera of frame `frame` for a spec.
pub fn frame_camera(spec: &RenderSpec, scene: &Scene, frame: u64) -> FrameCamera {
    let size = (spec.width, spec.height);
    match spec.camera {
        Some(pose) => FrameCamera {
            pose,
            prev_pose: pose,
            frame,
            size,
            render_size: None,
        },
        None => FrameCamera::from_rig(&scene.camera, frame, size),
    }
}

/// Builds the frame graph of a spec's techniques (settings applied).
pub fn build_graph(gpu: &Gpu, scene: &Scene, spec: &RenderSpec) -> Result<FrameGraph, RenderError> {
    if spec.techniques.is_empty() {
        return Err(RenderError::NoTechnique);
    }
    let mut graph = FrameGraph::new(gpu.clone(), scene);
    graph.set_overlay(spec.overlay);
    graph.set_specular_aa(spec.specular_aa);
    graph.set_tonemap(spec.tonemap_of(scene));
    for t in &spec.techniques {
        graph.add(t.create(gpu)?);
    }
    Ok(graph)
}

/// Renders a spec headless and reads every output back.
pub fn run(
    gpu: &Gpu,
    scene: &Scene,
    spec: &RenderSpec,
    options: &RunOptions<'_>,
) -> Result<RenderOutput, RenderError> {
    if spec.frame > MAX_FRAME {
        return Err(RenderError::FrameTooLarge(spec.frame));
    }
    let mut graph = build_graph(gpu, scene, spec)?;
    for slot in graph.slots_mut() {
        slot.technique.set_debug_views(options.debug_views);
    }
    if let Some(image) = options.image {
        let info = FrameInfo {
            camera: frame_camera(spec, scene, spec.frame),
            reset_history: true,
        };
        if let Some(reason) = graph
            .slots()
            .iter()
            .find_map(|s| aa::image_refusal(s.technique.as_ref(), &info))
        {
            return Err(RenderError::NotOnImage(reason));
        }
        graph.set_image_input(Some(image.clone()));
    }
    let temporal = graph.slots().iter().any(|s| s.technique.temporal());
    let first = if temporal { 0 } else { spec.frame };
    let total = spec.frame - first + 1;
    for frame in first..=spec.frame {
        let info = FrameInfo {
            camera: frame_camera(spec, scene, frame),
            reset_history: frame == first,
        };
        let scope = if frame == spec.frame {
            FrameScope::All
        } else {
            FrameScope::TemporalOnly
        };
        graph.render(&info, scope)?;
        if let Some(progress) = options.progress {
            // Keep the queue short so progress reflects finished work.
            gpu.wait_idle();
            progress(frame - first + 1, total);
        }
    }
    graph.finish();
    let mut images = Vec::new();
    for slot in graph.slots() {
        let id = slot.technique.id().to_owned();
        let label = slot.technique.label();
        if let Some(output) = slot.output() {
            let image = read_texture_rgba8(gpu, output)?;
            images.push(TechniqueImage {
                id: id.clone(),
                label: label.clone(),
                view: None,
                image,
            });
        }
        for view in slot.technique.debug_views() {
            let image = read_texture_rgba8(gpu, view.texture)?;
            images.push(TechniqueImage {
                id: id.clone(),
                label: label.clone(),
                view: Some(view.name),
                image,
            });
        }
    }
    let mut radiance = Vec::new();
    for slot in graph.slots().iter().filter(|_| options.radiance) {
        if let Some(texture) = slot.hdr_output() {
            let image = crate::gpu::readback::read_texture_radiance(gpu, texture)?;
            radiance.push((slot.technique.id().to_owned(), image));
        }
    }
    let notes = graph
        .slots()
        .iter()
        .filter_map(|s| {
            s.technique
                .path_note()
                .map(|n| (s.technique.id().to_owned(), n))
        })
        .collect();
    let scene_renders = graph.scene_renders_last_frame();
    let memory = graph.memory_report();
    let mut timings = graph.timings().cloned();
    if options.timing_repeats > 0 {
        let info = FrameInfo {
            camera: frame_camera(spec, scene, spec.frame),
            reset_history: false,
        };
        let mut repeats = Vec::new();
        for _ in 0..options.timing_repeats {
            graph.render(&info, FrameScope::All)?;
            graph.finish();
            repeats.extend(graph.timings().cloned());
        }
        timings = FrameTimings::median(&repeats).or(timings);
    }
    Ok(RenderOutput {
        images,
        notes,
        timings,
        memory,
        scene_renders,
        radiance,
    })
}
