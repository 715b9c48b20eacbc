//! glTF 2.0 loading on small files generated here: a .glb with an embedded texture, a .gltf
//! with an external buffer, MASK and BLEND materials, a sparse accessor, node transforms,
//! cameras, extensions, and every malformed kind the loader must refuse with a clear message
//! naming the file (never a panic). The hostile URIs of issue 29 (`/dev/zero`, a FIFO, a
//! directory, a file far longer than its buffer, paths that leave the model's folder) and
//! hostile sizes run in a child process under an address-space and a time limit
//! ([`confined`]), so a loader that reads without bound fails the test instead of the machine.

use std::path::{Path, PathBuf};

use aa_lab::scene::gltf::{GltfError, load_gltf};
use aa_lab::scene::{AlphaMode, Filter, Scene, Wrap, source};
use glam::Vec3;
use serde_json::{Value, json};

/// A glTF asset being built: its JSON and its one binary buffer.
struct Asset {
    json: Value,
    bin: Vec<u8>,
}

const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;

impl Asset {
    fn new() -> Self {
        Self {
            json: json!({
                "asset": {"version": "2.0", "generator": "aa-lab tests"},
                "buffers": [], "bufferViews": [], "accessors": [],
                "meshes": [], "nodes": [], "scenes": [{"nodes": []}], "scene": 0,
            }),
            bin: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, value: Value) -> usize {
        let list = self.json[key]
            .as_array_mut()
            .unwrap_or_else(|| panic!("{key} is a list"));
        list.push(value);
        list.len() - 1
    }

    /// A buffer view of `bytes` (4-byte aligned in the buffer).
    fn view(&mut self, bytes: &[u8]) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}),
        )
    }

    /// A float accessor of `ty` (VEC2, VEC3) over `values`, with min/max for VEC3.
    fn floats(&mut self, values: &[f32], ty: &str, components: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        let mut accessor = json!({
            "bufferView": view, "componentType": FLOAT,
            "count": values.len() / components, "type": ty,
        });
        if components == 3 {
            let bound = |f: fn(f32, f32) -> f32, start: f32| -> Vec<f32> {
                (0..3)
                    .map(|c| {
                        values
                            .iter()
                            .skip(c)
                            .step_by(3)
                            .fold(start, |a, &b| f(a, b))
                    })
                    .collect()
            };
            accessor["min"] = json!(bound(f32::min, f32::INFINITY));
            accessor["max"] = json!(bound(f32::max, f32::NEG_INFINITY));
        }
        self.push("accessors", accessor)
    }

    fn indices(&mut self, values: &[u16]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": UNSIGNED_SHORT,
                   "count": values.len(), "type": "SCALAR"}),
        )
    }

    /// A unit quad in the z = 0 plane (corners at ±1) as a mesh with one primitive.
    fn quad(&mut self, material: Option<usize>, normals: bool) -> usize {
        let positions = [
            -1.0, -1.0, 0.0, 1.0, -1.0, 0.0, 1.0, 1.0, 0.0, -1.0, 1.0, 0.0,
        ];
        let mut attributes = json!({
            "POSITION": self.floats(&positions, "VEC3", 3),
            "TEXCOORD_0": self.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "VEC2", 2),
        });
        if normals {
            attributes["NORMAL"] = json!(self.floats(&[0.0, 0.0, 1.0].repeat(4), "VEC3", 3));
        }
        let mut primitive = json!({
            "attributes": attributes,
            "indices": self.indices(&[0, 1, 2, 0, 2, 3]),
        });
        if let Some(material) = material {
            primitive["material"] = json!(material);
        }
        self.push("meshes", json!({"name": "quad", "primitives": [primitive]}))
    }

    /// A node, added to the scene's roots when `root`.
    fn node(&mut self, node: Value, root: bool) -> usize {
        let index = self.push("nodes", node);
        if root {
            self.json["scenes"][0]["nodes"]
                .as_array_mut()
                .expect("scene nodes")
                .push(json!(index));
        }
        index
    }

    /// A textured MASK material whose 2x2 PNG (nearest, clamped) comes from a buffer view.
    fn textured_material(&mut self) -> usize {
        let png = png_bytes(&image::RgbaImage::from_fn(2, 2, |x, _| {
            image::Rgba([255 * (x as u8), 0, 0, if x == 0 { 0 } else { 255 }])
        }));
        let view = self.view(&png);
        let image = self.push(
            "images",
            json!({"bufferView": view, "mimeType": "image/png"}),
        );
        let sampler = self.push(
            "samplers",
            json!({"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33648}),
        );
        let texture = self.push("textures", json!({"source": image, "sampler": sampler}));
        self.push(
            "materials",
            json!({
                "name": "leaf",
                "pbrMetallicRoughness": {
                    "baseColorFactor": [0.5, 1.0, 1.0, 0.8],
                    "baseColorTexture": {"index": texture},
                },
                "alphaMode": "MASK", "alphaCutoff": 0.3, "doubleSided": true,
            }),
        )
    }

    fn ensure(&mut self, key: &str) {
        if self.json.get(key).is_none() {
            self.json[key] = json!([]);
        }
    }

    fn finish_buffer(&mut self, uri: Option<&str>) {
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = uri {
            buffer["uri"] = json!(uri);
        }
        self.json["buffers"] = json!([buffer]);
    }

    /// Writes a .glb holding the JSON and the buffer.
    fn write_glb(&mut self, path: &Path) {
        self.finish_buffer(None);
        let mut json = serde_json::to_vec(&self.json).expect("json");
        while !json.len().is_multiple_of(4) {
            json.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + json.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(json.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&json);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        std::fs::write(path, out).expect("write glb");
    }

    /// Writes a .gltf with the buffer in `<stem>.bin` beside it.
    fn write_gltf(&mut self, path: &Path) {
        let bin_name = format!("{}.bin", path.file_stem().expect("stem").to_string_lossy());
        self.finish_buffer(Some(&bin_name));
        std::fs::write(path.with_file_name(&bin_name), &self.bin).expect("write bin");
        self.write_json(path);
    }

    /// Writes the JSON only (buffers as they are).
    fn write_json(&self, path: &Path) {
        std::fs::write(path, serde_json::to_vec_pretty(&self.json).expect("json"))
            .expect("write gltf");
    }
}

fn png_bytes(image: &image::RgbaImage) -> Vec<u8> {
    let mut bytes = Vec::new();
    image
        .write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )
        .expect("encode png");
    bytes
}

/// A quad asset: the quad under a parent node (matrix: scale 2) with a TRS child
/// (translation +3 x), and a camera at z = 10 looking down -Z.
fn scene_asset(material: bool) -> Asset {
    let mut asset = Asset::new();
    for key in ["images", "samplers", "textures", "materials", "cameras"] {
        asset.ensure(key);
    }
    let material = material.then(|| asset.textured_material());
    let mesh = asset.quad(material, true);
    let child = asset.node(
        json!({"name": "child", "mesh": mesh, "translation": [3.0, 0.0, 0.0]}),
        false,
    );
    asset.node(
        json!({"name": "parent", "children": [child],
               "matrix": [2,0,0,0, 0,2,0,0, 0,0,2,0, 0,0,0,1]}),
        true,
    );
    let camera = asset.push(
        "cameras",
        json!({"name": "front", "type": "perspective",
               "perspective": {"yfov": 0.8, "znear": 0.1}}),
    );
    asset.node(
        json!({"name": "camera node", "camera": camera, "translation": [6.0, 0.0, 10.0]}),
        true,
    );
    asset
}

fn load(path: &Path) -> Scene {
    load_gltf(path).unwrap_or_else(|e| panic!("{e}"))
}

fn error(path: &Path) -> String {
    match load_gltf(path) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => {
            let text = e.to_string();
            assert!(
                text.contains(&path.display().to_string()),
                "message does not name the file: {text}"
            );
            text
        }
    }
}

fn temp_file(dir: &tempfile::TempDir, name: &str) -> PathBuf {
    dir.path().join(name)
}

#[test]
fn glb_with_embedded_texture_loads_materials_transforms_and_camera() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = temp_file(&dir, "quad.glb");
    scene_asset(true).write_glb(&path);
    let scene = load(&path);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.name, "quad");
    assert_eq!(scene.triangle_count(), 2);

    // Parent scale 2 times child translation 3: x spans (3 ± 1) * 2.
    let (lo, hi) = scene.bounds().expect("bounds");
    assert!((lo - Vec3::new(4.0, -2.0, 0.0)).length() < 1e-5, "{lo}");
    assert!((hi - Vec3::new(8.0, 2.0, 0.0)).length() < 1e-5, "{hi}");

    let mesh = &scene.meshes[0];
    let material = &scene.materials[mesh.material];
    assert_eq!(material.alpha_mode, AlphaMode::Mask { cutoff: 0.3 });
    assert!(material.double_sided);
    assert_eq!(material.base_color, Vec3::new(0.5, 1.0, 1.0));
    assert!((material.opacity - 0.8).abs() < 1e-6);
    assert_eq!(material.sampler.mag_filter, Filter::Nearest);
    assert_eq!(material.sampler.min_filter, Filter::Nearest);
    assert_eq!(material.sampler.mipmap_filter, None);
    assert_eq!(material.sampler.wrap_u, Wrap::ClampToEdge);
    assert_eq!(material.sampler.wrap_v, Wrap::MirroredRepeat);
    let texture = &scene.textures[material.base_color_texture.expect("texture")];
    assert_eq!(texture.image.dimensions(), (2, 2));
    assert_eq!(texture.image.get_pixel(1, 0).0, [255, 0, 0, 255]);
    assert_eq!(texture.image.get_pixel(0, 0)[3], 0);
    // glTF puts (0, 0) at the top-left of the image, as the renderer does: no flip.
    assert_eq!(mesh.vertices[3].uv, [0.0, 0.0]);
    assert_eq!(mesh.vertices[0].normal, [0.0, 0.0, 1.0]);

    // The camera is the default view: eye at (6, 0, 10), looking down -Z.
    assert_eq!(scene.views.len(), 1);
    assert_eq!(scene.views[0].name, "front");
    assert_eq!(scene.camera, scene.views[0].camera);
    let pose = aa_lab::scene::camera::OrbitPose::at_frame(&scene.camera, 0);
    assert!(
        (pose.eye() - Vec3::new(6.0, 0.0, 10.0)).length() < 1e-3,
        "{}",
        pose.eye()
    );
    let forward = (pose.target - pose.eye()).normalize();
    assert!((forward - Vec3::NEG_Z).length() < 1e-4, "{forward}");
    assert!((scene.camera.fov_y_degrees - 0.8f32.to_degrees()).abs() < 1e-3);
}

#[test]
fn gltf_with_external_buffer_loads_through_the_scene_source() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = temp_file(&dir, "external.gltf");
    scene_asset(false).write_gltf(&path);
    let scene = source::load(
        path.to_str().expect("utf-8"),
        &aa_lab::scene::procedural::SceneOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.triangle_count(), 2);
    // No material: the neutral mid-grey default.
    let material = &scene.materials[scene.meshes[0].material];
    assert_eq!(material.base_color, Vec3::splat(0.18));
    assert_eq!(material.alpha_mode, AlphaMode::Opaque);
}

#[test]
fn data_uri_buffers_and_missing_normals_and_blend() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = temp_file(&dir, "inline.gltf");
    let mut asset = Asset::new();
    asset.ensure("materials");
    let material = asset.push(
        "materials",
        json!({"name": "glass", "alphaMode": "BLEND",
               "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 0.4]}}),
    );
    let mesh = asset.quad(Some(material), false);
    asset.node(json!({"mesh": mesh, "scale": [-1.0, 1.0, 1.0]}), true);
    use base64::Engine as _;
    let encoded = base64::engine::general_purpose::STANDARD.encode(&asset.bin);
    asset.finish_buffer(Some(&format!(
        "data:application/octet-stream;base64,{encoded}"
    )));
    asset.write_json(&path);
    let scene = load(&path);
    let mesh = &scene.meshes[0];
    // Flat normals: one vertex per corner of each triangle, facing +Z; the mirroring scale
    // (x to -x) flips the winding back, so the face is still counter-clockwise from +Z.
    assert_eq!(mesh.vertices.len(), 6);
    for v in &mesh.vertices {
        assert_eq!(v.normal, [0.0, 0.0, 1.0], "{v:?}");
    }
    // BLEND is alpha-blended by the renderer: no longer a mask, nothing to warn about.
    let material = &scene.materials[mesh.material];
    assert_eq!(material.alpha_mode, AlphaMode::Blend);
    assert_eq!(material.opacity, 0.4);
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
}

#[test]
fn sparse_accessor_overrides_positions() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = temp_file(&dir, "sparse.glb");
    let mut asset = Asset::new();
    let mesh = asset.quad(None, true);
    // Move vertex 2 to z = 5 through a sparse substitution on the POSITION accessor.
    let indices = asset.view(&2u16.to_le_bytes());
    let values: Vec<u8> = [1.0f32, 1.0, 5.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let values = asset.view(&values);
    let position = asset.json["meshes"][mesh]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .expect("position accessor") as usize;
    asset.json["accessors"][position]["sparse"] = json!({
        "count": 1,
        "indices": {"bufferView": indices, "componentType": UNSIGNED_SHORT},
        "values": {"bufferView": values},
    });
    asset.json["accessors"][position]["max"] = json!([1.0, 1.0, 5.0]);
    asset.node(json!({"mesh": mesh}), true);
    asset.write_glb(&path);
    let scene = load(&path);
    assert_eq!(scene.meshes[0].vertices[2].position, [1.0, 1.0, 5.0]);
    assert_eq!(scene.meshes[0].vertices[1].position, [1.0, -1.0, 0.0]);

    // A sparse index past the accessor's end is an error, not a panic.
    let bad = asset.view(&9u16.to_le_bytes());
    asset.json["accessors"][position]["sparse"]["indices"]["bufferView"] = json!(bad);
    let path = temp_file(&dir, "sparse-bad.glb");
    asset.write_glb(&path);
    let text = error(&path);
    assert!(text.contains("sparse index 9 is out of range"), "{text}");
}

#[test]
fn emission_and_its_strength_make_an_hdr_scene_and_an_emissive_map_warns() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut asset = Asset::new();
    asset.ensure("materials");
    let material = |asset: &mut Asset, extra: Value| {
        let mut json = json!({"name": format!("m{extra}"), "emissiveFactor": [1.0, 0.5, 0.25]});
        json.as_object_mut()
            .expect("object")
            .extend(extra.as_object().expect("object").clone());
        let index = asset.push("materials", json);
        let mesh = asset.quad(Some(index), true);
        asset.node(json!({"mesh": mesh}), true);
    };
    // A lamp 8 times brighter than the display's white, a dim glow, and a map.
    let strength = json!({"KHR_materials_emissive_strength": {"emissiveStrength": 8.0}});
    material(&mut asset, json!({"extensions": strength}));
    material(&mut asset, json!({}));
    asset.json["extensionsUsed"] = json!(["KHR_materials_emissive_strength"]);
    asset.json["extensionsRequired"] = json!(["KHR_materials_emissive_strength"]);
    let path = temp_file(&dir, "lamps.glb");
    asset.write_glb(&path);
    let scene = load(&path);
    let emission: Vec<[f32; 3]> = scene
        .meshes
        .iter()
        .map(|m| scene.materials[m.material].emissive.to_array())
        .collect();
    assert_eq!(emission, [[8.0, 4.0, 2.0], [1.0, 0.5, 0.25]]);
    assert!(scene.is_hdr(), "an emitter above white makes the scene HDR");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);

    let mut dim = Asset::new();
    dim.ensure("materials");
    material(&mut dim, json!({}));
    let dim_path = temp_file(&dir, "glow.glb");
    dim.write_glb(&dim_path);
    assert!(
        !load(&dim_path).is_hdr(),
        "an emission up to white stays on the LDR path"
    );

    let mut mapped = scene_asset(true);
    mapped.json["materials"][0]["emissiveFactor"] = json!([1.0, 1.0, 1.0]);
    mapped.json["materials"][0]["emissiveTexture"] = json!({"index": 0});
    let mapped_path = temp_file(&dir, "mapped.glb");
    mapped.write_glb(&mapped_path);
    let scene = load(&mapped_path);
    assert!(scene.materials.iter().all(|m| m.emissive == Vec3::ZERO));
    assert!(
        scene.warnings.iter().any(|w| w.contains("emissive map")),
        "{:?}",
        scene.warnings
    );
}

#[test]
fn required_unknown_extension_is_refused_and_used_one_warns() {
    let dir = tempfile::tempdir().expect("temp dir");
    let mut asset = scene_asset(false);
    asset.json["extensionsUsed"] = json!(["KHR_draco_mesh_compression", "EXT_lights_image_based"]);
    let used = temp_file(&dir, "used.glb");
    asset.write_glb(&used);
    let scene = load(&used);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("KHR_draco_mesh_compression") && w.contains("ignored")),
        "{:?}",
        scene.warnings
    );
    asset.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    let required = temp_file(&dir, "required.glb");
    asset.write_glb(&required);
    let text = error(&required);
    assert!(
        text.contains("requires the glTF extension KHR_draco_mesh_compression"),
        "{text}"
    );
    assert!(matches!(
        load_gltf(&required),
        Err(GltfError::UnsupportedExtension { .. })
    ));
}

#[test]
fn malformed_files_are_clear_errors() {
    let dir = tempfile::tempdir().expect("temp dir");
    let case = |name: &str, edit: &dyn Fn(&mut Asset), needle: &str| {
        let mut asset = scene_asset(true);
        edit(&mut asset);
        let path = temp_file(&dir, name);
        asset.write_glb(&path);
        let text = error(&path);
        assert!(
            text.contains(needle),
            "{name}: `{needle}` missing from: {text}"
        );
    };
    // A vertex index past the last vertex.
    case(
        "bad-index.glb",
        &|a| {
            let view = a.view(
                &[0u16, 1, 7]
                    .iter()
                    .flat_map(|v| v.to_le_bytes())
                    .collect::<Vec<_>>(),
            );
            let accessor = a.push(
                "accessors",
                json!({"bufferView": view, "componentType": UNSIGNED_SHORT, "count": 3, "type": "SCALAR"}),
            );
            a.json["meshes"][0]["primitives"][0]["indices"] = json!(accessor);
        },
        "vertex index 7 is out of range (4 vertices)",
    );
    // An accessor that reads past its buffer view.
    case(
        "accessor-overrun.glb",
        &|a| {
            let position = a.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                .as_u64()
                .expect("position") as usize;
            a.json["accessors"][position]["count"] = json!(400);
        },
        "run past the end of buffer view",
    );
    // A buffer view past its buffer.
    case(
        "view-overrun.glb",
        &|a| {
            let position = a.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                .as_u64()
                .expect("position") as usize;
            let view = a.json["accessors"][position]["bufferView"]
                .as_u64()
                .expect("view") as usize;
            a.json["bufferViews"][view]["byteLength"] = json!(1_000_000);
        },
        "spans bytes",
    );
    // An index to an accessor that does not exist (caught by the glTF validator).
    case(
        "dangling.glb",
        &|a| a.json["meshes"][0]["primitives"][0]["indices"] = json!(99),
        "not a valid glTF 2.0 file",
    );
    // A primitive without positions.
    case(
        "no-position.glb",
        &|a| {
            let attributes = a.json["meshes"][0]["primitives"][0]["attributes"]
                .as_object_mut()
                .expect("attributes");
            attributes.remove("POSITION");
        },
        "POSITION",
    );

    // A missing external buffer, and one shorter than it says.
    let path = temp_file(&dir, "missing-buffer.gltf");
    let mut asset = scene_asset(false);
    asset.write_gltf(&path);
    std::fs::remove_file(dir.path().join("missing-buffer.bin")).expect("remove bin");
    let text = error(&path);
    assert!(
        text.contains("buffer 0") && text.contains("missing-buffer.bin"),
        "{text}"
    );
    let path = temp_file(&dir, "short-buffer.gltf");
    asset.write_gltf(&path);
    std::fs::write(dir.path().join("short-buffer.bin"), [0u8; 8]).expect("truncate");
    let text = error(&path);
    assert!(text.contains("holds only 8"), "{text}");

    // Not JSON at all, and a GLB cut short.
    let path = temp_file(&dir, "garbage.gltf");
    std::fs::write(&path, b"{ not json").expect("write");
    assert!(error(&path).contains("not a valid glTF 2.0 file"));
    let path = temp_file(&dir, "cut.glb");
    scene_asset(true).write_glb(&path);
    let bytes = std::fs::read(&path).expect("read");
    std::fs::write(&path, &bytes[..40]).expect("cut");
    assert!(error(&path).contains("not a valid glTF 2.0 file"));
}

#[test]
fn missing_image_draws_the_checker_with_a_warning() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = temp_file(&dir, "missing-image.glb");
    let mut asset = scene_asset(true);
    asset.json["images"][0] = json!({"uri": "nowhere.png"});
    asset.write_glb(&path);
    let scene = load(&path);
    assert!(
        scene
            .warnings
            .iter()
            .any(|w| w.contains("nowhere.png") && w.contains("checker")),
        "{:?}",
        scene.warnings
    );
    let material = &scene.materials[scene.meshes[0].material];
    assert_eq!(material.alpha_mode, AlphaMode::Opaque);
}

#[cfg(unix)]
#[path = "common/confined.rs"]
mod confined;

/// Issue 29, item 1 (Unix: FIFOs, devices and address-space limits).
#[cfg(unix)]
mod hostile {
    use std::path::Path;
    use std::time::Duration;

    use super::*;

    /// A hostile case: the file written into the case folder and what the load must come to.
    struct HostileCase {
        file: &'static str,
        build: fn(&Path),
        /// `refused: ...` or `loaded: ...` with these words in the message or a warning.
        expect: &'static [&'static str],
    }

    /// The quad scene as a .gltf whose buffer (or textured scene whose image) has this URI.
    fn with_buffer_uri(dir: &Path, file: &str, uri: &str, byte_length: Option<u64>) {
        let mut asset = scene_asset(false);
        asset.write_gltf(&dir.join(file));
        let length = byte_length.unwrap_or(asset.bin.len() as u64);
        asset.json["buffers"][0] = json!({"uri": uri, "byteLength": length});
        asset.write_json(&dir.join(file));
    }

    fn with_image_uri(dir: &Path, file: &str, uri: &str) {
        let mut asset = scene_asset(true);
        asset.json["images"][0] = json!({"uri": uri});
        asset.write_glb(&dir.join(file));
    }

    const HOSTILE_CASES: &[HostileCase] = &[
        HostileCase {
            file: "zero-buffer.gltf",
            build: |dir| with_buffer_uri(dir, "zero-buffer.gltf", "/dev/zero", Some(100)),
            expect: &["refused", "/dev/zero", "outside the model's folder"],
        },
        HostileCase {
            file: "fifo-buffer.gltf",
            build: |dir| with_buffer_uri(dir, "fifo-buffer.gltf", "pipe", None),
            expect: &["refused", "pipe", "a FIFO"],
        },
        HostileCase {
            file: "directory-buffer.gltf",
            build: |dir| with_buffer_uri(dir, "directory-buffer.gltf", "folder", None),
            expect: &["refused", "folder", "a directory"],
        },
        HostileCase {
            file: "traversal-buffer.gltf",
            build: |dir| {
                with_buffer_uri(dir, "traversal-buffer.gltf", "../../../../etc/passwd", None);
            },
            expect: &["refused", "etc/passwd", "outside the model's folder"],
        },
        HostileCase {
            file: "huge-declared-buffer.gltf",
            build: |dir| {
                with_buffer_uri(dir, "huge-declared-buffer.gltf", "a.bin", Some(1 << 40));
            },
            expect: &["refused", "1099511627776 bytes", "more than"],
        },
        HostileCase {
            // A 3 GiB (sparse) file behind a small buffer: only byteLength bytes are read.
            file: "long-file.gltf",
            build: |dir| {
                let mut asset = scene_asset(false);
                asset.write_gltf(&dir.join("long-file.gltf"));
                let file = std::fs::OpenOptions::new()
                    .append(true)
                    .open(dir.join("long-file.bin"))
                    .expect("bin");
                file.set_len(3 << 30).expect("a sparse file");
            },
            expect: &["loaded"],
        },
        HostileCase {
            file: "zero-image.glb",
            build: |dir| with_image_uri(dir, "zero-image.glb", "/dev/zero"),
            expect: &[
                "loaded",
                "/dev/zero",
                "outside the model's folder",
                "checker",
            ],
        },
        HostileCase {
            file: "fifo-image.glb",
            build: |dir| with_image_uri(dir, "fifo-image.glb", "pipe"),
            expect: &["loaded", "pipe", "a FIFO", "checker"],
        },
        HostileCase {
            file: "traversal-image.glb",
            build: |dir| with_image_uri(dir, "traversal-image.glb", "../../../../etc/passwd"),
            expect: &[
                "loaded",
                "etc/passwd",
                "outside the model's folder",
                "checker",
            ],
        },
        HostileCase {
            file: "fifo-model.gltf",
            build: |dir| {
                nix::unistd::mkfifo(&dir.join("fifo-model.gltf"), nix::sys::stat::Mode::S_IRWXU)
                    .expect("mkfifo");
            },
            expect: &["refused", "fifo-model.gltf", "a FIFO"],
        },
        HostileCase {
            // Four billion vertices without a buffer view (zeros but for one sparse value).
            file: "huge-count.gltf",
            build: |dir| {
                let mut asset = scene_asset(false);
                asset.json["accessors"][0] = json!({
                    "componentType": FLOAT, "count": 4_000_000_000u64, "type": "VEC3",
                    "min": [-1, -1, 0], "max": [1, 1, 0],
                    "sparse": {"count": 1, "indices": {"bufferView": 3, "componentType": 5123},
                               "values": {"bufferView": 0}},
                });
                asset.write_gltf(&dir.join("huge-count.gltf"));
            },
            expect: &["refused", "4000000000", "more than"],
        },
        HostileCase {
            // 40 levels of nodes, each listing the next twice: 2^40 paths to the mesh.
            file: "node-fan.gltf",
            build: |dir| {
                let mut asset = scene_asset(false);
                let mesh = asset.json["nodes"][0]["mesh"].clone();
                let mut below = asset.node(json!({"mesh": mesh}), false);
                for _ in 0..40 {
                    below = asset.node(json!({"children": [below, below]}), false);
                }
                asset.json["scenes"][0]["nodes"] = json!([below]);
                asset.write_gltf(&dir.join("node-fan.gltf"));
            },
            expect: &["refused", "node"],
        },
    ];

    /// The child's side of [`hostile_uris_and_sizes_are_refused_within_bounds`]: load the file
    /// the case names and report the outcome.
    fn run_hostile_case(path: &Path) {
        match load_gltf(path) {
            Ok(scene) => confined::report(&format!("loaded: {}", scene.warnings.join(" / "))),
            Err(err) => confined::report(&format!("refused: {err}")),
        }
    }

    /// Issue 29, item 1: every hostile file ends quickly in a clear error or a warning, within
    /// [`confined::ADDRESS_SPACE_LIMIT`] of address space (before the fix `/dev/zero` was read
    /// until memory ran out and a FIFO hung the load for ever).
    #[test]
    fn hostile_uris_and_sizes_are_refused_within_bounds() {
        if let Some(case) = confined::case() {
            return run_hostile_case(Path::new(&case));
        }
        let dir = tempfile::tempdir().expect("temp dir");
        nix::unistd::mkfifo(&dir.path().join("pipe"), nix::sys::stat::Mode::S_IRWXU)
            .expect("mkfifo");
        std::fs::create_dir(dir.path().join("folder")).expect("folder");
        std::fs::write(dir.path().join("a.bin"), [0u8; 16]).expect("a.bin");
        let mut failures = Vec::new();
        for case in HOSTILE_CASES {
            (case.build)(dir.path());
            let path = dir.path().join(case.file);
            let ended = confined::run(
                "hostile::hostile_uris_and_sizes_are_refused_within_bounds",
                &path.display().to_string(),
                confined::ADDRESS_SPACE_LIMIT,
                Duration::from_secs(20),
            );
            let failure = match ended {
                confined::Ended::Reported(outcome)
                    if case.expect.iter().all(|word| outcome.contains(word)) =>
                {
                    continue;
                }
                confined::Ended::Reported(outcome) => format!("reported: {outcome}"),
                confined::Ended::Failed(output) => {
                    format!("the child failed (a panic, or memory past the limit):\n{output}")
                }
                confined::Ended::TimedOut(output) => {
                    format!("the child was still running after 20 s:\n{output}")
                }
            };
            failures.push(format!(
                "{}: expected {:?}; {failure}",
                case.file, case.expect
            ));
        }
        assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    }
}
