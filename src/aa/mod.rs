//! The antialiasing techniques: each implements [`Technique`] (defined in `crate::graph`, which
//! runs techniques without knowing them), the registry lists them, and the helpers here set
//! their parameters from any value form and create them with their pipelines checked.
//!
//! Every technique has the same shape: a folder `src/aa/<name>/` with `mod.rs` (its `ID`
//! constant, its registry entry `INFO` (or `INFOS` for a family such as MSAA 2x..16x), the
//! [`Technique`] implementation), `settings.rs` (typed settings; choices are
//! [`named_enum!`](crate::named_enum)s, which give the CLI, the viewer and the sidecars their
//! names and docs), its passes and debug views, and its `.wgsl` files, which it lists in its
//! entry. What several techniques share lives once in [`common`] (samplers, encoded views,
//! debug textures, a pipeline cache, colour maths, sample patterns and filters). Adding a
//! technique is one folder and one line in [`registry::registry`].
//!
//! [`floor`] is a technique outside the registry: the full-screen copy `bench` measures every
//! post-process pass against (it lives here so that `metrics/` does not depend on `aa/`).

pub mod cmaa2;
pub mod combo;
pub mod common;
pub mod floor;
pub mod fxaa;
pub mod info;
pub mod mlaa;
pub mod msaa;
pub mod none;
pub mod registry;
pub mod scaled;
pub mod smaa;
pub mod ssaa;
pub mod taa;
pub mod taau;
pub mod user;

pub use crate::graph::params::{self, Named, Param, ParamError, ParamKind, ParamMap, ParamValue};
pub use crate::graph::technique::{DebugView, FrameInfo, SceneInput, Technique};
pub use info::TechniqueInfo;
pub use registry::registry;

use crate::gpu::Gpu;

/// Errors a technique can raise while being created or configured.
#[derive(Debug, thiserror::Error)]
pub enum TechniqueError {
    /// The adapter cannot run it.
    #[error("{technique} is not available on this adapter: {reason}")]
    Unavailable {
        /// Technique id.
        technique: String,
        /// Why.
        reason: String,
    },
    /// A combination string (render scale, upscaler, sharpening) was refused.
    #[error(transparent)]
    Combo(#[from] combo::ComboError),
    /// No technique by that id.
    #[error("unknown technique `{0}`; valid techniques: {1}")]
    Unknown(String, String),
    /// A setting was rejected.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// A user technique's file could not be read, compiled or built (see [`user`]).
    #[error(transparent)]
    User(#[from] user::LoadError),
    /// A record's user technique file no longer has the contents the record was made with.
    #[error(
        "{path} has changed since the record was made (content hash {recorded}, now {current}); \
         restore the file, or render it again without the record"
    )]
    SourceChanged {
        /// The file.
        path: String,
        /// The hash in the record.
        recorded: String,
        /// The file's hash now.
        current: String,
    },
}

/// Why a technique cannot run on a finished image (image mode), or `None` when it can: only
/// techniques that read nothing but one 1x render's colour can.
pub fn image_refusal(technique: &dyn Technique, frame: &FrameInfo) -> Option<String> {
    let why = match technique.scene_input(frame) {
        _ if technique.render_size(frame) != frame.size() => {
            "it renders the scene below the output size (a render scale), and a finished image \
             has only the output's pixels"
                .to_owned()
        }
        _ if technique.temporal() => {
            "it accumulates jittered renders of several frames, with motion vectors".to_owned()
        }
        None => "it renders the scene itself (several jittered or larger renders)".to_owned(),
        Some(SceneInput::Msaa { samples, .. }) => format!(
            "it reads {samples} samples per pixel of the scene render, which a finished image \
             does not have"
        ),
        Some(SceneInput::Jittered1x { .. }) => "it needs jittered scene renders".to_owned(),
        Some(SceneInput::Shared1x) if technique.color_only() => return None,
        Some(SceneInput::Shared1x) => {
            "with these settings it reads the scene's depth (depth edges or predication)".to_owned()
        }
    };
    Some(format!(
        "{} ({}) cannot run on an image: {why}",
        technique.label(),
        technique.id()
    ))
}

/// Sets a parameter from any value form, validating it against the technique's description.
pub fn set_param(
    technique: &mut dyn Technique,
    key: &str,
    value: ParamValue,
) -> Result<(), ParamError> {
    let (_, value) = params::validate_setting(&technique.params(), technique.id(), key, value)?;
    technique.set_param(key, &value)
}

/// The current settings of a technique as a map (sidecar form).
pub fn param_map(technique: &dyn Technique) -> ParamMap {
    technique
        .params()
        .into_iter()
        .map(|p| (p.key.to_owned(), p.value))
        .collect()
}

/// Restores settings from a map (sidecar form); every key must be known and valid.
pub fn apply_param_map(technique: &mut dyn Technique, map: &ParamMap) -> Result<(), ParamError> {
    map.iter()
        .try_for_each(|(key, value)| set_param(technique, key, value.clone()))
}

/// Creates a technique ready to use: a registered one by id, or a user technique
/// (`user:PATH`, see [`user`]), either at a render scale with an upscaler and sharpening when
/// the id says so (`ID@SCALE:UPSCALER+SHARPEN=STRENGTH`, see [`combo`] and [`scaled`]); this is
/// the one place that resolves ids.
pub fn create(gpu: &Gpu, id: &str) -> Result<Box<dyn Technique>, TechniqueError> {
    let combo = combo::Combo::parse(id)?;
    if combo.is_plain() {
        return create_plain(gpu, &combo.base);
    }
    let inner = create_plain(gpu, &combo.base)?;
    let combo = combo.resolve(inner.reconstructs_at_output())?;
    info::needs_encoded_views(&gpu.caps).map_err(|reason| TechniqueError::Unavailable {
        technique: id.to_owned(),
        reason: format!("its upscale and sharpening passes cannot run: {reason}"),
    })?;
    Ok(Box::new(scaled::Scaled::new(gpu, inner, combo)))
}

/// A registered technique or a user technique by its own id.
fn create_plain(gpu: &Gpu, id: &str) -> Result<Box<dyn Technique>, TechniqueError> {
    if user::is_user_id(id) {
        return Ok(user::create(gpu, id)?);
    }
    let all = registry();
    let info = all.iter().find(|t| t.id == id).ok_or_else(|| {
        TechniqueError::Unknown(
            id.to_owned(),
            all.iter().map(|t| t.id).collect::<Vec<_>>().join(", "),
        )
    })?;
    let unavailable = |reason| TechniqueError::Unavailable {
        technique: id.to_owned(),
        reason,
    };
    (info.availability)(&gpu.caps).map_err(unavailable)?;
    // A pipeline the backend cannot build (a shader feature it cannot translate) is an error
    // of this technique, not a panic of wgpu's default error handler.
    let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let technique = (info.create)(gpu);
    match pollster::block_on(scope.pop()) {
        Some(error) => Err(unavailable(format!(
            "its GPU pipelines could not be created: {error}"
        ))),
        None => Ok(technique),
    }
}
