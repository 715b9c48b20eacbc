//! Turning what a user names (`hairball`, `atrium`, `chart`, or a path to an `.obj`, `.gltf`
//! or `.glb` file) into a [`Scene`], with errors that list the valid names or say what is
//! wrong with the file.

use std::path::Path;

use super::Scene;
use super::gltf::{self, GltfError};
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
    /// The glTF file could not be loaded.
    #[error(transparent)]
    Gltf(#[from] GltfError),
    /// The scene has nothing to draw.
    #[error("{0} has no triangles to draw")]
    Empty(String),
}

/// The default scene of the viewer and `render`.
pub const DEFAULT_SCENE: &str = "hairball";

/// File extensions of the scene formats a path may name (lower case).
pub const SCENE_EXTENSIONS: &[&str] = &["obj", "gltf", "glb"];

/// Whether a path names a scene file by its extension.
pub fn is_scene_file(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| SCENE_EXTENSIONS.iter().any(|x| e.eq_ignore_ascii_case(x)))
}

/// Loads a built-in scene by name or an OBJ, glTF or GLB file by path (glTF for `.gltf` and
/// `.glb`, OBJ otherwise).
pub fn load(spec: &str, options: &SceneOptions) -> Result<Scene, SceneError> {
    if let Some(scene) = procedural::builtin(spec, options) {
        return Ok(scene);
    }
    let path = Path::new(spec);
    if !is_scene_file(path) && !path.exists() {
        return Err(SceneError::Unknown(spec.to_owned()));
    }
    let is_gltf = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"));
    let scene = if is_gltf {
        gltf::load_gltf(path)?
    } else {
        obj::load_obj(path)?
    };
    if scene.triangle_count() == 0 {
        return Err(SceneError::Empty(spec.to_owned()));
    }
    Ok(scene)
}
