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
//!   masks, so MSAA's alpha-to-coverage setting applies; `BLEND`, which the forward renderer
//!   cannot sort and blend: it is drawn as a mask with cutoff 0.5 (alpha-to-coverage under
//!   MSAA when enabled), and a warning names the materials. Metallic and roughness values,
//!   normal, occlusion and emissive maps are not used: the renderer shades Blinn-Phong with a
//!   fixed dim specular. `KHR_materials_unlit` is honoured.
//! * Cameras: every perspective camera of the drawn nodes becomes a [`SceneView`] (its
//!   position and viewing direction; roll is dropped because the orbit camera keeps +Y up);
//!   the first is the default view. The rig turns about a point ahead of the camera at the
//!   depth of the model's centre. Without cameras the OBJ loader's default applies: the orbit
//!   framing, or an inside view for an interior ([`super::interior`]).
//! * Extensions: a file that *requires* an extension other than `KHR_materials_unlit` is
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

/// Extensions this loader implements (a file may require these).
const IMPLEMENTED_EXTENSIONS: &[&str] = &["KHR_materials_unlit"];

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
        blended: Vec::new(),
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
    if !loader.blended.is_empty() {
        warnings.push(format!(
            "{}: material(s) {} use alphaMode BLEND, which aa-lab does not blend: they are \
             drawn alpha-masked at cutoff 0.5 (alpha-to-coverage under MSAA when enabled)",
            path.display(),
            loader.blended.join(", ")
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

/// Decodes a `data:` URI's payload (base64 or percent-encoded).
fn decode_data_uri(uri: &str) -> Result<Vec<u8>, String> {
    let (header, payload) = uri
        .strip_prefix("data:")
        .and_then(|rest| rest.split_once(','))
        .ok_or("a data: URI without a comma")?;
    if header.ends_with(";base64") {
        base64::engine::general_purpose::STANDARD
            .decode(payload.trim())
            .map_err(|e| format!("bad base64 in its data: URI ({e})"))
    } else {
        Ok(percent_decode(payload))
    }
}

/// Percent-decodes a URI (`%20` to a space); malformed escapes are kept as written.
fn percent_decode(uri: &str) -> Vec<u8> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = bytes
            .get(i + 1..i + 3)
            .and_then(|h| std::str::from_utf8(h).ok())
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match (bytes[i], hex) {
            (b'%', Some(value)) => {
                out.push(value);
                i += 3;
            }
            (byte, _) => {
                out.push(byte);
                i += 1;
            }
        }
    }
    out
}

/// What a URI is read as: a buffer (no further than its declared length) or an image.
#[derive(Clone, Copy)]
enum UriUse {
    Buffer { length: u64 },
    Image,
}

/// Whether a relative path leaves the folder it is relative to (absolute, or `..` climbing
/// above it).
fn leaves_folder(relative: &Path) -> bool {
    let mut depth = 0usize;
    for component in relative.components() {
        match component {
            Component::Normal(_) => depth += 1,
            Component::CurDir => {}
            Component::ParentDir if depth == 0 => return true,
            Component::ParentDir => depth -= 1,
            Component::RootDir | Component::Prefix(_) => return true,
        }
    }
    false
}

/// Reads a URI a glTF file names: a `data:` URI or a path relative to the file, inside its
/// folder, read within the bounds of its use (see the module docs).
fn read_uri(base: &Path, uri: &str, usage: UriUse) -> Result<(Vec<u8>, String), String> {
    if uri.starts_with("data:") {
        return decode_data_uri(uri).map(|bytes| (bytes, "an embedded data: URI".to_owned()));
    }
    if let Some((scheme, _)) = uri.split_once("://") {
        return Err(format!(
            "{uri} is a {scheme}:// URI; only files and data: URIs are read"
        ));
    }
    let decoded = String::from_utf8_lossy(&percent_decode(uri)).into_owned();
    if leaves_folder(Path::new(&decoded)) {
        return Err(format!(
            "{uri} lies outside the model's folder; aa-lab reads only files in the folder of \
             the glTF file and below it"
        ));
    }
    let path = base.join(decoded);
    let bytes = match usage {
        UriUse::Buffer { length } => files::read_head(&path, length, "a glTF buffer"),
        UriUse::Image => files::read_bounded(&path, MAX_IMAGE_FILE_BYTES, "a texture"),
    }
    .map_err(|e| e.to_string())?;
    Ok((bytes, path.display().to_string()))
}

/// Every buffer's bytes, checked against its declared length.
fn load_buffers(
    path: &Path,
    base: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
) -> Result<Vec<Vec<u8>>, GltfError> {
    let invalid = |message: String| GltfError::Invalid {
        path: path.to_owned(),
        message,
    };
    document
        .buffers()
        .map(|buffer| {
            let name = describe("buffer", buffer.index(), buffer.name());
            let length = buffer.length() as u64;
            if length > MAX_BUFFER_BYTES {
                return Err(invalid(format!(
                    "{name} declares {length} bytes, more than the {MAX_BUFFER_BYTES} bytes \
                     aa-lab reads for a glTF buffer"
                )));
            }
            let (data, from) = match buffer.source() {
                gltf::buffer::Source::Bin => (
                    blob.take().ok_or_else(|| {
                        invalid(format!(
                            "{name} refers to the GLB binary chunk, but the file has none"
                        ))
                    })?,
                    "the GLB binary chunk".to_owned(),
                ),
                gltf::buffer::Source::Uri(uri) => read_uri(base, uri, UriUse::Buffer { length })
                    .map_err(|e| invalid(format!("{name}: {e}")))?,
            };
            if data.len() < buffer.length() {
                return Err(invalid(format!(
                    "{name} declares {} bytes, but {from} holds only {}",
                    buffer.length(),
                    data.len()
                )));
            }
            Ok(data)
        })
        .collect()
}

/// `kind N 'name'` for messages.
fn describe(kind: &str, index: usize, name: Option<&str>) -> String {
    match name {
        Some(name) if !name.is_empty() => format!("{kind} {index} '{name}'"),
        _ => format!("{kind} {index}"),
    }
}

/// Size in bytes of one component.
fn component_size(ty: gltf::accessor::DataType) -> usize {
    use gltf::accessor::DataType;
    match ty {
        DataType::I8 | DataType::U8 => 1,
        DataType::I16 | DataType::U16 => 2,
        DataType::U32 | DataType::F32 => 4,
    }
}

/// One component at the start of `bytes` (little-endian), normalised to 0..1 or -1..1 when
/// `normalized`. `bytes` holds at least [`component_size`] bytes.
fn component(bytes: &[u8], ty: gltf::accessor::DataType, normalized: bool) -> f64 {
    use gltf::accessor::DataType;
    let array = |n: usize| -> [u8; 4] {
        let mut out = [0; 4];
        out[..n].copy_from_slice(&bytes[..n]);
        out
    };
    let (value, scale) = match ty {
        DataType::I8 => (f64::from(bytes[0] as i8), 127.0),
        DataType::U8 => (f64::from(bytes[0]), 255.0),
        DataType::I16 => {
            let [a, b, ..] = array(2);
            (f64::from(i16::from_le_bytes([a, b])), 32767.0)
        }
        DataType::U16 => {
            let [a, b, ..] = array(2);
            (f64::from(u16::from_le_bytes([a, b])), 65535.0)
        }
        DataType::U32 => (f64::from(u32::from_le_bytes(array(4))), 4_294_967_295.0),
        DataType::F32 => return f64::from(f32::from_le_bytes(array(4))),
    };
    if normalized {
        (value / scale).max(-1.0)
    } else {
        value
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
    blended: Vec<String>,
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

    /// The bytes of a buffer view, checked against its buffer.
    fn view_bytes(&self, view: &gltf::buffer::View<'_>) -> Result<&[u8], GltfError> {
        let buffer = &self.buffers[view.buffer().index()];
        let end = view.offset().checked_add(view.length());
        match end {
            Some(end) if end <= buffer.len() => Ok(&buffer[view.offset()..end]),
            _ => Err(self.invalid(format!(
                "buffer view {} spans bytes {}..{} of buffer {}, which holds {}",
                view.index(),
                view.offset(),
                view.offset().saturating_add(view.length()),
                view.buffer().index(),
                buffer.len()
            ))),
        }
    }

    /// `count` elements of `element` bytes at `offset` in a view, `stride` apart; checks
    /// that they lie inside the view.
    fn strided(
        &self,
        view: &gltf::buffer::View<'_>,
        offset: usize,
        count: usize,
        element: usize,
        stride: usize,
        what: &str,
    ) -> Result<&[u8], GltfError> {
        let data = self.view_bytes(view)?;
        if count == 0 {
            return Ok(&[]);
        }
        if stride < element {
            return Err(self.invalid(format!(
                "{what}: byteStride {stride} is smaller than its {element}-byte elements"
            )));
        }
        let end = stride
            .checked_mul(count - 1)
            .and_then(|n| n.checked_add(offset))
            .and_then(|n| n.checked_add(element));
        match end {
            Some(end) if end <= data.len() => Ok(&data[offset..end]),
            _ => Err(self.invalid(format!(
                "{what}: {count} elements from byte {offset} run past the end of buffer view {} \
                 ({} bytes)",
                view.index(),
                data.len()
            ))),
        }
    }

    /// Every element of an accessor with `components` components, as f64 (normalised where
    /// the accessor says so), sparse substitutions applied.
    fn read(
        &self,
        accessor: &gltf::Accessor<'_>,
        components: usize,
        what: &str,
    ) -> Result<Vec<f64>, GltfError> {
        let what = format!("{what} ({})", describe("accessor", accessor.index(), None));
        if accessor.dimensions().multiplicity() != components {
            return Err(self.invalid(format!(
                "{what} has {:?} elements, {components} component(s) expected",
                accessor.dimensions()
            )));
        }
        let ty = accessor.data_type();
        let size = component_size(ty);
        let element = size * components;
        let count = accessor.count();
        if count.saturating_mul(components) > MAX_ACCESSOR_VALUES {
            return Err(self.invalid(format!(
                "{what} has {count} elements, more than the {MAX_ACCESSOR_VALUES} values \
                 aa-lab reads from one accessor"
            )));
        }
        let normalized = accessor.normalized();
        let decode = |bytes: &[u8], out: &mut Vec<f64>| {
            for c in 0..components {
                out.push(component(&bytes[c * size..], ty, normalized));
            }
        };
        let mut values = Vec::with_capacity(count * components);
        match accessor.view() {
            Some(view) => {
                let stride = view.stride().unwrap_or(element);
                let bytes =
                    self.strided(&view, accessor.offset(), count, element, stride, &what)?;
                for i in 0..count {
                    decode(&bytes[i * stride..], &mut values);
                }
            }
            None => values.resize(count * components, 0.0),
        }
        if let Some(sparse) = accessor.sparse() {
            let indices = sparse.indices();
            let index_type = match indices.index_type() {
                gltf::accessor::sparse::IndexType::U8 => gltf::accessor::DataType::U8,
                gltf::accessor::sparse::IndexType::U16 => gltf::accessor::DataType::U16,
                gltf::accessor::sparse::IndexType::U32 => gltf::accessor::DataType::U32,
            };
            let index_size = component_size(index_type);
            let sparse_what = format!("{what}, sparse");
            let index_bytes = self.strided(
                &indices.view(),
                indices.offset(),
                sparse.count(),
                index_size,
                index_size,
                &format!("{sparse_what} indices"),
            )?;
            let value_bytes = self.strided(
                &sparse.values().view(),
                sparse.values().offset(),
                sparse.count(),
                element,
                element,
                &format!("{sparse_what} values"),
            )?;
            let mut substitute = Vec::with_capacity(components);
            for i in 0..sparse.count() {
                let target = component(&index_bytes[i * index_size..], index_type, false);
                if target >= count as f64 {
                    return Err(self.invalid(format!(
                        "{sparse_what} index {target} is out of range: the accessor has {count} \
                         elements"
                    )));
                }
                substitute.clear();
                decode(&value_bytes[i * element..], &mut substitute);
                let at = target as usize * components;
                values[at..at + components].copy_from_slice(&substitute);
            }
        }
        Ok(values)
    }

    fn add_primitive(
        &mut self,
        mesh: &gltf::Mesh<'_>,
        primitive: &gltf::Primitive<'_>,
        world: Mat4,
    ) -> Result<(), GltfError> {
        use gltf::mesh::Mode;
        let name = format!(
            "{}, primitive {}",
            describe("mesh", mesh.index(), mesh.name()),
            primitive.index()
        );
        if !matches!(
            primitive.mode(),
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            self.skipped_modes.push(name);
            return Ok(());
        }
        let positions = primitive
            .get(&gltf::Semantic::Positions)
            .ok_or_else(|| self.invalid(format!("{name} has no POSITION attribute")))?;
        self.check_size(&name, positions.count(), 0)?;
        let positions = self.read(&positions, 3, &format!("{name} POSITION"))?;
        let vertex_count = positions.len() / 3;
        let positions: Vec<Vec3> = positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32))
            .collect();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(self.invalid(format!("{name}: POSITION {i} is not finite")));
        }

        let raw_indices: Vec<u32> = match primitive.indices() {
            Some(accessor) => {
                let what = format!("{name} indices");
                if matches!(
                    accessor.data_type(),
                    gltf::accessor::DataType::F32
                        | gltf::accessor::DataType::I8
                        | gltf::accessor::DataType::I16
                ) {
                    return Err(self.invalid(format!(
                        "{what}: component type {:?} is not an unsigned integer",
                        accessor.data_type()
                    )));
                }
                let values = self.read(&accessor, 1, &what)?;
                if let Some(bad) = values.iter().find(|&&v| v >= vertex_count as f64) {
                    return Err(self.invalid(format!(
                        "{what}: vertex index {bad} is out of range ({vertex_count} vertices)"
                    )));
                }
                values.into_iter().map(|v| v as u32).collect()
            }
            None => (0..u32::try_from(vertex_count).unwrap_or(u32::MAX)).collect(),
        };
        let mut indices = triangle_list(primitive.mode(), &raw_indices);

        let (material, tex_coord) = self.material(&primitive.material());
        let uvs = match primitive.get(&gltf::Semantic::TexCoords(tex_coord)) {
            Some(accessor) => {
                let uvs = self.read(&accessor, 2, &format!("{name} TEXCOORD_{tex_coord}"))?;
                if uvs.len() != vertex_count * 2 {
                    return Err(self.invalid(format!(
                        "{name}: TEXCOORD_{tex_coord} has {} elements, POSITION {vertex_count}",
                        uvs.len() / 2
                    )));
                }
                uvs.chunks_exact(2)
                    .map(|uv| [uv[0] as f32, uv[1] as f32])
                    .collect()
            }
            None => vec![[0.0; 2]; vertex_count],
        };
        let normals = match primitive.get(&gltf::Semantic::Normals) {
            Some(accessor) => {
                let normals = self.read(&accessor, 3, &format!("{name} NORMAL"))?;
                if normals.len() != vertex_count * 3 {
                    return Err(self.invalid(format!(
                        "{name}: NORMAL has {} elements, POSITION {vertex_count}",
                        normals.len() / 3
                    )));
                }
                Some(
                    normals
                        .chunks_exact(3)
                        .map(|n| Vec3::new(n[0] as f32, n[1] as f32, n[2] as f32))
                        .collect::<Vec<_>>(),
                )
            }
            None => None,
        };

        // Bake the node transform; a mirroring one flips the winding.
        let normal_matrix = Mat3::from_mat4(world).inverse().transpose();
        if Mat3::from_mat4(world).determinant() < 0.0 {
            for triangle in indices.chunks_exact_mut(3) {
                triangle.swap(1, 2);
            }
        }
        let world_positions: Vec<Vec3> = positions
            .iter()
            .map(|&p| world.transform_point3(p))
            .collect();
        let (vertices, indices) = match normals {
            Some(normals) => {
                let vertices = world_positions
                    .iter()
                    .zip(&normals)
                    .zip(&uvs)
                    .map(|((&p, &n), &uv)| {
                        let n = (normal_matrix * n).try_normalize().unwrap_or(Vec3::Y);
                        Vertex::new(p, n, uv)
                    })
                    .collect();
                (vertices, indices)
            }
            None => flat_shaded(&world_positions, &uvs, &indices),
        };
        self.check_size(&name, vertices.len(), indices.len())?;
        self.scene_vertices += vertices.len();
        self.scene_indices += indices.len();
        self.meshes.push(Mesh {
            name,
            vertices,
            indices,
            material,
            spin: None,
        });
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

    /// The scene material of a glTF material (converted on first use) and the texture
    /// coordinate set its base texture reads.
    fn material(&mut self, material: &gltf::Material<'_>) -> (usize, u32) {
        let pbr = material.pbr_metallic_roughness();
        let info = pbr.base_color_texture();
        let tex_coord = info.as_ref().map_or(0, gltf::texture::Info::tex_coord);
        if let Some(&slot) = self.material_slots.get(&material.index()) {
            return (slot, tex_coord);
        }
        let Some(index) = material.index() else {
            let slot = self.materials.len();
            self.materials.push(Material::default());
            self.material_slots.insert(None, slot);
            return (slot, tex_coord);
        };
        let name = describe("material", index, material.name());
        let [r, g, b, a] = pbr.base_color_factor().map(|c| c.clamp(0.0, 1.0));
        let mut converted = Material {
            name: material.name().map_or_else(|| name.clone(), str::to_owned),
            base_color: Vec3::new(r, g, b),
            opacity: a,
            double_sided: material.double_sided(),
            unlit: material.unlit(),
            // The renderer's Blinn-Phong term: a dim, broad highlight for every glTF material.
            specular: Vec3::splat(0.04),
            shininess: 32.0,
            ..Material::default()
        };
        converted.alpha_mode = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask {
                cutoff: material.alpha_cutoff().unwrap_or(0.5).clamp(0.0, 1.0),
            },
            gltf::material::AlphaMode::Blend => {
                self.blended.push(name.clone());
                AlphaMode::Mask { cutoff: 0.5 }
            }
        };
        if let Some(info) = info {
            let texture = info.texture();
            let (slot, failed) = self.texture(&texture.source(), &name);
            converted.base_color_texture = Some(slot);
            converted.sampler = sampler(&texture.sampler());
            if failed {
                // The checker must show at full strength whatever the material's colour.
                converted.base_color = Vec3::ONE;
                converted.alpha_mode = AlphaMode::Opaque;
            }
        }
        let slot = self.materials.len();
        self.materials.push(converted);
        self.material_slots.insert(Some(index), slot);
        (slot, tex_coord)
    }

    /// The scene texture of a glTF image (decoded on first use) and whether it is the
    /// checker that stands in for an image that could not be loaded.
    fn texture(&mut self, image: &gltf::Image<'_>, usage: &str) -> (usize, bool) {
        if let Some(&slot) = self.texture_slots.get(&image.index()) {
            return slot;
        }
        let name = describe("image", image.index(), image.name());
        let decoded = match image.source() {
            gltf::image::Source::View { view, .. } => self
                .view_bytes(&view)
                .map(|bytes| (bytes.to_vec(), format!("buffer view {}", view.index())))
                .map_err(|e| e.to_string()),
            gltf::image::Source::Uri { uri, .. } => read_uri(self.base, uri, UriUse::Image),
        }
        .and_then(|(bytes, from)| {
            image::load_from_memory(&bytes)
                .map(|decoded| (decoded.to_rgba8(), from.clone()))
                .map_err(|e| format!("{from}: {e}"))
        });
        let (texture, failed) = match decoded {
            Ok((image, from)) => (
                TextureImage {
                    label: format!("{name} ({from})"),
                    image,
                },
                false,
            ),
            Err(reason) => {
                self.warnings.push(format!(
                    "{}: {name} (used by {usage}) could not be loaded: {reason}; a \
                     magenta/black checker is drawn instead",
                    self.path.display()
                ));
                (
                    TextureImage {
                        label: format!("{name} (missing)"),
                        image: checker_image(),
                    },
                    true,
                )
            }
        };
        let slot = (self.textures.len(), failed);
        self.textures.push(texture);
        self.texture_slots.insert(image.index(), slot);
        slot
    }
}

/// A glTF sampler as a [`TextureSampler`]; unspecified filters are linear.
fn sampler(sampler: &gltf::texture::Sampler<'_>) -> TextureSampler {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let wrap = |mode: WrappingMode| match mode {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
    };
    let mag_filter = match sampler.mag_filter() {
        Some(MagFilter::Nearest) => Filter::Nearest,
        Some(MagFilter::Linear) | None => Filter::Linear,
    };
    let (min_filter, mipmap_filter) = match sampler.min_filter() {
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) | None => (Filter::Linear, Some(Filter::Linear)),
    };
    TextureSampler {
        mag_filter,
        min_filter,
        mipmap_filter,
        wrap_u: wrap(sampler.wrap_s()),
        wrap_v: wrap(sampler.wrap_t()),
    }
}

/// A triangle list from the indices of a triangle list, strip or fan (strips alternate
/// winding so every triangle keeps the first one's orientation).
fn triangle_list(mode: gltf::mesh::Mode, indices: &[u32]) -> Vec<u32> {
    use gltf::mesh::Mode;
    match mode {
        Mode::TriangleStrip => (2..indices.len())
            .flat_map(|i| {
                let (a, b, c) = (indices[i - 2], indices[i - 1], indices[i]);
                if i % 2 == 0 { [a, b, c] } else { [b, a, c] }
            })
            .collect(),
        Mode::TriangleFan => (2..indices.len())
            .flat_map(|i| [indices[0], indices[i - 1], indices[i]])
            .collect(),
        _ => indices[..indices.len() - indices.len() % 3].to_vec(),
    }
}

/// Flat-shaded vertices (each triangle its own three, with the face normal), as the
/// specification asks when a primitive has no normals. Degenerate faces get +Y.
fn flat_shaded(positions: &[Vec3], uvs: &[[f32; 2]], indices: &[u32]) -> (Vec<Vertex>, Vec<u32>) {
    let mut vertices = Vec::with_capacity(indices.len());
    for triangle in indices.chunks_exact(3) {
        let [a, b, c] = [triangle[0], triangle[1], triangle[2]].map(|i| i as usize);
        let normal = (positions[b] - positions[a])
            .cross(positions[c] - positions[a])
            .try_normalize()
            .unwrap_or(Vec3::Y);
        for i in [a, b, c] {
            vertices.push(Vertex::new(positions[i], normal, uvs[i]));
        }
    }
    let indices = (0..u32::try_from(vertices.len()).unwrap_or(u32::MAX)).collect();
    (vertices, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn data_uris_decode() {
        assert_eq!(
            decode_data_uri("data:application/octet-stream;base64,AAEC").as_deref(),
            Ok(&[0u8, 1, 2][..])
        );
        assert_eq!(decode_data_uri("data:,a%20b").as_deref(), Ok(&b"a b"[..]));
        assert!(decode_data_uri("data:;base64,@@@").is_err());
        assert!(decode_data_uri("data:nocomma").is_err());
    }

    #[test]
    fn uris_outside_the_folder_are_recognised() {
        assert!(!leaves_folder(Path::new("a.bin")));
        assert!(!leaves_folder(Path::new("./textures/../a.png")));
        assert!(leaves_folder(Path::new("../a.png")));
        assert!(leaves_folder(Path::new("textures/../../a.png")));
        assert!(leaves_folder(Path::new("/dev/zero")));
    }

    #[test]
    fn components_normalise() {
        use gltf::accessor::DataType;
        assert_eq!(component(&[255], DataType::U8, true), 1.0);
        assert_eq!(component(&[0x80], DataType::I8, true), -1.0);
        assert_eq!(component(&[0x01, 0x00], DataType::U16, false), 1.0);
        assert_eq!(component(&1.5f32.to_le_bytes(), DataType::F32, true), 1.5);
    }

    #[test]
    fn strips_and_fans_become_lists() {
        use gltf::mesh::Mode;
        assert_eq!(
            triangle_list(Mode::TriangleStrip, &[0, 1, 2, 3]),
            vec![0, 1, 2, 2, 1, 3]
        );
        assert_eq!(
            triangle_list(Mode::TriangleFan, &[0, 1, 2, 3]),
            vec![0, 1, 2, 0, 2, 3]
        );
        assert_eq!(triangle_list(Mode::Triangles, &[0, 1, 2, 3]), vec![0, 1, 2]);
    }
}
