//! Wavefront OBJ/MTL loading: [`load_obj`] turns an `.obj` file, its material libraries and
//! their textures into a [`Scene`] whose camera is framed to the model.
//!
//! The file is read whole, bounded ([`MAX_OBJ_BYTES`], [`MAX_MTL_BYTES`]) and required to be a
//! regular file of UTF-8 text, so a device or FIFO named as a model is refused instead of read
//! forever. `tobj` parses it, but only after a validation pass of our own: `tobj` reports errors
//! without line numbers, accepts `nan`/`inf` coordinates, turns 3-point polylines into faces and
//! can overflow on absurd relative indices, so this pass rejects malformed or non-finite records
//! and out-of-range indices naming the line, and rewrites what `tobj` would mishandle
//! (polylines, short faces, vertex colours, spacing of names), with one warning per kind. MTL
//! text gets the same treatment. Each `tobj` model then becomes vertices (UV `v` flipped to the
//! renderer's top-left origin; area-weighted normals generated where the model has none, smooth
//! across UV seams), merged into one [`Mesh`] per (object, material) pair.
//!
//! Materials map onto the renderer's [`Material`]: `Kd`/`Ks` are read as sRGB-encoded colours
//! (the usual reading of hand-written MTL files; a fixed convention beats guessing per file),
//! `Ns` as the Blinn-Phong exponent, `map_Kd` as the base texture and `map_d` as an alpha mask
//! merged into its alpha ([`AlphaMode::Mask`]). Translucency is not rendered (a warning says
//! so), a missing or undecodable texture draws a checker and is named in
//! [`Scene::warnings`] instead of failing the load, and the records that are ignored are
//! counted in [`Scene::notes`].
//!
//! The camera orbits the centre of the model's bounding box, slightly from above, at a
//! distance at which no orbit angle clips the model; a model that encloses that centre (a room,
//! a Cornell box: see [`super::interior`]) opens with an inside view instead, and
//! [`Scene::interior`] says so.
//!
//! Every rule in full (what each record means, texture options, the camera's framing):
//! `docs/content.md`, "How OBJ/MTL files are read".

mod build;
mod check;
mod error;
pub(crate) mod mtl;

use std::cell::RefCell;
use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::Scene;
use super::framing::{bounding_sphere, framed_camera};
use build::SceneBuilder;
use check::check_obj;
use error::read_text;
pub use error::{MAX_MTL_BYTES, MAX_OBJ_BYTES, ObjError};
use mtl::{Libraries, Textures};

/// Loads an OBJ file (and its MTL and textures) into a Scene, camera framed to the bounds.
///
/// Problems that do not stop the load (missing or corrupt textures, unsupported translucency,
/// unknown material names, skipped records) are listed in [`Scene::warnings`].
pub fn load_obj(path: &Path) -> Result<Scene, ObjError> {
    let text = read_text(path, MAX_OBJ_BYTES, "an OBJ file")
        .map_err(|failure| failure.into_error(path))?;
    let checked = check_obj(path, &text)?;
    let mut warnings = checked.warnings;

    // `single_index` and `triangulate`, points and lines ignored.
    let options = tobj::GPU_LOAD_OPTIONS;
    let libraries = RefCell::new(Libraries::default());
    let loaded = tobj::load_obj_buf(&mut checked.text.as_bytes(), &options, |mtllib| {
        libraries.borrow_mut().load(path, mtllib)
    });
    let libraries = libraries.into_inner();
    if let Some(error) = libraries.error {
        return Err(error);
    }
    let parse_error = |source| ObjError::Parse {
        path: path.to_owned(),
        source,
    };
    let (models, materials) = loaded.map_err(parse_error)?;
    let materials = materials.map_err(parse_error)?;

    let known: HashSet<&str> = materials.iter().map(|m| m.name.as_str()).collect();
    let mut reported = HashSet::new();
    for (line, name) in &checked.usemtl {
        if !known.contains(name.as_str()) && reported.insert(name.as_str()) {
            warnings.push(format!(
                "{}, line {line}: usemtl '{name}' names no material of the material libraries; \
                 the default material is used",
                path.display()
            ));
        }
    }

    let mut builder = SceneBuilder {
        obj: path,
        library: &materials,
        sources: &libraries.sources,
        meshes: Vec::new(),
        mesh_slots: HashMap::new(),
        material_slots: HashMap::new(),
        materials: Vec::new(),
        textures: Textures::default(),
        warnings,
    };
    for model in &models {
        builder.add_model(model);
    }
    let mut scene = builder.finish();
    if !libraries.ignored.is_empty() {
        let list: Vec<String> = libraries
            .ignored
            .iter()
            .map(|(keyword, count)| format!("{keyword} ({count})"))
            .collect();
        scene.notes.push(format!(
            "{}: material statements aa-lab does not use were ignored: {}",
            path.display(),
            list.join(", ")
        ));
    }
    match bounding_sphere(&scene) {
        Some((center, radius)) if scene.triangle_count() > 0 => {
            let inside = super::interior::inside_view(&scene);
            Ok(Scene {
                camera: inside.unwrap_or_else(|| framed_camera(center, radius)),
                interior: inside.is_some(),
                ..scene
            })
        }
        _ => Err(ObjError::NoFaces {
            path: path.to_owned(),
        }),
    }
}
