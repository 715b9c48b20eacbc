//! Writes any scene aa-lab loads (a built-in scene or an OBJ/glTF file) as a binary glTF
//! (`.glb`), optionally with a perspective camera, so the glTF path can be shown and tested on
//! real models:
//!
//! ```sh
//! cargo run --release --example scene_to_glb -- MODEL.obj OUT.glb [EYE_X,EYE_Y,EYE_Z LOOK_X,LOOK_Y,LOOK_Z [FOV_DEG]]
//! ```
//!
//! Every mesh becomes a node (world-space vertices) under one root node; materials keep the
//! base colour (linear, as glTF wants), opacity, alpha mask and sidedness; textures are
//! embedded as PNG in the binary chunk. The camera, when given, is a node whose matrix is the
//! inverse of the look-at view.

use std::path::Path;

use aa_lab::cli::parse_vec3;
use aa_lab::scene::procedural::SceneOptions;
use aa_lab::scene::{AlphaMode, Scene, source};
use anyhow::{Context, bail};
use glam::Vec3;
use serde_json::{Value, json};

/// The JSON and binary chunk being built.
#[derive(Default)]
struct Writer {
    views: Vec<Value>,
    accessors: Vec<Value>,
    bin: Vec<u8>,
}

impl Writer {
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut view =
            json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(target) = target {
            view["target"] = json!(target);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(view);
        self.views.len() - 1
    }

    fn floats(&mut self, values: &[f32], ty: &str, components: usize, bounds: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34962));
        let mut accessor = json!({"bufferView": view, "componentType": 5126,
                                  "count": values.len() / components, "type": ty});
        if bounds {
            let pick = |f: fn(f32, f32) -> f32, start: f32| -> Vec<f32> {
                (0..components)
                    .map(|c| {
                        values
                            .iter()
                            .skip(c)
                            .step_by(components)
                            .fold(start, |a, &b| f(a, b))
                    })
                    .collect()
            };
            accessor["min"] = json!(pick(f32::min, f32::INFINITY));
            accessor["max"] = json!(pick(f32::max, f32::NEG_INFINITY));
        }
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn indices(&mut self, values: &[u32]) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34963));
        self.accessors
            .push(json!({"bufferView": view, "componentType": 5125,
                                   "count": values.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }
}

fn convert(scene: &Scene, camera: Option<(Vec3, Vec3, f32)>) -> anyhow::Result<Vec<u8>> {
    let mut w = Writer::default();
    let mut images = Vec::new();
    for texture in &scene.textures {
        let mut png = Vec::new();
        texture
            .image
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .context("encoding a texture")?;
        let view = w.view(&png, None);
        images.push(json!({"bufferView": view, "mimeType": "image/png", "name": texture.label}));
    }
    let textures: Vec<Value> = (0..scene.textures.len())
        .map(|i| json!({"source": i}))
        .collect();
    let materials: Vec<Value> = scene
        .materials
        .iter()
        .map(|m| {
            let mut pbr = json!({
                "baseColorFactor": [m.base_color.x, m.base_color.y, m.base_color.z, m.opacity],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.6,
            });
            if let Some(t) = m.base_color_texture {
                pbr["baseColorTexture"] = json!({"index": t});
            }
            let mut material = json!({"name": m.name, "pbrMetallicRoughness": pbr,
                                      "doubleSided": m.double_sided});
            if let AlphaMode::Mask { cutoff } = m.alpha_mode {
                material["alphaMode"] = json!("MASK");
                material["alphaCutoff"] = json!(cutoff);
            }
            material
        })
        .collect();
    let mut meshes = Vec::new();
    let mut nodes = vec![json!({"name": scene.name, "children": []})];
    for mesh in &scene.meshes {
        if mesh.indices.is_empty() {
            continue;
        }
        let flat = |f: fn(&aa_lab::scene::Vertex) -> &[f32]| -> Vec<f32> {
            mesh.vertices
                .iter()
                .flat_map(|v| f(v).iter().copied())
                .collect()
        };
        let position = w.floats(&flat(|v| &v.position), "VEC3", 3, true);
        let normal = w.floats(&flat(|v| &v.normal), "VEC3", 3, false);
        let uv = w.floats(&flat(|v| &v.uv), "VEC2", 2, false);
        let indices = w.indices(&mesh.indices);
        meshes.push(json!({"name": mesh.name, "primitives": [{
            "attributes": {"POSITION": position, "NORMAL": normal, "TEXCOORD_0": uv},
            "indices": indices, "material": mesh.material,
        }]}));
        nodes.push(json!({"name": mesh.name, "mesh": meshes.len() - 1}));
    }
    let children: Vec<usize> = (1..nodes.len()).collect();
    nodes[0]["children"] = json!(children);
    let mut roots = vec![0];
    let mut cameras = Vec::new();
    if let Some((eye, look_at, fov)) = camera {
        let world = glam::camera::rh::view::look_at_mat4(eye, look_at, Vec3::Y).inverse();
        cameras.push(json!({"name": "interior", "type": "perspective",
                            "perspective": {"yfov": fov.to_radians(), "znear": 0.01}}));
        nodes.push(json!({"name": "interior camera", "camera": 0,
                          "matrix": world.to_cols_array()}));
        roots.push(nodes.len() - 1);
    }
    let mut root = json!({
        "asset": {"version": "2.0", "generator": "aa-lab examples/scene_to_glb"},
        "scene": 0,
        "scenes": [{"name": scene.name, "nodes": roots}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "accessors": w.accessors, "bufferViews": w.views,
        "buffers": [{"byteLength": w.bin.len()}],
    });
    if !images.is_empty() {
        root["images"] = json!(images);
        root["textures"] = json!(textures);
    }
    if !cameras.is_empty() {
        root["cameras"] = json!(cameras);
    }
    let mut json = serde_json::to_vec(&root)?;
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    let mut bin = w.bin;
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = u32::try_from(12 + 8 + json.len() + 8 + bin.len()).context("model too large")?;
    let mut out = Vec::with_capacity(total as usize);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total.to_le_bytes());
    for (kind, chunk) in [(b"JSON", &json), (b"BIN\0", &bin)] {
        out.extend_from_slice(&u32::try_from(chunk.len())?.to_le_bytes());
        out.extend_from_slice(kind);
        out.extend_from_slice(chunk);
    }
    Ok(out)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (input, output, rest) = match args.as_slice() {
        [input, output, rest @ ..] => (input, Path::new(output), rest),
        _ => bail!(
            "usage: scene_to_glb MODEL OUT.glb [EYE_X,EYE_Y,EYE_Z LOOK_X,LOOK_Y,LOOK_Z [FOV_DEG]]"
        ),
    };
    let camera = match rest {
        [] => None,
        [eye, look_at, fov @ ..] => {
            let fov = match fov {
                [] => 60.0,
                [fov] => fov.parse().context("FOV_DEG is a number")?,
                _ => bail!("too many arguments"),
            };
            Some((
                parse_vec3(eye).map_err(anyhow::Error::msg)?,
                parse_vec3(look_at).map_err(anyhow::Error::msg)?,
                fov,
            ))
        }
        [_] => bail!("a camera needs EYE and LOOK_AT"),
    };
    let scene = source::load(input, &SceneOptions::default())?;
    let bytes = convert(&scene, camera)?;
    let temp = output.with_extension("glb.tmp");
    std::fs::write(&temp, &bytes).with_context(|| format!("cannot write {}", temp.display()))?;
    std::fs::rename(&temp, output).with_context(|| format!("cannot write {}", output.display()))?;
    println!(
        "wrote {} ({} triangles, {} materials, {} textures, {} bytes)",
        output.display(),
        scene.triangle_count(),
        scene.materials.len(),
        scene.textures.len(),
        bytes.len()
    );
    Ok(())
}
