//! glTF 2.0 loading: [`load_gltf`] turns a `.gltf` (with external or `data:` buffers and
//! images) or a `.glb` into the same [`Scene`] the OBJ loader builds.
//!
//! The `gltf` crate parses the JSON (and the GLB container) and checks that every index
//! refers to an existing object. Everything that touches bytes is done here, with bounds
//! checks, so a malformed file gives an error naming the file and the object at fault, never
//! a panic: buffer sizes against their declared length, buffer views against their buffer,
//! accessors (dense and sparse) against their view, vertex indices against the vertex count,
//! and positions, normals and node transforms for finite values.
//!
//! # What is read
//! * The default scene (else the first; a file without scenes draws every root node). Node
//!   transforms (matrix or translation/rotation/scale) are multiplied down the hierarchy and
//!   baked into world-space vertices; a mirroring transform reverses the winding so front
//!   faces stay front faces. Every primitive becomes one [`Mesh`]; a mesh used by several
//!   nodes is instanced by copying.
//! * Primitives of mode triangles, triangle strip and triangle fan. Points and lines draw
//!   nothing (one warning). `POSITION` is required; `NORMAL` when present, otherwise flat
//!   normals are generated, as the specification asks; `TEXCOORD_n` of the set the base
//!   texture names. Any component type the specification allows, normalised or not, and
//!   sparse accessors (with or without a base buffer view).
//! * Materials (metallic-roughness): `baseColorFactor` (linear RGB; its alpha multiplies the
//!   texture's alpha), `baseColorTexture` (sRGB, PNG or JPEG, from a file, a `data:` URI or a
//!   buffer view) with its sampler's filters and wrapping, `doubleSided`, `alphaMode`:
//!   `OPAQUE`; `MASK` with `alphaCutoff` (default 0.5), drawn like the OBJ and atrium alpha
//!   masks, so MSAA's alpha-to-coverage setting applies; `BLEND`, alpha-blended by the
//!   renderer after the opaque surfaces, sorted back to front by object; `emissiveFactor`
//!   times `KHR_materials_emissive_strength` as the material's emitted radiance (a strength
//!   above 1 makes the scene HDR, as `neon` is: `crate::graph::hdr`). Metallic and roughness
//!   values, normal, occlusion and emissive maps are not used (a material whose emission
//!   comes from a map emits nothing, with a warning): the renderer shades Blinn-Phong with a
//!   fixed dim specular. `KHR_materials_unlit` is honoured.
//! * Cameras: every perspective camera of the drawn nodes becomes a [`SceneView`] (its
//!   position and viewing direction; roll is dropped because the orbit camera keeps +Y up);
//!   the first is the default view. The rig turns about a point ahead of the camera at the
//!   depth of the model's centre. Without cameras the OBJ loader's default applies: the orbit
//!   framing, or an inside view for an interior ([`super::interior`]).
//! * Extensions: a file that *requires* an extension other than the two above is
//!   refused with an error naming it; one that merely uses others loads with a warning
//!   naming them (they are ignored).
//! * A missing or undecodable image does not fail the load, as with OBJ: the material draws
//!   the magenta/black checker and a warning names the image (`--strict` makes it an error).
//!   A missing or short buffer is an error.
//!
//! # What is read from disk, and how much
//! The glTF file and every file its URIs name must be regular files (a device, a FIFO or a
//! directory is refused up front, as for OBJ). The file itself is read up to
//! [`MAX_GLTF_BYTES`]; a buffer file no further than the buffer's `byteLength` (a larger file
//! is not read whole), which may not exceed [`MAX_BUFFER_BYTES`]; an image file up to the
//! texture limit of the OBJ loader. A URI must stay in the model's folder: an absolute path or
//! one whose `..` climbs above the folder is refused (an error for a buffer, the checker and a
//! warning for an image). What the loader builds is bounded too: one accessor yields at most
//! [`MAX_ACCESSOR_VALUES`] values, the scene (meshes instanced by several nodes counted each
//! time) at most [`MAX_SCENE_VERTICES`] vertices and three times as many indices, and the node
//! hierarchy is walked through at most [`MAX_NODE_VISITS`] nodes, so a small hostile file
//! cannot make the loader allocate without bound or run for ever.

use std::collections::HashMap;
use std::path::{Component, Path, PathBuf};

use base64::Engine as _;
use glam::{Mat3, Mat4, Vec3};

use crate::files::{self, FileError, MAX_IMAGE_FILE_BYTES};

use super::framing::{bounding_sphere, framed_camera};
use super::model::{Filter, SceneView, TextureSampler, Wrap};
use super::obj::mtl::checker_image;
use super::{AlphaMode, CameraRig, DirectionalLight, Material, Mesh, Scene, TextureImage, Vertex};

mod accessor;
mod material;
mod primitive;
mod uri;

use uri::{UriUse, load_buffers, read_uri};

/// Extensions this loader implements (a file may require these).
const IMPLEMENTED_EXTENSIONS: &[&str] = &["KHR_materials_unlit", "KHR_materials_emissive_strength"];

/// Deepest node hierarchy followed (deeper means a cycle or a hostile file).
const MAX_NODE_DEPTH: usize = 256;

/// Largest `.gltf` or `.glb` file read.
pub const MAX_GLTF_BYTES: u64 = 2 << 30;
/// Largest `byteLength` of a buffer.
pub const MAX_BUFFER_BYTES: u64 = 2 << 30;
/// Most values (elements times components) read from one accessor.
pub const MAX_ACCESSOR_VALUES: usize = 1 << 26;
/// Most vertices in a loaded scene (indices: three times as many).
pub const MAX_SCENE_VERTICES: usize = 1 << 25;
/// Most node visits while walking the hierarchy (a node listed as the child of several
/// parents is visited once per path to it).
pub const MAX_NODE_VISITS: usize = 1 << 20;

/// Background colour of glTF scenes (linear RGB), as for OBJ scenes.
const CLEAR_COLOR: Vec3 = Vec3::splat(0.1);

/// Why a glTF file could not be loaded. Every message names the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum GltfError {
    /// The file could not be read, is not a regular file or is too large.
    #[error(transparent)]
    File(#[from] FileError),
    /// The JSON or the GLB container is malformed, or an index refers to nothing.
    #[error("{} is not a valid glTF 2.0 file: {message}", path.display())]
    Parse {
        /// The glTF file.
        path: PathBuf,
        /// The parser's or validator's message.
        message: String,
    },
    /// The file requires an extension this loader does not implement.
    #[error(
        "{} requires the glTF extension {extension}, which aa-lab does not implement \
         (implemented: {list})",
        path.display(),
        list = IMPLEMENTED_EXTENSIONS.join(", ")
    )]
    UnsupportedExtension {
        /// The glTF file.
        path: PathBuf,
        /// The extension's name.
        extension: String,
    },
    /// The data is inconsistent (bad indices, accessors out of bounds, missing buffers, ...).
    #[error("{}: {message}", path.display())]
    Invalid {
        /// The glTF file.
        path: PathBuf,
        /// What is wrong, naming the object.
        message: String,
    },
    /// Nothing in the drawn scene has triangles.
    #[error("{} has no triangles to draw", path.display())]
    NoTriangles {
        /// The glTF file.
        path: PathBuf,
    },
}

/// Loads a `.gltf` or `.glb` file into a Scene (see the module docs).
pub fn load_gltf(path: &Path) -> Result<Scene, GltfError> {
    let bytes = files::read_bounded(path, MAX_GLTF_BYTES, "a glTF file")?;
    let parse = |message: String| GltfError::Parse {
        path: path.to_owned(),
        message,
    };
    let json: std::borrow::Cow<'_, [u8]> = if bytes.starts_with(b"glTF") {
        gltf::binary::Glb::from_slice(&bytes)
            .map_err(|e| parse(e.to_string()))?
            .json
    } else {
        std::borrow::Cow::Borrowed(&bytes[..])
    };
    let mut warnings = check_extensions(path, &json)?;
    let gltf::Gltf { document, blob } =
        gltf::Gltf::from_slice(&bytes).map_err(|e| parse(e.to_string()))?;
    let base = path.parent().unwrap_or(Path::new(""));
    let buffers = load_buffers(path, base, &document, blob)?;
    let mut loader = Loader {
        path,
        base,
        buffers: &buffers,
        meshes: Vec::new(),
        materials: Vec::new(),
        material_slots: HashMap::new(),
        textures: Vec::new(),
        texture_slots: HashMap::new(),
        cameras: Vec::new(),
        skipped_modes: Vec::new(),
        warnings: Vec::new(),
        scene_vertices: 0,
        scene_indices: 0,
        node_visits: 0,
    };
    let roots: Vec<gltf::Node<'_>> = match document
        .default_scene()
        .or_else(|| document.scenes().next())
    {
        Some(scene) => scene.nodes().collect(),
        None => {
            let children: std::collections::HashSet<usize> = document
                .nodes()
                .flat_map(|n| n.children().map(|c| c.index()))
                .collect();
            document
                .nodes()
                .filter(|n| !children.contains(&n.index()))
                .collect()
        }
    };
    for node in roots {
        loader.add_node(&node, Mat4::IDENTITY, 0)?;
    }
    warnings.append(&mut loader.warnings);
    if !loader.skipped_modes.is_empty() {
        warnings.push(format!(
            "{}: {} primitive(s) of points or lines draw nothing (only triangles are drawn)",
            path.display(),
            loader.skipped_modes.len()
        ));
    }
    let mut scene = Scene {
        name: path
            .file_stem()
            .map_or_else(|| "gltf".to_owned(), |s| s.to_string_lossy().into_owned()),
        meshes: loader.meshes,
        materials: loader.materials,
        textures: loader.textures,
        camera: CameraRig::default(),
        interior: false,
        light: DirectionalLight::default(),
        clear_color: CLEAR_COLOR,
        views: Vec::new(),
        notes: Vec::new(),
        warnings,
    };
    let Some((center, radius)) = bounding_sphere(&scene).filter(|_| scene.triangle_count() > 0)
    else {
        return Err(GltfError::NoTriangles {
            path: path.to_owned(),
        });
    };
    let framed = framed_camera(center, radius);
    scene.views = loader
        .cameras
        .into_iter()
        .filter_map(|c| c.view(center, radius, framed.orbit_degrees_per_frame))
        .collect();
    scene.camera = match scene.views.first() {
        Some(view) => view.camera,
        None => match super::interior::inside_view(&scene) {
            Some(inside) => {
                scene.interior = true;
                inside
            }
            None => framed,
        },
    };
    Ok(scene)
}

/// Refuses required extensions this loader does not implement; lists the used ones it
/// ignores as warnings.
fn check_extensions(path: &Path, json: &[u8]) -> Result<Vec<String>, GltfError> {
    #[derive(serde::Deserialize)]
    struct Extensions {
        #[serde(default, rename = "extensionsUsed")]
        used: Vec<String>,
        #[serde(default, rename = "extensionsRequired")]
        required: Vec<String>,
    }
    let extensions: Extensions = serde_json::from_slice(json).map_err(|e| GltfError::Parse {
        path: path.to_owned(),
        message: e.to_string(),
    })?;
    if let Some(extension) = extensions
        .required
        .iter()
        .find(|e| !IMPLEMENTED_EXTENSIONS.contains(&e.as_str()))
    {
        return Err(GltfError::UnsupportedExtension {
            path: path.to_owned(),
            extension: extension.clone(),
        });
    }
    let ignored: Vec<&str> = extensions
        .used
        .iter()
        .map(String::as_str)
        .filter(|e| !IMPLEMENTED_EXTENSIONS.contains(e))
        .collect();
    Ok(if ignored.is_empty() {
        Vec::new()
    } else {
        vec![format!(
            "{} uses glTF extension(s) {}, which aa-lab does not implement; they are ignored",
            path.display(),
            ignored.join(", ")
        )]
    })
}

/// `kind N 'name'` for messages.
fn describe(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) if !name.is_empty() => format!("{kind} {index} '{name}'"),
        _ => format!("{kind} {index}"),
    }
}

/// The drawn content being collected.
struct Loader<'a> {
    path: &'a Path,
    base: &'a Path,
    buffers: &'a [Vec<u8>],
    meshes: Vec<Mesh>,
    materials: Vec<Material>,
    /// Scene material index by glTF material index (`None`: the default material).
    material_slots: HashMap<Option<usize>, usize>,
    textures: Vec<TextureImage>,
    /// Scene texture index (and whether it is the checker) by glTF image index.
    texture_slots: HashMap<usize, (usize, bool)>,
    cameras: Vec<CameraNode>,
    skipped_modes: Vec<String>,
    warnings: Vec<String>,
    /// Vertices and indices of the meshes so far (see [`MAX_SCENE_VERTICES`]).
    scene_vertices: usize,
    scene_indices: usize,
    /// Nodes visited so far (see [`MAX_NODE_VISITS`]).
    node_visits: usize,
}

/// A perspective camera placed by a node.
struct CameraNode {
    name: String,
    world: Mat4,
    fov_y_degrees: f32,
    near: f32,
}

impl CameraNode {
    /// The camera as a view whose rig turns about a point ahead of it at the depth of the
    /// model's centre; `None` when its transform has no usable direction.
    fn view(&self, center: Vec3, radius: f32, orbit_degrees_per_frame: f32) -> Option<SceneView> {
        let eye = self.world.transform_point3(Vec3::ZERO);
        let forward = self.world.transform_vector3(Vec3::NEG_Z).try_normalize()?;
        let depth = (center - eye).dot(forward).max(radius * 0.05).max(1e-3);
        let camera = CameraRig::looking_at(
            eye,
            eye + forward * depth,
            self.fov_y_degrees,
            self.near,
            orbit_degrees_per_frame,
        )?;
        Some(SceneView {
            name: self.name.clone(),
            camera,
        })
    }
}

impl Loader<'_> {
    fn invalid(&self, message: String) -> GltfError {
        GltfError::Invalid {
            path: self.path.to_owned(),
            message,
        }
    }

    fn add_node(
        &mut self,
        node: &gltf::Node<'_>,
        parent: Mat4,
        depth: usize,
    ) -> Result<(), GltfError> {
        let name = describe("node", node.index(), node.name());
        self.node_visits += 1;
        if self.node_visits > MAX_NODE_VISITS {
            return Err(self.invalid(format!(
                "walking the node hierarchy reached {name} after {MAX_NODE_VISITS} nodes (nodes \
                 that are the children of several parents multiply the hierarchy)"
            )));
        }
        if depth > MAX_NODE_DEPTH {
            return Err(self.invalid(format!(
                "{name} is nested more than {MAX_NODE_DEPTH} levels deep (a cycle in the node \
                 hierarchy?)"
            )));
        }
        let local = Mat4::from_cols_array_2d(&node.transform().matrix());
        if !local.is_finite() {
            return Err(self.invalid(format!("{name} has a non-finite transform")));
        }
        let world = parent * local;
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                self.add_primitive(&mesh, &primitive, world)?;
            }
        }
        if let Some(camera) = node.camera() {
            let camera_name = describe("camera", camera.index(), camera.name());
            match camera.projection() {
                gltf::camera::Projection::Perspective(p) => self.cameras.push(CameraNode {
                    name: camera.name().map_or(camera_name, str::to_owned),
                    world,
                    fov_y_degrees: p.yfov().to_degrees().clamp(1.0, 170.0),
                    near: p.znear().max(1e-4),
                }),
                gltf::camera::Projection::Orthographic(_) => self.warnings.push(format!(
                    "{}: {camera_name} is orthographic, which aa-lab does not render; it is \
                     not offered as a view",
                    self.path.display()
                )),
            }
        }
        for child in node.children() {
            self.add_node(&child, world, depth + 1)?;
        }
        Ok(())
    }

    /// Refuses a mesh of `vertices` and `indices` that would take the scene past
    /// [`MAX_SCENE_VERTICES`] (or three times as many indices).
    fn check_size(&self, name: &str, vertices: usize, indices: usize) -> Result<(), GltfError> {
        let vertex_total = self.scene_vertices.saturating_add(vertices);
        let index_total = self.scene_indices.saturating_add(indices);
        if vertex_total > MAX_SCENE_VERTICES || index_total > 3 * MAX_SCENE_VERTICES {
            return Err(self.invalid(format!(
                "{name} takes the scene to {vertex_total} vertices and {index_total} indices, \
                 more than the {MAX_SCENE_VERTICES} vertices (and three times as many indices) \
                 aa-lab loads (meshes used by several nodes count once per use)"
            )));
        }
        Ok(())
    }
}
