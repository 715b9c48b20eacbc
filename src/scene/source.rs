//! Turning what a user names (`hairball`, `atrium`, `chart`, or a path to an `.obj`) into a
//! [`Scene`], with errors that list the valid names or say what is wrong with the file.

use std::path::Path;

use super::Scene;
use super::obj::{self, ObjError};
use super::procedural::{self, SceneOptions};

/// Errors of scene loading.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Neither a built-in scene nor an existing file.
    #[error(
        "unknown scene `{0}`: not a built-in scene and no such file; built-in scenes: {list}",
        list = procedural::BUILTIN_SCENES.join(", ")
    )]
    Unknown(String),
    /// The OBJ could not be loaded.
    #[error(transparent)]
    Obj(#[from] ObjError),
    /// The scene has nothing to draw.
    #[error("{0} has no triangles to draw")]
    Empty(String),
}

/// The default scene of the viewer and `render`.
pub const DEFAULT_SCENE: &str = "hairball";

/// Loads a built-in scene by name or an OBJ file by path.
pub fn load(spec: &str, options: &SceneOptions) -> Result<Scene, SceneError> {
    if let Some(scene) = procedural::builtin(spec, options) {
        return Ok(scene);
    }
    let path = Path::new(spec);
    let is_obj = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("obj"));
    if !is_obj && !path.exists() {
        return Err(SceneError::Unknown(spec.to_owned()));
    }
    let scene = obj::load_obj(path)?;
    if scene.triangle_count() == 0 {
        return Err(SceneError::Empty(spec.to_owned()));
    }
    Ok(scene)
}
